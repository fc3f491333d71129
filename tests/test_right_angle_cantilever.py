"""Simo & Vu-Quoc's right-angle cantilever (cases/right_angle_cantilever.py).

Checked three ways: (a) while it moves little, against an independent linear solution of the
L's out-of-plane motion, computed here (Euler–Bernoulli bending with the section's rotary
inertia and Saint-Venant torsion on Hermite/linear elements, modal superposition with the
exact response of each mode to the piecewise-linear pulse); (b) in large motion, against the
published tip curve (Simo & Vu-Quoc, Comput. Methods Appl. Mech. Eng. 66, 1988, digitized point
by point from its figure); (c) its own convergence in h and the mesh.
After the pulse (t = 2 s) nothing works on the L, and at rho_inf = 1 its energy stays."""

import numpy as np
import pytest
from conftest import load_case
from scipy.linalg import eigh

from fecontact.testing import trace

EI = GJ = 1e3  # N·m²
RHO_A, RHO_BEND, RHO_TORSION = 1.0, 10.0, 20.0  # kg/m, kg·m (rotary, per length)
ROOT, ELBOW, TIP = np.array([[0.0, 10.0], [10.0, 10.0], [10.0, 0.0]])


def _element(le, t):
    """Stiffness and mass (6 × 6) of an element of length ``le`` along the unit in-plane
    direction ``t``, on the global dofs (w, θ_x, θ_y) of both ends: Hermite bending of w
    with dw/ds = θ·(t × e_z) (consistent translational and rotary mass), linear torsion
    φ = θ·t."""
    a = np.array([t[1], -t[0]])  # t × e_z: the bending rotation's axis
    kb = (
        EI
        / le**3
        * np.array(
            [
                [12, 6 * le, -12, 6 * le],
                [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                [-12, -6 * le, 12, -6 * le],
                [6 * le, 2 * le**2, -6 * le, 4 * le**2],
            ]
        )
    )
    mt = (
        RHO_A
        * le
        / 420
        * np.array(
            [
                [156, 22 * le, 54, -13 * le],
                [22 * le, 4 * le**2, 13 * le, -3 * le**2],
                [54, 13 * le, 156, -22 * le],
                [-13 * le, -3 * le**2, -22 * le, 4 * le**2],
            ]
        )
    )
    mr = (
        RHO_BEND
        / (30 * le)
        * np.array(
            [
                [36, 3 * le, -36, 3 * le],
                [3 * le, 4 * le**2, -3 * le, -(le**2)],
                [-36, -3 * le, 36, -3 * le],
                [3 * le, -(le**2), -3 * le, 4 * le**2],
            ]
        )
    )
    k, m = np.zeros((6, 6)), np.zeros((6, 6))
    bend, twist = [0, 1, 3, 4], [2, 5]  # local (w₁, β₁, φ₁, w₂, β₂, φ₂)
    k[np.ix_(bend, bend)], m[np.ix_(bend, bend)] = kb, mt + mr
    k[np.ix_(twist, twist)] = GJ / le * np.array([[1, -1], [-1, 1]])
    m[np.ix_(twist, twist)] = RHO_TORSION * le / 6 * np.array([[2, 1], [1, 2]])
    node = np.array([[1.0, 0.0, 0.0], [0.0, *a], [0.0, *t]])  # (w, β, φ) from (w, θ_x, θ_y)
    T = np.kron(np.eye(2), node)
    return T.T @ k @ T, T.T @ m @ T


def linear_out_of_plane(times, peak, n_per_leg=80):
    """w (m) of the elbow and the tip at ``times`` under the pulse of ``peak`` N at the
    elbow, for the linearised L clamped at the root (its in-plane motion is not excited)."""
    s = np.linspace(0.0, 1.0, n_per_leg + 1)[:, None]
    X = np.vstack([ROOT + s * (ELBOW - ROOT), ELBOW + s[1:] * (TIP - ELBOW)])
    n = 3 * len(X)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    for e in range(len(X) - 1):
        d = X[e + 1] - X[e]
        ke, me = _element(np.linalg.norm(d), d / np.linalg.norm(d))
        dofs = np.arange(3 * e, 3 * e + 6)
        K[np.ix_(dofs, dofs)] += ke
        M[np.ix_(dofs, dofs)] += me
    K, M = K[3:, 3:], M[3:, 3:]  # the root clamped
    w2, Phi = eigh(K, M)
    omega = np.sqrt(w2)
    elbow, tip = 3 * n_per_leg - 3, n - 6  # w of those nodes, after the root's three dofs
    force = Phi[elbow] * peak  # modal forces of the unit-slope ramp's peak

    def ramp(tau):  # each mode's response to a force growing at 1/s from tau = 0
        tau = np.maximum(np.asarray(tau, dtype=float), 0.0)[:, None]
        return tau / omega**2 - np.sin(tau * omega) / omega**3

    g = ramp(times) - 2 * ramp(times - 1.0) + ramp(times - 2.0)  # the triangle 0-1-2 s
    return (g * force) @ Phi[elbow], (g * force) @ Phi[tip]


def run(n_per_leg, dt, peak=50.0, t_end=30.0):
    sim = load_case("right_angle_cantilever").build(
        n_per_leg=n_per_leg, dt=dt, peak_force=peak, t_end=t_end
    )
    out = trace(sim, max_wall=600.0)
    assert out["status"] == "completed", out["message"]
    return out["t"], out["elbow_z"], out["tip_z"]


def test_the_linear_reference_is_converged():
    """The reference's own mesh error: its linear torsion elements converge at order 2
    (elbow histories over 30 s at 20, 40, 80, 160 elements a leg differ by 1.6e-3, 3.9e-4,
    9.6e-5 of the peak); at its 80 the error is 1.3e-4 (Richardson), far below the
    solver's errors tested against it."""
    t = np.linspace(0.0, 30.0, 301)
    fine, _ = linear_out_of_plane(t, 50.0, 160)
    used, _ = linear_out_of_plane(t, 50.0)
    assert np.abs(used - fine).max() < 1.5e-4 * np.abs(fine).max()


@pytest.mark.parametrize("n_per_leg, dt, bound", [(8, 0.025, 0.016), (16, 0.0125, 0.0042)])
def test_a_small_pulse_follows_the_linear_modal_solution(n_per_leg, dt, bound):
    """A pulse of 0.05 N (a thousandth of the case's: displacements of a few mm) over 10 s:
    the elbow and the tip against the linear solution, relative to their largest values.
    Measured 1.34e-2 and 3.45e-3 (elbow; tip 6.9e-3 and 1.7e-3), ratio 3.9 (4.1) when h
    and the elements halve together: the beam's one-point elements and the step are both
    of order 2. Bounds: the measured errors with 20 % room."""
    t, elbow, tip = run(n_per_leg, dt, peak=0.05, t_end=10.0)
    lin_elbow, lin_tip = linear_out_of_plane(t, 0.05)
    assert np.abs(elbow - lin_elbow).max() < bound * np.abs(lin_elbow).max()
    assert np.abs(tip - lin_tip).max() < bound * np.abs(lin_tip).max()


def test_the_case_starts_on_the_linear_solution_while_its_rotations_are_small():
    """The case's own 50 N pulse at its defaults (4 elements a leg, h = 0.05 s): up to
    t = 1 s the elbow rises to 0.94 m (rotations below 0.1 rad) on the linear solution:
    1.9 % of its largest value off, of which the same resolution's discretization error is
    1.6 % (the 0.05 N pulse) and the large motion 0.3 %. Bound 2.5 %."""
    t, elbow, tip = run(4, 0.05, t_end=1.0)
    lin_elbow, lin_tip = linear_out_of_plane(t, 50.0)
    assert np.abs(elbow - lin_elbow).max() < 0.025 * np.abs(lin_elbow).max()
    assert np.all(elbow >= -1e-12) and elbow[-1] > 0.5


# the published tip curve (Simo & Vu-Quoc 1988, digitized point by point from its figure):
# its first maximum, its minimum (a plateau from 14.4 to 15.1 s) and its last maximum
PUBLISHED = {"max": (6.58, 8.32), "min": (14.75, -9.21), "max2": (25.82, 7.50)}


def extremes(t, tip):
    first = np.argmax(np.where(t < 10.0, tip, -np.inf))
    low = np.argmin(np.where(t < 20.0, tip, np.inf))
    last = np.argmax(np.where((t > 24.0) & (t < 28.0), tip, -np.inf))
    return {"max": (t[first], tip[first]), "min": (t[low], tip[low]), "max2": (t[last], tip[last])}


@pytest.mark.slow
def test_the_tip_swings_to_the_published_extremes():
    """Large motion, 8 elements a leg at h = 0.025 s (within 0.1 m of the converged history
    below): the tip's extremes against the published curve. Measured 8.23 m at 7.40 s,
    −9.77 m at 15.80 s, 7.25 m at 26.03 s against 8.32 at 6.58, −9.21 at 14.4–15.1 and 7.50
    at 25.82: amplitudes within 1 %, 6 % and 3.3 %; the first two later by 0.8 and 1 s, the
    last within 0.2 s. Bounds: 8 % and 1.2 s. (The digitized curve's first seconds do not
    follow the linear solution above, 0.93 m at 1.54 s where the linear tip has moved 2 cm,
    so its times are read from the figure with that much doubt.)"""
    t, _, tip = run(8, 0.025)
    ours = extremes(t, tip)
    for key, (when, value) in PUBLISHED.items():
        assert ours[key][1] == pytest.approx(value, rel=0.08), key
        assert abs(ours[key][0] - when) < 1.2, key


@pytest.mark.slow
def test_the_tip_history_converges_at_order_two_in_h_and_the_mesh():
    """4, 8 and 16 elements a leg at h = 0.05, 0.025, 0.0125 s over 10 s: the differences of
    successive tip histories fall by 4 (measured |u4 − u8| 0.141 m, |u8 − u16| 0.035 m: 4.0)."""
    runs = [run(n, 0.2 / n, t_end=10.0) for n in (4, 8, 16)]
    grid = np.arange(0.0, 10.0 + 1e-9, 0.05)
    tips = [np.interp(grid, t, tip) for t, _, tip in runs]
    d1, d2 = np.abs(tips[0] - tips[1]).max(), np.abs(tips[1] - tips[2]).max()
    assert 3.0 < d1 / d2 < 5.5, (d1, d2)


def test_the_pulse_moves_the_elbow_out_of_the_plane_first():
    # before the rotations grow (t ≤ 1 s) the shared stepper follows the case already
    run_ = trace(load_case("right_angle_cantilever").build(t_end=1.0))
    assert run_["status"] == "completed"
    assert run_["elbow_z"][-1] > 0.5 and np.all(run_["elbow_z"] >= -1e-12)


def test_energy_is_kept_after_the_pulse_at_rho_inf_one():
    run_ = trace(load_case("right_angle_cantilever").build(t_end=10.0), max_wall=30.0)
    assert run_["status"] == "completed", run_["message"]
    after = run_["total"][run_["t"] >= 2.0 + 1e-9]
    # generalized-alpha at rho_inf = 1 conserves energy up to its O(h²) error of a nonlinear
    # system: 1e-3 of the energy the pulse gave over 8 s at h = 0.05 s
    assert np.abs(after - after[0]).max() < 1e-3 * after[0]
