r"""Solves of a linear model's iteration matrix at step sizes met once, without factorizing
each.

An undamped linear model's iteration matrix is S(a) = a M + K, a = β′(h) (1/s²). The sizes of
a split step (:mod:`fecontact.time.localize`: the refining smooth steps to an impact's
instant, the rest of the step after it) are each used once, so a factorization made for one
of them serves a single step. Two ways avoid it, chosen once per model by its size:

- Small models (at most ``SPECTRAL_LIMIT`` free dofs): the generalized eigenproblem
  K Φ = M Φ Ω², Φᵀ M Φ = I, gives every size at once, S(a)⁻¹ = Φ (a I + Ω²)⁻¹ Φᵀ, a solve
  costing two dense products (on the 387-dof ball as much as the sparse factors' solve, with
  the same round-off). The eigendecomposition costs about n/32 factorizations (387 dofs: 23
  against 1.8 ms; 290 dofs: 11 against 0.6 ms): it is made once the model has made
  ``ceil(n / SPECTRAL_AFTER)`` factorizations for sizes met once, so a run that splits few
  steps pays no more than it did, and one that splits many at most twice what it needs.
- Larger models: preconditioned conjugate gradients with the factors of a nearby size b.
  With M and K positive semidefinite, P⁻¹ S(a) = I + (a − b) P⁻¹ M, P = S(b), has its
  eigenvalues between 1 and a/b. The factors are kept on a geometric ladder of a, each at
  least ``RATIO`` from the others (the run's own step sizes among them): a size within
  ``RATIO`` of a factor is solved by PCG from the nearest, a size farther from every factor
  is factorized and becomes a rung. A run then holds O(log) factors however many instants
  it locates, and meets the same rungs again. A size PCG does not solve (below) is
  factorized and becomes a rung too; of the rungs of sizes met once the ``LIVE`` latest
  keep their factors, an older one's are made again where PCG takes it. On the 2,499-dof
  ball a factorization takes 54 ms and PCG 8 to 19 ms (5 to 16 iterations for a/b from 1.01
  to 2); on the 387-dof ball 10 iterations cost more than its 1.8 ms factorization, hence
  the spectral way there.

Both are exact to round-off: the spectral solve's relative residual is 3e-15 (the direct
solve's 5e-16), PCG's ``TOLERANCE``. A PCG solve that does not reach it in
``MAX_ITERATIONS`` is made again with a factorization of S(a) (counted), which then serves
that size, as is a size solved for more than ``MAX_COLUMNS`` columns at once (the contact
rows' S⁻¹Gᵀ), where PCG's iterations would cost more than the factorization.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .direct import factorize

__all__ = [
    "LIVE",
    "MAX_COLUMNS",
    "MAX_ITERATIONS",
    "RATIO",
    "SPECTRAL_AFTER",
    "SPECTRAL_LIMIT",
    "TOLERANCE",
    "Ladder",
    "Spectral",
    "iteration_solver",
]

SPECTRAL_LIMIT = 600
"""Free dofs up to which the sizes met once are solved through the eigendecomposition: its
dense solve costs 2n² a column, as the sparse factors' solve on the 387-dof ball (0.044
against 0.042 ms), 7 times it on the 1,113-dof ball on a slab (0.77 against 0.11 ms)."""

SPECTRAL_AFTER = 32
"""Free dofs per factorization of a size met once after which the eigendecomposition is
made (its cost over a factorization's, module docstring)."""

RATIO = 2.0
"""Largest ratio between a size's a and the factor's that solves it by PCG: the eigenvalues
of P⁻¹S lie in [1, 2], a contraction of (√2 − 1)/(√2 + 1) ≈ 0.17 per iteration at worst."""

TOLERANCE = 1e-13
"""Relative residual |b − S x| / |b| of a PCG solve: a direct solve's own (5e-16) within a
few hundred ulps, far below the Newton tolerance (1e-8) and the contact columns' use."""

MAX_COLUMNS = 4
"""Columns of b above which a size's solve factorizes S(a) instead of PCG (then kept for that
size): PCG pays its iterations for every column, a factorization once (the 2,499-dof ball:
16 iterations of about 1 ms a column against a 54 ms factorization and 0.8 ms a column)."""

MAX_ITERATIONS = 40
"""PCG iterations of one solve, at most (16 to 17 reach ``TOLERANCE`` at a/b = 2 or 1/2)."""

LIVE = 8
"""Rungs of sizes met once whose factors are kept, at most (the latest made); an older one
keeps its place on the ladder and its factors are made again, from the same S(a), when a
PCG solve takes it (counted ``rungs_remade``): every size that PCG refactorized stayed a
rung, and ``two_balls`` at 10 m/s held 525 factors of its 2,706 dofs, 3.6 GB."""


def iteration_solver(model, a: float, S, K):
    """The factors of a linear ``model``'s iteration matrix ``S`` = S(a) with its constant
    stiffness ``K``, kept by the model's ``ladder`` where one applies (:func:`_ladder`)."""
    # (a size met while passing serves one step: "auto" weighs it over that step)
    solve = factorize(S, symmetric=True, solver=model.solver, once=model.passing)
    ladder = _ladder(model, K)
    if ladder is not None:
        ladder.keep(a, solve)
    return solve


def passing_matrix(model, a: float):
    """(S(a), its solver, None) at a size the ``model`` meets once, from its ladder, or None
    where none applies (the caller factorizes). S is the one sum of data arrays of the
    model's pattern, the damping C (zero) left out; None where the solve is spectral and
    nothing reads S: affine contacts (a correction's metric is then its solve alone, no
    curvature is added to it) and no joints (no bordered update), decided by the model
    (:func:`unread`)."""
    ladder = _ladder(model)
    if ladder is None:
        return None
    if ladder.spectral() and unread(model):
        return None, ladder.solver(a, None), None
    S = model.iteration_sum(a, ladder.K)
    return S, ladder.solver(a, S), None


def unread(model) -> bool:
    """Whether no step reads a linear ``model``'s iteration matrix S itself, only its solve:
    its contacts' gaps are affine (the correction's metric H = S/β′ is only added a
    curvature where gaps are curved) and it has no joints (the updates bordered by their
    rows take S)."""
    return model.contacts.affine and not model.joints.size


def _ladder(model, K=None) -> Ladder | None:
    """The ``model``'s ladder (made on first use, with its constant stiffness ``K``, or
    assembled), or None where none applies: damped (S depends on more than a), dense (a
    dense factorization costs less than any of its solves), or an iterative solver (PCG
    takes exact factors)."""
    if model.dense or any(model.damping) or model.solver.cg:
        return None
    if model.ladder is None:
        K = model.internal(np.zeros(model.n))[2] if K is None else K
        model.ladder = Ladder(
            model.M,
            K,
            lambda A: factorize(A, symmetric=True, solver=model.solver),
            lambda a: model.iteration_sum(a, K),  # (S(a) as passing_matrix makes it)
        )
    return model.ladder


class Ladder:
    """Solvers of S(a) = a M + K (``M``, ``K``: the model's over its free dofs, sparse) at the
    sizes a (1/s²) a run meets once (module docstring). ``factorize(S)`` returns S's solver
    (the model's seam, which counts the work). ``counts``: the factorizations made for such
    sizes, PCG solves, their iterations, PCG solves refactorized, eigendecompositions, rungs
    whose factors were made again (:data:`LIVE`), factorizations of S(a) plus a contact
    curvature made in place of its columns (:meth:`met_once`). They decide (:meth:`spectral`)
    and are put back after steps taken aside (:meth:`put_back`); :meth:`work` is what was
    done, never put back, with the factorizations of the run's own sizes (:meth:`keep`)."""

    def __init__(self, M, K, factorize, assemble=None):
        self.M, self.K, self._factorize = M, K, factorize
        n = M.shape[0]
        # (decided once: the spectral way for small models, after n/32 factorizations)
        self.after = math.ceil(n / SPECTRAL_AFTER) if n <= SPECTRAL_LIMIT else None
        self.rungs: dict[float, object] = {}
        self.modes = None  # (ω² (1/s²), Φ): the eigendecomposition, once made
        self.projected: dict = {}  # Φᵀb of constant columns by their key (Spectral.modal)
        self.counts = dict.fromkeys(
            ("factorizations", "pcg_solves", "pcg_iterations", "pcg_refactorized", "spectral"),
            0,
        )
        self.counts["rungs_remade"] = 0
        self.counts["curvature_factorizations"] = 0  # (S(a) + C in the columns' place)
        # (updates at sizes met once through the factors of S(a₀) + C₀ of a nearby size, and
        # those refused for a residual that did not contract: fecontact.time.held_curvature)
        self.counts["curvature_reuses"] = self.counts["curvature_reuse_fallbacks"] = 0
        # (work the deciding counts leave out: put back, or at the run's own sizes)
        self.outside = dict.fromkeys(self.counts, 0)
        self.own: set[float] = set()  # (the run's own sizes: their factors always kept)
        self.assemble = assemble  # (a -> S(a) at a size met once: a rung's factors remade)

    def spectral(self) -> bool:
        """Whether the sizes met once are now solved by the eigendecomposition (made, or
        made at the next such size), which reads no S(a)."""
        if self.after is None:
            return False
        return self.modes is not None or self.counts["factorizations"] >= self.after

    def work(self) -> dict:
        """The work done so far by its ``counts``' names, put back or not: it never falls."""
        return {key: value + self.outside[key] for key, value in self.counts.items()}

    def put_back(self, rungs: dict, modes, counts: dict) -> None:
        """The rungs, eigendecomposition and ``counts`` (a copy) as they were before steps
        taken aside, so the run decides as without them; their work stays in :meth:`work`."""
        for key, value in self.counts.items():
            self.outside[key] += value - counts[key]
        self.rungs, self.modes, self.counts = rungs, modes, counts

    def met_once(self, a: float) -> bool:
        """Whether S(a) is a size met once solved from factors (not a run's own size, not
        the eigendecomposition's): where the columns S(a)⁻¹e_i of a curvature's dofs serve
        one smooth step only (:meth:`fecontact.linalg.UnitColumns.factorize_instead`)."""
        return self.after is None and a not in self.own

    def keep(self, a: float, solve) -> None:
        """Note the factors ``solve`` of S(a), made for a size the run steps with (in
        :meth:`work`: sub-steps of a retaken step are such sizes, met once)."""
        self.outside["factorizations"] += 1
        if self.after is None:
            self.rungs[a] = solve
            self.own.add(a)

    def solver(self, a: float, S):
        """``solve(b)`` of S = S(a) (``S`` itself, in the model's format) at a size met once."""
        if self.after is not None:
            if self.modes is None and self.spectral():
                self._decompose()
            if self.modes is None:
                return self.factor(a, S)
            return Spectral(a, *self.modes, self.projected)
        near = min(self.rungs, key=lambda b: abs(math.log(a / b)), default=None)
        if near is not None and max(a / near, near / a) <= RATIO:
            if near == a:
                return self.rungs[a]
            return _Preconditioned(self, a, S, self.rungs[near])
        return self.factor(a, S)

    def factor(self, a: float, S):
        """S(a)'s factors (counted), kept as a rung where PCG uses them. The pattern's
        explicit zeros are left out, as the sparse sums that make a run's own S(a) leave
        them: the same structure, so the same ordering and round-off as its factorization."""
        self.counts["factorizations"] += 1
        if sp.issparse(S):
            S = S.copy()
            S.eliminate_zeros()
        solve = self._factorize(S)
        if self.after is None:
            self.rungs[a] = solve
            self._retire()
        return solve

    def _retire(self) -> None:
        """Keep the factors of the ``LIVE`` latest rungs of sizes met once; the older ones'
        factors are dropped, to be made again where PCG takes them (:class:`_Remade`)."""
        if self.assemble is None:
            return
        own = self.own
        made = [b for b, r in self.rungs.items() if b not in own and not isinstance(r, _Remade)]
        for b in made[:-LIVE]:  # (a dict keeps its insertion order: the oldest first)
            self.rungs[b] = _Remade(self, b)

    def _decompose(self) -> None:
        """Φ and Ω² of K Φ = M Φ Ω² (dense, once)."""
        self.counts["spectral"] += 1
        dense = (A.toarray() if sp.issparse(A) else np.asarray(A) for A in (self.K, self.M))
        self.modes = sla.eigh(*dense, driver="gvd", check_finite=False)


class Spectral:
    """``solve(b)``: S(a)⁻¹b = Φ (a I + Ω²)⁻¹ Φᵀ b for the eigenvalues ``omega2`` (Ω², 1/s²)
    and M-orthonormal modes ``phi``; ``scale`` = (a + Ω²)⁻¹. ``projected``: Φᵀb of the
    columns b a caller keeps constant, by their key (:meth:`modal`), shared by every size."""

    __slots__ = ("phi", "scale", "projected")

    def __init__(self, a: float, omega2, phi, projected: dict):
        self.phi, self.scale, self.projected = phi, 1.0 / (a + omega2), projected

    def __call__(self, b):
        b = b.toarray() if sp.issparse(b) else np.asarray(b, dtype=float)
        y = self.phi.T @ b
        y *= self.scale if y.ndim == 1 else self.scale[:, None]
        return self.phi @ y

    def modal(self, keys, B) -> np.ndarray:
        """Φᵀ B (n × len(keys)) of the columns of ``B`` (dense, n × len(keys)) that stay the
        same under their ``keys`` (a contact's constant gradient): made once per key and
        kept, for every size a."""
        kept = self.projected
        if len(keys) == 1 and keys[0] in kept:  # (one contact pressed: most located impacts)
            return kept[keys[0]][:, None]
        missing = [i for i, key in enumerate(keys) if key not in kept]
        if missing:
            Y = self.phi.T @ B[:, missing]
            for col, i in enumerate(missing):
                kept[keys[i]] = Y[:, col]
        return np.column_stack([kept[key] for key in keys])


class _Remade:
    """A rung whose factors were dropped (:meth:`Ladder._retire`): made again from S(a) at
    its first solve, the same matrix as they were made from, so the same numbers."""

    __slots__ = ("a", "ladder", "solve")

    def __init__(self, ladder: Ladder, a: float):
        self.ladder, self.a, self.solve = ladder, a, None

    def __call__(self, b):
        if self.solve is None:
            ladder = self.ladder
            ladder.counts["rungs_remade"] += 1
            S = ladder.assemble(self.a)
            if sp.issparse(S):  # (as Ladder.factor: the pattern's explicit zeros left out)
                S = S.copy()
                S.eliminate_zeros()
            self.solve = ladder._factorize(S)
        return self.solve(b)


class _Preconditioned:
    """``solve(b)``: S⁻¹b by conjugate gradients preconditioned by a rung's ``factor``, every
    column of b at once (each its own step lengths)."""

    __slots__ = ("a", "factor", "ladder", "S", "exact")

    def __init__(self, ladder: Ladder, a: float, S, factor):
        self.ladder, self.a, self.S, self.factor = ladder, a, S, factor
        self.exact = None  # (S's own factors, where a solve did not converge)

    def __call__(self, b):
        if self.exact is not None:
            return self.exact(b)
        b = b.toarray() if sp.issparse(b) else np.asarray(b, dtype=float)
        B = b.reshape(b.shape[0], -1)
        x = self._pcg(B) if B.shape[1] <= MAX_COLUMNS else None
        if x is None:  # (not converged, or many columns: S(a) factorized, counted)
            ladder = self.ladder
            ladder.counts["pcg_refactorized"] += 1
            self.exact = ladder.factor(self.a, self.S)
            return self.exact(b)
        return x.reshape(b.shape)

    def _pcg(self, B):
        """X with |B − S X| ≤ ``TOLERANCE`` |B| column by column, or None."""
        S, P, counts = self.S, self.factor, self.ladder.counts
        counts["pcg_solves"] += 1
        bound = TOLERANCE * np.linalg.norm(B, axis=0)
        X = P(B).reshape(B.shape)
        R = B - S @ X
        Z = P(R).reshape(B.shape)
        D, rz = Z.copy(), np.einsum("ij,ij->j", R, Z)
        for it in range(MAX_ITERATIONS + 1):
            if np.all(np.linalg.norm(R, axis=0) <= bound):
                counts["pcg_iterations"] += it
                return X
            if it == MAX_ITERATIONS:
                break
            Q = S @ D
            dq = np.einsum("ij,ij->j", D, Q)
            alpha = np.divide(rz, dq, out=np.zeros_like(rz), where=dq > 0.0)
            X += alpha * D
            R -= alpha * Q
            Z = P(R).reshape(B.shape)
            rz, before = np.einsum("ij,ij->j", R, Z), rz
            beta = np.divide(rz, before, out=np.zeros_like(rz), where=before > 0.0)
            D = Z + beta * D
        counts["pcg_iterations"] += MAX_ITERATIONS
        return None
