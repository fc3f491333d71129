"""A peg between two boundary nodes of a 2D solid held by node rows (``nodes`` named) is seen
by the run's penetration record."""

import numpy as np

from fecontact import Model
from fecontact.bodies import LinearElastic, Solid
from fecontact.contact import Circle, Contact
from fecontact.contact.node_pairs import NodeContact

R = 0.05


def test_peg_between_nodes_is_measured():
    disk = Solid.disk([0.0, 0.0], R, 2, LinearElastic(1e6, 0.3, rho=1000.0))
    facets = disk.boundary_facets()
    a, b = disk.X[facets[0, 0]], disk.X[facets[0, 1]]
    mid = 0.5 * (a + b)
    n = mid / np.linalg.norm(mid)  # outward, the disk is centred at the origin
    r, into = 0.2 * R, 0.004  # the peg overlaps the edge's midpoint by 4 mm
    circle = Circle(mid + (r - into) * n, r)
    pair = Contact(disk, circle, nodes=disk.boundary_nodes())
    model = Model([disk], [pair], (0.0, 0.0))
    assert isinstance(pair, NodeContact)
    # both nodes stay outside the peg: their rows see nothing
    assert np.all(pair.gaps(np.zeros(model.n)) > 0.0)
    depth, _ = pair.watch().depth(np.zeros(model.n))
    # exact geometry: the centre's distance to the straight edge is r − 4 mm (round-off)
    assert abs(depth - into) < 1e-12
