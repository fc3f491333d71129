r"""The solid's rows of the tube mortar blended toward the tube's tangent plane: the form for
solid faces finer than the tube (:func:`~fecontact.contact.tube_line_mortar.tube_mortar`).

The dual-weighted distance to the tube (:class:`~fecontact.contact.mortar_beam3d.MortarBeam3D`)
holds ∫ Φ_j D dA₀, not D at each point: over a face under a straight tube D grows as y²/(2r)
to the side (y the offset from the contact line), the dual functions' negative lobes weigh that
growth, and the tube rests where the rows of the nodes near the line are zero, above or below
the face by up to 0.08 H²/r (H the cells' width), by an amount that moves with the tube's place
on the mesh: a washboard of period H that a rolling rod rides (0.64 mm high for r = 2 cm on
1 cm cells). Here each row j is blended toward its node's gap from the plane tangent to the
tube and parallel to the node's face,

    g_j ← g_j + w_j (P_j − g_j),   P_j = ν_j·(p_j − x_j) − r,

with p_j the node's closest point on the centreline (its closest segment, ξ clamped) and ν_j
the node's outward face normal (the area-weighted normal of its triangles within 45° of the
one facing the axis most squarely). On a flat face under a straight segment parallel to it P
is the same at every node, the tube's own gap from the face's plane: the rows with w_j = 1
read it exactly, wherever the tube lies on the mesh, whatever its angle to the mesh's lines.
Under an end cap P is the cap's exact gap from the plane; under a segment tilted by α to the
face it reads the centreline's height less r, below the exact gap by r(1/cos α − 1) (the
tilted tube's lowest point is at its lower end, whose cap reads exact). P ≤ D everywhere
(|ν_j| = 1): the plane never lets a node into the tube that D would keep out.

w_j = S((c_j − c₀)/(c₁ − c₀)), S the C² smoothstep, c_j = ν_j·(p_j − x_j)/|p_j − x_j| the cosine
of the node's angle under the axis: 1 for nodes within 0.6 of a face cell to the side of the
contact line (c₁ from :data:`SIDE`: a line of nodes of any mesh lies within), 0 beyond 1.2
cells (c₀), where a tangent plane would claim contact for nodes far from the tube. The rows
between read above zero on a flat face (D there is well above the plane), and the least row
is the exact gap. Decided once per pair: H is the face's cell width (:func:`face_size`).

Derivatives: P and w are compositions of a dozen steps; their gradients and Hessians over the
12 local variables (x_j, the area vector of the node's face, the segment's ends a, b) come
from second-order forward differentiation (:mod:`fecontact.contact.jets`), chained through the
area vector's exact derivatives on the star's nodes (the face's triangles and the closest
segment held, as the weighted gaps hold their closest segments). The blend's derivatives
follow the product rule with those of g_j.
"""

from __future__ import annotations

import numpy as np

from ..rotations import hat
from .jets import Jet, dot, variables
from .mortar_beam3d import FACE, MortarBeam3D, row_triangles
from .polyline_distance import closest_on_polyline
from .rigid_distance import SUBDIVISIONS

__all__ = ["SIDE", "TangentPlaneRows", "face_size", "smoothstep", "tangent_plane_gap"]

SIDE = (0.6, 1.2)
"""The offsets from the contact line, in face cells, within which a row is the tangent plane's
gap (w = 1: more than half a cell, so that a line of nodes of any mesh lies within) and beyond
which it is the weighted distance alone (w = 0)."""


def face_size(solid) -> float:
    """The width (m) of a right isosceles triangle of the mean area of the solid's boundary
    triangles: the size of a face's cells, weighed by their area."""
    t = solid.X[solid.contact_facets()]
    area = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
    return float(np.sqrt(2.0 * area.mean()))


def smoothstep(z: Jet) -> Jet:
    """S(z) = 10z³ − 15z⁴ + 6z⁵ on [0, 1], 0 below, 1 above (C²: the rows' curvature has no
    jump where a node enters or leaves the blend)."""
    s = np.clip(z.val, 0.0, 1.0)
    inside = (z.val > 0.0) & (z.val < 1.0)
    value = s**3 * (10.0 - 15.0 * s + 6.0 * s * s)
    first = np.where(inside, 30.0 * s * s * (1.0 - s) ** 2, 0.0)
    second = np.where(inside, 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s), 0.0)
    return z.apply(value, first, second)


def tangent_plane_gap(x, area, a, b, r: float, full: float, none: float):
    """P (m) and the blend's weight w of nodes x (m, 3) with face area vectors ``area``
    (m, 3) against segments (a, b) (m, 3 each), as jets over (x, area, a, b) (module
    docstring; ``full``, ``none`` the cosines c₁, c₀)."""
    X, A, Pa, Pb = variables([x, area, a, b], 12)
    d = Pb - Pa
    xi = dot(X - Pa, d) / dot(d, d)
    inside = ((xi.val > 0.0) & (xi.val < 1.0)).astype(float)
    t = xi.apply(np.clip(xi.val, 0.0, 1.0), inside, np.zeros_like(inside))
    u = Pa + t.scalar() * d - X  # from the node to its closest point on the axis
    nu = A / dot(A, A).sqrt().scalar()
    h = dot(nu, u)
    c = h / dot(u, u).sqrt()
    return h - r, smoothstep((c - none) / (full - none))


