"""Linear algebra: one ``factorize(A) -> solve`` seam for every system the steppers solve,
dense below ``DENSE_LIMIT`` unknowns and sparse above: SuperLU, and sparse Cholesky for the
large symmetric positive definite systems when pypardiso is installed; symmetric sparse
systems can go to AMG-preconditioned CG instead, always (``"amg"``) or where the run's
measured costs say so (``"auto"``; ``use_sparse_solver``). ``ITERATIVE``,
``SPARSE_FACTORIZATIONS`` and ``set_near_null_space`` are deprecated (:mod:`.legacy`)."""

import dataclasses

from .direct import DENSE_LIMIT, SYMMETRIC_PIVOT, Pattern, factorize
from .legacy import LastRunCounts, deprecated, set_near_null_space
from .low_rank import UnitColumns, low_rank_solver, touched
from .solver import Factorizations, IterativeStats, LinearSolver
from .sparse_solvers import SPARSE_SOLVERS, sparse_solver, use_sparse_solver

__all__ = [
    "DENSE_LIMIT",
    "ITERATIVE",
    "SPARSE_FACTORIZATIONS",
    "Factorizations",
    "IterativeStats",
    "LinearSolver",
    "SPARSE_SOLVERS",
    "SYMMETRIC_PIVOT",
    "Pattern",
    "UnitColumns",
    "factorize",
    "low_rank_solver",
    "set_near_null_space",
    "sparse_solver",
    "touched",
    "use_sparse_solver",
]

# the deprecated counter names: the counts of the calling thread's latest run, by their old keys
_COUNTERS = {
    "ITERATIVE": lambda stats: stats.iterative if stats is not None else IterativeStats(),
    "SPARSE_FACTORIZATIONS": lambda stats: (
        stats.factorizations if stats is not None else Factorizations()
    ),
}


def __getattr__(name: str):
    part = _COUNTERS.get(name)
    if part is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    deprecated(f"fecontact.linalg.{name}", "read the run's StepStats (fecontact.time.simulate)")
    return LastRunCounts(name, lambda stats: dataclasses.asdict(part(stats)))
