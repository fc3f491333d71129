r"""Pointwise rows of the quadratic mortar faces of two 2D P2 solids: a node's own gap to the
other solid's curved segment.

The rows of :mod:`fecontact.contact.mortar_safeguard` measure a node against the flat pieces
of the other surface (a P2 segment split through its mid node). Where that surface is
concave — a P2 block dented by a disk — a node resting on the curved segment lies behind the
pieces by their sagitta: e²/8R of a piece of length e, 0.57 mm on the 21 mm pieces of a
block's face conforming to a disk of radius 0.1 m, several allowances δ. Such rows hold
nodes off a surface they rest on, and the static solution of a P2 disk pressed into a P2
block did not settle. Here the gap is the node's signed distance from the curved segment
itself, y(η) = N_a y_a + N_b y_b + N_m y_m (η ∈ [−1, 1]):

    g_s = (x − y(η*))·n(η*) / |n(η*)| + δ,   (x − y(η*))·y′(η*) = 0,

n = (t_y, −t_x), t = y′ (outward on a counter-clockwise boundary), η* the foot of x on the
segment (the cubic of :func:`~fecontact.contact.mortar_p2_curves.curve_foot`), clamped to
the segment's ends (there the gap along the end's normal). The segment is the one whose
piece is the node's closest facet. Gradients and Hessians over the node's and the
segment's six coordinates are exact (Jet arithmetic, the foot's derivatives those of the
implicit function). Which rows are candidates, the allowance δ and the twins are those of
:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows`.

A P2 boundary turns at its segments' end nodes (the two segments' tangents differ there), and
a node pressed onto such a vertex — two P2 disks meeting head-on, vertex to vertex on their
axis — is equally deep behind both segments. One segment's gap pushed it along that
segment's normal, sideways: the disks left the axis at 9 % of the impact speed. As the 3D
rows (:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows3D`), the row reads the two
segments around the end node (of its closest segment) nearest the node, each gap less the
excess of the node's foot beyond the segment's ends (``edge_excess``'s ramp, zero on the
segment), and takes their smooth maximum

    g_s = ε ln Σ_k exp((g_k − P_k) / ε) + δ,   ε = ``VERTEX_SMOOTHING`` δ,

whose gradient is the two normals' weighted mean: along the vertex's bisector where they
tie, the one segment's own away from the vertex.
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet
from .mortar_p2_curves import curve_at, curve_foot, quadratic_curve, quadratic_segments
from .mortar_safeguard import DeepNodeRows

__all__ = ["VERTEX_SMOOTHING", "DeepNodeRowsP2", "curved_gaps", "piece_depths", "vertex_gaps"]

VERTEX_SMOOTHING = 0.3
"""ε over δ of the rows' smooth maximum at a vertex. A node pressed onto a convex vertex
lies on a rounded apex: too sharp a rounding and the node, pushed along the normal of the
side it leans to, slides further that way (the 3D rows' 0.1: P2 disks head-on left their axis
by 2e-8 and 5.5e-2 of the impact speed at Δx/c and Δx/2c); too wide and a node sinks deeper
before its row holds it (1: 0.6 % of an edge, and 5e-4 of the ledger's scale created).
Measured on six head-on runs (docs/explanation/mortar.md, *A node on a vertex*)."""


def _gap(x, curve, order: int) -> Jet:
    """The signed distance (Jet) of the point x (a pair of Jets) from the curve (c, d, e)."""
    eta = curve_foot(curve, x, order)
    with np.errstate(invalid="ignore"):
        eta = eta.where(eta.v > -1.0, -1.0).where(eta.v < 1.0, 1.0)  # (no foot: an end)
    y, t = curve_at(curve, eta)
    reach = (x[0] - y[0]) * t[1] - (x[1] - y[1]) * t[0]
    return reach * (t[0] * t[0] + t[1] * t[1]).sqrt().reciprocal()


def curved_gaps(z: np.ndarray, hessian: bool | None = False) -> Jet:
    """Signed distances (Jet, P) of the points x from the curved segments (y_a, y_b, y_m),
    ``z`` (P, 8) = (x, y_a, y_b, y_m) (m); ``hessian`` as in :meth:`Jet.variables`."""
    c = Jet.variables(z, hessian)
    x, a, b, m = ((c[2 * i], c[2 * i + 1]) for i in range(4))
    return _gap(x, quadratic_curve(a, b, m), 0 if hessian is None else (2 if hessian else 1))


def _ramp(e: Jet, eps: float) -> Jet:
    """r(e) = 0 (e ≤ 0), e²/2ε (0 < e < ε), e − ε/2 (e ≥ ε): a ramp with a continuous slope."""
    return (e - 0.5 * eps).where(e.v >= eps, (e * e * (0.5 / eps)).where(e.v > 0.0, 0.0))


def _excess(x, a, b, curve, eps: float) -> Jet:
    """Σ over the segment's two ends of r(e), e (m) how far x lies beyond the end along the
    segment's outward tangent there (negative short of it)."""
    total = None
    for end, xi, sign in ((a, -1.0, -1.0), (b, 1.0, 1.0)):
        _, t = curve_at(curve, xi)
        e = ((x[0] - end[0]) * t[0] + (x[1] - end[1]) * t[1]) * (
            (t[0] * t[0] + t[1] * t[1]).sqrt().reciprocal() * sign
        )
        r = _ramp(e, eps)
        total = r if total is None else total + r
    return total


def vertex_gaps(z: np.ndarray, real: np.ndarray, eps: float, hessian: bool | None = False):
    """The smooth maximum (Jet, P) of the gaps g_k − P_k of the points x from the two curved
    segments around a vertex (module docstring), ``z`` (P, 14) = (x, segment 1's (y_a, y_b,
    y_m), segment 2's); ``real`` (P,): whether the second segment is one (else it is left
    out); ``eps`` (m) the smoothing length."""
    c = Jet.variables(z, hessian)
    x = (c[0], c[1])
    order = 0 if hessian is None else (2 if hessian else 1)
    gaps = []
    for k in range(2):
        a, b, m = ((c[2 + 6 * k + 2 * i], c[3 + 6 * k + 2 * i]) for i in range(3))
        curve = quadratic_curve(a, b, m)
        gaps.append(_gap(x, curve, order) - _excess(x, a, b, curve, eps))
    top = np.where(real, np.maximum(gaps[0].v, gaps[1].v), gaps[0].v)  # (a constant shift)
    w = [((g - top) * (1.0 / eps)).exp() for g in gaps]
    return (w[0] + w[1].where(real, 0.0)).log() * eps + top


def piece_depths(segments: np.ndarray, points: np.ndarray, xm: np.ndarray, pieces):
    """Depths (m, ≥ 0) of ``points`` (n, 2) behind the curved segments (``segments``, the
    P2 solid's (a, b, m) at positions ``xm``) whose flat pieces are ``pieces`` (n,): the
    depth inside the flat pieces read on the curve (a dent's sagitta taken out)."""
    seg = segments[pieces % len(segments)]  # (piece i and n + i: segment i)
    z = np.concatenate([points, xm[seg].reshape(len(seg), 6)], axis=1)
    return np.maximum(-curved_gaps(z, None).v, 0.0)


class DeepNodeRowsP2(DeepNodeRows):
    """:class:`DeepNodeRows` of a P2 solid's boundary nodes against the curved segments of
    another P2 solid: each row the smooth maximum of the gaps from the two segments around a
    vertex (module docstring)."""

    def __init__(self, body, master, restitution: float = 0.0):
        super().__init__(body, master, restitution)
        self.segments = quadratic_segments(master)
        n = len(self.segments)
        self._segment_dofs = master.node_translation_dofs(self.segments.ravel()).reshape(n, -1)
        # the segments around each end node: its first as the end b, its second as a
        self.around = np.full((master.n_nodes, 2), -1)
        self.around[self.segments[:, 1], 0] = np.arange(n)
        self.around[self.segments[:, 0], 1] = np.arange(n)
        self.width = 2 + 2 * self._segment_dofs.shape[1]
        self.smoothing = VERTEX_SMOOTHING * self.allowance
        self.pair = np.full((self.size, 2), -1)
        """The two segments each row reads (−1: none), at the last evaluation."""

    def _pairs(self, xs, xm, s, f):
        """The two segments (n, 2) the rows s read: those around the end of their closest
        piece's segment nearest to the node (the second −1 where the boundary is open)."""
        seg = f % len(self.segments)  # (piece i and n + i: segment i)
        ends = self.segments[seg, :2]
        near = np.linalg.norm(xm[ends] - xs[s, None], axis=2).argmin(axis=1)
        pair = self.around[ends[np.arange(len(s)), near]]
        # (an open end has one segment: its own, with no second)
        pair[:, 0] = np.where(pair[:, 0] >= 0, pair[:, 0], pair[:, 1])
        pair[:, 1] = np.where(pair[:, 1] == pair[:, 0], -1, pair[:, 1])
        return pair

    def _rows(self, q, s, hessian):
        """The gaps (Jet) of the rows s from the segments ``self.pair[s]``."""
        xs, xm = self.positions(q)
        pair = self.pair[s]
        real = pair[:, 1] >= 0
        seg = self.segments[np.where(real[:, None], pair, pair[:, :1])]  # (n, 2, 3)
        z = np.concatenate([xs[self._row_node[s]], xm[seg].reshape(len(s), 12)], axis=1)
        return vertex_gaps(z, real, self.smoothing, hessian)

    def _shifted(self, q):
        xs, xm = self.positions(q)
        m, (oa, ob) = self.size, self.offsets
        g = np.full(m, np.inf)
        dofs = np.empty((m, self.width), dtype=int)
        dofs[:, :2] = oa + self._slave_dofs
        dofs[:, 2:] = ob + np.tile(self._segment_dofs[0], 2)
        G = np.zeros((m, self.width))
        s, f, _ = self.closest_facets(xs, xm)
        self.selected = np.full(m, -1)
        self.selected[s] = f
        self.closest = self.selected.copy()
        self.pair = np.full((m, 2), -1)
        if s.size:
            self.pair[s] = pair = self._pairs(xs, xm, s, f)
            used = np.where(pair >= 0, pair, pair[:, :1])
            dofs[s, 2:] = ob + self._segment_dofs[used].reshape(len(s), -1)
            jet = self._rows(q, s, False)
            g[s], G[s] = jet.v + self.allowance, jet.g
        return g, dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_s (len(rows), 14, 14) of the ``rows`` at q (zero where shallow or far)."""
        self.evaluate(q)  # (the selection at q)
        rows = np.asarray(rows)
        H = np.zeros((len(rows), self.width, self.width))
        near = (self.selected[rows] >= 0) & (self.pair[rows, 0] >= 0)
        if near.any():
            H[near] = self._rows(q, rows[near], True).h
        return H
