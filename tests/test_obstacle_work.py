"""The moving obstacles' work as a term of the energy ledger (fecontact.ledger, W_obstacles):
the contact impulses and forces times the obstacles' velocity, checked against the exact
answers of a belt, a rising floor and a paddle; the ledger closes with it, and a creation on
a run with a moving obstacle is a warning."""

import numpy as np
import pytest

from fecontact import Contact, Model, Plane
from fecontact.bodies import RigidBody2D, RigidBody3D
from fecontact.bodies.rigid import Polygon
from fecontact.bodies.shapes3d import Ball
from fecontact.io.history_plot import ledger_layers
from fecontact.io.output import COLUMN_UNITS, LEDGER_COLUMNS, read_history
from fecontact.simulation import Simulation, run
from fecontact.time import IntegratorOptions

G, MU, U = 9.81, 0.3, 1.0  # gravity (m/s²), the belt's friction and speed (m/s)


def _run(sim, out):
    summary = run(sim, out, frames=False)
    return summary, read_history(out / "history.csv")


def _closure(history, summary) -> float:
    """The largest |E(t) − E(0) − W_loads − W_obstacles + ΣD| over the steps (J)."""
    D = sum(history[k] for k in LEDGER_COLUMNS[1:])
    supplied = history["load_work"] + history["obstacle_work"]
    return float(np.max(np.abs(history["total_energy"] - summary["energy_initial"] - supplied + D)))


def _belt(integrator, t_end):
    block = RigidBody2D.uniform(1.0, (0.0, 0.05), Polygon.box(0.1, 0.1))
    belt = Plane([0.0, 0.0], [0.0, 1.0], motion=lambda t: np.array([U * t, 0.0]))
    model = Model([block], [Contact(block, belt, friction=MU)], gravity=(0.0, -G))
    options = IntegratorOptions(integrator=integrator)
    return Simulation(model, dt=2e-3, t_end=t_end, options=options)


def _ball(z, speed, restitution=0.0, gravity=G, velocity=None):
    """A 3D rigid ball (1 kg, r = 0.1 m) centred at height ``z`` over a plane rising at
    ``speed`` (m/s); ``velocity``: the plane's velocity as given (None: of its motion)."""
    ball = RigidBody3D.uniform(1.0, (0.0, 0.0, z), Ball(0.1))
    plane = Plane(
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        motion=lambda t: np.array([0.0, 0.0, speed * t]),
        velocity=velocity,
    )
    contact = Contact(ball, plane, restitution=restitution)
    return ball, Model([ball], [contact], gravity=(0.0, 0.0, -gravity))


@pytest.mark.parametrize("integrator", ["nsga", "moreau"])
def test_the_belt_s_work_while_the_block_slips_and_after_it_sticks(integrator, tmp_path):
    """A block (1 kg) put on a belt moving at U = 1 m/s, μ = 0.3: while it slips the belt
    does μ m g U t (0.8829 J at 0.3 s) and friction takes μ m g (U t − ½ μ g t²); once the
    block rides with the belt (t = U/(μ g) = 0.34 s) the belt does no more work: m U² in all,
    half of it the block's kinetic energy, half friction's. Before the term of its own, the
    belt's work was booked as impact_dissipation = −0.8829 J, a creation of 0.92 of the
    scale the ledger did not warn about."""
    summary, history = _run(_belt(integrator, 0.5), tmp_path)
    row, t = 150, 0.3  # (the row of t = 0.3 s, slipping: h = 2 ms)
    assert history["t"][row] == pytest.approx(t, abs=1e-12)
    # sums of products of impulses and speeds: round-off ~1e-15 J; 1e-9 J holds anywhere
    assert history["obstacle_work"][row] == pytest.approx(MU * G * U * t, abs=1e-9)
    slip = MU * G * (U * t - 0.5 * MU * G * t**2)
    assert history["friction_dissipation"][row] == pytest.approx(slip, abs=1e-9)
    assert np.max(np.abs(history["impact_dissipation"])) < 1e-12
    assert _closure(history, summary) < 1e-12
    assert COLUMN_UNITS["obstacle_work"] == "J"
    ledger = summary["energy_ledger"]
    # the belt's impulses sum to m U whatever step the block sticks in: exact to round-off
    assert ledger["obstacle_work"] == pytest.approx(U**2, abs=1e-9)
    assert ledger["kinetic"] == pytest.approx(0.5 * U**2, abs=1e-9)
    assert ledger["friction_dissipation"] == pytest.approx(0.5 * U**2, abs=1e-9)
    assert ledger["created"] < 1e-12
    assert not [w for w in summary["warnings"] if w.startswith("energy")]


def test_a_rising_floor_s_work_is_the_ball_s_energy_and_its_lift(tmp_path):
    """A ball (1 kg) resting on a floor that rises at U = 0.5 m/s from t = 0: the floor's
    first impulse gives it U (½ m U² to the ball, ½ m U² lost: a plastic impact), then
    carries it up by U t against gravity: W_obstacles = m U² + m g U t, 1.7215 J at 0.3 s,
    and the ledger closes with every term but the impact's ½ m U² at zero."""
    speed, t = 0.5, 0.3
    _, model = _ball(0.1, speed)
    summary, history = _run(Simulation(model, dt=2e-3, t_end=t), tmp_path)
    ledger = summary["energy_ledger"]
    # the floor's work is its impulses times U: round-off of 150 steps, 1e-9 J anywhere
    assert ledger["obstacle_work"] == pytest.approx(speed**2 + G * speed * t, abs=1e-9)
    assert ledger["gravity"] == pytest.approx(G * speed * t, abs=1e-9)
    assert ledger["impact_dissipation"] == pytest.approx(0.5 * speed**2, abs=1e-9)
    assert abs(ledger["numerical_dissipation"]) < 1e-9 and ledger["created"] < 1e-9
    assert _closure(history, summary) < 1e-9
    # history.png's layers stack to the energy supplied, the floor's work in it
    layers, supply = ledger_layers(history)
    np.testing.assert_allclose(sum(y for _, y in layers), supply, rtol=0, atol=1e-12)


