"""A peg between two boundary nodes of a 2D solid, or two nodes of a beam (a Sphere between
a rod's), held by node rows (``nodes`` named) is seen by the run's penetration record."""

import numpy as np
import pytest

from fecontact import Model
from fecontact.bodies import Beam2D, Beam3D, LinearElastic, Material, Section, Solid
from fecontact.contact import Circle, Contact, Sphere
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


@pytest.mark.parametrize("dim", [2, 3])
def test_peg_between_beam_nodes_is_measured(dim):
    # a strip of 4 elements (25 cm) whose named nodes a 1 cm peg presses mid-element (a rod
    # and a Sphere in 3D): the rows see the nodes 12.5 cm away, the watch the peg's 3 mm
    # into the 5 mm half thickness
    steel, section = Material(210e9, rho=7850.0), Section.rectangle(0.02, 0.01)
    if dim == 2:
        beam = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 4, steel, section)
        peg = Circle([0.375, -0.012], 0.01)
    else:
        beam = Beam3D.straight([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 4, steel, Section.circle(0.005))
        peg = Sphere([0.375, 0.0, -0.012], 0.01)
    pair = Contact(beam, peg, nodes=np.arange(5), clearance=0.005)
    model = Model([beam], [pair], (0.0,) * dim)
    assert isinstance(pair, NodeContact)
    assert np.all(pair.gaps(np.zeros(model.n)) > 0.0)
    depth, relative = pair.watch().depth(np.zeros(model.n))
    # exact geometry: 1 cm + 5 mm less the centre's 1.2 cm from the centreline (round-off)
    assert abs(depth - 0.003) < 1e-12
    assert abs(relative - 0.003 / 0.25) < 1e-12
