r"""Mortar contact between two 2D solids of quadratic (P2) triangles: curved 3-node segments.

The form is that of :mod:`fecontact.contact.mortar` (dual multipliers, one per slave boundary
node, the weighted gaps g̃_j = ∫ Φ_j g_N ds as the constraints, rows g_j = g̃_j / L_j), on the
quadratic boundary itself: every P2 face node, end or mid, carries a row. Slave segment
(x_a, x_b, x_m), ξ ∈ [−1, 1],

    x(ξ) = N_a x_a + N_b x_b + N_m x_m,   N_{a,b} = ξ (ξ ∓ 1)/2,   N_m = 1 − ξ²,

master segment (y_1, y_2, y_m) likewise in η. The gap is measured along the slave segment's
own normal n(ξ) = (t_y, −t_x), t = x′(ξ) (outward on a counter-clockwise boundary): the
master point y(η) met by the line x(ξ) + s n(ξ) solves (y(η) − x(ξ))·t = 0, a quadratic in
η, and g_N ds = (y(η) − x(ξ))·n(ξ) dξ (|n| = |t| = ds/dξ: no square root). The overlap of
the two segments is bounded by the master's end nodes projected onto the slave curve along
its normals, (x(ξ) − y_i)·x′(ξ) = 0, a cubic in ξ: at its ends the slave normal meets the
master's end, so that the integrand is smooth on the overlap and a 5-point Gauss rule
integrates the patch test's polynomial integrands (degree 4 on a straight face) exactly.

Dual functions: those of the quadratic reference segment, Φ = A N with A = D M⁻¹ from
:func:`fecontact.contact.mortar_p2.dual_coefficients` (on the 3-node segment the end functions
integrate to 1/6 of the length, so no basis transformation is needed). They are biorthogonal
in the measure ds exactly on straight segments (a constant Jacobian) and to the curvature's
order on curved ones; A does not depend on the geometry, so the rows' derivatives need no
derivative of A, and Σ_j Φ_j = 1 holds on any segment: a uniform pressure z_j = p puts on
every node k of either body its consistent P2 load p ∫ N_k ds (ends 1/6, mid 2/3 of a
straight segment's length), the property the patch test needs. L_j = Σ_e ∫_e N_j ds.

Segments face each other when their chords make more than 120°; between 120° and 104.5° a
pair's overlap shrinks to 0 as on linear segments (``mortar_segments.TURNED``), so that a pair
enters and leaves the weighted gaps continuously as the bodies turn. A pair deep behind
(its mean gap below −margin) leaves likewise, by a weight on its points, and so does a pair
far in front (above +margin): a far master segment in the fade band, its overlap clamped at
the slave segment's end with no facing neighbour to take the rest over, put a kink into a
row that the smooth step's Newton iterates jumped across (two P2 disks at 29 m/s).
A node's own gap to the other solid's curved segments backs the weighted gaps where a node
sinks between them (:mod:`fecontact.contact.mortar_p2_safeguard`).

A slave segment the master covers in part takes the dual functions biorthogonal on its
covered part (Popp, Seitz, Gee & Wall, CMAME 2013), A = D M⁻¹ with M = ∫_covered N Nᵀ ds
(:func:`~fecontact.contact.mortar_p2.covered_part_gaps`); a node takes part when its covered
weight ∫_covered N_j ds is at least half of its support, as on linear segments.

Linearisation: written once in :class:`~fecontact.contact.dual_numbers.Jet` arithmetic over
the 12 coordinates z = (x_a, x_b, x_m, y_1, y_2, y_m). The projections' values are found by
Newton's method (ξ) or in closed form (η); one step of Chebyshev's method in Jet arithmetic
from the converged value gives their exact first and second derivatives (those of the
implicit function), so the gradients and Hessians of g̃ are exact and Newton's method keeps
its quadratic rate; on a segment covered in part too, the Hessians with the terms coupling
two pairs of the segment (:func:`~fecontact.contact.mortar_p2.covered_part_gaps`).
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet
from .mortar import MortarContact
from .mortar_p2 import QuadraticFacePairs, counted_weights, covered_part_gaps, dual_coefficients
from .mortar_p2_curves import curve_at, curve_foot, curve_meet, quadratic_curve, quadratic_segments
from .mortar_p2_curves import dot as _dot
from .mortar_p2_safeguard import DeepNodeRowsP2
from .mortar_safeguard import safeguard_rows
from .mortar_segments import FACING, GAUSS_POINTS, TURNED, fade_weight, smooth_step

__all__ = [
    "MortarContactP2",
    "p2_segment_integrals",
    "quadratic_segments",
    "segment_shares",
]

_THETA, _WEIGHT = np.polynomial.legendre.leggauss(GAUSS_POINTS)
DUALS = dual_coefficients("segment")[0]
"""A (3, 3) of the reference segment's dual functions Φ = A N, nodes (a, b, m)."""


