r"""The distance from points in space to a polyline (a beam's centreline), and the regions of
its closest points.

A polyline of S segments (a_s, b_s) has, at a point x, the distance

    d(x) = min_s |x − p_s(x)|,  p_s = a_s + ξ_s d_s,  ξ_s = clamp((x − a_s)·d_s / |d_s|², 0, 1),

d_s = b_s − a_s. The closest point p lies in the interior of a segment (0 < ξ < 1: the
distance to its line, a cylinder's field) or at a node (ξ ∈ {0, 1}: the distance to a point,
a sphere's field, the end caps and the wedge outside a bend). Across the boundary between two
such regions d is C¹ at best: its curvature jumps (the plane through an end node normal to
its segment, the planes bounding a joint's wedge), and on the concave side of a bend, where
the closest points of two segments meet, its gradient jumps. :func:`region_labels` names the
region of each point so that a triangle whose vertices lie in different regions can be
integrated on sub-triangles, as a box's region planes are.

The gradient and curvature of one segment's distance with respect to x, a_s and b_s are those
of :func:`fecontact.contact.segment3d.tube_distance` with the point as the partner.
"""

from __future__ import annotations

import numpy as np

__all__ = ["AT_NODE", "closest_on_polyline", "region_labels"]

AT_NODE = 1e-9
"""A point whose closest parameter ξ on its segment is within this of 0 or 1 has its closest
point at the node: the label of a point on a region's boundary does not change with round-off
(a solid's node under a straight rod's joint reads the joint from either segment)."""


def closest_on_polyline(x: np.ndarray, ends: np.ndarray):
    """For points x (P, 3) and segments ``ends`` (S, 2, 3): the closest segment (P,), its
    unclamped parameter ξ of the projection on the segment's line (P,) and the distance (P,)
    (m) to the polyline. Ties between segments (the joint of a straight rod) go to the first,
    whose closest point is the same node."""
    a, d = ends[:, 0], ends[:, 1] - ends[:, 0]
    dd = np.sum(d * d, axis=1)
    # per coordinate on (P, S) arrays: three passes cheaper than (P, S, 3) contractions
    w = [x[:, i, None] - a[None, :, i] for i in range(3)]
    xi = (w[0] * d[:, 0] + w[1] * d[:, 1] + w[2] * d[:, 2]) / dd
    t = np.clip(xi, 0.0, 1.0)
    dist2 = sum((w[i] - t * d[:, i]) ** 2 for i in range(3))
    which = np.argmin(dist2, axis=1)
    rows = np.arange(len(x))
    return which, xi[rows, which], np.sqrt(dist2[rows, which])


def region_labels(which: np.ndarray, xi: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """The region of each point's closest point: the segment's index s ≥ 0 where it lies in
    the interior of segment s, −1 − k where it is node k (``segments`` (S, 2) node indices)."""
    at_a, at_b = xi <= AT_NODE, xi >= 1.0 - AT_NODE
    label = which.copy()
    label[at_a] = -1 - segments[which[at_a], 0]
    label[at_b] = -1 - segments[which[at_b], 1]
    return label
