"""A whole step of solids that leaves a closing unrefined is retaken in sub-steps
(:meth:`fecontact.time.substeps.Releases._retaken`) only where the sub-steps leave no deeper
gap unrefined than the whole step did: a gap that jumps is found by no step size, and a
sub-step corrects its jump in the stiffer metric of its own size."""

import sys
from pathlib import Path

import pytest

from fecontact import run

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))


def created(summary) -> float:
    ledger = summary["energy_ledger"]
    return ledger["created"] / ledger["scale"]


def test_the_disks_whose_mortar_gap_jumped_need_no_retake(tmp_path):
    """The mortar disks of benchmarks/stress_2d.py at 14.5 m/s each, 8 Δx/c, 0.3 R off
    centre, through the closing step (2.6 ms). A mortar row jumped from +4.8e-5 to −1.2e-3 m
    within 3 µm of motion, where a master segment turning past 120° from the slave segment
    left the weighted gap whole (the facing cut, ``mortar_segments.TURNED``): the whole step
    left that closing unrefined, its retake in sub-steps went deeper (9.6e-4 → 1.2e-3 m) and
    created 1.7e-2 of the run's scale (27.8 J), and the whole step was kept (1.4e-16). With
    the gap continuous the whole step locates every closing: nothing unrefined, nothing
    retaken, 1.4e-16 created (2.3e-13 J of 1.6e3 J). The bound 1e-9 is the ledger's
    round-off over a few steps of 1e3 J (1e-16) with a wide margin, and seven orders below
    what the retake made."""
    from stress_2d import cell_speed, two_disks

    sim, _ = two_disks(speed=cell_speed(1, 8), courant=8, offset=0.015, t_end=2.6e-3)
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    assert created(summary) <= 1e-9
    assert summary["localization_fallbacks"]["unrefined"] == 0  # (1 with the facing cut)
    assert summary["localization_cost"]["retakes_kept_whole"] == 0
    assert summary["max_penetration"] <= 1e-4  # as before (9.75e-5 m, halved steps)


@pytest.mark.parametrize("v", [1.0, 3.0])
def test_a_retake_that_locates_the_closing_is_kept(v, tmp_path):
    """The elastic ball on a rigid box's corner (benchmarks/stress_3d.py): the whole step
    leaves a corner row unrefined (9.9e-5 m deep at 3 m/s), its sub-steps leave none or a
    shallower one (1.1e-5 m), and the retake is kept: 0 created (with the whole steps 2.2e-2
    and 2.5e-2 of the scale; with every retake kept whole that left anything unrefined,
    6.7e-5 at 3 m/s). 0 is the measured value: the ledger finds no fall at all."""
    from stress_3d import ball_on_box

    summary = run(ball_on_box(v, "corner").sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    assert created(summary) <= 1e-9  # (the first test's round-off bound)
    assert summary["localization_cost"]["subdivided_steps"] >= 1
    assert summary["localization_cost"]["retakes_kept_whole"] == 0
