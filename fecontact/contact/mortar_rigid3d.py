r"""Dual mortar contact of a 3D :class:`~fecontact.Solid` against a rigid body in space.

The solid's boundary triangles (:meth:`~fecontact.Solid.contact_facets`) are the slave surface,
the exact shape of a :class:`~fecontact.bodies.rigid3d.RigidBody3D` (``Ball`` or ``Box``) the
master. Each slave boundary node j carries one multiplier and one row,

    g_j = d_j + w_j (g̃_j / L_j − d_j),   g̃_j = Σ_e ∫_e Φ_j g(x) dA₀,
    g(x) = D(Rᵀ(x − c)) − clearance,

with D the shape's exact signed distance (:mod:`fecontact.contact.rigid_distance`), d_j = g at
the node, c and R the body's centre and rotation, x = Σ λ_k x_k the current point of area
coordinates λ, Φ_j = 4λ_j − 1 the dual functions of the linear triangle
(∫_e Φ_j λ_k dA₀ = δ_jk |e|₀/3), L_j = Σ_e |e|₀/3 the reference area node j carries, and w_j
the weight of :func:`~fecontact.contact.rigid_distance.feature_weights`. The master's distance
field is defined everywhere, so every slave triangle is covered whole and keeps the dual
functions of the whole triangle: no projection, no clipping, no partial coverage.

Why the weight: by biorthogonality g̃_j / L_j = d_j + ∫ Φ_j (g − ℓ_j) dA₀ / L_j, ℓ_j the
distance linearised at the node: the weighted gap adds to the node's distance only the
dual-weighted curvature of D over the node's triangles. Where the mesh resolves that curvature
it is a second-order artefact with the sign of the negative lobes: a stand-off (−0.166 h²/r
where a sphere touches a flat mesh at a node) and, at a box edge, a tangential force from face
nodes whose triangles reach across the edge's region plane (+17.5 % of the approach speed
sideways for a ball landing 1 cm inside an edge its contact patch never reaches). Where it
does not (a box's edge or corner seen from its region) it is what keeps the feature out
between the nodes. So w_j = 0 over a box's faces (the rows are the nodal distances, which the
weighted gap of a linear field equals: the patch test), ramping to 1 over the node's own
triangle size into an edge or corner region. Against a ball w_j = 0: where the triangles
outgrow it (a node's longest edge above r) the ball's centre has rows of its own against
them (:class:`~fecontact.contact.box_corners.BallCentre`), which hold the sphere out of the
faces between the nodes; the weighted gap did it with a stand-off of 23 % of r (a 2 cm ball
on 3.3 cm cells).

The integral is over the reference surface (dA₀), unlike the solid–solid mortar's current
area: the multiplier λ_j / L_j is then the nominal (first Piola–Kirchhoff) pressure, uniform
to round-off under a uniform load at any strain, as node-to-surface's nodal forces over the
same areas. Over the current area the rows of a block pressed at 0.1 % strain carried the
strain of the faces beside the contact into the pressure of the perimeter nodes (0.1 %
spread, measured).

Integration: the degree-5 rule of :func:`~fecontact.contact.rigid_distance.triangle_rule` on
each triangle, on s² sub-triangles where a box's region plane cuts it.

Gradients and curvature (of d_j, g̃_j and w_j, combined by the product rule): over the 15 local
dofs of a triangle, its nodes' translations and the body's (u, Θ), Θ body-frame (R ⊕ δΘ = R
exp(δΘ̃)). At a point ρ = Rᵀ(x − c), with ∂ρ/∂(x_k, u, Θ) = (λ_k Rᵀ, −Rᵀ, ρ̃), so ∂g = n_bᵀ ∂ρ.
The curvature is the derivative of the gradient along the dofs (the rotation's included:
Newton's tangent of the force Gᵀλ on the group), J_ρᵀ ∇²D J_ρ plus the terms of R moving n_b
and ρ̃ moving with Θ: (x_k, Θ): −λ_k R ñ_b, (u, Θ): R ñ_b, their mirror images, and (Θ, Θ): ñ_b
ρ̃ (unsymmetric). The integration points are fixed in area coordinates; where a box's region
plane crosses a triangle the sub-triangles do not follow it, and the curvature of D jumps
there: the rate of Newton's method can drop to superlinear while such a triangle is pressed.

Rows of nodes farther from the shape than the detection margin plus 1.4 times their triangles'
longest edge (``LIPSCHITZ``) report g = +inf and a zero gradient: their distance and their
weighted gap exceed the margin. Only the triangles of rows with w_j > 0 are integrated. Every
node's exact distance is measured at every evaluation (no search to miss one), and
:class:`NodeDepths` reports the deepest node inside the shape (the weighted gaps hold the
integrals, not each node: a node may sit inside by the discretization's own amount).
Friction: slip rows T_j·[(1 − w_j)(ẋ_j − ẏ_j) + w_j ∫ Φ_j (ẋ − ẏ) dA₀ / L_j], ẏ the velocity of
the body's material point under x, T_j the tangents of the shape's normal at node j (as the
solid–solid mortar does). A box's corners and edges, and the pole of a ball smaller than the
triangles, which can enter between the nodes, carry rows of their own
(:mod:`fecontact.contact.box_corners`, :mod:`fecontact.contact.box_edges`, the pair's
``companions``), and :class:`NodeDepths` also measures the box's corners and edges
inside the solid (:class:`~fecontact.contact.rigid_distance.FeatureDepths`).
"""

