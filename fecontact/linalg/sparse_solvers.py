"""The sparse solver behind :func:`fecontact.linalg.factorize`.

``"direct"`` (default) factorizes the symmetric sparse systems (S_t, M, the metric) by sparse
Cholesky when the optional ``pypardiso`` package is installed (:mod:`.cholesky`;
``pip install "fecontact[pardiso]"``, x86-64), and everything else by SciPy's SuperLU, always
available. ``"superlu"`` uses SuperLU for all of them. ``"pardiso"`` is Intel MKL PARDISO for
all: Cholesky for the symmetric systems, its multithreaded supernodal LU for the others. The
direct solvers return the same solutions to round-off; the choice only changes speed
(``docs/validation/large_solids.md``). ``"amg"`` solves the symmetric systems by CG
preconditioned with algebraic multigrid (:mod:`fecontact.linalg.iterative`) to a relative
residual of 1e-10; ``"auto"`` solves each by CG or by the direct path, whichever the run's
measured costs say is cheaper (:mod:`fecontact.linalg.choice`).

Select the process default with :func:`use_sparse_solver` or the environment variable
``FECONTACT_SPARSE_SOLVER`` (read at import); a run reads it once, when it starts, into its
own :class:`fecontact.linalg.LinearSolver`. ``"amg"`` needs the optional ``pyamg`` package;
``"auto"`` without it has one path to choose, the direct one, and says so in the run's record.
"""

from __future__ import annotations

import os
import weakref

import numpy as np

from ..errors import InputError

__all__ = [
    "SPARSE_SOLVERS",
    "amg_available",
    "check_sparse_solver",
    "sparse_solver",
    "use_sparse_solver",
]

SPARSE_SOLVERS = ("direct", "superlu", "pardiso", "amg", "auto")
_default = {"name": "direct"}  # the process default: runs read it when they start


def use_sparse_solver(name: str) -> None:
    """Factorize sparse matrices with ``name`` (one of ``SPARSE_SOLVERS``) in the runs and
    solvers made from now on."""
    _default["name"] = check_sparse_solver(name)


def check_sparse_solver(name: str) -> str:
    """``name`` if it is one of ``SPARSE_SOLVERS`` and its package is installed, else an
    ``InputError`` that says how to install it (``"auto"`` takes the direct path without
    pyamg: :func:`amg_available`)."""
    if not isinstance(name, str) or name not in SPARSE_SOLVERS:
        known = ", ".join(SPARSE_SOLVERS)
        raise InputError(f"sparse solver must be one of {known}, got {name!r}")
    if name == "pardiso":
        try:
            import pypardiso  # noqa: F401
        except ImportError:
            raise InputError(
                'sparse solver "pardiso" needs the pypardiso package: '
                'pip install "fecontact[pardiso]"'
            ) from None
    if name == "amg" and not amg_available():
        raise InputError(
            'sparse solver "amg" needs the pyamg package: pip install "fecontact[amg]"'
        )
    return name


def amg_available() -> bool:
    """Whether the ``pyamg`` package, AMG-CG's preconditioner, is installed (asked at every
    call: an installed one is imported once)."""
    try:
        import pyamg  # noqa: F401
    except ImportError:
        return False
    return True


def sparse_solver() -> str:
    """The name of the process default sparse solver."""
    return _default["name"]


def pardiso_factorize(A):
    """``solve(b)`` with A factorized once by PARDISO (real unsymmetric LU, mtype 11)."""
    import pypardiso

    A = A.tocsr()
    A.sort_indices()
    solver = pypardiso.PyPardisoSolver(mtype=11)
    try:
        solver.factorize(A)
    except pypardiso.pardiso_wrapper.PyPardisoError as err:
        raise np.linalg.LinAlgError(f"PARDISO: {err}") from None

    def solve(b):
        b = np.asarray(b, dtype=float)
        return solver.solve(A, b)

    # MKL keeps the factors outside Python's heap: release them with the last reference
    weakref.finalize(solve, solver.free_memory, True)
    return solve


if os.environ.get("FECONTACT_SPARSE_SOLVER"):
    use_sparse_solver(os.environ["FECONTACT_SPARSE_SOLVER"])
