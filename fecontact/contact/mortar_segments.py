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
need no linearisation (Popp, Gee & Wall 2009). On a segment the master covers in part they
are those of the covered part (:mod:`~fecontact.contact.mortar_duals`), which move with it.

Everything is written once in :class:`~fecontact.contact.dual_numbers.Jet` arithmetic over
the 12 local coordinates z = (x_p, x_a, x_b, x_c, y_1, y_2) (16 with the master nodes that
bound the covered part): the gradients and Hessians of g̃ — through the normals, the
projections, the moving overlap bounds, the dual functions and the Jacobian — are exact.
The projection ξ of a master node solves a quadratic: its root nearest the segment is found
in closed form, then one step of Chebyshev's method in Jet arithmetic from it gives
its exact first and second derivatives (those of the implicit function).
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet
from .mortar_duals import FOREIGN, OWN, STANDARD, dual_coefficients

__all__ = ["GAUSS_POINTS", "fade_weight", "segment_pair_integrals", "smooth_step"]

GAUSS_POINTS = 5
"""Gauss points per overlap: exact for the linear patch (a quadratic integrand); on curved
surfaces the rational projection is integrated to well below the discretization error."""

FACING = 0.5
"""Segments face each other when their normals make more than 120° (n_s·n_m ≤ −½): a side
face meeting the other body at a corner does not take the contact of the face below it."""

