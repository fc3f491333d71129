r"""A 2D :class:`~fecontact.Solid`'s nodes against the exact outline of a planar
:class:`~fecontact.bodies.rigid.RigidBody2D` (node-to-surface on a rigid master).

``Contact(solid, body)`` (either way round) builds these pairs, one contact per slave node x
(the solid's boundary nodes by default, or ``nodes``), against the body's shape:

===========  =====================================================================================
``Disk``     g = |x − c| − r − clearance, c the disk's centre; the normal e = (x − c)/|x − c|
``Polygon``  g = s(ρ) − clearance with ρ = R(φ)ᵀ(x − c) the node in the polygon's frame and s
             the signed distance to the convex polygon (negative inside: the depth below the
             nearest edge), as for a rigid disk's centre (:mod:`fecontact.contact.rigid_pairs`)
===========  =====================================================================================

Gaps are in m, positive open. Gradients act on the node's (u_x, u_y) and on the body's
(u_x, u_y, θ), θ counter-clockwise. For the disk G = [e, −e, 0] and the curvature is exact,
K = (I − e eᵀ)/|x − c| on the two translations (the disk's rotation moves no point of its
outline off it). For the polygon, with J the rotation by +90°, A = ∂ρ/∂(x, c, θ) =
[Rᵀ, −Rᵀ, −Jρ] and s' = ∂s/∂ρ: G = s'ᵀA and ∇²g = Aᵀ s'' A + Σ_i s'_i ∇²ρ_i, the only second
derivatives of ρ being ∂²ρ/∂x∂θ = −J Rᵀ, ∂²ρ/∂c∂θ = J Rᵀ and ∂²ρ/∂θ² = −ρ; s'' is zero on an
edge and the vertex distance's curvature near a vertex. The rows hold nodes only: a polygon's
vertex can enter the solid between two nodes, where no node row sees it. Each vertex p =
c + R r therefore carries a row of its own (:class:`VertexRows`, the pair's companion): its
signed distance to the solid's boundary, g = s(p) − clearance, negative inside. Its closest
boundary segment (x₁, x₂) is numbered with the outward normal on its right; with ξ = (p −
x₁)·(x₂ − x₁)/|x₂ − x₁|², where 0 ≤ ξ ≤ 1 the closest point is on the segment and s = −f(p,
x₁, x₂), f the signed distance from its line (positive on its left,
:func:`~fecontact.contact.geometry.point_line_distance`); beyond an end x_e the closest
point is that node and s = ±|p − x_e|, inside (−) by the winding number of the boundary
(no one segment's line tells the side there: near a sharp convex corner a point outside
lies behind the line of a segment that ends there, near a concave one a point inside lies
before both lines). s is continuous across segments, and reads the true distance however
far the vertex is. G and ∇²g are exact on both branches, through ∂p/∂(c, θ) = [I, J R r] and
∂²p/∂θ² = −R r, the node branch's curvature (I − e eᵀ)/|p − x_e| on p − x_e. The pair's
watch (:class:`VertexDepths`) measures the vertices inside the solid for the step's
penetration test.

Coulomb friction: the node rows slip as the node against the body's material point under it
(:mod:`fecontact.contact.node_rigid`); a vertex row as the vertex against the boundary's
closest point, ṗ − ((1 − ξ) ẋ₁ + ξ ẋ₂) with ξ clamped to [0, 1] (the end node beyond the
segment), so that G = n·W, n = ∂s/∂p, and the slip rows are T W, W = [I, J R r, −(1 − ξ) I,
−ξ I], with the pair's μ.
"""

from __future__ import annotations

import numpy as np

from ..bodies.rigid import Disk, Polygon, RigidBody2D, rotation
from ..bodies.solid import Solid
from ..errors import InputError
from .base import PairDefaults
from .circle_watch import DiskSegmentDepths
from .disk_segments import DiskSegmentRows
from .friction import tangent_basis
from .geometry import point_line_distance
from .inside import Surface, winding_numbers
from .node_rigid import NodeRigidRows, NodeRoundRows, node_rows
from .registry import register_pair

