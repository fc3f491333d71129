"""Linear algebra seam: one ``factorize(A) -> solve`` and assembly into a fixed pattern.

Small systems (a few hundred unknowns) are faster dense: LAPACK's LU costs microseconds where
sparse slicing and ``splu`` cost a millisecond. Larger ones use SuperLU with a fill-reducing
ordering, or the sparse Cholesky factorization (:mod:`.cholesky`) for symmetric positive
definite ones when it is installed. Without it, symmetric matrices (the mass, the iteration
matrix β′M + K_t, the metric H − C) are factorized in SuperLU's symmetric mode: a minimum
degree ordering of A + Aᵀ applied to rows and columns alike, and the diagonal taken as pivot
unless it is below ``SYMMETRIC_PIVOT`` of its column. With the default threshold of 1, row
interchanges destroy the symmetric ordering and the fill grows by an order of magnitude on 3D
iteration matrices (docs/explanation/speed.md). Element matrices are scattered into a
sparsity pattern computed once per model, so every assembly is a single ``np.bincount``.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .cholesky import MIN_UNKNOWNS, cholesky_available, cholesky_factorize
from .iterative import amg_factorize
from .solver import LinearSolver
from .sparse_solvers import pardiso_factorize

__all__ = ["DENSE_LIMIT", "SYMMETRIC_PIVOT", "Pattern", "factorize"]

DENSE_LIMIT = 120
"""Systems with at most this many unknowns are assembled and factorized dense: below it the
dense LU of a banded beam matrix costs less than SuperLU's analysis and slicing
(``benchmarks/speed.py`` measures the crossing)."""


SYMMETRIC_PIVOT = 1e-2
"""Relative size below which SuperLU's symmetric mode leaves a diagonal pivot for a row
interchange: never for the positive definite matrices of linear bodies, a safeguard for the
indefinite tangents of buckling ones."""

_getrf, _getrs = sla.get_lapack_funcs(("getrf", "getrs"), (np.zeros(1),))


def factorize(A, symmetric: bool = False, solver: LinearSolver | None = None, once: bool = False):
    """Return ``solve(b)`` applying A⁻¹ to a vector or to the columns of a matrix.

    ``solver``: the run's :class:`LinearSolver` (the sparse solver, AMG's near-null space and
    hierarchies, the choices of ``"auto"``, and where the work is counted); default a new one
    with the process default sparse solver.

    ``symmetric``: A = Aᵀ (its pattern and values). A symmetric sparse A goes to the sparse
    Cholesky factorization when it is installed (:mod:`.cholesky`; SuperLU's symmetric mode
    otherwise, and for an A that is not positive definite), or to AMG-preconditioned CG with
    the sparse solver ``"amg"``, or to either with ``"auto"`` as the run's measured costs choose
    (:mod:`.choice`; a solver without a run's plan takes the direct path; ``once``: A serves
    one step, a size of a split step, and is weighed over it). Raises
    ``np.linalg.LinAlgError`` if A is singular: here for a factorization, from ``solve`` for
    CG (when its fallback factorization fails).
    """
    if sp.issparse(A):
        solver = LinearSolver() if solver is None else solver
        name, choice = solver.name, solver.choice
        if symmetric and solver.cg:

            def direct():
                return _symmetric_direct(A, solver)

            if name == "amg":
                return amg_factorize(A, direct, solver)
            if choice is not None:  # without a run's plan there are no costs to weigh: direct
                return choice.auto(A, direct, lambda: amg_factorize(A, direct, solver), once)
        if symmetric and name != "superlu":
            return _symmetric_direct(A, solver)
        if name == "pardiso":
            return pardiso_factorize(A)
        return _superlu(A, symmetric, solver)
    # LAPACK directly: the scipy wrappers cost more than the factorization of small systems
    lu, piv, info = _getrf(A)
    if info != 0:
        raise np.linalg.LinAlgError(f"singular matrix (LAPACK getrf info {info})")

    def solve(b):
        x, _ = _getrs(lu, piv, b)
        return x

    return solve


def _symmetric_direct(A, solver: LinearSolver):
    """``solve(b)`` of the symmetric sparse A by the sparse Cholesky factorization when it is
    installed, A has at least ``cholesky.MIN_UNKNOWNS`` rows and is positive definite, else
    by SuperLU's symmetric mode."""
    if A.shape[0] >= MIN_UNKNOWNS and cholesky_available():
        start = time.perf_counter()
        factor = cholesky_factorize(A)
        seconds = time.perf_counter() - start
        refused = factor is None  # not positive definite: SuperLU factorizes it below
        solver.count_factorization(
            "cholesky (not positive definite)" if refused else "cholesky",
            seconds,
            0.0 if refused else factor.memory_mb,
        )
        if factor is not None:
            return factor
    return _superlu(A, True, solver)


