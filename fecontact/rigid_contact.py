r"""Contact pairs of rigid disks: against obstacles, other disks, polygons and beams.

Every pair here is one contact (``size`` 1) whose gap g(q) (m; > 0 open, < 0 penetrating) is
the distance between the two shapes, with its exact gradient G = ∂g/∂q and Hessian ∇²g over the
few dofs it depends on. Notation: c the disk centre and r its radius, d = |·| distances,
e unit vectors, J = [[0, −1], [1, 0]] the rotation by +90°, and for a point at distance d
along e the curvature of the distance K = (I − e eᵀ)/d.

==========================  ======================================================================
pair                        gap
==========================  ======================================================================
``DiskObstacleContact``     φ(c) − r, φ the signed gap of a ``Plane`` or ``Circle`` obstacle
``DiskDiskContact``         |c_b − c_a| − r_a − r_b
``DiskPolygonContact``      s(ρ) − r with ρ = R(φ_p)ᵀ(c − c_p) the centre in the polygon's frame
                            and s the signed distance to the convex polygon
``DiskBeamContact``         distance from c to the closest centreline segment − r − clearance,
                            signed by the side of the beam the disk started on
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

from .beam import Beam2D
from .errors import InputError, check_positive, check_range
from .obstacles import Circle, Plane
from .rigid import Disk, Polygon, RigidBody2D, rotation

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


def _distance_curvature(e: np.ndarray, d: float) -> np.ndarray:
    """Hessian (I − e eᵀ)/d of the distance |x| at x = d e."""
    return (np.eye(2) - np.outer(e, e)) / d


def _unit(x: np.ndarray, what: str) -> tuple[np.ndarray, float]:
    d = float(np.linalg.norm(x))
    if d == 0.0:
        raise InputError(f"{what} coincide: contact normal undefined")
    return x / d, d


class _Pair:
    """What every pair here shares: one contact, its restitution and its place in q."""

    size = 1
    linear = False
    obstacle = None

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
        e, d = _unit(b.center(self._local(q, 1)) - a.center(self._local(q, 0)), "disk centres")
        g = d - a.shape.radius - b.shape.radius
        K = _distance_curvature(e, d)
        G = np.concatenate([-e, e])
        H = np.block([[K, -K], [-K, K]])
        dofs = np.concatenate([self.offsets[0] + np.arange(2), self.offsets[1] + np.arange(2)])
        return np.array([g]), dofs[None, :], G[None, :], H[None, :, :]


def polygon_distance(vertices: np.ndarray, normals: np.ndarray, x: np.ndarray):
    """Signed distance s (m) from point ``x`` to a convex counter-clockwise polygon (negative
    inside), with its gradient (2,) and Hessian (2, 2) on the piece that contains ``x``.

    ``normals[i]`` is the outward unit normal of the edge from vertex i to vertex i + 1.
    """
    edges = np.roll(vertices, -1, axis=0) - vertices
    rel = x - vertices
    s_edge = np.einsum("ij,ij->i", normals, rel)
    if np.all(s_edge < 0.0):  # inside: the nearest edge (largest s) gives the distance
        i = int(np.argmax(s_edge))
        return float(s_edge[i]), normals[i], np.zeros((2, 2))
    t = np.clip(np.einsum("ij,ij->i", rel, edges) / np.einsum("ij,ij->i", edges, edges), 0, 1)
    dist = np.linalg.norm(rel - t[:, None] * edges, axis=1)
    i = int(np.argmin(dist))
    if 0.0 < t[i] < 1.0:
        return float(s_edge[i]), normals[i], np.zeros((2, 2))
    k = i if t[i] == 0.0 else (i + 1) % len(vertices)
    e, d = _unit(x - vertices[k], "the disk centre and a polygon vertex")
    return d, e, _distance_curvature(e, d)


class DiskPolygonContact(_Pair):
    """A rigid ``Disk`` against a rigid convex ``Polygon`` (its edges and vertices).

    In the polygon's frame the disk centre is ρ = R(φ)ᵀ(c − c_p), φ the polygon's angle, and
    g = s(ρ) − r. With A = ∂ρ/∂(c, c_p, θ_p) = [Rᵀ, −Rᵀ, −Jρ] and s' = ∂s/∂ρ:
    G = s'ᵀA and ∇²g = Aᵀ s'' A + Σ_i s'_i ∇²ρ_i, where the only second derivatives of ρ are
    ∂²ρ/∂c∂θ = −J Rᵀ, ∂²ρ/∂c_p∂θ = J Rᵀ and ∂²ρ/∂θ² = −ρ. The disk's rotation does not enter
    (frictionless). ``body`` is whichever of the two was given first.
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


def point_line_distance(P: np.ndarray, x1: np.ndarray, x2: np.ndarray):
    """Signed distance f = (d × w)/|d| of P from the line through x1 and x2 (d = x2 − x1,
    w = P − x1; positive on the left of d), with its gradient (6,) and Hessian (6, 6) with
    respect to (P, x1, x2)."""
    d, w = x2 - x1, P - x1
    L = float(np.linalg.norm(d))
    c = d[0] * w[1] - d[1] * w[0]
    c_d = np.array([w[1], -w[0]])  # ∂c/∂d
    c_w = np.array([-d[1], d[0]])  # ∂c/∂w
    f_d = c_d / L - c * d / L**3
    f_w = c_w / L
    f_dd = -(np.outer(c_d, d) + np.outer(d, c_d)) / L**3 - c * np.eye(2) / L**3
    f_dd += 3.0 * c * np.outer(d, d) / L**5
    f_dw = -_PERP / L - np.outer(d, c_w) / L**3  # ∂²c/∂d∂w = −J
    Hdw = np.block([[f_dd, f_dw], [f_dw.T, np.zeros((2, 2))]])
    I, Z = np.eye(2), np.zeros((2, 2))
    T = np.block([[Z, -I, I], [I, -I, Z]])  # (d, w) as linear maps of (P, x1, x2)
    return c / L, T.T @ np.concatenate([f_d, f_w]), T.T @ Hdw @ T


