r"""Conjugate gradients preconditioned by algebraic multigrid (the sparse solver ``"amg"``).

The iteration matrix S_t = β′M + K_t of elastic bodies, the mass M and the metric S_t/β′ are
symmetric positive definite. A sparse LU of a 3D one fills in like n^{4/3} and costs like n²
(53.6 s at 65,856 dofs here, README *Speed*), while one V-cycle of smoothed-aggregation AMG
(pyamg) costs a few products with A and keeps the CG iterations about constant as n grows.

- Near-null space: the rigid motions of the bodies (:func:`set_near_null_space`, registered
  by the model), which aggregation then interpolates exactly. Measured on the 24,000-dof cube
  of ``benchmarks/scaling.py`` at h = 1e-3 and 1e-2 s: 16 and 19 CG iterations, against
  27 and 52 with a constant per displacement component and 75 and 149 with one constant. At
  the wave-resolving steps of the cases β′M dominates and all three need 7–13.
- Tolerance: ‖b − A x‖ ≤ ``RTOL`` ‖b‖, two decades below the Newton residual tolerance
  (1e-8 of the force scale), so that an inexact solve changes no stopping test; the true
  residual is checked once at the end (CG's recursive one drifts).
- Reuse: a hierarchy is kept per sparsity pattern (``CACHE_SIZE`` of them) and serves every
  matrix with that pattern, across Newton iterations and steps. It is rebuilt from the matrix
  in hand when a solve needs ``SETUP_ITERATIONS`` more iterations than the hierarchy needed
  for its own matrix: a setup costs about that many iterations (measured 19–20 at 24,000 and
  65,856 dofs), so the next solve alone repays it.
- Breakdown: an indefinite matrix shows as a direction with pᵀAp ≤ 0 (or a preconditioned
  residual with rᵀz ≤ 0). Then, or without convergence in ``MAX_ITERATIONS``, a hierarchy
  made for another matrix is rebuilt once; one made for this matrix gives way to the direct
  factorization, counted in ``ITERATIVE["fallbacks"]`` (beams' tangents after impacts).
"""

from __future__ import annotations

import time
import weakref

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["AUTO_DOFS", "ITERATIVE", "amg_factorize", "set_near_null_space"]

RTOL = 1e-10
"""Relative residual of every CG solve (module docstring)."""

TRUE_RESIDUAL = 10.0
"""The true residual may exceed ``RTOL`` ‖b‖ by this factor: the recursive residual of CG drifts
from it by about ε κ(A), below 1e-11 for the condition numbers κ ≤ 1e5 of S_t here."""

MAX_ITERATIONS = 200
"""CG iterations before a solve counts as failed: ten times the most a fresh hierarchy needed on
the solids measured (≤ 20); a system that needs more is cheaper to factorize."""

SETUP_ITERATIONS = 20
"""Extra iterations of one solve, over those of a fresh hierarchy, that trigger a rebuild."""

CACHE_SIZE = 4
"""Hierarchies kept (per pattern): the mass, S_t and the contact metric of a model fit."""

AUTO_DOFS = 5000
"""With the sparse solver ``"auto"``, symmetric systems of at least this many unknowns go to
AMG-CG and smaller ones to SuperLU (crossing measured by ``benchmarks/iterative_speed.py``)."""

ITERATIVE = {
    "solves": 0,
    "iterations": 0,
    "setups": 0,
    "fallbacks": 0,
    "setup_seconds": 0.0,
    "seconds": 0.0,
}
"""AMG-CG work of this process: solves (one per right-hand side), CG iterations, hierarchy
setups, fallbacks to the direct factorization, and wall time (s) of the setups and of all of
it. ``fecontact.run`` reports a run's share in ``summary.json`` (``iterative_solver``)."""

_hierarchies: list = []  # most recently used last
_modes: dict[int, weakref.ref] = {}


def set_near_null_space(modes: np.ndarray) -> None:
    """Use ``modes`` (n × k, the rigid motions of a model on its n free dofs) as the near-null
    space of the symmetric n × n systems solved from now on, for as long as the caller keeps
    the array (the model does). The most recent registration of a size wins: the modes only
    speed CG up, they never change its answer."""
    _modes[modes.shape[0]] = weakref.ref(modes)


def _near_null_space(n: int):
    """The registered modes of size n without their zero columns, or None (pyamg's constant)."""
    modes = _modes.get(n, lambda: None)()
    if modes is None:
        return None
    B = np.ascontiguousarray(modes[:, np.abs(modes).max(axis=0) > 0], dtype=float)
    return B if B.shape[1] else None


