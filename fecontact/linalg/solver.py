"""The linear solver of one run: which sparse solver factorizes its matrices, the near-null
space that AMG interpolates, the AMG hierarchies kept per sparsity pattern, and the counts of
the work done. A run owns one (:class:`LinearSolver`), so that two runs in one process, in
two threads say, neither share nor mix any of it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .sparse_solvers import check_sparse_solver, sparse_solver

__all__ = ["Factorizations", "IterativeStats", "LinearSolver"]


@dataclass
class Factorizations:
    """Sparse direct factorizations (SuperLU) and their wall time (s)."""

    count: int = 0
    seconds: float = 0.0


@dataclass
class IterativeStats:
    """Preconditioned CG work: solves (one per right-hand side), of which preconditioned by
    the diagonal, CG iterations, AMG hierarchy setups, fallbacks to the direct factorization,
    and wall time (s) of the setups and of all of it (setups included)."""

    solves: int = 0
    diagonal: int = 0
    iterations: int = 0
    setups: int = 0
    fallbacks: int = 0
    setup_seconds: float = 0.0
    seconds: float = 0.0


class LinearSolver:
    """What :func:`fecontact.linalg.factorize` needs besides the matrix, for one run.

    ``name``: one of ``SPARSE_SOLVERS`` (default: the process default of
    :func:`use_sparse_solver`, read here, once). ``modes`` (n × k): the rigid motions of the
    model on its n free dofs, the near-null space of AMG for the n × n systems (None: pyamg's
    constant). ``factorizations`` and ``iterative`` receive the counts of the work."""

    def __init__(
        self,
        name: str | None = None,
        modes: np.ndarray | None = None,
        factorizations: Factorizations | None = None,
        iterative: IterativeStats | None = None,
    ):
        self.name = sparse_solver() if name is None else check_sparse_solver(name)
        self.modes = modes
        self.factorizations = Factorizations() if factorizations is None else factorizations
        self.iterative = IterativeStats() if iterative is None else iterative
        self.patterns: list = []  # AMG: the sparsity patterns met, most recently used last

    def near_null_space(self, n: int):
        """The modes of size n without their zero columns, or None (pyamg's constant)."""
        modes = self.modes
        if modes is None or modes.shape[0] != n:
            return None
        B = np.ascontiguousarray(modes[:, np.abs(modes).max(axis=0) > 0], dtype=float)
        return B if B.shape[1] else None