__all__ = ["NodeDiskContact", "NodePolygonContact", "VertexDepths", "VertexRows"]

_PERP = np.array([[0.0, -1.0], [1.0, 0.0]])  # J, the rotation by +90°


class NodeRigid2DContact(NodeRigidRows):
    """Nodes of a 2D solid against a planar rigid body; the subclasses give the shape."""

    dim, rigid_dofs = 2, 3

    def _rotation(self, qr: np.ndarray) -> np.ndarray:
        return rotation(self.rigid.orientation(qr))

    def _turn_rows(self, arm: np.ndarray, qr: np.ndarray) -> np.ndarray:
        return -(arm @ _PERP.T)[:, :, None]  # ẏ = ċ + θ̇ J (y − c)


class NodeDiskContact(NodeRoundRows, NodeRigid2DContact):
    """Nodes of a 2D solid against a rigid ``Disk`` (outside it; :class:`.NodeRoundRows`);
    on P1 cells the boundary segments have rows of their own (:class:`.DiskSegmentRows`)."""

    def __init__(self, body, rigid, nodes, restitution, clearance):
        super().__init__(body, rigid, nodes, restitution, clearance)
        # on P2 cells the boundary is curved and its chords are not its surface (as for a
        # fixed Circle): the nodes' rows alone, the watch measuring the disk in the chords
        self.companions = (DiskSegmentRows(self),) if body.element == "P1" else ()

    def bind(self, model) -> None:
        super().bind(model)
        for pair in self.companions:
            pair.bind(model)

    def watch(self) -> DiskSegmentDepths:
        """The disk's arc against the solid's boundary segments: the node rows let it in
        between two nodes, by up to the sagitta L²/8r of an edge L."""
        return DiskSegmentDepths(self)


def polygon_distances(vertices: np.ndarray, normals: np.ndarray, rho: np.ndarray):
    """Signed distances s (m,) of the points ``rho`` (m, 2) to a convex counter-clockwise
    polygon (negative inside), their gradients s' (m, 2) and Hessians s'' (m, 2, 2) on the
    piece that holds each point: an edge's plane (inside, or the closest point inside the
    edge) or a vertex's distance."""
    rel = rho[:, None, :] - vertices[None]  # (m, k, 2)
    s_edge = np.einsum("kj,mkj->mk", normals, rel)
    d = np.roll(vertices, -1, axis=0) - vertices
    t = np.clip(np.einsum("mkj,kj->mk", rel, d) / np.einsum("kj,kj->k", d, d), 0.0, 1.0)
    dist = np.linalg.norm(rel - t[:, :, None] * d[None], axis=2)
    rows = np.arange(len(rho))
    inside = np.all(s_edge < 0.0, axis=1)
    i = np.where(inside, np.argmax(s_edge, axis=1), np.argmin(dist, axis=1))
    ti = t[rows, i]
    corner = ~inside & ((ti == 0.0) | (ti == 1.0))
    s, ds = s_edge[rows, i], normals[i]
    dds = np.zeros((len(rho), 2, 2))
    if corner.any():
        k = np.where(ti[corner] == 0.0, i[corner], (i[corner] + 1) % len(vertices))
        w = rho[corner] - vertices[k]
        r = np.linalg.norm(w, axis=1)
        if np.any(r == 0.0):
            raise InputError("a node lies on a rigid polygon's vertex: no contact normal")
        e = w / r[:, None]
        s[corner], ds[corner] = r, e
        dds[corner] = (np.eye(2) - e[:, :, None] * e[:, None, :]) / r[:, None, None]
    return s, ds, dds


