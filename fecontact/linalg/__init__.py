"""Linear algebra: one ``factorize(A) -> solve`` seam for every system the steppers solve,
dense below ``DENSE_LIMIT`` unknowns and sparse (SuperLU, or PARDISO when installed) above."""

from .direct import DENSE_LIMIT, SPARSE_FACTORIZATIONS, SYMMETRIC_PIVOT, Pattern, factorize
from .low_rank import UnitColumns, low_rank_solver
from .sparse_solvers import SPARSE_SOLVERS, sparse_solver, use_sparse_solver

__all__ = [
    "DENSE_LIMIT",
    "SPARSE_FACTORIZATIONS",
    "SPARSE_SOLVERS",
    "SYMMETRIC_PIVOT",
    "Pattern",
    "UnitColumns",
    "factorize",
    "low_rank_solver",
    "sparse_solver",
    "use_sparse_solver",
]