class DiskBeamContact(_Pair):
    """A rigid ``Disk`` striking the centreline of a ``Beam2D``.

    The disk touches the closest centreline segment; the contact point slides along the beam
    from element to element. Where the closest point is inside a segment, the gap is the
    signed distance of the centre from the segment's line, with the sign of the side the disk
    starts on at t = 0, less r and ``clearance`` (m, half the beam thickness, say); where it
    is a node, it is the distance to that node less r and ``clearance``. The gap depends on the
    disk's centre and the translations of the segment's two nodes.
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
        self.side = 1.0
        x = beam.positions(np.zeros(beam.ndof))
        e, xi, f = self._closest(disk.position, x)
        if 0.0 < xi < 1.0:
            self.side = 1.0 if f > 0.0 else -1.0
            if f == 0.0:
                raise InputError("the disk centre lies on the beam centreline at t = 0")
        else:  # beyond an end of the beam: the side of the nearest segment's line
            self.side = 1.0 if f >= 0.0 else -1.0

    def _closest(self, P, x):
        """Closest segment e, parameter ξ ∈ [0, 1] of the closest point, signed distance of P
        from the segment's line."""
        x1, x2 = x[self.segments[:, 0]], x[self.segments[:, 1]]
        d = x2 - x1
        w = P - x1
        xi = np.clip(np.einsum("ei,ei->e", w, d) / np.einsum("ei,ei->e", d, d), 0.0, 1.0)
        dist = np.linalg.norm(w - xi[:, None] * d, axis=1)
        e = int(np.argmin(dist))
        f = (d[e, 0] * w[e, 1] - d[e, 1] * w[e, 0]) / np.linalg.norm(d[e])
        return e, xi[e], f

    def evaluate(self, q: np.ndarray):
        """Gap (1,), global dofs (1, 6): disk (x, y) then the two segment nodes' (u_x, u_y),
        gradient (1, 6), Hessian (1, 6, 6)."""
        disk, beam = self.bodies
        P = disk.center(self._local(q, 0))
        x = beam.positions(self._local(q, 1))
        e, xi, _ = self._closest(P, x)
        a, b = self.segments[e]
        r = disk.shape.radius + self.clearance
        if 0.0 < xi < 1.0:
            f, G, H = point_line_distance(P, x[a], x[b])
            g, G, H = self.side * f - r, self.side * G, self.side * H
        else:
            k = 0 if xi == 0.0 else 1
            u, dist = _unit(P - x[(a, b)[k]], "the disk centre and a beam node")
            g = dist - r
            G = np.zeros(6)
            H = np.zeros((6, 6))
            K = _distance_curvature(u, dist)
            j = slice(2 + 2 * k, 4 + 2 * k)
            G[:2], G[j] = u, -u
            H[:2, :2] = H[j, j] = K
            H[:2, j] = H[j, :2] = -K
        beam_dofs = self.offsets[1] + beam.node_translation_dofs([a, b]).ravel()
        dofs = np.concatenate([self.offsets[0] + np.arange(2), beam_dofs])
        return np.array([g]), dofs[None, :], G[None, :], H[None, :, :]


def rigid_pair(body, other, nodes=None, restitution: float = 0.0, clearance: float = 0.0):
    """The contact pair of a rigid disk with ``other`` (an obstacle or a body), or None when
    neither is a rigid disk (then the pair is a node or segment contact).

    ``clearance`` (m) is only for a disk against a beam; ``nodes`` must be None here, the
    contact point of a disk being found from the geometry.
    """
    if not (_is_disk(body) or _is_disk(other)):
        if _is_polygon(body) and _is_polygon(other):
            raise InputError("polygon against polygon contact is not supported")
        if isinstance(other, RigidBody2D):
            raise InputError(
                f"no contact between {type(body).__name__} and a rigid body with a "
                f"{type(other.shape).__name__} shape"
            )
        return None
    if nodes is not None:
        raise InputError("nodes: a disk's contact point follows from the geometry; pass None")
    disk, rest = (body, other) if _is_disk(body) else (other, body)
    if clearance and not isinstance(rest, Beam2D):
        raise InputError("clearance applies to a disk against a beam only")
    if isinstance(rest, (Plane, Circle)):
        return DiskObstacleContact(disk, rest, restitution)
    if _is_disk(rest):
        return DiskDiskContact(body, other, restitution)
    if _is_polygon(rest):
        pair = DiskPolygonContact(disk, rest, restitution)
    elif isinstance(rest, Beam2D):
        pair = DiskBeamContact(disk, rest, restitution, clearance)
    else:
        raise InputError(f"no contact between a rigid disk and a {type(rest).__name__}")
    pair.body = body
    return pair
