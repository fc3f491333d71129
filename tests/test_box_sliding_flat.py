"""A rigid box thrown flat along the top face of an elastic cube clamped at its base, with
friction: the cube's nodes under the face, the box's corners and its edges across the ridges
all hold one plane, so that the Coulomb solves' Delassus matrix is singular (25 contacts,
rank 48 of 75 rows). Newton stalled there and Gauss–Seidel sweeps ran 2000 times over the
contacts (17 s for the first step, the second failing); the law is now solved by the
proximal point method (:func:`fecontact.contact.friction_redundant.proximal`)."""

import warnings

import numpy as np
import pytest

from fecontact import Model, simulate
from fecontact.bodies import LinearElastic, RigidBody3D, Solid
from fecontact.bodies.shapes3d import Box
from fecontact.contact import Contact, friction_redundant
from fecontact.contact.friction import coulomb_residual
from fecontact.time.settings import IntegratorOptions
from fecontact.time.stats import StepStats

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
A, G, MU, V0, H = 0.04, 9.81, 0.3, 0.05, 1e-3


def box_on_clamped_cube(cell="tetra", speed=V0):
    """A 0.5 kg rigid box 3 × 3 × 1 cm resting flat (gap 0) on a 4 cm rubber cube (3 cells a
    side, of ``cell``) clamped at its base, under gravity, thrown along x at ``speed`` (5 cm/s),
    μ = 0.3."""
    cube = Solid.box([-A / 2] * 3, [A / 2] * 3, 3, RUBBER, cell=cell)
    cube.fix(np.flatnonzero(np.isclose(cube.positions(np.zeros(cube.ndof))[:, 2], -A / 2)))
    box = RigidBody3D.uniform(0.5, [0.0, 0.0, A / 2 + 0.005], Box(0.03, 0.03, 0.01))
    pair = Contact(cube, box, friction=MU, method="node-to-surface")
    model = Model([cube, box], [pair], (0.0, 0.0, -G))
    return model, np.asarray(model.translation(box, (speed, 0.0, 0.0)))


def run(options, stats=None, cell="tetra", speed=V0, steps=3):
    model, v0 = box_on_clamped_cube(cell, speed)
    with warnings.catch_warnings():  # (energy warnings: not what is tested here)
        warnings.simplefilter("ignore", UserWarning)
        states = list(simulate(model, H, steps * H, options, v0=v0, stats=stats))
    return model, states


def test_a_box_sliding_flat_on_redundant_rows_keeps_coulomb_and_reads_neither_p_nor_k():
    """Three steps of the slide. The box's friction and normal impulses keep
    m v_x + μ m v_z = m v₀ − μ m g t while every contact slips along −x (measured 1.4e-5
    m/s at 3 ms; bound 1e-3 of v₀: the clamped cube's face is dragged sideways too, the box
    takes v_y = 1.6e-4 m/s); no contact inside beyond the gap tolerance (tol_gap × the size;
    measured ≤ 3e-17 m); p × 100 and k ÷ 100 leave the positions within the solves' tolerance
    (measured 5.5e-13 m, the Coulomb solves stopping at their tolerance of 6.9e-14 m along
    other paths; bound 1e-10 of the 4 cm side, 4e-12 m). The proximal solves are counted."""
    stats = StepStats()
    model, states = run(IntegratorOptions(), stats)
    n = model.bodies[0].ndof
    assert len(states) == 4
    assert stats.contact.coulomb.proximal_solves > 0
    tol = IntegratorOptions().tol_gap * model.length
    assert max(st.penetration for st in states) <= tol
    for st in states:
        drift = st.v[n] + MU * st.v[n + 2] - (V0 - MU * G * st.t)
        assert abs(drift) <= 1e-3 * V0
    for options in (
        IntegratorOptions(penalty_scale=100.0),
        IntegratorOptions(multiplier_scale=0.01),
    ):
        other = run(options)[1]
        assert len(other) == len(states)
        for a, b in zip(states, other, strict=True):
            assert np.max(np.abs(a.q - b.q)) <= 1e-10 * A


