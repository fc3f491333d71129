r"""Nonsmooth generalized-α time integration, in its fully decoupled form.

After Brüls, Acary & Cardona (2014) and Cosimo, Galvez, Cavalieri, Cardona & Brüls (2020).
Notation: q positions (displacements and rotations), v velocities, v̇ accelerations, a the
acceleration-like variable of Arnold & Brüls, h the step, M the constant mass matrix,
f_int(q) the internal force with tangent K_t, f_ext(t) the external force.

Parameters from the spectral radius at infinite frequency ρ∞ ∈ [0, 1] (Chung & Hulbert):

    α_m = (2ρ∞ − 1)/(ρ∞ + 1),  α_f = ρ∞/(ρ∞ + 1),  γ = ½ + α_f − α_m,  β = ¼(γ + ½)².

One step from t_n to t_{n+1} = t_n + h:

1. smooth step: Newton on M v̇_{n+1} + f_int(q̃_{n+1}) − f_ext(t_{n+1}) = 0 with
   (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) v̇_{n+1} + α_f v̇_n,
   q̃_{n+1} = q_n + h v_n + h²(½ − β) a_n + h² β a_{n+1},
   ṽ_{n+1} = v_n + h(1 − γ) a_n + h γ a_{n+1};
   iteration matrix S_t = β′M + K_t, β′ = (1 − α_m)/(β h² (1 − α_f)), γ′ = γ/(β h);
2. position correction q_{n+1} = q̃_{n+1} + U with H U = Σ G_jᵀ [k ν_j − p g_j(q_{n+1})]_+
   (Alart–Curnier, eq. 9 of the 2014 paper); the metric H is S_t/β′ or M;
3. velocity jump v_{n+1} = ṽ_{n+1} + W with M W = Σ G_jᵀ [k Λ_j − p ġ_j]_+ and
   ġ_j = G_j(q_{n+1}) v_{n+1} + e_j G_j(q_n) v_n (eq. 10).

W never enters a or v̇; after the correction of a step in which a contact closed, v̇ and a take
the step's response to the strain of U (:mod:`.position_jump`, Δv̇ = −β′S_t⁻¹[f_int(q̃ + U) −
f_int(q̃)]) in the decoupled scheme and on beams, and v its share hγΔa before Newton's law is
applied again; solids with smooth contact restart them (:mod:`.smooth_contact`).
Impacts make the global error first order. Steps without a contact candidate skip 2 and 3.
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from ..joints import newton_remainder
from ..linalg import low_rank_solver
from .constraints import (
    StepFailure,
    bordered,
    factorize_or_fail,
    plus_curvature,
)
from .correction import correction_metric, position_correction, unit_columns
from .coulomb import SmoothFriction, frictional_correction
from .descent import Armijo, descent_direction
from .generalized_alpha import coefficients, predict
from .impacts import velocity_jump
from .position_jump import acceleration_jump, velocity_follows
from .records import FrictionRecord, SmoothForces
from .settings import run_settings
from .smooth_contact import (
    SmoothContacts,
    force_shares,
    held_shares,
    persistent_contacts,
    released,
    restarted_acceleration,
    without_released,
)
from .state import IntegratorOptions, JointTolerance, PhaseTimer, State, length_scale

__all__ = ["decoupled_step", "nsga_step"]


def nsga_step(model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer) -> State:
    """One step of the nonsmooth generalized-α method from ``st`` over ``h`` (s): the smooth
    step, the position correction and the velocity jump (module docstring)."""
    return decoupled_step(model, st, h, opts, timer)[0]


def decoupled_step(
    model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer, smooth_step=None
) -> tuple[State, np.ndarray]:
    """The NSGA step with step 1 made by ``smooth_step`` (default: generalized-α), and the
    positions q̃ it reached before the correction."""
    opts = run_settings(model, opts)
    # another step 1 (:mod:`.energy_step`) corrects in the metric of the trapezoidal rule
    c = coefficients(1.0 if smooth_step else opts.rho_inf, h)
    t = st.t + h
    m, joints = model.contacts.size, model.joints
    smooth, restarts, friction = opts.smooth, opts.restarts, opts.friction
    P = persistent_contacts(model, st, opts.detection_margin * model.length) if smooth else None
    st_s = st  # the state the smooth step starts from
    step = (smooth_step or _smooth_step)(model, st, t, c, opts, timer, P)
    if smooth and (rows := released(st, P, step.force, opts.tol_residual)).size:
        st_s, first = without_released(model, st, rows), step.iterations
        opts.stats.releases += 1
        step = _smooth_step(model, st_s, t, c, opts, timer, P)
        step = step._replace(iterations=step.iterations + first)
    q, v, vd, a, lam, S, it, Gb, force, smooth_t, work_t = step
    iters = {"smooth": it, "position": 0, "velocity": 0}
    clock = time.perf_counter()
    if m == 0 and joints.size == 0:
        return State(t, q, v, vd, a, h=h, lam=lam, iterations=iters), q
    record = FrictionRecord.start(st.friction, m, model.dim) if friction else None
    forces = None  # the smooth forces' record
    if smooth:
        normal, tangential = np.zeros(m) if force is None else force, None
        if friction:
            tangential = np.zeros((m, model.dim - 1)) if force is None else smooth_t
            record.work += work_t
        forces = SmoothForces(normal, tangential, *force_shares(model, st_s, c, force, smooth_t))
    q_smooth = q
    # (λ_N, λ_T) of the smooth step (N): the corrections hold the step's total in the cone
    grip = None if smooth_t is None else np.column_stack([force, smooth_t])

    # 2. position correction, only if a contact candidate penetrates (joints already hold)
    model.contacts.set_time(t)
    g_tilde = model.contacts.gaps(q)
    cand = (g_tilde <= opts.detection_margin * model.length).nonzero()[0]
    # (only the candidates use the gap tolerance)
    tol_gap = opts.tol_gap * length_scale(model, q) if cand.size else 0.0
    nu, impulse, gaps = np.zeros(m), np.zeros(m), g_tilde
    short = g_tilde[cand] < 0.0
    corrected = None  # (q̃, the metric's solve) after a correction of the decoupled scheme
    if force is not None:  # the persistent contacts the smooth step closed are not short
        short &= ~(np.isin(cand, P) & (g_tilde[cand] >= -tol_gap))
    if short.any():
        # the working set: the penetrating candidates and those active in the previous step,
        # then any other candidate that the correction pushes below the plane of its gap; the
        # work follows the contact zone, not the detection margin (a long body has hundreds
        # of candidates, a few in contact)
        was_active = st.nu[cand] > 0.0 if st.nu.size == m else False
        if grip is not None:  # contacts gripped by the smooth step keep their grip
            was_active = was_active | (force[cand] > 0.0)
        work = cand[short | was_active]
        q_tilde = q
        metric = correction_metric(model, q_tilde, S, c, opts.metric)
        while True:
            if friction:
                pre = None if grip is None else grip[work] / c.bp  # as positional multipliers
                U, nu_w, nu_t, U_t, its = frictional_correction(
                    model, st, q_tilde, work, metric[1], opts, tol_gap, t, pre
                )
            else:
                nu0 = st.nu[work] / opts.multiplier_scale  # warm start: the previous step's
                U, nu_w, its = position_correction(
                    model, q_tilde, work, metric, c, opts, tol_gap, nu0
                )
            iters["position"] += its
            q = q_tilde.copy()
            q[model.free_slice] += U
            gaps = model.contacts.gaps(q)
            pushed = cand[gaps[cand] < -tol_gap]
            pushed = pushed[~np.isin(pushed, work)]
            if pushed.size == 0:
                break
            work = np.union1d(work, pushed)
        if model.inverted(q):
            raise StepFailure("the position correction inverts an element (det F <= 0)", np.nan)
        nu[work] = nu_w[: work.size]
        if friction:
            record.nu[work] = nu_t
            # the work of the positional friction against the forces at q̃ (exact for the
            # constant forces of rigid bodies under gravity)
            f = model.external(t) - model.internal(q_tilde, tangent=False)[1]
            record.work += f[model.free] @ U_t
        Gb = None  # the joints' gradient moved with q
        corrected = None if restarts else (q_tilde, metric[1])

    # 3. velocity jump on the contacts closed at q_{n+1}, and on the joints
    closed = cand[gaps[cand] <= tol_gap] if cand.size else cand
    if closed.size or joints.size:
        held = None if force is None else force[closed] > 0.0
        v_tilde = v.copy()  # ṽ, the smooth step's velocity
        preload = None if grip is None else h * grip[closed]  # the smooth forces' impulse
        W, Lam, iters["velocity"], tangential = velocity_jump(
            model, st, q, v, closed, g_tilde, opts, t, tol_gap, Gb, held, preload
        )
        v[model.free_slice] += W
        if closed.size:
            impulse[closed] = Lam[: closed.size]
        if restarts and _impact(nu, impulse[closed], held):
            # restart the acceleration variable from the post-impact state
            restart = restarted_acceleration(
                model, q, v, v_tilde, t, closed, tol_gap / h, opts.stats.contact
            )
            if restart is not None:
                vd[model.free_slice] = a[model.free_slice] = restart[0]
                shares = force_shares(model, st_s, c, force, smooth_t, restart[1])
                forces.in_vd, forces.in_a = shares
        if tangential is not None:
            lam_t, status, work = tangential
            record.impulse[closed] = lam_t
            record.status[closed] = status
            record.work += work
    # v̇ and a follow the correction (:mod:`.position_jump`) in a step where a contact closed
    impact = st.gaps.size == m and np.any(st.gaps[closed] > tol_gap)
    if corrected is not None and impact:
        q_tilde, solve_H = corrected
        if opts.metric != "stiffness":  # the update is always in the step's own S_t
            solve_H = correction_metric(model, q_tilde, S, c, "stiffness")[1]
        dvd, hold = acceleration_jump(
            model, q, q_tilde, v, closed, solve_H, tol_gap / h, stats=opts.stats.contact
        )
        if not smooth_step:  # (the energy-decaying step's v̇ stays its smooth Δv/h)
            vd[model.free_slice] += dvd
            a[model.free_slice] += (1.0 - c.af) / (1.0 - c.am) * dvd
        if smooth:
            forces.in_vd, forces.in_a = held_shares(forces, closed, hold, c)
        if not friction:
            v, impulse[closed], its = velocity_follows(
                model,
                st,
                q,
                v,
                v_tilde,
                dvd,
                hold,
                impulse[closed],
                c,
                opts,
                t,
                tol_gap,
                (closed, g_tilde, Gb, held),
            )
            iters["velocity"] += its
    timer.add("contact", clock)
    return State(
        t,
        q,
        v,
        vd,
        a,
        h=h,
        gaps=gaps,
        candidates=cand,
        nu=nu,
        impulse=impulse,
        lam=lam,
        iterations=iters,
        smooth=forces,
        friction=record,
    ), q_smooth


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


def _impact(nu, impulse, held) -> bool:
    """Whether the step stopped a contact that was not held by a smooth force: a position
    correction, or an impulse on a contact outside the held ones (``held``: mask or None)."""
    if np.any(nu > 0.0):
        return True
    new = impulse > 0.0
    return bool(np.any(new if held is None else new & ~held))


def _smooth_step(model, st, t, c, opts, timer, P=None) -> SmoothStep:
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
