"""Which facet each slave node of a node-to-surface pair takes among its candidate pairs.

Of the candidate (node, facet) pairs of the broad phase (:mod:`.facet_search`), a node takes
the facet closest to it (the Euclidean distance to the facet itself, its projection clipped
to the facet) among those within the ``margin``; among facets equally close to within
``tie`` (m), the one with the largest |g|, g the node's signed gap from the facet's plane
(:mod:`.body_pairs` says why); among equal |g|, the first candidate.

A step of a 2D pair has a few candidate pairs (about ten in ``two_disks``), where numpy's
per-call overhead (about 1 µs a call, some thirty calls) outweighs the arithmetic: up to
``FEW`` pairs are chosen in plain floats, the same operations in the same order as the
arrays' path (:func:`fecontact.contact.geometry.closest_facet_distance`), so the same
numbers to the bit.
"""

from __future__ import annotations

import math

import numpy as np

from .geometry import closest_facet_distance

__all__ = ["FEW", "closest_among"]

FEW = 32
"""Candidate pairs up to which a 2D pair chooses in plain floats."""


def closest_among(xs, xm, facets, s, f, margin: float, tie: float):
    """(slave indices, facet indices, plane gaps in m) of the slave nodes (positions xs (n, d),
    m) with a facet of ``facets`` (master node positions xm) within ``margin`` among the
    candidate pairs (s, f): each node's closest facet (module docstring), in the order of the
    nodes."""
    if s.size == 0:
        return s, f, np.zeros(0)
    if xs.shape[1] == 2 and s.size <= FEW:
        return _few_segments(xs[s].tolist(), xm[facets[f]].tolist(), s, f, margin, tie)
    dist, g = closest_facet_distance(xs[s], xm[facets[f]])
    keep = dist <= margin
    s, f, dist, g = s[keep], f[keep], dist[keep], g[keep]
    if s.size == 0:
        return s, f, g
    dmin = np.full(len(xs), np.inf)
    np.minimum.at(dmin, s, dist)
    score = np.where(dist <= dmin[s] + tie, np.abs(g), -1.0)
    order = np.lexsort((-score, s))  # by node, then the largest score first (stable)
    s_sorted = s[order]
    first = np.empty(len(s), dtype=bool)
    first[0] = True
    np.not_equal(s_sorted[1:], s_sorted[:-1], out=first[1:])
    first = order[first]
    return s[first], f[first], g[first]


def _few_segments(points: list, segments: list, s, f, margin: float, tie: float):
    """:func:`closest_among` in 2D over a few candidate pairs, in plain floats: ``points``
    [(x, y)] and ``segments`` [((a_x, a_y), (b_x, b_y))] of each pair (m)."""
    kept, dmin = [], {}
    for i, ((px, py), ((ax, ay), (bx, by))) in enumerate(zip(points, segments, strict=True)):
        tx, ty, wx, wy = bx - ax, by - ay, px - ax, py - ay
        tt = tx * tx + ty * ty
        xi = min(max((wx * tx + wy * ty) / tt, 0.0), 1.0)  # (NaN stays NaN, as np.clip)
        rx, ry = wx - xi * tx, wy - xi * ty
        dist = math.sqrt(rx * rx + ry * ry)
        if dist <= margin:
            node = int(s[i])
            kept.append((node, i, dist, (ty * wx - tx * wy) / math.sqrt(tt)))
            if not dist >= dmin.get(node, math.inf):
                dmin[node] = dist
    best = {}  # node: (score, pair, g), the first of the largest score
    for node, i, dist, g in kept:
        score = abs(g) if dist <= dmin[node] + tie else -1.0
        if node not in best or score > best[node][0]:
            best[node] = (score, i, g)
    nodes = sorted(best)
    pairs = [best[n][1] for n in nodes]
    return np.array(nodes, dtype=s.dtype), f[pairs], np.array([best[n][2] for n in nodes])