TURNED = 0.25
"""Beyond 120° a pair's weight φ falls as t²(3 − 2t), t = (−n_s·n_m − TURNED)/(FACING −
TURNED), to 0 at n_s·n_m = −TURNED (104.5°; a block's side face against the face below,
n_s·n_m = 0, stays out): a pair enters and leaves the weighted gaps continuously
(:func:`_faded_overlap`)."""

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
    """Jet points (x_p, x_a, x_b, x_c, y_1, y_2, then the master nodes that bound the slave
    segment's covered part when z has 16 columns) of the local coordinates z (P, 12 or 16);
    a missing neighbour is the reflection of the segment's other end (the segment's own
    normal)."""
    c = Jet.variables(z, hessian)
    xp, xa, xb, xc, *ys = ((c[2 * i], c[2 * i + 1]) for i in range(z.shape[1] // 2))
    ghost_p = _sub(_scale(2.0, xa), xb)
    ghost_c = _sub(_scale(2.0, xb), xa)
    xp = (xp[0].where(has_prev, ghost_p[0]), xp[1].where(has_prev, ghost_p[1]))
    xc = (xc[0].where(has_next, ghost_c[0]), xc[1].where(has_next, ghost_c[1]))
    return xp, xa, xb, xc, *ys


def _project_master_node(xm, xd, nm, nd, y, order):
    """ξ (Jet) of the master node y projected onto the slave segment along n(ξ): the root
    of p(ξ) = c0 + c1 ξ + c2 ξ² = (x(ξ) − y) × n(ξ), x(ξ) = x_m + ξ x_d, n(ξ) = n_m + ξ n_d.

    The root ξ₀ is found in closed form; the derivatives of ξ over z come from one step
    of Chebyshev's method from the constant ξ₀, ξ₀ − u − c2 u²/p′ with u = p/p′, whose
    first and second derivatives at a root are those of the implicit function (``order``
    0: values, 1: gradients, 2: Hessians too)."""
    r = _sub(xm, y)
    c0, c1, c2 = _cross(r, nm), _cross(r, nd) + _cross(xd, nm), _cross(xd, nd)
    with np.errstate(divide="ignore", invalid="ignore"):
        # the root that tends to the linear one, −c0/c1, as c2 → 0, in the form without
        # cancellation; no real root: the node does not project (inf)
        b, disc = c1.v, c1.v * c1.v - 4.0 * c0.v * c2.v
        xi = -2.0 * c0.v / (b + np.where(b < 0.0, -1.0, 1.0) * np.sqrt(disc))
    xi = np.where(np.isfinite(xi), xi, np.inf)
    x0 = np.where(np.isfinite(xi), xi, 0.0)
    if order == 0:
        return c0.constant_like(xi)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = c0 + c1 * x0 + c2 * (x0 * x0)
        inv = (c1 + c2 * (2.0 * x0)).reciprocal()
        u = p * inv
        x = -u if order == 1 else -u - c2 * (u * u) * inv
    x.v = xi  # the root itself: the same value whatever the derivatives carried
    return x


def _overlap(xm, xd, nm, nd, y1, y2, nab, order):
    """The overlap [lo, hi] (Jets, finite) of the master segment's projection with
    [−1, 1], its span hi − lo (0 where not covered), the covered fraction (P,), the
    master node (0: y_1, 1: y_2; −1: clamped at ∓1) whose projection each end is, the
    cosine n_s·n_m of the segments' normals (Jet) and the node of each end unclamped."""
    s1 = _project_master_node(xm, xd, nm, nd, y1, order)
    s2 = _project_master_node(xm, xd, nm, nd, y2, order)
    first = s1.v <= s2.v
    lo, hi = s1.where(first, s2), s2.where(first, s1)
    lo_node, hi_node = np.where(first, 0, 1), np.where(first, 1, 0)
    lo, hi, lo_node, hi_node, lost = _unwrapped(lo, hi, lo_node, hi_node, (xm, xd, nm, nd, y1, y2))
    nodes = (np.where(lo.v > -1.0, lo_node, -1), np.where(hi.v < 1.0, hi_node, -1))
    lo = lo.where(lo.v > -1.0, -1.0)
    hi = hi.where(hi.v < 1.0, 1.0)
    turn = _dot(nab, _segment_normal(y1, y2))
    facing = (turn.v < -TURNED) & ~lost
    with np.errstate(invalid="ignore"):
        coverage = np.where(facing & np.isfinite(s1.v + s2.v), np.maximum(hi.v - lo.v, 0.0), 0.0)
    coverage = 0.5 * np.nan_to_num(coverage)
    span = (hi - lo).where(np.isfinite(hi.v - lo.v) & (coverage > 0.0), 0.0)
    lo = lo.where(np.isfinite(lo.v), 0.0)
    return lo, hi, span, coverage, nodes, turn, (lo_node, hi_node)


def smooth_step(t: Jet) -> Jet:
    """t²(3 − 2t) of t clipped to [0, 1] (Jet): 0 and 1 with their slopes continuous."""
    s = t * t * (3.0 - t * 2.0)
    with np.errstate(invalid="ignore"):
        return s.where(t.v < 1.0, 1.0).where(t.v > 0.0, 0.0)


def fade_weight(turn: Jet) -> Jet:
    """φ (Jet) of the cosine ``turn`` = n_s·n_m of a pair's normals: 1 up to −``FACING``,
    t²(3 − 2t) in the band, 0 from −``TURNED`` (``TURNED``)."""
    return smooth_step((turn * -1.0 - TURNED) * (1.0 / (FACING - TURNED)))


def _faded_overlap(frame, nab, y1, y2, depth: float, order, integrate: bool = True):
    """The overlap of the master segment (y1, y2) on the slave segment (``frame`` = x_m,
    x_d, n_m, n_d; ``nab`` its normal) as :func:`_overlap`, shrunk to φ of its span
    (``TURNED``) toward the end that is the projection of the master node nearer the slave
    segment's line ((y − x_m)·n smaller: the contact zone's side, where the neighbouring
    master segment faces more; the two nodes' distances differ by more than 0.86 of the
    segment's length within the band, so the side cannot change while φ < 1). As φ falls
    to 0 the pair's integral, its coverage and the end of the covered part it bounds (and
    with them the dual functions of the other pairs on the segment) go continuously to
    their values without it. A pair whose mean gap over its whole overlap is below
    −``depth`` is dropped. Returns (lo, hi, coverage, nodes, (ξ, w J, g_N w J) at the Gauss
    points, fading (P,): 0 < φ < 1), or (lo, hi) alone without ``integrate``."""
    lo, hi, span, coverage, nodes, turn, ids = _overlap(*frame, y1, y2, nab, order)
    fading = (coverage > 0.0) & (turn.v > -FACING)
    if not fading.any():  # (most pairs: the overlap and its integral as they are)
        if not integrate:
            return lo, hi
        xi, gap, wJ = _integration(frame, y1, y2, lo, span, coverage)
        return _kept(lo, hi, coverage, nodes, (xi, gap, wJ), depth, fading)
    if integrate:  # (whether behind, from the values over the whole overlap)
        plain = _integration(*_plain((frame, y1, y2, lo, span)), coverage)
        behind = _behind(plain[1], plain[2], depth)
        coverage, fading = np.where(behind, 0.0, coverage), fading & ~behind
    phi = fade_weight(turn)
    reach = [(y[0].v - frame[0][0].v) * nab[0].v + (y[1].v - frame[0][1].v) * nab[1].v
             for y in (y1, y2)]  # fmt: skip
    near = np.where(reach[0] <= reach[1], 0, 1)
    toward_lo = (ids[0] == near) & (ids[1] != near)
    part = span * phi
    lo, hi = (lo.where(toward_lo, hi - part).where(fading, lo),
              (lo + part).where(toward_lo, hi).where(fading, hi))  # fmt: skip
    if not integrate:
        return lo, hi
    nodes = (np.where(fading & ~toward_lo, ids[0], nodes[0]),
             np.where(fading & toward_lo, ids[1], nodes[1]))  # fmt: skip
    coverage = np.where(fading, coverage * phi.v, coverage)
    points = _integration(frame, y1, y2, lo, part.where(fading, span), coverage)
    return _kept(lo, hi, coverage, nodes, points, np.inf, fading & (coverage > 0.0))


def _plain(x):
    """``x`` (a Jet, or tuples of them) without derivatives."""
    return Jet(x.v, None, None) if isinstance(x, Jet) else tuple(_plain(c) for c in x)


def _behind(gap: Jet, wJ: Jet, depth: float) -> np.ndarray:
    """The pairs (P,) whose mean gap over the Gauss points (P G) is below −``depth``."""
    P, G = len(gap.v) // GAUSS_POINTS, GAUSS_POINTS
    with np.errstate(invalid="ignore"):
        return (gap.v * wJ.v).reshape(P, G).sum(1) < -depth * wJ.v.reshape(P, G).sum(1)


def _kept(lo, hi, coverage, nodes, points, depth: float, fading):
    """:func:`_faded_overlap`'s answer, the pairs behind (:func:`_behind`) dropped."""
    xi, gap, wJ = points
    behind = _behind(gap, wJ, depth)
    if behind.any():
        coverage = np.where(behind, 0.0, coverage)
        wJ = wJ.where(~np.repeat(behind, GAUSS_POINTS), 0.0)
    return lo, hi, coverage, nodes, (xi, wJ, gap * wJ), fading


def _integration(frame, y1, y2, lo, span, coverage):
    """ξ, g_N (m) and w J (m) (Jets, P G) at the Gauss points of the overlaps [lo,
    lo + span] (0 where ``coverage`` is 0): see :func:`segment_pair_integrals`."""
    xm, xd, nm, nd = frame
    d = _sub(y2, y1)
    coef = (_cross(_sub(y1, xm), d), _cross(xd, d), _cross(nm, d), _cross(nd, d),
            _dot(nm, nm), _dot(nm, nd), _dot(nd, nd), _dot(xd, xd).sqrt() * span)  # fmt: skip
    G, P = GAUSS_POINTS, len(coverage)
    keep = np.repeat(coverage > 0.0, G)
    A, B, C, D, E, F, H, Jspan = (c.repeat(G) for c in coef)
    xi = lo.repeat(G) + span.repeat(G) * np.tile(0.5 * (1.0 + _THETA), P)
    nn = E + xi * (F * 2.0 + xi * H)
    gap = (A - xi * B) / (C + xi * D).where(keep, 1.0) * nn.sqrt()
    wJ = (Jspan * np.tile(0.5 * _WEIGHT, P)).where(keep, 0.0)
    return xi, gap.where(keep, 0.0), wJ


def _unwrapped(lo, hi, lo_node, hi_node, frame):
    """The image [lo, hi] of the master segment on the slave's parameter line where it
    passes through infinity: the projection ξ(η) is a rational function of the master point,
    and where the slave's normal field turns parallel to the master line within the segment
    (a far slave segment that sees the master edge-on) the image is the two rays
    (−∞, lo] ∪ [hi, ∞), not [lo, hi]; the midpoint's projection tells which. Of the rays
    the one that meets [−1, 1] is kept ([−1, lo] or [hi, 1]; the master node that bounds
    it kept with it); none or both (a slave segment whose normals sweep across the master
    line at both ends): no overlap (``lost``). Taking [lo, hi] instead made such a pair
    jump from no coverage to full as one projection passed through infinity (measured: two
    disks at 29 m/s, a slave segment 2 cm from the contact, its node's weighted gap from
    +0.43 to −0.93 mm within 1/40 of one Newton update)."""
    xm, xd, nm, nd, y1, y2 = frame
    middle = _scale(0.5, _add(y1, y2))
    mid = _project_master_node(xm, xd, nm, nd, middle, 0).v
    with np.errstate(invalid="ignore"):
        wrapped = np.isfinite(lo.v + hi.v) & ~((lo.v <= mid) & (mid <= hi.v))
    none = np.zeros(len(lo.v), bool)
    if not wrapped.any():
        return lo, hi, lo_node, hi_node, none
    left = wrapped & (lo.v > -1.0) & (hi.v >= 1.0)  # [−1, lo]: lo bounds it from above
    right = wrapped & (hi.v < 1.0) & (lo.v <= -1.0)  # [hi, 1]: hi bounds it from below
    new_lo = lo.where(~left, -1.0).where(~right, hi)
    new_hi = hi.where(~left, lo).where(~right, 1.0)
    new_lo_node = np.where(right, hi_node, lo_node)
    new_hi_node = np.where(left, lo_node, hi_node)
    return new_lo, new_hi, new_lo_node, new_hi_node, wrapped & ~left & ~right


def _covered_end(kind, own, foreign, clamp: float, context):
    """An end of the slave segment's covered part (Jet): ∓1, the entry's own overlap end,
    or the projection of the master node ``foreign`` (``mortar_duals.covered_ends``); where
    ``foreign`` is the two nodes of the master segment whose overlap bounds the part (a
    shrinking overlap, :func:`_faded_overlap`), that overlap's end."""
    end = own.where(kind == OWN, clamp)
    if np.any(kind == FOREIGN):
        frame, nab, depth, order = context
        with np.errstate(divide="ignore", invalid="ignore"):
            if len(foreign) == 2:
                x = _faded_overlap(frame, nab, *foreign, depth, order, False)[int(clamp > 0)]
                return end.where(kind != FOREIGN, x)
            x = _project_master_node(*frame, foreign[0], order)
        inside = (x.v > -1.0) & (x.v < 1.0)
        end = end.where(kind != FOREIGN, x.where(inside, clamp))
    return end


def segment_pair_integrals(z, has_prev, has_next, hessian=None, depth=np.inf, ends=None):
    """Weighted-gap contributions of P (slave segment, master segment) pairs.

    ``z`` (P, 12): the coordinates (m) of (x_p, x_a, x_b, x_c, y_1, y_2); ``has_prev``,
    ``has_next`` (P,) whether x_p and x_c exist. ``hessian``: None for values only, False
    for gradients, True for gradients and Hessians over z. ``depth`` (m): a master segment
    whose mean gap over the overlap is below −depth lies behind the slave segment, not in
    contact with it (a far part of the master whose segment happens to face it): dropped.
    ``ends``: None for the dual functions of the whole segment, or (kind_lo, kind_hi) (P,)
    from :func:`~fecontact.contact.mortar_duals.covered_ends`: the dual functions are then
    those of the segment's covered part (:mod:`~fecontact.contact.mortar_duals`), whose
    foreign ends are the master nodes in z[:, 12:14] and z[:, 14:16] (z then (P, 16)), or
    the ends of the overlaps of the master segments z[:, 12:16] and z[:, 16:20] (P, 20)
    where an overlap that bounds a covered part may be shrinking (``TURNED``).

    Returns (ga, gb, coverage, quad, ends): the Jets of g̃_a, g̃_b (m²), the fraction of
    the slave segment the master segment covers (P,; 0 where the segments do not face each
    other, ``FACING`` and ``TURNED``, or miss each other), the quadrature of the overlap as
    values — ξ and η (P, G), the weights w J (P, G) in m and the dual coefficients A (P, 2,
    2) — for the slip rows of friction, and (lo, hi, lo_node, hi_node, m1, m2, fading): the
    overlap's ends (P,), the master node each is the projection of (0: y_1, 1: y_2, −1: the
    segment's end; a shrinking end keeps its node), the values of ∫ N_1 g_N ds and
    ∫ N_2 g_N ds over the overlap (m²), and whether the overlap is shrinking (P,).

    At a point ξ, x(ξ) + s n(ξ) lies on the master line y_1 + η d, d = y_2 − y_1, for
    s = (y_1 − x) × d / (n × d); with x(ξ) = x_m + ξ x_d and n(ξ) = n_m + ξ n_d that is
    s = (A − ξ B)/(C + ξ D), A = (y_1 − x_m) × d, B = x_d × d, C = n_m × d, D = n_d × d, and
    g_N = s |n(ξ)|: the per-point work is a few operations on per-pair coefficients.
    """
    xp, xa, xb, xc, y1, y2, *bound = _points(z, hessian, has_prev, has_next)
    nab = _segment_normal(xa, xb)
    na = _unit(_add(_segment_normal(xp, xa), nab))
    nb = _unit(_add(nab, _segment_normal(xb, xc)))
    xm, xd = _scale(0.5, _add(xa, xb)), _scale(0.5, _sub(xb, xa))
    nm, nd = _scale(0.5, _add(na, nb)), _scale(0.5, _sub(nb, na))
    order = 0 if hessian is None else (2 if hessian else 1)
    frame = (xm, xd, nm, nd)
    lo, hi, coverage, nodes, points, fading = _faded_overlap(frame, nab, y1, y2, depth, order)
    xi, wJ, gw = points
    G, P = GAUSS_POINTS, len(z)
    s0, s1 = _sum_gauss(gw, P, G), _sum_gauss(xi * gw, P, G)
    m1, m2 = (s0 - s1) * 0.5, (s0 + s1) * 0.5  # ∫ N_k g_N ds
    if ends is None or not (np.any(ends[0]) or np.any(ends[1])):
        ga, gb, duals = m1 * 2.0 - m2, m2 * 2.0 - m1, np.broadcast_to(STANDARD, (P, 2, 2))
    else:
        # the master nodes bounding the covered part, or the master segments whose
        # overlaps do (z then (P, 20))
        k = len(bound) // 2
        foreign = (bound[:k], bound[k:]) if bound else ((None,), (None,))
        context = (frame, nab, depth, order)
        a = _covered_end(ends[0], lo, foreign[0], -1.0, context)
        b = _covered_end(ends[1], hi, foreign[1], 1.0, context)
        A11, A12, A21, A22 = dual_coefficients(a, b)
        ga, gb = A11 * m1 + A12 * m2, A21 * m1 + A22 * m2
        duals = np.stack([A11.v, A12.v, A21.v, A22.v], axis=1).reshape(P, 2, 2)
    d = _sub(y2, y1)
    eta = _master_parameter(xi.v, xm, xd, nm, nd, y1, d, G)
    quad = (xi.v.reshape(P, G), eta.reshape(P, G), wJ.v.reshape(P, G), duals)
    return ga, gb, coverage, quad, (lo.v, hi.v, *nodes, m1.v, m2.v, fading)


def _master_parameter(xi, xm, xd, nm, nd, y1, d, G):
    """η (values) of the master point met from x(ξ) along n(ξ) at the points ξ (P G,)."""
    rep = [np.repeat(c[k].v, G) for c in (xm, xd, nm, nd, y1, d) for k in range(2)]
    xmx, xmy, xdx, xdy, nmx, nmy, ndx, ndy, y1x, y1y, dx, dy = rep
    x = (xmx + xi * xdx - y1x, xmy + xi * xdy - y1y)
    n = (nmx + xi * ndx, nmy + xi * ndy)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = (x[0] * n[1] - x[1] * n[0]) / (dx * n[1] - dy * n[0])
    return np.where(np.isfinite(eta), eta, 0.0)


def _sum_gauss(f: Jet, P: int, G: int) -> Jet:
    """Σ over the G Gauss points of each of the P pairs."""
    h = None if f.h is None else f.h.reshape(P, G, *f.h.shape[1:]).sum(axis=1)
    g = None if f.g is None else f.g.reshape(P, G, f.g.shape[1]).sum(axis=1)
    return Jet(f.v.reshape(P, G).sum(axis=1), g, h)
