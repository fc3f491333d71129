r"""Mortar integrals of one slave segment against one master segment (2D, linear segments).

Slave segment (x_a, x_b) with parameter ξ ∈ [−1, 1], x(ξ) = N_a x_a + N_b x_b, N_{a,b} =
(1 ∓ ξ)/2; its nodes carry averaged unit normals n_a = unit(ν(x_p, x_a) + ν(x_a, x_b)) and
n_b = unit(ν(x_a, x_b) + ν(x_b, x_c)), ν(u, w) = ((w − u)_y, −(w − u)_x)/|w − u| the outward
unit normal of a counter-clockwise boundary segment, x_p and x_c the neighbours of a and b
along the slave boundary (a missing neighbour: the segment's own normal). The normal field is
interpolated, n(ξ) = N_a n_a + N_b n_b, and not normalised (only its direction counts).

Master segment (y_1, y_2), y(η) = y_1 + η (y_2 − y_1), η ∈ [0, 1]. Each master node is
projected onto the slave segment along n(ξ): (x(ξ) − y_i) × n(ξ) = 0, a quadratic in ξ. The
overlap [ξ_lo, ξ_hi] is where the two projections and [−1, 1] intersect. At Gauss points of
the overlap the slave point x(ξ) is projected onto the master along n(ξ) (linear in η), and
the gap is g_N(ξ) = (y(η) − x(ξ))·n(ξ)/|n(ξ)| (> 0 open).

The weighted gaps of the two slave nodes (m²) are g̃_k = ∫ Φ_k(ξ) g_N(ξ) J dξ over the
overlap, with the dual (biorthogonal) shape functions of a linear segment, Φ_a = ½ − 3ξ/2,
Φ_b = ½ + 3ξ/2 (∫ Φ_k N_l J dξ = δ_kl ∫ N_l J dξ; Wohlmuth 2000), and J = |x_b − x_a|/2. On
a straight segment J is constant, so the dual functions do not depend on the geometry and
need no linearisation (Popp, Gee & Wall 2009).

Everything is written once in :class:`~fecontact.contact.dual_numbers.Jet` arithmetic over
the 12 local coordinates z = (x_p, x_a, x_b, x_c, y_1, y_2): the gradients and Hessians of
g̃ — through the normals, the projections, the moving overlap bounds and the Jacobian — are
exact. The projection ξ of a master node solves a quadratic: it is found in floating point by
Newton's method, then two more Newton steps in Jet arithmetic starting from the converged
value give its exact first and second derivatives (the Newton map has zero derivative with
respect to ξ at the root).
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet

__all__ = ["GAUSS_POINTS", "segment_pair_integrals"]

GAUSS_POINTS = 5
"""Gauss points per overlap: exact for the linear patch (a quadratic integrand); on curved
surfaces the rational projection is integrated to well below the discretization error."""

FACING = 0.5
"""Segments face each other when their normals make more than 120° (n_s·n_m < −½): a side
face meeting the other body at a corner does not take the contact of the face below it."""

_THETA, _WEIGHT = np.polynomial.legendre.leggauss(GAUSS_POINTS)


def _cross(u, w):
    return u[0] * w[1] - u[1] * w[0]


def _dot(u, w):
    return u[0] * w[0] + u[1] * w[1]


def _sub(u, w):
    return (u[0] - w[0], u[1] - w[1])


def _add(u, w):
    return (u[0] + w[0], u[1] + w[1])


def _scale(c, u):
    return (u[0] * c, u[1] * c)


def _unit(u):
    r = (u[0] * u[0] + u[1] * u[1]).sqrt()
    return (u[0] / r, u[1] / r)


def _segment_normal(u, w):
    t = _sub(w, u)
    return _unit((t[1], -t[0]))


def _points(z: np.ndarray, hessian, has_prev, has_next):
    """Jet points (x_p, x_a, x_b, x_c, y_1, y_2) of the local coordinates z (P, 12); a missing
    neighbour is the reflection of the segment's other end (the segment's own normal)."""
    c = Jet.variables(z, hessian)
    xp, xa, xb, xc, y1, y2 = ((c[2 * i], c[2 * i + 1]) for i in range(6))
    ghost_p = _sub(_scale(2.0, xa), xb)
    ghost_c = _sub(_scale(2.0, xb), xa)
    xp = (xp[0].where(has_prev, ghost_p[0]), xp[1].where(has_prev, ghost_p[1]))
    xc = (xc[0].where(has_next, ghost_c[0]), xc[1].where(has_next, ghost_c[1]))
    return xp, xa, xb, xc, y1, y2


def _projection_coefficients(xa, xb, na, nb, y):
    """c0 + c1 ξ + c2 ξ² = (x(ξ) − y) × n(ξ)."""
    xm, xd = _scale(0.5, _add(xa, xb)), _scale(0.5, _sub(xb, xa))
    nm, nd = _scale(0.5, _add(na, nb)), _scale(0.5, _sub(nb, na))
    r = _sub(xm, y)
    return _cross(r, nm), _cross(r, nd) + _cross(xd, nm), _cross(xd, nd)


def _project_master_node(xa, xb, na, nb, y):
    """ξ (Jet) of the master node y projected onto the slave segment along n(ξ)."""
    c0, c1, c2 = _projection_coefficients(xa, xb, na, nb, y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = -c0.v / c1.v
        for _ in range(30):
            step = (c0.v + xi * (c1.v + xi * c2.v)) / (c1.v + 2.0 * xi * c2.v)
            xi = xi - step
            if np.all(~np.isfinite(step) | (np.abs(step) <= 1e-15 * (1.0 + np.abs(xi)))):
                break
    xi = np.where(np.isfinite(xi), xi, np.inf)
    safe = np.where(np.isfinite(xi), xi, 0.0)
    x = c0.constant_like(safe)
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(2):  # exact first, then second derivatives (module docstring)
            x = x - (c0 + x * (c1 + x * c2)) / (c1 + x * c2 * 2.0)
    x.v = np.where(np.isfinite(xi), x.v, np.inf)
    return x


def segment_pair_integrals(z, has_prev, has_next, hessian=None, depth=np.inf):
    """Weighted-gap contributions of P (slave segment, master segment) pairs.

    ``z`` (P, 12): the coordinates (m) of (x_p, x_a, x_b, x_c, y_1, y_2); ``has_prev``,
    ``has_next`` (P,) whether x_p and x_c exist. ``hessian``: None for values only, False
    for gradients, True for gradients and Hessians over z. ``depth`` (m): a master segment
    whose mean gap over the overlap is below −depth lies behind the slave segment, not in
    contact with it (a far part of the master whose segment happens to face it): dropped.

    Returns (ga, gb, coverage, quad): the Jets of g̃_a, g̃_b (m²), the fraction of the slave
    segment the master segment covers (P,; 0 where the segments do not face each other,
    ``FACING``, or miss each other), and the quadrature of the overlap as values — ξ and η
    (P, G) and the weights w J (P, G) in m — for the slip rows of friction.
    """
    xp, xa, xb, xc, y1, y2 = _points(z, hessian, has_prev, has_next)
    nab = _segment_normal(xa, xb)
    na = _unit(_add(_segment_normal(xp, xa), nab))
    nb = _unit(_add(nab, _segment_normal(xb, xc)))
    s1, s2 = _project_master_node(xa, xb, na, nb, y1), _project_master_node(xa, xb, na, nb, y2)
    lo = s1.where(s1.v <= s2.v, s2)
    hi = s1.where(s1.v > s2.v, s2)
    lo = lo.where(lo.v > -1.0, -1.0)
    hi = hi.where(hi.v < 1.0, 1.0)
    facing = _dot(nab, _segment_normal(y1, y2)).v < -FACING
    coverage = np.where(facing & np.isfinite(s1.v + s2.v), np.maximum(hi.v - lo.v, 0.0), 0.0)
    coverage = 0.5 * np.nan_to_num(coverage)
    G = GAUSS_POINTS
    P = len(z)
    keep = np.repeat(coverage > 0.0, G)
    span = (hi - lo).where(np.isfinite(hi.v - lo.v) & (coverage > 0.0), 0.0)
    lo = lo.where(np.isfinite(lo.v), 0.0)
    theta, weight = np.tile(_THETA, P), np.tile(_WEIGHT, P)
    xi = lo.repeat(G) + span.repeat(G) * (0.5 * (1.0 + theta))
    xa_r = (xa[0].repeat(G), xa[1].repeat(G))
    xb_r = (xb[0].repeat(G), xb[1].repeat(G))
    na_r = (na[0].repeat(G), na[1].repeat(G))
    nb_r = (nb[0].repeat(G), nb[1].repeat(G))
    y1_r = (y1[0].repeat(G), y1[1].repeat(G))
    y2_r = (y2[0].repeat(G), y2[1].repeat(G))
    Na, Nb = (1.0 - xi) * 0.5, (1.0 + xi) * 0.5
    x = _add(_scale(Na, xa_r), _scale(Nb, xb_r))
    n = _add(_scale(Na, na_r), _scale(Nb, nb_r))
    d = _sub(y2_r, y1_r)
    den = _cross(d, n)
    den = den.where(keep, 1.0)
    eta = _cross(_sub(x, y1_r), n) / den
    gap = _dot(_sub(_add(y1_r, _scale(eta, d)), x), n) / _dot(n, n).sqrt()
    J = _dot(_sub(xb_r, xa_r), _sub(xb_r, xa_r)).sqrt() * 0.5
    wJ = J * span.repeat(G) * (0.5 * weight)
    wJ = wJ.where(keep, 0.0)
    gap = gap.where(keep, 0.0)
    behind = (gap.v * wJ.v).reshape(P, G).sum(1) < -depth * wJ.v.reshape(P, G).sum(1)
    if behind.any():
        coverage = np.where(behind, 0.0, coverage)
        wJ = wJ.where(~np.repeat(behind, G), 0.0)
    ga = _sum_gauss((0.5 - 1.5 * xi) * gap * wJ, P, G)
    gb = _sum_gauss((0.5 + 1.5 * xi) * gap * wJ, P, G)
    quad = (xi.v.reshape(P, G), eta.v.reshape(P, G), wJ.v.reshape(P, G))
    return ga, gb, coverage, quad


def _sum_gauss(f: Jet, P: int, G: int) -> Jet:
    """Σ over the G Gauss points of each of the P pairs."""
    h = None if f.h is None else f.h.reshape(P, G, *f.h.shape[1:]).sum(axis=1)
    g = None if f.g is None else f.g.reshape(P, G, f.g.shape[1]).sum(axis=1)
    return Jet(f.v.reshape(P, G).sum(axis=1), g, h)
