r"""Pointwise rows that keep a mortar interface's nodes from sinking into the other solid.

A dual mortar interface holds the weighted gaps g̃_j = ∫ Φ_j g_N dA ≥ 0: an average over
each slave node's elements, not the node's own distance. Where the gap field is far from
linear over an element — a convex kink under a coarse pole, the bulge of a disk hit at tens
of m/s — a node can lie inside the other body while its weighted gap is positive. The
safeguard adds, for every boundary node of each solid of the interface (two passes: the
slave's nodes against the master's surface, the master's nodes against the slave's), the
node-to-surface gap of :class:`~fecontact.contact.body_pairs.NodeSurfaceContact` shifted by
an allowance δ:

    g_s = g_N(x) + δ ≥ 0,   δ = ``ALLOWANCE`` × the shortest boundary edge of the surface,

g_N the signed plane gap of the node from its closest facet (−distance inside a convex
surface). The row is a candidate only for a node deeper than δ/2 (elsewhere it reports
g = +inf and a zero gradient): a node that the weighted gaps keep out, or let in by their
usual few tenths of a per cent of an edge, never sees it, so that every run in which no node
sinks deeper is unchanged bit for bit, its symmetry included. A node deeper than δ makes the
row active at both levels of the step, as any contact: Signorini at the position correction
(g_s ≥ 0 with the Alart–Curnier multiplier), Newton's impact law on the velocity jump (with
the interface's e_N and μ). Together with the node's own mortar row it can be redundant up
to round-off; the interface declares it (minimum-norm multipliers, decided once per run).

This is the active-set safeguard of segment-to-segment methods that complement a weighted
(integrated) constraint with pointwise checks where the integral lets a point through (the
two-pass node-to-segment rows of Puso & Laursen, Comput. Methods Appl. Mech. Engrg. 193,
2004, used here only where a node is found inside).
"""

from __future__ import annotations

import numpy as np

from .body_pairs import NodeSurfaceContact
from .inside import bounding_box

__all__ = [
    "ALLOWANCE",
    "MasterNodeRows",
    "SafeguardRows",
    "deep_hessians",
    "deep_rows",
    "safeguard_rows",
    "shortest_edge",
    "take_deep",
]

ALLOWANCE = 0.005
"""δ over the shortest boundary edge of the surface a node is held out of: half the depth
(1 % of an edge) a node of a mortar interface may reach, so that a node held by its row ends
within it, and above the 0.03–0.3 % the weighted gaps let a node in when they hold."""


def shortest_edge(body, facets: np.ndarray) -> float:
    """The shortest edge (m) of the boundary ``facets`` of ``body`` in its reference
    configuration."""
    x = body.positions(np.zeros(body.ndof))
    corners = x[facets]
    edges = corners - np.roll(corners, 1, axis=1)
    return float(np.sqrt((edges**2).sum(-1)).min())


class SafeguardRows(NodeSurfaceContact):
    """Every boundary node of the solid ``body`` against the surface of the solid ``master``,
    g_s = g_N + δ ≥ 0 for the nodes deeper than δ/2, +inf for the others (module
    docstring); ``restitution`` e_N as the interface's."""

    def __init__(self, body, master, restitution: float = 0.0):
        super().__init__(body, master, restitution=restitution)
        # one row per node, its closest facet's (the rows of concave features are left out:
        # the row only has to stop a node that sinks, not balance it in a dent)
        self.extra = 0
        self._row_node = np.arange(len(self.nodes))
        self._slave_dofs = body.node_translation_dofs(self.nodes)
        self.selected = self.closest = np.full(self.size, -1)
        self.allowance = ALLOWANCE * shortest_edge(master, self.facets)
        """δ (m): how deep a node may sink before its row holds it."""

    def _evaluate(self, q):
        g, dofs, G, H = super()._evaluate(q)
        return g + self.allowance, dofs, G, H

    def closest_facets(self, xs: np.ndarray, xm: np.ndarray):
        # a node farther than the margin from the master's bounding box has no facet within
        # it (the search would find none): bodies whose boxes are apart need no search
        lo, hi = bounding_box(xm)
        lo, hi = lo - self.margin, hi + self.margin
        if not np.any(np.all((xs >= lo) & (xs <= hi), axis=1)):
            empty = np.zeros(0, int)
            return empty, empty, np.zeros(0)
        return super().closest_facets(xs, xm)


