r"""Conjugate gradients preconditioned by algebraic multigrid (the sparse solver ``"amg"``).

The iteration matrix S_t = β′M + K_t of elastic bodies, the mass M and the metric S_t/β′ are
symmetric positive definite. A sparse LU of a 3D one fills in like n^{4/3} and costs like n²
(53.6 s at 65,856 dofs here, docs/explanation/speed.md), while preconditioned CG costs a few
products with A per iteration and, with smoothed-aggregation AMG (pyamg), about as many iterations
whatever n.

- Preconditioner: the diagonal of A first, AMG once CG needs more than
  ``DIAGONAL_ITERATIONS`` with it. At the wave-resolving steps of the cases β′M dominates and
  A is well conditioned: CG with the diagonal converges in 28–78 iterations, each one product
  with A, while one V-cycle costs 15–17 of them (measured; 5x faster on the 255,552-dof ball
  of ``benchmarks/iterative_speed.py``). At larger steps K_t dominates and the diagonal needs
  hundreds to thousands of iterations, AMG 10–30. The choice is made per sparsity pattern.
- Near-null space of AMG: the rigid motions of the bodies (``LinearSolver.modes``, given by
  the model), which aggregation then interpolates exactly. Measured on the
  24,000-dof cube of ``benchmarks/scaling.py`` at h = 1e-3 and 1e-2 s: 16 and 19 CG
  iterations, against 27 and 52 with a constant per displacement component and 75 and 149
  with one constant.
- Tolerance: ‖b − A x‖ ≤ ``RTOL`` ‖b‖, two decades below the Newton residual tolerance
  (1e-8 of the force scale), so that an inexact solve changes no stopping test; the true
  residual is checked once at the end (CG's recursive one drifts).
- Reuse: a pattern's hierarchy (``CACHE_SIZE`` patterns are kept) serves every matrix with
  that pattern, across Newton iterations and steps. It is rebuilt from the matrix in hand when
  a solve needs ``SETUP_ITERATIONS`` more iterations than it needed when new: a setup costs
  about that many iterations (measured 19–20 at 24,000 and 65,856 dofs), so the next solve
  alone repays it.
- Breakdown: a direction with pᵀAp ≤ 0 (or a nonpositive diagonal) proves A indefinite; then,
  or when CG does not converge in ``MAX_ITERATIONS`` with a hierarchy made for A, the direct
  factorization takes over for A, counted in the run's ``IterativeStats.fallbacks`` (beams'
  tangents after impacts). A hierarchy made for another matrix is first rebuilt for this one.
"""

from __future__ import annotations

import inspect
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

# the relative tolerance of scipy's cg: ``tol`` before SciPy 1.12, ``rtol`` since
_RTOL = "rtol" if "rtol" in inspect.signature(spla.cg).parameters else "tol"

__all__ = [
    "amg_factorize",
]

RTOL = 1e-10
"""Relative residual of every CG solve (module docstring)."""

TRUE_RESIDUAL = 10.0
"""The true residual may exceed ``RTOL`` ‖b‖ by this factor: the recursive residual of CG drifts
from it by about ε κ(A), below 1e-11 for the condition numbers κ ≤ 1e5 of S_t here."""

MAX_ITERATIONS = 200
"""AMG-CG iterations before a solve counts as failed: about seven times the most a fresh
hierarchy needed on the solids measured (29); a system that needs more is cheaper to factorize."""

SETUP_ITERATIONS = 20
"""Extra iterations of one solve, over those of a fresh hierarchy, that trigger a rebuild."""

DIAGONAL_ITERATIONS = 200
"""CG iterations with the diagonal preconditioner after which a pattern moves to AMG for good.
A V-cycle costs 15–17 products with A (measured at 65,856 and 255,552 dofs) and AMG-CG needs
9–29 iterations on the solids here, so that below about 200 iterations the diagonal is the
cheaper preconditioner: it needs 28–78 at the wave-resolving steps of the cases (β′M
dominates), and 317–612 on the 24,000-dof cube at h = 1e-3 and 1e-2 s."""

CACHE_SIZE = 4
"""Sparsity patterns (and their hierarchies) kept: the mass, S_t and the contact metric of a
model fit."""


class _Amg:
    """A smoothed-aggregation hierarchy built from the matrix ``A``, as a preconditioner."""

    def __init__(self, A, solver):
        import pyamg

        start = time.perf_counter()
        ml = pyamg.smoothed_aggregation_solver(
            A, B=solver.near_null_space(A.shape[0]), symmetry="hermitian", improve_candidates=None
        )
        self.precondition = ml.aspreconditioner(cycle="V").matvec
        self.iterations = None  # CG iterations of its first solve
        solver.iterative.setups += 1
        solver.iterative.setup_seconds += time.perf_counter() - start


class _Pattern:
    """A sparsity pattern met before, and the AMG hierarchy of its matrices once the diagonal
    preconditioner did not suffice for one of them."""

    def __init__(self, A):
        self.shape, self.nnz = A.shape, A.nnz
        self.indptr, self.indices = A.indptr, A.indices
        self.amg = None

    def serves(self, A) -> bool:
        """Whether A (a CSR matrix) has this pattern: the same arrays, or equal ones."""
        if A.shape != self.shape or A.nnz != self.nnz:
            return False
        if _address(A.indices) == _address(self.indices) and _address(A.indptr) == _address(
            self.indptr
        ):
            return True  # the pattern arrays are held here: one address is one pattern
        return np.array_equal(A.indptr, self.indptr) and np.array_equal(A.indices, self.indices)