class VertexDepths:
    """A rigid polygon's vertices against a 2D solid's discretized boundary: what the rows of
    a ``pair`` of the two (one per node of the solid) cannot see, a vertex entering between
    two nodes. ``depth(q)``: the deepest vertex inside the solid's boundary polygon (m, ≥ 0)
    and that depth over the length of the segment it lies under (the pair's ``offsets`` are
    read at each call: set when the model binds it)."""

    def __init__(self, pair):
        self.pair = pair
        self.facets = pair.body.contact_facets()
        self.surface = Surface(self.facets)

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        (oa, ob), solid, rigid = self.pair.offsets, self.pair.body, self.pair.rigid
        x = solid.positions(q[oa : oa + solid.ndof])
        qr = q[ob : ob + 3]
        p = rigid.shape.vertices @ rotation(rigid.orientation(qr)).T + rigid.center(qr)
        s, f = self.surface.signed_distance(x, p, outside=False)
        inside = np.flatnonzero(s < 0.0)
        if inside.size == 0:
            return 0.0, 0.0
        seg = x[self.facets[f[inside]]]
        length = np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1)
        return float(-s[inside].min()), float(np.max(-s[inside] / length))

    def entering(self, q: np.ndarray) -> str:
        """What of the polygon enters the solid (for a message)."""
        return "a vertex of a rigid polygon"


