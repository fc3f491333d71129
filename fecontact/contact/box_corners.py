r"""Points of a rigid shape against the boundary of a 3D solid: the rows a solid–rigid pair
adds for what its own rows, one per node of the solid, cannot hold.

A box dropped corner first on an elastic slab put its corner 6.7 mm (54 % of a cell) between
the slab's nodes with every node outside the box (``benchmarks/stress_3d.py``): a feature
narrower than the cells enters between the nodes. A ball smaller than the triangles does the
same with its pole (0.25 h²/r between the nodes, through a triangle when r < h). Each such
point p = c + R r (r its body-frame position) carries one row against the solid's
discretized boundary (its triangles, numbered with the outward normal), node-to-surface with
the point as the slave:

    g = n·(p − x_a) − a − clearance,

the gap of p to the plane of its closest triangle (a, b, c), n that triangle's unit outward
normal, a the point's own radius: 0 for a box's eight corners (:class:`BoxCorners`), r for a
ball's centre (:class:`BallCentre`), whose row is then the exact gap of the sphere over a
facet's interior and conservative near a convex edge (the plane there lies outside the
surface). The gradient is exact for the plane gap: moving the triangle's nodes within its
plane leaves the plane, moving node i along n by δ moves the plane at the projection of p by
λ_i δ (λ its area coordinates), so

    ∂g/∂x_i = −λ_i n,   ∂g/∂u = n,   ∂g/∂Θ = r × (Rᵀ n)   (δp = δu − R r̃ δΘ),

(0 for a ball's centre) and the curvature is left out (Newton's rate, not its answer), as for
the other box pairs. Coulomb friction, with the coefficient of the pair that brings the rows
(``owner``), acts on the slip of the material point under the contact, p − a n (body-frame
arm r − a Rᵀn), against the triangle's point under it, T (ṗ − Σ λ_i ẋ_i), T the tangents of
n: the rows T·[I, −R ã, −λ_a I, −λ_b I, −λ_c I], applied over a step to the body's
body-frame increment (Δu, log(R_nᵀR)) and the nodes' displacements. Points whose closest
triangle lies farther than the search distance plus their radius (plus the triangles' size)
read +inf; the closest triangle is searched among those whose bounding spheres can hold it.
The rows take the pair's restitution and friction. A box's edges have rows of their own
against the solid's boundary edges (:mod:`.box_edges`), and the pair's watch measures
corners and edges inside the solid (:class:`~.rigid_distance.FeatureDepths`).
"""

from __future__ import annotations

import numpy as np

from ..rotations import cross, exp, hat, log
from .base import PairDefaults
from .friction import tangent_basis
from .inside import facet_distances, triangle_closest
from .rigid_distance import box_features

__all__ = ["BallCentre", "BoxCorners", "FeatureRows", "RigidPoints"]


class FeatureRows(PairDefaults):
    """Rows of the features (points, a box's edges) of the shape of ``rigid`` (a
    ``RigidBody3D``) against the 3D solid ``body``, for the pair ``owner`` (its restitution
    and friction),
    ``clearance`` (m) kept from the surface, ``margin`` (m) the search distance (default: the
    integrator's detection distance)."""

    linear = False
    frictional = True

    def __init__(self, owner, body, rigid, clearance=0.0, margin=None):
        self.owner = owner
        self.body, self.rigid = body, rigid
        self.bodies = (body, rigid)
        self.restitution, self.clearance = owner.restitution, clearance
        self.facets = body.contact_facets()
        self.own_margin = margin is not None
        self.margin = margin if margin is not None else 0.05 * body.characteristic_length
        self.offsets = (0, 0)

    @property
    def friction(self) -> float:
        """Coulomb's μ of the pair that brings the rows (``Contact`` sets it there)."""
        return self.owner.friction

    def detect_within(self, distance: float) -> None:
        if not self.own_margin and distance > 0.0:
            self.margin = distance


