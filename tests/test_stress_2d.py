"""Planar contact beyond the cases: regression tests of what the sweep
(``benchmarks/stress_2d.py``) found broken, each on a small mesh."""

import numpy as np

from fecontact import simulate
from fecontact.testing import case


def test_frictional_disks_whose_safeguard_row_lets_go_complete():
    # off-centre disks with friction and e_N = 0.5 (refinements 2): a node held by the
    # mortar interface's frictionless pointwise safeguard is released in a step; the slip
    # rows of that release hold no frictional contact, and the retake must still take its
    # force out (it stopped with a ValueError in the slip rows' shapes)
    sim = case("two_disks").build(refinements=2, offset=0.015, friction=0.3, restitution=0.5)
    states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options, v0=sim.v0))
    assert states[-1].t == sim.t_end or np.isclose(states[-1].t, sim.t_end)
    vx = [float(np.mean(b.nodal(states[-1].v[sim.model.body_slice(i)])[:, 0]))
          for i, b in enumerate(sim.model.bodies)]  # fmt: skip
    assert vx[0] < 0.0 < vx[1]  # they have struck and part
