"""Linear algebra seam: one ``factorize(A) -> solve`` and assembly into a fixed pattern.

Small systems (a few hundred unknowns) are faster dense: LAPACK's LU costs microseconds where
sparse slicing and ``splu`` cost a millisecond. Larger ones use SuperLU with a fill-reducing
ordering. Element matrices are scattered into a sparsity pattern computed once per model, so
every assembly is a single ``np.bincount``.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["DENSE_LIMIT", "Pattern", "factorize"]

DENSE_LIMIT = 120
"""Systems with at most this many unknowns are assembled and factorized dense (measured
here: LU of a banded beam matrix costs the same dense or with SuperLU at about 130
unknowns, dense being 20x cheaper at 15 and sparse 5x cheaper at 300)."""


_getrf, _getrs = sla.get_lapack_funcs(("getrf", "getrs"), (np.zeros(1),))


def factorize(A):
    """Return ``solve(b)`` applying A⁻¹ to a vector or to the columns of a matrix.

    Raises ``np.linalg.LinAlgError`` if A is singular.
    """
    if sp.issparse(A):
        try:
            lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as err:
            raise np.linalg.LinAlgError(str(err)) from None
        return lambda b: lu.solve(np.asarray(b, dtype=float))
    # LAPACK directly: the scipy wrappers cost more than the factorization of small systems
    lu, piv, info = _getrf(A)
    if info != 0:
        raise np.linalg.LinAlgError(f"singular matrix (LAPACK getrf info {info})")

    def solve(b):
        x, _ = _getrs(lu, piv, b)
        return x

    return solve


class Pattern:
    """Scatter of element matrices with global dofs ``edofs`` (E, d) into the free×free matrix.

    ``free_index`` maps every global dof to its row among the free dofs, or −1 if it is fixed.
    The result is a dense array when there are at most ``DENSE_LIMIT`` free dofs, else CSR with a
    structure computed once here.
    """

    def __init__(self, edofs: np.ndarray, free_index: np.ndarray, n_free: int):
        r = free_index[edofs][:, :, None]
        c = free_index[edofs][:, None, :]
        r, c = np.broadcast_arrays(r, c)
        self.keep = ((r >= 0) & (c >= 0)).ravel()
        rows, cols = r.ravel()[self.keep], c.ravel()[self.keep]
        self.n = n_free
        self.dense = n_free <= DENSE_LIMIT
        flat = rows.astype(np.int64) * n_free + cols
        if self.dense:
            self.pos, self.size = flat, n_free * n_free
            return
        keys, self.pos = np.unique(flat, return_inverse=True)
        self.size = len(keys)
        self.indices = (keys % n_free).astype(np.int32)
        self.indptr = np.searchsorted(keys // n_free, np.arange(n_free + 1)).astype(np.int32)

    def assemble(self, values: np.ndarray):
        """Sum the element matrices ``values`` (E, d, d) into the pattern."""
        data = np.bincount(self.pos, values.reshape(-1)[self.keep], minlength=self.size)
        if self.dense:
            return data.reshape(self.n, self.n)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))
