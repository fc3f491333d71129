"""Singular value decompositions that do not stop where LAPACK's divide and conquer does.

NumPy's ``svd`` and ``lstsq`` use LAPACK's divide-and-conquer drivers (gesdd, gelsd), which
on some finite, well-scaled matrices report that their iteration did not converge: on a box
lying flat on a rubber cube with friction, the 78 × 78 Jacobian of a Coulomb solve
(entries 1e-11 to 2e-5, rank 70) stopped gesdd, and the bidiagonal QR iteration of gesvd
decomposed it. There the decomposition is taken again by the QR drivers (gesvd, gelss),
and the caller counts it; a matrix that holds a NaN or an inf, or that neither driver
decomposes, raises :class:`SVDFailure`, a ``RuntimeError`` that the solvers turn into a
failed step."""

from __future__ import annotations

import numpy as np
import scipy.linalg

__all__ = ["SVDFailure", "lstsq", "svd"]


class SVDFailure(RuntimeError):
    """Neither LAPACK driver decomposed the matrix (or it is not finite)."""


def _failure(a: np.ndarray, what: str) -> SVDFailure:
    finite = bool(np.isfinite(a).all())
    kind = "did not converge" if finite else "met a NaN or inf entry"
    return SVDFailure(f"{what} of a {a.shape[0]} × {a.shape[1]} matrix {kind}")


def svd(a, full_matrices: bool = True):
    """(U, s, Vᵀ, fell_back) of ``a``: NumPy's (gesdd), or where that does not converge
    gesvd's, ``fell_back`` True then."""
    a = np.asarray(a, dtype=float)
    try:
        return (*np.linalg.svd(a, full_matrices=full_matrices), False)
    except np.linalg.LinAlgError:
        if not np.isfinite(a).all():
            raise _failure(a, "singular value decomposition") from None
    try:
        out = scipy.linalg.svd(a, full_matrices=full_matrices, lapack_driver="gesvd")
    except (np.linalg.LinAlgError, ValueError):
        raise _failure(a, "singular value decomposition") from None
    return (*out, True)


def lstsq(a, b, rcond: float | None = None):
    """(x, fell_back): the minimum-norm least-squares solution of a x = b (singular values
    below ``rcond`` of the largest taken as zero; None: machine precision times the larger
    dimension), NumPy's (gelsd), or where that does not converge gelss's."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    try:
        return np.linalg.lstsq(a, b, rcond=rcond)[0], False
    except np.linalg.LinAlgError:
        if not (np.isfinite(a).all() and np.isfinite(b).all()):
            raise _failure(a, "least-squares solve") from None
    cond = np.finfo(float).eps * max(a.shape) if rcond is None else rcond
    try:
        x = scipy.linalg.lstsq(a, b, cond=cond, lapack_driver="gelss")[0]
    except (np.linalg.LinAlgError, ValueError):
        raise _failure(a, "least-squares solve") from None
    return x, True
