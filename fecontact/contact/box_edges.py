r"""A rigid box's edges against the boundary edges of a 3D solid: the rows a solid–box pair
adds for what neither its nodes' rows nor the corners' rows (:mod:`.box_corners`) hold, a box
edge entering the solid's faceted surface between the nodes, away from the box's corners.

Two polyhedral surfaces meet vertex to face, face to vertex or edge to edge. The nodes' rows
hold the first (a node against the box's exact surface), the corners' rows the second; with
both held, a box edge enters the solid only by passing under the solid's boundary edges. Each
boundary edge (c, d) of the solid (a "ridge", between two of its triangles) therefore carries
one row, its signed distance to the box edge (a, b) it crosses, along the common normal of
the two lines (the classical edge–edge contact of polyhedra):

    g = n·(p − y) − clearance,   n = ±(b − a) × (d − c) / |(b − a) × (d − c)|,

p = a + s (b − a) and y = c + t (d − c) the closest points of the two lines, the sign such
that −n points into the box edge's normal cone (the side of its two faces' outward normals).
The row is the edge–edge contact where the closest points lie inside both segments
(0 < s, t < 1) and n lies in both normal cones: −n between the box edge's two face normals,
n between the ridge's two triangles' outward normals (widened by ``CONE``: a flat ridge's cone
is one direction). Elsewhere a ridge by a box edge is no edge–edge contact: a ridge on a box
face beside its edge has lines whose common normal lies along the face, and their distance
(the ridge's offset from the edge along the face) is no penetration. A ridge has ``SLOTS``
rows, for the first box edges it crosses in the box's own order of its edges (one by a corner
passes under two at once, and a row that switched edges with the least gap made Newton
cycle); a row reads +inf without its edge, and where the ridge's midpoint lies farther from
the box than the search distance plus half the ridge's length. Lines nearer
parallel than ``PARALLEL`` have no common normal: their ends hold the contact.

The lines' distance is the depth of the ridge in the box edge's wedge (two half-spaces, in
the plane normal to the edge) only where the ridge does not clear the wedge along one of its
faces' normals with less motion: f = max_i min_j (y_j − a)·a_i, how far the ridge lies in
front of face i at its deeper end (it is straight). A ridge crossing the wedge with both its
ends outside has f ≤ n·(p − y) (the apex's distance to its line is no more than either end's
reach); where f exceeds the lines' distance by more than ``TIE`` ℓ, either a ridge's end is
in the box (its node's own row holds it) or the ridge misses the edge, and the pair has no
row: the lines of a ridge on a face of a solid laid over a box edge, 1 cm from the edge and
parallel to the box's side face, read −1 cm with the ridge wholly in front of the top face
(a rubber box laid over a box's edge was refused at t = 0). The tie keeps the row where the
two are nearly equal: a ridge flat on a face or a node on the edge has them equal up to
round-off, and a ridge from a node on a face by the edge has its line pass under the edge by
the node's distance from it times the ridge's slope, the lines' distance reading that small
false depth until it exceeds the tie (the measured margins of the tie:
``docs/validation/solid_sweep.md``). Within a Newton loop the pairs admitted at its start,
and those admitted at an iterate, are held to its end (:meth:`BoxEdges.hold_rows`): a pair
that came and went between the iterates, as f and the lines' distance cross, would make the
active set cycle.

A row that holds must not vanish within a Newton iteration (the smooth step's active set
cycles between an iterate with the row, pushed out, and one without, falling back in). Where
the closest point leaves the ridge, or −n leaves the box edge's cone, the row goes on as the
lines' distance plus ``RAMP`` ℓ (σ(φ(t)) + σ(ψ)), ℓ the ridge's length, φ(t) = max(0, −t,
t − 1), ψ = max(0, max_i n·a_i) (a_i the box edge's face normals), σ(x) = x²/(2 ``SOFT``)
below ``SOFT`` and x − SOFT/2 above: continuous with its gradient, growing, so the row opens
and the nodes' rows take over; it ends ``REACH`` beyond. The gradient must not jump where the
ramp starts: a ridge pressed flat on a box face beside the edge has its common normal on the
face's normal, ψ = 0 to round-off, and with a kink there round-off chose between two
gradients, the set of the next update and the run's path (k ÷ 100 moved the elastic ball
on a box's edge line by 2.6e-6 of its radius, now by round-off). Beyond the box edge's ends
(s outside (0, 1)) a row ends: there the corner's own row holds, and rows ramped past a
corner met the rows of the corner's other edges and made Newton cycle.

The gradient is exact. Without the ramp the closest points are stationary in s and t, and n
stays normal to both lines (∂n·(p − y) = g ∂n·n − s ∂n·(b − a) + t ∂n·(d − c) with ∂n·n = 0
and ∂n·(b − a) = −n·∂(b − a)), so

    ∂g/∂x_c = −(1 − t) n,   ∂g/∂x_d = −t n,   ∂g/∂u = n,   ∂g/∂Θ = r × (Rᵀ n),

r the body-frame position of p (δp = δu − R r̃ δΘ); the ramp adds the derivatives of t (from
those of the two closest-point conditions) and of ψ (:meth:`BoxEdges._ramp_gradient`).
The curvature is left out (Newton's rate, not its answer), as for the corners. Coulomb
friction, with the coefficient of the pair that brings the rows (``owner``), acts on the slip
of the box's material point at p against the ridge's point y: the rows T·[I, −R r̃,
−(1 − t) I, −t I], T the tangents along the box edge (normal to n) and n × it, applied over a
step to the box's body-frame increment (Δu, log(R_nᵀR)) and the nodes' displacements.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..rotations import cross, exp, hat, log
from .box_corners import FeatureRows
from .friction import tangent_basis
from .rigid_distance import shape_distance

__all__ = ["CONE", "PARALLEL", "RAMP", "REACH", "SLOTS", "SOFT", "TIE", "BoxEdges", "box_edges"]

PARALLEL = 1e-6
"""Smallest |sin| of the angle between a box edge and a ridge for a row: nearer parallel the
common normal is undefined, and the ridge's ends (the nodes' rows) hold the contact."""


RAMP = 2.0
"""The release ramp's slope: beyond the ends of the ridge a row goes on as the lines'
distance plus RAMP ℓ φ (ℓ the ridge's length, φ how far beyond, in units of the ridge),
continuous where the closest point leaves the ridge, so that a row that holds does not vanish
within a Newton iteration: it opens, and the nodes' rows hold the ends."""

SLOTS = 2
"""Rows per ridge: the box edges it crosses, at most two (by a corner) at once."""

CONE = 1e-3
"""How far (rad) the common normal may lie outside the cone of the ridge's two triangles'
normals: a flat ridge's cone is one direction, met by a box edge parallel to it."""

REACH = 0.5
"""How far beyond the ridge's end (in its length), or outside the box edge's cone (n·a_i), the
ramp reaches before the row ends."""


TIE = 1e-4
"""How far (in the ridge's length) the ridge's reach in front of a face of the box edge must
exceed the lines' distance before the pair has no row (module docstring): the false depth a
row may read. A ridge flat on a face, or a node on the edge, has the two equal up to
round-off; a ridge from a node on a face by the edge differs by the node's distance from the
edge times its slope (a few 1e-6 ℓ measured), the far ridge over a box edge by 0.7 ℓ."""

SOFT = 0.05
"""How far (in the units of φ and ψ) the ramp grows quadratically before it grows linearly:
its gradient then starts from zero (module docstring), and a tenth of ``REACH`` leaves the
ramp's reach and slope beyond it as they were."""


def _soft(x: np.ndarray) -> np.ndarray:
    """The ramp of x ≥ 0 (φ or ψ): x²/(2 SOFT) below SOFT, x − SOFT/2 above (C¹ at 0)."""
    return np.where(x < SOFT, 0.5 * x * x / SOFT, x - 0.5 * SOFT)


def _soft_slope(x: np.ndarray) -> np.ndarray:
    """d(:func:`_soft`)/dx: x / SOFT below SOFT, 1 above."""
    return np.minimum(x / SOFT, 1.0)


def _beyond(u: np.ndarray) -> np.ndarray:
    """φ(u) = max(0, −u, u − 1): how far the parameter u lies outside [0, 1]."""
    return np.maximum(np.maximum(-u, u - 1.0), 0.0)


def _slope(u: np.ndarray) -> np.ndarray:
    """d(:func:`_soft` φ)/du: 0 inside [0, 1], growing from 0 at its ends to ∓1."""
    return np.where(u < 0.0, -1.0, 1.0) * _soft_slope(_beyond(u))


def _reach(ends: np.ndarray, A: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """How far (K, 12) the ridges of ends ``ends`` (K, 2, 3) lie in front of the box edges
    through ``A`` (12, 3), of outward face normals ``faces`` (12, 2, 3): f = max_i min_j
    (y_j − A)·a_i, the reach of the deeper end in front of the face it clears most."""
    front = np.einsum("kjd,eid->keij", ends, faces)
    front -= np.einsum("ed,eid->ei", A, faces)[None, :, :, None]  # (K, 12, face, end)
    return front.min(axis=3).max(axis=2)


def box_edges(sides: np.ndarray):
    """A box's twelve edges in its body frame (m): their ends a, b (12, 3) and the outward
    unit normals of their two faces (12, 2, 3)."""
    signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float)
    pairs = [(i, j) for i in range(8) for j in range(i + 1, 8) if np.sum(signs[i] != signs[j]) == 1]
    ends = np.array(pairs)
    a, b = 0.5 * signs[ends[:, 0]] * sides, 0.5 * signs[ends[:, 1]] * sides
    along = np.argmax(signs[ends[:, 0]] != signs[ends[:, 1]], axis=1)
    faces = np.zeros((12, 2, 3))
    for e, k in enumerate(along):
        others = [axis for axis in range(3) if axis != k]
        for i, axis in enumerate(others):
            faces[e, i, axis] = signs[ends[e, 0], axis]
    return a, b, faces


def _ridges(facets: np.ndarray):
    """The boundary edges (N, 2) of the closed triangle surface ``facets`` (F, 3) and the two
    triangles (N, 2) on each."""
    sides = np.sort(facets[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2), axis=1)
    ridges, inverse, counts = np.unique(sides, axis=0, return_inverse=True, return_counts=True)
    if np.any(counts != 2):
        raise InputError(
            "a box's edge rows need the solid's boundary closed (two triangles an edge)"
        )
    order = np.argsort(inverse.ravel(), kind="stable")
    return ridges, (order // 3).reshape(-1, 2)


class BoxEdges(FeatureRows):
    """The twelve edges of the ``Box`` of ``rigid`` (a ``RigidBody3D``) against the boundary
    edges of the 3D solid ``body``: one row per boundary edge (module docstring); arguments
    as :class:`~fecontact.contact.box_corners.FeatureRows`."""

    # a ridge pressed flat on the box's face beside the edge pushes its nodes along the face's
    # normal, as their own rows and the mortar rows do: rows redundant up to round-off, whose
    # LU split the force by round-off amplified by k (minimum-norm μ instead)
    redundant_rows = True
    holds_rows = True  # (the wedge's test, held within a Newton loop: hold_rows)

    def __init__(self, owner, body, rigid, clearance=0.0, margin=None):
        super().__init__(owner, body, rigid, clearance, margin)
        self.a, self.b, self.faces = box_edges(np.asarray(rigid.shape.sides, dtype=float))
        self.ridges, self._sides = _ridges(self.facets)
        self.size = SLOTS * len(self.ridges)
        self._ridge = np.tile(np.arange(len(self.ridges)), SLOTS)  # the ridge of each row
        self._ridge_dofs = body.node_translation_dofs(self.ridges.ravel()).reshape(-1, 6)
        self._ridge_dofs = np.tile(self._ridge_dofs, (SLOTS, 1))
        self.dofs = np.zeros((self.size, 12), dtype=int)
        self._held = None  # the pairs held by hold_rows (ridges, box edges) bool

    def bind(self, model) -> None:
        super().bind(model)
        oa, ob = self.offsets
        box = np.broadcast_to(ob + np.arange(6), (self.size, 6))
        self.dofs = np.concatenate([box, oa + self._ridge_dofs], axis=1)
        self.dofs.flags.writeable = False

    def _near(self, x: np.ndarray, R: np.ndarray, c: np.ndarray) -> np.ndarray:
        """The ridges (K,) whose midpoint lies within the search distance plus half their
        length of the box (no point of a farther ridge is within the search distance)."""
        y0, y1 = x[self.ridges[:, 0]], x[self.ridges[:, 1]]
        D = shape_distance(self.rigid.shape, (0.5 * (y0 + y1) - c) @ R, False)[0]
        return np.flatnonzero(D - 0.5 * np.linalg.norm(y1 - y0, axis=1) <= self.margin)

    def _geometry(self, q: np.ndarray):
        """The solid's node positions x, R, and for every ridge: its gap (N,) (+inf: no row),
        the box edge it takes (N,), the parameters s, t (N,) of the closest points, the
        common normal n (N, 3) and the release ramp (N,) in the gap."""
        (oa, ob), body = self.offsets, self.body
        x = body.positions(q[oa : oa + body.ndof])
        qr = q[ob : ob + 6]
        R, c = exp(qr[3:6]), self.rigid.center(qr)
        N = self.size
        g, edge = np.full(N, np.inf), np.zeros(N, dtype=int)
        s, t, n, ramp = np.zeros(N), np.zeros(N), np.zeros((N, 3)), np.zeros(N)
        near = self._near(x, R, c)
        if near.size:
            rows, found = self._crossings(x, R, c, near)
            g[rows], edge[rows], s[rows], t[rows], n[rows], ramp[rows] = found
        return x, R, g, edge, s, t, n, ramp

    def _crossings(self, x, R, c, near):
        """For the ridges ``near``: those with a row, and their (gap, box edge, s, t, n,
        ramp)."""
        A, B = self.a @ R.T + c, self.b @ R.T + c  # (12, 3)
        y0, y1 = x[self.ridges[near, 0]], x[self.ridges[near, 1]]
        d1, d2 = B - A, y1 - y0  # (12, 3), (K, 3)
        r = A[None] - y0[:, None]  # (K, 12, 3)
        aa, ee = np.einsum("ed,ed->e", d1, d1)[None], np.einsum("kd,kd->k", d2, d2)[:, None]
        bb = d2 @ d1.T  # (K, 12)
        cc, ff = np.einsum("ed,ked->ke", d1, r), np.einsum("kd,ked->ke", d2, r)
        det = aa * ee - bb * bb
        crossing = det > PARALLEL**2 * aa * ee
        det = np.where(crossing, det, 1.0)
        s, t = (bb * ff - cc * ee) / det, (aa * ff - bb * cc) / det
        n = cross(d1[None], d2[:, None])  # (K, 12, 3)
        n /= np.maximum(np.linalg.norm(n, axis=2), 1e-300)[..., None]
        faces = self.faces @ R.T  # (12, 2, 3) in space
        n *= np.where(np.einsum("ked,ed->ke", n, faces.sum(axis=1)) > 0.0, -1.0, 1.0)[..., None]
        tri = x[self.facets[self._sides[near]]]  # (K, 2, 3, 3)
        m = cross(tri[..., 1, :] - tri[..., 0, :], tri[..., 2, :] - tri[..., 0, :])
        m /= np.linalg.norm(m, axis=2)[..., None]  # the ridge's two outward normals (K, 2, 3)
        # the common normal in both normal cones: −n between the box edge's two faces, n
        # between the ridge's two triangles (widened by CONE: a flat ridge has one normal)
        outside = np.maximum(np.einsum("ked,eid->kei", n, faces).max(axis=2), 0.0)
        angles = np.arccos(np.clip(np.einsum("ked,kid->kei", n, m), -1.0, 1.0)).sum(axis=2)
        spread = np.arccos(np.clip(np.einsum("kd,kd->k", m[:, 0], m[:, 1]), -1.0, 1.0))
        ok = crossing & (outside < REACH) & (angles <= spread[:, None] + 2.0 * CONE)
        beyond = _soft(_beyond(s)) + _soft(_beyond(t)) + _soft(outside)
        ok &= (s > 0.0) & (s < 1.0) & (_beyond(t) < REACH)  # beyond a box corner: its row
        # the ridge's point on the edge's side of the box's two middle planes along its faces
        # (the lines of a ridge by one edge also cross the box's far edges, a box width away)
        y = (y0[:, None] + t[..., None] * d2[:, None] - c) @ R  # (K, 12, 3) in the body frame
        ok &= np.all(np.einsum("ked,eid->kei", y, self.faces) >= 0.0, axis=2)
        gap = np.einsum("ked,ked->ke", n, r + s[..., None] * d1[None] - t[..., None] * d2[:, None])
        # a penetration deeper than the ridge is long is no crossing of this edge: nearly
        # parallel lines of a ridge and a far edge of the box meet across the box's width
        ok &= gap > -np.sqrt(ee)
        # a ridge that clears the wedge along a face's normal with less motion than along n
        # has no row (module docstring): its end in the box is held by its node, or it misses
        own = _reach(np.stack([y0, y1], axis=1), A, faces) <= gap + TIE * np.sqrt(ee)
        ok &= self._admitted(near, own)
        ramp = RAMP * np.sqrt(ee) * beyond
        gap = np.where(ok, gap + ramp - self.clearance, np.inf)
        # the first SLOTS box edges (in their own order, so that a row keeps its edge) with a
        # row: a ridge by a box corner passes under two of its edges at once
        first = np.argsort(~np.isfinite(gap), axis=1, kind="stable")[:, :SLOTS]  # (K, SLOTS)
        k = np.broadcast_to(np.arange(len(near))[:, None], first.shape)
        slot = np.broadcast_to(np.arange(SLOTS), first.shape)
        keep = np.isfinite(gap[k, first])
        k, e, slot = k[keep], first[keep], slot[keep]
        rows = slot * len(self.ridges) + near[k]
        return rows, (gap[k, e], e, s[k, e], t[k, e], n[k, e], ramp[k, e])

    def _admitted(self, near: np.ndarray, own: np.ndarray) -> np.ndarray:
        """The pairs (K, 12) of the ridges ``near`` with a row: those the wedge admits
        (``own``), and while held those admitted since :meth:`hold_rows`."""
        if self._held is None:
            return own
        self._held[near] |= own
        return self._held[near]

    def hold_rows(self, q: np.ndarray) -> None:
        """Hold the pairs (ridge, box edge) the wedge admits at q, and those it admits at
        any later evaluation, until :meth:`release_rows`: no row of a Newton loop's iterates
        vanishes by the wedge's test (module docstring)."""
        self._held = np.zeros((len(self.ridges), len(self.a)), dtype=bool)
        self._geometry(q)

    def release_rows(self) -> None:
        """Decide the pairs at each evaluation again."""
        self._held = None

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._geometry(q)[2]

    def evaluate(self, q: np.ndarray):
        """Gaps (N,), dofs (N, 12): the box's six then the ridge's two nodes', gradients
        (N, 12), no curvature."""
        x, R, g, edge, s, t, n, ramp = self._geometry(q)
        G = np.zeros((self.size, 12))
        on = np.flatnonzero(np.isfinite(g))
        if on.size == 0:
            return g, self.dofs, G, None
        e = edge[on]
        r = self.a[e] + s[on, None] * (self.b[e] - self.a[e])
        G[on, :3] = n[on]
        G[on, 3:6] = cross(r, n[on] @ R)  # r × (Rᵀ n)
        G[on, 6:9] = -(1.0 - t[on, None]) * n[on]
        G[on, 9:] = -t[on, None] * n[on]
        ramped = on[ramp[on] > 0.0]
        if ramped.size:
            G[ramped] += self._ramp_gradient(x, R, g, edge, s, t, n, ramp, ramped)
        return g, self.dofs, G, None

    def _ramp_gradient(self, x, R, g, edge, s, t, n, ramp, rows):
        """The gradient (k, 12) of the ramp RAMP ℓ (σ(φ(s)) + σ(φ(t)) + σ(ψ)) of the ``rows``, ℓ the
        ridge's length: the closest points' parameters move by (∂s, ∂t) = −M⁻¹ (d₁·δ + w
        n·∂d₁, d₂·δ + w n·∂d₂), from the derivative of (p − y)·d₁ = (p − y)·d₂ = 0, with
        M = [[d₁·d₁, −d₁·d₂], [d₁·d₂, −d₂·d₂]], δ the motion of the material points at p
        and y, and w = n·(p − y)."""
        e, k = edge[rows], len(rows)
        d1b = self.b[e] - self.a[e]  # (k, 3) body frame
        d1 = d1b @ R.T
        y0, y1 = x[self.ridges[self._ridge[rows], 0]], x[self.ridges[self._ridge[rows], 1]]
        d2 = y1 - y0
        w = g[rows] - ramp[rows] + self.clearance  # n·(p − y)
        rb = self.a[e] + s[rows, None] * d1b
        J = np.zeros((k, 3, 12))  # δ over the local dofs
        J[:, :, :3] = np.eye(3)
        J[:, :, 3:6] = -R @ hat(rb)
        J[:, :, 6:9] = -(1.0 - t[rows, None, None]) * np.eye(3)
        J[:, :, 9:] = -t[rows, None, None] * np.eye(3)
        Jd1 = np.zeros((k, 3, 12))
        Jd1[:, :, 3:6] = -R @ hat(d1b)
        nr = n[rows]
        rhs1 = np.einsum("kd,kdj->kj", d1, J) + w[:, None] * np.einsum("kd,kdj->kj", nr, Jd1)
        rhs2 = np.einsum("kd,kdj->kj", d2, J)
        rhs2[:, 6:9] -= w[:, None] * nr  # ∂d₂ = ∂y₁ − ∂y₀
        rhs2[:, 9:] += w[:, None] * nr
        a, b, ee = (d1 * d1).sum(1), (d1 * d2).sum(1), (d2 * d2).sum(1)
        det = b * b - a * ee  # of M
        ds = -(-ee[:, None] * rhs1 + b[:, None] * rhs2) / det[:, None]
        dt = -(-b[:, None] * rhs1 + a[:, None] * rhs2) / det[:, None]
        length = np.sqrt(ee)
        dpsi, psi = self._cone_gradient(R, e, nr, d1, d2, Jd1)
        out = _slope(s[rows])[:, None] * ds + _slope(t[rows])[:, None] * dt + dpsi
        out *= RAMP * length[:, None]
        u = d2 / length[:, None]  # ∂ℓ = u·(∂y₁ − ∂y₀)
        lever = RAMP * (_soft(_beyond(s[rows])) + _soft(_beyond(t[rows])) + _soft(psi))
        out[:, 6:9] -= lever[:, None] * u
        out[:, 9:] += lever[:, None] * u
        return out

    def _cone_gradient(self, R, e, n, d1, d2, Jd1):
        """ψ = max(0, max_i n·a_i), how far −n lies outside the box edge's cone (a_i the
        outward normals of its faces), and its gradient (k, 12): with v = d₁ × d₂ and
        n = ±v/|v|, ∂n = ±(I − n nᵀ) ∂v/|v| and ∂a_i = −R ã_i δΘ (body-frame a_i)."""
        faces = self.faces[e] @ R.T  # (k, 2, 3)
        along = np.einsum("kd,kid->ki", n, faces)
        i = np.argmax(along, axis=1)
        psi = np.maximum(along[np.arange(len(e)), i], 0.0)
        a, ab = faces[np.arange(len(e)), i], self.faces[e, i]
        v = cross(d1, d2)
        size = np.linalg.norm(v, axis=1)
        sign = np.sign(np.einsum("kd,kd->k", n, v))
        Jd2 = np.zeros_like(Jd1)
        Jd2[:, :, 6:9], Jd2[:, :, 9:] = -np.eye(3), np.eye(3)
        dv = -hat(d2) @ Jd1 + hat(d1) @ Jd2  # (k, 3, 12)
        w = (a - along[np.arange(len(e)), i, None] * n) * (sign / size)[:, None]
        out = np.einsum("kd,kdj->kj", w, dv)
        out[:, 3:6] += np.einsum("kd,kdj->kj", n, -R @ hat(ab))
        return out * _soft_slope(psi)[:, None], psi

    def _relative_motion(self, q: np.ndarray):
        """Rows with a gap (N,) bool, the tangents T (N, 2, 3) of their contact planes (along
        the box edge, which is normal to n, and n × it: no basis switch as n turns) and the
        motion of the box's point p relative to the ridge's point y over the local dofs
        (N, 3, 12) (zero where no row)."""
        _, R, g, edge, s, t, n, _ = self._geometry(q)
        on = np.isfinite(g)
        T = np.broadcast_to(tangent_basis(np.array([[0.0, 0.0, 1.0]])), (self.size, 2, 3)).copy()
        W = np.zeros((self.size, 3, 12))
        if on.any():
            along = (self.b[edge[on]] - self.a[edge[on]]) @ R.T
            along /= np.linalg.norm(along, axis=1)[:, None]
            T[on] = np.stack([along, cross(n[on], along)], axis=1)
            r = self.a[edge[on]] + s[on, None] * (self.b[edge[on]] - self.a[edge[on]])
            W[on, :, :3] = np.eye(3)
            W[on, :, 3:6] = -R @ hat(r)  # ∂p/∂Θ = −R r̃
            W[on, :, 6:9] = -(1.0 - t[on, None, None]) * np.eye(3)
            W[on, :, 9:] = -t[on, None, None] * np.eye(3)
        return on, T, W

    def tangents(self, q: np.ndarray):
        """Dofs (N, 12), slip rows (N, 2, 12) and tangents T (N, 2, 3) (zero rows where the
        ridge has no row)."""
        _, T, W = self._relative_motion(q)
        return self.dofs, np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The relative motion's rows at q applied to the step (the box's body-frame increment
        (Δu, log(R_nᵀR)) and the nodes' displacements), along the step's tangents T."""
        _, _, W = self._relative_motion(q)
        step = q - q_n
        ob = self.offsets[1]
        step[ob + 3 : ob + 6] = log(exp(q_n[ob + 3 : ob + 6]).T @ exp(q[ob + 3 : ob + 6]))
        return np.einsum("mti,mik,mk->mt", T, W, step[self.dofs])
