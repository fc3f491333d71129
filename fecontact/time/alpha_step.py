"""Step 1 of the NSGA step, the smooth generalized-α step: Newton on the equations of motion
with the joints (index 3) and the smooth forces of persistent contacts
(:mod:`.smooth_contact`), globalized in units of energy (:mod:`.descent`)."""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from ..joints import newton_remainder
from ..linalg import low_rank_solver
from .constraints import StepFailure, bordered, factorize_or_fail, plus_curvature
from .correction import unit_columns
from .coulomb import SmoothFriction
from .descent import Armijo, descent_direction
from .generalized_alpha import predict
from .lie import LieStep, on_group, predict_increment
from .settings import RunSettings, run_settings
from .smooth_contact import SmoothContacts
from .state import JointTolerance

__all__ = ["SmoothStep", "alpha_smooth_step"]


class SmoothStep(NamedTuple):
    """The smooth step's result: positions, velocities, accelerations v̇ and a, joint
    multipliers λ (N), the iteration matrix with its solver for the correction metric (None
    with joints), the Newton iterations, and the joints' gradient at q (None when stale)."""

    q: np.ndarray
    v: np.ndarray
    vd: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    S: tuple | None
    iterations: int
    Gb: np.ndarray | None
    force: np.ndarray | None  # λ of every contact (N), None without persistent contacts
    friction_force: np.ndarray | None  # λ_T (m, nt) (N), None without persistent friction
    friction_work: float  # the energy λ_T dissipated over the step's slip (J)


def alpha_smooth_step(model, st, t, c, opts, timer, P=None) -> SmoothStep:
    """Step 1: Newton on M v̇ + C_t v + f_int(q) + G_bᵀλ_b − G_Pᵀλ = f_ext(t), g_b(q) = 0,
    0 ≤ g_P(q) ⊥ λ ≥ 0 on the persistent contacts ``P`` (:mod:`.smooth_contact`).

    Returns a :class:`SmoothStep`: S = (S_t, its solver) for the metric of the position
    correction (None with joints), G_b the joint gradient at the returned q (None when the
    last update moved q after it was evaluated)."""
    if not isinstance(opts, RunSettings):
        opts = run_settings(model, opts)
    newton = _AlphaNewton(model, st, t, c, opts, timer, P)
    for it in range(opts.max_iterations + 1):
        if newton.residual(it):
            return newton.result(it, stale=False)
        if it == opts.max_iterations:
            raise StepFailure("smooth step", newton.rnorm / newton.ref)
        if newton.update():
            return newton.result(it + 1, stale=True)
    raise AssertionError("unreachable")


def _smooth_contacts(model, st, t, c, opts, P):
    """The persistent contacts ``P`` (not empty) as a force term of the smooth step."""
    model.contacts.set_time(t)
    if opts.friction:
        return SmoothFriction(model, st, P, t, opts)
    force = None if st.smooth is None else st.smooth.normal
    force0 = np.zeros(P.size) if force is None else force[P]
    return SmoothContacts(model, P, force0, c.bp, opts)


