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
