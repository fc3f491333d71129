"""Segments against a rigid ``Circle``: contact between the nodes, of a beam's centreline or
of a 2D solid's boundary.

A strip wrapped on a cylinder touches it at the middle of its chords, not at its nodes: node
contacts let each segment cut into the cylinder by up to L²/(8R), and a peg narrower than a
solid's boundary edge enters between two nodes. Here every segment carries
one contact at its closest point to the centre c,

    x* = a + ξ(b − a),  ξ = clamp((c − a)·(b − a)/|b − a|², 0, 1),  g = |x* − c| − R − t,

t the clearance (half the beam's thickness). Since ξ makes the distance stationary, the
gradient is that of the point x* with ξ frozen, G = [(1 − ξ)e, ξe] over (a, b) with
e = (x* − c)/|x* − c|; the Hessian adds the motion of x* along the segment (the exact second
derivative of the distance to the segment's line, :func:`point_line_distance`). At an end
(ξ = 0 or 1) the gap is that node's distance. Notation as in :mod:`fecontact.contact.laws`.

With ``joints`` (a solid's closed boundary) a node's row is not repeated: a row whose closest
point is the node it shares with the next segment (ξ = 1), or with a previous segment whose
closest point lies inside it (ξ = 0), reads g = +∞ (no row). The node then lies on a segment
whose own row is at least as close, and two equal rows (both segments at the node, under a
peg on a node's normal) or nearly equal ones (one just inside its segment) are never both
held: those made the multipliers least-squares at every step. A row left out is still a
candidate of the correction by its distance (:meth:`SegmentCircleContact.reach`): a
correction that dents the node under a peg makes both segments' closest points inner, two
touching points, and holds the second one too (before, the step was retaken).
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam import Beam2D
from ..bodies.solid import Solid
from ..errors import InputError, check_range
from .base import PairDefaults
from .friction import tangent_basis
from .geometry import closest_on_segments, point_line_distance
from .node_pairs import NodeContact
from .obstacles import Circle
from .registry import register_pair

__all__ = ["SegmentCircleContact"]


class SegmentCircleContact(PairDefaults):
    """The ``segments`` (node pairs, default a ``Beam2D``'s centreline) of a body against a
    rigid ``Circle`` seen from outside; one contact per segment. ``clearance`` (m) keeps the
    segments that far from the circle (half a beam's thickness); ``restitution`` is Newton's
    e_N in [0, 1]; ``joints``: a node's row is not repeated by the two segments at it."""

    linear = False
    frictional = True
    duplicate_rows = True  # (two segments clipped to their shared node: one row twice)

    def __init__(
        self, body, obstacle: Circle, restitution=0.0, clearance=0.0, segments=None, joints=False
    ) -> None:
        self.body = body
        self.obstacle = obstacle
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = clearance
        self.segments = body.segments() if segments is None else segments
        self.offset = 0
        self.joints = None  # (m,) the segment starting at each one's end and ending at its start
        if joints:
            self.joints = _chain(self.segments, body.n_nodes)
            self.hides_rows = True

    @property
    def size(self) -> int:
        return len(self.segments)

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)

    @property
    def radius(self) -> float:
        """The circle's radius (m)."""
        return self.obstacle.radius

    def centre(self, q: np.ndarray) -> np.ndarray:
        """The circle's centre (2,) at q (m)."""
        return self.obstacle.center + self.obstacle.shift()

    def _closest(self, q: np.ndarray):
        """Ends a, b (m, 2), parameter ξ (m,), distance (m,) and unit normal e (m, 2) from
        the centre to the closest point."""
        x = self.body.positions(q[self.offset : self.offset + self.body.ndof])
        a, b = x[self.segments[:, 0]], x[self.segments[:, 1]]
        centre = self.centre(q)
        xi, dist = closest_on_segments(centre, a, b)
        if np.any(dist == 0.0):
            raise InputError("a segment passes through the circle's centre: no normal")
        e = (a + xi[:, None] * (b - a) - centre) / dist[:, None]
        return a, b, xi, dist, e

    def _used(self, xi: np.ndarray) -> np.ndarray:
        """Rows (m,) that are not another segment's at their node (module docstring)."""
        if self.joints is None:
            return np.ones(len(xi), bool)
        after, before = self.joints
        shared_end = (xi == 1.0) & (after >= 0)
        prev = xi[np.maximum(before, 0)]
        shared_start = (xi == 0.0) & (before >= 0) & (prev > 0.0) & (prev < 1.0)
        return ~(shared_end | shared_start)

    def _dofs(self) -> np.ndarray:
        nodes = self.segments.ravel()
        return self.offset + self.body.node_translation_dofs(nodes).reshape(self.size, 4)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """Gaps (m,) alone, without their derivatives."""
        _, _, xi, dist, _ = self._closest(q)
        g = dist - self.radius - self.clearance
        return np.where(self._used(xi), g, np.inf)

    def reach(self, q: np.ndarray) -> np.ndarray:
        """Every segment's distance (m,) to the circle, a row left out at its node included:
        the node can dent within a correction, and the row then holds the segment."""
        _, _, _, dist, _ = self._closest(q)
        return dist - self.radius - self.clearance

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dof indices (m, 4), gradient values (m, 4), Hessians (m, 4, 4)."""
        a, b, xi, dist, e = self._closest(q)
        G = np.concatenate([(1.0 - xi)[:, None] * e, xi[:, None] * e], axis=1)
        H = np.zeros((self.size, 4, 4))
        inner = (xi > 0.0) & (xi < 1.0)
        if inner.any():
            centre = np.broadcast_to(self.centre(q), a.shape)
            f, _, Hf = point_line_distance(centre[inner], a[inner], b[inner])
            H[inner] = np.sign(f)[:, None, None] * Hf[:, 2:, 2:]
        for end, k in ((xi == 0.0, 0), (xi == 1.0, 2)):
            if end.any():
                ee = e[end]
                block = (np.eye(2) - ee[:, :, None] * ee[:, None, :]) / dist[end, None, None]
                H[np.ix_(end.nonzero()[0], range(k, k + 2), range(k, k + 2))] = block
        g = dist - self.radius - self.clearance
        used = self._used(xi)
        if not used.all():
            g, G, H = np.where(used, g, np.inf), G * used[:, None], H * used[:, None, None]
        return g, self._dofs(), G, H

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g/∂t = −e·ċ (m/s) of a moving circle, per segment."""
        if not self.obstacle.moving:
            return np.zeros(self.size)
        _, _, xi, _, e = self._closest(q)
        return np.where(self._used(xi), -(e @ self.obstacle.speed()), 0.0)

    def tangents(self, q: np.ndarray):
        """Slip rows of the material point at ξ: T((1 − ξ)ȧ + ξḃ), T the circle's tangent."""
        _, _, xi, _, e = self._closest(q)
        T = tangent_basis(e) * self._used(xi)[:, None, None]
        GT = np.concatenate([(1.0 - xi)[:, None, None] * T, xi[:, None, None] * T], axis=2)
        return self._dofs(), GT, T


@register_pair(Beam2D, Circle)
def _beam_on_circle(beam, circle, nodes, restitution, clearance):
    """The chords cut into a convex obstacle between the nodes: a beam's segments against a
    Circle seen from outside, unless ``nodes`` are named; nodes against a cavity."""
    if circle.inside or nodes is not None:
        return NodeContact(beam, circle, nodes, restitution, clearance)
    return SegmentCircleContact(beam, circle, restitution, clearance)


@register_pair(Solid, Circle)
def _solid_on_circle(solid, circle, nodes, restitution, clearance):
    """A peg narrower than an edge enters between two boundary nodes: a 2D P1 solid's
    boundary segments against a Circle seen from outside, unless ``nodes`` are named; nodes
    against a cavity (a convex cavity cannot enter between nodes), in 3D, and on P2 cells
    (whose boundary is curved: straight segments are not its surface; the run measures the
    circle's depth into their chords, :mod:`fecontact.contact.circle_watch`)."""
    if circle.inside or nodes is not None or circle.dim != 2 or solid.element != "P1":
        return NodeContact(solid, circle, nodes, restitution, clearance)
    segments = solid.contact_facets()
    return SegmentCircleContact(solid, circle, restitution, clearance, segments, joints=True)


def _chain(segments: np.ndarray, n_nodes: int):
    """For each segment (m, 2 node indices) the one starting at its end node and the one
    ending at its start node (m,) each, −1 where there is none."""
    start, end = np.full(n_nodes, -1), np.full(n_nodes, -1)
    index = np.arange(len(segments))
    start[segments[:, 0]], end[segments[:, 1]] = index, index
    return start[segments[:, 1]], end[segments[:, 0]]
