r"""Planar rigid bodies and point masses.

A ``RigidBody2D`` has three dofs q = (u_x, u_y, θ): the displacement (m) of its centre of mass
from the initial ``position`` and its rotation (rad, counter-clockwise) from the initial
``angle``. With c = c₀ + u, φ = φ₀ + θ and R(φ) the rotation by φ, a point r of the body frame
(measured from the centre of mass) sits at

    x = c + R(φ) r,   ∂x/∂(u, θ) = [I | R′(φ) r] = [I | J R(φ) r],   ∂²x/∂θ² = −R(φ) r,

J = [[0, −1], [1, 0]] being the rotation by +90°; every other second derivative vanishes.
The mass matrix diag(m, m, I_G) about the centre of mass is constant in planar motion and there
is no internal energy, so the body has no elements.

Contact geometry comes from a ``shape``: a ``Disk`` (contact through its centre and radius,
see :mod:`fecontact.contact.rigid_pairs`) or a convex ``Polygon`` whose vertices are the contact
points. Output points are the vertices, then the centre of mass, then (for a disk) points on
its rim; they are drawn as the closed outline (plus a radius of the disk, so that its rotation
shows).

A ``PointMass`` is a body of its own with two translation dofs and one output point.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..errors import (
    MIN_MAGNITUDE,
    InputError,
    check_count,
    check_finite,
    check_positive,
    check_vector,
)
from .base import BodyDefaults, RigidDefaults

__all__ = ["Disk", "Polygon", "RigidBody2D", "PointMass"]

_PERP = np.array([[0.0, -1.0], [1.0, 0.0]])  # rotation by +90°: J a = (−a_y, a_x)


_DOFS2, _DOFS3, _EYE2 = np.arange(2)[None], np.arange(3)[None], np.eye(2)[None]


def rotation(phi) -> np.ndarray:
    """Rotation matrix R(φ) for an angle in rad (counter-clockwise)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z component of the cross products of rows of a and b."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _point(name: str, value) -> np.ndarray:
    x = check_finite(name, value)
    if x.shape != (2,):
        raise InputError(f"{name} must be a 2-vector (x, y) in m, got shape {x.shape}")
    return x


class Disk:
    """Circular shape of ``radius`` (m) centred on the centre of mass.

    ``n_outline`` points on the rim are written for output; they take no part in contact.
    """

    vertices = np.zeros((0, 2))

    def __init__(self, radius: float, n_outline: int = 48):
        self.radius = check_positive("radius", radius)
        n_outline = check_count("n_outline", n_outline, 8)
        s = np.linspace(0.0, 2.0 * np.pi, n_outline, endpoint=False)
        self._rim = self.radius * np.column_stack([np.cos(s), np.sin(s)])

    @property
    def size(self) -> float:
        """Diameter, m."""
        return 2.0 * self.radius

    def moment(self, mass: float) -> float:
        """Moment of inertia (kg·m²) of a uniform disk of ``mass`` (kg) about its centre."""
        return 0.5 * check_positive("mass", mass) * self.radius**2

    def output_points(self) -> np.ndarray:
        """Body-frame output points: the centre, then the rim."""
        return np.vstack([[0.0, 0.0], self._rim])

    def cells(self) -> np.ndarray:
        """Line cells: the rim as a closed loop and the radius to its first point."""
        n = len(self._rim)
        rim = 1 + np.arange(n)
        loop = np.column_stack([rim, np.roll(rim, -1)])
        return np.vstack([loop, [[0, 1]]])