from __future__ import annotations

import numpy as np

from ..bodies.rigid3d import RigidBody3D
from ..bodies.shapes3d import Ball, Box
from ..bodies.solid import Solid
from ..errors import InputError, check_positive
from ..rotations import exp, hat, log
from .boundary_mortar import BoundaryRows
from .box_corners import BallCentre, BoxCorners
from .box_edges import BoxEdges
from .friction import tangent_basis
from .rigid_distance import (
    SUBDIVISIONS,
    FeatureDepths,
    feature_weights,
    shape_distance,
    straddles,
)

__all__ = ["LIPSCHITZ", "MortarRigid3D", "NodeDepths"]

_EYE = np.eye(3)
_NODE9 = np.r_[0:3, 9:15]  # a point at a triangle's first end: its node's and the body's dofs

LIPSCHITZ = 1.4
"""A node's row is at least d_j − 1.375 reach_j: with n_j the distance's gradient at the node,
r(x) = D(x) − d_j − n_j·(x − x_j) lies in [0, 2|x − x_j|] (the signed distance of a convex
shape is convex and 1-Lipschitz), the linear part integrates to zero against Φ_j
(biorthogonality), every point of the node's triangles lies within reach_j (their longest
edge) of it, and the negative lobe of Φ_j weighs 0.229 |e|₀ on each triangle (3 × 0.229 per
unit of the node's area L_j)."""


def _columns(star_positions: np.ndarray, K: int) -> np.ndarray:
    """The columns (E, 3, 15) of each triangle end's 15 local dofs in its row: its nodes'
    translations at their places in the row's star of K nodes, then the body's six dofs."""
    E = len(star_positions)
    node_cols = 3 * star_positions[..., None] + np.arange(3)
    rigid = np.broadcast_to(3 * K + np.arange(6), (E, 3, 6))
    return np.concatenate([node_cols.reshape(E, 3, 9), rigid], axis=2)


def _local_rows(lam, node, other, turn) -> np.ndarray:
    """(P, 3, 15): the blocks λ_k ``node`` (3, 3) for the triangle's nodes k, ``other`` (3, 3)
    for the body's u and ``turn`` (P, 3, 3) for its Θ."""
    J = np.empty((len(lam), 3, 15))
    for k in range(3):
        J[:, :, 3 * k : 3 * k + 3] = lam[:, k, None, None] * node
    J[:, :, 9:12] = other
    J[:, :, 12:] = turn
    return J


def _rule_duals(lam: np.ndarray, w: np.ndarray):
    """A quadrature rule's area coordinates λ (n, 3), its dual weights w_p Φ_i (n, 3) and the
    coefficients (n, 12) of the gradients' sums (:func:`_end_gradients`): w_p Φ_i λ_k for
    (i, k), then w_p Φ_i."""
    wphi = w[:, None] * (4.0 * lam - 1.0)
    coef = (wphi[:, :, None] * lam[:, None, :]).reshape(len(w), 9)
    return lam, wphi, np.concatenate([coef, wphi], axis=1)


