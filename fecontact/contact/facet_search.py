"""The broad phase of node-to-surface contact: which facets of a master body are near each
slave node, and which slave nodes may lie inside the master, kept while the bodies move little.

A search at positions (x_s, x_m) with margin m finds the (node, facet) pairs whose node and
facet centroid are within r + ρ (r = 1.25 m, ρ the largest centroid-to-vertex distance) with
a k-d tree, among the nodes in the master's box grown by r and the facets near those nodes.
It is kept while no node of either body has moved more than δ/2 = m/8 since; then every
facet within m of a node is still among its pairs.

Which nodes may be inside the master ("watched"): those within 0.3 m of a facet at the
search, and the others that the inside/outside test (:mod:`fecontact.contact.inside`) finds
inside then. While the search is kept every node of either body, and so every point of a
facet, moves by less than m/8: a node relative to the surface by less than m/4 < 0.3 m. A node
outside and farther than 0.3 m from every facet (a node without a pair is farther than r)
cannot cross the surface meanwhile: it stays outside, and no test needs to look at it again.

Which pairs may hold a node's closest facet (:meth:`FacetSearch.closest_candidates`, 3D): the
distance d of every pair is taken at the search, and again once the bodies have moved by a
few per cent of the margin (``RERANK``): d₀, and each node's least d₀*. While no node of the
slave has moved by more than μ_s and none of the master by more than μ_m in a component
since, a node's distance to a facet (a point of a triangle moves no farther than its farthest
vertex) has changed by at most b = √3 (μ_s + μ_m). A pair with d₀ > d₀* + 2b + τ is then
farther than the node's closest facet by more than the tie τ of
:func:`~fecontact.contact.closest_facet.closest_among`: it can be neither that facet nor one
of its ties, and leaving it out chooses the same facet with the same numbers. On the default
two balls a node has some 80 candidate facets within the search's reach, of which about 4
are within 5 % of the margin of its closest.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .geometry import closest_facet_distance
from .inside import Surface, bounding_box, facet_distances

__all__ = ["NEAR", "RERANK", "FacetSearch"]

NEAR = 0.3
"""Nodes within this fraction of the margin of a facet are watched: while the search is kept
the two bodies move relative to each other by less than 1/4 of the margin."""

RERANK = 0.05
"""The pairs' distances are taken again once the bound 2b of the motion since they were taken
exceeds this fraction of the margin: 2b grows to 0.87 of it while a search is kept, and
the pairs within 2b of a node's closest with it (on the default two balls a step moves them
by about 1 % of the margin, 2b)."""


class FacetSearch:
    """Candidate (slave node, facet) pairs of a master's ``facets`` (n, k) and the slave
    nodes that may be inside it (module docstring)."""

    def __init__(self, facets: np.ndarray):
        self.facets = facets
        self.surface = Surface(facets)
        self._cache = None  # (x_s, x_m, margin, (slave, facet) pairs, watched nodes)
        self._ranked = None  # (the search, (x_s, x_m) ranked at, d₀ of its pairs, their d₀*)

    def reset(self) -> None:
        self._cache = None
        self._ranked = None

    def pairs(self, xs: np.ndarray, xm: np.ndarray, margin: float):
        """(slave indices, facet indices) of the candidate pairs at positions xs, xm (m)."""
        return self._search(xs, xm, margin)[3]

    def watched(self, xs: np.ndarray, xm: np.ndarray, margin: float) -> np.ndarray:
        """Mask of the slave nodes that may be inside the master at positions xs, xm."""
        return self._search(xs, xm, margin)[4]

    def found(self, xs: np.ndarray, xm: np.ndarray, margin: float):
        """(slave indices, facet indices, watched mask) of one search: :meth:`pairs` and
        :meth:`watched` at once."""
        cache = self._search(xs, xm, margin)
        return cache[3][0], cache[3][1], cache[4]

    def closest_candidates(self, xs: np.ndarray, xm: np.ndarray, margin: float, tie: float):
        """:meth:`found` less the pairs that cannot hold a node's closest facet at xs, xm, nor
        one within ``tie`` (m) of it (module docstring); all of them in 2D, where a node's
        candidates are few and their distances cheap."""
        cache = self._search(xs, xm, margin)
        s, f = cache[3]
        if xs.shape[1] == 2 or s.size == 0:
            return s, f, cache[4]
        ranked = self._ranked
        b = 0.0 if ranked is None else np.sqrt(3.0) * sum(_moved(xs, xm, ranked[1]))
        if ranked is None or ranked[0] is not cache or 2.0 * b > RERANK * margin:
            d0 = closest_facet_distance(xs[s], xm[self.facets[f]])[0]
            least = np.full(len(xs), np.inf)
            np.minimum.at(least, s, d0)
            ranked = self._ranked = (cache, (xs.copy(), xm.copy()), d0, least[s])
            b = 0.0
        # (1e-6 of the margin: far beyond the round-off of the distances, and too little to
        # keep a pair that the bound leaves out)
        keep = ranked[2] <= ranked[3] + (2.0 * b + tie + 1e-6 * margin)
        return s[keep], f[keep], cache[4]

    @property
    def kept(self):
        """The search kept for the next ones (both bodies' node positions at it, the margin,
        the pairs, the watched nodes), None before one."""
        return self._cache

    @property
    def last_watched(self) -> np.ndarray:
        """The watched nodes of the last search (all, before any)."""
        return np.ones(1, dtype=bool) if self._cache is None else self._cache[4]

    def _search(self, xs, xm, margin):
        cache = self._cache
        if cache is not None and cache[2] == margin:
            if 2.0 * max(_moved(xs, xm, cache)) <= 0.25 * margin:
                return cache
        s, f = self._search_pairs(xs, xm, 1.25 * margin)
        # nodes within NEAR × margin of a facet are watched; the others, if outside, cannot
        # reach the surface before the search is refreshed (module docstring)
        near = np.zeros(len(xs), dtype=bool)
        if s.size:
            near[s[facet_distances(xs[s], xm[self.facets[f]]) <= NEAR * margin]] = True
        watch = near.copy()
        rest = np.flatnonzero(~near)
        if rest.size:
            depth = self.surface.signed_distance(xm, xs[rest], outside=False)[0]
            watch[rest[depth < 0.0]] = True
        self._cache = (xs.copy(), xm.copy(), margin, (s, f), watch)
        return self._cache

    def _search_pairs(self, xs: np.ndarray, xm: np.ndarray, r: float):
        lo, hi = bounding_box(xm)
        lo, hi = lo - r, hi + r
        near = np.flatnonzero(np.all((xs >= lo) & (xs <= hi), axis=1))
        if near.size == 0:
            return near, near
        xf = xm[self.facets]
        centroid = xf.mean(axis=1)
        reach = float(np.sqrt(np.max(np.sum((xf - centroid[:, None]) ** 2, axis=2))))
        slo, shi = bounding_box(xs[near])
        slo, shi = slo - r - reach, shi + r + reach
        fnear = np.flatnonzero(np.all((centroid >= slo) & (centroid <= shi), axis=1))
        if fnear.size == 0:
            return fnear, fnear
        pairs = cKDTree(xs[near]).sparse_distance_matrix(
            cKDTree(centroid[fnear]), r + reach, output_type="ndarray"
        )
        return near[pairs["i"]], fnear[pairs["j"]]


def _moved(xs: np.ndarray, xm: np.ndarray, cache) -> tuple[float, float]:
    """The largest change of a component (m) of a slave node's and of a master node's position
    since the search ``cache``."""
    return np.abs(xs - cache[0]).max(initial=0.0), np.abs(xm - cache[1]).max()
