"""Lemke's complementary pivoting (Lemke 1965; Cottle, Pang & Stone, *The Linear
Complementarity Problem*, 1992, §4.4): z ≥ 0 with w = q + M z ≥ 0 and zᵀw = 0, for a square M
that need be neither symmetric nor regular. Each pivot exchanges one basic variable of the
tableau w − M z − d z₀ = q for its complement, the artificial z₀ (covering vector d = 1)
entering first and the path ending where it leaves; a column with no positive entry (a ray)
ends it without an answer."""

from __future__ import annotations

import numpy as np

__all__ = ["lemke"]


def lemke(M: np.ndarray, q: np.ndarray, max_pivots: int | None = None, rtol: float = 1e-11):
    """(z, pivots) of the linear complementarity problem (M, q), or (None, pivots) where the
    path ends on a ray or exceeds ``max_pivots`` (default 10 n). M and q are scaled to unit
    largest entries first, so that ``rtol`` (a pivot's least entry, relative to its column's
    largest) does not depend on their units."""
    n = len(q)
    if np.all(q >= 0.0):
        return np.zeros(n), 0
    sM = float(np.max(np.abs(M), initial=0.0)) or 1.0
    sq = float(np.max(np.abs(q)))
    T = np.hstack([np.eye(n), -M / sM, -np.ones((n, 1)), q[:, None] / sq])
    basis = np.arange(n)
    row, entering = int(np.argmin(q)), 2 * n
    for pivots in range(1, (max_pivots or 10 * n) + 1):
        leaving = _pivot(T, basis, row, entering)
        if leaving == 2 * n:  # (z₀ left: a complementary basis)
            z = np.zeros(2 * n + 1)
            z[basis] = T[:, -1]
            return np.maximum(z[n : 2 * n], 0.0) * (sq / sM), pivots
        entering = leaving + n if leaving < n else leaving - n
        row = _ratio_test(T, basis, entering, rtol, 2 * n)
        if row is None:
            return None, pivots
    return None, max_pivots or 10 * n


def _pivot(T, basis, row, col) -> int:
    """Pivot the tableau T on (row, col) in place; returns the variable that left."""
    T[row] /= T[row, col]
    factor = T[:, col].copy()
    factor[row] = 0.0
    T -= factor[:, None] * T[row][None, :]
    leaving, basis[row] = int(basis[row]), col
    return leaving


def _ratio_test(T, basis, col, rtol, artificial):
    """The row whose basic variable reaches zero first as ``col`` enters (the artificial
    variable preferred among ties: it ends the path); None on a ray."""
    a = T[:, col]
    positive = a > rtol * float(np.max(np.abs(a), initial=0.0))
    if not positive.any():
        return None
    ratios = np.full(len(a), np.inf)
    ratios[positive] = np.maximum(T[positive, -1], 0.0) / a[positive]
    least = ratios.min()
    ties = np.flatnonzero(ratios <= least + 1e-12 * max(least, 1e-300))
    last = ties[basis[ties] == artificial]
    return int(last[0] if last.size else ties[0])
