r"""Shapes of rigid bodies in space, in the body frame about the centre of mass.

Each shape gives its volume (m³), the inertia tensor J (kg·m², body frame, about the centre of
mass, principal axes along the body axes) of a uniform body of a given mass, its size (m), the
points that touch planes (``vertices``: a box's corners, a cylinder's rims), the spheres that
touch (``balls``: centres and radius of a ball, of a capsule's two caps) and a triangulated
surface for output. The long axis of a cylinder and a capsule is the body z axis.

==============  ===================================================  ========================
shape           J / m (diagonal)                                     contact
==============  ===================================================  ========================
``Ball``        2r²/5 (each)                                         a ball at the centre
``Box``         (b² + c²)/12, (a² + c²)/12, (a² + b²)/12             its 8 corners
``Cylinder``    (3r² + L²)/12, (3r² + L²)/12, r²/2                   points on its two rims
``Capsule``     cylinder + two hemispheres (exact, parallel axes)    balls at its two ends
``ConvexMesh``  the hull's tetrahedra from its centroid (exact)      its hull's vertices
==============  ===================================================  ========================

A ``ConvexMesh`` is the convex hull of given points (scipy's Qhull), moved so that its centre
of mass is the body origin; its inertia tensor is full (the hull's principal axes need not be
the body axes).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError, check_count, check_finite, check_positive

__all__ = ["Ball", "Box", "Capsule", "ConvexMesh", "Cylinder"]


def _ring(radius: float, z: float, n: int) -> np.ndarray:
    s = 2.0 * np.pi * np.arange(n) / n
    return np.column_stack([radius * np.cos(s), radius * np.sin(s), np.full(n, z)])


def _count(n) -> int:
    # at least 8 points draw a rim that reads as round (they are for output only)
    return check_count("n_rim", n, 8)


def _tube(rings: list[np.ndarray], caps=True):
    """Points and triangles of a surface made of rings of equal size (closed by two fans)."""
    n = len(rings[0])
    P = np.vstack(rings)
    tris = []
    for k in range(len(rings) - 1):
        a = k * n + np.arange(n)
        b = k * n + (np.arange(n) + 1) % n
        tris += [np.column_stack([a, b, b + n]), np.column_stack([a, b + n, a + n])]
    if caps:
        lo, hi = len(P), len(P) + 1
        P = np.vstack([P, rings[0].mean(0), rings[-1].mean(0)])
        a, b = np.arange(n), (np.arange(n) + 1) % n
        top = (len(rings) - 1) * n
        tris += [np.column_stack([np.full(n, lo), b, a])]
        tris += [np.column_stack([np.full(n, hi), top + a, top + b])]
    return P, np.vstack(tris)


class Ball:
    """A ball of ``radius`` (m)."""

    def __init__(self, radius: float, n_rim: int = 24):
        self.radius = check_positive("radius", radius)
        self._n = _count(n_rim)
        self.vertices = np.zeros((0, 3))
        self.balls = (np.zeros((1, 3)), self.radius)

    @property
    def volume(self) -> float:
        return 4.0 / 3.0 * math.pi * self.radius**3

    @property
    def size(self) -> float:
        return 2.0 * self.radius

    def inertia(self, mass: float) -> np.ndarray:
        return np.eye(3) * 0.4 * mass * self.radius**2

    def surface(self):
        n, r = self._n, self.radius
        polar = np.pi * np.arange(1, n // 2) / (n // 2)
        rings = [_ring(r * math.sin(a), r * math.cos(a), n) for a in polar]
        P, T = _tube(rings, caps=False)
        poles = len(P) + np.arange(2)
        P = np.vstack([P, [[0.0, 0.0, r], [0.0, 0.0, -r]]])
        a, b = np.arange(n), (np.arange(n) + 1) % n
        last = (len(rings) - 1) * n
        caps = [np.column_stack([np.full(n, poles[0]), a, b])]
        caps += [np.column_stack([np.full(n, poles[1]), last + b, last + a])]
        return P, np.vstack([T, *caps])


class Box:
    """A box of side lengths ``a``, ``b``, ``c`` (m) along the body x, y, z axes; its corners
    are its contact points."""

    def __init__(self, a: float, b: float, c: float):
        self.sides = np.array([check_positive(n, v) for n, v in zip("abc", (a, b, c), strict=True)])
        half = 0.5 * self.sides
        signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float)
        self.vertices = signs * half
        self.balls = (np.zeros((0, 3)), 0.0)

    @property
    def volume(self) -> float:
        return float(np.prod(self.sides))

    @property
    def size(self) -> float:
        return float(np.linalg.norm(self.sides))

    def inertia(self, mass: float) -> np.ndarray:
        s2 = self.sides**2
        return np.diag([s2[1] + s2[2], s2[0] + s2[2], s2[0] + s2[1]]) * mass / 12.0

    def surface(self):
        # corners numbered 4i + 2j + k; each face as two triangles, outward
        faces = [
            (0, 1, 3, 2),
            (4, 6, 7, 5),
            (0, 4, 5, 1),
            (2, 3, 7, 6),
            (0, 2, 6, 4),
            (1, 5, 7, 3),
        ]
        tris = [t for f in faces for t in ((f[0], f[1], f[2]), (f[0], f[2], f[3]))]
        return self.vertices.copy(), np.array(tris)


class Cylinder:
    """A cylinder of ``radius`` and ``length`` (m) along the body z axis; ``n_rim`` points on
    each rim are its contact points."""

    def __init__(self, radius: float, length: float, n_rim: int = 24):
        self.radius = check_positive("radius", radius)
        self.length = check_positive("length", length)
        n = _count(n_rim)
        h = 0.5 * self.length
        self.vertices = np.vstack([_ring(self.radius, -h, n), _ring(self.radius, h, n)])
        self.balls = (np.zeros((0, 3)), 0.0)

    @property
    def volume(self) -> float:
        return math.pi * self.radius**2 * self.length

    @property
    def size(self) -> float:
        return math.hypot(2.0 * self.radius, self.length)

    def inertia(self, mass: float) -> np.ndarray:
        r2, L2 = self.radius**2, self.length**2
        return np.diag([(3 * r2 + L2) / 12, (3 * r2 + L2) / 12, r2 / 2]) * mass

    def surface(self):
        n = len(self.vertices) // 2
        return _tube([self.vertices[:n], self.vertices[n:]])


class Capsule:
    """A cylinder of ``radius`` and ``length`` (m, between the caps' centres) along the body
    z axis, closed by two hemispheres; it touches through the balls of its two caps."""

    def __init__(self, radius: float, length: float, n_rim: int = 24):
        self.radius = check_positive("radius", radius)
        self.length = check_positive("length", length)
        self._n = _count(n_rim)
        self.vertices = np.zeros((0, 3))
        self.balls = (
            np.array([[0.0, 0.0, -0.5 * self.length], [0.0, 0.0, 0.5 * self.length]]),
            self.radius,
        )

    @property
    def volume(self) -> float:
        r, L = self.radius, self.length
        return math.pi * r**2 * L + 4.0 / 3.0 * math.pi * r**3

    @property
    def size(self) -> float:
        return self.length + 2.0 * self.radius

    def inertia(self, mass: float) -> np.ndarray:
        """Cylinder plus two hemispheres, each about its own centroid (3r/8 from the flat
        face) moved to the centre by the parallel axes."""
        r, L = self.radius, self.length
        mc = mass * L / (L + 4.0 * r / 3.0)  # the masses share the volume
        mh = 0.5 * (mass - mc)
        axial = 0.5 * mc * r**2 + 2.0 * 0.4 * mh * r**2
        d = 0.5 * L + 3.0 * r / 8.0  # hemisphere centroid from the centre
        hemi = (0.4 - (3.0 / 8.0) ** 2) * mh * r**2  # about its centroid, transverse
        trans = mc * (3 * r**2 + L**2) / 12.0 + 2.0 * (hemi + mh * d**2)
        return np.diag([trans, trans, axial])

    def surface(self):
        n, r, h = self._n, self.radius, 0.5 * self.length
        m = max(n // 4, 2)
        polar = 0.5 * np.pi * np.arange(1, m + 1) / m
        bottom = [_ring(r * math.sin(a), -h - r * math.cos(a), n) for a in polar]
        top = [_ring(r * math.sin(a), h + r * math.cos(a), n) for a in polar[::-1]]
        return _tube(bottom + top)


def _solid_moments(P: np.ndarray, tris: np.ndarray):
    """Volume V, centroid c and second moment ∫ x xᵀ dV of the solid bounded by the outward
    triangles ``tris`` of ``P``: the sum over the tetrahedra (o, a, b, c) from the origin o,
    each contributing V_t/20 (Σ x_i x_iᵀ + s sᵀ), s the sum of its four vertices (exact)."""
    a, b, c = P[tris[:, 0]], P[tris[:, 1]], P[tris[:, 2]]
    vol = np.einsum("ti,ti->t", a, np.cross(b, c)) / 6.0
    s = a + b + c
    second = np.einsum("ti,tj->tij", a, a) + np.einsum("ti,tj->tij", b, b)
    second += np.einsum("ti,tj->tij", c, c) + np.einsum("ti,tj->tij", s, s)
    V = vol.sum()
    return V, (vol[:, None] * s).sum(0) / (4.0 * V), np.einsum("t,tij->ij", vol, second) / 20.0


class ConvexMesh:
    """The convex hull of ``points`` (n, 3) in m; the body origin is the hull's centre of
    mass, ``offset`` (m) where that centre lies in the coordinates of ``points``."""

    def __init__(self, points):
        from scipy.spatial import ConvexHull, QhullError

        P = check_finite("points", points)
        if P.ndim != 2 or P.shape[1] != 3 or len(P) < 4:
            raise InputError(f"points must be a finite (n, 3) array with n >= 4, got {P.shape}")
        try:
            hull = ConvexHull(P)
        except QhullError as err:
            raise InputError("points span no volume (coplanar or repeated)") from err
        keep = hull.vertices
        index = np.full(len(P), -1)
        index[keep] = np.arange(len(keep))
        tris = index[hull.simplices]
        V = P[keep]
        # orient each triangle outward (Qhull's order is arbitrary)
        a, b, c = V[tris[:, 0]], V[tris[:, 1]], V[tris[:, 2]]
        flip = np.einsum("ti,ti->t", np.cross(b - a, c - a), hull.equations[:, :3]) < 0.0
        tris[flip] = tris[flip][:, ::-1]
        vol, self.offset, _ = _solid_moments(V - V.mean(0), tris)
        self.offset = self.offset + V.mean(0)
        self.vertices = V - self.offset
        self._tris = tris
        self._volume, _, self._second = _solid_moments(self.vertices, tris)
        self.balls = (np.zeros((0, 3)), 0.0)

    @property
    def volume(self) -> float:
        return float(self._volume)

    @property
    def size(self) -> float:
        return float(np.linalg.norm(np.ptp(self.vertices, axis=0)))

    def inertia(self, mass: float) -> np.ndarray:
        """J = ρ (tr(S) I − S), S = ∫ x xᵀ dV about the centre of mass, ρ = mass / volume."""
        S = self._second * (mass / self._volume)
        return np.trace(S) * np.eye(3) - S

    def surface(self):
        return self.vertices.copy(), self._tris.copy()