class TangentPlaneRows(MortarBeam3D):
    """The solid's rows of a 3D :class:`~fecontact.Solid` against a Beam3D's tube of radius
    ``clearance`` (m, > 0), each blended toward its node's gap from the tube's tangent plane
    parallel to its face (module docstring); the arguments of
    :class:`~fecontact.contact.mortar_beam3d.MortarBeam3D`."""

    def __init__(self, body, beam, restitution=0.0, clearance=0.0, margin=None,
                 subdivisions: int = SUBDIVISIONS):  # fmt: skip
        super().__init__(body, beam, restitution, clearance, margin, subdivisions)
        cell, r = face_size(body), self.clearance
        self.full, self.none = (1.0 / np.sqrt(1.0 + (s * cell / r) ** 2) for s in SIDE)
        m = self.size
        self.triangles = row_triangles(self.element_rows, m)  # (m, K_t), −1 padded
        self.own = np.argmax(self.star == np.arange(m)[:, None], axis=1)  # j in its star
        tri = np.maximum(self.triangles, 0)
        end = np.argmax(self.element_rows[tri] == np.arange(m)[:, None, None], axis=2)
        self.tri_pos = self.star_positions[tri, end]  # (m, K_t, 3) nodes' places in the star
        self.plane_cached = self.plane_gaps = None

    def reset(self) -> None:
        super().reset()
        self.plane_cached = self.plane_gaps = None

    # -- the tangent plane ------------------------------------------------------------------
    def _face(self, x, rows, u):
        """The kept triangles (R, K_t) of each row's face toward the axis (direction u (R, 3))
        and their node positions (R, K_t, 3, 3)."""
        tris = self.triangles[rows]
        real = tris >= 0
        t = x[self.facets[np.maximum(tris, 0)]]
        area = np.cross(t[:, :, 1] - t[:, :, 0], t[:, :, 2] - t[:, :, 0])
        unit = area / np.linalg.norm(area, axis=2)[..., None]
        score = np.where(real, np.einsum("rki,ri->rk", unit, u), -np.inf)
        best = unit[np.arange(len(rows)), np.argmax(score, axis=1)]
        return real & (np.einsum("rki,ri->rk", unit, best) >= FACE), t

    def _geometry(self, q, rows):
        """Per row: its node (R, 3), its closest segment (R,) and ends (R, 3) each, its face's
        kept triangles (R, K_t) and their nodes (R, K_t, 3, 3), the face's area vector
        (R, 3) and the cosine c of the node's angle under the axis (R,)."""
        x, ends = self._frame(q)
        xj = x[self.nodes[rows]]
        seg, xi, d = closest_on_polyline(xj, ends)
        t = np.clip(xi, 0.0, 1.0)[:, None]
        a, b = ends[seg, 0], ends[seg, 1]
        u = (1.0 - t) * a + t * b - xj
        keep, tx = self._face(x, rows, u)
        sides = np.cross(tx[:, :, 1] - tx[:, :, 0], tx[:, :, 2] - tx[:, :, 0])
        area = 0.5 * np.einsum("rk,rki->ri", keep.astype(float), sides)
        c = np.einsum("ri,ri->r", area, u) / (np.linalg.norm(area, axis=1) * d)
        return xj, seg, a, b, keep, tx, area, c

    def _plane(self, q, rows):
        """P and w of ``rows`` as jets over the local variables, and the Jacobian (R, 12, k)
        of those variables on the rows' columns, the kept triangles and their positions."""
        xj, seg, a, b, keep, tx, area, _ = self._geometry(q, rows)
        P, w = tangent_plane_gap(xj, area, a, b, self.clearance, self.full, self.none)
        R, k = len(rows), self.dofs.shape[1]
        J = np.zeros((R, 12, k))
        r3 = np.arange(R)[:, None]
        J[r3, np.arange(3), 3 * self.own[rows, None] + np.arange(3)] = 1.0
        for i, node in enumerate(self.segments[seg].T):  # a, b: the beam's translations
            cols = self._beam_col0 + 3 * node[:, None] + np.arange(3)
            J[r3, 6 + 3 * i + np.arange(3), cols] = 1.0
        pos = self.tri_pos[rows]  # (R, K_t, 3)
        for i in range(3):  # ∂A/∂x_i = −½ hat(x_{i+1} − x_{i+2}) on each kept triangle
            D = -0.5 * hat(tx[:, :, (i + 1) % 3] - tx[:, :, (i + 2) % 3]) * keep[..., None, None]
            cols = 3 * pos[:, :, i, None] + np.arange(3)  # (R, K_t, 3)
            for kk in range(D.shape[1]):
                J[np.arange(R)[:, None, None], 3 + np.arange(3)[None, :, None],
                  cols[:, kk][:, None, :]] += D[:, kk]  # fmt: skip
        return P, w, J, keep, pos

    def _full(self, f: Jet, J, keep, pos, curvature=True):
        """The gradient (R, k) and Hessian (R, k, k; None without ``curvature``) on the rows'
        columns of a jet f over the local variables: Jᵀ∇²f J, plus the area vector's own
        curvature weighted by ∂f/∂A."""
        G = np.einsum("rz,rzk->rk", f.grad, J)
        if not curvature:
            return G, None
        H = np.einsum("rzk,rzy,ryl->rkl", J, f.hess, J)
        Hg = -0.5 * hat(f.grad[:, 3:6])  # (R, 3, 3): ∂²(g·A)/∂x_i∂x_{i+1} on each triangle
        R = len(G)
        for i in range(3):
            ci = 3 * pos[:, :, i, None] + np.arange(3)
            cj = 3 * pos[:, :, (i + 1) % 3, None] + np.arange(3)
            for kk in range(pos.shape[1]):
                block = Hg * keep[:, kk, None, None]
                at = (np.arange(R)[:, None, None], ci[:, kk][:, :, None], cj[:, kk][:, None, :])
                np.add.at(H, at, block)
                at = (np.arange(R)[:, None, None], cj[:, kk][:, :, None], ci[:, kk][:, None, :])
                np.add.at(H, at, block.transpose(0, 2, 1))
        return G, H

    def _blend(self, q, g):
        """The rows taking part with a weight (R,), and P, w, J, kept triangles, positions."""
        rows = np.flatnonzero(np.isfinite(g))
        if rows.size:  # (the jets only where the weight is not zero)
            rows = rows[self._geometry(q, rows)[-1] > self.none]
        if rows.size == 0:
            return rows, None
        P, w, J, keep, pos = self._plane(q, rows)
        on = w.val > 0.0  # (S' = 0 where S = 0: those rows are the weighted gaps alone)
        if not on.any():
            return rows[:0], None
        sub = (Jet(P.val[on], P.grad[on], P.hess[on]), Jet(w.val[on], w.grad[on], w.hess[on]))
        return rows[on], (*sub, J[on], keep[on], pos[on])

    # -- rows -------------------------------------------------------------------------------
    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The rows g_j (m) alone (+inf for rows that take no part)."""
        for cached in (self.plane_cached, self.plane_gaps):
            if cached is not None and np.array_equal(cached[0], q):
                return cached[1].copy()
        g = super().gaps(q)
        rows, terms = self._blend(q, g)
        if terms is not None:
            P, w = terms[:2]
            g[rows] += w.val * (P.val - g[rows])
        self.plane_gaps = (q.copy(), g)
        return g.copy()

    def evaluate(self, q: np.ndarray):
        """Rows (m,) in m, dofs (m, k), gradients (m, k), no curvature (:meth:`hessians`)."""
        if self.plane_cached is not None and np.array_equal(self.plane_cached[0], q):
            return self.plane_cached[1].copy(), self.dofs, self.plane_cached[2], None
        g, dofs, G, _ = super().evaluate(q)
        rows, terms = self._blend(q, g)
        if terms is not None:
            P, w, J, keep, pos = terms
            GP, _ = self._full(P, J, keep, pos, curvature=False)
            Gw, _ = self._full(w, J, keep, pos, curvature=False)
            G = G.copy()
            base = G[rows]
            G[rows] = base + w.val[:, None] * (GP - base) + (P.val - g[rows])[:, None] * Gw
            g[rows] += w.val * (P.val - g[rows])
            G.flags.writeable = False
        self.plane_cached = (q.copy(), g, G)
        return g.copy(), dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the rows ``rows`` at q, in the layout of
        :meth:`evaluate`."""
        rows = np.asarray(rows, dtype=int)
        H = super().hessians(q, rows)
        g, _, G, _ = super().evaluate(q)
        asked = np.full(self.size, np.inf)
        asked[rows] = g[rows]
        blended, terms = self._blend(q, asked)
        if terms is None:
            return H
        P, w, J, keep, pos = terms
        GP, HP = self._full(P, J, keep, pos)
        Gw, Hw = self._full(w, J, keep, pos)
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        at = where[blended]
        dG = GP - G[blended]
        H[at] += (w.val[:, None, None] * (HP - H[at]) + (P.val - g[blended])[:, None, None] * Hw
                  + Gw[:, :, None] * dG[:, None, :] + dG[:, :, None] * Gw[:, None, :])  # fmt: skip
        return H