class MasterNodeRows(SafeguardRows):
    """The second pass: every boundary node of the interface's master (``body`` here)
    against the slave's surface (``master`` here), g_s = g_N + δ for a node deeper than δ/2;
    the others report a gap ``far`` beyond any detection distance (twice the pair's), with
    a zero gradient: never a candidate, and finite, so that a row that a correction's
    iterate lifts out stays a number. Frictionless: the rows only stop a node sinking."""

    inside_test = False  # g_s is held to round-off like a signed distance
    # the base margin is enough: a node that sinks is found by the inside test however deep
    looks_ahead = False
    _far = None  # (margin and placement, the rows of a free flight)

    def evaluate(self, q: np.ndarray):
        xs, xm = self.positions(q)
        lo, hi = bounding_box(xm)
        lo, hi = lo - self.margin, hi + self.margin
        if np.any(np.all((xs >= lo) & (xs <= hi), axis=1)):
            return super().evaluate(q)
        # every node farther than the margin from the other body: the rows of a free flight,
        # made once per margin and placement (most steps of a run)
        key = (self.base_margin, self.offsets)
        if self._far is None or self._far[0] != key:
            far = super()._evaluate(q)
            for array in far[1:3]:
                array.flags.writeable = False
            self._far = (key, far)
        self.selected = np.full(self.size, -1)
        g, dofs, G, H = self._far[1]
        return g.copy(), dofs, G, H

    def _evaluate(self, q):
        g, dofs, G, H = super()._evaluate(q)
        shallow = ~(g < 0.5 * self.allowance)
        g[shallow] = 2.0 * self.base_margin
        G[shallow] = 0.0
        self.selected[shallow] = -1  # (no curvature either)
        return g, dofs, G, H


def safeguard_rows(body, master, restitution: float, nodes: np.ndarray):
    """The pointwise rows of a 2D interface: its slave ``nodes``' own gaps (those of its
    weighted gaps, in their order) and the rows of the master's nodes; (None, None) in 3D
    (module docstring)."""
    if body.dim != 2:
        return None, None
    rows = SafeguardRows(body, master, restitution)
    if not np.array_equal(rows.nodes, nodes):
        raise ValueError("the mortar rows' nodes must be the slave body's boundary nodes")
    return rows, MasterNodeRows(master, body, restitution)


def deep_rows(rows: SafeguardRows | None, q: np.ndarray, g: np.ndarray, entries: int):
    """The rows (m,) whose node's own gap g_N + δ (``rows`` at q) is below its weighted gap g
    and below δ/2: the node lies deeper than δ/2 inside the master. None without ``entries``
    (the interface's element pairs at q): then no element of the master lies within the
    margin of the slave's, and no slave node inside it (a free flight, at no cost)."""
    if rows is None or entries == 0:
        return np.zeros(len(g), bool)
    g_s = rows.gaps(q)
    return (g_s < g) & (g_s < 0.5 * rows.allowance)


def take_deep(rows, q, deep: np.ndarray, g: np.ndarray, dofs=None, G=None):
    """The weighted rows (g, dofs, G) with the ``deep`` ones replaced by the nodes' own
    (``rows`` at q): the dofs widened by the pointwise rows' (zero gradient on the unused
    part of a row), unchanged when none is deep."""
    if not deep.any():
        return g, dofs, G
    g_s, dofs_s, G_s, _ = rows.evaluate(q)
    g[deep] = g_s[deep]
    if G is None:
        return g, dofs, G
    G = np.concatenate([np.where(deep[:, None], 0.0, G), G_s * deep[:, None]], axis=1)
    dofs = np.concatenate([dofs, dofs_s], axis=1)
    dofs.flags.writeable = False
    return g, dofs, G


def deep_hessians(rows, q, select: np.ndarray, deep: np.ndarray, dofs: np.ndarray, k: int):
    """Hessians (len(select), w, w) of the rows ``select`` in the widened layout ``dofs``
    (width w), with the deep rows' own curvature in the pointwise block and zero elsewhere
    (the weighted rows' block, the first k columns, is the caller's to fill); and which of
    ``select`` are deep."""
    width = dofs.shape[1]
    H = np.zeros((len(select), width, width))
    deep = deep[select]
    if width > k:
        H[deep, k:, k:] = rows.hessians(q, select[deep])
    return H, deep
