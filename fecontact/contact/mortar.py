r"""Mortar (segment-to-segment) contact between two deformable solids, 2D.

The form chosen: dual mortar with weighted gaps (Wohlmuth 2000; Popp, Gee & Wall, IJNME 2009).
The slave body's boundary (the one with the shorter segments, :func:`finer_first`; the first
body where they are alike) carries one multiplier per node, interpolated by
dual shape functions Φ_j, biorthogonal to the nodal shape functions N_j; the constraint of node
j is its weighted gap

    g̃_j = ∫ Φ_j g_N ds ≥ 0  (m²),

integrated over the slave boundary segments, where g_N is the gap along the interpolated,
averaged slave normal to the master boundary (:mod:`fecontact.contact.mortar_segments`). The
rows handed to the Alart–Curnier laws are g_j = g̃_j / L_j (m), L_j the reference length the
node carries (half of each adjacent slave segment): a positive scaling, so 0 ≤ g_j ⊥ ν_j ≥ 0
is the same complementarity, and gaps, tolerances and the scale p_j keep their units. Biorthog-
onality keeps every multiplier a nodal unknown with its own complementarity — the contact set,
the NSGA position and velocity levels, the smooth contact force and friction take the rows as
they take a node's gap — and the discrete pressure field λ_h = Σ_j z_j Φ_j has nodal values

    z_j = λ_j / (L_j t)  (Pa),

λ_j the normal force of row j (N) and t the thickness of the 2D body (m).

Partly covered segments: where the master covers only a part [a, b] of a slave segment (the
edge of the contact zone; on a coarse boundary, a vertex meeting a vertex) the dual functions
are those biorthogonal on [a, b] (Popp, Seitz, Gee & Wall, CMAME 2013;
:mod:`fecontact.contact.mortar_duals`): a gap field linear on the segment then weighs in with
its own nodal value and a positive weight. The dual functions of the whole segment would weigh
the covered part alone with their lobes of both signs: on two octagons meeting vertex to
vertex, the vertex read a gap of +4 mm while 4 mm deep inside the other disk.

Linearisation: the rows' gradients G_j = ∂g_j/∂q and curvatures ∇²g_j are exact, from a
second-order forward differentiation of the integral (:mod:`fecontact.contact.dual_numbers`):
through the averaged normals, the projections, the moving bounds of the overlaps, the dual
functions of partly covered segments and the segment Jacobian. This is the consistent
linearisation of Popp, Gee & Wall (2009) obtained without deriving its terms by hand, so the
position correction keeps Newton's quadratic rate. Two P2 solids meet on their quadratic
segments themselves (:mod:`fecontact.contact.mortar_p2_segments`); a P2 solid against a P1
one is taken with its boundary split through the mid nodes into linear segments.

Contact rows are the slave boundary nodes. The master covers a part of a node's segments
(where the slave normals meet master segments facing them); a node takes part when the
covered part carries at least half of the shape-function weight of its covered segments from
the node to their farthest covered point, Σ_e ∫_covered N_j ds ≥ ½ Σ_e ∫_{x_j}^{far} N_j ds:
a node whose segments are covered only at their far ends would read a gap extrapolated from
there, and a node inside the covered part always takes part (a segment counted whole, the
node at a contact zone's edge left it as its outer segment began to be covered: from a
sliver of it, W_j / Σ_e |e|/2 fell to |e_1| / (|e_1| + |e_2|), below ½ where the inner
segment is compressed). Other rows report g = +inf with a zero gradient. A master segment
whose mean gap over its overlap is deeper than the margin behind the slave segment is a far
part of the master that happens to face it, not a contact partner, and is left out. One
whose normal turns from the slave's by less than 120° is left out gradually: its overlap
shrinks to nothing by 104.5° (``mortar_segments.TURNED``), so that the rows stay continuous
as it leaves. The search keeps the (slave, master) segment pairs whose midpoints are within
the detection margin plus both segment lengths, refreshed when a node has moved by more than
an eighth of the margin; a value-only pass drops the pairs that do not overlap before the
differentiated one.

Friction: the slip row of node j is the weighted relative motion t_j·∫ Φ_j (ẋ − ẏ) ds / L_j
along the slave node's tangent t_j, with the projections frozen over the step.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError
from .dual_numbers import Jet
from .mortar_duals import CLAMPED, FOREIGN, covered_ends, dual_coefficients
from .mortar_interface import MortarInterface, element_measures, linear_faces
from .mortar_segments import GAUSS_POINTS, segment_pair_integrals

__all__ = ["MortarContact", "finer_first"]


ALIKE = 1e-9
"""Relative difference of two mean segment lengths below which the boundaries count as alike
(the coordinates' round-off moves a length by about 1e-16 of it)."""


def finer_first(a, b):
    """(slave, master) of two 2D solids: the one whose boundary segments are shorter on
    average first, ``a`` where they are alike. The weighted gaps integrate the master's
    distance over the slave's segments with the slave's dual functions: from the coarser
    side a vertex reads less than its distance to the finer boundary's curvature (two disks
    of 8 and 5 cm, 20 mm against 6.2 mm segments, 2 mm apart: −0.63 mm), from the finer
    side its distance (1.96 mm). Mortar methods put the multipliers on the finer side
    (Wohlmuth 2000)."""

    def mean_segment(body):
        return float(np.mean(element_measures(body.X, linear_faces(body))))

    # "Alike" up to round-off: equal meshes placed at other angles measure their segments
    # a few ulps apart, and a strict comparison turned the scene's rotation into a choice of
    # side (a square on an equal block rotated 0.25 rad took the other side and left with
    # 7 % of its impact speed sideways). Meshes meant to differ differ by far more than 1e-9.
    return (b, a) if mean_segment(b) < (1.0 - ALIKE) * mean_segment(a) else (a, b)


def _neighbours(facets: np.ndarray):
    """For each segment (a, b) of an oriented boundary, the node before a and after b along
    the boundary (−1: none)."""
    n = facets.max() + 1
    ending, starting = np.full(n, -1), np.full(n, -1)
    ending[facets[:, 1]] = np.arange(len(facets))
    starting[facets[:, 0]] = np.arange(len(facets))
    e_prev, e_next = ending[facets[:, 0]], starting[facets[:, 1]]
    prev = np.where(e_prev >= 0, facets[np.maximum(e_prev, 0), 0], -1)
    nxt = np.where(e_next >= 0, facets[np.maximum(e_next, 0), 1], -1)
    return prev, nxt


def _tangent_of(X: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unit tangents (X_b − X_a)/|X_b − X_a| (zero where a or b is −1)."""
    t = X[b] - X[a]
    norm = np.linalg.norm(t, axis=1)
    ok = (a >= 0) & (b >= 0) & (norm > 0.0)
    return np.where(ok[:, None], t / np.where(ok, norm, 1.0)[:, None], 0.0)


class MortarContact(MortarInterface):
    """Dual mortar contact of the boundary of a 2D :class:`~fecontact.Solid` (the slave
    ``body``) with the boundary of another (the ``master``); see the module docstring.

    One contact per slave boundary node (``size``), with the weighted gap g_j (m);
    ``restitution`` is Newton's e_N in [0, 1]; ``margin`` (m) the search distance (default:
    the integrator's detection distance). Both directions are covered by one interface:
    the master's nodes cannot enter the slave either, to the discretization's accuracy.
    """

    def __init__(self, body, master, restitution: float = 0.0, margin=None):
        super().__init__(body, master, restitution, margin)
        if self.dim != 2:
            raise InputError("MortarContact is 2D; 3D solids take MortarContact3D")
        prev, nxt = _neighbours(self.facets)
        # a corner sharper than 60° (the faces of a block) splits the normal field: there each
        # segment keeps its own normal, so that a face's gap is measured along its normal
        X, f = body.X, self.facets
        t = _tangent_of(X, f[:, 0], f[:, 1])
        smooth_prev = np.einsum("ij,ij->i", t, _tangent_of(X, prev, f[:, 0])) > 0.5
        smooth_next = np.einsum("ij,ij->i", t, _tangent_of(X, f[:, 1], nxt)) > 0.5
        self.has_prev, self.has_next = (prev >= 0) & smooth_prev, (nxt >= 0) & smooth_next
        self.local_nodes = np.stack(
            [np.where(self.has_prev, prev, f[:, 0]), *f.T,
             np.where(self.has_next, nxt, f[:, 1])], axis=1
        )  # fmt: skip

    def _pairs(self, xs: np.ndarray, xm: np.ndarray):
        """(slave segment, master segment) pairs near each other (module docstring)."""
        if (pairs := self._kept_pairs(xs, xm)) is not None:
            return pairs
        fs, fm = self.facets, self.master_facets
        cs, cm = 0.5 * (xs[fs[:, 0]] + xs[fs[:, 1]]), 0.5 * (xm[fm[:, 0]] + xm[fm[:, 1]])
        ls = np.linalg.norm(xs[fs[:, 1]] - xs[fs[:, 0]], axis=1)
        lm = np.linalg.norm(xm[fm[:, 1]] - xm[fm[:, 0]], axis=1)
        r = 1.25 * self.margin + ls.max() + lm.max()
        found = cKDTree(cs).sparse_distance_matrix(cKDTree(cm), r, output_type="ndarray")
        e, f = found["i"].astype(int), found["j"].astype(int)
        return self._keep_search(xs, xm, e, f, found["v"] - 0.5 * (ls[e] + lm[f]))

    def _overlapping(self, q: np.ndarray):
        """The slave nodes' positions, and the candidate segment pairs that overlap: their
        slave segments e, local slave and master nodes, local coordinates z (P, 12) and the
        results of the value-only pass that selected them (``segment_pair_integrals``)."""
        xs, xm = self.positions(q)
        e, f = self._near(xs, xm, *self._pairs(xs, xm))
        sn, mn = self.local_nodes[e], self.master_facets[f]
        z = np.concatenate([xs[sn], xm[mn]], axis=1).reshape(len(e), 12)
        if len(e) == 0:  # no pair near (a free flight): no integrals
            nothing, none, empty = Jet(np.zeros(0), None, None), np.zeros((0, GAUSS_POINTS)), e
            ends = (empty * 0.0, empty * 0.0, empty, empty, empty * 0.0, empty * 0.0, empty > 0)
            return xs, xm, e, sn, mn, z, (nothing, nothing, np.zeros(0), (none, none), ends)
        # the candidates that do not overlap contribute nothing: left out before the
        # differentiated integrals, by a value-only pass that also gives the overlaps' ends
        prior = segment_pair_integrals(z, self.has_prev[e], self.has_next[e], None, self.margin)
        keep = prior[2] > 0.0
        ga, gb, coverage, (xi, eta, wJ, _), ends = prior
        prior = (ga.take(keep), gb.take(keep), coverage[keep], (xi[keep], wJ[keep]),
                 tuple(x[keep] for x in ends))  # fmt: skip
        return xs, xm, e[keep], sn[keep], mn[keep], z[keep], prior

    def _local(self, q: np.ndarray):
        """The slave segments e of the segment pairs that overlap, their local coordinates z
        (P, 14, 18 or 22: the 12 of the pair, the master nodes that bound the slave
        segment's covered part when another pair's nodes do, or the master segments of
        those pairs when a pair's overlap shrinks (``mortar_segments.TURNED``), then how each
        end is found) and global dofs (P, 12, 16 or 20), and the slave nodes' positions."""
        xs, xm, e, sn, mn, z, prior = self._overlapping(q)
        lo, hi, lo_node, hi_node, _, _, fading = prior[4]
        kinds = covered_ends(e, lo, hi, lo_node, hi_node, len(self.facets))
        kind_lo, kind_hi, src_lo, src_hi = kinds
        if np.any(kind_lo == FOREIGN) or np.any(kind_hi == FOREIGN):
            shrinking = ((kind_lo == FOREIGN) & fading[src_lo]) | (
                (kind_hi == FOREIGN) & fading[src_hi]
            )
            if shrinking.any():  # an end that a shrinking overlap bounds: its master segment
                bound = np.concatenate([mn[src_lo], mn[src_hi]], axis=1)
            else:
                bound = np.stack([mn[src_lo, np.maximum(lo_node[src_lo], 0)],
                                  mn[src_hi, np.maximum(hi_node[src_hi], 0)]], axis=1)  # fmt: skip
            z = np.concatenate([z, xm[bound].reshape(len(e), -1)], axis=1)
            mn = np.concatenate([mn, bound], axis=1)
        z = np.concatenate([z, kind_lo[:, None], kind_hi[:, None]], axis=1)
        return e, z, self._global_dofs(sn, mn), xs

    def _values(self, q: np.ndarray):
        """The entries' values for :meth:`gaps`, from the value-only pass that selects them:
        the dual functions of each segment's covered part applied to its ∫ N_k g_N ds (the
        ends of the covered part are the overlaps' own ends; the same values as
        :meth:`_integrate` gives)."""
        xs, _, e, _, _, _, (ga, gb, coverage, (xi, wJ), ends) = self._overlapping(q)
        if len(e) == 0:  # no pair near: every row +inf (``_gap_values``)
            return e, [ga, gb], coverage, np.zeros((0, 2)), xs
        lo, hi, lo_node, hi_node, m1, m2, _ = ends
        kind_lo, kind_hi, src_lo, src_hi = covered_ends(e, lo, hi, lo_node, hi_node,
                                                        len(self.facets))  # fmt: skip
        if np.any(kind_lo) or np.any(kind_hi):
            a = Jet(np.where(kind_lo == CLAMPED, -1.0, lo[src_lo]), None, None)
            b = Jet(np.where(kind_hi == CLAMPED, 1.0, hi[src_hi]), None, None)
            A11, A12, A21, A22 = dual_coefficients(a, b)
            m1, m2 = Jet(m1, None, None), Jet(m2, None, None)
            ga, gb = A11 * m1 + A12 * m2, A21 * m1 + A22 * m2
        covered = np.stack([((0.5 - 0.5 * xi) * wJ).sum(1), ((0.5 + 0.5 * xi) * wJ).sum(1)], 1)
        return e, [ga, gb], coverage, covered, xs

    def _integrate(self, e, z, hessian):
        """Jets of the ends' weighted gaps, coverage, covered weights ∫ N_k ds (P, 2) and
        the quadrature (ξ, η, w J, A) of the pairs."""
        ends = (z[:, -2].astype(int), z[:, -1].astype(int))
        ga, gb, coverage, quad, _ = segment_pair_integrals(
            z[:, :-2], self.has_prev[e], self.has_next[e], hessian, self.margin, ends
        )
        xi, _, wJ, _ = quad
        covered = np.stack([((0.5 - 0.5 * xi) * wJ).sum(1), ((0.5 + 0.5 * xi) * wJ).sum(1)], 1)
        return [ga, gb], coverage, covered, quad

    def _slip_weights(self, quad, k: int) -> np.ndarray:
        """Weights (P, 6) of the local nodes' motion in end k's slip: ∫ Φ_k N_i over the
        slave's ends, −∫ Φ_k N_i over the master's (the projections frozen)."""
        xi, eta, wJ, A = quad
        w = (A[:, k, :1] * 0.5 * (1.0 - xi) + A[:, k, 1:] * 0.5 * (1.0 + xi)) * wJ
        zero = np.zeros(len(xi))
        return np.stack(
            [zero, (w * 0.5 * (1.0 - xi)).sum(1), (w * 0.5 * (1.0 + xi)).sum(1), zero,
             -(w * (1.0 - eta)).sum(1), -(w * eta).sum(1)], axis=1
        )  # fmt: skip
