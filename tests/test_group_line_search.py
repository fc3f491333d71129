"""The smooth step's line search on a Lie group (fecontact.time.descent): a beam struck in
its plane takes the planar step's cuts, update for update."""

import numpy as np
from conftest import load_case

from fecontact.testing import trace


def test_the_spatial_pendulum_rebounding_at_half_restitution_is_its_planar_twin():
    # the case matrix's e_N = 0.5 row in space: at 0.322 s Newton's first update (1.9 m on
    # a node, the strip just struck) was taken whole, the step converged to a state 5.4 J
    # above the run's energy and the run blew up at 0.325 s; the planar step cuts it to a
    # quarter. Through the strike, the rebound and the second approach (0.6 s, the case
    # matrix's end) the twin's tip to 1e-6 m, the bound asked of the twin (measured 3e-15 m)
    flat = trace(load_case("flexible_pendulum").build(restitution=0.5), t_end=0.6)
    space = trace(load_case("spatial_pendulum").build(restitution=0.5), t_end=0.6)
    assert space["status"] == flat["status"] == "completed"
    for q in ("tip_x", "tip_y"):
        np.testing.assert_allclose(space[q], flat[q], rtol=0, atol=1e-6)
    assert np.abs(space["tip_z"]).max() == 0.0
