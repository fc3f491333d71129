"""Rows' Hessians of quadratic (P2) faces covered in part by several master faces: the dual
functions of a covered part depend on every pair of the face, so a row's Hessian couples the
pairs (``mortar_p2._coupled_hessians``). A P2 box tilted 5° with an edge in a P2 slab has
its lowered side face covered by slivers of the slab's faces; without the coupling its edge
rows' Hessians were wrong by their own size and Newton's method diverged at the edge
landing (docs/explanation/mortar.md, *A face covered by several pairs*)."""

import numpy as np
import skfem

from fecontact.bodies import Solid
from fecontact.bodies.meshes import box_mesh
from fecontact.contact.mortar3d_p2 import MortarContact3DP2
from fecontact.model import Model
from fecontact.scenes import solid_material

MAT = solid_material("linear", 1e7, 0.3, 1e3)


def tilted_box_in_slab(tilt: float = 5.0, sink: float = 1e-6, shift=(1.37e-3, 0.71e-3)):
    """A 2 × 2 × 1 cm P2 box turned by ``tilt`` degrees about y, its lowest edge ``sink``
    (m) into a 6 × 4 × 1 cm P2 slab (3 × 2 × 1 cells), moved by ``shift`` (m) in plan (no
    edge of the box over a node or an edge of the slab's)."""
    slab = Solid.box([-0.03, -0.02, -0.01], [0.03, 0.02, 0.0], (3, 2, 1), MAT, element="P2")
    mesh = box_mesh([-0.01, -0.01, -0.005], [0.01, 0.01, 0.005], (2, 2, 1))
    a = np.radians(tilt)
    p = np.array([[np.cos(a), 0.0, np.sin(a)], [0.0, 1.0, 0.0], [-np.sin(a), 0.0, np.cos(a)]])
    p = p @ mesh.p
    p[2] -= sink + p[2].min()
    p[:2] += np.asarray(shift)[:, None]
    box = Solid(skfem.MeshTet(p, mesh.t), MAT, element="P2")
    pair = MortarContact3DP2(box, slab)
    return pair, Model([box, slab], [pair], gravity=(0.0, 0.0, 0.0))


def test_rows_hessians_couple_the_pairs_of_a_face_covered_in_part():
    # the lowered side face is covered by 0.2-10 % in slivers of several slab faces; the
    # rows of the lowest edge's nodes off the corners (the corners also bound the faces at
    # exactly 90° to the slab, whose slivers switch there: their gradients jump, not traced
    # here), their second derivatives along a random direction d against central
    # differences of their gradients: before, off by 0.5-1.0 of their size; measured now
    # 7e-9 (step 1e-8 m along d of unit entries: truncation ~1e-8 of the rows' curvature
    # scale, round-off of G ~1e-16/1e-8 against H d ~ 1e3-1e4; the bound 1e-5 holds on any
    # machine)
    pair, model = tilted_box_in_slab()
    pair.detect_within(1e-3)
    rng = np.random.default_rng(2)
    q = rng.normal(0.0, 1e-7, model.n)
    g, dofs, G, _ = pair.evaluate(q)
    x = pair.body.X[pair.nodes]
    low = x[:, 2] < x[:, 2].min() + 1e-6  # the lowest edge's five nodes
    inner = np.abs(x[:, 1] - x[low, 1].mean()) < 0.009  # (off the corners)
    rows = np.flatnonzero(low & inner & np.isfinite(g))
    assert rows.size == 3
    H = pair.hessians(q, rows)
    d = rng.normal(0.0, 1.0, model.n)
    eps = 1e-8
    up, down = (pair.evaluate(q + s * eps * d)[2][rows] for s in (1.0, -1.0))
    Hd = np.einsum("rkl,rl->rk", H, d[dofs[rows]])
    # (a dof listed twice in a row: its entries add)
    fd = np.stack([np.bincount(dofs[j], up[i] - down[i], model.n) for i, j in enumerate(rows)])
    hd = np.stack([np.bincount(dofs[j], Hd[i], model.n) for i, j in enumerate(rows)])
    err = np.linalg.norm(fd / (2.0 * eps) - hd, axis=1) / np.linalg.norm(hd, axis=1)
    assert err.max() < 1e-5, err
