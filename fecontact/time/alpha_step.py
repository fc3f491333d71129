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
from .settings import run_settings
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
    opts = run_settings(model, opts)
    F, nF = model.free_slice, model.n_free
    X = predict(st, c)
    q, v, vd, a = X
    lam = st.lam.copy()
    fext = model.external(t)[F]
    ff = fext @ fext
    joints = model.joints
    nb = joints.size
    alpha, beta_k = model.damping
    sc = None
    if P is not None and P.size:
        model.contacts.set_time(t)
        force = None if st.smooth is None else st.smooth.normal
        if opts.friction:
            sc = SmoothFriction(model, st, P, t, opts)
        else:
            force0 = np.zeros(P.size) if force is None else force[P]
            sc = SmoothContacts(model, P, force0, c.bp, opts)
    curved = sc is not None and not model.contacts.linear
    tol_b = JointTolerance(model, q, opts.tol_gap) if nb or sc else None
    S = Gb = None
    plain = True  # every solve was with S_t alone (not bordered): S_t's solver is a metric
    # linear bodies: S_t = β′M + γ′C + K is assembled and factorized once per step size;
    # joints border it with their (q-dependent) gradient and curvature
    linear = model.linear
    # ... and then the joints' Taylor remainders bound the residual an update leaves
    bounded = linear and nb and not joints.linear and sc is None
    clock = time.perf_counter()
    armijo = None  # the test of the last full update, decided by the energy at its end
    for it in range(opts.max_iterations + 1):
        W, fint, K = model.internal(q, tangent=not linear)
        if armijo is not None and not armijo.accepts(W):
            s = armijo.backtrack(model, opts.stats.newton)
            X[:] = armijo.X
            X[:, F] += np.multiply.outer(c.w, s * armijo.dq)
            W, fint, K = model.internal(q, tangent=not linear)
        armijo = None
        fi = fint[F]
        Mvd = model.M @ vd[F]
        r = Mvd + fi - fext
        if alpha or beta_k:
            Ct = model.iteration_matrix(c.bp, c.gp)[2] if linear else alpha * model.M + beta_k * K
            r += Ct @ v[F]
        if nb:
            # the joints' curvature where a solve is sure to follow (the first iteration),
            # else only once one does
            first = it == 0 and not joints.linear
            gb, Gb, Cb = joints.linearize(q, joints.all, lam if first else None)
            r += Gb.T @ lam
        if sc is not None:
            sc.update(q, curved)
            r -= sc.force_term()
        clock = timer.add("assembly", clock)
        ref = math.sqrt(max(ff, fi @ fi, Mvd @ Mvd, 1e-300))
        rnorm = math.sqrt(r @ r)
        if not math.isfinite(rnorm):
            why = "" if np.all(np.isfinite(fi)) else ": an element inverts (det F <= 0)"
            raise StepFailure("smooth step diverged" + why, rnorm)
        if (
            rnorm <= opts.tol_residual * ref
            and (not nb or tol_b.admits(np.abs(gb).max()))
            and (sc is None or sc.satisfied(tol_b.admits))
        ):
            break
        if it == opts.max_iterations:
            raise StepFailure("smooth step", rnorm / ref)
        if linear:
            S, solve, _ = model.iteration_matrix(c.bp, c.gp)
        else:
            S = model.iteration_sum(c.bp, K)
            if alpha or beta_k:
                S = S + c.gp * Ct
        touching = sc is not None and sc.active.any()
        if touching and not nb:  # S_t's own factors, and the contact zone's curvature
            if not linear:
                solve = factorize_or_fail(S, rnorm / ref, True, model.solver)
            if sc.C is None:  # straight gaps: S_t⁻¹G_jᵀ kept per contact on a linear body
                dq = sc.schur_update(model, r, solve, (c.bp, c.gp) if linear else None)
            else:
                units = unit_columns(model, ("smooth", c.bp, c.gp), solve, linear)
                dq = sc.schur_update(model, r, _with_curvature(solve, sc.C, units, rnorm / ref))
        elif nb or touching:
            if nb and Cb is None and not joints.linear:
                Cb = joints.curvature(q, joints.all, lam)
            Kb = plus_curvature(S, 1.0, Cb if nb else None)
            g_rows, G_rows = (gb, Gb) if nb else (np.zeros(0), np.zeros((0, nF)))
            if touching:
                gA, GA = sc.rows()
                Kb = plus_curvature(Kb, 1.0, sc.C)
                g_rows, G_rows = np.concatenate([g_rows, gA]), np.vstack([G_rows, GA])
            solve = factorize_or_fail(bordered(Kb, G_rows), rnorm / ref, False, model.solver)
            plain = False
            x = -solve(np.concatenate([r, g_rows]))
            dq, lam = x[:nF], lam + x[nF : nF + nb]
            if touching:
                sc.take(x[nF + nb :])
        else:
            if not linear:
                solve = factorize_or_fail(S, rnorm / ref, True, model.solver)
            if linear:  # Π is quadratic and S_t positive definite: Newton's step is exact
                dq = -solve(r)
            else:
                shift, res = c.bp * model.M, rnorm / ref
                newton = (opts.tol_increment, res, opts.stats.newton, model.solver)
                dq, *test = descent_direction(model, r, fi, S, K, solve, shift, *newton)
                if test[-1] is not None:
                    armijo = Armijo(X.copy(), dq, *test, W, res)
        X[:, F] += np.multiply.outer(c.w, dq)  # q, v, v̇, a
        clock = timer.add("solve", clock)
        if (bounded and _converged_by_bound(model, vd, dq, lam, x[nF:], ff, tol_b, opts)) or (
            model.update_size(dq) <= opts.tol_increment
            and (not nb or tol_b.admits(np.abs(gb).max()))
            and (sc is None or sc.settled(q, tol_b.admits))
        ):
            it += 1
            Gb = None
            break
    # the metric of the position correction reuses S_t and its factors; a bordered
    # factorization (joints) is no metric, so then S_t is rebuilt on demand
    S = (S, solve) if S is not None and plain and not nb else None
    if isinstance(sc, SmoothFriction):
        force, force_t = sc.forces(model.contacts.size)
        return SmoothStep(q, v, vd, a, lam, S, it, Gb, force, force_t, sc.work())
    force = None if sc is None else sc.forces(model.contacts.size)
    return SmoothStep(q, v, vd, a, lam, S, it, Gb, force, None, 0.0)


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