class VertexRows(PairDefaults):
    """The vertices of the ``Polygon`` of the pair ``owner``'s rigid body against the 2D
    solid's boundary segments: one row each (module docstring), the owner's restitution.
    Gaps in m, dofs (k, 7): the body's (u_x, u_y, θ) then the segment's two nodes'
    (u_x, u_y)."""

    linear = False
    redundant_rows = True  # (a vertex on a node: its row and the node's hold one point)

    def __init__(self, owner):
        self.owner = owner
        self.body, self.rigid = owner.body, owner.rigid
        self.bodies = (self.body, self.rigid)
        self.restitution, self.clearance = owner.restitution, owner.clearance
        self.vertices = self.rigid.shape.vertices
        self.size = len(self.vertices)
        self.facets = self.body.contact_facets()
        self._facet_dofs = self.body.node_translation_dofs(self.facets.ravel()).reshape(-1, 4)
        self.offsets = (0, 0)

    def _geometry(self, q: np.ndarray):
        """The vertices' arms R r (k, 2) and positions p (k, 2), the nodes (k, 2, 2) and
        indices (k,) of their closest segments and the parameters ξ (k,) of the points
        under them on the segments' lines (not clamped)."""
        (oa, ob), body = self.offsets, self.body
        x = body.positions(q[oa : oa + body.ndof])
        qr = q[ob : ob + 3]
        arm = self.vertices @ rotation(self.rigid.orientation(qr)).T
        p = arm + self.rigid.center(qr)
        xf = x[self.facets]  # (F, 2, 2)
        a, b = xf[None, :, 0], xf[None, :, 1]  # (1, F, 2)
        d, w = b - a, p[:, None] - a
        t = np.clip(np.einsum("kfi,kfi->kf", w, d) / np.einsum("kfi,kfi->kf", d, d), 0.0, 1.0)
        # the end node itself at t = 1: a vertex nearest a node is at one distance from its
        # two segments to the bit, and keeps the first of them
        closest = np.where((t == 1.0)[:, :, None], b, a + t[:, :, None] * d)
        f = np.argmin(np.linalg.norm(p[:, None] - closest, axis=2), axis=1)
        seg = xf[f]
        d = seg[:, 1] - seg[:, 0]
        xi = np.einsum("kd,kd->k", p - seg[:, 0], d) / np.einsum("kd,kd->k", d, d)
        return arm, p, seg, f, xi, x

    def _distances(self, q: np.ndarray, hessian: bool = True):
        """Signed distances s (k,) of the vertices to the solid's boundary (m, negative
        inside), with their gradients (k, 6) and Hessians (k, 6, 6) with respect to
        (p, x₁, x₂); the arms, segments and clamped ξ of :meth:`_geometry`."""
        arm, p, seg, f, xi, x = self._geometry(q)
        f_line, G6, H6 = point_line_distance(p, seg[:, 0], seg[:, 1], hessian=hessian)
        s, G6 = -f_line, -G6
        H6 = None if H6 is None else -H6
        node = (xi < 0.0) | (xi > 1.0)
        if node.any():  # the closest point is the end node x_e: s = ±|p − x_e|
            at = (xi[node] > 1.0).astype(float)  # 1 at x₂, 0 at x₁
            w = p[node] - ((1.0 - at)[:, None] * seg[node, 0] + at[:, None] * seg[node, 1])
            r = np.linalg.norm(w, axis=1)
            # inside or out by the winding number: the sign of no single line is right there
            a, b = x[self.facets[:, 0]], x[self.facets[:, 1]]
            sign = np.where(winding_numbers(p[node], a, b) > 0.5, -1.0, 1.0)
            B = np.zeros((len(r), 2, 6))  # ∂(p − x_e)/∂(p, x₁, x₂)
            B[:, :, :2] = np.eye(2)
            B[:, :, 2:4] = -(1.0 - at)[:, None, None] * np.eye(2)
            B[:, :, 4:] = -at[:, None, None] * np.eye(2)
            e = w / r[:, None]
            s[node] = sign * r
            G6[node] = sign[:, None] * np.einsum("mi,mij->mj", e, B)
            if hessian:
                K = (np.eye(2) - e[:, :, None] * e[:, None, :]) * (sign / r)[:, None, None]
                H6[node] = np.einsum("mia,mij,mjb->mab", B, K, B)
        return s, G6, H6, arm, seg, f, np.clip(xi, 0.0, 1.0)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._distances(q, hessian=False)[0] - self.clearance

    def evaluate(self, q: np.ndarray):
        """Gaps (k,), dofs (k, 7), gradients (k, 7) and Hessians (k, 7, 7)."""
        s, G6, H6, arm, _, f, _ = self._distances(q)
        k = self.size
        A = np.zeros((k, 6, 7))  # ∂(p, x₁, x₂)/∂(c, θ, x₁, x₂)
        A[:, :2, :2] = np.eye(2)
        A[:, :2, 2] = arm @ _PERP.T
        A[:, 2:, 3:] = np.eye(4)
        G = np.einsum("mi,mij->mj", G6, A)
        H = np.einsum("mia,mij,mjb->mab", A, H6, A)
        H[:, 2, 2] -= np.einsum("mi,mi->m", G6[:, :2], arm)  # G_p·∂²p/∂θ², ∂²p/∂θ² = −R r
        return s - self.clearance, self._dofs(f), G, H

    def _dofs(self, f: np.ndarray) -> np.ndarray:
        """Dofs (k, 7) of the rows: the body's (u_x, u_y, θ), then the segments' ``f``."""
        oa, ob = self.offsets
        body = np.broadcast_to(ob + np.arange(3), (self.size, 3))
        return np.concatenate([body, oa + self._facet_dofs[f]], axis=1)

    frictional = True

    @property
    def friction(self) -> float:
        """Coulomb's μ of the pair that brings the rows (``Contact`` sets it there)."""
        return self.owner.friction

    def _slip_geometry(self, q: np.ndarray):
        """The vertices' arms R r (k, 2), their segments (k,), the parameters ξ ∈ [0, 1] (k,)
        of the closest points and the rows' unit normals n = ∂s/∂p (k, 2) (out of the
        solid)."""
        _, G6, _, arm, _, f, xi = self._distances(q, hessian=False)
        return arm, f, xi, G6[:, :2]

    def tangents(self, q: np.ndarray):
        """Dofs (k, 7), slip rows (k, 1, 7) and unit tangents T (k, 1, 2): the vertex's
        material point against the segment's point under it, ṗ − ((1 − ξ) ẋ₁ + ξ ẋ₂) with
        ṗ = ċ + θ̇ J R r, so that G = n·[I, J R r, −(1 − ξ) I, −ξ I]."""
        arm, f, xi, n = self._slip_geometry(q)
        W = np.zeros((self.size, 2, 7))
        W[:, :, :2] = np.eye(2)
        W[:, :, 2] = arm @ _PERP.T
        W[:, :, 3:5] = -(1.0 - xi)[:, None, None] * np.eye(2)
        W[:, :, 5:] = -xi[:, None, None] * np.eye(2)
        T = tangent_basis(n)
        return self._dofs(f), np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·((p − p_n) − (1 − ξ)(x₁ − x₁ₙ) − ξ(x₂ − x₂ₙ)) (k, 1): the vertex against the
        segment's material point under it at q, over the step (exact)."""
        arm, f, xi, _ = self._slip_geometry(q)
        (oa, ob), body = self.offsets, self.body
        qr_n = q_n[ob : ob + 3]
        p_n = self.vertices @ rotation(self.rigid.orientation(qr_n)).T + self.rigid.center(qr_n)
        p = arm + self.rigid.center(q[ob : ob + 3])
        ends = self.facets[f]
        x = body.positions(q[oa : oa + body.ndof])[ends]
        x_n = body.positions(q_n[oa : oa + body.ndof])[ends]
        dx = (1.0 - xi)[:, None] * (x[:, 0] - x_n[:, 0]) + xi[:, None] * (x[:, 1] - x_n[:, 1])
        return np.einsum("mtd,md->mt", T, p - p_n - dx)


