r"""The exact signed distance to a rigid shape in space, and the triangle rules that integrate it.

In the body frame, a point at ρ (m, from the centre) has the signed distance D(ρ) (m; > 0
outside), its gradient n_b = ∇D (the unit outward normal of the closest surface point) and its
curvature ∇²D (1/m):

=======  ===================================================================================
Ball     D = |ρ| − r,  n_b = ρ/|ρ|,  ∇²D = (I − n_b n_bᵀ)/|ρ|
Box      outside: D = |ρ − p|, p = clamp(ρ, ±h) the closest point (h the half sides),
         n_b = (ρ − p)/D, ∇²D = (diag(m) − n_b n_bᵀ)/D, m_k = 1 on the axes where ρ is
         clamped; inside: D = −min_k (h_k − |ρ_k|), n_b = ±e_k of the nearest face, ∇²D = 0
=======  ===================================================================================

Outside a convex shape D is C¹ (its gradient is the unit vector to the closest point), its
curvature jumps where the closest point moves from a face to an edge or a corner: across the
planes ρ_k = ±h_k of a box. A triangle rule of degree 5 integrates the mortar integrands
(a linear dual function times D) exactly where D is linear (over one face region) and to
O(ℓ⁶) where it is smooth; a triangle cut by one of the box's region planes is integrated with
the same rule on each of s² sub-triangles (:func:`triangle_rule`), where the error of the
kink in the curvature falls as s grows (docs/explanation/mortar.md, the measured order).
Inside the box D is only C⁰ (the nearest face changes across the medial planes): the
penetrated part is integrated with the same rules, without subdivision.
"""

from __future__ import annotations

import numpy as np

from ..bodies.shapes3d import Ball, Box
from ..errors import InputError
from ..rotations import exp
from .inside import Surface

__all__ = [
    "EDGE_POINTS",
    "FeatureDepths",
    "SUBDIVISIONS",
    "box_features",
    "feature_weights",
    "shape_distance",
    "straddles",
    "triangle_rule",
]

SUBDIVISIONS = 4
"""Sub-triangles per edge (s) of a triangle that a box's region plane cuts: s² pieces, 7·s²
points."""

ON_PLANE = 1e-9
"""Vertices within this fraction of the box's largest half side of a region plane lie on it."""

# Dunavant's 7-point rule of degree 5: area coordinates and weights (fractions of the area)
_A1, _B1, _W1 = 0.059715871789770, 0.470142064105115, 0.132394152788506
_A2, _B2, _W2 = 0.797426985353087, 0.101286507323456, 0.125939180544827
_POINTS = np.array(
    [[1 / 3, 1 / 3, 1 / 3],
     [_A1, _B1, _B1], [_B1, _A1, _B1], [_B1, _B1, _A1],
     [_A2, _B2, _B2], [_B2, _A2, _B2], [_B2, _B2, _A2]]
)  # fmt: skip
_WEIGHTS = np.array([0.225, _W1, _W1, _W1, _W2, _W2, _W2])