def _address(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


def _pattern(patterns: list, A) -> _Pattern:
    """The pattern of A among ``patterns`` (now the most recently used), or a new one."""
    for entry in patterns:
        if entry.serves(A):
            patterns.remove(entry)
            break
    else:
        entry = _Pattern(A)
    patterns.append(entry)
    del patterns[:-CACHE_SIZE]
    return entry


_CONVERGED, _INDEFINITE, _STALLED = "converged", "indefinite", "stalled"


class AmgSolve:
    """``solve(b)`` with A⁻¹ by preconditioned CG, for a symmetric sparse A; ``direct`` is
    called (once) for the factorization to fall back on; ``solver`` is the run's
    :class:`fecontact.linalg.LinearSolver` (hierarchies, near-null space, counts)."""

    def __init__(self, A, direct, solver):
        self.A = A.tocsr()
        self.solver, self.stats = solver, solver.iterative
        self.pattern = _pattern(solver.patterns, self.A)
        self.direct_factorize, self.direct = direct, None
        self.built = None  # the hierarchy built from this A, if any
        d = self.A.diagonal()
        # a positive diagonal is necessary for A to be positive definite
        self.inverse_diagonal = 1.0 / d if np.all(d > 0.0) else None

    def __call__(self, b):
        if sp.issparse(b):
            b = b.toarray()
        b = np.asarray(b, dtype=float)
        if b.ndim == 1:
            return self._solve(b)
        x = np.empty_like(b)
        for j in range(b.shape[1]):
            x[:, j] = self._solve(b[:, j])
        return x

    def _solve(self, b):
        if self.direct is not None:
            return self.direct(b)
        if not b.any():
            return np.zeros_like(b)
        start = time.perf_counter()
        x = self._iterate(b) if self.inverse_diagonal is not None else None
        self.stats.seconds += time.perf_counter() - start
        if x is None:
            self.stats.fallbacks += 1
            self.direct = self.direct_factorize()
            return self.direct(b)
        self.stats.solves += 1
        return x

    def _iterate(self, b):
        """CG on A x = b: with the diagonal while it suffices for this pattern, then with its
        AMG hierarchy; None when A is not positive definite or CG does not converge."""
        pattern = self.pattern
        if pattern.amg is None:
            dinv = self.inverse_diagonal
            status, x, _ = self._cg(b, lambda r: dinv * r, DIAGONAL_ITERATIONS)
            if status == _CONVERGED:
                self.stats.diagonal += 1
                return x
            if status == _INDEFINITE:
                return None
            self._build()  # the diagonal is not enough for matrices of this pattern
        status, x, its = self._cg(b, pattern.amg.precondition, MAX_ITERATIONS)
        if status == _STALLED and pattern.amg is not self.built:
            self._build()  # a hierarchy of another matrix: make this one's
            status, x, its = self._cg(b, pattern.amg.precondition, MAX_ITERATIONS)
        if status != _CONVERGED:
            return None
        amg = pattern.amg
        if amg.iterations is None:
            amg.iterations = its
        elif its > amg.iterations + SETUP_ITERATIONS:
            self._build()  # for the next solves
        return x

    def _build(self):
        self.pattern.amg = self.built = _Amg(self.A, self.solver)

    def _cg(self, b, precondition, maxiter: int):
        """(status, x, iterations) of CG from x = 0 with the preconditioner ``precondition``
        (r -> z): indefinite when a direction has pᵀAp <= 0, stalled when the preconditioner
        is not positive definite (rᵀz <= 0) or CG has not converged in ``maxiter``."""
        A, count = self.A, [0]

        class Indefinite(Exception):
            pass

        class Stalled(Exception):
            pass

        def matvec(p):
            count[0] += 1
            q = A @ p
            if p @ q <= 0.0:
                raise Indefinite
            return q

        def psolve(r):
            z = precondition(r)
            if r @ z <= 0.0:
                raise Stalled
            return z

        n = A.shape[0]
        op = spla.LinearOperator((n, n), matvec=matvec, dtype=float)
        M = spla.LinearOperator((n, n), matvec=psolve, dtype=float)
        status, x = _STALLED, None
        try:
            x, info = spla.cg(op, b, atol=0.0, maxiter=maxiter, M=M, **{_RTOL: RTOL})
            r = b - A @ x
            if info == 0 and np.sqrt(r @ r) <= TRUE_RESIDUAL * RTOL * np.sqrt(b @ b):
                status = _CONVERGED
        except Indefinite:
            status = _INDEFINITE
        except Stalled:
            pass
        self.stats.iterations += count[0]
        return status, x, count[0]


def amg_factorize(A, direct, solver):
    """``solve(b)`` for a symmetric sparse A (vector or matrix b); ``direct()`` returns the
    direct ``solve`` used when A turns out indefinite or CG does not converge; ``solver`` is
    the run's :class:`fecontact.linalg.LinearSolver`."""
    return AmgSolve(A, direct, solver)
