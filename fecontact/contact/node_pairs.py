"""Points of a body against rigid obstacles: nodes against a ``Plane`` or ``Circle``, and a rigid
``Point`` against a beam's centreline segments. Notation as in :mod:`fecontact.contact.laws`."""

from __future__ import annotations

import numpy as np

from ..bodies.base import RigidDefaults
from ..bodies.beam import Beam2D
from ..bodies.solid import Solid
from ..errors import InputError, check_range
from .base import PairDefaults, at_beam_ends
from .beam_sides import line_coordinates, swept
from .circle_watch import CircleSegmentDepths
from .friction import tangent_basis
from .geometry import closest_on_segments, point_line_distance, unit
from .obstacles import Circle, Plane, Point
from .registry import register_pair

__all__ = ["NodeContact", "PointSegmentContact"]


class NodeContact(PairDefaults):
    """Points of a body (its nodes, or a rigid body's vertices) against a rigid ``Plane`` or
    ``Circle``; one contact per point.

    ``restitution`` (Newton's coefficient e_N in [0, 1]) applies to every point of the pair.
    The body maps its dofs to the point positions x(q) (``point_kinematics``); the gap of the
    obstacle φ(x) then gives G = ∇φ ∂x/∂q and ∇²g = (∂x/∂q)ᵀ ∇²φ (∂x/∂q) + ∇φ·∂²x/∂q².
    """

    def __init__(self, body, obstacle, nodes=None, restitution: float = 0.0, clearance=0.0):
        if not isinstance(obstacle, (Plane, Circle)):
            raise InputError(f"obstacle must be a Plane or Circle, got {type(obstacle).__name__}")
        self.body = body
        self.obstacle = obstacle
        self.nodes = body.contact_nodes(nodes)
        if len(self.nodes) == 0:
            raise InputError("nodes must name at least one node")
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = clearance  # m kept between the points and the obstacle
        self.at_beam_ends = at_beam_ends(body, self.nodes)
        self.linear = obstacle.linear and body.linear_kinematics
        # a rigid body moves off a plane in 3 dofs in space (2 in the plane): more points
        # than that (a box's four bottom corners) give rows redundant up to round-off
        self.redundant_rows = isinstance(body, RigidDefaults) and len(self.nodes) > (
            3 if body.ndof == 6 else 2
        )
        self.offset = 0
        # positions alone where the body has a cheaper path to them (rigid bodies)
        self._positions = body.point_positions

    @property
    def size(self) -> int:
        return len(self.nodes)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offset = model.offset_of(self.body)

    def watch(self):
        """A 2D solid's boundary segments against an outside Circle: its nodes' rows let a
        circle smaller than an edge in between two nodes, which the watch measures."""
        circle = self.obstacle
        if isinstance(self.body, Solid) and isinstance(circle, Circle) and circle.dim == 2:
            return None if circle.inside else CircleSegmentDepths(self)
        return None

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g/∂t = −∇φ·ḋ (m/s) of a moving obstacle at its current time, per contact."""
        if not self.obstacle.moving:
            return np.zeros(self.size)
        qb = q[self.offset : self.offset + self.body.ndof]
        x = self.body.point_kinematics(qb, self.nodes)[0]
        return -(self.obstacle.gap(x)[1] @ self.obstacle.speed())

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip rows: the tangents of the obstacle at each point applied to ∂x/∂q (a rigid
        body's rotation included: its vertices roll)."""
        qb = q[self.offset : self.offset + self.body.ndof]
        x, dofs, Jx, _ = self.body.point_kinematics(qb, self.nodes)
        T = tangent_basis(self.obstacle.gap(x)[1])
        return dofs + self.offset, np.einsum("mti,mik->mtk", T, Jx), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·(x(q) − x(q_n)): a rigid body's vertex moves along a chord, not along the
        tangent of its rotation."""
        if self.body.linear_kinematics:
            return None
        s = slice(self.offset, self.offset + self.body.ndof)
        dx = self._positions(q[s], self.nodes) - self._positions(q_n[s], self.nodes)
        return np.einsum("mtd,md->mt", T, dx)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """Gaps (m,) alone, without their derivatives."""
        qb = q[self.offset : self.offset + self.body.ndof]
        return self.obstacle.gap_values(self._positions(qb, self.nodes)) - self.clearance

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dof indices (m, d), gradient values (m, d), Hessians (m, d, d) or None."""
        qb = q[self.offset : self.offset + self.body.ndof]
        x, dofs, Jx, Hx = self.body.point_kinematics(qb, self.nodes)
        g, Gx, Hphi = self.obstacle.gap(x)
        G = np.einsum("mi,mik->mk", Gx, Jx)
        H = None
        if Hphi is not None:
            H = np.einsum("mik,mij,mjl->mkl", Jx, Hphi, Jx)
        if Hx is not None:
            H = np.einsum("mi,mikl->mkl", Gx, Hx) + (0.0 if H is None else H)
        return g - self.clearance, dofs + self.offset, G, H


