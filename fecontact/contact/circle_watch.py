"""The depth of a rigid Circle into a 2D solid's boundary polygon or a beam's centreline.

Node rows against a Circle keep the boundary nodes out, and a circle smaller than an edge
enters between two nodes unseen by them. The watch measures the circle's depth into every
boundary segment (the radius less the centre's distance to the segment, where the centre
lies on the segment's inner side or within the radius of it) at every step's end: the run's
``max_penetration`` and its warning over ``BOUND`` of the shortest boundary edge. A beam's
named nodes against a Circle (a ``Beam3D``'s against a Sphere) are watched the same way,
its elements as the segments and the pair's clearance (the section's half height or
radius) added to the radius. A rigid
``Disk`` (a moving circle) against a 2D solid's nodes is watched the same way
(:class:`DiskSegmentDepths`).
"""

from __future__ import annotations

import numpy as np

from ..bodies.solid import Solid

__all__ = ["CircleSegmentDepths", "DiskSegmentDepths"]


class CircleSegmentDepths:
    """The deepest point of an outside ``Circle`` inside a 2D solid's boundary segments, or
    within the clearance of a beam's elements (a ``Beam3D``'s against a ``Sphere``)."""

    def __init__(self, pair):
        self.pair = pair
        body = pair.body
        # (m, 2) node pairs: a solid's boundary, a beam's elements
        self.segments = body.contact_facets() if isinstance(body, Solid) else body.segments()
        X = pair.body.X[self.segments]
        self.edge = float(np.linalg.norm(X[:, 1] - X[:, 0], axis=1).min())

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        """(depth in m ≥ 0, depth over the shortest boundary edge) of the circle at q."""
        x, c, radius = self.circle(q)
        radius = radius + self.pair.clearance
        a, b = x[self.segments[:, 0]], x[self.segments[:, 1]]
        t = b - a
        s = np.clip(np.einsum("md,md->m", c - a, t) / np.einsum("md,md->m", t, t), 0.0, 1.0)
        r = np.linalg.norm(a + s[:, None] * t - c, axis=1)
        d = float(max(np.max(radius - r), 0.0))
        return d, d / self.edge

    def circle(self, q: np.ndarray):
        """The solid's node positions (n, 2), the circle's centre (2,) and radius (m) at q."""
        pair, circle = self.pair, self.pair.obstacle
        x = pair.body.positions(q[pair.offset : pair.offset + pair.body.ndof])
        return x, circle.center + circle.shift(), circle.radius

    def entering(self, q: np.ndarray) -> str:
        """What enters the solid (for a message)."""
        return "a circle between two nodes"


class DiskSegmentDepths(CircleSegmentDepths):
    """The deepest point of a rigid ``Disk`` (the pair's ``rigid``, a RigidBody2D) inside a
    2D solid's boundary segments (the pair's ``offsets`` are read at each call: set when the
    model binds it)."""

    def circle(self, q: np.ndarray):
        (oa, ob), solid, rigid = self.pair.offsets, self.pair.body, self.pair.rigid
        x = solid.positions(q[oa : oa + solid.ndof])
        return x, rigid.center(q[ob : ob + 3]), rigid.shape.radius

    def entering(self, q: np.ndarray) -> str:
        return "a rigid disk between boundary nodes"