def _end_gradients(duals, counts, normal, moment) -> np.ndarray:
    """Each triangle's sums Σ_p w_p Φ_i ∂g over its points (T, 3, 15), ∂g = n_bᵀ ∂ρ = [λ_k n,
    −n, n_b × ρ] with n = R n_b the world ``normal`` (P, 3) and ``moment`` = n_b × ρ (P, 3),
    the points ``counts`` triangles on each rule of ``duals`` (:func:`_rule_duals`) in turn.
    Every triangle of a rule has the same λ and weights: one matrix product per rule. (Point
    by point, ∂g (P, 15) and its products with Φ (P, 3, 15) took 12 of an evaluation's 15 ms
    for a box on a slab, 10⁴ points.)"""
    out, start = [], 0
    for (lam, _, coef), T in zip(duals, counts, strict=True):
        n = len(lam)
        points = slice(start, start + T * n)
        start += T * n
        f = np.concatenate([normal[points], moment[points]], axis=1).reshape(T, n, 6)
        s = np.tensordot(coef, f, axes=([0], [1])).transpose(1, 0, 2)  # (T, 12, 6)
        g = np.empty((T, 3, 15))
        g[:, :, :9] = s[:, :9, :3].reshape(T, 3, 9)
        g[:, :, 9:12] = -s[:, 9:, :3]
        g[:, :, 12:] = s[:, 9:, 3:]
        out.append(g)
    return np.concatenate(out)


def _slip_integrals(duals, parts, R, c) -> np.ndarray:
    """Σ_p w_p Φ_i ∂(x − y)/∂(local dofs) (T, 3, 3, 15) over each triangle's points, the
    triangles' nodes ``parts`` (T_r, 3, 3) on each rule of ``duals`` in turn: ∂(x − y) =
    [λ_k I, −I, R ρ̃] is linear in the point, so its sums are [M_ik I, −m_i I, R r̃_i] with
    M_ik = Σ_p w_p Φ_i λ_k and m_i = Σ_p w_p Φ_i the rule's own (the same on each of its
    triangles) and r_i = Σ_p w_p Φ_i ρ_p, one product per rule (point by point, (P, 3, 3, 15)
    products took 29 ms a call for a box on a slab, 10⁴ points)."""
    out = []
    for (lam, wphi, coef), t in zip(duals, parts, strict=True):
        r = wphi.T @ ((lam @ t - c) @ R)  # (T, 3, 3): r_i of each triangle
        W = np.zeros((len(t), 3, 3, 15))
        M = coef[:, :9].sum(axis=0).reshape(3, 3)
        W[..., :9] = np.einsum("ik,ab->iakb", M, _EYE).reshape(3, 3, 9)
        W[..., 9:12] = -wphi.sum(axis=0)[:, None, None] * _EYE
        W[..., 12:] = R @ hat(r)
        out.append(W)
    return np.concatenate(out)


def _rotation_terms(R, nb, rho, lam) -> np.ndarray:
    """The curvature's terms (P, 15, 15) from R turning n_b and from ρ̃ (module
    docstring)."""
    P = len(nb)
    E = np.zeros((P, 15, 15))
    Rn = R @ hat(nb)  # (P, 3, 3)
    for k in range(3):
        E[:, 3 * k : 3 * k + 3, 12:] = -lam[:, k, None, None] * Rn
        E[:, 12:, 3 * k : 3 * k + 3] = -lam[:, k, None, None] * Rn.transpose(0, 2, 1)
    E[:, 9:12, 12:] = Rn
    E[:, 12:, 9:12] = Rn.transpose(0, 2, 1)
    E[:, 12:, 12:] = hat(nb) @ hat(rho)
    return E