def test_a_box_thrown_along_a_mirror_symmetric_face_slides_straight():
    """The same throw on a cube of hexahedra, whose mesh is symmetric under y → −y: the box
    keeps v_y = 0 to 1e-4 of v₀ (measured 5.4e-7 m/s at 3 ms, 1.1e-5 of v₀: the box pitches
    at 0.7 rad/s and the face's nodes move with it). Six tetrahedra a cube, split along one
    diagonal, are not mirror symmetric: their face slides under a vertical load, and the box
    with it, 1.6e-4 m/s across at 3 ms (at rest: 1.5e-4 m/s along the diagonal)."""
    model, states = run(IntegratorOptions(), cell="hexahedron")
    n = model.bodies[0].ndof
    assert len(states) == 4
    assert states[-1].v[n] < V0  # (it slides, slowed by friction)
    assert max(abs(st.v[n + 1]) for st in states) <= 1e-4 * V0


@pytest.mark.parametrize(("speed", "steps", "sticking"), [(V0, 3, False), (0.0, 1, True)])
def test_where_the_proximal_iterations_settle_the_pivoting_step_solves_the_law(
    monkeypatch, speed, steps, sticking
):
    """Thrown, the third step's smooth Coulomb solve (from its warm start and from zero):
    the proximal iterations settle with 20 contacts slipping, 5 open and the normal rows
    inside by 4 times the tolerance; Lemke's pivoting on the normal multipliers with the
    slips held, then Newton, reach the law's solution, which opens 9 of the 25 contacts. At
    rest, the first step's (26 contacts): 4 held sticking, their tangents free unknowns of
    the pivoting, the answer 10 open, 2 sticking, 14 slipping. The law holds there to its
    own tolerance (the solve's: the error of a row in the units of w, a force's error times
    the inverse effective mass of its row): every closed normal row at zero, no open one
    inside, no multiplier tensile, every tangential multiplier in its cone (to a force error
    that moves its row by the tolerance), the Alart–Curnier residual at p = 1/D_ii (the
    solve's stopping measure) below it (measured thrown: closed rows 7e-21 m, open ones
    1.3e-14 m and more apart, the cone's excess 2.2e-15 m, the residual 5.5e-15 m against
    6.9e-15 m: the bound is the solve's own tolerance). No contact is left out one at a time
    and the counts say which path was taken."""
    found = []
    pivoted = friction_redundant.pivoted

    def recorded(c, D, p, k, mu, nt, x, tol, max_iter, stats):
        out = pivoted(c, D, p, k, mu, nt, x, tol, max_iter, stats)
        found.append((c, D, k, mu, nt, x, tol, out))
        return out

    monkeypatch.setattr(friction_redundant, "pivoted", recorded)
    stats = StepStats()
    run(IntegratorOptions(), stats, speed=speed, steps=steps)
    counts = stats.contact.coulomb
    assert len(found) == counts.pivoted_solves == 2
    assert counts.pivoted_failures == counts.opened_contact_solves == 0
    assert counts.pivots > 0
    for c, D, k, mu, nt, settled, tol, (x, _) in found:
        m, b = len(mu), 1 + nt
        w = c + k * (D @ x)
        xs, ws, d = (v[: m * b].reshape(m, b) for v in (x, w, np.diag(D)))
        closed = xs[:, 0] > 0.0
        assert np.all(xs[:, 0] >= 0.0)
        assert np.max(np.abs(ws[closed, 0])) <= tol
        assert np.min(ws[~closed, 0]) >= -tol
        excess = np.linalg.norm(xs[:, 1:], axis=1) - mu * xs[:, 0]
        assert np.max(k * excess * d[:, 1]) <= tol
        # (the default augmentation, one p for a contact's tangents; a row without a
        # gradient, a node with no facet near, takes the mean as the solver does)
        p = 1.0 / np.where(d > 0.0, d, d[d > 0.0].mean())
        p[:, 1:] = p[:, 1:].mean(axis=1, keepdims=True)
        assert coulomb_residual(w, x, p.ravel(), k, mu, nt) <= tol
        assert np.sum(~closed) > np.sum(settled[: m * b : b] == 0.0)  # (it opened contacts)
        inside = np.linalg.norm(xs[:, 1:], axis=1) < mu * xs[:, 0] * (1.0 - 1e-9)
        assert inside.any() == sticking
