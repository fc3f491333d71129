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
integrated on sub-triangles, as a box's region planes are. Two segments meeting at a joint
that turns by less than ``KINK`` count as one region (a straight rod has no boundary there).

The gradient and curvature of one segment's distance with respect to x, a_s and b_s are those
of :func:`fecontact.contact.segment3d.tube_distance` with the point as the partner.
"""

from __future__ import annotations

import numpy as np

__all__ = ["AT_NODE", "KINK", "closest_on_polyline", "region_labels", "straight_runs"]

AT_NODE = 1e-9
"""A point whose closest parameter ξ on its segment is within this of 0 or 1 has its closest
point at the node: the label of a point on a region's boundary does not change with round-off
(a solid's node under a straight rod's joint reads the joint from either segment)."""


KINK = 1e-2
"""Turn angle (rad) at a joint below which its two segments count as one region: the jump of
D's curvature across the joint's planes bounds a wedge of angular width θ, whose effect on a
triangle's integral stayed below the degree-5 rule's own error on a tube as wide as the
triangles (measured: rule on one triangle against 16² sub-triangles, 6.1e-7 m at θ = 0,
5.9–6.3e-7 at θ = 1e-3, 1.2–1.3e-6 at 1e-2, 0.8–3.3e-5 at 0.1; r = 1 cm, edges 1.25 cm)."""


def straight_runs(ends: np.ndarray, segments: np.ndarray, n_nodes: int):
    """The run of each segment (S,), consecutive segments whose joints turn by less than
    ``KINK`` sharing one, and each node's run where it is such a joint (n_nodes,; −1 at the
    ends and at sharper joints). The segments are a chain: segment s + 1 starts where s ends."""
    t = ends[:, 1] - ends[:, 0]
    t = t / np.linalg.norm(t, axis=1)[:, None]
    straight = np.sum(t[1:] * t[:-1], axis=1) > np.cos(KINK)  # (S − 1,) joints
    run = np.concatenate([[0], np.cumsum(~straight)])
    joint = np.full(n_nodes, -1)
    joint[segments[1:, 0][straight]] = run[1:][straight]
    return run, joint


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


def region_labels(which, xi, segments, runs) -> np.ndarray:
    """The region of each point's closest point: the run (:func:`straight_runs`) of its
    segment where it lies in a segment's interior or at a joint inside the run, −1 − k where
    it is node k (an end cap, a sharper joint). ``segments`` (S, 2) node indices, ``runs``
    the pair of arrays of :func:`straight_runs`."""
    run, joint = runs
    node = np.where(xi <= AT_NODE, segments[which, 0], segments[which, 1])
    at = (xi <= AT_NODE) | (xi >= 1.0 - AT_NODE)
    label = run[which].copy()
    at_end = at & (joint[node] < 0)
    label[at_end] = -1 - node[at_end]
    return label
