"""A P2 box laid on a P2 slab with mortar on the curved faces (``MortarContact3DP2``): its side
faces stand at 90° to the slab's top. The pairs' facing weight (``mortar3d.TURNED``) keeps
them out of the rows continuously, and a node whose faces are covered by less than
``mortar_p2.SMALLEST`` takes no part (docs/explanation/mortar.md, *A face against a face at
90°*)."""

import numpy as np

from fecontact.bodies import Solid
from fecontact.contact.mortar3d_p2 import MortarContact3DP2
from fecontact.contact.mortar_p2_triangles import p2_triangle_integrals
from fecontact.model import Model
from fecontact.scenes import solid_material

MAT = solid_material("linear", 1e7, 0.3, 1e3)


def p2_box_on_slab(sink: float = 0.0):
    """A 2 × 2 × 1 cm P2 box on a 4 × 4 × 1 cm P2 slab, sunk into it by ``sink`` (m)."""
    slab = Solid.box([-0.02, -0.02, -0.01], [0.02, 0.02, 0.0], (2, 2, 1), MAT, element="P2")
    low = -sink
    box = Solid.box([-0.01, -0.01, low], [0.01, 0.01, low + 0.01], (2, 2, 1), MAT, element="P2")
    pair = MortarContact3DP2(box, slab)
    model = Model([box, slab], [pair], gravity=(0.0, 0.0, 0.0))
    return box, pair, model


def test_rows_of_a_p2_box_on_a_slab_do_not_follow_the_roundoff_of_its_side_faces():
    # moved at random by 1e-8 m (1e-6 of a cell), the box's side faces turn by 1e-6 rad
    # about 90° to the slab. Before, pairs of side faces facing by round-off entered the
    # rows: side nodes took part with a row of gap 0 and gradient 0 (the faces covered by
    # less than SMALLEST, whose weighted gaps are zero; the run stopped at its first step,
    # "no positive effective mass"), and the corner rows' gradients jumped by up to 2.7
    # times between draws. Now the rows are the 25 nodes of the bottom face in every draw
    # and their gradients those at rest to 1e-3 relative (measured 8.7e-6: the draws move
    # them by the rows' curvature over 1e-8 m; before, changes of order 1)
    box, pair, model = p2_box_on_slab()
    pair.detect_within(1e-3)
    g, dofs, G, _ = pair.evaluate(np.zeros(model.n))
    bottom = np.flatnonzero(np.isclose(box.X[pair.nodes, 2], 0.0))
    assert len(bottom) == 25 and np.array_equal(np.flatnonzero(np.isfinite(g)), bottom)

    def dense(dofs, G):  # the rows' gradients over the model's dofs
        return np.stack([np.bincount(dofs[j], G[j], model.n) for j in bottom])

    at_rest = dense(dofs, G)
    size = np.linalg.norm(at_rest, axis=1)
    rng = np.random.default_rng(0)
    for _ in range(4):
        q = rng.normal(0.0, 1e-8, model.n)
        g1, dofs1, G1, _ = pair.evaluate(q)
        assert np.array_equal(np.flatnonzero(np.isfinite(g1)), bottom)
        change = np.linalg.norm(dense(dofs1, G1) - at_rest, axis=1) / size
        assert change.max() <= 1e-3


def steep_pairs(slopes, bulge: float):
    """z (P, 36) of pairs of 6-node faces: a slave face in the plane z = 0 (legs 1 cm, normal
    +z) under a master face standing above it, turned by an angle whose cosine c is
    ``slopes``/√(1 + slope²) from the vertical (c = −n_s·n_m); the edge nodes of both moved
    by ``bulge`` (m) at random (curved faces)."""
    rng = np.random.default_rng(5)
    rows = []
    for slope in slopes:
        a, b = np.array([0.002, 0.002, 0.001]), np.array([0.002, 0.007, 0.001])
        c = np.array([0.002 + 0.01 * slope, 0.0045, 0.011])
        faces = [
            np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0]]),
            np.stack([a, b, c]),
        ]
        for x in faces:
            mid = 0.5 * (x + np.roll(x, -1, axis=0)) + rng.normal(0.0, bulge, (3, 3))
            rows.append(np.concatenate([x, mid]).ravel())
    return np.array(rows).reshape(len(slopes), 36)


def test_the_facing_weight_of_p2_faces_has_exact_derivatives():
    # steep pairs of faces (curved by 1e-6 m), c = 0.05 to 0.2: between 90° and 104.5°, the
    # weight's band, where φ(c) scales their integrals. Their Jets (gradients and Hessians)
    # against central differences of 1e-7 m along a random direction, as for the curved
    # faces (test_mortar_p2.py): measured 8e-8 and 1.7e-6 relative (the differences'
    # truncation on pairs this steep); bounds about 100 times that. The weight's own
    # derivatives left out read 0.5 to 2
    z = steep_pairs([0.05, 0.1, 0.15, 0.2], 1e-6)
    moments, _, coverage, _, _ = p2_triangle_integrals(z, True)
    assert np.all(coverage > 0.0)
    dz = np.random.default_rng(2).normal(size=z.shape)
    eps = 1e-7
    plus, minus = (p2_triangle_integrals(z + s * eps * dz, False)[0] for s in (1.0, -1.0))
    for j, a, b in zip(moments, plus, minus, strict=True):
        slope = np.einsum("pi,pi->p", j.g, dz)
        assert np.max(np.abs((a.v - b.v) / (2 * eps) - slope)) <= 1e-5 * np.max(np.abs(slope))
        curve = np.einsum("pij,pj->pi", j.h, dz)
        assert np.max(np.abs((a.g - b.g) / (2 * eps) - curve)) <= 1e-4 * np.max(np.abs(curve))
