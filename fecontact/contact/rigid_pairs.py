r"""Contact pairs of rigid disks: against obstacles, other disks, polygons and beams.

Every pair here is one contact (``size`` 1; a disk against a beam has one per element) whose
gap g(q) (m; > 0 open, < 0 penetrating) is the distance between the two shapes, with its exact
gradient G = ∂g/∂q and Hessian ∇²g over the few dofs it depends on. Notation: c the disk
centre and r its radius, e unit vectors, J = [[0, −1], [1, 0]] the rotation by +90°, and
K = (I − e eᵀ)/d the curvature of the distance d = |x| at x = d e.

==========================  ======================================================================
pair                        gap
==========================  ======================================================================
``DiskObstacleContact``     φ(c) − r, φ the signed gap of a ``Plane`` or ``Circle`` obstacle
``DiskDiskContact``         |c_b − c_a| − r_a − r_b
``DiskPolygonContact``      s(ρ) − r with ρ = R(φ_p)ᵀ(c − c_p) the centre in the polygon's frame
                            and s the signed distance to the convex polygon
``DiskBeamContact``         per element: distance from c to the centreline segment − r −
                            clearance, signed by the side of the element the disk is on,
                            decided from its motion over the step (:mod:`.beam_sides`)
==========================  ======================================================================

A polygon's distance s(ρ) is piecewise: n_e·(ρ − v_e) where the closest point lies inside an
edge (or when ρ is inside the polygon, the largest such value), |ρ − v_i| near a vertex. It is
continuously differentiable across the pieces; the Hessian is that of the current piece.
Body–body pairs carry ``body`` (the first body given), ``bodies`` (both) and
``obstacle = None``. Polygon vertices against a ``Plane`` or ``Circle`` are
:class:`fecontact.contact.NodeContact` pairs (through the body's ``point_kinematics``).
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam import Beam2D
from ..bodies.rigid import Disk, Polygon, RigidBody2D, rotation
from ..errors import InputError, check_positive, check_range
from .base import PairDefaults
from .beam_sides import line_coordinates, swept
from .disk_batches import DiskDiskBatch, DiskPlaneBatch
from .friction import tangent_basis
from .geometry import distance_curvature, point_line_distance, polygon_distance, unit
from .node_pairs import NodeContact
from .obstacles import Circle, Plane
from .registry import pair_factory, register_pair
from .section_segments import segment_turns

__all__ = [
    "DiskObstacleContact",
    "DiskDiskContact",
    "DiskPolygonContact",
    "DiskBeamContact",
    "rigid_pair",
]

_PERP = np.array([[0.0, -1.0], [1.0, 0.0]])


def _is_disk(body) -> bool:
    return isinstance(body, RigidBody2D) and isinstance(body.shape, Disk)


def _is_polygon(body) -> bool:
    return isinstance(body, RigidBody2D) and isinstance(body.shape, Polygon)


class _Pair(PairDefaults):
    """What every pair here shares: one contact, its restitution and its place in q."""

    size = 1
    linear = False

    def __init__(self, bodies, restitution: float):
        self.bodies = tuple(bodies)
        self.body = self.bodies[0]
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.offsets = [0] * len(self.bodies)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offsets = [model.offset_of(b) for b in self.bodies]

    def _local(self, q: np.ndarray, i: int) -> np.ndarray:
        o = self.offsets[i]
        return q[o : o + self.bodies[i].ndof]


class DiskObstacleContact(_Pair):
    """A rigid ``Disk`` against a rigid ``Plane`` or ``Circle`` (outside or cavity):
    g = φ(c) − r, the obstacle's gap of the centre less the radius."""

    def __init__(self, disk: RigidBody2D, obstacle, restitution: float = 0.0):
        if not _is_disk(disk):
            raise InputError("body must be a RigidBody2D with a Disk shape")
        if not isinstance(obstacle, (Plane, Circle)):
            raise InputError(f"obstacle must be a Plane or Circle, got {type(obstacle).__name__}")
        super().__init__([disk], restitution)
        self.obstacle = obstacle
        self.linear = obstacle.linear

    def evaluate(self, q: np.ndarray):
        """Gap (1,), global dofs (1, 2) of the centre, gradient (1, 2), Hessian (1, 2, 2)."""
        disk = self.body
        c = disk.center(self._local(q, 0))[None, :]
        g, G, H = self.obstacle.gap(c)
        dofs = self.offsets[0] + np.arange(2)[None, :]
        return g - disk.shape.radius, dofs, np.array(G), H

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g/∂t = −∇φ(c)·ḋ (m/s) of a moving obstacle at its current time."""
        if not self.obstacle.moving:
            return np.zeros(1)
        c = self.body.center(self._local(q, 0))[None, :]
        return -(self.obstacle.gap(c)[1] @ self.obstacle.speed())

    def batch_key(self):
        """Fixed planes, with friction or without, are evaluated together."""
        if not isinstance(self.obstacle, Plane) or self.obstacle.moving:
            return None
        return DiskPlaneBatch, self.friction > 0.0

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip of the disk's lowest point c − r n: t·ċ + r ω over (x, y, θ) (t = (n_y, −n_x),
        so a disk rolling along +t turns clockwise, ω < 0)."""
        disk = self.body
        n = self.obstacle.gap(disk.center(self._local(q, 0))[None, :])[1]
        T = tangent_basis(n)
        GT = np.concatenate([T, [[[disk.shape.radius]]]], axis=2)
        return self.offsets[0] + np.arange(3)[None, :], GT, T


