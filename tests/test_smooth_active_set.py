"""The smooth step's active set reads neither p nor k.

Two elastic disks meeting off-centre at 14.5 m/s each, 8 Δx/c: the nodes pressed in one
step carry a smooth force into the next, and some of them come out of its predictor slightly
open. The semi-smooth test k λ − p g > 0 kept or dropped such a node depending on p, and each
choice took its own Newton path, its own step halvings (16, 17 and 20 with p × 1, × 1e3 and
× 1e-3) and its own trajectory: the nodes' velocities parted by 27 % and 34 % of the speed.
Decided on the force and the gap apart, the set is the same for every p and k.
"""

import dataclasses

import numpy as np
import pytest

from fecontact.testing import load_case
from fecontact.time.simulate import simulate

SPEED = 14.5  # m/s, each disk


def oblique_disks(**options):
    """The disks' velocities (m/s) at each step of 8 Δx/c through the impact, and the step
    halvings taken."""
    sim = load_case("two_disks").build(refinements=2, offset=0.015, velocity=SPEED, gap=0.01)
    opts = dataclasses.replace(sim.options, **options)
    states = list(simulate(sim.model, 8 * sim.dt, 0.0045, opts, q0=sim.q0, v0=sim.v0))
    return np.array([st.v for st in states]), sum(st.halvings for st in states)


@pytest.fixture(scope="module")
def default():
    return oblique_disks()


@pytest.mark.parametrize(
    "options",
    [{"penalty_scale": 1e-3}, {"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}],
    ids=["p x1e-3", "p x1e3", "k /100"],
)
def test_oblique_fast_disks_take_one_path_whatever_p_and_k(default, options):
    """The same halvings and the same velocities to the correction's tolerance: the smooth
    step does not read p or k, and the correction and the jump solve their piecewise-linear
    laws exactly for a given active set. p moves nothing (measured 0). k ÷ 100 rounds the
    multipliers in their last bit (ν/k·k ≠ ν), and a correction at a located impact beside
    pressed rows, which stops at the gap tolerance, then takes 3 or 5 iterations (measured
    4.0e-12 of the speed in the first contact step, 2.8e-13 at the end; 0 with k ÷ 128,
    whose scaling is exact). The bound is what a correction stopped at the gap tolerance may
    leave: tol_gap × the model size over one step (1.1e-11 of the speed here), far below
    the 0.17–0.34 of the speed by which the paths parted before."""
    v, halvings = default
    other, other_halvings = oblique_disks(**options)
    assert halvings > 0  # (the case exercises the halving path)
    assert other_halvings == halvings
    assert other.shape == v.shape
    sim = load_case("two_disks").build(refinements=2)
    correction_bound = sim.options.tol_gap * sim.model.length / (8 * sim.dt)  # m/s
    assert np.max(np.abs(other - v)) <= max(1e-12 * SPEED, correction_bound)


def flat_landing(t_end: float):
    """A rigid box 3 × 3 × 1 cm landing flat at 1 m/s on the top face of a free elastic cube
    (4 cm, 3 cells a side, as heavy as the box), no gravity: the run's summary."""
    import tempfile

    from fecontact import Model, Simulation, run
    from fecontact.bodies import LinearElastic, RigidBody3D, Solid
    from fecontact.bodies.shapes3d import Box
    from fecontact.contact import Contact
    from fecontact.scenes import wave_step

    a = 0.04
    cube = Solid.box([-a / 2] * 3, [a / 2] * 3, 3, LinearElastic(E=1e7, nu=0.3, rho=1000.0))
    box = RigidBody3D.uniform(cube.mass, [0.002, -0.001, a / 2 + 0.006], Box(0.03, 0.03, 0.01))
    model = Model([cube, box], [Contact(cube, box)], (0.0, 0.0, 0.0))
    v0 = model.translation(box, (0.0, 0.0, -1.0))
    sim = Simulation(model, dt=wave_step(cube, 1.0), t_end=t_end, v0=v0, output_interval=t_end)
    with tempfile.TemporaryDirectory() as tmp:
        return run(sim, tmp, frames=False, checkpoint_every=0), sim


def test_a_rigid_box_landing_flat_on_an_elastic_face_ends_its_smooth_steps():
    """The box's face closes the cube's top nodes and its edges press into the face at once:
    the persistent rows are coupled through the box's six dofs, and changing every violating
    row at once wandered between sets of 12 to 17 of 23 rows, then round-off flipped the
    coplanar ones (g = ±1e-18): six halvings and the run stopped at 1.03 ms (step 10). With
    one row per update once the set stalls, and rows entering beyond the gap tolerance only,
    the step ends, counted in ``smooth_active_set_pivots``; no penetration beyond the gap
    tolerance (tol_gap × the model size: what every completed step holds)."""
    summary, sim = flat_landing(0.0012)
    assert summary["status"] == "completed"
    assert summary["smooth_active_set_pivots"] >= 1
    assert summary["max_penetration"] <= sim.options.tol_gap * sim.model.length