class RigidPoints(FeatureRows):
    """Points of the shape of ``rigid`` (a ``RigidBody3D``), body-frame ``points`` (k, 3) in
    m, each kept its ``radii`` (k,) (m) plus ``clearance`` from the planes of the boundary
    triangles of the 3D solid ``body``: one row each (module docstring); the other arguments
    as :class:`FeatureRows`."""

    plane_rows = True  # the closest triangle's plane (False: the triangle, clipped)

    def __init__(self, owner, body, rigid, points, radii, clearance=0.0, margin=None):
        super().__init__(owner, body, rigid, clearance, margin)
        self.points, self.radii = np.asarray(points, float), np.asarray(radii, float)
        self.size = len(self.points)
        self._facet_dofs = body.node_translation_dofs(self.facets.ravel()).reshape(-1, 9)
        self.kept = None  # (q, the geometry at q, the rows at q or None): the last state

    def reset(self) -> None:
        self.kept = None

    def detect_within(self, distance: float) -> None:
        if distance != self.margin:
            self.reset()
        super().detect_within(distance)

    def measured(self, q: np.ndarray) -> tuple:
        """``_geometry`` at q, kept for the next call at the same q: the gaps, the gradients
        and the slip rows of one state are asked for in turn (a box's corners on a slab:
        2572 measurements, of 1403 states). (Its geometry is a function of q alone.)"""
        if self.kept is not None and np.array_equal(self.kept[0], q):
            return self.kept[1]
        out = self._geometry(q)
        self.kept = (q.copy(), out, None)
        return out

    def evaluate(self, q: np.ndarray):
        """Gaps, dofs, gradients (read-only) and no curvature (:meth:`_rows`), kept with the
        geometry for the next call at the same q."""
        self.measured(q)
        if self.kept[2] is None:
            g, dofs, G, _ = self._rows(q)
            G.flags.writeable = False
            self.kept = (*self.kept[:2], (g, dofs, G))
        g, dofs, G = self.kept[2]
        return g.copy(), dofs, G, None

    def _geometry(self, q: np.ndarray):
        """Points p (k, 3), R, their closest triangles (k,) (−1: none near), the triangles'
        nodes (k, 3, 3), the rows' unit normals n (k, 3), their gaps (k,) and the points y
        (k, 3) whose area coordinates the rows take (p itself for a plane's row)."""
        (oa, ob), body = self.offsets, self.body
        x = body.positions(q[oa : oa + body.ndof])
        qr = q[ob : ob + 6]
        R = exp(qr[3:6])
        p = self.points @ R.T + self.rigid.center(qr)
        f = self._closest(p, x)
        if np.all(f < 0):  # no point near the solid: nothing to measure
            far = np.full((self.size, 3), np.nan)
            return p, R, f, np.zeros((self.size, 3, 3)), far, np.full(self.size, np.inf), p
        t = x[self.facets[np.maximum(f, 0)]]
        n = cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        n /= np.linalg.norm(n, axis=1)[:, None]
        g = np.einsum("kd,kd->k", n, p - t[:, 0])
        y = p
        if not self.plane_rows:  # off the face: the distance to its closest edge or vertex
            y, near = p.copy(), np.flatnonzero(f >= 0)
            dist, off, y[near] = triangle_closest(p[near], t[near])
            k = near[off]
            n[k] = (p[k] - y[k]) / dist[off, None]
            g[k] = dist[off]
        g = g - self.radii - self.clearance
        return p, R, f, t, n, np.where(f >= 0, g, np.inf), y

    def _closest(self, p: np.ndarray, x: np.ndarray) -> np.ndarray:
        """The closest triangle (k,) of each point p (k, 3) among the solid's boundary
        triangles (its nodes at x) within the search distance plus the point's radius of it
        (−1: none). A triangle whose bounding sphere (its centroid, radius ρ) lies farther
        than the nearest sphere plus twice the largest ρ cannot be the closest, and none is
        tested beyond that reach; points outside the solid's box grown by it need no
        triangle at all."""
        f = np.full(len(p), -1)
        reach = self.margin + self.radii
        lo, hi = x.min(axis=0) - reach.max(), x.max(axis=0) + reach.max()
        near = np.flatnonzero(np.all((p >= lo) & (p <= hi), axis=1))
        if near.size == 0:
            return f
        xf = x[self.facets]
        centre = xf.mean(axis=1)
        radius = np.linalg.norm(xf - centre[:, None], axis=2).max(axis=1)
        d = np.linalg.norm(p[near, None] - centre[None], axis=2) - radius  # (k, F) ≤ distance
        bound = np.minimum(d.min(axis=1), reach[near]) + 2.0 * radius.max()
        k, j = np.nonzero(d <= bound[:, None])
        dist = facet_distances(p[near][k], xf[j])
        order = np.lexsort((dist, k))  # by point, nearest first
        first = order[np.r_[0, np.flatnonzero(np.diff(k[order])) + 1]]
        keep = dist[first] <= reach[near][k[first]] + 2.0 * radius.max()
        f[near[k[first][keep]]] = j[first][keep]
        return f

    @staticmethod
    def _area_coordinates(p: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Area coordinates (k, 3) of the projections of points p (k, 3) on the planes of the
        triangles t (k, 3, 3)."""
        e1, e2, w = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0], p - t[:, 0]
        d11, d12, d22 = (np.einsum("kd,kd->k", a, b) for a, b in ((e1, e1), (e1, e2), (e2, e2)))
        w1, w2 = np.einsum("kd,kd->k", w, e1), np.einsum("kd,kd->k", w, e2)
        det = d11 * d22 - d12 * d12
        l1, l2 = (d22 * w1 - d12 * w2) / det, (d11 * w2 - d12 * w1) / det
        return np.stack([1.0 - l1 - l2, l1, l2], axis=1)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self.measured(q)[-2].copy()

    def _rows(self, q: np.ndarray):
        """Gaps (k,), dofs (k, 15): the body's six then the triangle's nine, gradients (k, 15),
        no curvature."""
        p, R, f, t, n, g, y = self.measured(q)
        oa, ob = self.offsets
        dofs = np.concatenate(
            [np.broadcast_to(ob + np.arange(6), (self.size, 6)),
             oa + self._facet_dofs[np.maximum(f, 0)]], axis=1
        )  # fmt: skip
        G = np.zeros((self.size, 15))
        if np.all(f < 0):
            return g, dofs, G, None
        lam = self._area_coordinates(y, t)
        G[:, :3] = n
        G[:, 3:6] = cross(self.points, n @ R)  # r × (Rᵀ n)
        G[:, 6:] = (-lam[:, :, None] * n[:, None, :]).reshape(-1, 9)
        G[~np.isfinite(g)] = 0.0
        return g, dofs, G, None

    def tangents(self, q: np.ndarray):
        """Dofs (k, 15), slip rows (k, 2, 15) and tangents T (k, 2, 3) of the points' material
        points under the contact (zero rows where no triangle is near)."""
        p, R, f, t, n, g, y = self.measured(q)
        dofs = self.evaluate(q)[1]
        near = np.isfinite(g)
        T = np.broadcast_to(tangent_basis(np.array([[0.0, 0.0, 1.0]])), (self.size, 2, 3)).copy()
        W = np.zeros((self.size, 3, 15))
        if near.any():
            T[near] = tangent_basis(n[near])
            lam = self._area_coordinates(y, t)
            W[:, :, :3] = np.eye(3)
            arm = self.points - self.radii[:, None] * np.where(near[:, None], n @ R, 0.0)
            W[:, :, 3:6] = -R @ hat(arm)  # ∂(p − a n)/∂Θ at fixed n = −R ã
            for i in range(3):
                W[:, :, 6 + 3 * i : 9 + 3 * i] = -lam[:, i, None, None] * np.eye(3)
            W[~near] = 0.0
        return dofs, np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The slip rows at q applied to the step: the body's body-frame increment
        (Δu, log(R_nᵀR)) and the nodes' displacements."""
        dofs, W, _ = self.tangents(q)
        step = q - q_n
        ob = self.offsets[1]
        step[ob + 3 : ob + 6] = log(exp(q_n[ob + 3 : ob + 6]).T @ exp(q[ob + 3 : ob + 6]))
        return np.einsum("mtk,mk->mt", W, step[dofs])


class BoxCorners(RigidPoints):
    """The eight corners of the ``Box`` of ``rigid`` against the boundary of the 3D solid
    ``body`` (radius 0); arguments as :class:`FeatureRows`."""

    def __init__(self, owner, body, rigid, clearance=0.0, margin=None):
        corners = box_features(rigid.shape, 0)
        super().__init__(owner, body, rigid, corners, np.zeros(len(corners)), clearance, margin)


class BallCentre(RigidPoints):
    """The centre of the ``Ball`` of ``rigid`` against each boundary triangle of the 3D solid
    ``body``, kept the ball's radius from it (clipped to the triangle): one row per
    triangle, +inf beyond the search distance; arguments as :class:`FeatureRows`. A row per
    triangle rather than the closest one: a ball pressed into a dimple rests on several of
    its triangles at once, where the closest one changes between Newton's iterates and one
    row stalled them (a 2 cm ball on a node of a 6 × 6 slab)."""

    redundant_rows = True  # (the pole on a node: its triangles' rows and the node's hold it)
    plane_rows = False  # (the plane of a dimple's triangle passes above its lowest node)

    def __init__(self, owner, body, rigid, clearance=0.0, margin=None):
        size = len(body.contact_facets())
        radii = np.full(size, rigid.shape.radius)
        super().__init__(owner, body, rigid, np.zeros((size, 3)), radii, clearance, margin)

    def _closest(self, p: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Each row's triangle (k,), −1 where the centre lies beyond the search distance plus
        the radius of it."""
        xf, reach = x[self.facets], self.margin + self.radii[0]
        centre = xf.mean(axis=1)
        radius = np.linalg.norm(xf - centre[:, None], axis=2).max(axis=1)
        # a triangle whose bounding sphere lies beyond the reach is beyond it
        near = np.flatnonzero(np.linalg.norm(p - centre, axis=1) - radius <= reach)
        f = np.full(self.size, -1)
        near = near[facet_distances(p[near], xf[near]) <= reach]
        f[near] = near
        return f