class DiskDiskContact(_Pair):
    """Two rigid disks: g = |c_b − c_a| − r_a − r_b."""

    def __init__(self, a: RigidBody2D, b: RigidBody2D, restitution: float = 0.0):
        if not (_is_disk(a) and _is_disk(b)):
            raise InputError("both bodies must be RigidBody2D with a Disk shape")
        if a is b:
            raise InputError("a disk cannot contact itself")
        super().__init__([a, b], restitution)

    def evaluate(self, q: np.ndarray):
        """Gap (1,), global dofs (1, 4) of both centres, gradient (1, 4), Hessian (1, 4, 4)."""
        a, b = self.bodies
        e, d = unit(b.center(self._local(q, 1)) - a.center(self._local(q, 0)), "disk centres")
        g = d - a.shape.radius - b.shape.radius
        K = distance_curvature(e, d)
        G = np.concatenate([-e, e])
        H = np.block([[K, -K], [-K, K]])
        dofs = np.concatenate([self.offsets[0] + np.arange(2), self.offsets[1] + np.arange(2)])
        return np.array([g]), dofs[None, :], G[None, :], H[None, :, :]

    def batch_key(self):
        return DiskDiskBatch, self.friction > 0.0

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip of b's contact point against a's: t·(ċ_b − ċ_a) + r_b ω_b + r_a ω_a over
        (x, y, θ) of a then b; e = (c_b − c_a)/|c_b − c_a| is b's normal."""
        a, b = self.bodies
        e, _ = unit(b.center(self._local(q, 1)) - a.center(self._local(q, 0)), "disk centres")
        t = tangent_basis(e[None])[0, 0]
        GT = np.r_[-t, a.shape.radius, t, b.shape.radius]
        dofs = np.r_[self.offsets[0] + np.arange(3), self.offsets[1] + np.arange(3)]
        return dofs[None, :], GT[None, None, :], t[None, None, :]


