"""Sparse Cholesky factorization of symmetric positive definite matrices.

The backend is Intel MKL PARDISO in its real symmetric positive definite mode (matrix type 2:
supernodal L Lᵀ after a METIS nested-dissection ordering) through the optional ``pypardiso``
package (``pip install "fecontact[pardiso]"``, x86-64). It was chosen by measurement among the
bindings that install from wheels (``docs/validation/large_solids.md``): on the iteration
matrix of a 65,856-dof ball it factorizes in 4.5 s where SuperLU's symmetric mode takes 33 s
and 1.9 GB, and cholespy's bundled CHOLMOD 61 s. Without pypardiso,
:func:`cholesky_factorize` is unavailable and SuperLU factorizes everything.

A matrix that turns out not to be positive definite (the tangent of a buckling body) is
refused (``None``): the caller factorizes it with SuperLU instead.
"""

from __future__ import annotations

import functools
import importlib.util
import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["MIN_UNKNOWNS", "CholeskyFactor", "cholesky_available", "cholesky_factorize"]

_SPD = 2  # PARDISO's real symmetric positive definite matrix type

_IPARM = {1: 1, 2: 2}
"""PARDISO's settings (1-based iparm): these, not MKL's defaults (1); METIS nested dissection
(2), MKL's default ordering; every other entry 0, so no iterative refinement (8): MKL's
defaults refine every solve once, which doubled a solve's time on the 65,856-dof ball
(87 against 41 ms) for a relative residual already at round-off (5.7e-15 against 1.1e-14)."""

MIN_UNKNOWNS = 2000
"""Smaller systems stay with SuperLU: its factorization is as fast there (the 3D ball's S_t,
one thread: 1,029 dofs 4.9 ms against PARDISO's 10.8 ms; 3,993 dofs 59 ms against 31 ms), and
the shipped cases (at most 606 dofs) keep their results to the bit with or without pypardiso."""


@functools.cache
def cholesky_available() -> bool:
    """Whether the sparse Cholesky backend (pypardiso, and the MKL library it loads) is
    installed; asked once per process."""
    try:  # (an import hook may refuse the package in find_spec already)
        if importlib.util.find_spec("pypardiso") is None:
            return False
        import pypardiso  # noqa: F401  (loads MKL: fails without it)
    except (ImportError, OSError, AttributeError):
        return False
    return True


@dataclass
class CholeskyFactor:
    """``solve(b)`` applying A⁻¹ to a vector or to the columns of a matrix with the factor
    L Lᵀ = A; ``memory_mb`` is the peak memory PARDISO reported for the factorization (MB)."""

    solve: object
    memory_mb: float

    def __call__(self, b):
        return self.solve(b)


def cholesky_factorize(A) -> CholeskyFactor | None:
    """The Cholesky factor of the symmetric sparse A, or None if A is not positive definite.

    Only the upper triangle of A is read (A = Aᵀ is the caller's promise)."""
    import pypardiso

    upper = sp.triu(A, format="csr")
    upper.sort_indices()
    solver = pypardiso.PyPardisoSolver(mtype=_SPD)
    for i, value in _IPARM.items():
        solver.set_iparm(i, value)
    try:
        solver.factorize(upper)
    except (pypardiso.pardiso_wrapper.PyPardisoError, ValueError):
        # error −4 (a zero or negative pivot) proves A indefinite, an empty row (ValueError)
        # singular: the fallback factorization reports what it finds
        solver.free_memory(True)
        return None
    # iparm(15): peak of the analysis, (16) permanent, (17) the numerical factorization (kB)
    iparm = solver.iparm
    memory_kb = max(int(iparm[14]), int(iparm[15]) + int(iparm[16]))

    def solve(b):
        b = b.toarray() if sp.issparse(b) else np.asarray(b, dtype=float)
        return solver.solve(upper, b)

    # MKL keeps the factor outside Python's heap: release it with the last reference
    weakref.finalize(solve, solver.free_memory, True)
    return CholeskyFactor(solve, memory_kb / 1024.0)
