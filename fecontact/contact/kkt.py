r"""The multipliers of the active rows: k (G_A Y) μ = b, Y = H⁻¹G_Aᵀ (the Schur complement of
the bordered Newton system), solved by LU where the rows are independent and by least squares
where they are redundant (counted in ``ContactStats.least_squares``).

One redundancy is exact and known in advance: two segments of a beam clipped to their shared
node give that node's row twice, the same gradient and the same gap. In a run whose model can
produce such rows (``ContactStats.merge_duplicates``, decided once), duplicate rows are merged
before the solve: the group takes one multiplier, solved on one row, and each of its rows
holds an equal share (counted in ``ContactStats.duplicate_rows``). The rows' summed force
Σ G_jᵀ k μ_j is the group's, every row keeps a positive multiplier on a closed gap (its
Alart–Curnier residual zero, and the next active set keeps both rows, as the law's
symmetric answer), and each row's Coulomb bound is its share of the node's pressure.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg.lapack import dgetrf, dgetrs

from .stats import ContactStats

__all__ = ["duplicate_groups", "kkt_multipliers", "schur_multipliers"]

# rows of one node reached from two segments clipped to it: ξ = 0 and ξ = 1 are exact shape
# weights, so the point, normal and gap come out of the same products and sums up to their
# order, a few ulps of the values (measured: bit for bit on the disk on a strip, 29 solves);
# rows that differ by a geometric amount (a row signed the other way at a kink, a point not
# clipped) differ far beyond 64 ulps and stay apart
ROUND_OFF = 64 * np.finfo(float).eps


def kkt_multipliers(GA, Y, rhs, k, stats: ContactStats | None = None, rcond: float = 1e-10):
    """Solve k (G_A Y) μ = rhs for the active multipliers (least squares if redundant, and
    counted in ``stats.least_squares``). In a run whose rows can be redundant up to round-off
    (``stats.minimum_norm``) a pivot below ``rcond`` of the largest counts as singular."""
    return schur_multipliers(k * (GA @ Y), rhs, stats, rcond, GA)[0]


def schur_multipliers(S, rhs, stats, rcond=1e-10, GA=None):
    """:func:`kkt_multipliers` of the Schur matrix S = k G_A Y (``GA``: the active rows, read
    where ``stats.merge_duplicates``), and whether S was singular (least squares)."""
    if GA is not None and stats is not None and stats.merge_duplicates and len(rhs) > 1:
        groups = duplicate_groups(S, GA, rhs)
        if groups is not None:
            return _merged(S, rhs, stats, rcond, groups)
    return _solved(S, rhs, stats, rcond)


def duplicate_groups(S, GA, rhs):
    """Each active row's representative, the first row it duplicates (itself if none), or
    None where no two rows are duplicates: the same gradient row and the same right-hand
    side (so the same gap) within ``ROUND_OFF``. Candidates first from S = k G_A Y, m × m:
    duplicates have S_ij = S_ii = S_jj; the gradient rows then confirm them."""
    d = np.diagonal(S)
    tol = ROUND_OFF * np.abs(d)
    near = (np.abs(S - d[:, None]) <= tol[:, None]) & (np.abs(S - d[None, :]) <= tol[None, :])
    rows, cols = np.nonzero(np.triu(near, 1))
    if not rows.size:
        return None
    rep = np.arange(len(rhs))
    for i, j in zip(rows, cols, strict=True):  # (i < j, in increasing i: the first leads)
        if rep[j] == j and _same(GA[i], GA[j], rhs[i], rhs[j]):
            rep[j] = rep[i]
    return None if np.all(rep == np.arange(len(rhs))) else rep


def _same(a, b, ra, rb) -> bool:
    """Whether two gradient rows and their right-hand sides agree within ``ROUND_OFF``."""
    scale = max(float(np.max(np.abs(a))), float(np.max(np.abs(b))))
    if np.any(np.abs(a - b) > ROUND_OFF * scale):
        return False
    return abs(ra - rb) <= ROUND_OFF * max(abs(ra), abs(rb))


def _merged(S, rhs, stats, rcond, rep):
    """The multipliers with each group of duplicate rows (``rep``: each row's first) solved
    as its first row, the group's multiplier shared equally among its rows."""
    keep = np.flatnonzero(rep == np.arange(len(rep)))
    stats.duplicate_rows += len(rep) - len(keep)
    mu, singular = _solved(S[np.ix_(keep, keep)], rhs[keep], stats, rcond)
    where = np.searchsorted(keep, rep)
    return mu[where] / np.bincount(where)[where], singular


def _solved(S, rhs, stats, rcond=1e-10):
    """The multipliers of S μ = rhs: LU, or least squares where S is singular (counted);
    and whether it was."""
    if S.shape == (1, 1):  # (one row, most contact phases: getrf and getrs divide, to the bit)
        s = S[0, 0]
        if s != 0.0 and math.isfinite(s) and rcond < 1.0:  # (else the paths below decide)
            return rhs / s, False
    if stats is None or not stats.minimum_norm:
        # (np.linalg.solve's own LAPACK path, getrf and getrs, without its 5 µs of checks
        # on the few rows of a contact step; an exactly zero pivot is its LinAlgError)
        lu, piv, info = dgetrf(S) if S.size else (S, None, 1)
        if info == 0:
            return dgetrs(lu, piv, rhs)[0], False
        if S.size and stats is not None:
            stats.least_squares += 1
        return np.linalg.lstsq(S, rhs, rcond=None)[0], bool(S.size)
    lu, piv, _ = dgetrf(S)  # (LAPACK's getrf and getrs: np.linalg.solve's own path)
    pivots = np.abs(np.diagonal(lu))
    # rows that meet at a concave vertex are redundant up to round-off: an LU would return
    # their round-off amplified by a pivot near zero, the truncated SVD the minimum norm
    if S.size and pivots.min() > rcond * pivots.max():
        return dgetrs(lu, piv, rhs)[0], False
    if stats is not None:
        stats.least_squares += 1
    return np.linalg.lstsq(S, rhs, rcond=rcond)[0], True
