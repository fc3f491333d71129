"""The sparse solver of a run: its record, and the cost-based choice of ``"auto"``.

A :class:`SolverChoice` lives for one run (``fecontact.run`` makes it). Every sparse
factorization of the run is counted in it (backend, time, the factor's memory), and it reports
them in ``summary.json`` (``sparse_solver``) with the process's peak memory.

With the sparse solver ``"auto"``, each symmetric sparse matrix (S_t, M, the metric: one
*role* per sparsity pattern) goes to the direct path (sparse Cholesky when installed, else
SuperLU) or to AMG-preconditioned CG, whichever is expected to cost the rest of the run less
CPU time:

    direct = F t_f + N t_s,        CG = N t_cg,

with N the solves (right-hand sides: a block of k columns is k solves) and F the factorizations
still to come: N = (columns in hand) + (steps left) × (solves a step), F = 1 for a linear model
before its one factorization and 0 after, F = (steps left) × (factorizations a step) for a
nonlinear one (one a Newton iteration). Solves and factorizations per step are measured as the
run goes, over the steps since the role's first solve and first matrix (``SOLVES_GUESS`` and
``NEWTON_GUESS`` before a step is over): a role may come late, the iteration matrix of a step
size met at a located closing. t_f and t_s are measured once the role has been factorized, and
until then estimated from the measured time of one product with A by ``FACTOR_MODEL``, or
``PLANAR_MODEL`` where A's graph grows like a planar one (:mod:`.graph_growth`: a 2D body, a
thin slab), ``docs/validation/large_solids.md``. t_cg is measured on CG's solves; the first
solve of a role is CG with the diagonal preconditioner, stopped once it has cost what a CG
solve may cost for the paths to tie (so that a role the direct path serves better loses little
to it): if it converges, its time is t_cg; if not, AMG-CG is estimated by ``AMG_MODEL`` until
measured. The choice is made again at every new matrix of a role, and on the CG path once a
step and at every block of right-hand sides; each change of path is recorded with its reason.

Times are the process's CPU time (``time.process_time``): on a shared machine wall time adds
the other jobs' to a solve (a 66,050-dof disk's first CG solve took 0.163 s of wall time for
about 0.06 s of work under a load of 12 on 2 cores, and "auto" left CG, 2 × its time), and
the unit, the best of three products, hardly sees them. With several BLAS threads it counts
every thread's work: a path's parallel speed-up is not credited.
"""

from __future__ import annotations

import inspect
import resource
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .graph_growth import PLANAR_GROWTH, graph_growth
from .iterative import DIAGONAL_ITERATIONS, RTOL, TRUE_RESIDUAL

__all__ = ["FACTOR_MODEL", "PLANAR_MODEL", "RunPlan", "SolverChoice"]

# the relative tolerance of scipy's cg: ``tol`` before SciPy 1.12, ``rtol`` since
_RTOL = "rtol" if "rtol" in inspect.signature(spla.cg).parameters else "tol"

SOLVES_GUESS = 2.0
"""Solves a step with a role's matrix, before the first step is over (measured 1.5–2.2 on
the linear ball impacts of ``benchmarks/large_solids.py``)."""

NEWTON_GUESS = 3.0
"""Factorizations a step of a nonlinear model before the first step is over (Newton
iterations: 2–4 measured on the Neo-Hookean ball)."""

PRODUCTS_PER_ITERATION = 1.5
"""Cost of a CG iteration with the diagonal preconditioner, in products with A (the product,
the scaling and three vector updates)."""

AMG_MODEL = (450.0, 0.3)
"""(K, q): an AMG-preconditioned CG solve costs K (n/10⁴)^q products with A, its hierarchy's
setups included, until one is measured: fitted to the ``amg`` rows of the linear balls of
``benchmarks/large_solids.py`` at t_c/20 (351, 465 and 805 products a solve at 3,993, 20,577
and 65,856 dofs, beyond the direct path's work of a step). At 255,552 dofs a trial solve at
the former flat 300 cost the run 30 % over the direct path."""