def triangle_rule(s: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Area coordinates (7 s², 3) and weights (7 s²,) summing to 1 of the degree-5 rule on
    each of the s² congruent sub-triangles of a triangle (s ≥ 1 per edge)."""
    corners = []
    for i in range(s):
        for j in range(s - i):
            corners.append([(i, j), (i + 1, j), (i, j + 1)])
            if i + j < s - 1:
                corners.append([(i + 1, j), (i + 1, j + 1), (i, j + 1)])
    c = np.array(corners, dtype=float) / s  # (s², 3 corners, (λ₂, λ₃))
    lam23 = np.einsum("pk,tkd->tpd", _POINTS, c).reshape(-1, 2)
    lam = np.column_stack([1.0 - lam23.sum(axis=1), lam23])
    return lam, np.tile(_WEIGHTS, len(c)) / len(c)


def straddles(shape, rho: np.ndarray) -> np.ndarray:
    """Whether each triangle with body-frame vertices ``rho`` (E, 3, 3) is cut by a plane
    where the curvature of D jumps (a box's ρ_k = ±h_k): it has vertices on both sides of
    it, farther than ``ON_PLANE`` of the box's size (a vertex on the plane, as of a face
    resting on the box, cuts nothing). A ball has none."""
    if isinstance(shape, Ball):
        return np.zeros(len(rho), dtype=bool)
    half = 0.5 * shape.sides
    tol = ON_PLANE * float(half.max())
    cut = np.zeros(len(rho), dtype=bool)
    for plane in (half, -half):
        above, below = rho > plane + tol, rho < plane - tol  # (E, 3 vertices, 3 axes)
        cut |= np.any(above.any(axis=1) & below.any(axis=1), axis=1)
    return cut


def shape_distance(shape, rho: np.ndarray, curvature: bool = True):
    """D (P,), n_b (P, 3) and, with ``curvature``, ∇²D (P, 3, 3) at body-frame points ρ
    (P, 3) (module docstring)."""
    if isinstance(shape, Ball):
        return _ball(shape.radius, rho, curvature)
    if isinstance(shape, Box):
        return _box(0.5 * shape.sides, rho, curvature)
    raise InputError(f"mortar contact meets a Ball or a Box, got a {type(shape).__name__}")


def _ball(radius: float, rho: np.ndarray, curvature: bool):
    dist = np.linalg.norm(rho, axis=1)
    if np.any(dist == 0.0):
        raise InputError("a point lies at the rigid ball's centre: no contact normal")
    n = rho / dist[:, None]
    if not curvature:
        return dist - radius, n, None
    K = (np.eye(3) - n[:, :, None] * n[:, None, :]) / dist[:, None, None]
    return dist - radius, n, K


def _box(half: np.ndarray, rho: np.ndarray, curvature: bool):
    # (np.clip's and np.linalg.norm's own operations, without their wrappers, and n without
    # the masked copies: the same numbers, at 0.58 of the time on 10⁴ points)
    d = rho - np.minimum(np.maximum(rho, -half), half)
    dist = np.sqrt(np.add.reduce(d * d, axis=1))
    out = dist > 0.0
    n = np.divide(d, dist[:, None], out=np.zeros_like(rho), where=out[:, None])
    if not out.all():  # inside: leave by the nearest face
        rows = np.flatnonzero(~out)
        depth = half - np.abs(rho[rows])
        k = np.argmin(depth, axis=1)
        n[rows, k] = np.where(rho[rows, k] >= 0.0, 1.0, -1.0)
        dist[rows] = -depth[np.arange(len(rows)), k]
    if not curvature:
        return dist, n, None
    K = np.zeros((len(rho), 3, 3))
    if out.any():
        clamped = (np.abs(rho[out]) > half).astype(float)
        K[out] = (clamped[:, :, None] * np.eye(3) - n[out, :, None] * n[out, None, :]) / dist[
            out, None, None
        ]
    return dist, n, K


def _smoothstep(t: np.ndarray):
    """s(t) = 3t² − 2t³ on [0, 1] (0 below, 1 above; C¹), s' and s''."""
    t = np.clip(t, 0.0, 1.0)
    inner = (t > 0.0) & (t < 1.0)
    d1, d2 = np.where(inner, 6 * t * (1 - t), 0.0), np.where(inner, 6 - 12 * t, 0.0)
    return 3 * t**2 - 2 * t**3, d1, d2


def feature_weights(shape, rho: np.ndarray, reach: np.ndarray):
    """How much of the weighted gap (rather than the node's own distance) each slave node's
    row takes, and its derivatives: (w, v, w1, w2), w (m,) in [0, 1], dw/dρ = w1 v and
    d²w/dρ² = w2 v vᵀ with v (m, 3) a unit axis (or 0), at nodes ρ (m, 3) (body frame, m)
    whose triangles' longest edge is ``reach`` (m,) (m).

    The weighted gap differs from the node's own distance by the dual-weighted curvature of
    D over the node's triangles only; where the mesh resolves that curvature the difference
    is a second-order artefact (a stand-off; a tangential force where a node's triangles
    reach across a box edge), where it does not (a box edge or corner, a ball smaller than
    the triangles) it is what keeps the feature out between the nodes. Box: w = s(e/reach),
    e the node's depth into an edge or corner region (the second largest of the outward
    offsets |ρ_k| − h_k > 0; 0 over a face or inside). Ball: w = 0, the nodes' own distances;
    where the triangles outgrow the ball its centre has rows of its own against them
    (:class:`~fecontact.contact.box_corners.BallCentre`), which hold the sphere out of the
    faces without the weighted gap's stand-off (4.5 mm, 23 % of r, for a 2 cm ball on
    3.3 cm cells: ``docs/explanation/mortar_rigid.md``)."""
    m = len(rho)
    if isinstance(shape, Ball):
        return np.zeros(m), np.zeros((m, 3)), np.zeros(m), np.zeros(m)
    offsets = np.maximum(np.abs(rho) - 0.5 * shape.sides, 0.0)
    axis = np.argsort(offsets, axis=1, kind="stable")[:, 1]
    e = offsets[np.arange(m), axis]
    w, d1, d2 = _smoothstep(e / reach)
    v = np.zeros((m, 3))
    v[np.arange(m), axis] = np.where(e > 0.0, np.sign(rho[np.arange(m), axis]), 0.0)
    return w, v, d1 / reach, d2 / reach**2


EDGE_POINTS = 7
"""Points inside each edge of a box (besides its corners) that :class:`FeatureDepths` tests."""


def box_features(box: Box, per_edge: int = EDGE_POINTS) -> np.ndarray:
    """Body-frame points (8 + 12 ``per_edge``, 3) in m: a box's corners, then ``per_edge``
    points evenly spaced inside each of its twelve edges."""
    signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float)
    corners = 0.5 * signs * box.sides
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if np.sum(signs[a] != signs[b]) == 1]
    t = (np.arange(1, per_edge + 1) / (per_edge + 1))[:, None, None]
    a, b = corners[[e[0] for e in edges]], corners[[e[1] for e in edges]]
    return np.vstack([corners, ((1.0 - t) * a + t * b).reshape(-1, 3)])


