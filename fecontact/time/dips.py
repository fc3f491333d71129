r"""Contacts that close and open again inside one step: a gap open at both ends of the step
whose path dips below zero between them (a ball whose apex grazes a ceiling, a corner that
brushes an obstacle at the turn of its path).

Both ends of the step are admissible, so the end-of-step treatment never sees the contact:
the ball's apex 1e-6 m beyond the ceiling at h = 1e-3 s passed through it without an
impact, and its rebound √(2 g 1e-6)(1 + e) = 6.6e-3 m/s was lost (3.6e-3 m of height 0.55 s
later). The cubic Hermite interpolant of the gap that locates closings
(:mod:`fecontact.time.localize`) shows the dip: its minimum in the step is below the gap
tolerance. The contact is then located as a closing on [0, s_m], s_m the interpolant's
minimum, the end of the bracket its value there.

Scanned on models of rigid bodies and point masses only (:func:`scans_dips`, decided once
per run), whose gaps between the ends of a step follow the Hermite cubic to O(h⁴) (exactly
for a constant force): a flexible body's node at ωh ≈ 1 does not, and a dip read from it is
not its path.
"""

from __future__ import annotations

import numpy as np

from .hermite import hermite_root

__all__ = ["dip_closings", "hermite_minimum", "may_dip", "scans_dips"]


def scans_dips(model) -> bool:
    """Whether a localized run of ``model`` scans its steps for dips: rigid bodies and point
    masses only (module docstring)."""
    return not (model.continuum or model.slender)


def may_dip(g0: np.ndarray, g1: np.ndarray, low: float, reach: float) -> np.ndarray:
    """Per contact: whether its gap, ``g0`` at the start of the step and ``g1`` at its end,
    open at both (above ``low``, m) and within ``reach`` (m; the detection margin) of the
    obstacle at both, may dip below zero inside the step: the rows whose slopes are read."""
    return (g0 > low) & (g1 > low) & (g0 < reach) & (g1 < reach)


def hermite_minimum(g0, s0, g1, s1) -> tuple[np.ndarray, np.ndarray]:
    """(s_m, p(s_m)): the interior local minimum s_m ∈ (0, 1) of the cubic Hermite p with
    p(0) = g0, p'(0) = s0, p(1) = g1, p'(1) = s1 (arrays), and its value; s_m = 1 and p(1)
    where p has none inside the step."""
    d = g1 - g0
    c2, c3 = 3.0 * d - 2.0 * s0 - s1, s0 + s1 - 2.0 * d
    # p' = 3 c3 s² + 2 c2 s + s0: its roots in the stable form (c3 ≈ 0 for a constant force,
    # where the quadratic formula cancels: the root is then c/q = −s0 / 2c2)
    a, b = 3.0 * c3, 2.0 * c2
    disc = np.maximum(b * b - 4.0 * a * s0, 0.0)
    q = -0.5 * (b + np.copysign(np.sqrt(disc), b))
    with np.errstate(divide="ignore", invalid="ignore"):  # (a zero divisor: 2, outside)
        roots = np.stack([np.where(q != 0.0, s0 / q, 2.0), np.where(a != 0.0, q / a, 2.0)])
    # the minimum: p'' = 2 c2 + 6 c3 s > 0, inside (0, 1)
    inside = (roots > 0.0) & (roots < 1.0) & (2.0 * c2 + 6.0 * c3 * roots > 0.0)
    s = np.where(inside, roots, 1.0).min(axis=0)
    return s, ((c3 * s + c2) * s + s0) * s + g0


def dip_closings(g0, s0, g1, s1, depth: float):
    """(which, τ, slope, s_m, p(s_m)) of the rows whose Hermite gap (``g0``, ``g1`` at the
    step's ends, less the aim; slopes ``s0``, ``s1`` in s) dips below −``depth`` (m) inside
    the step: τ the first root of the interpolant in (0, s_m), its slope there in s, and the
    bracket's closed end s_m with the interpolant's value."""
    s_m, p_m = hermite_minimum(g0, s0, g1, s1)
    which = (s_m < 1.0) & (p_m < -depth)
    if not which.any():
        return which, None, None, None, None
    s_m, p_m = s_m[which], p_m[which]
    g0, s0, g1, s1 = g0[which], s0[which], g1[which], s1[which]
    # the cubic on [0, s_m] scaled to [0, 1] is the Hermite cubic of its own end data
    d = g1 - g0
    c2, c3 = 3.0 * d - 2.0 * s0 - s1, s0 + s1 - 2.0 * d
    end_slope = ((3.0 * c3 * s_m + 2.0 * c2) * s_m + s0) * s_m
    u, slope = hermite_root(g0, s0 * s_m, p_m, end_slope)
    return which, u * s_m, slope / s_m, s_m, p_m


def near_dips(model, st, g1: np.ndarray, opts, least: float | None = None) -> bool:
    """Whether a step from ``st`` whose trial ends with the gaps ``g1`` (``least`` their
    smallest, if known) has a contact that :func:`may_dip`, where the run scans for dips
    (``opts.dips``)."""
    reach = opts.detection_margin * model.length
    if not (opts.dips and g1.size):
        return False
    # (every gap beyond the reach: most steps of a flight, decided by one comparison)
    if (g1.min() if least is None else least) >= reach:
        return False
    g0 = st.gaps if st.gaps.size == g1.size else model.contacts.gaps(st.q)
    low = opts.tol_gap * model.length
    return bool(may_dip(g0, g1, low, reach).any())


def with_dips(contacts, st, phases, left: float, F, near, g0, aim: float, tol: float, found):
    """``found`` (rows, τ, slopes in s, sloped, (s_end, p_end)) of a step's closings, None
    for none, with the rows ``near`` (a mask) whose Hermite gap over ``left`` (s) dips below
    −``tol`` (m) appended (:func:`dip_closings`; ``aim``: the gap the closing aims at)."""
    rows = near.nonzero()[0]
    if not rows.size:
        return found
    _, G0 = contacts.jacobian(st.q, rows)
    G1 = G0 if contacts.affine else contacts.jacobian(phases.q, rows)[1]
    s0, s1 = left * (G0 @ st.v[F]), left * (G1 @ phases.v[F])
    g1 = phases.g_tilde[rows] - aim
    which, tau, slope, s_m, p_m = dip_closings(g0[rows] - aim, s0, g1, s1, tol + aim)
    if not which.any():
        return found
    dipped = (rows[which], tau, slope, np.ones(tau.size, dtype=bool), (s_m, p_m))
    if found is None:
        return dipped
    merged = [np.concatenate(pair) for pair in zip(found[:4], dipped[:4], strict=True)]
    return (*merged, tuple(np.concatenate(pair) for pair in zip(found[4], dipped[4], strict=True)))