class Polygon:
    """Convex polygon with ``vertices`` (n ≥ 3, 2) in m in the body frame, counter-clockwise,
    measured from the centre of mass. The vertices are the contact points of the shape."""

    def __init__(self, vertices):
        V = check_finite("vertices", vertices)
        if V.ndim != 2 or V.shape[1] != 2 or V.shape[0] < 3:
            raise InputError(f"vertices must be an (n >= 3, 2) array, got shape {V.shape}")
        edges = np.roll(V, -1, axis=0) - V
        lengths = np.linalg.norm(edges, axis=1)
        scale = np.max(np.linalg.norm(V - V.mean(axis=0), axis=1))
        if scale == 0.0 or np.any(lengths <= 1e-12 * scale):
            raise InputError("vertices must be distinct (consecutive vertices coincide)")
        turn = _cross(edges, np.roll(edges, -1, axis=0))
        if np.all(turn < 0.0):
            raise InputError("vertices must be counter-clockwise (they are clockwise)")
        # the exterior angles of a simple convex polygon add up to one full turn
        angles = np.arctan2(turn, np.einsum("ij,ij->i", edges, np.roll(edges, -1, axis=0)))
        if np.any(turn <= 1e-12 * scale**2) or abs(angles.sum() - 2.0 * np.pi) > 1e-9:
            raise InputError("vertices must form a convex polygon, counter-clockwise")
        self.vertices = V
        self.normals = (edges @ _PERP) / lengths[:, None]  # outward: edge rotated by −90°
        self.radius = float(np.max(np.linalg.norm(V, axis=1)))

    @classmethod
    def box(cls, width: float, height: float) -> Polygon:
        """Rectangle ``width`` × ``height`` (m) centred on the centre of mass, edges along the
        body axes; vertices from the bottom-left corner, counter-clockwise."""
        w = 0.5 * check_positive("width", width)
        h = 0.5 * check_positive("height", height)
        return cls([[-w, -h], [w, -h], [w, h], [-w, h]])

    @classmethod
    def regular(cls, n: int, radius: float) -> Polygon:
        """Regular polygon with ``n`` ≥ 3 vertices on a circle of ``radius`` (m)."""
        if isinstance(n, bool) or int(n) != n or n < 3:
            raise InputError(f"n must be an integer >= 3, got {n!r}")
        r = check_positive("radius", radius)
        s = 2.0 * np.pi * np.arange(int(n)) / int(n)
        return cls(r * np.column_stack([np.cos(s), np.sin(s)]))

    @property
    def size(self) -> float:
        """Largest distance between two vertices, m."""
        d = self.vertices[:, None, :] - self.vertices[None, :, :]
        return float(np.max(np.linalg.norm(d, axis=-1)))

    @property
    def area(self) -> float:
        """Area, m²."""
        V, W = self.vertices, np.roll(self.vertices, -1, axis=0)
        return 0.5 * float(np.sum(_cross(V, W)))

    @property
    def centroid(self) -> np.ndarray:
        """Centroid of the area in the body frame, m (the origin for a uniform body)."""
        V, W = self.vertices, np.roll(self.vertices, -1, axis=0)
        c = _cross(V, W)
        return np.sum((V + W) * c[:, None], axis=0) / (6.0 * self.area)

    def moment(self, mass: float) -> float:
        """Moment of inertia (kg·m²) about the body-frame origin of a uniform plate of
        ``mass`` (kg) with this outline."""
        V, W = self.vertices, np.roll(self.vertices, -1, axis=0)
        c = _cross(V, W)
        Jo = np.sum(c * (np.sum(V * V, 1) + np.sum(V * W, 1) + np.sum(W * W, 1))) / 12.0
        return check_positive("mass", mass) * float(Jo) / self.area

    def output_points(self) -> np.ndarray:
        """Body-frame output points: the vertices, then the centre of mass."""
        return np.vstack([self.vertices, [[0.0, 0.0]]])

    def cells(self) -> np.ndarray:
        """Line cells: the outline as a closed loop."""
        n = len(self.vertices)
        return np.column_stack([np.arange(n), np.roll(np.arange(n), -1)])