class RigidMortarGeometry(BoundaryRows):
    """The geometry of :class:`MortarRigid3D` (its constructor's arguments): the slave rows
    (:class:`~fecontact.contact.boundary_mortar.BoundaryRows`), the body's frame, the rows'
    weights w_j and the integrals of their weighted gaps."""

    def __init__(self, body, rigid, restitution=0.0, clearance=0.0, margin=None,
                 subdivisions: int = SUBDIVISIONS):  # fmt: skip
        if not isinstance(body, Solid) or body.dim != 3 or not isinstance(rigid, RigidBody3D):
            raise InputError("mortar contact with a RigidBody3D needs a 3D Solid")
        if not isinstance(rigid.shape, Ball | Box):
            raise InputError(
                f"a Solid's mortar contact meets a RigidBody3D with a Ball or a Box shape, "
                f"got a {type(rigid.shape).__name__}"
            )
        clearance = check_positive("clearance", clearance, allow_zero=True)
        super().__init__(body, restitution, clearance, margin, subdivisions)
        self.rigid, self.bodies = rigid, (body, rigid)
        m, K = self.star.shape
        self._duals = tuple(_rule_duals(lam, w) for lam, w in self.rules)
        self._cols = _columns(self.star_positions, K)
        own = np.argmax(self.star == np.arange(m)[:, None], axis=1)
        rigid = np.broadcast_to(3 * K + np.arange(6), (m, 6))
        self._own_cols = np.concatenate([3 * own[:, None] + np.arange(3), rigid], axis=1)
        self.reference_reach = self.reach(body.X)
        """The longest reference edge (m) of each slave node's triangles: the length over
        which its row turns from the node's own distance to the weighted gap."""
        self._node_dofs = body.node_translation_dofs(self.nodes)
        self.offsets = (0, 0)
        self.dofs = np.zeros((len(self.nodes), self._cols.shape[2]), dtype=int)
        # a box's corners and edges, which the nodes' rows let in between them; the centre of
        # a ball the triangles outgrow, whose pole would sink between the nodes
        shape = self.rigid.shape
        if isinstance(shape, Box):
            self.companions = (BoxCorners(self, body, self.rigid, clearance, margin),
                               BoxEdges(self, body, self.rigid, clearance, margin))  # fmt: skip
        elif np.any(self.reference_reach > shape.radius):
            self.companions = (BallCentre(self, body, self.rigid, clearance, margin),)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        oa, ob = self.offsets = (model.offset_of(self.body), model.offset_of(self.rigid))
        m, K = self.star.shape
        nodes = (oa + self._node_dofs[self.star]).reshape(m, 3 * K)
        self.dofs = np.concatenate([nodes, np.broadcast_to(ob + np.arange(6), (m, 6))], 1)
        self.dofs.flags.writeable = False
        self.reset()
        for pair in self.companions:
            pair.bind(model)

    # -- geometry ---------------------------------------------------------------------------
    def _frame(self, q: np.ndarray):
        """Every node's position (m) of the solid, the body's R and centre c at q."""
        (oa, ob), body = self.offsets, self.body
        qr = q[ob : ob + 6]
        return body.positions(q[oa : oa + body.ndof]), exp(qr[3:]), self.rigid.center(qr)

    def node_distances(self, q: np.ndarray) -> np.ndarray:
        """The exact signed distance g(x_j) (m) of every slave node to the shape, less the
        clearance."""
        x, R, c = self._frame(q)
        return shape_distance(self.rigid.shape, (x[self.nodes] - c) @ R, False)[0] - self.clearance

    def _near(self, x, R, c):
        """The rows that take part (m,) bool, those whose bound from below
        d_j − LIPSCHITZ reach_j is within the margin, and the triangles (T,) to integrate for
        them."""
        rho = (x[self.nodes] - c) @ R
        d = shape_distance(self.rigid.shape, rho, False)[0]
        near = d - self.clearance - LIPSCHITZ * self.reach(x) <= self.margin
        weighted = near & (feature_weights(self.rigid.shape, rho, self.reference_reach)[0] > 0.0)
        tris = np.flatnonzero(weighted[self.element_rows].any(axis=1))
        return near, tris

    def _points(self, tris, x, R, c):
        """The triangles reordered, those a box's region plane cuts last (on the subdivided
        rule), and how many are on each rule (plain, cut)."""
        rho = (x[self.facets[tris]] - c) @ R
        cut = straddles(self.rigid.shape, rho)
        tris = np.concatenate([tris[~cut], tris[cut]])
        return tris, (len(tris) - int(cut.sum()), int(cut.sum()))

    def _integrals(self, q: np.ndarray, order: int, tris=None):
        """The triangles' end integrals ∫ Φ_i g dA₀ (T, 3), and with ``order`` ≥ 1 their
        gradients (T, 3, 15), with ``order`` 2 their curvatures (T, 3, 15, 15): over the
        triangles of the rows that take part (or ``tris``). Returns (near, tris, values...).
        The points of each rule are taken for all its triangles at once (:func:`_rule_duals`:
        the same λ and weights on each)."""
        x, R, c = self._frame(q)
        near, found = self._near(x, R, c)
        tris = found if tris is None else tris
        if len(tris) == 0:
            return near, tris, np.zeros((0, 3)), np.zeros((0, 3, 15)), np.zeros((0, 3, 15, 15))
        tris, counts = self._points(tris, x, R, c)
        t = x[self.facets[tris]]
        rules = tuple(zip(self._duals, np.split(t, [counts[0]]), strict=True))
        rho = (np.concatenate([(d[0] @ tr).reshape(-1, 3) for d, tr in rules]) - c) @ R
        D, nb, K = shape_distance(self.rigid.shape, rho, order == 2)
        g = np.split(D - self.clearance, [counts[0] * len(self._duals[0][0])])
        s = [gr.reshape(len(tr), len(d[0])) @ d[1] for (d, tr), gr in zip(rules, g, strict=True)]
        A = self.area0[tris]
        values = A[:, None] * np.concatenate(s)
        if order == 0:
            return near, tris, values, None, None
        gs = _end_gradients(self._duals, counts, nb @ R.T, np.cross(nb, rho))
        grads = A[:, None, None] * gs
        if order == 1:
            return near, tris, values, grads, None
        lam = np.concatenate([np.tile(d[0], (len(tr), 1)) for d, tr in rules])
        wphi = np.concatenate([np.tile(d[1], (len(tr), 1)) for d, tr in rules])
        Hp = _rotation_terms(R, nb, rho, lam)
        curved = np.flatnonzero(K.any(axis=(1, 2)))  # a box face's points have ∇²D = 0
        # ∂ρ/∂(x_1, x_2, x_3, u, Θ) (P, 3, 15) of the curved points
        Jc = _local_rows(lam[curved], R.T, -R.T, hat(rho[curved]))
        Hp[curved] += Jc.transpose(0, 2, 1) @ (K[curved] @ Jc)
        sizes = np.repeat([len(d[0]) for d in self._duals], counts)
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        Hs = np.add.reduceat(wphi[:, :, None, None] * Hp[:, None], starts, axis=0)
        return near, tris, values, grads, A[:, None, None, None] * Hs

    # -- rows -------------------------------------------------------------------------------
    def _nodal(self, q: np.ndarray, order: int, rows=None):
        """At the nodes ``rows`` (default all): their own distance g (n,) less the clearance,
        the weight w (n,) of the weighted gap in their row, and with ``order`` ≥ 1 the
        gradients of g and w over the node's and the body's dofs (n, 9), with ``order`` 2
        their curvatures (n, 9, 9)."""
        x, R, c = self._frame(q)
        rows = np.arange(self.size) if rows is None else rows
        rho = (x[self.nodes[rows]] - c) @ R
        shape = self.rigid.shape
        D, nb, K = shape_distance(shape, rho, order == 2)
        w, v, w1, w2 = feature_weights(shape, rho, self.reference_reach[rows])
        if order == 0:
            return D - self.clearance, w
        lam = np.broadcast_to(np.array([1.0, 0.0, 0.0]), (len(rows), 3))
        J = _local_rows(lam, R.T, -R.T, hat(rho))[:, :, _NODE9]
        de = (v[:, None, :] @ J)[:, 0]  # ∂e along the feature's axis
        Gn, Gw = (nb[:, None, :] @ J)[:, 0], w1[:, None] * de
        if order == 1:
            return D - self.clearance, w, Gn, Gw
        sel = np.ix_(np.arange(len(rows)), _NODE9, _NODE9)
        Hn = _rotation_terms(R, nb, rho, lam)[sel] + J.transpose(0, 2, 1) @ K @ J
        Hw = w2[:, None, None] * de[:, :, None] * de[:, None, :]
        Hw += w1[:, None, None] * _rotation_terms(R, v, rho, lam)[sel]
        return D - self.clearance, w, Gn, Gw, Hn, Hw

    def _on_rows(self, nodal: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """Nodal arrays (n, 9[, 9]) of ``rows`` placed in their rows' columns (n, k[, k])."""
        k, n = self.dofs.shape[1], len(rows)
        cols = self._own_cols[rows]
        if nodal.ndim == 2:
            out = np.zeros((n, k))
            out[np.arange(n)[:, None], cols] = nodal
            return out
        out = np.zeros((n, k, k))
        out[np.arange(n)[:, None, None], cols[:, :, None], cols[:, None, :]] = nodal
        return out


class MortarRigid3D(RigidMortarGeometry):
    """Dual mortar contact of the boundary of a 3D :class:`~fecontact.Solid` (``body``, the
    slave) with the exact surface of a :class:`~fecontact.bodies.rigid3d.RigidBody3D` with a
    ``Ball`` or ``Box`` shape; see the module docstring. One contact per slave boundary node;
    ``restitution`` Newton's e_N in [0, 1]; ``clearance`` (m, ≥ 0) kept from the shape;
    ``margin`` (m) the search distance (default: the integrator's detection distance);
    ``subdivisions`` (s ≥ 1) the sub-triangles per edge of a triangle a box's region plane
    cuts."""

    frictional = True

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The rows g_j (m) alone (+inf for rows that take no part)."""
        for cached in (self.cached, self.cached_gaps):
            if cached is not None and np.array_equal(cached[0], q):
                return cached[1].copy()
        near, tris, values = self._integrals(q, 0)[:3]
        g, w = self._nodal(q, 0)
        g = np.where(near, g + w * (self.weighted_rows(tris, values) - g), np.inf)
        self.cached_gaps = (q.copy(), g)
        return g.copy()

    def evaluate(self, q: np.ndarray):
        """Rows (m,) in m, dofs (m, k), gradients (m, k), no curvature (:meth:`hessians`)."""
        if self.cached is not None and np.array_equal(self.cached[0], q):
            return self.cached[1].copy(), self.dofs, self.cached[2], None
        near, tris, values, grads, _ = self._integrals(q, 1)
        g, w, Gn, Gw = self._nodal(q, 1)
        m = self.weighted_rows(tris, values)
        # Σ over the triangles' ends into their rows' columns: one bincount over the ends in
        # turn adds in np.add.at's order (the same sums to the bit), at a fifth of its cost
        r = self.element_rows[tris].T  # (3, T)
        at = r[..., None] * self.dofs.shape[1] + self._cols[tris].transpose(1, 0, 2)
        scaled = grads.transpose(1, 0, 2) / self.length[r, None]
        Gm = np.bincount(at.ravel(), scaled.ravel(), self.dofs.size).reshape(self.dofs.shape)
        every = np.arange(self.size)
        G = w[:, None] * Gm + self._on_rows((1.0 - w[:, None]) * Gn + (m - g)[:, None] * Gw, every)
        G[~near] = 0.0
        G.flags.writeable = False
        g = np.where(near, g + w * (m - g), np.inf)
        self.cached = (q.copy(), g, G)
        return g.copy(), self.dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the rows ``rows`` at q (the derivative of the gradient
        along the dofs), in the layout of :meth:`evaluate`."""
        rows = np.asarray(rows, dtype=int)
        k = self.dofs.shape[1]
        g, w, Gn, Gw, Hn, Hw = self._nodal(q, 2, rows)
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        weighted = np.full(self.size, False)
        weighted[rows[w > 0.0]] = True  # rows with w = 0 have no weighted-gap terms
        tris = np.flatnonzero(weighted[self.element_rows].any(axis=1))
        near, tris, values, grads, H = self._integrals(q, 2, tris)
        Hm, Gm = np.zeros((len(rows), k, k)), np.zeros((len(rows), k))
        for end in range(3):
            r = self.element_rows[tris, end]
            sel = where[r] >= 0
            c, at = self._cols[tris[sel], end], where[r[sel]]
            scale = 1.0 / self.length[r[sel]]
            np.add.at(Hm, (at[:, None, None], c[:, :, None], c[:, None, :]),
                      H[sel, end] * scale[:, None, None])  # fmt: skip
            np.add.at(Gm, (at[:, None], c), grads[sel, end] * scale[:, None])
        m = self.weighted_rows(tris, values)[rows]
        dG, Gw = Gm - self._on_rows(Gn, rows), self._on_rows(Gw, rows)
        out = w[:, None, None] * Hm + self._on_rows((1.0 - w[:, None, None]) * Hn, rows)
        out += dG[:, :, None] * Gw[:, None, :] + Gw[:, :, None] * dG[:, None, :]
        out += (m - g)[:, None, None] * self._on_rows(Hw, rows)
        out[~near[rows]] = 0.0
        return out

    # -- friction ---------------------------------------------------------------------------
    def tangents(self, q: np.ndarray):
        """Slip rows (m, 2, k): T_j·∫ ψ_j (ẋ − ẏ) dA₀ / L_j, ẏ = u̇ − R ρ̃ Ω the body's material
        point at x, ψ_j the row's weight (w_j Φ_j and 1 − w_j at the node), T_j (m, 2, 3) the
        tangents of the shape's normal at node j."""
        x, R, c = self._frame(q)
        near, tris = self._near(x, R, c)
        rho = (x[self.nodes] - c) @ R
        nb = shape_distance(self.rigid.shape, rho, False)[1]
        w = feature_weights(self.rigid.shape, rho, self.reference_reach)[0]
        T = tangent_basis(nb @ R.T)
        W = np.zeros((self.size, 3, self.dofs.shape[1]))
        lam = np.broadcast_to(np.array([1.0, 0.0, 0.0]), (self.size, 3))
        Wn = _local_rows(lam, _EYE, -_EYE, R @ hat(rho))[:, :, _NODE9]
        at = (np.arange(self.size)[:, None, None], np.arange(3)[None, :, None])
        W[at + (self._own_cols[:, None, :],)] = (1.0 - w[:, None, None]) * Wn
        if len(tris):
            tris, counts = self._points(tris, x, R, c)
            parts = np.split(x[self.facets[tris]], [counts[0]])
            Ws = _slip_integrals(self._duals, parts, R, c) * self.area0[tris, None, None, None]
            scale = w / self.length
            for k in range(3):
                r = self.element_rows[tris, k]
                at = (r[:, None, None], np.arange(3)[None, :, None], self._cols[tris, k][:, None])
                np.add.at(W, at, Ws[:, k] * scale[r, None, None])
        W[~near] = 0.0
        return self.dofs, np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The slip rows at q applied to the step's increment, the body's rotation by
        log(R_nᵀR) (its body-frame increment), the solid's translations by their difference."""
        _, W, _ = self.tangents(q)
        step = q - q_n
        ob = self.offsets[1]
        step[ob + 3 : ob + 6] = log(exp(q_n[ob + 3 : ob + 6]).T @ exp(q[ob + 3 : ob + 6]))
        return np.einsum("mtk,mk->mt", W, step[self.dofs])

    # -- what the rows do not hold ----------------------------------------------------------
    def admissible_gaps(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """The nodes' exact distances (m) where the rows take part: a state is admitted unless
        a node lies inside the shape (a weighted gap reads a stand-off where none is)."""
        return np.where(np.isfinite(rows), self.node_distances(q), np.inf)

    def watch(self) -> NodeDepths:
        return NodeDepths(self)


class NodeDepths:
    """The deepest slave node of a :class:`MortarRigid3D` inside the rigid shape, by its exact
    signed distance, over the shortest reference boundary edge at that node, and the deepest
    corner or edge of a box inside the solid (:class:`FeatureDepths`), over the longest edge
    of the triangle it lies under."""

    def __init__(self, pair: MortarRigid3D):
        self.pair = pair
        t = pair.body.X[pair.facets]
        edge = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).min(axis=1)
        self.edge = np.full(pair.size, np.inf)
        for k in range(3):
            np.minimum.at(self.edge, pair.element_rows[:, k], edge)
        # a rigid box's corners and edges (the tube pair, which shares the class, has none)
        self.features = FeatureDepths(pair) if isinstance(pair, MortarRigid3D) else None

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        """(deepest point's depth in m, ≥ 0; the largest depth over its local edge)."""
        d = -self.pair.node_distances(q)
        corner, ratio = (0.0, 0.0) if self.features is None else self.features.depth(q)
        return max(0.0, float(d.max()), corner), max(0.0, float((d / self.edge).max()), ratio)

    def entering(self, q: np.ndarray) -> str:
        """What enters the other body deepest over its local edge: a slave node, or a box's
        edge or corner (for a message)."""
        if self.features is None:
            return "a node"
        nodes = float(np.max(-self.pair.node_distances(q) / self.edge, initial=0.0))
        return self.features.entering(q) if self.features.depth(q)[1] > nodes else "a node"
