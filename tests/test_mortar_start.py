"""The start of two solids in a dual mortar interface: admitted unless a node of either body
lies inside the other, by the nodes' exact distances, not by the weighted gaps (which read a
stand-off below zero under a fine curved master where no node is inside)."""

import re

import numpy as np
import pytest

from fecontact import Model, Solid
from fecontact.bodies import LinearElastic
from fecontact.contact import Contact
from fecontact.contact.contact_set import admissible_gaps
from fecontact.contact.inside import Surface
from fecontact.errors import InputError
from fecontact.time.state import initial_state

RUBBER = LinearElastic(1e7, 0.3, rho=1000.0)
R = 0.05


def block_under_ball(pole=(0.0, 0.0), element="P1", layers=4):
    """A coarse block 0.2 × 0.2 m (8 × 8 cells, ``layers`` through 0.1 m; 4 × 4 × 1 cells of a
    slab 4 cm thick for P2), its top z = 0, named the slave, under a fine ball (R = 5 cm,
    refinements 2) whose pole is 1 mm above the top at ``pole``."""
    if element == "P2":
        block = Solid.box([-0.1, -0.1, -0.04], [0.1, 0.1, 0.0], (4, 4, 1), RUBBER, element="P2")
    else:
        block = Solid.box([-0.1, -0.1, -0.1], [0.1, 0.1, 0.0], (8, 8, layers), RUBBER)
    ball = Solid.ball([pole[0], pole[1], R + 0.001], R, 2, RUBBER)
    model = Model([block, ball], [Contact(block, ball, method="mortar")], (0.0, 0.0, -9.81))
    return model, model.contacts.pairs[0], block, ball


@pytest.mark.parametrize(
    "pole, element", [((0.0, 0.0), "P1"), ((0.1, 0.1), "P1"), ((0.0, 0.0), "P2")]
)
def test_a_coarse_slave_under_a_fine_ball_starts_with_a_warning(pole, element):
    """The block's weighted gaps read −1.6e-4 m (face, P1 and P2) and −1.9e-4 m (the ball
    over the corner) with no node of either body inside the other: admitted, warned of the
    stand-off (it was refused as a penetration)."""
    model, pair, block, _ = block_under_ball(pole, element)
    assert pair.body is block
    q = np.zeros(model.n)
    g = model.contacts.gaps(q)
    assert g.min() < -1e-4  # the stand-off, 16 % of the 1 mm the bodies are apart
    # no node inside: each row reads its own gap where it is not negative, 0 where it is
    admitted = admissible_gaps(model.contacts, q, g)
    np.testing.assert_array_equal(admitted, np.maximum(g, 0.0))
    with pytest.warns(UserWarning, match="stand-off"):
        initial_state(model, accelerate=False)


def test_2d_two_coarse_disks_closer_than_their_stand_off_start_with_a_warning():
    """Two disks (R = 5 cm, refinements 2) 0.5 mm apart, vertex to vertex: the left disk's
    vertex row reads −6.2e-5 m (the stand-off on coarse polygons), no node inside: admitted,
    warned (it was refused, "contact 0 penetrates by 6.238e-05 m")."""
    left = Solid.disk([-R - 0.00025, 0.0], R, 2, RUBBER)
    right = Solid.disk([R + 0.00025, 0.0], R, 2, RUBBER)
    model = Model([left, right], [Contact(left, right, method="mortar")], gravity=(0.0, 0.0))
    q = np.zeros(model.n)
    g = model.contacts.gaps(q)
    assert g.min() < -6e-5
    np.testing.assert_array_equal(admissible_gaps(model.contacts, q, g), np.maximum(g, 0.0))
    with pytest.warns(UserWarning, match="stand-off"):
        initial_state(model, accelerate=False)


def refused_depth(model, q) -> tuple[int, float]:
    """The contact and the depth (m) that ``initial_state`` names in refusing q."""
    with pytest.raises(InputError, match=r"contact \d+ penetrates by") as info:
        initial_state(model, q, accelerate=False)
    j, depth = re.search(r"contact (\d+) penetrates by (\S+) m", str(info.value)).groups()
    return int(j), float(depth)


