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

A P2 boundary turns at its segments' end nodes, and a node pressed onto such a vertex from
inside — two P2 disks head-on meet vertex to vertex on their axis — ties between the two
segments: its gaps g₁, g₂ from them are equal. One segment's row pushes it along that
segment's normal, sideways (11.25° off the axis on a 16-segment disk), the more so the
further it then leans: the disks left their axis at 9 % of the impact speed. A deep node
that is a vertex of its own boundary facing the other's vertex (``VERTEX_FACING``), and whose
gaps from its segment and from the segment across its nearer end differ by less than
τ = ``VERTEX_TIE`` δ, is on the vertex's tie, and its row is their mean raised by τ/2,

    g_s = (g₁ + g₂ + τ) / 2 + δ   (|g₁ − g₂| < τ),

the vertex's apex cut by a flat chamfer: at the band's edge the mean equals the larger gap,
the convex vertex's depth, and the chamfer pushes the node along the vertex's bisector with
no sideways force, so that a node on it does not slide off. The band is a round-off
tolerance, not a smoothing: its curvature is the two segments' own (no term grows as the
band narrows), and every run whose deep nodes never tie is unchanged. The facing test keeps
it to a symmetric impact's vertex on vertex, where the node stays on the band: a node that
slides across a vertex and lands on the band within a Newton loop meets two kinks τ apart
instead of one (a fast off-centre impact stalled so). Measured in
docs/explanation/mortar.md, *A node on a vertex of a P2 boundary*.
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet
from .mortar_p2_curves import curve_at, curve_foot, quadratic_curve, quadratic_segments
from .mortar_safeguard import DeepNodeRows

__all__ = ["VERTEX_FACING", "VERTEX_TIE", "DeepNodeRowsP2", "curved_gaps", "piece_depths"]

VERTEX_TIE = 1e-3
"""τ over δ: a deep node whose gaps from the two segments around its nearer vertex differ by
less than τ is on that vertex's tie, and its row is their mean (module docstring)."""

VERTEX_FACING = 1.0 - 1e-6
"""A tie row also needs the node to be a vertex of its own boundary whose outward bisector
faces the other vertex's: their cosine below −``VERTEX_FACING`` (within 0.08°)."""