def test_a_rising_floor_carries_a_rigid_disk_at_its_speed(tmp_path):
    """The planar rigid disk (1 kg, r = 0.1 m) on the floor rising at U = 0.5 m/s: its rows
    read the floor's ∂g/∂t, so the disk rides at U (T = ½ m U²) and the ledger books the
    same m U² + m g U t as for the ball, warning on. Before, the disk's rows had no ∂g/∂t:
    the position correction alone lifted it with v = 0 (T = 0), a work no term showed."""
    from fecontact.bodies.rigid import Disk

    speed, t = 0.5, 0.3
    disk = RigidBody2D.uniform(1.0, (0.0, 0.1), Disk(0.1))
    floor = Plane([0.0, 0.0], [0.0, 1.0], motion=lambda t: np.array([0.0, speed * t]))
    model = Model([disk], [Contact(disk, floor)], gravity=(0.0, -G))
    summary, history = _run(Simulation(model, dt=2e-3, t_end=t), tmp_path)
    ledger = summary["energy_ledger"]
    # round-off of 150 steps, as for the ball: 1e-9 J anywhere
    assert ledger["kinetic"] == pytest.approx(0.5 * speed**2, abs=1e-9)
    assert ledger["obstacle_work"] == pytest.approx(speed**2 + G * speed * t, abs=1e-9)
    assert ledger["created"] < 1e-9 and _closure(history, summary) < 1e-9


def test_a_paddle_strikes_a_ball_at_e_1(tmp_path):
    """A ball (1 kg) at 1 m/s met by a paddle rising at 2 m/s, e = 1, no gravity: it leaves
    at 2·2 + 1 = 5 m/s, 12.5 J; the paddle's impulse m·6 m/s times its 2 m/s is the 12 J
    it gained, and the impact takes nothing."""
    ball, model = _ball(0.2, 2.0, restitution=1.0, gravity=0.0)
    v0 = np.zeros(model.n)
    v0[2] = -1.0
    summary, history = _run(Simulation(model, dt=1e-3, t_end=0.05, v0=v0), tmp_path)
    ledger = summary["energy_ledger"]
    assert ledger["kinetic"] == pytest.approx(12.5, abs=1e-9)  # (round-off of one jump)
    assert ledger["obstacle_work"] == pytest.approx(12.0, abs=1e-9)
    assert abs(ledger["impact_dissipation"]) < 1e-9 and ledger["created"] < 1e-9
    assert _closure(history, summary) < 1e-9


def test_a_floor_whose_velocity_is_not_its_motion_s_creates_and_warns(tmp_path):
    """The floor of the test above given velocity 0 while it rises at 0.5 m/s: the velocity
    rows do not see it move, the position correction alone lifts the ball, m g U t = 1.47 J
    that no impulse's work explains. That is a creation, and the ledger says so (before,
    no run with a moving obstacle was warned)."""
    _, model = _ball(0.1, 0.5, velocity=lambda t: np.zeros(3))
    with pytest.warns(UserWarning, match="energy: the run created 1.47 J .all beyond"):
        summary, _ = _run(Simulation(model, dt=2e-3, t_end=0.3), tmp_path)
    ledger = summary["energy_ledger"]
    assert ledger["obstacle_work"] == 0.0  # (no ∂g/∂t: the floor's rows read no motion)
    assert ledger["created"] == pytest.approx(G * 0.5 * 0.3, rel=1e-9)
    assert [w for w in summary["warnings"] if w.startswith("energy: the run created")]


def test_the_smooth_forces_work_on_a_strip_a_floor_lifts(tmp_path):
    """A strip (6 beam elements, 32.4 g) dropped 1 cm onto a floor rising at 0.5 m/s, then
    carried: after the strike the smooth contact forces hold it, and their work is the
    impulse by which the step moves v, h((1 − γ) λ^a_n + γ λ^a_{n+1}), times the floor's
    speed. The ledger creates nothing (1.5e-14 J measured); the trapezoidal rule of the
    forces of v̇ instead created 1.5e-5 J, 0.37 % of the scale, in the steps after the strike
    where a settles (warned)."""
    from fecontact.bodies import Beam2D, Material, Section

    mat, sec = Material(E=70e9, rho=2700.0, nu=0.33), Section.rectangle(0.02, 0.002)
    beam = Beam2D.straight([0.0, 0.0], [0.3, 0.0], 6, mat, sec)
    floor = Plane([0.0, -0.01], [0.0, 1.0], motion=lambda t: np.array([0.0, 0.5 * t]))
    model = Model([beam], [Contact(beam, floor)], gravity=(0.0, -G))
    summary, history = _run(Simulation(model, dt=1e-3, t_end=0.1), tmp_path)
    ledger = summary["energy_ledger"]
    assert ledger["kinetic"] == pytest.approx(0.5 * 0.0324 * 0.5**2, rel=1e-6)  # ½ m U²
    # round-off of the energies summed (~1e-2 J) over 100 steps: 1e-12 J; the old reading
    # left 1.5e-5 J
    assert ledger["created"] < 1e-9 * ledger["scale"]
    assert not [w for w in summary["warnings"] if w.startswith("energy")]
    assert _closure(history, summary) < 1e-12
