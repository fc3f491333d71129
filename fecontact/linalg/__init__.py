"""Linear algebra: one ``factorize(A) -> solve`` seam for every system the steppers solve,
dense below ``DENSE_LIMIT`` unknowns and sparse above: SuperLU, and sparse Cholesky for the
large symmetric positive definite systems when pypardiso is installed; symmetric sparse
systems can go to AMG-preconditioned CG instead, always (``"amg"``) or where the run's
measured costs say so (``"auto"``; ``use_sparse_solver``)."""

from .direct import DENSE_LIMIT, SYMMETRIC_PIVOT, Pattern, factorize
from .low_rank import UnitColumns, low_rank_solver
from .solver import Factorizations, IterativeStats, LinearSolver
from .sparse_solvers import SPARSE_SOLVERS, sparse_solver, use_sparse_solver

__all__ = [
    "DENSE_LIMIT",
    "Factorizations",
    "IterativeStats",
    "LinearSolver",
    "SPARSE_SOLVERS",
    "SYMMETRIC_PIVOT",
    "Pattern",
    "UnitColumns",
    "factorize",
    "low_rank_solver",
    "sparse_solver",
    "use_sparse_solver",
]