class NodePolygonContact(NodeRigid2DContact):
    """Nodes of a 2D solid against a rigid convex ``Polygon``; its vertices have rows of their
    own (:class:`VertexRows`)."""

    def __init__(self, body, rigid, nodes, restitution, clearance):
        super().__init__(body, rigid, nodes, restitution, clearance)
        self.companions = (VertexRows(self),)

    def bind(self, model) -> None:
        super().bind(model)
        for pair in self.companions:
            pair.bind(model)

    def watch(self) -> VertexDepths:
        """The polygon's vertices against the solid's boundary (the rows hold nodes only)."""
        return VertexDepths(self)

    def _geometry(self, q):
        """Rᵀ, ρ (m, 2) and s, s', s'' of the nodes in the polygon's frame."""
        x, qr = self._state(q)
        Rt = rotation(self.rigid.orientation(qr)).T
        rho = (x - self.rigid.center(qr)) @ Rt.T
        shape = self.rigid.shape
        return Rt, rho, *polygon_distances(shape.vertices, shape.normals, rho)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._geometry(q)[2] - self.clearance

    def _normals(self, q: np.ndarray) -> np.ndarray:
        Rt, _, _, ds, _ = self._geometry(q)
        return ds @ Rt  # R s'

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, 5), gradients (m, 5) and Hessians (m, 5, 5)."""
        Rt, rho, s, ds, dds = self._geometry(q)
        m = self.size
        A = np.zeros((m, 2, 5))
        A[:, :, :2], A[:, :, 2:4] = Rt, -Rt
        A[:, :, 4] = -rho @ _PERP.T
        G = np.einsum("mi,mij->mj", ds, A)
        H = np.einsum("mia,mij,mjb->mab", A, dds, A)
        b = -ds @ (_PERP @ Rt)  # Σ_i s'_i ∂²ρ_i/∂x∂θ
        H[:, :2, 4] += b
        H[:, 4, :2] += b
        H[:, 2:4, 4] -= b
        H[:, 4, 2:4] -= b
        H[:, 4, 4] -= np.einsum("mi,mi->m", ds, rho)
        return s - self.clearance, self._dofs(), G, H


# the shapes a solid's nodes meet, each its pair's class
SHAPES = {Disk: NodeDiskContact, Polygon: NodePolygonContact}


@register_pair(Solid, RigidBody2D)
def _solid_rigid2d(solid, rigid, nodes, restitution, clearance):
    """The solid's nodes (default its boundary nodes) against a rigid Disk or Polygon."""
    return node_rows(SHAPES, solid, rigid, nodes, restitution, clearance)


@register_pair(RigidBody2D, Solid)
def _rigid2d_solid(rigid, solid, nodes, restitution, clearance):
    """The same pair named the other way round (``nodes`` of the solid)."""
    return _solid_rigid2d(solid, rigid, nodes, restitution, clearance)