FACTOR_MODEL = {
    "cholesky": ((520.0, 1.0), (39.0, 0.4)),
    "superlu": ((1790.0, 1.4), (56.0, 0.7)),
}
"""Per backend, ((K_f, q_f), (K_s, q_s)): a factorization costs K_f (n/10⁴)^q_f and a solve
K_s (n/10⁴)^q_s products with A (n unknowns), fitted to the iteration matrices of the 3D ball at
20,577 and 65,856 dofs (PARDISO's Cholesky and SuperLU's symmetric mode, one thread). Only the
first decision of a role uses it; measured times replace it. Matrices whose graph is planar
take ``PLANAR_MODEL``."""

PLANAR_MODEL = {
    "cholesky": ((195.0, 0.34), (47.0, 0.0)),
    "superlu": ((673.0, 0.34), (67.0, 0.0)),
}
"""``FACTOR_MODEL`` of the matrices whose graph grows like a planar one
(:func:`.graph_growth.graph_growth` below ``PLANAR_GROWTH``). SuperLU's is fitted to the
iteration matrices of P1 and P2 disks and squares and of a slab of two layers of tetrahedra,
4,226 to 80,802 dofs, 34 runs (its factorizations took 0.48–3.2 and its solves 0.23–3.0
times the fit; the volume law overestimated these factorizations 6.6–50 times from 45,602
dofs on). The
Cholesky path's is not measured on planar meshes: SuperLU's times the ratio of the two
backends' volume laws at 10⁴ dofs (0.29 for a factorization, 0.70 for a solve)."""


@dataclass
class RunPlan:
    """What a run will ask of its solver: ``steps`` time steps; a ``linear`` model factorizes
    its iteration matrix once, a nonlinear one at every Newton iteration."""

    steps: int
    linear: bool


@dataclass
class _Role:
    """The measured costs (CPU s) of the matrices of one sparsity pattern."""

    n: int
    product: float  # one product with A
    met: int  # the step of the run in which the first matrix of the pattern came
    requests: int = 0  # matrices of this pattern to solve with
    solves: int = 0
    solving: int | None = None  # the step of its first solve
    path: str | None = None
    t_f: float | None = None  # direct factorization, measured
    t_s: float | None = None  # direct solve, measured
    t_cg: float | None = None  # CG solve, measured (setups included but the first)
    growth: float | None = None  # of the pattern's graph (None: too small to read)
    cg_solves: int = 0
    cg_timed: int = 0  # the CG solves t_cg averages (not the one that built the first hierarchy)
    setups: int = 0  # CG solves that built an AMG hierarchy
    direct_solves: int = 0

    def average(self, name: str, seconds: float, columns: int, count: int) -> None:
        """The mean time of a column of ``name``, with ``columns`` more solved in ``seconds``
        (``count`` columns in all)."""
        old, each = getattr(self, name), seconds / columns
        setattr(self, name, each if old is None else old + (each - old) * columns / count)


