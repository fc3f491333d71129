"""The linear solver of one run: which sparse solver factorizes its matrices, the near-null
space that AMG interpolates, the AMG hierarchies kept per sparsity pattern, the record and
the cost-based choices of ``"auto"`` (:class:`fecontact.linalg.choice.SolverChoice`), and the
counts of the work done. A run owns one (:class:`LinearSolver`), so that two runs in one
process, in two threads say, neither share nor mix any of it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .choice import RunPlan, SolverChoice
from .cholesky import cholesky_available
from .sparse_solvers import amg_available, check_sparse_solver, sparse_solver

__all__ = ["Factorizations", "IterativeStats", "LinearSolver"]


@dataclass
class Factorizations:
    """Sparse direct factorizations (SuperLU and Cholesky) and their wall time (s)."""

    count: int = 0
    seconds: float = 0.0


@dataclass
class IterativeStats:
    """Preconditioned CG work and its wall time."""

    solves: int = 0  # one per right-hand side
    diagonal: int = 0  # of the solves, those preconditioned by the diagonal
    iterations: int = 0  # CG iterations
    setups: int = 0  # AMG hierarchies built
    fallbacks: int = 0  # solves handed to the direct factorization
    setup_seconds: float = 0.0  # wall time of the setups (s)
    seconds: float = 0.0  # wall time of all of it, setups included (s)


class LinearSolver:
    """What :func:`fecontact.linalg.factorize` needs besides the matrix, for one run.

    ``name``: one of ``SPARSE_SOLVERS`` (default: the process default of
    :func:`use_sparse_solver`, read here, once). ``modes`` (n × k): the rigid motions of the
    model on its n free dofs, the near-null space of AMG for the n × n systems (None: pyamg's
    constant). ``factorizations`` and ``iterative`` receive the counts of the work. ``plan``:
    what the run will ask of the solver (:class:`RunPlan`), which ``choice`` (a
    :class:`SolverChoice`, None without a plan) weighs for ``"auto"`` and where it records
    the factorizations by backend and their memory; without a plan ``"auto"`` factorizes.
    ``cg``: whether CG may solve the symmetric systems (``"amg"``, and ``"auto"`` with pyamg
    installed: without it the direct path is its only one, the ladder's included)."""

    def __init__(
        self,
        name: str | None = None,
        modes: np.ndarray | None = None,
        factorizations: Factorizations | None = None,
        iterative: IterativeStats | None = None,
        plan: RunPlan | None = None,
    ):
        self.name = sparse_solver() if name is None else check_sparse_solver(name)
        self.modes = modes
        self.factorizations = Factorizations() if factorizations is None else factorizations
        self.iterative = IterativeStats() if iterative is None else iterative
        self.patterns: list = []  # AMG: the sparsity patterns met, most recently used last
        self.cg = self.name == "amg" or (self.name == "auto" and amg_available())
        self.choice = None
        if plan is not None:
            direct = "superlu" if self.name == "superlu" or not cholesky_available() else None
            self.choice = SolverChoice(
                self.name, plan, direct or "cholesky", cg=self.cg, iterative=self.iterative
            )

    def count_factorization(self, backend: str, seconds: float, memory_mb: float = 0.0):
        """Count a sparse factorization by ``backend`` that took ``seconds`` and whose factor
        holds ``memory_mb`` (0 when the backend does not say)."""
        self.factorizations.count += 1
        self.factorizations.seconds += seconds
        if self.choice is not None:
            self.choice.count_factorization(backend, seconds, memory_mb)

    def near_null_space(self, n: int):
        """The modes of size n without their zero columns, or None (pyamg's constant)."""
        modes = self.modes
        if modes is None or modes.shape[0] != n:
            return None
        B = np.ascontiguousarray(modes[:, np.abs(modes).max(axis=0) > 0], dtype=float)
        return B if B.shape[1] else None
