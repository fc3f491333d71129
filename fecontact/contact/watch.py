"""The inside/outside watch of two solids in a dual mortar interface.

A mortar interface constrains weighted gaps, integrals over the slave surface, and no node's
own distance: a node may sit inside the other body by the discretization's own amount, and a
node that no weighted gap covers (no facet overlap within the search) is not seen at all. The
watch measures every boundary node of each body against the other's discretized boundary at
the end of every step, by the inside/outside test of :mod:`fecontact.contact.inside`, through
the broad phase of :mod:`fecontact.contact.facet_search` (a node outside and far from the
other surface is not tested again until the bodies have moved). The depth is reported (the
run's ``max_penetration``): the weighted gaps let a node in by the interpolation's own error
(measured 0.03–0.3 % of the shortest edge on a ball landing on a slab), and a step is not
retaken for it; in 2D a node of either body deeper than half a per cent of an edge is held
by its own gap (:mod:`fecontact.contact.mortar_safeguard`; on the quadratic faces of two 2D
P2 solids a node inside the flat pieces is measured on the curved segment, as its row
measures it, :mod:`fecontact.contact.mortar_p2_safeguard`). A node deeper than ``BOUND`` of
the other surface's shortest edge is a warning of the run. What the watch has measured
beyond that: 19 % of an edge (2.4 mm) in an oblique frictional impact of two disks
(``two_disks``, refinements 2, offset 0.02 m, μ = 0.3), and two coarse balls (one
refinement, pole to pole) that no weighted gap covered and that passed through each other
while triangles counted as facing only beyond 120°.
"""

from __future__ import annotations

import numpy as np

from .beam_sides import StripNodeDepths
from .circle_watch import CircleSegmentDepths
from .facet_search import FacetSearch
from .inside import bounding_box
from .mortar_interface import MortarInterface
from .mortar_p2_safeguard import DeepNodeRowsP2, piece_depths
from .mortar_safeguard import DeepNodeRows, shortest_edge

__all__ = [
    "BOUND",
    "SolidWatch",
    "entering",
    "entry_depth",
    "held_nodes",
    "solid_watches",
    "watched_depth",
]

BOUND = 0.01
"""Deepest a node of a mortar interface may sit inside the other solid, over the shortest
boundary edge of that solid: the discretization's own amount; deeper is reported."""