class RigidBody2D(RigidDefaults):
    """Planar rigid body: ``mass`` (kg), ``inertia`` I_G (kg·m²) about the centre of mass,
    initial ``position`` of the centre of mass (m), initial ``angle`` (rad) and a ``shape``
    (``Disk`` or ``Polygon``, in the body frame about the centre of mass).

    Dofs (u_x, u_y, θ): displacement of the centre of mass (m) and rotation (rad,
    counter-clockwise) from the initial pose. ``fix("x", "y", "theta")`` holds some of them.
    """

    round_contact = "its centre and radius"  # how a shape without vertices touches

    dofs_per_node = 3
    ndof = 3
    linear_kinematics = False
    rigid_frame = True
    linear = True  # no stiffness: the iteration matrix is constant
    element_dofs = np.zeros((0, 3), dtype=int)
    components = ("x", "y", "theta")

    def __init__(self, mass: float, inertia: float, position, angle: float = 0.0, shape=None):
        self.mass = check_positive("mass", mass)
        self.inertia = check_positive("inertia", inertia)
        self.position = _point("position", position)
        self.angle = float(check_vector("angle", angle, 1)[0])
        if not isinstance(shape, (Disk, Polygon)):
            raise InputError(f"shape must be a Disk or a Polygon, got {type(shape).__name__}")
        self.shape = shape
        self.fixed: set[int] = set()
        self._points = shape.output_points()
        self.center_index = len(shape.vertices)
        self._frame_maps: dict = {}  # body-frame points -> their _FrameMap
        self._node_maps: dict = {}  # output point indices -> their _FrameMap
        self._outline = _FrameMap(self.position, self.angle, self._points)

    @classmethod
    def uniform(cls, mass: float, position, shape, angle: float = 0.0) -> RigidBody2D:
        """Body of uniform density: the inertia is that of the shape's area about its origin,
        which must be the centroid of the area."""
        if isinstance(shape, Polygon) and np.linalg.norm(shape.centroid) > 1e-9 * shape.size:
            raise InputError(
                f"shape: the centroid {shape.centroid} of a uniform polygon must be the origin "
                "of its vertices (the centre of mass)"
            )
        if not isinstance(shape, (Disk, Polygon)):
            raise InputError(f"shape must be a Disk or a Polygon, got {type(shape).__name__}")
        inertia = shape.moment(check_positive("mass", mass))
        if inertia < MIN_MAGNITUDE:
            raise InputError(
                f"mass {mass!r} kg is too small for this shape: its inertia {inertia:.3g} kg m^2 "
                f"is below {MIN_MAGNITUDE:g}"
            )
        return cls(mass, inertia, position, angle, shape)

    def fix(self, *components) -> RigidBody2D:
        """Hold ``components`` of the body's frame at their initial value: any of "x", "y",
        "theta" (or 0, 1, 2; all when none are given)."""
        self.support(0, components)
        return self

    # -- the body protocol -------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        """Number of output points."""
        return len(self._points)

    def mass_matrix(self) -> sp.csr_matrix:
        """diag(m, m, I_G) in kg, kg, kg·m²."""
        return sp.diags([self.mass, self.mass, self.inertia]).tocsr()

    def translation_field(self, vector) -> np.ndarray:
        """(v_x, v_y, 0): ``vector`` on the translation of the centre of mass."""
        return np.array([vector[0], vector[1], 0.0])

    def velocity(self, vx: float, vy: float, omega: float = 0.0) -> np.ndarray:
        """Body dof vector of a velocity: centre of mass (m/s) and angular velocity (rad/s)."""
        return check_finite("velocity", [vx, vy, omega])

    def center(self, q: np.ndarray) -> np.ndarray:
        """Current centre of mass c₀ + u, m."""
        return self.position + q[:2]

    def orientation(self, q: np.ndarray) -> float:
        """Current angle φ₀ + θ of the body frame, rad."""
        return self.angle + q[2]

    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current output points c + R(φ) r, shape (n, 2), m."""
        return self._outline.positions(q)

    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """Rigid-body field of the dof vector ``x`` = (a_x, a_y, ω) at the output points:
        a + ω J R(φ) r, with the orientation of configuration ``q`` (the initial pose when
        None). For a velocity, the velocities of the points (m/s); the centre of mass gets
        (a_x, a_y) whatever ``q``."""
        q = np.zeros(3) if q is None else q
        arm = self._points @ rotation(self.orientation(q)).T
        return x[:2] + x[2] * (arm @ _PERP.T)

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Positions x = c + R(φ) r (m, 2) of output points ``nodes``, their local dofs (m, 3),
        ∂x/∂q (m, 2, 3) and the exact ∂²x/∂q² (m, 2, 3, 3) (only the θθ entry, −R r)."""
        key = nodes.tobytes()  # contacts ask for the same points at every step
        kin = self._node_maps.get(key)
        if kin is None:
            if len(self._node_maps) > 64:
                self._node_maps.clear()
            kin = self._node_maps[key] = self.frame_point_function(self._points[nodes])
        return kin(q)

    def point_positions(self, q: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """Positions x = c + R(φ) r (m, 2) of output points ``nodes`` alone: the first output
        of ``point_kinematics``, without the derivatives (gaps away from contact need no
        more)."""
        kin = self._node_maps.get(nodes.tobytes())
        if kin is None:
            return self.point_kinematics(q, nodes)[0]
        return kin.positions(q)

    def to_frame(self, point) -> np.ndarray:
        """Body-frame coordinates (m, from the centre of mass) of ``point`` given in the
        initial configuration."""
        d = check_vector("point", point, 2) - self.position
        return d @ rotation(self.angle)  # Rᵀ d

    def frame_point_kinematics(self, q: np.ndarray, r):
        """As ``point_kinematics`` for any points ``r`` (m, 2) given in the body frame (m, from
        the centre of mass): a joint's pivot, say."""
        return self.frame_point_function(r)(q)

    def frame_point_function(self, r):
        """The function q ↦ ``frame_point_kinematics(q, r)``, for points evaluated often."""
        r = np.atleast_2d(r)
        key = r.tobytes()
        kin = self._frame_maps.get(key)
        if kin is None:
            if len(self._frame_maps) > 64:
                self._frame_maps.clear()
            kin = self._frame_maps[key] = _FrameMap(self.position, self.angle, r)
        return kin

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """Output fields at the output points: displacement and velocity (2D vectors, m and
        m/s), rotation θ (rad) and angular velocity ω (rad/s) of the body."""
        n = self.n_nodes
        return {
            "displacement": self.positions(q) - self.positions(np.zeros(3)),
            "velocity": self.nodal(v, q),
            "rotation": np.full(n, q[2]),
            "angular_velocity": np.full(n, v[2]),
        }

    def cells(self) -> list[tuple[str, np.ndarray]]:
        """Cells for VTU output: the outline as ``line`` cells."""
        return [("line", self.shape.cells())]


class _FrameMap:
    """Kinematics of body-frame points r (m, 2) as one linear map of (1, u_x, u_y, cos φ, sin φ):
    x = c₀ + u + R(φ) r, ∂x/∂q = [I | J R(φ) r], ∂²x/∂θ² = −R(φ) r are all linear in these
    five numbers, so each evaluation is a single small matrix product (small systems pay per
    numpy call, not per flop)."""

    def __init__(self, position: np.ndarray, angle: float, r: np.ndarray):
        self.angle = angle
        m = len(r)
        self.shapes = ((m, 2), (m, 2, 3), (m, 2, 3, 3))
        self.dofs = np.repeat(_DOFS3, m, axis=0)
        self.dofs.flags.writeable = False
        cols = [self._outputs(position, r, *e) for e in np.eye(5)]
        self.B = np.column_stack(cols)
        # Python ints: slicing with numpy integers costs more than the product
        self.ends = tuple(int(e) for e in np.cumsum([int(np.prod(s)) for s in self.shapes]))
        self.Bx = np.ascontiguousarray(self.B[: self.ends[0]])  # the positions' rows

    @staticmethod
    def _outputs(position, r, one, ux, uy, c, s) -> np.ndarray:
        arm = np.column_stack([c * r[:, 0] - s * r[:, 1], s * r[:, 0] + c * r[:, 1]])
        m = len(r)
        x = one * position + np.array([ux, uy]) + arm
        Jx = np.zeros((m, 2, 3))
        Jx[:, 0, 0] = Jx[:, 1, 1] = one
        Jx[:, 0, 2], Jx[:, 1, 2] = -arm[:, 1], arm[:, 0]  # J R(φ) r
        Hx = np.zeros((m, 2, 3, 3))
        Hx[:, :, 2, 2] = -arm
        return np.concatenate([x.ravel(), Jx.ravel(), Hx.ravel()])

    def _basis(self, q) -> np.ndarray:
        u0, u1, theta = q.tolist()
        phi = self.angle + theta
        return np.array([1.0, u0, u1, math.cos(phi), math.sin(phi)])

    def positions(self, q) -> np.ndarray:
        """The points' positions x (m, 2) alone, m."""
        return (self.Bx @ self._basis(q)).reshape(self.shapes[0])

    def __call__(self, q):
        y = self.B @ self._basis(q)
        a, b, _ = self.ends
        (sx, sj, sh) = self.shapes
        return y[:a].reshape(sx), self.dofs, y[a:b].reshape(sj), y[b:].reshape(sh)


class PointMass(BodyDefaults):
    """A point of ``mass`` (kg) at ``position`` (m): two dofs (u_x, u_y), one output point.

    ``size`` (m) is the length scale of the scene it belongs to; it sets the gap tolerance and
    the contact detection margin of a model made of point masses only.
    """

    dofs_per_node = 2
    components = ("x", "y")
    ndof = 2
    n_nodes = 1
    linear_kinematics = True
    linear = True
    element_dofs = np.zeros((0, 2), dtype=int)

    def __init__(self, mass: float, position, size: float = 1.0):
        self.mass = check_positive("mass", mass)
        self.position = _point("position", position)
        self.characteristic_length = check_positive("size", size)
        self.fixed: set[int] = set()

    def fix(self, *components) -> PointMass:
        """Hold ``components`` ("x", "y", or 0, 1; both when none are given) at zero."""
        self.support(0, components)
        return self

    def node_index(self, node: int) -> int:
        check_count("point", node, -1, 0)  # a point mass has one point
        return 0

    def internal(self, q: np.ndarray, tangent: bool = True):
        return 0.0, np.zeros(2), (np.zeros((0, 2, 2)) if tangent else None)

    def energy(self, q: np.ndarray) -> float:
        return 0.0

    def mass_matrix(self) -> sp.csr_matrix:
        """diag(m, m) in kg."""
        return sp.diags([self.mass, self.mass]).tocsr()

    def translation_field(self, vector) -> np.ndarray:
        return np.array([vector[0], vector[1]], dtype=float)

    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current position (1, 2), m."""
        return (self.position + q[:2])[None, :]

    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        return x[None, :2]

    def contact_nodes(self, nodes=None) -> np.ndarray:
        if nodes is not None:
            for i in np.atleast_1d(nodes):
                self.node_index(i)
        return np.zeros(1, dtype=int)

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Position (m, 2), local dofs (m, 2), ∂x/∂q = I (m, 2, 2), no curvature (None)."""
        m = len(nodes)
        x = np.repeat((self.position + q[:2])[None], m, axis=0)
        return x, np.repeat(_DOFS2, m, axis=0), np.repeat(_EYE2, m, axis=0), None

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        return {"displacement": q[None, :2], "velocity": v[None, :2]}

    def cells(self) -> list[tuple[str, np.ndarray]]:
        """No cells: the point is written on its own."""
        return [("line", np.zeros((0, 2), dtype=int))]
