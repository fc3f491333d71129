"""Bodies at rest on a plane for 10 s: gap exactly 0, no drift, no chatter, and the work per
step stays flat (issue: resting contact)."""

import numpy as np
import pytest
from conftest import load_case

from fecontact import Beam2D, Contact, Material, Model, Plane, Section, simulate


def rest(model, dt, t_end, speed):
    gaps, speeds, its = [], [], []
    for st in simulate(model, dt, t_end):
        if st.step == 0:
            continue
        gaps.append(st.gaps.min())
        speeds.append(speed(st))
        its.append(st.newton_iterations)
    return np.array(gaps), np.array(speeds), np.array(its)


def flat_work(its):
    """Iterations per step over the last second are no more than over the second one (the
    first holds the settling of round-off from the initial state: 2.74 then 2.90 per step
    for the strip, then 2.90 every second up to 10 s)."""
    n = len(its) // 10
    early = its[n : 2 * n]
    return its[-n:].mean() <= early.mean() + 1e-12 and its[-n:].max() <= early.max()


def test_ball_resting_on_the_plane_for_ten_seconds():
    sim = load_case("bouncing_ball").build(height=0.0)
    gaps, speeds, its = rest(sim.model, 1e-3, 10.0, lambda st: np.abs(st.v).max())
    assert gaps.min() >= -1e-10 and np.abs(gaps).max() <= 1e-10
    assert speeds.max() < 1e-10
    assert flat_work(its)


@pytest.mark.slow
def test_beam_lying_on_the_plane_for_ten_seconds():
    """A 20-element strip lying flat on a plane under gravity: every node in contact."""
    beam = Beam2D.straight(
        [0, 0], [0.4, 0], 20, Material(70e9, 2700, 0.33), Section.rectangle(0.02, 0.002)
    )
    model = Model([beam], [Contact(beam, Plane([0, 0], [0, 1]))])
    gaps, speeds, its = rest(model, 1e-3, 10.0, lambda st: np.abs(st.v).max())
    assert gaps.min() >= -1e-10
    assert np.abs(gaps).max() <= 1e-10  # stays in contact: no lift-off, no chatter
    assert speeds.max() < 1e-10
    assert flat_work(its)