class SolidWatch:
    """Every boundary node of each solid of a mortar ``pair`` against the other's boundary."""

    def __init__(self, pair: MortarInterface):
        self.pair = pair
        a, b = pair.bodies
        facets = (a.contact_facets(), b.contact_facets())
        self.nodes = tuple(np.unique(f) for f in facets)
        # the nodes of a against the surface of b, then those of b against a
        self.searches = (FacetSearch(facets[1]), FacetSearch(facets[0]))
        # the shortest boundary edge of the surface each body's nodes are tested against (m)
        self.edges = (shortest_edge(b, facets[1]), shortest_edge(a, facets[0]))
        # quadratic faces: a node inside the flat pieces is measured on the curve, as their
        # pointwise rows measure it (a dented face's pieces lie in front of it)
        rows = (pair.pointwise, pair.master_rows)
        self.curves = tuple(r.segments if isinstance(r, DeepNodeRowsP2) else None for r in rows)

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        """The deepest boundary node of either body inside the other at q: its depth (m, ≥ 0)
        and the largest depth over the shortest boundary edge of the surface entered."""
        return self.measure(q)[:2]

    def entry(self, q: np.ndarray, q_start: np.ndarray | None = None) -> float:
        """The largest depth at q of a boundary node inside the other body over the shortest
        edge of the facet closest to it (the facet it entered), the measure of the predictor
        (:data:`fecontact.time.penetration.DEEPEST`): a node is judged by the facet it
        meets, not by the finest cell elsewhere on the surface (a graded mesh). With
        ``q_start`` (the start of the step) a node that was deeper there than twice ``BOUND``
        of that edge is measured by what the step adds beyond it. The weighted gaps hold no
        node's own depth, and on coarse P1 balls they let nodes sink a few per cent of an
        edge over a lasting contact (reported); a smaller step does not take that out, and
        measured from outside it failed every halving of the step. Within twice the bound
        the total depth counts: measured from each node's start, the head-on balls at
        63 Δx/c went deeper (1.4 % of the local edge) and created 0.47 % of the scale. The facet's
        shortest edge, not its longest or their mean: on the balls' graded meshes, whose finest
        triangles are those under the contact, those let the head-on approach at 63 Δx/c in
        deeper and create 0.45 % and 0.47 % of the energy scale (0 with the shortest)."""
        return self.measure(q, q_start)[2]

    def _positions(self, q: np.ndarray) -> list[np.ndarray]:
        pair = self.pair
        return [
            b.positions(q[o : o + b.ndof]) for b, o in zip(pair.bodies, pair.offsets, strict=True)
        ]

    def measure(self, q: np.ndarray, q_start: np.ndarray | None = None):
        """(deepest node's depth in m, the largest depth over the shortest boundary edge of
        the surface entered, the largest over the shortest edge of each node's closest
        facet, less its depth at ``q_start`` if given), 0 when no node is inside."""
        deepest = relative = entered = 0.0
        for i, nodes, d, f, xm in self.inside(q):
            t = xm[self.searches[i].facets[f]]
            edge = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).min(axis=1)
            deepest = max(deepest, float(d.max()))
            relative = max(relative, float(d.max()) / self.edges[i])
            if q_start is not None:  # (beyond twice the allowance: what the step adds)
                start = self._start_depth(q_start, i, nodes)
                d = d - np.maximum(start - 2.0 * BOUND * edge, 0.0)
            entered = max(entered, float(np.max(d / edge)))
        return deepest, relative, entered

    def inside(self, q: np.ndarray):
        """For each body i with boundary nodes inside the other at q: (i, those nodes as
        indices into ``self.nodes[i]``, their depths (m, > 0), the closest facet of each
        among the other body's, the other body's node positions)."""
        x = self._positions(q)
        # no node lies inside a closed surface from outside its bounding box: two bodies
        # whose boxes are apart (a free flight) need no test
        (lo_a, hi_a), (lo_b, hi_b) = (bounding_box(y) for y in x)
        if np.any(hi_a < lo_b) or np.any(hi_b < lo_a):
            return
        for i, search in enumerate(self.searches):
            xs, xm = x[i][self.nodes[i]], x[1 - i]
            watched = search.watched(xs, xm, self.pair.margin)
            s, f = search.surface.signed_distance(xm, xs[watched], outside=False)
            inside = s < 0.0
            if inside.any():
                d = self._depths(i, xs[watched][inside], xm, -s[inside], f[inside])
                yield i, np.flatnonzero(watched)[inside], d, f[inside], xm

    def admissible_gaps(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """The gaps (m) that admit a state at t = 0, from the interface's ``rows`` at q (one
        per slave node): a state is admitted unless a node of either body lies inside the
        other. A row reads −depth of the deepest node it answers for inside the other body
        (its own slave node; a master node inside the slave, by the corners of the slave
        facet closest to it), else its own reading where that is not negative, 0 where it
        is: the weighted gaps' stand-off under a fine curved master, with no node inside."""
        pair = self.pair
        row_of = np.full(pair.body.n_nodes, -1)
        row_of[pair.nodes] = np.arange(pair.size)
        depth = np.zeros(pair.size)
        for i, nodes, d, f, _ in self.inside(q):
            if i == 0:
                at = row_of[self.nodes[0][nodes]]
            else:
                corners = self.searches[1].facets[f]
                at, d = row_of[corners].ravel(), np.repeat(d, corners.shape[1])
            if np.any(at < 0):
                raise ValueError("the watched slave nodes must be the interface's row nodes")
            np.maximum.at(depth, at, d)
        return np.where(depth > 0.0, -depth, np.maximum(rows, 0.0))

    def _start_depth(self, q_start: np.ndarray, i: int, nodes: np.ndarray) -> np.ndarray:
        """The depth (m, ≥ 0) at ``q_start`` of the boundary nodes ``nodes`` (indices into
        ``self.nodes[i]``) of body i inside the other body."""
        x = self._positions(q_start)
        surface = self.searches[i].surface
        points = x[i][self.nodes[i][nodes]]
        s, f = surface.signed_distance(x[1 - i], points, outside=False)
        inside = s < 0.0
        d = np.zeros(len(s))
        d[inside] = self._depths(i, points[inside], x[1 - i], -s[inside], f[inside])
        return d

    def _depths(self, i: int, points, xm, depth, facets) -> np.ndarray:
        """The depths (m) of body i's ``points`` inside the other body's flat pieces
        (``depth``, closest ``facets``), on quadratic faces read on the curve."""
        if self.curves[i] is None:
            return depth
        return piece_depths(self.curves[i], points, xm, facets)

    def entering(self, q: np.ndarray) -> str:
        """What of the pair enters the other at its deepest (for a message)."""
        return "a node"


def solid_watches(pairs) -> list[SolidWatch]:
    """The watches of the mortar interfaces among ``pairs``."""
    return [SolidWatch(pair) for pair in pairs if isinstance(pair, MortarInterface)]


def held_nodes(pairs, q: np.ndarray) -> int:
    """How many nodes of the mortar interfaces among ``pairs`` lie deeper than half the
    allowance δ inside the other solid at q, so that their own rows hold them
    (:mod:`fecontact.contact.mortar_safeguard`): a held node ends a step about δ deep."""
    return sum(pair.held(q) for pair in pairs if isinstance(pair, DeepNodeRows))


def watched_depth(watches, q: np.ndarray) -> tuple[float, float]:
    """The deepest boundary node of the ``watches``' solids inside the other at q: (depth in
    m, depth over the shortest edge of the surface entered), as :meth:`SolidWatch.depth`."""
    depths = [watch.depth(q) for watch in watches]
    return max((d for d, _ in depths), default=0.0), max((r for _, r in depths), default=0.0)


def entry_depth(watches, q: np.ndarray, q_start: np.ndarray | None = None) -> float:
    """The largest depth at q of a point of the ``watches``' bodies inside another body over
    the size of the facet it entered, less a mortar node's depth at ``q_start``
    (:meth:`SolidWatch.entry`; a rigid pair's own local measure, the second of its
    ``depth``)."""
    return max((_entry(watch, q, q_start) for watch in watches), default=0.0)


def _entry(watch, q: np.ndarray, q_start: np.ndarray | None = None) -> float:
    if isinstance(watch, (CircleSegmentDepths, StripNodeDepths)):
        # no row holds a circle between two nodes or a strip's nodes that only the reversed
        # pair would hold, and a smaller step does not take them out: they are reported (the
        # run's record and warning), not retaken
        return 0.0
    return watch.entry(q, q_start) if isinstance(watch, SolidWatch) else watch.depth(q)[1]


def entering(watches, q: np.ndarray) -> str:
    """What enters another body deepest at q, over its local facet (as :func:`entry_depth`),
    among the ``watches``: a node, or a rigid box's edge or corner."""
    ratios = [_entry(watch, q) for watch in watches]
    return watches[int(np.argmax(ratios))].entering(q) if watches else "a node"
