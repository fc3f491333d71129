r"""Mortar contact between two 3D solids: dual mortar on the slave's boundary triangles.

The form is that of :mod:`fecontact.contact.mortar` (dual Lagrange multipliers, one per slave
boundary node, weighted gaps g̃_j = ∫ Φ_j g_N dA as the constraints, rows g_j = g̃_j / L_j with
L_j the reference area the node carries, exact gradients), over triangles: the
boundary of P1 tetrahedra, or of P2 tetrahedra split through their edge nodes into four flat
triangles (as for node-to-surface contact; the curved quadratic faces themselves, with the
basis transformation of Popp, Wohlmuth, Gee & Wall 2012, are
:class:`~fecontact.contact.mortar3d_p2.MortarContact3DP2`). The integral is evaluated over the
overlap of each slave triangle with the master triangles (segment-based integration: each
master triangle is projected onto the slave triangle's plane along its normal, the overlap
clipped, cut into a fan of cells and integrated with a degree-2 rule,
:func:`~fecontact.contact.mortar_facets.clipped_points`): the cells follow the master's
edges, so the mortar integrals are exact where the integrand is polynomial on each cell —
the patch test holds to round-off. The gap is measured along the slave triangle's own normal
(no averaged normals: the kinematics stay local to one triangle pair per point).

Partners: master triangles facing the slave triangle (normals at more than 90°,
``mortar_facets.FACING``; up to 104.5° with a weight rising from 0, :func:`_turned`) whose
vertices lie on average less than three times the detection margin ahead of it and at most
the margin behind it. Beyond twice the margin a pair's
weight falls smoothly to 0 at three times (:func:`_faded`, its gradient included): a hard
cut there let a pair enter a row's weighted gap with a finite overlap, and the gap jump
under a held row's force created energy (``docs/validation/stress_3d.md``).
A slave triangle the master covers in part (the edge of the contact zone, or every triangle
at the pole of a coarse ball) takes the dual functions biorthogonal on its covered polygon
(:mod:`fecontact.contact.mortar_cover`, Popp, Seitz, Gee & Wall 2013); one covered by less
than ``mortar_cover.SMALLEST`` of its area counts as not covered.

Linearisation: the gradient is exact. On a fully covered triangle the cells' boundaries move
with q, but the integrand Φ_j g_N is continuous across the master's edges, so the moving
interior boundaries cancel, and the triangle's own edges do not move in its area
coordinates. On a partly covered triangle the covered polygon's edges move, and with them
its dual functions: the gradient adds their derivatives through the clipped vertices
(:func:`~fecontact.contact.mortar_facets.clipped_moments`). The Hessian is that of the fixed
integration points and fixed dual functions: it leaves out the jumps of ∂g_N/∂q across the
master's edges as the cells move (the clip vertex terms of Popp, Gitterle, Gee & Wall 2010)
and the second derivatives through the covered polygon, so Newton's method converges faster
than linearly but not quadratically once those terms matter.

The nodal pressure is z_j = λ_j / L_j (Pa), λ_j the normal force of row j (N).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError
from .mortar_cover import covered_duals, triangles_taking_part
from .mortar_facets import FACING, clipped_points, facet_pair_integrals, meet_triangles
from .mortar_interface import MortarInterface, element_measures

__all__ = ["MortarContact3D"]


class MortarContact3D(MortarInterface):
    """Dual mortar contact of the boundary of a 3D :class:`~fecontact.Solid` (the slave
    ``body``) with the boundary of another (the ``master``); see the module docstring. One
    contact per slave boundary node; ``restitution`` is Newton's e_N in [0, 1]; ``margin``
    (m) the search distance (default: the integrator's detection distance)."""

    taking_part = 0.25
    """A node takes part from a quarter of its covered weight (half in 2D): at the pole of a
    coarse ball (four triangles) the share swings around ½ as the pole flattens (0.47-0.57
    measured on two balls of 18 boundary nodes meeting node on node), and a node dropped
    there is released while it is pressed in (it then lay 1.1 % of an edge inside the other
    ball and the impact gained 1.7 % of the energy)."""

    def __init__(self, body, master, restitution: float = 0.0, margin=None):
        super().__init__(body, master, restitution, margin)
        if self.dim != 3:
            raise InputError("MortarContact3D is 3D; 2D solids take MortarContact")

    def _pairs(self, xs: np.ndarray, xm: np.ndarray):
        """(slave triangle, master triangle) pairs whose centroids are within 1.25 × the
        margin plus both triangles' reach, kept while no node has moved an eighth of the
        margin."""
        if (pairs := self._kept_pairs(xs, xm)) is not None:
            return pairs
        ts, tm = xs[self.facets], xm[self.master_facets]
        cs, cm = ts.mean(axis=1), tm.mean(axis=1)
        rs = np.max(np.linalg.norm(ts - cs[:, None], axis=2), axis=1)
        rm = np.max(np.linalg.norm(tm - cm[:, None], axis=2), axis=1)
        r = 1.25 * self.margin + rs.max() + rm.max()
        found = cKDTree(cs).sparse_distance_matrix(cKDTree(cm), r, output_type="ndarray")
        i, j = found["i"].astype(int), found["j"].astype(int)
        # each pair within the margin plus its own triangles' reach (graded meshes)
        apart = found["v"] - rs[i] - rm[j]
        keep = apart <= 1.25 * self.margin
        return self._keep_search(xs, xm, i[keep], j[keep], apart[keep])

    def _local(self, q: np.ndarray, derivatives: bool = True):
        """Entries: the Gauss points of the overlaps of the slave triangles with the master
        triangles projected onto them along the slave normal (module docstring). Returns the
        slave triangles e, z (P, 112) = (18 coordinates, the moments Σ w Φ_i λ_k and
        Σ w Φ_i μ_k (18), the covered fraction, the gradients (3 × 18) through the dual
        functions of a partly covered triangle — zeros without ``derivatives`` — Σ w λ_k
        (3), and ∂ ln(fade)/∂z (18) of the entries on the whole triangle's duals), the dofs
        (P, 18) and the slave nodes' positions."""
        xs, xm = self.positions(q)
        e, f = self._near(xs, xm, *self._pairs(xs, xm))
        if len(e) == 0:  # no pair near (a free flight): no clipping
            dofs = self._global_dofs(self.facets[e], self.master_facets[f])
            return e, np.zeros((0, 112)), dofs, xs
        ts, tm = xs[self.facets[e]], xm[self.master_facets[f]]
        u, v = ts[:, 1] - ts[:, 0], ts[:, 2] - ts[:, 0]
        N = np.cross(u, v)
        n = N / np.linalg.norm(N, axis=1)[:, None]
        Nm = np.cross(tm[:, 1] - tm[:, 0], tm[:, 2] - tm[:, 0])
        r = tm - ts[:, None, 0]  # (P, 3 master vertices, 3)
        depth = np.einsum("pkd,pd->pk", r, n).mean(axis=1)
        facing = np.einsum("pd,pd->p", n, Nm) < -FACING * np.linalg.norm(Nm, axis=1)
        near = np.flatnonzero(facing & (depth >= -self.margin) & (depth < 3.0 * self.margin))
        e, f, ts, tm, u, v, n, r = (
            e[near],
            f[near],
            ts[near],
            tm[near],
            u[near],
            v[near],
            n[near],
            r[near],
        )
        fade, dfade = _faded(depth[near] / self.margin, u, v, n, r, self.margin)
        fade, dfade = _turned(fade, dfade, u, v, n, tm)
        # the master vertices' (λ₂, λ₃) in the slave triangle (orthogonal projection)
        uu, uv, vv = (np.einsum("pd,pd->p", a, b) for a, b in ((u, u), (u, v), (v, v)))
        ru, rv = np.einsum("pkd,pd->pk", r, u), np.einsum("pkd,pd->pk", r, v)
        det = (uu * vv - uv * uv)[:, None]
        plane = np.stack([(vv[:, None] * ru - uv[:, None] * rv) / det,
                          (uu[:, None] * rv - uv[:, None] * ru) / det], axis=2)  # fmt: skip
        # the projected master triangles whose bounding box misses the slave triangle
        # (λ₂, λ₃ ≥ 0, λ₂ + λ₃ ≤ 1) do not overlap it: left out before the clipping
        total = plane.sum(axis=2)
        meets = (plane.max(axis=1) >= 0.0).all(axis=1) & (total.min(axis=1) <= 1.0)
        e, f, ts, tm, n, plane = e[meets], f[meets], ts[meets], tm[meets], n[meets], plane[meets]
        u, v, fade, dfade = u[meets], v[meets], fade[meets], dfade[meets]
        pair, lam, w = clipped_points(plane)
        w = w * fade[pair]
        # the dual functions of partly covered triangles, those of the covered part
        # (mortar_cover), with their derivatives through the overlaps' vertices
        weight = np.bincount(pair, w, len(e))
        area = element_measures(xs, self.facets)
        covered = self._covered(pair, w, lam, len(e)) * area[e, None]
        needed = triangles_taking_part(
            self.element_rows, e, weight, covered, area, self.taking_part
        )
        if self._held is not None:  # (a held row keeps its covered part's dual functions)
            needed = needed | self._held[self.element_rows].any(axis=1)
        part, A, extra, drop = covered_duals(
            e, ts, tm, u, v, plane, weight, needed, derivatives, (fade, dfade)
        )
        w = np.where(drop[pair], 0.0, w)
        x = np.einsum("pk,pkd->pd", lam, ts[pair])
        _, mu, _ = meet_triangles(x, n[pair], tm[pair], np.inf)
        # the points' moments per pair, Σ w Φ_i λ_k and Σ w Φ_i μ_k: the integrands are
        # linear in λ at fixed vertices (mortar_facets.facet_pair_integrals)
        phi = w[:, None] * (4.0 * lam - 1.0)
        if part.any():
            which = np.full(len(e), -1)
            which[part] = np.arange(part.sum())
            at = np.flatnonzero(part[pair])
            phi[at] = w[at, None] * np.einsum("pjk,pk->pj", A[which[pair[at]]], lam[at])
        gradient = np.zeros((len(e), 54))
        gradient[part] = extra.reshape(-1, 54)
        values = np.stack([phi[:, :, None] * lam[:, None, :], phi[:, :, None] * mu[:, None, :]],
                          axis=1).reshape(-1, 18)  # fmt: skip
        flat = (pair[:, None] * 18 + np.arange(18)).ravel()
        moments = np.bincount(flat, values.ravel(), 18 * len(e)).reshape(-1, 2, 3, 3)
        weight = np.bincount(pair, w, len(e))
        keep = np.flatnonzero(weight > 0.0)
        covered = self._covered(pair, w, lam, len(e))
        z = np.concatenate(
            [ts[keep].reshape(-1, 9), tm[keep].reshape(-1, 9), moments[keep].reshape(-1, 18),
             weight[keep, None], gradient[keep], covered[keep],
             np.where(part[:, None], 0.0, dfade / fade[:, None])[keep]], axis=1
        )  # fmt: skip
        ee, ff = e[keep], f[keep]
        return ee, z, self._global_dofs(self.facets[ee], self.master_facets[ff]), xs

    def _values(self, q: np.ndarray):
        """The entries' values for :meth:`gaps` (no derivatives)."""
        e, z, _, xs = self._local(q, derivatives=False)
        jets, coverage, dual, _ = self._integrate(e, z, None)
        return e, jets, coverage, dual, xs

    @staticmethod
    def _covered(pair, w, lam, P: int) -> np.ndarray:
        """Σ w λ_k (P, 3): the pairs' ∫_C N_k dA as fractions of the slave triangle's area."""
        flat = (3 * pair[:, None] + np.arange(3)).ravel()
        return np.bincount(flat, (w[:, None] * lam).ravel(), 3 * P).reshape(P, 3)

    def _integrate(self, e, z, hessian):
        """Jets of the ends' weighted gaps, coverage (the fraction of the slave triangle the
        pair covers), covered dual weights (P, 3) and the moments and areas of the pairs."""
        jets = facet_pair_integrals(z, hessian)
        if hessian is not None:  # the derivatives through the covered-part dual functions
            extra = z[:, 37:91].reshape(-1, 3, 18)
            ratio = z[:, 94:112]  # ∂ ln(fade)/∂z of the entries with the whole triangle's duals
            for k, jet in enumerate(jets):
                jet.g = jet.g + extra[:, k] + jet.v[:, None] * ratio
        ts = z[:, :9].reshape(-1, 3, 3)
        area = 0.5 * np.linalg.norm(np.cross(ts[:, 1] - ts[:, 0], ts[:, 2] - ts[:, 0]), axis=1)
        moments = z[:, 18:36].reshape(-1, 2, 3, 3)
        # ∫_C N_i dA, equal summed over a triangle's pairs to ∫_C Φ_i dA (biorthogonality)
        dual = z[:, 91:94] * area[:, None]
        return jets, z[:, 36], dual, (moments, area)

    def _slip_weights(self, quad, k: int) -> np.ndarray:
        """Weights (P, 6) of the local nodes' motion in end k's slip: Σ w Φ_k λ_i A on the
        slave triangle's nodes, −Σ w Φ_k μ_i A on the master triangle's."""
        moments, area = quad
        return np.concatenate([moments[:, 0, k], -moments[:, 1, k]], axis=1) * area[:, None]


def _faded(d, u, v, n, r, margin: float):
    """The pairs' weights, 1 up to a mean master depth ``d`` (in margins) of 2 and falling to
    0 at 3 as t² (3 − 2 t), t = 3 − d, so that a pair enters and leaves the weighted gaps
    with their value and slope continuous, and their gradients (P, 18) in the pair's local
    coordinates (slave a, b, c, master 1-3): ∂d = (r̄⊥·∂N/|N| − n·∂x_a + n·Σ ∂y_k/3)/margin,
    r̄⊥ the mean of ``r`` normal to n."""
    t = np.clip(3.0 - d, 0.0, 1.0)
    N = np.linalg.norm(np.cross(u, v), axis=1)[:, None]
    rbar = r.mean(axis=1)
    rho = rbar - np.einsum("pd,pd->p", rbar, n)[:, None] * n
    gb, gc = np.cross(v, rho) / N, np.cross(rho, u) / N
    grad = np.concatenate([-gb - gc - n, gb, gc, n / 3.0, n / 3.0, n / 3.0], axis=1)
    return t * t * (3.0 - 2.0 * t), (-6.0 * t * (1.0 - t) / margin)[:, None] * grad


TURNED = 0.25
"""Between normals at 90° (n_s·n_m = 0, where a pair starts to face) and at 104.5°
(−n_s·n_m = ``TURNED``) a pair's weight rises from 0 as t²(3 − 2t), t = −n_s·n_m / TURNED,
so that a pair enters and leaves the weighted gaps continuously as its triangles turn: a
block's side face stands at exactly 90° to the face it rests on, and a cut there took its
pairs in and out with every round-off of the normals (the active set cycled and a block laid
on a slab stopped at its second step; docs/explanation/mortar.md, *A face against a face at
90°*). The 2D pairs fade the same way, between 104.5° and 120° (``mortar_segments.TURNED``:
a block's side face there stays out)."""


def _turned(fade, dfade, u, v, n, tm):
    """The pairs' weights ``fade`` (P,) and their gradients ``dfade`` (P, 18) times the facing
    weight φ(c) = t²(3 − 2t), t = min(c / ``TURNED``, 1), c = −n·m of the slave triangle's unit
    normal n (edges u, v) and the master's m (vertices ``tm``): ∂c/∂N = −(I − n nᵀ) m / |N|
    through N = u × v, and the same of the master's."""
    U, V = tm[:, 1] - tm[:, 0], tm[:, 2] - tm[:, 0]
    M = np.cross(U, V)
    Mn = np.linalg.norm(M, axis=1)[:, None]
    m = M / Mn
    c = -np.einsum("pd,pd->p", n, m)
    t = np.clip(c / TURNED, 0.0, 1.0)
    if np.all(t >= 1.0):  # (every pair faces by more than 104.5°: the weights as they were)
        return fade, dfade
    Nn = np.linalg.norm(np.cross(u, v), axis=1)[:, None]
    gN = -(m - np.einsum("pd,pd->p", n, m)[:, None] * n) / Nn
    gM = -(n - np.einsum("pd,pd->p", n, m)[:, None] * m) / Mn
    sb, sc, mb, mc = np.cross(v, gN), np.cross(gN, u), np.cross(V, gM), np.cross(gM, U)
    dc = np.concatenate([-sb - sc, sb, sc, -mb - mc, mb, mc], axis=1)
    phi = t * t * (3.0 - 2.0 * t)
    dphi = np.where(t < 1.0, 6.0 * t * (1.0 - t) / TURNED, 0.0)[:, None] * dc
    return fade * phi, dfade * phi[:, None] + fade[:, None] * dphi
