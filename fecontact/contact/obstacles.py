r"""Rigid obstacles: signed gap functions of a point and their derivatives.

Each obstacle gives, for points x (shape (m, d)), the signed gap g(x) in m (positive when
separated, zero in contact, negative when penetrating), its gradient ∂g/∂x (m, d) and its
Hessian ∂²g/∂x² (m, d, d), or None where it vanishes. ``Plane`` and ``Circle`` work in the plane
(d = 2) and in space (d = 3: a plane and a sphere), the dimension taken from the given point or
centre; ``Sphere`` is the three-dimensional ``Circle``. ``Point`` is the exception: a rigid
point (or small disk) acts against beam segments, so its gap is computed in
:mod:`fecontact.contact` from the segment geometry.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, check_finite, check_kind, check_positive, check_vector

__all__ = ["Plane", "Circle", "Sphere", "Point"]


class _Motion:
    """A prescribed rigid translation d(t) (m) of an obstacle; ``time`` (s) is set by the
    integrator before the gaps are evaluated. The velocity ḋ (m/s) is the given function or
    a central difference of d."""

    motion = None
    velocity = None
    time = 0.0
    extent = None  # size (m) drawn in the output; None: from the scene

    def _set_motion(self, motion, velocity):
        if motion is not None and not callable(motion):
            raise InputError("motion must be a function of time t (s) returning a displacement")
        if velocity is not None and not callable(velocity):
            raise InputError("velocity must be a function of time t (s)")
        if velocity is not None and motion is None:  # a velocity alone would be ignored
            raise InputError("velocity is the rate of motion: give motion(t) too")
        self.motion, self.velocity = motion, velocity

    @property
    def moving(self) -> bool:
        return self.motion is not None

    def shift(self) -> np.ndarray | float:
        """Displacement d(t) of the obstacle at its current time (0 when fixed)."""
        if self.motion is None:
            return 0.0
        return check_finite("motion", self.motion(self.time)).reshape(self.dim)

    def speed(self) -> np.ndarray:
        """Velocity ḋ(t) at the current time, m/s."""
        if self.motion is None:
            return np.zeros(self.dim)
        if self.velocity is not None:
            return check_finite("velocity", self.velocity(self.time)).reshape(self.dim)
        dt = 1e-6 * max(1.0, abs(self.time))
        d = np.asarray(self.motion(self.time + dt)) - np.asarray(self.motion(self.time - dt))
        return d.reshape(self.dim) / (2.0 * dt)


class Plane(_Motion):
    """Half-plane (2D) or half-space (3D) bounded by the line or plane through ``point`` with
    outward unit ``normal`` (2 or 3 components, as ``point``).

    g(x) = n·(x − p): material is allowed on the side the normal points to. ``extent`` (m) is
    only the size drawn in the output (default: twice the model size). ``motion(t)`` (m) moves
    the plane along a prescribed path (``velocity(t)`` in m/s, optional).
    """

    linear = True

    def __init__(self, point, normal, extent: float | None = None, motion=None, velocity=None):
        self.extent = None if extent is None else check_positive("extent", extent)
        self._set_motion(motion, velocity)
        self.point = _vector("point", point)
        self.dim = len(self.point)
        n = check_finite("normal", normal).ravel()
        if n.shape != self.point.shape:
            raise InputError(f"normal must have {self.dim} components like point, got {n.shape[0]}")
        norm = np.linalg.norm(n)
        if norm == 0.0:
            raise InputError("normal must be a non-zero vector")
        self.normal = n / norm

    def gap(self, x: np.ndarray):
        """Gap (m,), gradient (m, d) and Hessian (None: zero) at points ``x`` (m, d)."""
        G = np.repeat(self.normal[None], len(x), axis=0)
        return self.gap_values(x), G, None

    def gap_values(self, x: np.ndarray) -> np.ndarray:
        """The gap (m,) alone at points ``x`` (m, d)."""
        _check_points(x, self.dim)
        p = self.point if self.motion is None else self.point + self.shift()
        return (x - p) @ self.normal

    @property
    def anchor(self) -> np.ndarray:
        return self.point

    def outline(self, size: float, around=None) -> np.ndarray:
        """A piece of the boundary of side ``size`` (m) for output: the end points (2, 2) of a
        segment in 2D, a closed square loop (5, 3) in 3D; centred at the plane's point, or at
        the foot of ``around`` (a point, m) on the plane."""
        base = self.point + self.shift()
        if around is not None:
            d = np.asarray(around, dtype=float)[: self.dim] - base
            base = base + d - (d @ self.normal) * self.normal
        if self.dim == 2:
            t = np.array([-self.normal[1], self.normal[0]])
            return base + 0.5 * size * np.array([-t, t])
        t1, t2 = _tangents(self.normal)
        corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]]) * (0.5 * size)
        return base + corners[:, :1] * t1 + corners[:, 1:] * t2


class Circle(_Motion):
    """Rigid disk (2D) or ball (3D) of ``radius`` (m) centred at ``center`` (2 or 3
    components); ``inside=True`` makes it a cavity.

    Outside: g = |x − c| − R. Inside (points kept within the circle): g = R − |x − c|. With
    e = (x − c)/|x − c|: ∂g/∂x = ±e and ∂²g/∂x² = ±(I − e⊗e)/|x − c| (at a cavity's
    centre, R from its wall, e is the first axis and the curvature 0). ``motion(t)`` (m)
    translates the centre along a prescribed path (``velocity(t)`` in m/s, optional).
    """

    linear = False

    def __init__(self, center, radius: float, inside: bool = False, motion=None, velocity=None):
        self._set_motion(motion, velocity)
        self.center = _vector("center", center)
        self.dim = len(self.center)
        self.radius = check_positive("radius", radius)
        # a string such as "no" would read as a cavity
        self.inside = bool(check_kind("inside", inside, (bool, np.bool_), "True or False"))
        self.sign = -1.0 if inside else 1.0

    def gap(self, x: np.ndarray):
        """Gap (m,), gradient (m, d) and Hessian (m, d, d) at points ``x`` (m, d)."""
        _check_points(x, self.dim)
        d = x - self.center - self.shift()
        r = np.linalg.norm(d, axis=1)
        centre = r == 0.0
        if np.any(centre) and not self.inside:
            raise InputError("a contact point lies exactly at the circle centre: normal undefined")
        # a cavity's centre is R from the wall (g = R > 0, no row there can be active): any
        # direction holds for its normal, the first axis, and its curvature term is dropped
        e = np.where(centre[:, None], np.eye(self.dim)[0], d / np.where(centre, 1.0, r)[:, None])
        g = self.sign * (r - self.radius)
        G = self.sign * e
        H = self.sign * (np.eye(self.dim) - e[:, :, None] * e[:, None, :])
        H = H / np.where(centre, np.inf, r)[:, None, None]
        return g, G, H

    def gap_values(self, x: np.ndarray) -> np.ndarray:
        """The gap (m,) alone at points ``x`` (m, d)."""
        _check_points(x, self.dim)
        r = np.linalg.norm(x - self.center - self.shift(), axis=1)
        return self.sign * (r - self.radius)

    @property
    def anchor(self) -> np.ndarray:
        return self.center

    def outline(self, size: float = 0.0, around=None, n: int = 96) -> np.ndarray:
        """Points on the rim for output (``size`` is not needed), joined in order: the circle
        (n + 1, 2) in 2D; in 3D the great circles in the xy, xz and yz planes, linked by a
        quarter of the first."""
        s = np.linspace(0.0, 2.0 * np.pi, n + 1)
        c, z = np.cos(s), np.zeros_like(s)
        center = self.center + self.shift()
        if self.dim == 2:
            return center + self.radius * np.stack([c, np.sin(s)], axis=1)
        quarter = np.linspace(0.0, 0.5 * np.pi, max(n // 4, 1) + 1)
        loops = [
            np.stack([c, np.sin(s), z], axis=1),
            np.stack([c, z, np.sin(s)], axis=1),
            np.stack([np.cos(quarter), np.sin(quarter), 0.0 * quarter], axis=1),
            np.stack([z, c, np.sin(s)], axis=1),
        ]
        return center + self.radius * np.vstack(loops)


class Sphere(Circle):
    """Rigid ball of ``radius`` (m) centred at ``center`` (3 components); ``inside=True`` makes
    it a spherical cavity. The three-dimensional :class:`Circle`."""

    def __init__(self, center, radius: float, inside: bool = False):
        c = check_finite("center", center).ravel()
        if c.shape != (3,):
            raise InputError(f"center of a Sphere must have 3 components, got {c.shape[0]}")
        super().__init__(c, radius, inside)


class Point:
    """Rigid point at ``position`` (m), or a small rigid disk of ``radius`` (m), hit by beams."""

    linear = False
    moving = False
    extent = None

    def __init__(self, position, radius: float = 0.0):
        self.position = check_vector("position", position, 2)
        self.radius = check_positive("radius", radius, allow_zero=True)

    @property
    def anchor(self) -> np.ndarray:
        return self.position

    def outline(self, size: float = 0.0, around=None, n: int = 48) -> np.ndarray:
        """Points on the rim for output (``size`` is not needed), joined in order."""
        s = np.linspace(0.0, 2.0 * np.pi, n + 1)
        return self.position + max(self.radius, 1e-9) * np.stack([np.cos(s), np.sin(s)], axis=1)


def _vector(name: str, value) -> np.ndarray:
    x = check_finite(name, value).ravel()
    if x.shape not in ((2,), (3,)):
        raise InputError(f"{name} must have 2 or 3 components, got {x.shape[0]}")
    return x


def _check_points(x: np.ndarray, dim: int) -> None:
    if x.ndim != 2 or x.shape[1] != dim:
        raise InputError(
            f"points must be an (m, {dim}) array for this {dim}D obstacle, got shape {x.shape}"
        )


def _tangents(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing the unit normal n to a right-handed basis (t1, t2, n)."""
    a = np.eye(3)[int(np.argmin(np.abs(n)))]
    t1 = np.cross(n, a)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)