def _superlu(A, symmetric: bool, solver: LinearSolver):
    """``solve(b)`` with A factorized by SuperLU (counted by ``solver``)."""
    options = {}
    if symmetric:
        options = {"diag_pivot_thresh": SYMMETRIC_PIVOT, "options": {"SymmetricMode": True}}
    start = time.perf_counter()
    try:
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", **options)
    except RuntimeError as err:
        raise np.linalg.LinAlgError(str(err)) from None
    finally:
        solver.count_factorization("superlu", time.perf_counter() - start)
    return lambda b: lu.solve(np.asarray(b, dtype=float))


class Pattern:
    """Scatter of element matrices into the free×free matrix, with a structure fixed here.

    ``blocks`` lists the element dof arrays (E, d) of the bodies (global dofs); ``free_index``
    maps every global dof to its row among the free dofs, or −1 if it is fixed. ``extra`` (a
    free×free sparse matrix, the mass) joins the structure, so that β′M + K is one sum of data
    arrays. The matrices are dense when there are at most ``DENSE_LIMIT`` free dofs, else CSR.
    """

    def __init__(self, blocks, free_index: np.ndarray, n_free: int, extra=None):
        self.n = n_free
        self.dense = n_free <= DENSE_LIMIT
        flats, self.keep = [], []
        for edofs in blocks:
            # (row, column) of entry (i, j) of every element matrix as row·n + column, made
            # in one int64 array: rows and columns apart cost 3x the memory of large 3D meshes
            fi = free_index[edofs].astype(np.int64)
            keep = ((fi[:, :, None] >= 0) & (fi[:, None, :] >= 0)).ravel()
            flat = (fi[:, :, None] * n_free + fi[:, None, :]).ravel()
            whole = bool(keep.all())
            self.keep.append(None if whole else keep)
            flats.append(flat if whole else flat[keep])
        extra = sp.coo_matrix(extra) if extra is not None else sp.coo_matrix((n_free, n_free))
        flats.append(extra.row.astype(np.int64) * n_free + extra.col)
        allflat = np.concatenate(flats)
        if self.dense:
            pos, self.size = allflat, n_free * n_free
        else:
            keys, pos = np.unique(allflat, return_inverse=True)
            self.size = len(keys)
            self.indices = (keys % n_free).astype(np.int32)
            self.indptr = np.searchsorted(keys // n_free, np.arange(n_free + 1)).astype(np.int32)
        bounds = np.cumsum([0] + [len(f) for f in flats])
        self.pos = [pos[a:b] for a, b in zip(bounds[:-1], bounds[1:], strict=True)]
        self.extra = np.bincount(self.pos[-1], extra.data, minlength=self.size)
        self._csc = None  # (the CSC order of the entries, found on first use)

    def assemble(self, values) -> np.ndarray:
        """Data array of the sum of the element matrices ``values`` (one (E, d, d) per block)."""
        data = np.zeros(self.size)
        for v, keep, pos in zip(values, self.keep, self.pos, strict=False):
            if v.size:  # (a block whose entries are all free is taken whole, unmasked)
                v = v.reshape(-1) if keep is None else v.reshape(-1)[keep]
                data += np.bincount(pos, v, minlength=self.size)
        return data

    def matrix(self, data: np.ndarray):
        """The matrix of a data array: dense (n, n) or CSR."""
        if self.dense:
            return data.reshape(self.n, self.n)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    def csc(self, A):
        """``A.tocsc()``: the same matrix, entries and order; where A is a CSR matrix of this
        structure (:meth:`matrix`), by the column order of its entries found once, not by
        sorting them again at every factorization."""
        if self.dense or not sp.issparse(A) or A.format != "csr" or A.indptr is not self.indptr:
            return A.tocsc()
        if self._csc is None:
            rows = np.repeat(np.arange(self.n, dtype=np.int32), np.diff(self.indptr))
            order = np.lexsort((rows, self.indices))  # by column, then row
            counts = np.bincount(self.indices, minlength=self.n)
            indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)
            self._csc = order, rows[order], indptr
        order, indices, indptr = self._csc
        return sp.csc_matrix((A.data[order], indices, indptr), shape=(self.n, self.n))
