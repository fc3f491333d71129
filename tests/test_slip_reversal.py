"""A persistent contact whose slip turns against the friction force the smooth step started
with (:mod:`fecontact.time.slip_reversal`): the step is taken again without that force, and
friction does no positive work."""

import json

import numpy as np

from fecontact import Model
from fecontact.bodies import Beam3D, Material, RigidBody3D, Section
from fecontact.bodies.shapes3d import Box
from fecontact.contact import Contact
from fecontact.io.output import read_history
from fecontact.simulation import Simulation, run
from fecontact.testing import case


def test_a_rod_whose_slip_turns_back_books_no_positive_friction_work(tmp_path):
    # cases/rod_drop.py coarsened (4 elements), thrown at 2 m/s, 10° down, turning at
    # 20 rad/s about the vertical, μ = 1: at t = 28.7 ms its far end, pressed, slips back
    # against the force of the step before. Read as the mean of λ_T,n and λ_T,n+1 over
    # that slip, friction gave 1.59e-3 J in that step (1.84e-3 J over the run, warned)
    # when the step kept λ_T,n; taken again without it, the step's friction is λ_T,n+1
    # alone, which opposes the slip
    sim = case("rod_drop").build(n_elements=4, friction=1.0, yaw_rate=20.0, angle=10.0,
                                 velocity=2.0)  # fmt: skip
    sim = sim.replace(t_end=0.029)
    run(sim, tmp_path, progress=False, frames=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    history = read_history(tmp_path / "history.csv")
    assert summary["slip_reversals"] >= 1
    assert not [w for w in summary["warnings"] if w.startswith("energy")]
    # every step's friction takes energy: the cumulative column never falls (its entries
    # are sums of products ≥ 0 each, so no round-off can make one fall)
    assert np.all(np.diff(history["friction_dissipation"]) >= 0.0)
    ledger = summary["energy_ledger"]
    assert ledger["friction_dissipation"] > 0.5  # J: the rod slides on its ends and side
    # the rule moves the split between friction and the integrator, not the energy: the run
    # creates 2.6e-5 of its scale with and without it, far below the ledger's warning (1e-3)
    assert ledger["created"] <= 1e-4 * ledger["scale"]


def test_a_rod_caught_on_a_box_s_edge_gains_nothing_from_friction(tmp_path):
    # a steel rod (0.3 m, 10 elements, r = 5 mm), its middle over the top edge of a held
    # 0.2 m cube, 20° across the edge and 10° down beyond it, dropped at 1 m/s from 1 mm,
    # μ = 1, h = 0.5 ms (docs/explanation/friction.md). At t = 2 ms the edge catches it:
    # λ_T,n = (−208, −55) N lies along that step's slip, and friction gave 4.89e-3 J in
    # that step (1.6 times what it had taken since the drop) when the step kept λ_T,n
    r, steel = 0.005, Material(E=210e9, rho=7850.0, nu=0.3)
    box = RigidBody3D.uniform(10.0, [-0.1, 0.0, -0.1], Box(0.2, 0.2, 0.2)).fix()
    across, down = np.radians(20.0), np.radians(10.0)
    d = np.array([np.cos(down) * np.cos(across), np.cos(down) * np.sin(across), -np.sin(down)])
    mid = np.array([0.0, 0.0, r + 0.001])
    rod = Beam3D.straight(mid - 0.15 * d, mid + 0.15 * d, 10, steel, Section.circle(r))
    model = Model([box, rod], [Contact(rod, box, clearance=r, friction=1.0)], (0.0, 0.0, -9.81))
    v0 = model.translation(rod, (0.0, 0.0, -1.0))
    sim = Simulation(model, dt=5e-4, t_end=3e-3, v0=v0)
    run(sim, tmp_path, progress=False, frames=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    history = read_history(tmp_path / "history.csv")
    assert summary["slip_reversals"] == 1  # the catch's step, taken again
    assert not [w for w in summary["warnings"] if w.startswith("energy")]
    assert np.all(np.diff(history["friction_dissipation"]) >= 0.0)
    # the catch dissipates now: 1.4e-3 J where it gave 2.1e-3 J net over these 6 steps
    assert summary["energy_ledger"]["friction_dissipation"] > 1e-3
