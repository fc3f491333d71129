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

Select one with :func:`use_sparse_solver` or the environment variable
``FECONTACT_SPARSE_SOLVER`` (read at import).
"""

from __future__ import annotations

import os
import weakref

import numpy as np

from ..errors import InputError
from .choice import RunPlan, SolverChoice
from .cholesky import cholesky_available

__all__ = [
    "SPARSE_SOLVERS",
    "finish_run",
    "run_choice",
    "sparse_solver",
    "start_run",
    "use_sparse_solver",
]

SPARSE_SOLVERS = ("direct", "superlu", "pardiso", "amg", "auto")
# the solver, and the record of the run in progress (``start_run``)
_current = {"name": "direct", "run": None}


def use_sparse_solver(name: str) -> None:
    """Factorize sparse matrices with ``name`` (one of ``SPARSE_SOLVERS``) from now on."""
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
    if name in ("amg", "auto"):
        try:
            import pyamg  # noqa: F401
        except ImportError:
            raise InputError(
                f'sparse solver "{name}" needs the pyamg package: pip install pyamg'
            ) from None
    _current["name"] = name


def sparse_solver() -> str:
    """The name of the sparse solver in use."""
    return _current["name"]


def start_run(steps: int, linear: bool) -> SolverChoice:
    """Begin the record of a run of ``steps`` time steps of a ``linear`` model (or not) with
    the sparse solver in use: its factorizations and, with ``"auto"``, its choices."""
    backend = "cholesky" if cholesky_available() and _current["name"] != "superlu" else "superlu"
    choice = SolverChoice(_current["name"], RunPlan(max(int(steps), 1), linear), backend)
    _current["run"] = choice
    return choice


def run_choice() -> SolverChoice | None:
    """The record of the run in progress, or None outside ``fecontact.run``."""
    return _current["run"]


def finish_run(choice: SolverChoice) -> dict:
    """End the run recorded in ``choice``; return its ``sparse_solver`` summary entry."""
    if _current["run"] is choice:
        _current["run"] = None
    return choice.record()


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
