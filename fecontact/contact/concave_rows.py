r"""Extra node-to-surface rows where the master's surface is concave.

A slave node held by the plane of one facet cannot rest at the bottom of a concave dent: no
single plane balances a force along the axis of the cone that the facets around a concave
vertex (or the two facets of a concave edge) form. Held by one facet the node slides across
the vertex onto the next, whose plane pushes it back, and the smooth step's Newton iteration
alternates between them. Near a concave feature the node therefore gets one row per facet of
the feature: the plane gap of each facet f′ that

- is nearly as close to the node as its closest facet: its distance to the facet itself
  exceeds the closest by at most ``NEAR_FEATURE`` times the closest facet's longest edge, and
  the node lies within that distance of the surface, and
- among those near facets, is concave against one that shares a vertex with it (the other's
  centroid lies above its plane by more than ``CONCAVE`` times that edge) and convex against
  none (a flat surface adds no row, so every result away from concave features is
  unchanged; the set does not depend on which near facet is the closest, so that the rows
  do not change while the node slides across the feature).

Near a concave feature the surface is the upper envelope of its facets' planes, so each
extended plane lies under the surface and its gap is never below the node's true distance:
the rows together describe the dent. Around a vertex the rows are redundant (six planes
meet in one point); their multipliers are then minimum-norm (see
:func:`fecontact.contact.laws.kkt_multipliers`). Each node has ``1 + extra`` rows i + j n
(j = 0 … extra; g = +inf when unused), so the number of contacts stays fixed over a run: a
node with one facet keeps row i, one at a concave feature fills them in the order of its
facets (:func:`slot_rows`).

Within a Newton loop (the smooth step, from q_n; the position correction, from q̃) a row
once present is held to the loop's end with its facet (:class:`ConcaveRows`): on a nearly
flat zone the test reads concave at one iterate and convex at the next (the loop's own move
flattens it), and rows that appeared and vanished between iterates kept the loop from
settling. A node that gains rows within the loop keeps its closest facet on its first row:
laid out by the facets' indices, that row's plane jumped to another facet of the dent.
Measured in ``docs/validation/stress_3d.md`` (node-to-surface balls with friction).
"""

from __future__ import annotations

import numpy as np

from .geometry import closest_facet_distance, facet_plane_gap

__all__ = [
    "CONCAVE",
    "NEAR_FEATURE",
    "ConcaveRows",
    "concave_rows",
    "first_closest",
    "held_rows",
    "joined",
    "slot_rows",
    "with_held",
]

CONCAVE = 1e-6
"""A facet is concave against another when its centroid lies this fraction of the other's
longest edge above the other's plane (a flat surface deformed by round-off stays flat)."""

NEAR_FEATURE = 0.1
"""A concave neighbour gets a row when its distance to the node exceeds the closest facet's
by at most this fraction of the closest facet's longest edge."""


class ConcaveRows:
    """The rows of a node-to-surface pair beyond each node's closest facet: ``extra`` per
    node (row i + j n of node i, j = 1 … extra), at concave features, decided at each
    evaluation or held from one configuration (:meth:`hold_rows`). The pair provides
    ``extra``, ``nodes``, ``_row_node`` (the node of each row), its search (``search``,
    ``margin``), ``facets``, ``closest``, ``selected``, ``evaluate`` and ``_last`` (the
    result it keeps)."""

    _held = None  # (rows, facets, nodes) held by hold_rows

    @property
    def shared_points(self) -> bool:
        """Whether a node has several rows (they hold one point, the node)."""
        return self.extra > 0

    def points(self) -> np.ndarray:
        return self._row_node

    @property
    def holds_rows(self) -> bool:
        """Whether :meth:`hold_rows` holds anything: rows at concave features (3D)."""
        return self.extra > 0

    def hold_rows(self, q: np.ndarray) -> None:
        """Hold the rows of the nodes with extra rows at q, with their facets, until
        :meth:`release_rows`: no row vanishes between the iterates of a Newton loop, and a
        node that gains rows at an iterate (a dent the loop makes) keeps them, its closest
        facet on its first row (:func:`first_closest`)."""
        self.evaluate(q)
        rows = np.flatnonzero(self.selected >= 0)
        self._held = held_rows(rows, self.selected[rows], len(self.nodes))

    def release_rows(self) -> None:
        """Decide the rows at each evaluation again."""
        self._held = self._last = None  # (the result kept was of the held rows)

    def node_rows(self, s, f, xs, xm):
        """The rows and facets of the primary pairs (s, f) (slave indices, facets) with the
        extra ones at the slave positions xs and master positions xm, or those held."""
        rows, facets = slot_rows(s, f, *self._concave(xs, xm), len(xs)) if s.size else (s, f)
        if self._held is None:
            return rows, facets
        n = len(xs)
        found = held_rows(*first_closest(rows, facets, s, f, n), n)
        self._held = joined(self._held, found, n)
        return with_held(s, f, self._held)

    def _concave(self, xs: np.ndarray, xm: np.ndarray):
        """(rows, facets) of the extra rows at concave features (:func:`concave_rows`)."""
        s, f = self.search.pairs(xs, xm, self.margin)
        dist = closest_facet_distance(xs[s], xm[self.facets[f]])[0]
        keep = dist <= self.margin
        primary = self.closest[: len(xs)]
        plane = lambda x, xf: facet_plane_gap(x, xf, hessian=False)[0]  # noqa: E731
        return concave_rows(
            (s[keep], f[keep]), dist[keep], primary, self.facets, xm, plane, self.extra
        )


