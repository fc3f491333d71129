r"""Rigid bodies in space.

A ``RigidBody3D`` has six dofs q = (u, ψ): the displacement u (m) of its centre of mass from
the initial ``position`` and its total rotation vector ψ (rad), R = exp(ψ̃) (:mod:`fecontact.
rotations`; R = I is the pose in which the shape and the inertia tensor are given). Its
velocities are (u̇, Ω): the centre's velocity in the inertial frame and the body-frame angular
velocity, Ṙ = R Ω̃, so that the mass matrix diag(m I, J) is constant and the kinetic energy is
½ m |u̇|² + ½ Ωᵀ J Ω. The equations of motion add the gyroscopic force Ω × JΩ (``inertial``).

A point r of the body frame sits at x = c₀ + u + R r; its variation under a body-frame rotation
δΘ (R ⊕ δΘ = R exp(δΘ̃)) is δx = δu − R r̃ δΘ, so ∂x/∂(u, Θ) = [I | −R r̃]. The curvature that
Newton needs is the derivative of the force Gᵀλ along the group: for the spatial component i,
∂²x_i/∂Θ∂Θ = r̃ (Rᵀe_i)~ (not symmetric: the body-frame derivatives do not commute).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import InputError, check_finite, check_positive
from ..rotations import cross, exp, hat
from .base import RigidDefaults
from .shapes3d import Ball, Box, Capsule, ConvexMesh, Cylinder

__all__ = ["RigidBody3D"]

_SHAPES = (Ball, Box, Capsule, Cylinder, ConvexMesh)
_DOFS6 = np.arange(6)[None]
_EYE3 = np.eye(3)
_EPS = np.zeros((3, 3, 3))  # ε_ijk: ã_ik = ε_ijk a_j
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _EPS[_i, _j, _k], _EPS[_i, _k, _j] = 1.0, -1.0


def _vector3(name: str, value) -> np.ndarray:
    x = check_finite(name, value).ravel()
    if x.shape != (3,):
        raise InputError(f"{name} must be a 3-vector, got shape {x.shape}")
    return x


def _inertia_tensor(inertia) -> np.ndarray:
    """A symmetric positive definite 3 × 3 inertia tensor (kg·m²), from 3 principal moments
    or a full matrix."""
    J = check_finite("inertia", inertia)
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3) or not np.allclose(J, J.T, rtol=1e-12, atol=0.0):
        raise InputError("inertia must be 3 principal moments or a symmetric 3 x 3 tensor")
    w = np.linalg.eigvalsh(J)
    if w[0] <= 0.0 or w[0] + w[1] < w[2] * (1.0 - 1e-12):
        raise InputError(
            "inertia must be positive definite with the triangle inequality J1 + J2 >= J3 "
            f"of the principal moments, got {w}"
        )
    return 0.5 * (J + J.T)


class RigidBody3D(RigidDefaults):
    """Rigid body in space: ``mass`` (kg), ``inertia`` J about the centre of mass in the body
    frame (kg·m²: three principal moments along the body axes or a full tensor), initial
    ``position`` of the centre of mass (m) and a ``shape`` (``Ball``, ``Box``, ``Cylinder``,
    ``Capsule``; body frame, about the centre of mass). ``uniform`` takes J from the shape.

    Dofs (u_x, u_y, u_z, ψ_x, ψ_y, ψ_z) (module docstring); velocities (u̇, Ω) with Ω in the
    body frame. ``fix()`` holds the body (ground); ``fix("x", "y", "z")`` its centre, and the
    rotation is held whole or not at all (``fix("rx", "ry", "rz")``).
    """

    round_contact = "its balls"  # how a shape without vertices touches

    dim = 3
    dofs_per_node = 6
    ndof = 6
    n_nodes = 0  # replaced per body: its output points
    linear_kinematics = False
    rigid_frame = True
    linear = True  # no internal force (the gyroscopic force is the model's ``inertial`` term)
    element_dofs = np.zeros((0, 6), dtype=int)
    components = ("x", "y", "z", "rx", "ry", "rz")
    rotation_triples = np.array([[3, 4, 5]])

    def __init__(self, mass: float, inertia, position, shape):
        self.mass = check_positive("mass", mass)
        self.J = _inertia_tensor(inertia)
        self.position = _vector3("position", position)
        if not isinstance(shape, _SHAPES):
            names = ", ".join(s.__name__ for s in _SHAPES)
            raise InputError(f"shape must be one of {names}, got {type(shape).__name__}")
        self.shape = shape
        self.fixed: set[int] = set()
        P, self._triangles = shape.surface()
        # output points: the surface (its first points are the shape's vertices), the centre
        self._points = np.vstack([P, np.zeros((1, 3))])
        self.n_nodes = len(self._points)
        self.center_index = len(P)
        nv = len(shape.vertices)
        if nv and not np.allclose(P[:nv], shape.vertices):
            raise AssertionError("a shape's surface starts with its vertices")

    @classmethod
    def uniform(cls, mass: float, position, shape) -> RigidBody3D:
        """A body of uniform density: the inertia tensor of the shape (:mod:`.shapes3d`)."""
        if not isinstance(shape, _SHAPES):
            names = ", ".join(s.__name__ for s in _SHAPES)
            raise InputError(f"shape must be one of {names}, got {type(shape).__name__}")
        return cls(mass, shape.inertia(check_positive("mass", mass)), position, shape)

    @classmethod
    def of_density(cls, density: float, position, shape) -> RigidBody3D:
        """A uniform body of ``density`` (kg/m³)."""
        mass = check_positive("density", density) * shape.volume
        return cls.uniform(mass, position, shape)

    def fix(self, *components) -> RigidBody3D:
        """Hold ``components`` ("x", "y", "z", "rx", "ry", "rz" or 0…5; all when none) at
        their initial value."""
        self.support(0, components)
        return self

    # -- the body protocol -------------------------------------------------------------------
    def mass_matrix(self) -> sp.csr_matrix:
        """diag(m I, J) (kg, kg·m²)."""
        M = np.zeros((6, 6))
        M[:3, :3] = self.mass * np.eye(3)
        M[3:, 3:] = self.J
        return sp.csr_matrix(M)

    def inertial(self, q: np.ndarray, v: np.ndarray):
        """The gyroscopic force (0, Ω × JΩ) (N·m, body frame) and its tangent ∂/∂v, whose
        rotation block is Ω̃J − (JΩ)~."""
        W = v[3:]
        JW = self.J @ W
        (a, b, c), (x, y, z) = W.tolist(), JW.tolist()
        f = np.zeros(6)
        f[3:] = (b * z - c * y, c * x - a * z, a * y - b * x)  # Ω × JΩ
        C = np.zeros((6, 6))
        C[3:, 3:] = hat(W) @ self.J - hat(JW)
        return f, C

    def translation_field(self, vector) -> np.ndarray:
        return np.concatenate([np.asarray(vector, float), np.zeros(3)])

    def rigid_modes(self) -> np.ndarray:
        return np.eye(6)

    def rotation(self, q: np.ndarray) -> np.ndarray:
        """R = exp(ψ̃) of the body at ``q``."""
        return exp(q[3:6])

    def center(self, q: np.ndarray) -> np.ndarray:
        """Current centre of mass c₀ + u, m."""
        return self.position + q[:3]

    def to_frame(self, point) -> np.ndarray:
        """Body-frame coordinates (m) of ``point`` given in the pose q = 0."""
        return _vector3("point", point) - self.position

    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current output points c + R r (n, 3), m."""
        return self.center(q) + self._points @ self.rotation(q).T

    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """The rigid field of the dof vector ``x`` = (a, ω) at the output points: a + R(ω × r)
        (for a velocity, the points' velocities in m/s)."""
        R = self.rotation(np.zeros(6) if q is None else q)
        return x[:3] + cross(x[3:6], self._points) @ R.T

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Positions (m, 3), local dofs (m, 6), ∂x/∂(u, Θ) (m, 3, 6) and the curvature
        (m, 3, 6, 6) of the output points ``nodes`` (module docstring)."""
        return self.frame_point_kinematics(q, self._points[nodes])

    def point_positions(self, q: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        return self.center(q) + self._points[nodes] @ self.rotation(q).T

    def point_positions_frame(self, q: np.ndarray, r: np.ndarray) -> np.ndarray:
        """Positions c + R r (m, 3) of body-frame points ``r`` (m, 3) alone."""
        return self.center(q) + r @ self.rotation(q).T

    def frame_point_kinematics(self, q: np.ndarray, r, r_hat=None):
        """As ``point_kinematics`` for body-frame points ``r`` (m, 3) (m, from the centre);
        ``r_hat``: their skew matrices r̃ (m, 3, 3) when the caller keeps them (fixed points
        evaluated at every iteration: a joint's pivot)."""
        r = np.atleast_2d(r)
        r_hat = hat(r) if r_hat is None else r_hat
        R = self.rotation(q)
        m = len(r)
        x = self.center(q) + r @ R.T
        J = np.zeros((m, 3, 6))
        J[:, :, :3] = _EYE3
        J[:, :, 3:] = -R @ r_hat
        H = np.zeros((m, 3, 6, 6))
        # H_i = r̃ (Rᵀe_i)~, (Rᵀe_i)~_lk = ε_lpk R_ip
        H[:, :, 3:, 3:] = np.einsum("mjl,lpk,ip->mijk", r_hat, _EPS, R)
        return x, np.repeat(_DOFS6, m, axis=0), J, H

    def frame_point_function(self, r):
        """q ↦ ``frame_point_kinematics(q, r)`` of fixed body-frame points ``r`` (m, 3) (m,
        from the centre): what does not depend on q is made once (a joint's pivot, evaluated
        at every Newton iteration). The curvature H_i = r̃ (Rᵀe_i)~ = Σ_p R_ip B_p, with the
        constant B_p = r̃ ε_{·p·} (ã_lk = ε_lpk a_p), is one product of R with a table."""
        r = np.atleast_2d(np.asarray(r, dtype=float))
        m = len(r)
        r_hat = hat(r)
        table = np.einsum("mjl,lpk->mpjk", r_hat, _EPS).reshape(m, 3, 9)
        dofs = np.repeat(_DOFS6, m, axis=0)
        dofs.flags.writeable = False
        position, minus_r_hat = self.position, -r_hat
        J0, H0 = np.zeros((m, 3, 6)), np.zeros((m, 3, 6, 6))
        J0[:, :, :3] = _EYE3

        def kinematics(q: np.ndarray):
            R = exp(q[3:6])
            x = (position + q[:3]) + r @ R.T
            J, H = J0.copy(), H0.copy()
            J[:, :, 3:] = R @ minus_r_hat
            H[:, :, 3:, 3:] = (R @ table).reshape(m, 3, 3, 3)
            return x, dofs, J, H

        return kinematics

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """Displacement and velocity of the output points (m, m/s), the body's rotation
        vector ψ (rad) and body-frame angular velocity Ω (rad/s) at every point."""
        n = self.n_nodes
        return {
            "displacement": self.positions(q) - self.positions(np.zeros(6)),
            "velocity": self.nodal(v, q),
            "rotation": np.repeat(q[None, 3:6], n, axis=0),
            "angular_velocity": np.repeat(v[None, 3:6], n, axis=0),
        }

    def cells(self) -> list[tuple[str, np.ndarray]]:
        """The shape's surface as ``triangle`` cells."""
        return [("triangle", self._triangles)]
