"""The first instant a gap crosses inside a step: the root in s = (t − t_n)/h ∈ (0, 1] of
the cubic Hermite interpolant of the gap from its values and slopes at the step's ends
(:mod:`fecontact.time.localize`)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["hermite_root"]

_GRID = np.linspace(0.0, 1.0, 33)
"""The samples of s at which the first sign change of a Hermite cubic is sought."""
_SAMPLES = _GRID.tolist()
_EPS = float(np.finfo(float).eps)


def hermite_root(g0, s0, g1, s1, samples: int = 32, iterations: int = 30):
    """(s, p'(s)) at the first root s ∈ (0, 1] of the cubic Hermite p with p(0) = g0 > 0,
    p'(0) = s0, p(1) = g1 < 0, p'(1) = s1 (arrays, one per contact): the first sign change
    on ``samples`` intervals, then Newton kept inside it (bisection where it leaves), to
    round-off (p within a few ulps of its largest term of zero, or a Newton step that no
    longer moves s by more than a few ulps)."""
    if g0.size == 1 and samples == _GRID.size - 1:  # (one closing: most located steps)
        found = _hermite_root_one(*(float(x[0]) for x in (g0, s0, g1, s1)), iterations)
        if found is not None:
            return found
    # p(s) = g0 + s0 s + c2 s² + c3 s³, by Horner (a dozen array operations fewer than the
    # Hermite basis: the root of the step's one or few closings costs 15 µs, not 60)
    d = g1 - g0
    c2, c3 = 3.0 * d - 2.0 * s0 - s1, s0 + s1 - 2.0 * d

    def p(s):
        return ((c3 * s + c2) * s + s0) * s + g0

    def dp(s):
        return (3.0 * c3 * s + 2.0 * c2) * s + s0

    grid = _GRID if samples == _GRID.size - 1 else np.linspace(0.0, 1.0, samples + 1)
    values = p(grid[:, None])  # (samples + 1, contacts)
    first = np.argmax(values <= 0.0, axis=0)  # p(1) = g1 < 0: a sign change exists
    a, b = grid[first - 1], grid[first]
    cols = np.arange(first.size)
    pa, pb = values[first - 1, cols], values[first, cols]
    s = a - pa * (b - a) / (pb - pa)  # the chord's root, then Newton
    eps = np.finfo(float).eps
    # round-off of p: a few ulps of its largest term
    big = np.maximum(np.maximum(np.abs(g0), np.abs(g1)), np.maximum(np.abs(s0), np.abs(s1)))
    small = 8.0 * eps * big
    for _ in range(iterations):
        ps = p(s)
        if (np.abs(ps) <= small).all():  # (the method: np.all's wrapper costs as much)
            break
        below = ps <= 0.0
        a, b = np.where(below, a, s), np.where(below, s, b)
        newton = s - ps / dp(s)
        if (np.abs(newton - s) <= 4.0 * eps * s).all():  # (stationary: s is the root)
            s = newton
            break
        s = np.where((newton > a) & (newton < b), newton, 0.5 * (a + b))
    return s, dp(s)


def _hermite_root_one(g0: float, s0: float, g1: float, s1: float, iterations: int):
    """:func:`hermite_root` of one contact in floats, on ``_GRID``: the same operations in
    the same order (so the same root to the bit) without the arrays' overhead, on a ball's
    first closing 40 → 6 µs of its crossing's search; None where a value is not finite
    (NaN and inf: left to the arrays)."""
    d = g1 - g0
    c2, c3 = 3.0 * d - 2.0 * s0 - s1, s0 + s1 - 2.0 * d
    if not all(map(math.isfinite, (g0, s0, g1, s1, c2, c3))):  # (the arrays' own way)
        return None
    values = []
    for s in _SAMPLES:  # (up to the first sign change: the samples after it are not read)
        values.append(((c3 * s + c2) * s + s0) * s + g0)
        if values[-1] <= 0.0:
            break
    first = len(values) - 1 if values[-1] <= 0.0 else 0  # (no sign change: argmax's 0)
    if first == 0:  # (no sign change, or p(0) ≤ 0 outside the contract: every sample)
        values = [((c3 * s + c2) * s + s0) * s + g0 for s in _SAMPLES]
    a, b = _SAMPLES[first - 1], _SAMPLES[first]
    pa, pb = values[first - 1], values[first]
    s = a - pa * (b - a) / (pb - pa)
    eps = _EPS
    small = 8.0 * eps * max(max(abs(g0), abs(g1)), max(abs(s0), abs(s1)))
    for _ in range(iterations):
        ps = ((c3 * s + c2) * s + s0) * s + g0
        if abs(ps) <= small:
            break
        if ps <= 0.0:
            b = s
        else:
            a = s
        newton = s - ps / ((3.0 * c3 * s + 2.0 * c2) * s + s0)
        if abs(newton - s) <= 4.0 * eps * s:
            s = newton
            break
        s = newton if a < newton < b else 0.5 * (a + b)
    return np.array([s]), np.array([(3.0 * c3 * s + 2.0 * c2) * s + s0])