def concave_rows(pairs, dist, primary, facets, xm, normal_gap, extra: int):
    """Extra (row, facet) pairs of the slave nodes near a concave feature.

    ``pairs`` = (slave indices, facet indices) of the candidate pairs with their distances
    ``dist`` (m) to the facets themselves; ``primary`` (n,) each node's closest facet (−1:
    none); ``facets`` (n_f, k) the master's facet vertices at positions ``xm``;
    ``normal_gap(x, xf)`` the signed plane gaps of points x from facets xf; ``extra`` the
    rows per node beyond the first. Returns the (slave indices, facets) of the extra pairs.
    """
    s, f = pairs
    n = len(primary)
    has = primary[s] >= 0
    s, f, dist = s[has], f[has], dist[has]
    xp = xm[facets[primary[s]]]
    edge = np.max(np.linalg.norm(xp - np.roll(xp, 1, axis=1), axis=2), axis=1)
    dmin = np.full(n, np.inf)
    np.minimum.at(dmin, s, dist)
    # the facets about as close as the closest, of a node near the surface (one deeper
    # inside the master is no longer in the dent: the correction takes it back along its
    # closest facet alone)
    near = (dist <= dmin[s] + NEAR_FEATURE * edge) & (dmin[s] <= NEAR_FEATURE * edge)
    s, f, dist, edge = s[near], f[near], dist[near], edge[near]
    i, j = _pairs_within(s)
    if i.size == 0:
        return i, i
    # facet j against facet i: sharing a vertex, its centroid above (concave) or below
    # (convex) the plane of i; the rows are the near facets concave against another and
    # convex against none, so that the set does not depend on which of them is the closest
    shares = np.any(facets[f[i]][:, :, None] == facets[f[j]][:, None, :], axis=(1, 2))
    height = normal_gap(xm[facets[f[j]]].mean(axis=1), xm[facets[f[i]]])
    tol = CONCAVE * edge[i]
    concave = np.bincount(i, shares & (height > tol), len(s)) > 0
    convex = np.bincount(i, shares & (height < -tol), len(s)) > 0
    keep = concave & ~convex & (f != primary[s])
    s, f, dist = s[keep], f[keep], dist[keep]
    # the facets nearest each node first, at most ``extra`` of them
    order = np.lexsort((dist, s))
    s, f = s[order], f[order]
    keep = _rank(s) < extra
    return s[keep], f[keep]


def _pairs_within(s):
    """Index pairs (i, j), i ≠ j, of the entries of s with equal values."""
    order = np.argsort(s, kind="stable")
    ss = s[order]
    start = np.r_[0, np.flatnonzero(ss[1:] != ss[:-1]) + 1] if ss.size else ss
    size = np.diff(np.r_[start, len(ss)])
    count = np.repeat(size, size)  # the group size of each sorted entry
    first = np.repeat(start, size)
    i = np.repeat(np.arange(len(ss)), count)
    j = np.repeat(first, count) + (np.arange(len(i)) - np.repeat(np.cumsum(count) - count, count))
    keep = i != j
    return order[i[keep]], order[j[keep]]


def slot_rows(s, f, se, fe, n: int):
    """Rows of the primary pairs (s, f) and the extra pairs (se, fe) of n slave nodes: a node
    with one facet keeps row s; a node with several takes rows s + j n in the order of its
    facets' indices, so that a row keeps its facet while the closest one changes among them
    (an active set and its multipliers stay attached to their facets)."""
    if se.size == 0:
        return s, f
    s, f = np.r_[s, se], np.r_[f, fe]
    order = np.lexsort((f, s))
    s, f = s[order], f[order]
    return s + n * _rank(s), f


def held_rows(rows, facets, n: int):
    """(rows, facets, nodes) of the slave nodes that have extra rows among ``rows`` (their
    ``facets``) of n nodes: every row of such a node, its primary one included."""
    nodes = np.unique(rows[rows >= n] % n)
    mine = np.isin(rows % n, nodes)
    return rows[mine], facets[mine], nodes


def first_closest(rows, facets, s, f, n: int):
    """The rows (slot layout of :func:`slot_rows`) with each node's closest facet (the
    primary pairs (s, f)) moved to its first row, the facet there to the closest's row: a
    node that gains rows within a Newton loop keeps the plane its first row had."""
    closest = np.full(n, -1)
    closest[s] = f
    node, slot = rows % n, rows // n
    at = np.zeros(n, int)
    mine = facets == closest[node]
    at[node[mine]] = slot[mine]
    j = at[node]
    slot = np.where(slot == 0, j, np.where(slot == j, 0, slot))
    return node + n * slot, facets


def joined(held, found, n: int):
    """The ``held`` rows (:func:`held_rows`) with those ``found`` of the nodes not held yet."""
    rows, facets, nodes = found
    new = ~np.isin(rows % n, held[2])
    return np.r_[held[0], rows[new]], np.r_[held[1], facets[new]], np.union1d(held[2], nodes)


def with_held(s, f, held):
    """The rows and facets of the primary pairs (s, f) with the ``held`` rows
    (:func:`held_rows`) in place of those of their nodes: a held node keeps its facets, the
    others their closest alone."""
    rows, facets, nodes = held
    keep = ~np.isin(s, nodes)
    return np.r_[s[keep], rows], np.r_[f[keep], facets]


def _rank(s):
    """The position of each entry among the equal entries of the sorted array s."""
    start = np.r_[0, np.flatnonzero(s[1:] != s[:-1]) + 1]
    return np.arange(len(s)) - np.repeat(start, np.diff(np.r_[start, len(s)]))
