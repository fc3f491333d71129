"""A step of another size than the run's (the last one, cut short to land on t_end) is the
generalized-α step of its own size: its variable a is taken to that size
(fecontact.time.generalized_alpha.resized), and such a step creates no energy."""

import dataclasses

import pytest

from fecontact.ledger import ROUND_OFF
from fecontact.simulation import run
from fecontact.testing import case
from fecontact.time.generalized_alpha import resized
from fecontact.time.simulate import simulate


@pytest.mark.parametrize("steps", [18, 45])
@pytest.mark.parametrize("cut", [0.1, 0.3, 0.5])
def test_a_last_step_cut_short_creates_no_energy(steps, cut, tmp_path):
    # the disk on the plane, its contact lasting: the step cut to t_end made 1.2e-4 to 5.1e-4
    # of the ledger's scale with a carried at the size of the step before; runs ending on the
    # grid create 1.2e-16 of it. The bound is the ledger's own floor of round-off (ROUND_OFF
    # of the scale): nothing but round-off may be created
    sim = case("disk_drop").build(refinements=1)
    sim = sim.replace(t_end=(steps + cut) * sim.dt)
    ledger = run(sim, tmp_path, frames=False, checkpoint_every=0)["energy_ledger"]
    assert ledger["created"] <= ROUND_OFF * ledger["scale"]


def test_a_step_of_the_same_size_starts_from_the_state_itself():
    # runs whose steps are all of one size are unchanged to the bit: nothing is rescaled
    sim = case("disk_drop").build(refinements=1)
    states = list(simulate(sim.model, sim.dt, 3 * sim.dt, sim.options, q0=sim.q0, v0=sim.v0))
    assert resized(states[0], sim.dt) is states[0]  # (the start: a = v̇, made by no step)
    assert resized(states[-1], sim.dt) is states[-1]
    half = resized(states[-1], 0.5 * sim.dt)
    # a − v̇ belongs to the step's size: halved with it, v̇ itself unchanged
    assert (half.a - half.vd) == pytest.approx(0.5 * (states[-1].a - states[-1].vd), abs=0)


def test_the_rungs_of_the_rtol_ladder_create_little(tmp_path):
    # with rtol the steps change size between the rungs dt·2^-k: the disk on the plane at
    # rtol = 1e-6 (t_end on the grid) created 6.7e-4 of its scale with a carried across the
    # rungs unscaled, 9.2e-6 now (the rest falls with rtol: 5.2e-6 at 1e-7, 1.9e-6 at 1e-8);
    # the bound, 1e-4 of the scale, is 11 × that and a seventh of the creation before
    sim = case("disk_drop").build(refinements=1)
    options = dataclasses.replace(sim.options, rtol=1e-6)
    sim = sim.replace(options=options, t_end=74 * sim.dt)
    ledger = run(sim, tmp_path, frames=False, checkpoint_every=0)["energy_ledger"]
    assert ledger["created"] <= 1e-4 * ledger["scale"]