@dataclass
class SolverChoice:
    """The sparse solver ``name`` of one run, the plan of the run, and what it did."""

    name: str
    plan: RunPlan
    backend: str  # the direct path of symmetric systems: "cholesky" or "superlu"
    cg: bool = True  # whether CG is a path ("auto" without pyamg: the direct path alone)
    steps_done: int = 0
    decisions: list = field(default_factory=list)
    factorizations: dict = field(default_factory=dict)
    factor_memory_mb: float = 0.0
    iterative: object = None  # the run's IterativeStats: AMG setups' time
    _roles: dict = field(default_factory=dict)

    def setup_seconds(self) -> float:
        """The time (s) spent building AMG hierarchies so far in the run."""
        return 0.0 if self.iterative is None else self.iterative.setup_seconds

    def note_step(self) -> None:
        """A time step is done (the measured rates per step count it)."""
        self.steps_done += 1

    def count_factorization(self, backend: str, seconds: float, memory_mb: float = 0.0):
        """Count a sparse factorization by ``backend`` that took ``seconds`` and whose factor
        holds ``memory_mb`` (0 when the backend does not say)."""
        entry = self.factorizations.setdefault(backend, {"count": 0, "seconds": 0.0})
        entry["count"] += 1
        entry["seconds"] += seconds
        self.factor_memory_mb = max(self.factor_memory_mb, memory_mb)

    def auto(self, A, direct, iterative, once: bool = False):
        """``solve(b)`` for the symmetric sparse A, by ``direct()`` or ``iterative()`` (each
        returns a solve) as the costs measured so far choose; ``once``: A serves one step (a
        step size of a split step), whose solves alone it is weighed over."""
        role = self.role(A)
        role.requests += 1
        return _AutoSolve(self, role, A, (direct, iterative), once)

    def role(self, A) -> _Role:
        """The measured costs of the matrices with the sparsity pattern of A (one per role),
        whether they share its index arrays or have equal ones (the iteration matrix of every
        step size is a sum of its own)."""
        same = self._roles.setdefault((A.format, A.shape[0], A.nnz), [])
        for indptr, indices, role in same:
            if _equal(A.indptr, indptr) and _equal(A.indices, indices):
                return role
        role = _Role(A.shape[0], _product_time(A), self.steps_done, growth=graph_growth(A))
        same.append((A.indptr, A.indices, role))
        return role

    def costs(
        self, role: _Role, factorized: bool, columns: int = 0, once: bool = False
    ) -> tuple[float, float, str]:
        """(direct, CG) seconds expected for the rest of the run (of this step, ``once``),
        ``columns`` in hand besides the solves (columns) a step to come, and how they were
        had."""
        left = 1 if once else max(self.plan.steps - self.steps_done, 1)
        # rates over the steps since the role's first matrix, and first solve: a pattern may
        # come late (the iteration matrix of a new step size, or first solved at a closing)
        solving = self.steps_done - (self.steps_done if role.solving is None else role.solving)
        per_step = role.solves / solving if solving else SOLVES_GUESS
        t_f, t_s, source = self._direct_times(role)
        if self.plan.linear:
            factorizations = 0.0 if factorized else 1.0
        else:
            met = self.steps_done - role.met
            factorizations = left * (role.requests / met if met else NEWTON_GUESS)
        solves = columns + left * per_step
        direct = factorizations * t_f + solves * t_s
        cg = solves * role.t_cg
        now = f"{columns} columns now + " if columns else ""
        how = (
            f"{now}{left} steps left x {per_step:.3g} solves, {factorizations:.3g} factorizations: "
            f"factorization {t_f:.3g} s + solve {t_s:.3g} s ({source}) against CG {role.t_cg:.3g}"
            f" s ({'measured' if role.cg_solves else 'estimated'})"
        )
        return direct, cg, how

    def _direct_times(self, role: _Role) -> tuple[float, float, str]:
        if role.t_f is not None:
            t_s = role.t_s if role.t_s is not None else role.t_f * 0.02
            return role.t_f, t_s, "measured"
        planar = role.growth is not None and role.growth < PLANAR_GROWTH
        (kf, qf), (ks, qs) = (PLANAR_MODEL if planar else FACTOR_MODEL)[self.backend]
        scale = role.n / 1e4
        graph = "graph unread" if role.growth is None else f"graph growth {role.growth:.2f}"
        source = f"estimated, {'planar' if planar else 'volume'} law, {graph}"
        return kf * scale**qf * role.product, ks * scale**qs * role.product, source

    def decide(self, role: _Role, path: str, reason: str) -> None:
        if path != role.path:
            self.decisions.append(
                {"n": role.n, "step": self.steps_done, "path": path, "reason": reason}
            )
        role.path = path

    def record(self) -> dict:
        """The run's ``sparse_solver`` entry of ``summary.json``."""
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux
        out = {
            "name": self.name,
            "direct": self.backend,
            "factorizations": self.factorizations,
            "factor_memory_mb": self.factor_memory_mb,
            "peak_memory_mb": peak,
        }
        if self.name == "auto":
            roles = [
                {
                    "n": r.n,
                    "path": r.path,
                    "cg_solves": r.cg_solves,
                    "direct_solves": r.direct_solves,
                    "graph_growth": r.growth,
                }
                for same in self._roles.values()
                for _, _, r in same
            ]
            out |= {"roles": roles, "decisions": self.decisions}
        out["reason"] = self._reason()
        return out

    def _reason(self) -> str:
        if self.name != "auto":
            return f'the sparse solver "{self.name}" (use_sparse_solver): no choice to make'
        if not self.cg:
            return (
                'the direct path: "auto" without the pyamg package has no CG path to weigh '
                '(pip install "fecontact[amg]")'
            )
        if not self.decisions:
            return "no symmetric sparse system was solved"
        last = self.decisions[-1]
        return f"{last['path']} for the last choice (n = {last['n']}): {last['reason']}"


