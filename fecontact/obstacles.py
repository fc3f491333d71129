r"""Rigid obstacles: signed gap functions of a point and their derivatives.

Each obstacle gives, for points x (shape (m, 2)), the signed gap g(x) in m (positive when
separated, zero in contact, negative when penetrating), its gradient ∂g/∂x and its Hessian
∂²g/∂x². ``Point`` is the exception: a rigid point (or small disk) acts against beam segments,
so its gap is computed in :mod:`fecontact.contact` from the segment geometry.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError, check_finite, check_positive

__all__ = ["Plane", "Circle", "Point"]


class Plane:
    """Half-plane bounded by the line through ``point`` with outward unit ``normal``.

    g(x) = n·(x − p): material is allowed on the side the normal points to. ``extent`` (m) is
    only the length drawn in the output (default: twice the model size).
    """

    linear = True

    def __init__(self, point, normal, extent: float | None = None):
        self.extent = None if extent is None else check_positive("extent", extent)
        self.point = check_finite("point", point).reshape(2)
        n = check_finite("normal", normal).reshape(2)
        norm = np.linalg.norm(n)
        if norm == 0.0:
            raise InputError("normal must be a non-zero vector")
        self.normal = n / norm

    def gap(self, x: np.ndarray):
        """Gap (m,), gradient (m, 2) and Hessian (m, 2, 2) at points ``x`` (m, 2)."""
        g = (x - self.point) @ self.normal
        G = np.broadcast_to(self.normal, x.shape)
        return g, G, None

    def outline(self, size: float) -> np.ndarray:
        """End points (2, 2) of a piece of the boundary line of length ``size`` (for output)."""
        t = np.array([-self.normal[1], self.normal[0]])
        return self.point + 0.5 * size * np.array([-t, t])


class Circle:
    """Rigid disk of ``radius`` (m) centred at ``center``; ``inside=True`` makes it a cavity.

    Outside: g = |x − c| − R. Inside (points kept within the circle): g = R − |x − c|.
    """

    linear = False

    def __init__(self, center, radius: float, inside: bool = False):
        self.center = check_finite("center", center).reshape(2)
        self.radius = check_positive("radius", radius)
        self.sign = -1.0 if inside else 1.0

    def gap(self, x: np.ndarray):
        d = x - self.center
        r = np.linalg.norm(d, axis=1)
        if np.any(r == 0.0):
            raise InputError("a contact point lies exactly at the circle centre: normal undefined")
        e = d / r[:, None]
        g = self.sign * (r - self.radius)
        G = self.sign * e
        H = self.sign * (np.eye(2) - e[:, :, None] * e[:, None, :]) / r[:, None, None]
        return g, G, H

    def outline(self, n: int = 96) -> np.ndarray:
        s = np.linspace(0.0, 2.0 * np.pi, n + 1)
        return self.center + self.radius * np.stack([np.cos(s), np.sin(s)], axis=1)


class Point:
    """Rigid point at ``position`` (m), or a small rigid disk of ``radius`` (m), hit by beams."""

    linear = False

    def __init__(self, position, radius: float = 0.0):
        self.position = check_finite("position", position).reshape(2)
        self.radius = check_positive("radius", radius, allow_zero=True)

    def outline(self, n: int = 48) -> np.ndarray:
        s = np.linspace(0.0, 2.0 * np.pi, n + 1)
        return self.position + max(self.radius, 1e-9) * np.stack([np.cos(s), np.sin(s)], axis=1)