class PointSegmentContact(PairDefaults):
    """A rigid ``Point`` (or small disk) against the centreline segments of a beam.

    The contact point slides along the beam: the gap is the distance from the point to the
    closest segment minus the radius, signed by the side of that segment the point is on,
    decided from the motion over the step (:mod:`.beam_sides`). When the closest point is a
    vertex the gap is the distance to that node.
    """

    linear = False

    def __init__(self, body, obstacle: Point, restitution: float = 0.0, clearance=0.0):
        self.body = body
        self.clearance = clearance  # m: half the beam's thickness
        self.obstacle = obstacle
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.segments = body.segments()
        self.offset = 0
        self._start = None  # line coordinates (t₀, f₀) of the point at the step's start
        f0 = self._signed_distance(np.zeros(body.ndof))
        if f0 == 0.0:
            raise InputError("the Point lies exactly on the beam centreline at t = 0")

    size = 1

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)
        self._start = None

    def _lines(self, q: np.ndarray):
        x = self.body.positions(q[self.offset : self.offset + self.body.ndof])
        return line_coordinates(
            self.obstacle.position, x[self.segments[:, 0]], x[self.segments[:, 1]]
        )

    looks_ahead = True

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Keep the point's line coordinates at the start of the coming step (the sides)."""
        self._start = self._lines(q)

    def _side(self, e: int, x1: np.ndarray, d: np.ndarray):
        """The side of element e (first node x1, direction d) the point is on, and whether it
        went through the element in this step (:func:`.beam_sides.swept`)."""
        t, f = line_coordinates(self.obstacle.position, x1, x1 + d)
        start = None if self._start is None else (self._start[0][e], self._start[1][e])
        side, crossed = swept(start, t, f)
        return float(side), bool(crossed)

    def _closest(self, x):
        x1, x2 = x[self.segments[:, 0]], x[self.segments[:, 1]]
        xi, dist = closest_on_segments(self.obstacle.position, x1, x2)
        e = int(np.argmin(dist))
        return e, xi[e], x1[e], x2[e] - x1[e]

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip row of the fixed point against the beam's material point at the closest
        parameter ξ: −T((1 − ξ) ẋ_a + ξ ẋ_b), T the tangent of the contact plane."""
        body = self.body
        e, xi, x1, d = self._closest(body.positions(q[self.offset : self.offset + body.ndof]))
        a, b = self.segments[e]
        dofs = self.offset + body.node_translation_dofs([a, b]).ravel()
        side, crossed = self._side(e, x1, d)
        if 0.0 < xi < 1.0 or crossed:  # the side's normal of the segment, as in the gap
            n = side * np.array([-d[1], d[0]]) / np.linalg.norm(d)
        else:
            n = unit(self.obstacle.position - (x1 + xi * d), "point and beam node")[0]
        T = tangent_basis(n[None])
        GT = -np.concatenate([(1.0 - xi) * T, xi * T], axis=2)
        return dofs[None, :], GT, T

    def _signed_distance(self, q_local):
        e, xi, x1, d = self._closest(self.body.positions(q_local))
        w = self.obstacle.position - x1
        return (d[0] * w[1] - d[1] * w[0]) / np.linalg.norm(d)

    def evaluate(self, q: np.ndarray):
        body = self.body
        q_local = q[self.offset : self.offset + body.ndof]
        e, xi, x1, d = self._closest(body.positions(q_local))
        a, b = self.segments[e]
        tdofs = self.offset + body.node_translation_dofs([a, b]).ravel()
        P, r = self.obstacle.position, self.obstacle.radius + self.clearance
        side, crossed = self._side(e, x1, d)
        if 0.0 < xi < 1.0 or crossed:
            # the point is rigid: derivatives with respect to the segment's ends only
            f, G, H = point_line_distance(P[None], x1[None], (x1 + d)[None])
            g, G, H = side * f[0] - r, side * G[0, 2:], side * H[0, 2:, 2:]
        else:
            xv = x1 + xi * d
            ev = xv - P
            dist = np.linalg.norm(ev)
            ev = ev / dist
            g = dist - r
            G = np.zeros(4)
            H = np.zeros((4, 4))
            k = 0 if xi == 0.0 else 2
            G[k : k + 2] = ev
            H[k : k + 2, k : k + 2] = (np.eye(2) - np.outer(ev, ev)) / dist
        return np.array([g]), tdofs[None, :], G[None, :], H[None, :, :]


@register_pair(object, Plane)
@register_pair(object, Circle)
def _nodes_on_obstacle(body, obstacle, nodes, restitution, clearance):
    """Any body's nodes (default: those ``contact_nodes`` gives) against a Plane or Circle."""
    return NodeContact(body, obstacle, nodes, restitution, clearance)


@register_pair(Beam2D, Point)
def _point_on_beam(beam, point, nodes, restitution, clearance):
    if nodes is not None:
        raise InputError("nodes: a Point obstacle acts on beam segments, not on nodes")
    return PointSegmentContact(beam, point, restitution, clearance)