def _equal(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the index arrays a and b are equal: the same array, or equal entries."""
    if a.__array_interface__["data"][0] == b.__array_interface__["data"][0]:
        return a.shape == b.shape
    return np.array_equal(a, b)


def _product_time(A) -> float:
    """CPU time (s) of one product A x: the unit of the cost model, measured on the best of
    three (the first touches the memory)."""
    x = np.ones(A.shape[0])
    best = np.inf
    for _ in range(3):
        start = time.process_time()
        A @ x
        best = min(best, time.process_time() - start)
    return best


class _AutoSolve:
    """``solve(b)`` of one matrix of a role, by the path its role's costs choose."""

    def __init__(self, choice: SolverChoice, role: _Role, A, paths, once: bool):
        self.choice, self.role, self.A, self.once = choice, role, A, once
        self.direct_factorize, self.iterative = paths
        self.solve, self.path, self.step = None, None, -1
        self.reweighed = False  # chosen again once the role's first CG solve was timed
        self.probed = False  # by CG with the diagonal (_probe)
        self.settled = False  # on the CG path for good (a matrix met once, by its probe)

    def __call__(self, b):
        if self.path is None and not self.probed and (self.role.t_cg is None or self.once):
            x = self._probe(b)
            if x is not None:
                return x
        columns = np.shape(b)[1] if len(np.shape(b)) > 1 else 1
        self._reweigh(columns)
        return self._timed_solve(b, columns)

    def _reweigh(self, columns: int) -> None:
        """On the CG path: choose at the first solve, right after the role's first CG solve
        (its cost now measured), at a block of columns (CG pays for each column what a solve
        costs, a factor little), else at most once a step."""
        probed = self.role.cg_solves > 0 and not self.reweighed
        again = self.step != self.choice.steps_done or probed or columns > 1
        if self.path != "direct" and again and not self.settled:
            self.step, self.reweighed = self.choice.steps_done, self.reweighed or probed
            self._choose(columns)

    def _timed_solve(self, b, columns: int):
        """A⁻¹ b on the chosen path, its CPU time counted in the role."""
        role = self.role
        role.solving = self.choice.steps_done if role.solving is None else role.solving
        role.solves += columns
        setups, wall, start = self.choice.setup_seconds(), time.perf_counter(), time.process_time()
        x = self.solve(b)
        seconds, wall = time.process_time() - start, time.perf_counter() - wall
        if self.path == "direct":
            role.direct_solves += columns
            role.average("t_s", seconds, columns, role.direct_solves)
        else:
            # the setups' wall time, as a share of the solve's, in CPU time
            share = min((self.choice.setup_seconds() - setups) / wall, 1.0) if wall else 0.0
            self._time_cg(seconds, share * seconds, columns)
        return x

    def _time_cg(self, seconds: float, setup: float, columns: int) -> None:
        """Count ``columns`` solved by CG in ``seconds``, ``setup`` of them building AMG
        hierarchies. The role's first hierarchy, and the diagonal's trial of up to
        ``DIAGONAL_ITERATIONS`` before it, are paid once, like a factorization: that solve
        stands for CG's cost only until a solve without them is timed (it took 0.155 s of a
        66,050-dof disk's S_t, the next ones about a fifth of it, and "auto" left CG)."""
        role = self.role
        role.cg_solves += columns
        if setup > 0.0 and not role.setups:
            role.setups += 1
            role.t_cg, role.cg_timed = (seconds - setup) / columns, 0  # replaced by the next
            return
        role.setups += setup > 0.0
        role.cg_timed += columns
        role.average("t_cg", seconds, columns, role.cg_timed)

    def _probe(self, b):
        """The first solve of a role, or of a matrix met once: CG with the diagonal on b (on
        its first column, for a block), stopped once it has cost what a solve may cost for
        CG to tie with the direct path (at most ``DIAGONAL_ITERATIONS``). Its answer if it
        converged (the CG path if within the time too; a role's first measures CG's cost; a
        block is then solved on the path); else None, and for a role's first AMG-CG's cost
        estimated (``AMG_MODEL``). A size of a split step is smaller than the role's step and
        better conditioned: the diagonal may suffice where it did not for the role's first
        matrix, whose AMG estimate would send it to a factorization of its own."""
        role, choice = self.role, self.choice
        self.probed, known = True, role.t_cg
        role.t_cg = 1.0  # a unit: the CG cost below is then the number of solves left
        block = np.ndim(b) > 1 and not sp.issparse(b)
        columns = np.shape(b)[1] if block else 0
        direct, solves, how = choice.costs(role, False, columns, once=self.once)
        amg = AMG_MODEL[0] * (role.n / 1e4) ** AMG_MODEL[1] * role.product
        role.t_cg = amg if known is None else known
        tie = direct / solves  # s a CG solve may cost
        iterations = int(min(tie / (PRODUCTS_PER_ITERATION * role.product), DIAGONAL_ITERATIONS))
        start = time.process_time()
        x = _diagonal_cg(self.A, np.asarray(b)[:, 0] if block else b, iterations)
        seconds = time.process_time() - start
        if x is None:
            return None
        role.cg_solves, role.solves = role.cg_solves + 1, role.solves + 1
        if known is None:
            role.t_cg, role.cg_timed, role.solving = seconds, 1, choice.steps_done
        if seconds <= tie:
            # a matrix met once keeps the path its own probe chose (the role's CG cost is
            # its first matrix's, the worse conditioned)
            self.path, self.solve, self.step = "cg", self.iterative(), choice.steps_done
            self.settled = self.once
            reason = f"CG with the diagonal solved in {seconds:.3g} s, below the tie {tie:.3g} s"
            choice.decide(role, "cg", f"{reason} of the direct path ({how})")
        # else within the iterations, not the time (a small system's overheads): weighed at
        # the next solve, CG's cost measured
        return None if block else x

    def _choose(self, columns: int) -> None:
        """The path of this matrix for the rest of the run, ``columns`` to solve now."""
        role, choice = self.role, self.choice
        factorized = role.t_f is not None and choice.plan.linear
        direct, cg, how = choice.costs(
            role, factorized and self.path == "direct", columns, self.once
        )
        path = "direct" if direct <= cg else "cg"
        reason = f"expected direct {direct:.3g} s, CG {cg:.3g} s: {how}"
        choice.decide(role, path, reason)
        if path == self.path:
            return
        self.path = path
        if path == "cg":
            self.solve = self.iterative()
            return
        start = time.process_time()
        self.solve = self.direct_factorize()
        role.t_f = time.process_time() - start


def _diagonal_cg(A, b, iterations: int):
    """x with ‖b − A x‖ ≤ TRUE_RESIDUAL · RTOL ‖b‖ by at most ``iterations`` of CG with the
    diagonal preconditioner, or None (not converged, a matrix block of right-hand sides, a
    nonpositive diagonal)."""
    d = A.diagonal()
    if iterations < 1 or sp.issparse(b) or np.ndim(b) != 1 or not np.all(d > 0.0):
        return None
    b = np.asarray(b, dtype=float)
    if not b.any():
        return np.zeros_like(b)
    M = spla.LinearOperator(A.shape, matvec=lambda r: r / d, dtype=float)
    x, info = spla.cg(A, b, atol=0.0, maxiter=iterations, M=M, **{_RTOL: RTOL})
    converged = np.linalg.norm(b - A @ x) <= TRUE_RESIDUAL * RTOL * np.linalg.norm(b)
    return x if info == 0 and converged else None