class _Breakdown(Exception):
    """CG met a direction of non-positive curvature: A (or the preconditioner) is indefinite."""


class _Hierarchy:
    """A smoothed-aggregation hierarchy for one sparsity pattern, from the matrix ``A``."""

    def __init__(self, A):
        import pyamg

        start = time.perf_counter()
        self.shape, self.nnz = A.shape, A.nnz
        self.indptr, self.indices = A.indptr, A.indices
        ml = pyamg.smoothed_aggregation_solver(
            A, B=_near_null_space(A.shape[0]), symmetry="hermitian", improve_candidates=None
        )
        self.precondition = ml.aspreconditioner(cycle="V").matvec
        self.iterations = None  # CG iterations of the first solve with its own matrix
        ITERATIVE["setups"] += 1
        elapsed = time.perf_counter() - start
        ITERATIVE["setup_seconds"] += elapsed
        ITERATIVE["seconds"] += elapsed

    def serves(self, A) -> bool:
        """Whether A (a CSR matrix or another hierarchy) has this hierarchy's sparsity
        pattern: the same arrays, or equal ones."""
        if A.shape != self.shape or A.nnz != self.nnz:
            return False
        if _address(A.indices) == _address(self.indices) and _address(A.indptr) == _address(
            self.indptr
        ):
            return True  # the pattern arrays are held here: one address is one pattern
        return np.array_equal(A.indptr, self.indptr) and np.array_equal(A.indices, self.indices)


def _address(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


def _hierarchy(A):
    """(hierarchy, made for A): a cached one for A's pattern, else a new one."""
    for h in _hierarchies:
        if h.serves(A):
            _hierarchies.remove(h)
            _hierarchies.append(h)
            return h, False
    return _store(_Hierarchy(A)), True


def _store(h):
    """Keep ``h`` as the hierarchy of its pattern, dropping the least recently used beyond
    ``CACHE_SIZE``."""
    _hierarchies[:] = [g for g in _hierarchies if not g.serves(h)]
    _hierarchies.append(h)
    del _hierarchies[:-CACHE_SIZE]
    return h


class AmgSolve:
    """``solve(b)`` with A⁻¹ by AMG-preconditioned CG, for a symmetric sparse A; ``direct`` is
    called (once) for the factorization to fall back on."""

    def __init__(self, A, direct):
        self.A = A.tocsr()
        self.direct_factorize, self.direct = direct, None
        self.hierarchy, self.own = _hierarchy(self.A)

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
        x, its = self._cg(b)
        if x is None and not self.own:  # a hierarchy of another matrix: make this one's
            self._rebuild()
            x, its = self._cg(b)
        ITERATIVE["seconds"] += time.perf_counter() - start
        if x is None:
            ITERATIVE["fallbacks"] += 1
            self.direct = self.direct_factorize()
            return self.direct(b)
        ITERATIVE["solves"] += 1
        h = self.hierarchy
        if h.iterations is None:
            h.iterations = its
        elif its > h.iterations + SETUP_ITERATIONS:
            self._rebuild()  # for the next solves
        return x

    def _rebuild(self):
        self.hierarchy, self.own = _store(_Hierarchy(self.A)), True

    def _cg(self, b):
        """(x, iterations), or (None, iterations) when CG breaks down or does not converge."""
        A, precondition, count = self.A, self.hierarchy.precondition, [0]

        def matvec(p):
            count[0] += 1
            q = A @ p
            if p @ q <= 0.0:
                raise _Breakdown
            return q

        def psolve(r):
            z = precondition(r)
            if r @ z <= 0.0:
                raise _Breakdown
            return z

        n = A.shape[0]
        op = spla.LinearOperator((n, n), matvec=matvec, dtype=float)
        M = spla.LinearOperator((n, n), matvec=psolve, dtype=float)
        try:
            x, info = spla.cg(op, b, rtol=RTOL, atol=0.0, maxiter=MAX_ITERATIONS, M=M)
        except _Breakdown:
            info = -1
        ITERATIVE["iterations"] += count[0]
        if info != 0:
            return None, count[0]
        r = b - A @ x
        if np.sqrt(r @ r) > TRUE_RESIDUAL * RTOL * np.sqrt(b @ b):
            return None, count[0]
        return x, count[0]


def amg_factorize(A, direct):
    """``solve(b)`` for a symmetric sparse A (vector or matrix b); ``direct()`` returns the
    direct ``solve`` used when A turns out indefinite or CG does not converge."""
    return AmgSolve(A, direct)
