"""The founding case: a flexible pendulum released horizontally against a rigid stop."""

import numpy as np
import pytest
from conftest import load_case
from scipy.linalg import eigh
from scipy.special import ellipk

from fecontact import Beam2D, IntegratorOptions, Material, Model, Section, simulate

CASE = load_case("flexible_pendulum")
L = 0.3
SECTION = Section.rectangle(0.02, 0.002)


def trajectory(t_end=1.5, dt=1e-3, options=None, **params):
    """Per-step arrays: t, tip x, tip vx, gap, impulse, total and kinetic energy, tip
    rotation rate."""
    sim = CASE.build(**params)
    model = sim.model
    beam = model.bodies[0]
    rows = []
    for st in simulate(model, dt, t_end, options or sim.options):
        tip = beam.positions(st.q)[-1]
        ke = model.kinetic_energy(st.v)
        total = ke + model.strain_energy(st.q) + model.potential_energy(st.q)
        rows.append((st.t, tip[0], st.v[-3], st.gaps[0], st.impulse.sum(), total, ke, st.v[-1]))
    names = ["t", "x", "vx", "gap", "impulse", "energy", "kinetic", "omega"]
    return dict(zip(names, np.array(rows).T, strict=True))


@pytest.fixture(scope="module")
def default_run():
    return trajectory()


def impact_steps(run):
    active = run["impulse"] > 0
    return np.flatnonzero(active & ~np.r_[False, active[:-1]])


def test_no_penetration_at_any_step(default_run):
    assert default_run["gap"].min() >= -1e-10


def test_tip_velocity_jumps_at_the_first_impact(default_run):
    n = impact_steps(default_run)[0]
    before, after = default_run["vx"][n - 1], default_run["vx"][n]
    assert before < -2.0  # swinging into the stop at about the rigid 2.47 m/s
    assert abs(after) < 0.05 * abs(before)  # e_N = 0: the normal velocity is stopped
    # the displacement itself is continuous: the tip reaches the stop without a jump
    assert abs(default_run["x"][n] - default_run["x"][n - 1]) < 2.5e-3 * 1.01


def test_bending_ringing_after_impact(default_run):
    """After the first impact the strip rings at its first bending frequency: the dominant
    frequency of the tip's rotation rate over the next 0.5 s is the lowest eigenfrequency
    of the same four elements held at the pin and, in x, at the stop (modal analysis of
    K φ = ω² M φ in the vertical configuration, 55.5 Hz; a continuous pinned-pinned strip
    without the tip mass's rotary part would give 51.3 Hz), to the resolution 1/T of the
    spectrum."""
    beam = Beam2D.straight([0, 0], [0, -L], 4, Material(E=70e9, nu=0.33, rho=2700.0), SECTION)
    beam.pin(0).add_mass(-1, 0.14).fix(-1, "x")
    model = Model([beam], gravity=(0.0, 0.0))
    K, M = model.internal(np.zeros(model.n))[2], model.M
    modal = np.sqrt(eigh(np.asarray(K), np.asarray(M), eigvals_only=True)[0]) / (2 * np.pi)
    run, span = default_run, 0.5
    first = impact_steps(run)[0]
    window = (run["t"] > run["t"][first]) & (run["t"] <= run["t"][first] + span)
    w = run["omega"][window] - run["omega"][window].mean()
    spectrum = np.abs(np.fft.rfft(w * np.hanning(len(w))))
    dominant = np.fft.rfftfreq(len(w), 1e-3)[1 + np.argmax(spectrum[1:])]
    assert 50.0 < modal < 60.0
    assert abs(dominant - modal) <= 1.0 / span


@pytest.mark.parametrize("penalty_scale", [1e-3, 1e3])
def test_trajectory_independent_of_penalty_scale(default_run, penalty_scale):
    other = trajectory(options=IntegratorOptions(penalty_scale=penalty_scale))
    assert np.max(np.abs(other["x"] - default_run["x"])) / L < 1e-8


@pytest.mark.parametrize("multiplier_scale", [1e-2, 1e2])
def test_trajectory_independent_of_multiplier_scale(default_run, multiplier_scale):
    other = trajectory(options=IntegratorOptions(multiplier_scale=multiplier_scale))
    assert np.max(np.abs(other["x"] - default_run["x"])) / L < 1e-8


def test_stiff_pendulum_hits_at_the_rigid_time():
    """E × 1000: the beam is practically rigid; the first impact lies within one step of the
    exact time K(sin 45°)/ω₀ of the rigid pendulum (J = m L² + m_b L²/3)."""
    dt = 1e-3
    run = trajectory(t_end=0.4, dt=dt, E=70e12)
    m, rho, A = 0.14, 2700.0, 0.02 * 0.002
    mb = rho * A * L
    J = m * L**2 + mb * L**2 / 3
    omega0 = np.sqrt(9.81 * (m * L + mb * L / 2) / J)
    t1 = ellipk(0.5) / omega0
    assert t1 == pytest.approx(0.318576, abs=1e-6)
    n = impact_steps(run)[0]
    assert run["t"][n - 1] - dt <= t1 <= run["t"][n] + dt
    assert abs(run["t"][n] - t1) <= dt


def test_self_convergence_of_the_tip_trajectory():
    """Differences between h, h/2 and h/4 shrink (first order through impacts)."""
    t_end = 0.6
    runs = [trajectory(t_end=t_end, dt=h) for h in (1e-3, 5e-4, 2.5e-4)]
    grid = runs[0]["t"]
    xs = [np.interp(grid, r["t"], r["x"]) for r in runs]
    d1 = np.max(np.abs(xs[0] - xs[1]))
    d2 = np.max(np.abs(xs[1] - xs[2]))
    assert d2 < 0.8 * d1


@pytest.mark.parametrize("restitution", [0.0, 0.5])
def test_impacts_do_not_create_energy(restitution):
    """Total energy after each impact exceeds the value before it by < 1 % of the kinetic
    energy at impact (the case's restitutions)."""
    run = trajectory(restitution=restitution)
    steps = impact_steps(run)
    assert len(steps) >= 1
    for n in steps:
        gain = run["energy"][n] - run["energy"][n - 1]
        assert gain < 0.01 * run["kinetic"][n - 1]