def pushed(model, body, node: int, shift: np.ndarray) -> np.ndarray:
    """q with the ``node`` of ``body`` moved by ``shift`` (m)."""
    q = np.zeros(model.n)
    q[model.offset_of(body) + body.node_translation_dofs(np.array([node]))[0]] = shift
    return q


@pytest.mark.parametrize("element", ["P1", "P2"])
def test_a_slave_node_pushed_into_the_ball_is_refused(element):
    """The block's node under the pole lifted 2 mm: its apex 0.96 mm deep in the faceted
    ball, the ball's pole 0.99 mm inside the tent the apex raises. Refused, naming the deeper
    of the two exact depths and a row of the tent's facets."""
    model, pair, block, ball = block_under_ball(element=element)
    node = int(np.argmin(np.linalg.norm(block.X, axis=1)))
    q = pushed(model, block, node, [0.0, 0.0, 0.002])
    top = block.X[[node]] + [0.0, 0.0, 0.002]
    apex = -Surface(ball.contact_facets()).signed_distance(ball.X, top)[0][0]
    xb = block.positions(q[model.offset_of(block) : model.offset_of(block) + block.ndof])
    lowest = ball.X[[np.argmin(ball.X[:, 2])]]
    pole = -Surface(block.contact_facets()).signed_distance(xb, lowest)[0][0]
    assert 0.9e-3 < apex < pole <= 1e-3
    j, reported = refused_depth(model, q)
    assert reported == float(f"{pole:.3e}")
    assert j < pair.size  # a row of the interface, a corner of a facet of the tent
    assert np.linalg.norm(block.X[pair.nodes[j]] - block.X[node]) < 0.05


@pytest.mark.parametrize("element", ["P1", "P2"])
def test_the_ball_pushed_into_the_slave_is_refused(element):
    """The ball's pole lowered 2 mm, 1 mm under the block's flat top: refused by the rows of
    the block's facet the pole entered, at the pole's depth."""
    model, pair, block, ball = block_under_ball(element=element)
    pole = int(np.argmin(ball.X[:, 2]))
    j, depth = refused_depth(model, pushed(model, ball, pole, [0.0, 0.0, -0.002]))
    assert depth == pytest.approx(1e-3, rel=1e-3)  # (the message's 4 digits)
    assert j < pair.size  # a row of the interface, a node of the facet over the pole
    assert np.linalg.norm(block.X[pair.nodes[j], :2] - ball.X[pole, :2]) < 0.05


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("who", ["block", "disk"])
def test_2d_a_node_pushed_into_the_other_solid_is_refused(element, who):
    """A coarse block under a fine disk (1 mm apart: admitted without a warning); the
    block's node under the pole lifted 2 mm, or the disk's lowest node lowered 2 mm, is
    refused at about 1 mm deep."""
    options = {"element": "P2"} if element == "P2" else {}
    block = Solid.rectangle([-0.1, -0.1], [0.1, 0.0], (4, 2), RUBBER, **options)
    disk = Solid.disk([0.0, R + 0.001], R, 3, RUBBER, **options)
    model = Model([block, disk], [Contact(block, disk, method="mortar")], (0.0, -9.81))
    initial_state(model, accelerate=False)
    if who == "block":
        q = pushed(model, block, int(np.argmin(np.linalg.norm(block.X, axis=1))), [0.0, 0.002])
    else:
        q = pushed(model, disk, int(np.argmin(disk.X[:, 1])), [0.0, -0.002])
    j, depth = refused_depth(model, q)
    assert j < model.contacts.pairs[0].size  # a row of the interface
    # 1 mm, less the disk's sag beside its lowest node for the block's node (the disk is
    # the slave: the finer side); never deeper than the 1 mm the node was pushed past
    assert 0.99e-3 < depth <= 1e-3
