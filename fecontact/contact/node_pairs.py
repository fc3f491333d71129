"""Points of a body against rigid obstacles: nodes against a ``Plane`` or ``Circle``, and a rigid
``Point`` against a beam's centreline segments. Notation as in :mod:`fecontact.contact.laws`."""

from __future__ import annotations

import numpy as np

from ..bodies.base import RigidDefaults
from ..bodies.beam import Beam2D
from ..bodies.beam3d import Beam3D
from ..bodies.solid import Solid
from ..errors import InputError, check_range
from .base import PairDefaults, at_beam_ends
from .beam_sides import closest_rows, line_coordinates
from .circle_watch import CircleSegmentDepths
from .friction import tangent_basis
from .geometry import closest_on_segments, point_line_distance
from .obstacles import Circle, Plane, Point
from .registry import register_pair
from .section_segments import segment_turns

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
        # a beam touches through its section, `clearance` from the node: the section's turn
        # moves the touching point, which the slip rows must see (a spun rod rolls)
        self.turning = clearance > 0.0 and isinstance(body, (Beam2D, Beam3D))

    @property
    def size(self) -> int:
        return len(self.nodes)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offset = model.offset_of(self.body)

    def watch(self):
        """A 2D solid's boundary segments, or a beam's elements, against an outside Circle
        (a Sphere for a ``Beam3D``): the nodes' rows let a circle smaller than an edge in
        between two nodes, which the watch measures."""
        circle, body = self.obstacle, self.body
        segments = isinstance(body, (Beam2D, Beam3D)) or (isinstance(body, Solid) and body.dim == 2)
        if segments and isinstance(circle, Circle) and circle.dim == body.dim:
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
        body's rotation included: its vertices roll); on a beam's section, whose touching
        point lies at arm = −c n from the node (c the clearance, n the obstacle's normal),
        also to the section's turn, ẋ_p = ẋ + ω × arm."""
        qb = q[self.offset : self.offset + self.body.ndof]
        x, dofs, Jx, _ = self.body.point_kinematics(qb, self.nodes)
        n = self.obstacle.gap(x)[1]
        T = tangent_basis(n)
        GT = np.einsum("mti,mik->mtk", T, Jx)
        if self.turning:
            turns, B = self.body.section_turns(qb, self.nodes, -self.clearance * n)
            dofs = np.concatenate([dofs, turns], axis=1)
            GT = np.concatenate([GT, np.einsum("mti,mik->mtk", T, B)], axis=2)
        return dofs + self.offset, GT, T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·(x(q) − x(q_n)): a rigid body's vertex moves along a chord, not along the
        tangent of its rotation; a beam section's touching point x + arm against where that
        material point was at q_n, turned back with its section."""
        s = slice(self.offset, self.offset + self.body.ndof)
        if self.turning:
            x = self._positions(q[s], self.nodes)
            arm = -self.clearance * self.obstacle.gap(x)[1]
            before = self.body.section_points_before(q[s], q_n[s], self.nodes, arm)
            return np.einsum("mtd,md->mt", T, x + arm - before)
        if self.body.linear_kinematics:
            return None
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
    vertex the gap is the distance to that node. Two rows, as a node against a beam
    (:func:`.beam_sides.closest_rows`): row 0 against the closest segment, and where the point
    lies in a valley of the beam (a node bent toward it, the point projecting inside both of
    its segments), rows 0 and 1 against the two lines in the order of their indices (row 1
    has g = +inf elsewhere). One row there swapped lines between the iterates: under a node
    of a landing strip the correction cycled.
    """

    linear = False
    size = 2
    shared_points = True  # both rows hold the one point

    def points(self) -> np.ndarray:
        return np.zeros(2, int)

    def __init__(self, body, obstacle: Point, restitution: float = 0.0, clearance=0.0):
        self.body = body
        self.clearance = clearance  # m: half the beam's thickness
        self.obstacle = obstacle
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.segments = body.segments()
        self.offset = 0
        self._start = None  # line coordinates (t₀, f₀) (1, E) of the point at the step's start
        f0 = self._signed_distance(np.zeros(body.ndof))
        if f0 == 0.0:
            raise InputError("the Point lies exactly on the beam centreline at t = 0")

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)
        self._start = None

    def _ends(self, q: np.ndarray):
        x = self.body.positions(q[self.offset : self.offset + self.body.ndof])
        return x[self.segments[:, 0]], x[self.segments[:, 1]]

    def _lines(self, q: np.ndarray):
        x1, x2 = self._ends(q)
        return line_coordinates(self.obstacle.position[None, None], x1[None], x2[None])

    looks_ahead = True

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Keep the point's line coordinates at the start of the coming step (the sides)."""
        self._start = self._lines(q)

    def _rows(self, q: np.ndarray):
        """Both rows' elements, sides, line flags, ξ and use (:func:`closest_rows`), and the
        elements' ends."""
        x1, x2 = self._ends(q)
        t, f = self._lines(q)
        P = self.obstacle.position[None]
        return closest_rows(self.segments, self._start, P, x1, x2, t, f), x1, x2

    def _closest(self, x):
        x1, x2 = x[self.segments[:, 0]], x[self.segments[:, 1]]
        xi, dist = closest_on_segments(self.obstacle.position, x1, x2)
        e = int(np.argmin(dist))
        return e, xi[e], x1[e], x2[e] - x1[e]

    frictional = True

    def _normals(self, e, side, line, xe, x1, x2):
        """Unit normals (2, 2) of both rows from the beam toward the point (zero unused)."""
        d = x2[e] - x1[e]
        n = side[:, None] * np.stack([-d[:, 1], d[:, 0]], axis=1)
        n /= np.linalg.norm(d, axis=1)[:, None]
        rel = self.obstacle.position - (x1[e] + xe[:, None] * d)
        caps = rel / np.linalg.norm(rel, axis=1)[:, None]
        return np.where(line[:, None], n, caps)

    def tangents(self, q: np.ndarray):
        """Slip rows of the fixed point against the beam's material point at each row's
        parameter ξ, on its section c n from the centreline (c the ``clearance``), which the
        section's turn moves (:mod:`.section_segments`): −T((1 − ξ) ẋ_a + ξ ẋ_b + ω(ξ) × c n),
        T the tangent of the contact plane; the linear form is the slip of a step."""
        (e, side, line, xe, used), x1, x2 = self._rows(q)
        n = self._normals(e, side, line, xe, x1, x2)
        T = tangent_basis(n) * used[:, None, None]
        qb = q[self.offset : self.offset + self.body.ndof]
        turns, B = segment_turns(self.body, qb, self.segments[e], xe, self.clearance * n)
        w = np.stack([1.0 - xe, xe], axis=1)[:, :, None, None] * T[:, None]
        GT = -np.concatenate([w[:, 0], w[:, 1], np.einsum("mti,mik->mtk", T, B)], axis=2)
        return np.concatenate([self._dofs(e), self.offset + turns], axis=1), GT, T

    def _dofs(self, e):
        nodes = self.segments[e].ravel()
        return self.offset + self.body.node_translation_dofs(nodes).reshape(len(e), 4)

    def _signed_distance(self, q_local):
        e, xi, x1, d = self._closest(self.body.positions(q_local))
        w = self.obstacle.position - x1
        return (d[0] * w[1] - d[1] * w[0]) / np.linalg.norm(d)

    def evaluate(self, q: np.ndarray):
        (e, side, line, xe, used), x1, x2 = self._rows(q)
        P, r = self.obstacle.position, self.obstacle.radius + self.clearance
        g, G, H = np.full(2, np.inf), np.zeros((2, 4)), np.zeros((2, 4, 4))
        for j in np.flatnonzero(used):
            a, b = x1[e[j]], x2[e[j]]
            if line[j]:  # the point is rigid: derivatives with respect to the ends only
                f, Gj, Hj = point_line_distance(P[None], a[None], b[None])
                g[j], G[j], H[j] = side[j] * f[0] - r, side[j] * Gj[0, 2:], side[j] * Hj[0, 2:, 2:]
                continue
            ev = a + xe[j] * (b - a) - P
            dist = np.linalg.norm(ev)
            ev = ev / dist
            k = 0 if xe[j] == 0.0 else 2
            g[j] = dist - r
            G[j, k : k + 2] = ev
            H[j, k : k + 2, k : k + 2] = (np.eye(2) - np.outer(ev, ev)) / dist
        return g, self._dofs(e), G, H


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