class FeatureDepths:
    """A rigid box's corners and edges against a 3D solid's discretized boundary: what the
    rows of a ``pair`` of the two (one per node of the solid) cannot see, a corner or an edge
    entering between the nodes. The pair names the ``body`` (the solid), the ``rigid`` body
    and the ``offsets`` of their dofs (read at each call: set when the model binds it).

    ``depth(q)``: the deepest of the box's points (:func:`box_features`) inside the solid's
    boundary, by the inside/outside test of :class:`fecontact.contact.inside.Surface`, in m
    (≥ 0), and that depth over the longest edge of the triangle it lies under. A ball's
    surface between the nodes sinks by the discretization's own sag, which the rows bound
    (``docs/explanation/mortar_rigid.md``): nothing is tested for a ball (0, 0)."""

    def __init__(self, pair):
        self.pair = pair
        shape = pair.rigid.shape
        self.points = box_features(shape) if isinstance(shape, Box) else None
        self.facets = pair.body.contact_facets()
        self.surface = Surface(self.facets) if self.points is not None else None

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        if self.points is None:
            return 0.0, 0.0
        (oa, ob), solid, rigid = self.pair.offsets, self.pair.body, self.pair.rigid
        x = solid.positions(q[oa : oa + solid.ndof])
        q_rigid = q[ob : ob + 6]
        p = self.points @ exp(q_rigid[3:6]).T + rigid.center(q_rigid)
        s, f = self.surface.signed_distance(x, p, outside=False)
        inside = np.flatnonzero(s < 0.0)
        if inside.size == 0:
            return 0.0, 0.0
        t = x[self.facets[f[inside]]]
        longest = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).max(axis=1)
        return float(-s[inside].min()), float(np.max(-s[inside] / longest))

    def entering(self, q: np.ndarray) -> str:
        """What of the box enters the solid (for a message)."""
        return "a box edge or corner of a rigid body"
