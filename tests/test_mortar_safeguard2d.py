"""The 2D pointwise safeguard rows: a node held under a vertex of the other solid's face reads
the smooth maximum of the two segments around it, not one of them, with exact derivatives."""

import math

import numpy as np

from fecontact import Model
from fecontact.bodies import Solid
from fecontact.bodies.meshes import rectangle_mesh
from fecontact.contact import Contact
from fecontact.contact.mortar_safeguard import SMOOTHING
from fecontact.contact.mortar_safeguard2d import DeepNodeRows2D
from fecontact.scenes import solid_material
from fecontact.testing import gap_derivatives_error


def corner_over_dent(dent: float):
    """A square of 4 cm turned 45° (4 × 4 cells), its lowest corner on the top face of a
    finer block (10 × 10 cells of 8 mm) at the block's vertex (0, 0), that vertex pushed
    ``dent`` (m) down: the face is a symmetric V there. Returns the model, the rows of the
    square's nodes against the block's surface, the corner's row and q's dofs of the corner."""
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    block = Solid(rectangle_mesh([-0.04, -0.08], [0.04, 0.0], 10), mat)
    mesh = rectangle_mesh([-0.02, -0.02], [0.02, 0.02], 4)
    c = math.cos(math.pi / 4)
    p = np.array([[c, -c], [c, c]]) @ mesh.p + np.array([[0.0], [0.02 * math.sqrt(2)]])
    square = Solid(type(mesh)(p, mesh.t), mat)
    pair = Contact(square, block, method="mortar")
    model = Model([square, block], [pair], gravity=(0.0, 0.0))
    pair.detect_within(0.005)
    rows = pair.master_rows if pair.master_rows.body is square else pair.pointwise
    q = np.zeros(model.n)
    vertex = int(np.argmin(np.linalg.norm(block.X, axis=1)))
    q[model.offset_of(block) + block.node_translation_dofs(np.array([vertex]))[0]] = [0, -dent]
    corner = int(np.argmin(square.X[:, 1]))
    j = int(np.flatnonzero(rows.nodes == corner)[0])
    dofs = model.offset_of(square) + square.node_translation_dofs(np.array([corner]))[0]
    return model, rows, j, q, dofs, square.X[corner]


def test_a_corner_held_under_the_vertex_of_a_dent_is_pushed_along_its_axis():
    """The square's corner (a node of the mortar's master) 0.1 mm under the vertex of a
    0.3 mm dent of the block's face (2.5 δ deep, slopes ±0.0375): the two segments of the
    V tie. A row of the closest segment alone took one of them and pushed the corner along
    its tilted normal, sideways by 0.0375 of its force (the sign decided by the tie); the
    smooth maximum of the two is their mean normal, straight up. Off the vertex the push
    turns toward it, continuously, and the row's derivatives are exact."""
    dent = 3e-4
    model, rows, j, q, dofs, x0 = corner_over_dent(dent)
    assert isinstance(rows, DeepNodeRows2D)
    delta, eps = rows.allowance, SMOOTHING * rows.allowance
    depth = 1e-4
    at = q.copy()
    at[dofs] = np.array([0.0, -dent - depth]) - x0
    g, _, G, _ = rows.evaluate(at)
    slope = dent / 0.008
    behind = -depth / math.sqrt(1.0 + slope**2)  # (the plane gap of either segment)
    # the two planes' tie reads ε ln 2 shallower; each foot lies s d beyond the vertex,
    # inside the excess's ramp (s d)² / 2δ: the row within 1e-3 δ of that sum
    foot = slope * depth / math.sqrt(1.0 + slope**2)
    expected = behind + eps * math.log(2.0) - foot**2 / (2.0 * delta) + delta
    assert abs(g[j] - expected) <= 1e-3 * delta
    # the mirror-symmetric planes: their x parts cancel to round-off (the old row: 0.0375)
    assert abs(G[j, 0]) <= 1e-12 and G[j, 1] > 0.99
    for dx in (1e-6, 1e-5, 4e-5, 1e-4):  # to the right: pushed back left, never right
        at[dofs] = np.array([dx, -dent - depth]) - x0
        G = rows.evaluate(at)[2]
        assert -0.2 < G[j, 0] < 0.0
    # central differences, step 1e-9 m against ε = 4 µm: truncation ~(h/ε)² relative
    err_g, err_h = gap_derivatives_error(rows, at, 1e-9)
    assert err_g < 1e-6 and err_h < 1e-4


def test_the_row_of_a_corner_mid_segment_is_its_segment_s_plane_gap():
    """The corner 0.1 mm under the middle of a flat segment of the block's face: the
    neighbouring segment's plane through the near vertex is as deep, but its foot lies 4 mm
    beyond that segment's end, and the row is the segment's own plane gap, exactly."""
    model, rows, j, q, dofs, x0 = corner_over_dent(0.0)
    at = q.copy()
    at[dofs] = np.array([0.004, -1e-4]) - x0
    g, _, G, _ = rows.evaluate(at)
    assert abs(g[j] - (-1e-4 + rows.allowance)) <= 1e-15
    assert np.array_equal(G[j, :2], [0.0, 1.0])
