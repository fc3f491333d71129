r"""The generalized-α form of the Newton loop (:mod:`.newton`), for the NSGA's smooth step
and the penalty step: it solves r(X) = M v̇ + Σ_k f_k(q, v, t) = 0, with the rows of the
terms that have multipliers (joints, persistent contacts) as constraints, for the iterate
X = (q, v, v̇, a) of one step: Newton moves q by dq and (v, v̇, a) by (γ′, β′, ∂a/∂q) dq.
Each update solves

    S_t dq = −r,   S_t = β′M + Σ_k (∂f_k/∂q + γ′ ∂f_k/∂v),

with S_t alone, with S_t's own factors and the Schur complement of one term's rows, or
bordered by every touching term's rows. The plan decides whether a linear model's S_t and
its factors are reused (no term brings a tangent of its own), and the globalization: the
energy descent of :mod:`.descent` (the NSGA's smooth step), or the halving of an update
that does not lower the residual (penalty). It converges when
|r| ≤ tol_residual · max(|f_ext|, |f_int|, |M v̇|) and every term's own test holds at the
iterate, or when an update is below the increment tolerance and every constrained term's
test holds after it (or, in a linear model with nonlinear joints, by the joints' remainder
bound), or, where the plan is exact (affine forces and gaps), after any update whose rows'
active set holds at its end (its residual is round-off).

The loop builds the form once per run and begins it again at every step.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from .constraints import (
    StepFailure,
    bordered,
    factorize_or_fail,
    independent_rows,
    plus_curvature,
)
from .descent import Armijo, descent_direction, energy_roundoff, group_direction
from .generalized_alpha import predict
from .lie import LieStep, predict_increment
from .terms import StepContext

__all__ = ["CONTRACTION", "AccelerationForm", "held_factors"]

CONTRACTION = 0.9
"""Modified Newton (the loop's ``frozen``): the factors of an earlier update are kept while
each update lowers the relative residual by at least this factor, else S_t is made again at
the iterate (a semi-smooth contact update lowers it by about half, full Newton or not)."""


class AccelerationForm:
    """The generalized-α form of the loop ``newton`` (module docstring): the unknown q_{n+1}
    (on a Lie group the increment D, q = q_n ⊕ D), with (v, v̇, a) following at the rates
    of the coefficients ``c``; the predictor from ``st``; the residual r = M v̇ + Σ_k f_k;
    updates from S_t, alone, through a Schur complement or bordered by the terms' rows.
    ``law``: unused (the step needs nothing else)."""

    __slots__ = (
        "S armijo coasted csc dq first group held lie model newton opts plain plan previous r "
        "ref rnorm s small solve step x"
    ).split()

    def __init__(self, newton, st, c, t: float, P, law=None):  # (newton: the loop)
        model, opts, plan = newton.model, newton.opts, newton.plan
        self.newton, self.model, self.opts, self.plan = newton, model, opts, plan
        self.group = plan.group
        # S_t in the column order of a direct sparse solver, made from its structure (the
        # same matrix as ``tocsc``); an iterative or automatic solver takes S_t as it is
        direct = model.solver.name in ("direct", "superlu") and not model.dense
        self.csc = model.pattern.csc if direct else None
        # (on a group: one LieStep for the run's steps, begun at each; :func:`_inertia`'s)
        self.lie, self.first = None, (None, None)
        self.begin(st, c, t, P, law)

    def begin(self, st, c, t: float, P, law=None) -> None:
        """Start the step from ``st`` with the coefficients ``c`` to the time ``t`` (s) at
        its predictor, nothing of a previous step kept."""
        self.S = self.solve = self.armijo = self.x = self.dq = self.small = self.r = None
        self.held = None  # (modified Newton: held_factors)
        self.plain = True  # every solve was with S_t alone: S_t's solver is a metric
        self.previous, self.s = math.inf, 1.0
        self.rnorm, self.ref = math.inf, 1.0
        self.coasted = False  # (started at constant velocity: :meth:`coast`)
        model = self.model
        # on a Lie group the first row of X is the increment D, and q = q_n ⊕ D (:mod:`.lie`)
        if self.group:
            lie = self.lie
            if lie is None:
                lie = self.lie = LieStep(self.group, st.q)
            else:
                lie.start(st.q)
            X = predict_increment(st, c, self.plan.bound)
            self.step = step = StepContext(model, c, t, st, self.opts, P, X)
            step.q = lie.configuration(X[0])
        else:
            self.lie = None
            self.step = StepContext(model, c, t, st, self.opts, P, predict(st, c))

    def coast(self) -> None:
        """Start again at the predictor of constant velocity (:func:`_coast`)."""
        _coast(self)

    def residual(self, it: int) -> bool:
        """The residual r at the iterate, after the Armijo test of the last full update
        (decided by the strain energy at its end); whether the iterate has converged."""
        newton, step = self.newton, self.step
        if self.armijo is None and not newton.evaluated:  # (the elastic term alone)
            newton.elastic.evaluate(step, it)
        else:
            newton.evaluate(it, None if self.armijo is None else lambda i: _armijo(self, i))
        Mvd = _inertia(self, it)
        r = Mvd
        for term in newton.forced:
            r = term.residual(r)
        self.r = r
        ref = max(Mvd @ Mvd, 1e-300)
        for term in newton.scaled:
            x = term.reference()
            if x > ref:
                ref = x
        self.ref = math.sqrt(ref)
        self.rnorm = rnorm = math.sqrt(r @ r)
        newton.clock = newton.timer.add("assembly", newton.clock)
        if not math.isfinite(rnorm):
            fi = newton.elastic.fi
            why = "" if np.all(np.isfinite(fi)) else ": an element inverts (det F <= 0)"
            raise StepFailure(newton.name + " diverged" + why, rnorm)
        if rnorm > self.opts.tol_residual * self.ref:
            return False
        for term in newton.checked:
            if not term.converged(step):
                return False
        return True

    def update(self) -> bool:
        """One Newton update of the iterate; whether it has converged with it."""
        step, newton = self.step, self.newton
        rowed = newton.rowed
        self.small = None  # (whether dq is below the increment tolerance, where known)
        touching = [term for term in rowed if term.touching()] if rowed else None
        if not held_factors(self, touching):
            self._matrix()
        dq = _rowed_update(self, touching) if touching else self._plain_update()
        if not np.isfinite(dq).all():  # (a solve that lost its numbers: fail the step here,
            # to be halved, rather than evaluate the contacts at a non-finite iterate)
            raise StepFailure(self.newton.name + " diverged: a non-finite update", math.nan)
        step.X[:, self.model.free_slice] += np.multiply.outer(step.c.w, dq)  # q, v, v̇, a
        if self.lie is not None:  # (D, v, v̇, a): the positions q_n ⊕ D
            step.q = self.lie.configuration(step.X[0])
        newton.clock = newton.timer.add("solve", newton.clock)
        self.dq = dq
        if not rowed:
            if self.small is not None:
                return self.small
            return self.model.update_size(dq) <= self.opts.tol_increment
        return self._settled(dq)

    def _matrix(self) -> None:
        """S_t: the linear model's, with its factors, or the sum of the terms' tangents."""
        if self.plan.reuse:
            c = self.step.c
            self.S, self.solve, _ = self.model.iteration_matrix(c.bp, c.gp)
            return
        self.S = self.newton.tangent()
        if self.lie is not None:  # the stiffness moves with D through T(D)
            self.S = self.lie.iteration_matrix(self.S, self.newton.elastic.K)

    def _factors(self):
        """S_t's solver (factorized here unless reused or held)."""
        if not (self.plan.reuse or _holding(self.held)):
            symmetric = self.lie is None  # (on a group: gyroscopic forces, T(D))
            S = self.S if self.csc is None else self.csc(self.S)
            self.solve = factorize_or_fail(S, self.rnorm / self.ref, symmetric, self.model.solver)
        return self.solve

    def _schur_update(self, term):
        """The update with one term's rows through S_t's own factors."""
        solve = self._factors()
        return term.schur_update(self.step, self.r, solve, self.plan.reuse, self.rnorm / self.ref)

    def _bordered_update(self, touching):
        """The update of the saddle-point system bordered by the rows of ``touching``."""
        nF = self.model.n_free
        K, gs, Gs = self.S, [], []
        for term in touching:
            g, G, C = term.border(self.step)
            if self.lie is not None:  # the forces' curvature moves with D through T(D)
                C = self.lie.right(C)
            K = plus_curvature(K, 1.0, C)
            gs.append(g)
            Gs.append(G)
        g_rows = gs[0] if len(gs) == 1 else np.concatenate(gs)
        G_rows = Gs[0] if len(Gs) == 1 else np.vstack(Gs)
        self.x = x = self._bordered_solve(K, G_rows, g_rows)
        start = nF
        for term, g in zip(touching, gs, strict=True):
            term.take(x[start : start + g.size])
            start += g.size
        return x[:nF]

    def _bordered_solve(self, K, G, g):
        """[Δq; Δλ] of the system bordered by the rows G with gaps g. Where the matrix is
        singular because rows are redundant (more rows than the dofs they move: a rigid
        face's four corners on a plane), the update is taken on a maximal independent subset
        of them (the others' gaps follow, being dependent) and its force Gᵀ Δλ shared over all
        of them by minimum norm, counted in the run's ``redundant_row_updates``."""
        res, nF = self.rnorm / self.ref, self.model.n_free
        b = self.lie.bordered if self.lie is not None else bordered
        self.plain = False
        # where rows can be redundant (decided once per run) they are tested first: an LU
        # need not fail on them, and its near-zero pivot would spread round-off into Δq
        keep = independent_rows(G) if self.opts.stats.contact.minimum_norm else None
        if keep is None or keep.size == g.size:
            try:
                self.solve = factorize_or_fail(b(K, G), res, False, self.model.solver)
                return -self.solve(np.concatenate([self.r, g]))
            except StepFailure:
                keep = independent_rows(G)
                if keep.size == g.size:
                    raise
        Gd = G.toarray() if sp.issparse(G) else np.asarray(G)
        self.opts.stats.contact.redundant_row_updates += 1
        self.solve = factorize_or_fail(b(K, G[keep]), res, False, self.model.solver)
        y = -self.solve(np.concatenate([self.r, g[keep]]))
        # (equal shares where rows are alike, as the frictional solves' minimum-norm steps)
        lam = np.linalg.lstsq(Gd.T, Gd[keep].T @ y[nF:], rcond=None)[0]
        return np.concatenate([y[:nF], lam])

    def _plain_update(self):
        """Newton's update with S_t alone, globalized in energy where the model is
        nonlinear and the plan asks for it."""
        model, r, plan = self.model, self.r, self.plan
        solve = self._factors()
        if plan.reuse or not plan.descent:  # (linear: Π is quadratic, S_t positive definite)
            return -solve(r)
        elastic, opts, res = self.newton.elastic, self.opts, self.rnorm / self.ref
        if self.lie is not None:  # (Newton's direction, its length cut in D)
            at = (self.lie, self.step.X, opts.tol_increment, res)
            dq, test = group_direction(model, r, elastic, self.S, solve, *at)
            if isinstance(test, bool):  # (taken whole; below the tolerance or not)
                self.small = test
            else:  # (above the tolerance, tested)
                self.armijo, self.small = test, False
            return dq
        newton = (opts.tol_increment, res, opts.stats.newton, model.solver)
        shift = self.newton.mass_shift(self.step.c)
        shifts = opts.stats.newton.shifted_directions
        dq, *test = descent_direction(
            model, r, elastic.fi, self.S, elastic.K, solve, shift, *newton
        )
        if test[-1] is None:  # below the increment tolerance: taken whole
            self.small = True
            return dq
        floor = energy_roundoff(model, elastic.W)
        self.armijo = Armijo(self.step.X.copy(), dq, *test, elastic.W, res, floor)
        # Newton's own direction, measured by the descent test: above the tolerance
        self.small = False if opts.stats.newton.shifted_directions == shifts else None
        return dq

    def _settled(self, dq) -> bool:
        """Whether the update ``dq`` ended the iteration: by the joints' remainder bound, or
        below the increment tolerance with every constrained term's test holding."""
        step, newton = self.step, self.newton
        joints, rowed = newton.joints, newton.rowed
        if self.plan.bound and len(rowed) == 1 and joints is not None:
            ff = 0.0 if newton.load is None else newton.load.ff
            # (on a group: the gyroscopic forces' own remainder, exact, once the gaps pass)
            gyro = newton.gyroscopic
            extra = None if gyro is None else (lambda: gyro.remainder(step, dq))
            if joints.bound(step, dq, self.x[self.model.n_free :], ff, extra):
                return True
        if self.plan.exact and all(term.solved(step) for term in rowed):
            return True  # (the update solved the step: its residual is round-off)
        return self.model.update_size(dq) <= self.opts.tol_increment and all(
            term.settled(step) for term in rowed
        )

    def halves(self) -> bool:
        """Halve the last update that did not lower the residual (six times at most)."""
        if self.dq is not None and self.rnorm >= self.previous and self.s > 1.0 / 64.0:
            self.s *= 0.5
            step = self.step
            step.X[:, self.model.free_slice] += np.multiply.outer(step.c.w, -self.s * self.dq)
            for term in self.newton.rowed:
                term.retreat(self.s)
            return True
        self.previous, self.s = self.rnorm, 1.0
        return False

    def lam(self) -> np.ndarray:
        """The joints' multipliers λ_b (N)."""
        return self.step.st.lam.copy() if self.newton.joints is None else self.newton.joints.lam

    def metric(self):
        """(S_t, its solver) where every solve was with S_t alone and there are no joints:
        the metric of the position correction; else None (rebuilt on demand)."""
        if self.S is not None and self.plain and not _holding(self.held):
            return (self.S, self.solve) if self.newton.joints is None else None
        return None


def _rowed_update(form: AccelerationForm, touching) -> np.ndarray:
    """The ``form``'s update bordered by the rows of the ``touching`` terms: through S_t's
    own factors where one term's rows allow it, else the bordered system; on beams cut to a
    quarter turn of any node (:mod:`.turns`)."""
    term = touching[0]
    dq = _complementary_update(form, term) if len(touching) == 1 and term.complementary() else None
    if dq is not None:
        bordered = False
    elif len(touching) == 1 and term.schur and (form.lie is None or term.schur_only):
        dq, bordered = form._schur_update(term), False
    else:
        dq, bordered = form._bordered_update(touching), True
    return dq if form.opts.turns is None else _cut(form, dq, touching, bordered)


def _complementary_update(form: AccelerationForm, term):
    """The ``form``'s update with the linearised law of ``term``'s live rows solved whole
    (:mod:`.smooth_redundant`), through the factors of K = S_t plus the forces' curvature;
    None where the law does not settle."""
    lie, res = form.lie, form.rnorm / form.ref
    L, G, C = term.live_border()
    if lie is not None:  # (the forces' curvature and the rows move with D through T(D))
        C = lie.right(C)
    if C is None:
        solve = form._factors()
    else:
        K = plus_curvature(form.S, 1.0, C)
        K = K.tocsc() if sp.issparse(K) else K
        solve = factorize_or_fail(K, res, False, form.model.solver)
    form.plain = False
    Y = solve(G.T).reshape(form.model.n_free, -1)
    lower = G if lie is None else lie.right(G)
    return term.sc.complementary_update(L, -solve(form.r), Y, lower, form.step.tolerance.low)


def _cut(form: AccelerationForm, dq: np.ndarray, touching, bordered: bool) -> np.ndarray:
    """The update ``dq`` bordered by the rows of the ``touching`` terms, with their
    multipliers' update (and the ``bordered`` solve's, which the joints' remainder bound
    reads), cut to turn no beam node by more than a quarter turn
    (:class:`~fecontact.time.turns.TurnBound` of the run's settings): no energy descent
    tests these updates, and the kinematics linearized at the iterate say nothing a quarter
    turn away."""
    opts = form.opts
    fraction = opts.turns.cut(dq, opts.stats)
    if fraction == 1.0:  # (every update of a step that resolves its rotations)
        return dq
    for term in touching:
        term.retreat(1.0 - fraction)
    if bordered:
        form.x = fraction * form.x
    return fraction * dq


def _coast(form: AccelerationForm) -> None:
    """Start the ``form``'s step again at the predictor of constant velocity, q_n + h v_n (on
    a group D = h v_n), with (v, v̇, a) moved at the rates of a Newton update: the
    generalized-α relations hold, so the step's equations and root are the same, only
    Newton's first iterate is another (:meth:`fecontact.time.turns.TurnBound.start`)."""
    step, lie = form.step, form.lie
    X, st, c = step.X, step.st, step.c
    at = c.h * st.v if lie is not None else st.q + c.h * st.v
    X += np.multiply.outer(c.w, at - X[0])
    if lie is not None:  # (q = q_n ⊕ D)
        step.q = lie.configuration(X[0])
    form.coasted = True


def _inertia(form: AccelerationForm, it: int) -> np.ndarray:
    """M v̇ (N) at the ``form``'s iterate. At the predictor v̇ = v̇_n whatever the step size,
    so another step from the same state (a located impact's refining smooth step, after its
    trial) takes the product its first step made, handed out as a copy (a force term may add
    into the loop's residual in place); not a step started at constant velocity (its v̇ is
    another)."""
    step, model = form.step, form.model
    if it == 0 and form.lie is None and not form.coasted:
        st, Mvd = form.first
        if st is not step.st:
            Mvd = model.M @ step.vd[model.free_slice]
            form.first = (step.st, Mvd)
        return Mvd.copy()
    return model.M @ step.vd[model.free_slice]


def _armijo(form: AccelerationForm, it: int) -> None:
    """The Armijo test of the ``form``'s last full update, by the strain energy the elastic
    term found at its end; where it fails, the update is cut back and the term evaluated
    again."""
    step, elastic, lie = form.step, form.newton.elastic, form.lie
    armijo, form.armijo = form.armijo, None
    if not armijo.accepts(elastic.W, form.opts.stats.newton):
        s = armijo.backtrack(form.model, form.opts.stats.newton, lie)
        step.X[:] = armijo.X
        step.X[:, form.model.free_slice] += np.multiply.outer(step.c.w, s * armijo.dq)
        if lie is not None:  # (q = q_n ⊕ D)
            step.q = lie.configuration(step.X[0])
        elastic.evaluate(step, it)


def held_factors(form: AccelerationForm, touching) -> bool:
    """Modified Newton, where the ``form``'s loop is ``frozen`` on a nonlinear model off a
    group: whether the update through S_t's own factors (one term's Schur complement, the
    ``touching`` terms) keeps those of an earlier update, which it may while the relative
    residual fell by ``CONTRACTION`` since. Notes in ``form.held`` the residual at which the
    factors serve: negative where they were not made at the iterate, None where none serve
    (a bordered solve)."""
    if not form.newton.frozen or form.plan.reuse or form.lie is not None:
        return False
    res = form.rnorm / form.ref  # (relative: the reference moves with the iterate)
    if not touching:  # (a plain update: its factors of S_t may serve later ones)
        form.held = res
        return False
    if not (len(touching) == 1 and touching[0].schur):
        form.held = None
        return False
    held, form.held = form.held, res
    if held is None or not res <= CONTRACTION * abs(held):
        return False
    form.held = -res
    return True


def _holding(held) -> bool:
    """Whether the factors of S_t serving the iterate were made at an earlier one."""
    return held is not None and held < 0.0