class _AlphaNewton:
    """The Newton iteration of one smooth step: the iterate X = (q, v, v̇, a) from the
    predictor, the joints' multipliers λ_b and the persistent contacts' term ``sc``;
    ``residual`` evaluates and tests the iterate, ``update`` moves it."""

    # the attributes (slots: every access of the step's hot loop is cheaper)
    __slots__ = (
        "Cb Ct F Gb K S W X a alpha armijo beta_k bounded c clock curved fext ff fi gb "
        "joints lam lie linear model nF nb opts plain q r ref rnorm sc solve timer tol_b "
        "unconstrained v vd x"
    ).split()

    def __init__(self, model, st, t, c, opts, timer, P):
        self.model, self.c, self.opts, self.timer = model, c, opts, timer
        self.F, self.nF = model.free_slice, model.n_free
        # on a Lie group (rotation vectors, gyroscopic forces; decided once per model) the
        # first row of X is the increment D and q = q_n ⊕ D is evaluated from it (:mod:`.lie`)
        self.lie = LieStep(model, st.q, c) if on_group(model) else None
        if self.lie is None:
            self.X = X = predict(st, c)
            self.q, self.v, self.vd, self.a = X  # views: the rows follow every update of X
        else:
            self.X = X = predict_increment(st, c)
            _, self.v, self.vd, self.a = X
            self.q = self.lie.configuration(X[0])
        self.lam = st.lam.copy()
        self.fext = model.external(t)[self.F]
        self.ff = self.fext @ self.fext
        self.joints, self.nb = model.joints, model.joints.size
        self.alpha, self.beta_k = model.damping
        self.sc = sc = (
            None if P is None or not P.size else _smooth_contacts(model, st, t, c, opts, P)
        )
        self.curved = sc is not None and not model.contacts.linear
        self.tol_b = JointTolerance(model, self.q, opts.tol_gap) if self.nb or sc else None
        self.S = self.Gb = self.solve = self.armijo = self.x = None
        self.gb = self.Cb = self.Ct = None  # the joints' rows and curvature, the damping
        self.plain = True  # every solve was with S_t alone (not bordered): S_t's solver is a metric
        # linear bodies: S_t = β′M + γ′C + K is assembled and factorized once per step size;
        # joints border it with their (q-dependent) gradient and curvature
        self.linear = model.linear and self.lie is None
        # ... and then the joints' Taylor remainders bound the residual an update leaves
        self.bounded = self.linear and self.nb and not self.joints.linear and sc is None
        self.unconstrained = not self.nb and sc is None
        self.clock = time.perf_counter()

    def residual(self, it: int) -> bool:
        """The residual r at the iterate, after the Armijo test of the last full update
        (decided by the energy at its end); whether the iterate has converged."""
        model, c, F, joints = self.model, self.c, self.F, self.joints
        q, v, vd = self.q, self.v, self.vd
        W, fint, K = model.internal(q, tangent=not self.linear)
        armijo, self.armijo = self.armijo, None
        if armijo is not None and not armijo.accepts(W):
            s = armijo.backtrack(model, self.opts.stats.newton)
            self.X[:] = armijo.X
            self.X[:, F] += np.multiply.outer(c.w, s * armijo.dq)
            W, fint, K = model.internal(q, tangent=not self.linear)
        fi = fint[F]
        Mvd = model.M @ vd[F]
        r = Mvd + fi - self.fext
        r += self._velocity_forces(K, v)  # (0.0 without damping and rotating bodies)
        if self.nb:
            # the joints' curvature where a solve is sure to follow (the first iteration),
            # else only once one does
            first = it == 0 and not joints.linear
            self.gb, self.Gb, self.Cb = joints.linearize(q, joints.all, self.lam if first else None)
            r += self.Gb.T @ self.lam
        if self.sc is not None:
            self.sc.update(q, self.curved)
            r -= self.sc.force_term()
        self.clock = self.timer.add("assembly", self.clock)
        self.r, self.fi, self.W, self.K = r, fi, W, K
        self.ref = math.sqrt(max(self.ff, fi @ fi, Mvd @ Mvd, 1e-300))
        self.rnorm = rnorm = math.sqrt(r @ r)
        if not math.isfinite(rnorm):
            why = "" if np.all(np.isfinite(fi)) else ": an element inverts (det F <= 0)"
            raise StepFailure("smooth step diverged" + why, rnorm)
        return (
            rnorm <= self.opts.tol_residual * self.ref
            and (not self.nb or self.tol_b.admits(np.abs(self.gb).max()))
            and (self.sc is None or self.sc.satisfied(self.tol_b.admits))
        )

    def _velocity_forces(self, K, v):
        """The damping force C_t v and the inertial forces of rotating bodies (:mod:`.lie`)."""
        f = 0.0
        if self.alpha or self.beta_k:
            f = self._damping(K) @ v[self.F]
        if self.lie is not None:
            f = f + self.lie.inertial(self.q, v)
        return f

    def _damping(self, K):
        """C_t = αM + βK_t (kept for the iteration matrix)."""
        model, c = self.model, self.c
        if self.linear:
            self.Ct = model.iteration_matrix(c.bp, c.gp)[2]
        else:
            self.Ct = self.alpha * model.M + self.beta_k * K
        return self.Ct

    def update(self) -> bool:
        """One Newton update of the iterate; whether it has converged with it."""
        sc, model, c = self.sc, self.model, self.c
        if self.linear:  # S_t = β′M + γ′C + K_t, factorized once per step size
            self.S, self.solve, _ = model.iteration_matrix(c.bp, c.gp)
        else:
            self.S = model.iteration_sum(c.bp, self.K)
            if self.Ct is not None:
                self.S = self.S + c.gp * self.Ct
        if self.lie is not None:
            self.S = self.lie.iteration_matrix(self.S, self.K)
        S = self.S
        touching = sc is not None and sc.active.any()
        # S_t's own factors, and the contact zone's curvature (S_t symmetric: not on a group)
        if touching and not self.nb and self.lie is None:
            dq = self._contact_update(S)
        elif self.nb or touching:
            dq = self._bordered_update(S, touching)
        else:
            dq = self._plain_update(S)
        self.X[:, self.F] += np.multiply.outer(c.w, dq)  # q, v, v̇, a
        if self.lie is not None:  # (D, v, v̇, a): the positions q_n ⊕ D
            self.q = self.lie.configuration(self.X[0])
        self.clock = self.timer.add("solve", self.clock)
        if self.unconstrained:  # (decided once: no joints, no persistent contacts)
            return model.update_size(dq) <= self.opts.tol_increment
        return self._settled(dq)

    def _contact_update(self, S):
        """The update with the persistent contacts' rows through S_t's own factors."""
        model, c, sc, residual = self.model, self.c, self.sc, self.rnorm / self.ref
        if not self.linear:
            self.solve = factorize_or_fail(S, residual, True, model.solver)
        if sc.C is None:  # straight gaps: S_t⁻¹G_jᵀ kept per contact on a linear body
            return sc.schur_update(model, self.r, self.solve, (c.bp, c.gp) if self.linear else None)
        units = unit_columns(model, ("smooth", c.bp, c.gp), self.solve, self.linear)
        return sc.schur_update(model, self.r, _with_curvature(self.solve, sc.C, units, residual))

    def _bordered_update(self, S, touching: bool):
        """The update of the saddle-point system bordered by the joints and the active
        persistent contacts."""
        model, nb, nF, joints, sc = self.model, self.nb, self.nF, self.joints, self.sc
        if nb and self.Cb is None and not joints.linear:
            self.Cb = joints.curvature(self.q, joints.all, self.lam)
        Cb = self.Cb if nb else None
        if self.lie is not None:  # the forces' curvature moves with D through T(D)
            Cb = self.lie.right(Cb)
        Kb = plus_curvature(S, 1.0, Cb)
        g_rows, G_rows = (self.gb, self.Gb) if nb else (np.zeros(0), np.zeros((0, nF)))
        if touching:
            gA, GA = sc.rows()
            Kb = plus_curvature(Kb, 1.0, sc.C)
            g_rows, G_rows = np.concatenate([g_rows, gA]), np.vstack([G_rows, GA])
        residual = self.rnorm / self.ref
        A = bordered(Kb, G_rows) if self.lie is None else self.lie.bordered(Kb, G_rows)
        self.solve = factorize_or_fail(A, residual, False, model.solver)
        self.plain = False
        self.x = x = -self.solve(np.concatenate([self.r, g_rows]))
        dq, self.lam = x[:nF], self.lam + x[nF : nF + nb]
        if touching:
            sc.take(x[nF + nb :])
        return dq

    def _plain_update(self, S):
        """Newton's update with S_t alone, globalized where the model is nonlinear."""
        model, r = self.model, self.r
        if self.lie is not None:  # S_t is not symmetric (gyroscopic, T(D)): plain Newton
            self.plain = False
            return -factorize_or_fail(S, self.rnorm / self.ref, False, model.solver)(r)
        if not self.linear:
            self.solve = factorize_or_fail(S, self.rnorm / self.ref, True, model.solver)
        if self.linear:  # Π is quadratic and S_t positive definite: Newton's step is exact
            return -self.solve(r)
        shift, res = self.c.bp * model.M, self.rnorm / self.ref
        newton = (self.opts.tol_increment, res, self.opts.stats.newton, model.solver)
        dq, *test = descent_direction(model, r, self.fi, S, self.K, self.solve, shift, *newton)
        if test[-1] is not None:
            self.armijo = Armijo(self.X.copy(), dq, *test, self.W, res)
        return dq

    def _settled(self, dq) -> bool:
        """Whether the update ``dq`` ended the iteration: by the joints' remainder bound, or
        below the increment tolerance with the constraints holding."""
        model, opts, tol_b, nF = self.model, self.opts, self.tol_b, self.nF
        vd, lam = self.vd, self.lam
        if self.bounded and _converged_by_bound(
            model, vd, dq, lam, self.x[nF:], self.ff, tol_b, opts
        ):
            return True
        return (
            model.update_size(dq) <= opts.tol_increment
            and (not self.nb or tol_b.admits(np.abs(self.gb).max()))
            and (self.sc is None or self.sc.settled(self.q, tol_b.admits))
        )

    def result(self, it: int, stale: bool) -> SmoothStep:
        """The step's result after ``it`` iterations; ``stale``: the last update moved q
        after the joints' gradient was evaluated."""
        q, v, vd, a = self.q, self.v, self.vd, self.a
        Gb = None if stale else self.Gb
        # the metric of the position correction reuses S_t and its factors; a bordered
        # factorization (joints) is no metric, so then S_t is rebuilt on demand
        S = (self.S, self.solve) if self.S is not None and self.plain and not self.nb else None
        sc, m = self.sc, self.model.contacts.size
        if isinstance(sc, SmoothFriction):
            force, force_t = sc.forces(m)
            return SmoothStep(q, v, vd, a, self.lam, S, it, Gb, force, force_t, sc.work())
        force = None if sc is None else sc.forces(m)
        return SmoothStep(q, v, vd, a, self.lam, S, it, Gb, force, None, 0.0)


