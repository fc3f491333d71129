"""A node-to-surface contact with no facet within its detection margin at the start of a
step (g = +inf) that closes within the step is an impact: it gets its impulse."""

import numpy as np

from fecontact import simulate
from fecontact.testing import case


def test_contact_closing_from_beyond_the_margin_gets_its_impulse():
    # coarse disks 12 mm apart at 1 m/s each, one step of 7 ms: the boundary nodes start far
    # outside the search margin of the other disk and end the step in contact
    sim = case("two_disks").build(
        refinements=1, gap=0.012, restitution=1.0, method="node-to-surface"
    )
    start, step = list(simulate(sim.model, 7e-3, 7e-3, sim.options, v0=sim.v0))
    closed = np.isfinite(step.gaps) & (step.gaps <= 1e-12)
    assert np.all(np.isinf(start.gaps[closed]))  # no facet near any of them at t = 0
    assert closed.any() and np.all(step.impulse[closed] >= 0.0)
    assert step.impulse.sum() > 0.0  # before: tau = inf/inf = NaN, and no impulse at all