def segment_shares(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """∫_e N_k ds (faces, 3) of the curved segments ``faces`` (a, b, m) at positions x (m)."""
    xi = _THETA
    N = np.stack(_shape(xi), axis=1)  # (G, 3)
    dN = np.stack([xi - 0.5, xi + 0.5, -2.0 * xi], axis=1)
    t = np.einsum("gk,fkd->fgd", dN, x[faces])
    ds = np.linalg.norm(t, axis=2) * _WEIGHT  # (faces, G)
    return ds @ N


def _shape(xi):
    """(N_a, N_b, N_m) at ξ (Jets or arrays)."""
    return (xi * (xi - 1.0)) * 0.5, (xi * (xi + 1.0)) * 0.5, 1.0 - xi * xi


def _overlap(s1, s2, facing):
    """[lo, hi] ∩ [−1, 1] of the master's end nodes' feet: lo (Jet), its span (Jet, 0 where
    not covered), the covered fraction of the slave segment and the master node (0: y_1,
    1: y_2) whose foot lo is (clamped or not)."""
    first = s1.v <= s2.v
    lo, hi = s1.where(first, s2), s2.where(first, s1)
    lo = lo.where(lo.v > -1.0, -1.0)
    hi = hi.where(hi.v < 1.0, 1.0)
    with np.errstate(invalid="ignore"):
        ok = facing & np.isfinite(s1.v + s2.v)
        coverage = 0.5 * np.where(ok, np.maximum(hi.v - lo.v, 0.0), 0.0)
    span = (hi - lo).where(coverage > 0.0, 0.0)
    return lo.where(np.isfinite(lo.v), 0.0), span, coverage, np.where(first, 0, 1)


def _turn(xa, xb, y1, y2) -> Jet:
    """n_s·n_m of the chords' normals (Jet): the normals are the chords turned alike."""
    cs, cm = (xb[0] - xa[0], xb[1] - xa[1]), (y2[0] - y1[0], y2[1] - y1[1])
    return _dot(cs, cm) * (_dot(cs, cs) * _dot(cm, cm)).sqrt().reciprocal()


def _faded(overlap, turn: Jet, fading: np.ndarray, nodes):
    """The overlap (lo, span, coverage, lo's master node) with the pairs ``fading``
    (``mortar_segments.TURNED``) shrunk to φ of their span toward the foot of the master
    node nearer the slave chord's line (``nodes`` = x_a, x_b, y_1, y_2; within the band the
    two nodes' distances to it differ by at least 0.86 of the master chord, so the side
    cannot change while φ < 1): lo (Jet), span (Jet), coverage."""
    lo, span, coverage, lo_node = overlap
    xa, xb, y1, y2 = ((p[0].v, p[1].v) for p in nodes)
    normal = (xb[1] - xa[1], xa[0] - xb[0])
    reach = [(y[0] - xa[0]) * normal[0] + (y[1] - xa[1]) * normal[1] for y in (y1, y2)]
    toward_lo = lo_node == np.where(reach[0] <= reach[1], 0, 1)
    phi = fade_weight(turn)
    part = span * phi
    lo = lo.where(toward_lo | ~fading, lo + span - part)
    return lo, part.where(fading, span), np.where(fading, coverage * phi.v, coverage)


def _gauss(slave, master, lo, span, keep, order):
    """ξ, x′(ξ), η, g_N ds/dξ and the weights of dξ (Jets, P G) at the Gauss points of the
    overlaps [lo, lo + span] (0 where not ``keep``, P G)."""
    G, P = GAUSS_POINTS, len(keep) // GAUSS_POINTS
    xi = lo.repeat(G) + span.repeat(G) * np.tile(0.5 * (1.0 + _THETA), P)
    x, t = curve_at(tuple(tuple(k.repeat(G) for k in part) for part in slave), xi)
    rep = tuple(tuple(k.repeat(G) for k in part) for part in master)
    eta = curve_meet(rep, x, t, order)
    y, _ = curve_at(rep, eta)
    gds = ((y[0] - x[0]) * t[1] - (y[1] - x[1]) * t[0]).where(keep, 0.0)  # g_N ds/dξ
    w = (span.repeat(G) * np.tile(0.5 * _WEIGHT, P)).where(keep, 0.0)
    return xi, t, eta, gds, w


def _depth_weights(gds: Jet, t, w: Jet, depth: float):
    """The pairs (P,) gone (mean gap ḡ over their points below −2 ``depth`` or above
    +2 ``depth``) and the pairs' weights ψ (Jet, P; None where no pair's ḡ lies in either
    ramp): 1 for |ḡ| up to ``depth``, t²(3 − 2t) of t = (2 depth − |ḡ|)/depth beyond, so
    that a pair leaves continuously as the bodies overlap beyond the margin (a far part of
    the master behind) and as its overlap lies far in front (a far part of the master that
    a faded or clamped overlap would make a kink of)."""
    G = GAUSS_POINTS
    ds = np.sqrt(t[0].v ** 2 + t[1].v ** 2) * w.v
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = (gds.v * w.v).reshape(-1, G).sum(1) / ds.reshape(-1, G).sum(1)
        gone = np.abs(mean) >= 2.0 * depth
        front, ramp = (mean > depth) & ~gone, (np.abs(mean) > depth) & ~gone
    if not ramp.any():  # (most evaluations: every pair whole or gone)
        return gone, None
    P = len(mean)
    measure = _sum_points((t[0] * t[0] + t[1] * t[1]).sqrt() * w, P, G)
    mean = _sum_points(gds * w, P, G) * measure.where(ramp, 1.0).reciprocal()
    mean = (mean * -1.0).where(front, mean)  # −|ḡ|
    psi = smooth_step((mean + 2.0 * depth) * (1.0 / depth))
    return gone, psi.where(ramp, 1.0)


def _shrunk(overlap, cosine: np.ndarray, nodes):
    """The overlap (lo, span, coverage) with the pairs in the fade band (``cosine`` of the
    chords' normals above −``FACING``) shrunk (:func:`_faded`)."""
    lo, span, coverage, _ = overlap
    fading = (coverage > 0.0) & (cosine > -FACING)
    if not fading.any():  # (most pairs: the overlap as it is)
        return lo, span, coverage
    return _faded(overlap, _turn(*nodes), fading, nodes)


def p2_segment_integrals(z: np.ndarray, hessian=None, depth: float = np.inf):
    """Weighted-gap contributions of P (slave segment, master segment) pairs of 3-node
    segments: ``z`` (P, 12) the coordinates (m) of (x_a, x_b, x_m, y_1, y_2, y_m);
    ``hessian`` None (values), False (gradients) or True (Hessians too) over z; ``depth``
    (m): a master segment whose mean gap over the overlap is below −depth lies behind the
    slave segment (a far part of the master facing it): its weight falls to 0 at −2 depth
    (:func:`_depth_weights`).

    Returns (moments, mass_of, coverage, covered, quad): the Jets of m_k = ∫ N_k g_N ds (m²)
    and a function of a mask of the pairs giving their M_kl = ∫ N_k N_l ds (m, 3 × 3) over
    the overlap (the weighted gaps are g̃ = A m,
    :func:`~fecontact.contact.mortar_p2.covered_part_gaps`), the fraction of the slave
    segment the pair covers (P,; 0 where the segments do not face each other,
    ``mortar_segments.FACING`` and ``TURNED``, or miss), ∫ N_k ds over the overlap (P, 3;
    m), and the quadrature as values, ξ, η and the weights of ds (P, G), for the slip rows."""
    c = Jet.variables(z, hessian)
    xa, xb, xm, y1, y2, ym = ((c[2 * i], c[2 * i + 1]) for i in range(6))
    slave, master = quadratic_curve(xa, xb, xm), quadratic_curve(y1, y2, ym)
    order = 0 if hessian is None else (2 if hessian else 1)
    feet = (curve_foot(slave, y1, order), curve_foot(slave, y2, order))
    cosine = _cosine(z)
    overlap = _overlap(*feet, cosine < -TURNED)
    lo, span, coverage = _shrunk(overlap, cosine, (xa, xb, y1, y2))
    G, P = GAUSS_POINTS, len(z)
    keep = np.repeat(coverage > 0.0, G)
    xi, t, eta, gds, w = _gauss(slave, master, lo, span, keep, order)
    ds = np.sqrt(t[0].v ** 2 + t[1].v ** 2) * w.v
    behind, psi = _depth_weights(gds, t, w, depth)
    if behind.any():
        coverage = np.where(behind, 0.0, coverage)
        w = w.where(~np.repeat(behind, G), 0.0)
        ds = np.where(np.repeat(behind, G), 0.0, ds)
    if psi is not None:  # (the moments, M and the coverage of a pair all weighed by ψ)
        w, coverage, ds = w * psi.repeat(G), coverage * psi.v, ds * np.repeat(psi.v, G)
    N = _shape(xi)
    moments = [_sum_points(Nk * (gds * w), P, G) for Nk in N]

    def mass_of(part):  # M_kl of the entries ``part``: points of those entries alone
        at = np.flatnonzero(np.repeat(part, G))
        tt = [c.take(at) for c in t]
        ds_ = ((tt[0] * tt[0] + tt[1] * tt[1]).sqrt() * w.take(at)).where(keep[at], 0.0)
        return _mass([Nk.take(at) for Nk in N], ds_, int(part.sum()), G)

    covered = np.stack([(Nk.v * ds).reshape(P, G).sum(1) for Nk in N], axis=1)
    quad = (xi.v.reshape(P, G), eta.v.reshape(P, G), ds.reshape(P, G))
    return moments, mass_of, coverage, covered, quad


def _cosine(z: np.ndarray) -> np.ndarray:
    """n_s·n_m (P,) of the pairs' normals, the chords turned alike: the segments face each
    other below −``TURNED`` (the fade band's end, ``mortar_segments.TURNED``)."""
    chord_s, chord_m = z[:, 2:4] - z[:, 0:2], z[:, 8:10] - z[:, 6:8]
    size = np.linalg.norm(chord_s, axis=1) * np.linalg.norm(chord_m, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.einsum("pi,pi->p", chord_s, chord_m) / size


def _mass(N, ds: Jet, P: int, G: int):
    """M_kl = ∫ N_k N_l ds per pair (3 × 3 Jets, symmetric)."""
    mass = [[None] * 3 for _ in range(3)]
    for k in range(3):
        for m in range(k, 3):
            mass[k][m] = mass[m][k] = _sum_points(N[k] * N[m] * ds, P, G)
    return mass


def _sum_points(f: Jet, P: int, G: int) -> Jet:
    """Σ over the G points of each of the P pairs."""
    g = None if f.g is None else f.g.reshape(P, G, f.g.shape[1]).sum(axis=1)
    h = None if f.h is None else f.h.reshape(P, G, *f.h.shape[1:]).sum(axis=1)
    return Jet(f.v.reshape(P, G).sum(axis=1), g, h)


class MortarContactP2(QuadraticFacePairs, MortarContact):
    """Dual mortar contact of the quadratic boundary of a 2D P2 :class:`~fecontact.Solid`
    (the slave ``body``) with the quadratic boundary of another P2 solid (the ``master``);
    see the module docstring. One contact per slave boundary node, ends and mid nodes;
    ``restitution`` is Newton's e_N in [0, 1]; ``margin`` (m) the search distance."""

    faces_of, shares_of = staticmethod(quadratic_segments), staticmethod(segment_shares)

    def __init__(self, body, master, restitution: float = 0.0, margin=None):
        super().__init__(body, master, restitution, margin)
        # the nodes' own rows measured to the curved segments: the flat pieces' rows would
        # hold a node resting on a concave (dented) P2 face by the pieces' sagitta
        self.pointwise, self.master_rows = safeguard_rows(self, DeepNodeRowsP2)

    def _integrate(self, e, z, hessian):
        """Jets of the segments' weighted gaps (the dual functions of the covered part on a
        segment covered in part), coverage, covered weights and the quadrature (with each
        entry's dual coefficients and the coupled Hessians of segments covered in part)."""
        moments, mass_of, coverage, covered, quad = p2_segment_integrals(z, hessian, self.margin)
        jets, A, coupled = covered_part_gaps(e, moments, mass_of, coverage, len(self.facets), DUALS)
        covered = counted_weights(e, coverage, covered, len(self.facets))
        return jets, coverage, covered, (*quad, A, coupled)

    def _slip_weights(self, quad, k: int) -> np.ndarray:
        """Weights (P, 6) of the local nodes' motion in end k's slip: ∫ Φ_k N_i ds on the
        slave's nodes, −∫ Φ_k N_i(η) ds on the master's (the projections frozen)."""
        xi, eta, ds, A, _ = quad
        Ns, Nm = np.stack(_shape(xi), axis=2), np.stack(_shape(eta), axis=2)  # (P, G, 3)
        w = np.einsum("pgl,pl->pg", Ns, A[:, k]) * ds
        return np.concatenate([np.einsum("pg,pgi->pi", w, Ns), -np.einsum("pg,pgi->pi", w, Nm)], 1)