class DiskPolygonContact(_Pair):
    """A rigid ``Disk`` against a rigid convex ``Polygon`` (its edges and vertices).

    In the polygon's frame the disk centre is ρ = R(φ)ᵀ(c − c_p), φ the polygon's angle, and
    g = s(ρ) − r. With A = ∂ρ/∂(c, c_p, θ_p) = [Rᵀ, −Rᵀ, −Jρ] and s' = ∂s/∂ρ:
    G = s'ᵀA and ∇²g = Aᵀ s'' A + Σ_i s'_i ∇²ρ_i, where the only second derivatives of ρ are
    ∂²ρ/∂c∂θ = −J Rᵀ, ∂²ρ/∂c_p∂θ = J Rᵀ and ∂²ρ/∂θ² = −ρ. The disk's rotation enters the
    slip only (friction). ``body`` is whichever of the two was given first.
    """

    def __init__(self, disk: RigidBody2D, polygon: RigidBody2D, restitution: float = 0.0):
        if not _is_disk(disk):
            raise InputError("disk must be a RigidBody2D with a Disk shape")
        if not _is_polygon(polygon):
            raise InputError("polygon must be a RigidBody2D with a Polygon shape")
        super().__init__([disk, polygon], restitution)

    def evaluate(self, q: np.ndarray):
        """Gap (1,), global dofs (1, 5): disk (x, y) then polygon (x, y, θ), gradient (1, 5),
        Hessian (1, 5, 5)."""
        disk, poly = self.bodies
        qd, qp = self._local(q, 0), self._local(q, 1)
        Rt = rotation(poly.orientation(qp)).T
        rho = Rt @ (disk.center(qd) - poly.center(qp))
        shape = poly.shape
        s, ds, dds = polygon_distance(shape.vertices, shape.normals, rho)
        A = np.hstack([Rt, -Rt, (-_PERP @ rho)[:, None]])
        G = ds @ A
        H = A.T @ dds @ A
        b = ds @ (-_PERP @ Rt)  # Σ_i s'_i ∂²ρ_i/∂c∂θ
        H[:2, 4] += b
        H[4, :2] += b
        H[2:4, 4] -= b
        H[4, 2:4] -= b
        H[4, 4] -= ds @ rho
        o_d, o_p = self.offsets
        dofs = np.concatenate([o_d + np.arange(2), o_p + np.arange(3)])
        return np.array([s - disk.shape.radius]), dofs[None, :], G[None, :], H[None, :, :]

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip of the disk's contact point x_c = c − r n against the polygon's material point
        there: t·(ċ − ċ_p) + r ω + ω_p n·(x_c − c_p), over (x, y, θ) of the disk then the
        polygon."""
        disk, poly = self.bodies
        qd, qp = self._local(q, 0), self._local(q, 1)
        R = rotation(poly.orientation(qp))
        c, cp = disk.center(qd), poly.center(qp)
        shape = poly.shape
        ds = polygon_distance(shape.vertices, shape.normals, R.T @ (c - cp))[1]
        n = R @ ds
        t = tangent_basis(n[None])[0, 0]
        r = disk.shape.radius
        GT = np.r_[t, r, -t, n @ (c - r * n - cp)]
        o_d, o_p = self.offsets
        dofs = np.r_[o_d + np.arange(3), o_p + np.arange(3)]
        return dofs[None, :], GT[None, None, :], t[None, None, :]


class DiskBeamContact(_Pair):
    """A rigid ``Disk`` striking the centreline of a ``Beam2D``: one contact per element.

    The gap of element e = (a, b) is the distance from the disk centre c to the segment, less
    r and ``clearance`` (m, half the beam thickness, say). Where the closest point lies inside
    the segment it is the distance to the segment's line, signed by the side of the element
    the disk is on, decided over each step from its motion (:mod:`.beam_sides`: the side it
    came from if its centre's path crossed the element, else where it is); at an end it is
    the distance to that node. Every element has its gap, continuous in the configuration:
    a disk over a node shared by two elements is held by both, by one row twice where both
    clip to the node (a straight or convex node: redundant rows, minimum-norm multipliers)
    and by the two lines in a kink (the beam bent around it). (Given to the element before it
    alone, the node left the next element's gap +inf, which a kink under the disk turned
    negative within a step: docs/explanation/energy_ledger.md.) Each contact
    depends on the disk's centre and on the translations of the element's two nodes.
    """

    def __init__(
        self, disk: RigidBody2D, beam: Beam2D, restitution: float = 0.0, clearance: float = 0.0
    ):
        if not _is_disk(disk):
            raise InputError("disk must be a RigidBody2D with a Disk shape")
        if not isinstance(beam, Beam2D):
            raise InputError(f"beam must be a Beam2D, got {type(beam).__name__}")
        super().__init__([disk, beam], restitution)
        self.clearance = check_positive("clearance", clearance, allow_zero=True)
        self.segments = beam.segments()
        self.size = len(self.segments)
        self._node_dofs = beam.node_translation_dofs(self.segments.ravel()).reshape(-1, 4)
        x = beam.positions(np.zeros(beam.ndof))
        xi, dist, f = self._project(disk.position, x)
        e = int(np.argmin(dist))
        # on the centreline itself no side can be told; on its line beyond an end the gap is
        # the distance to the end node, whatever the side
        if f[e] == 0.0 and 0.0 < xi[e] < 1.0:
            raise InputError("the disk centre lies on the beam centreline at t = 0")
        self._start = None  # line coordinates (t₀, f₀) of the centre at the step's start

    redundant_rows = True  # (two elements clipped to their shared node: one row twice)
    duplicate_rows = True

    def _project(self, P, x):
        """Parameter ξ ∈ [0, 1] of the closest point of each element, distance from P to the
        element, and signed distance from the element's line."""
        return self._coordinates(P, x)[1:]

    def _coordinates(self, P, x):
        """Unclamped line parameter t, clamped ξ, distance and signed distance f of the
        centre P against every element."""
        x1, x2 = x[self.segments[:, 0]], x[self.segments[:, 1]]
        t, f = line_coordinates(P, x1, x2)
        xi = np.clip(t, 0.0, 1.0)
        dist = np.linalg.norm(P - x1 - xi[:, None] * (x2 - x1), axis=1)
        return t, xi, dist, f

    def bind(self, model) -> None:
        super().bind(model)
        self._start = None

    looks_ahead = True

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Keep the centre's line coordinates at the start of the coming step (the sides)."""
        disk, beam = self.bodies
        t, _, _, f = self._coordinates(
            disk.center(self._local(q, 0)), beam.positions(self._local(q, 1))
        )
        self._start = (t, f)

    def evaluate(self, q: np.ndarray):
        """Gaps (E,), global dofs (E, 6): disk (x, y) then the element's two nodes' (u_x, u_y),
        gradients (E, 6), Hessians (E, 6, 6)."""
        disk, beam = self.bodies
        P = disk.center(self._local(q, 0))
        x = beam.positions(self._local(q, 1))
        x1, x2 = x[self.segments[:, 0]], x[self.segments[:, 1]]
        t, xi, _, f_now = self._coordinates(P, x)
        side, crossed = swept(self._start, t, f_now)
        r = disk.shape.radius + self.clearance
        E = self.size
        g, G = np.full(E, np.inf), np.zeros((E, 6))
        H = np.zeros((E, 6, 6))
        # clipped to a node: its end node or its first node, every element its own distance
        at_end = xi == 1.0
        at_end_node = xi == 0.0
        # the line holds a centre that went through the element, even at an end node (at a
        # node shared with the previous element both hold it: the beam may kink there)
        inner = ((xi > 0.0) & (xi < 1.0)) | crossed
        at_end &= ~inner
        at_end_node &= ~inner
        if inner.any():
            Pi = np.broadcast_to(P, (int(inner.sum()), 2))
            f, Gi, Hi = point_line_distance(Pi, x1[inner], x2[inner])
            s = side[inner]
            g[inner], G[inner], H[inner] = s * f - r, s[:, None] * Gi, s[:, None, None] * Hi
        for mask, k in ((at_end, 1), (at_end_node, 0)):
            if not mask.any():
                continue
            rel = P - (x2 if k else x1)[mask]
            dist = np.linalg.norm(rel, axis=1)
            if np.any(dist == 0.0):
                raise InputError("the disk centre and a beam node coincide: normal undefined")
            u = rel / dist[:, None]
            K = (np.eye(2) - u[:, :, None] * u[:, None, :]) / dist[:, None, None]
            j = slice(2 + 2 * k, 4 + 2 * k)
            g[mask] = dist - r
            G[mask, :2], G[mask, j] = u, -u
            Hm = np.zeros((len(u), 6, 6))
            Hm[:, :2, :2] = Hm[:, j, j] = K
            Hm[:, :2, j] = Hm[:, j, :2] = -K
            H[mask] = Hm
        dofs = np.hstack([np.broadcast_to(np.arange(2), (E, 2)), self.offsets[1] + self._node_dofs])
        dofs[:, :2] += self.offsets[0]
        return g, dofs, G, H

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip of the disk's contact point against the beam's at the element's closest
        parameter ξ: t·ċ + r ω − t·((1 − ξ) ẋ_a + ξ ẋ_b) + c((1 − ξ) θ̇_a + ξ θ̇_b), over
        the disk's (x, y, θ) and the element's two nodes' (u_x, u_y, θ): the beam touches
        through its section, c (the ``clearance``) from the centreline toward the disk, which
        the section's turn moves (:mod:`.section_segments`); zero for elements with no
        contact point. The linear form is the slip of a step: the section's arc c Δθ, as the
        disk's r Δφ."""
        disk, beam = self.bodies
        _, _, G, _ = self.evaluate(q)
        P = disk.center(self._local(q, 0))
        x = beam.positions(self._local(q, 1))
        xi = self._project(P, x)[0]
        n = G[:, :2]
        T = tangent_basis(n)[:, 0]  # zero where n is
        w = np.stack([1.0 - xi, xi], axis=1)[:, :, None] * T[:, None, :]
        r = disk.shape.radius * (np.linalg.norm(n, axis=1) > 0.0)
        turns, B = segment_turns(beam, self._local(q, 1), self.segments, xi, self.clearance * n)
        beam_rows = np.concatenate([w.reshape(-1, 4), np.einsum("mi,mik->mk", T, B)], axis=1)
        GT = np.concatenate([T, r[:, None], -beam_rows], axis=1)
        dofs = np.hstack(
            [
                self.offsets[0] + np.broadcast_to(np.arange(3), (self.size, 3)),
                self.offsets[1] + np.concatenate([self._node_dofs, turns], axis=1),
            ]
        )
        return dofs, GT[:, None, :], T[:, None, :]


def rigid_pair(body, other, nodes=None, restitution: float = 0.0, clearance: float = 0.0):
    """The contact pair of a rigid disk with ``other`` (an obstacle or a body), or None when
    neither is a rigid disk (then the pair is a node or segment contact).

    ``clearance`` (m) is only for a disk against a beam; ``nodes`` must be None here, the
    contact point of a disk being found from the geometry.
    """
    if not (_is_disk(body) or _is_disk(other)):
        return None
    return pair_factory(body, other)(body, other, nodes, restitution, clearance)


def _disk_first(body, other, nodes, clearance, beam: bool = False):
    """(disk, the other side) after the checks every disk pair makes."""
    if nodes is not None:
        raise InputError("nodes: a disk's contact point follows from the geometry; pass None")
    if clearance and not beam:
        raise InputError("clearance applies to a disk against a beam only")
    return (body, other) if _is_disk(body) else (other, body)


@register_pair(RigidBody2D, Plane)
@register_pair(RigidBody2D, Circle)
def _rigid_obstacle(body, obstacle, nodes, restitution, clearance):
    """A disk through its centre and radius; a polygon through its vertices."""
    if not _is_disk(body):
        return NodeContact(body, obstacle, nodes, restitution, clearance)
    disk, obstacle = _disk_first(body, obstacle, nodes, clearance)
    return DiskObstacleContact(disk, obstacle, restitution)


@register_pair(RigidBody2D, RigidBody2D)
def _rigid_rigid(body, other, nodes, restitution, clearance):
    if not (_is_disk(body) or _is_disk(other)):
        raise InputError("polygon against polygon contact is not supported")
    disk, rest = _disk_first(body, other, nodes, clearance)
    if _is_disk(rest):
        return DiskDiskContact(body, other, restitution)
    pair = DiskPolygonContact(disk, rest, restitution)
    pair.body = body
    return pair


@register_pair(RigidBody2D, Beam2D)
@register_pair(Beam2D, RigidBody2D)
def _disk_beam(body, other, nodes, restitution, clearance):
    if not (_is_disk(body) or _is_disk(other)):
        raise InputError("no contact between a Beam2D and a rigid polygon: only a Disk")
    disk, beam = _disk_first(body, other, nodes, clearance, beam=True)
    pair = DiskBeamContact(disk, beam, restitution, clearance)
    pair.body = body
    return pair