def _bisector(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """The outward unit normals (n, 2) of the chords from ``before`` to ``after`` (n, 2) of a
    counter-clockwise boundary: a vertex's bisector from its neighbouring vertices."""
    t = after - before
    n = np.stack([t[:, 1], -t[:, 0]], axis=1)
    return n / np.linalg.norm(n, axis=1)[:, None]


# the columns of a tie row (node, own segment (a, b, m), the neighbour's two other nodes)
# that the neighbour's coordinates (node, a, b, m) fill: across end a the neighbour's b is
# the own a, across end b its a is the own b
_TIE_COLUMNS = np.array([[0, 1, 8, 9, 2, 3, 10, 11], [0, 1, 4, 5, 8, 9, 10, 11]])


def curved_gaps(z: np.ndarray, hessian: bool | None = False) -> Jet:
    """Signed distances (Jet, P) of the points x from the curved segments (y_a, y_b, y_m),
    ``z`` (P, 8) = (x, y_a, y_b, y_m) (m); ``hessian`` as in :meth:`Jet.variables`."""
    c = Jet.variables(z, hessian)
    x, a, b, m = ((c[2 * i], c[2 * i + 1]) for i in range(4))
    curve = quadratic_curve(a, b, m)
    order = 0 if hessian is None else (2 if hessian else 1)
    eta = curve_foot(curve, x, order)
    with np.errstate(invalid="ignore"):
        eta = eta.where(eta.v > -1.0, -1.0).where(eta.v < 1.0, 1.0)  # (no foot: an end)
    y, t = curve_at(curve, eta)
    reach = (x[0] - y[0]) * t[1] - (x[1] - y[1]) * t[0]
    return reach * (t[0] * t[0] + t[1] * t[1]).sqrt().reciprocal()


def piece_depths(segments: np.ndarray, points: np.ndarray, xm: np.ndarray, pieces):
    """Depths (m, ≥ 0) of ``points`` (n, 2) behind the curved segments (``segments``, the
    P2 solid's (a, b, m) at positions ``xm``) whose flat pieces are ``pieces`` (n,): the
    depth inside the flat pieces read on the curve (a dent's sagitta taken out)."""
    seg = segments[pieces % len(segments)]  # (piece i and n + i: segment i)
    z = np.concatenate([points, xm[seg].reshape(len(seg), 6)], axis=1)
    return np.maximum(-curved_gaps(z, None).v, 0.0)


class DeepNodeRowsP2(DeepNodeRows):
    """:class:`DeepNodeRows` of a P2 solid's boundary nodes against the curved segments of
    another P2 solid (module docstring); a row on a vertex's tie reads both segments."""

    def __init__(self, body, master, restitution: float = 0.0):
        super().__init__(body, master, restitution)
        self.segments = seg = quadratic_segments(master)
        n = len(seg)
        self._segment_dofs = master.node_translation_dofs(seg.ravel()).reshape(n, -1)
        starts, ends = np.full(master.n_nodes, -1), np.full(master.n_nodes, -1)
        starts[seg[:, 0]], ends[seg[:, 1]] = np.arange(n), np.arange(n)
        self.neighbours = np.stack([ends[seg[:, 0]], starts[seg[:, 1]]], axis=1)
        """The segment across each segment's end a and end b (n, 2; −1: an open end)."""
        # the neighbour's two nodes that are not the shared end (its far end, its mid node);
        # at an open end the segment's own (their columns then carry zeros)
        other = seg[np.maximum(self.neighbours, 0)]  # (n, 2, 3)
        far = np.stack([other[:, 0, [0, 2]], other[:, 1, [1, 2]]], axis=1)  # (n, 2, 2)
        own = np.stack([seg[:, [0, 2]], seg[:, [1, 2]]], axis=1)
        far = np.where((self.neighbours >= 0)[:, :, None], far, own)
        self._far_dofs = master.node_translation_dofs(far.ravel()).reshape(n, 2, 4)
        self.width = 2 + self._segment_dofs.shape[1] + 4
        self.tie = VERTEX_TIE * self.allowance
        # each row node's neighbouring vertices along its own boundary (−1: not a vertex)
        own = quadratic_segments(body)
        where = np.full(body.n_nodes, -1)
        where[self.nodes] = np.arange(len(self.nodes))
        prev, after = np.full(body.n_nodes, -1), np.full(body.n_nodes, -1)
        prev[own[:, 1]], after[own[:, 0]] = where[own[:, 0]], where[own[:, 1]]
        ids = self.nodes[self._row_node]
        self._own = np.stack([prev[ids], after[ids]], axis=1)
        self.end = np.full(self.size, -1)
        """Per row, the end (0: a, 1: b) of its segment whose vertex tie it reads (−1: its
        segment alone), at the last evaluation."""

    def _rows(self, q, s, f, hessian):
        """The local coordinates (n, 8) of the rows s read from the pieces f and their gaps."""
        xs, xm = self.positions(q)
        seg = self.segments[f % len(self.segments)]  # (piece i and n + i: segment i)
        z = np.concatenate([xs[self._row_node[s]], xm[seg].reshape(len(s), 6)], axis=1)
        return curved_gaps(z, hessian)

    def _other_rows(self, q, s, f, end, hessian):
        """The gaps (Jet) of the rows s from the segments across the ends ``end`` of their
        pieces' segments, and the row's columns (n, 8) of their coordinates."""
        xs, xm = self.positions(q)
        other = self.neighbours[f % len(self.segments), end]
        z = np.concatenate(
            [xs[self._row_node[s]], xm[self.segments[other]].reshape(len(s), 6)], axis=1
        )
        return curved_gaps(z, hessian), _TIE_COLUMNS[end]

    def _ties(self, q, xs, xm, s, f, g):
        """The rows of s deeper than δ/2 (gaps ``g`` less δ, of their own segments) that lie
        on a vertex's tie, and the end of their segment there: the node's nearer end, whose
        neighbour's gap is within τ of the row's."""
        seg = f % len(self.segments)
        ends = self.segments[seg, :2]
        end = np.linalg.norm(xm[ends] - xs[s, None], axis=2).argmin(axis=1)
        other = self.neighbours[seg, end]
        deep = (g < -0.5 * self.allowance) & (other >= 0) & (self._own[s] >= 0).all(axis=1)
        if deep.any():  # (vertex on vertex, the node's own bisector on the other's)
            own = self._own[s[deep]]
            facing = _bisector(xs[own[:, 0]], xs[own[:, 1]])
            ahead = self.segments[other[deep], end[deep]]  # (the other segment's far end)
            first = np.where(end[deep] == 1, self.segments[seg[deep], 0], ahead)
            last = np.where(end[deep] == 1, ahead, self.segments[seg[deep], 1])
            axis = _bisector(xm[first], xm[last])
            deep[deep] = np.einsum("ij,ij->i", facing, axis) < -VERTEX_FACING
        if not deep.any():
            return deep, end
        other, _ = self._other_rows(q, s[deep], f[deep], end[deep], None)
        deep[deep] = np.abs(g[deep] - other.v) < self.tie
        return deep, end

    def _shifted(self, q):
        xs, xm = self.positions(q)
        m, (oa, ob) = self.size, self.offsets
        g = np.full(m, np.inf)
        dofs = np.empty((m, self.width), dtype=int)
        dofs[:, :2] = oa + self._slave_dofs
        dofs[:, 2:8] = ob + self._segment_dofs[0]
        dofs[:, 8:] = ob + self._far_dofs[0, 1]
        G = np.zeros((m, self.width))
        s, f, _ = self.closest_facets(xs, xm)
        self.selected = np.full(m, -1)
        self.selected[s] = f
        self.closest = self.selected.copy()
        self.end = np.full(m, -1)
        if s.size:
            jet = self._rows(q, s, f, False)
            g[s], G[s, :8] = jet.v + self.allowance, jet.g
            seg = f % len(self.segments)
            dofs[s, 2:8] = ob + self._segment_dofs[seg]
            tie, end = self._ties(q, xs, xm, s, f, jet.v)
            dofs[s, 8:] = ob + self._far_dofs[seg, end]
            if tie.any():
                self._on_ties(q, s[tie], f[tie], end[tie], g, G)
        return g, dofs, G, None

    def _on_ties(self, q, s, f, end, g, G):
        """The rows s on a vertex's tie: the mean of the two segments' rows, raised by τ/2
        (module docstring)."""
        self.end[s] = end
        other, cols = self._other_rows(q, s, f, end, False)
        g[s] = 0.5 * (g[s] + other.v + self.allowance + self.tie)
        G[s] *= 0.5
        np.add.at(G, (np.repeat(s, 8), cols.ravel()), 0.5 * other.g.ravel())

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_s (len(rows), 12, 12) of the ``rows`` at q (zero where shallow or far)."""
        self.evaluate(q)  # (the selection at q)
        rows = np.asarray(rows)
        H = np.zeros((len(rows), self.width, self.width))
        f = self.selected[rows]
        near = f >= 0
        if near.any():
            H[near, :8, :8] = self._rows(q, rows[near], f[near], True).h
        end = self.end[rows]
        tie = near & (end >= 0)
        if tie.any():
            other, cols = self._other_rows(q, rows[tie], f[tie], end[tie], True)
            where = np.flatnonzero(tie)
            H[where] *= 0.5
            at = (where[:, None, None], cols[:, :, None], cols[:, None, :])
            np.add.at(H, at, 0.5 * other.h)
        return H