def _with_curvature(solve, C, units, residual):
    """(S + C)⁻¹ from S's ``solve`` and the columns S⁻¹e_i (``units``) of the few dofs the
    curvature C of the contact forces touches (:func:`fecontact.linalg.low_rank_solver`)."""
    try:
        return low_rank_solver(solve, -C, units)
    except np.linalg.LinAlgError:
        raise StepFailure("singular smooth-step matrix in contact", residual) from None


def _converged_by_bound(model, vd, dq, lam, dlam, ff, tol_b, opts) -> bool:
    """Whether the smooth step has converged after the update (dq, dλ), without evaluating
    the residual: in a linear model with joints the residual left is the joints' Taylor
    remainder (:func:`fecontact.joints.newton_remainder`), and when its bound is below half
    the tolerances the residual test of the next iteration passes, at the same q: that
    iteration only confirms. The other half covers the round-off of the solve. The reference
    max(|f_ext|, |M v̇|) is at most that of the test (which includes |f_int|). ``tol_b`` is the
    joints' :class:`JointTolerance`."""
    bound = newton_remainder(model.joints, dq, lam, dlam)
    if bound is None:
        return False
    gap, force = bound
    if not tol_b.admits(gap, 0.5):
        return False
    limit = 0.5 * opts.tol_residual
    if force <= limit * math.sqrt(ff):
        return True
    Mvd = model.M @ vd[model.free_slice]
    return force <= limit * math.sqrt(Mvd @ Mvd)
