"""Which 2D mortar nodes take part: a node whose segments the master covers more does not leave.

A node takes part when its covered weight W_j = Σ_e ∫_covered N_j ds is at least half of its
covered segments' weight. Counted whole, a segment covered by a sliver at the node's own end
doubled that weight at once: the node at the edge of a contact zone, its inner segment covered
and shorter than the outer one (compressed), dropped out as the outer segment began to be
covered (W_j / Σ = |e_1| / (|e_1| + |e_2|) < ½), while it was pressed in. On the mortar disks
at 29 m/s, Δx/c, head-on (``benchmarks/stress_2d.py``) the row left its node to the pointwise
safeguard and came back 8.6e-5 m deep, a closing no instant could be found for: the
run created 9.1e-4 of its scale. A segment now counts up to the farthest covered point from
the node (``mortar_interface.segment_reach``).
"""

import numpy as np
import pytest

from fecontact import Contact, Model
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.contact.mortar_interface import segment_reach

RUBBER = NeoHookean(1e7, 0.3, 1000.0)


@pytest.mark.parametrize(("a", "b"), [(-1.0, 1.0), (-1.0, 0.2), (-0.4, 1.0), (-0.5, 0.3)])
def test_segment_reach_from_the_covered_weights(a, b):
    """A segment of length 2 (share 1 per end) covered on [a, b]: ∫_a^b N_0 dξ and ∫_a^b N_1
    dξ give back ∫_{−1}^{b} N_0 dξ and ∫_{a}^{1} N_1 dξ (exact: the moments of an interval)."""
    w0 = 0.5 * ((b - a) - 0.5 * (b * b - a * a))
    w1 = 0.5 * ((b - a) + 0.5 * (b * b - a * a))
    reach = segment_reach(np.ones((1, 2)), np.array([w0]), np.array([w1]))[0]
    expected = (0.5 * ((b + 1.0) - 0.5 * (b * b - 1.0)), 0.5 * ((1.0 - a) + 0.5 * (1.0 - a * a)))
    np.testing.assert_allclose(reach, expected, rtol=0.0, atol=1e-15)  # (round-off)


def test_a_node_stays_as_the_master_covers_more_of_its_segments():
    """A block's face 0.1 mm below a 10-segment slave face, its end moving over a slave node
    whose left segment is 10 % shorter than its right one (the node moved by 1 mm): once the
    node takes part (the end 0.29 of its segment before it: (1 − 0.29)² ≥ ½), it stays while
    the block goes on over it; it dropped out for the 0.5 mm after the end passed it."""
    slave = Solid.rectangle([0.0, 0.0], [0.1, 0.02], (10, 2), RUBBER)
    master = Solid.rectangle([-0.1, 0.0201], [0.03, 0.04], (4, 2), RUBBER)
    pair = Contact(slave, master, method="mortar")
    model = Model([slave, master], [pair], gravity=(0.0, 0.0))
    assert pair.body is slave
    node = int(np.argmin(np.linalg.norm(slave.X - [0.05, 0.02], axis=1)))
    row = int(np.flatnonzero(pair.nodes == node)[0])
    q = np.zeros(model.n)
    s, m = model.body_slice(0), model.body_slice(1)
    u = np.zeros_like(slave.X)
    u[node, 0] = -0.001
    q[s] = u.ravel()
    taking = []
    for end in np.linspace(0.045, 0.055, 201):
        q[m] = np.tile([end - 0.03, 0.0], master.n_nodes)
        taking.append(bool(np.isfinite(pair.gaps(q)[row])))
    first = taking.index(True)
    assert 0.045 + first * 5e-5 < 0.049 - 0.25 * 0.009  # (it joins before the end reaches it)
    assert all(taking[first:])
