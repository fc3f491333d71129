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
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet
from .mortar_p2_curves import curve_at, curve_foot, quadratic_curve, quadratic_segments
from .mortar_safeguard import DeepNodeRows

__all__ = ["DeepNodeRowsP2", "curved_gaps", "piece_depths"]


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
    another P2 solid (module docstring)."""

    def __init__(self, body, master, restitution: float = 0.0):
        super().__init__(body, master, restitution)
        self.segments = quadratic_segments(master)
        self._segment_dofs = master.node_translation_dofs(self.segments.ravel()).reshape(
            len(self.segments), -1
        )
        self.width = 2 + self._segment_dofs.shape[1]

    def _rows(self, q, s, f, hessian):
        """The local coordinates (n, 8) of the rows s read from the pieces f and their gaps."""
        xs, xm = self.positions(q)
        seg = self.segments[f % len(self.segments)]  # (piece i and n + i: segment i)
        z = np.concatenate([xs[self._row_node[s]], xm[seg].reshape(len(s), 6)], axis=1)
        return curved_gaps(z, hessian)

    def _shifted(self, q):
        xs, xm = self.positions(q)
        m, (oa, ob) = self.size, self.offsets
        g = np.full(m, np.inf)
        dofs = np.empty((m, self.width), dtype=int)
        dofs[:, :2] = oa + self._slave_dofs
        dofs[:, 2:] = ob + self._segment_dofs[0]
        G = np.zeros((m, self.width))
        s, f, _ = self.closest_facets(xs, xm)
        self.selected = np.full(m, -1)
        self.selected[s] = f
        self.closest = self.selected.copy()
        if s.size:
            jet = self._rows(q, s, f, False)
            g[s], G[s] = jet.v + self.allowance, jet.g
            dofs[s, 2:] = ob + self._segment_dofs[f % len(self.segments)]
        return g, dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_s (len(rows), 8, 8) of the ``rows`` at q (zero where shallow or far)."""
        self.evaluate(q)  # (the selection at q)
        rows = np.asarray(rows)
        H = np.zeros((len(rows), self.width, self.width))
        f = self.selected[rows]
        near = f >= 0
        if near.any():
            H[near] = self._rows(q, rows[near], f[near], True).h
        return H
