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

import time

import numpy as np

from ..contact.contact_set import candidates, held_together, rows_held
from ..ledger_records import pending_record
from .alpha_step import SmoothStep, alpha_plan, alpha_smooth_step
from .configuration import plus
from .constraints import StepFailure
from .correction import correction_metric, momentum_held, position_correction
from .coulomb import frictional_correction
from .generalized_alpha import coefficients
from .impacts import velocity_jump
from .penetration import check_predictor
from .position_jump import acceleration_jump, velocity_follows
from .records import FrictionRecord, SmoothForces
from .settings import RunSettings, run_settings
from .smooth_contact import (
    force_shares,
    held_shares,
    persistent_contacts,
    released,
    restarted_acceleration,
    without_released,
)
from .spin_restart import jumped
from .state import IntegratorOptions, PhaseTimer, State, length_scale

__all__ = ["SmoothStep", "alpha_smooth_step", "decoupled_step", "nsga_step", "smooth_phases"]


def nsga_step(model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer) -> State:
    """One step of the nonsmooth generalized-α method from ``st`` over ``h`` (s): the smooth
    step, the position correction and the velocity jump (module docstring)."""
    if not isinstance(opts, RunSettings):
        opts = run_settings(model, opts, plan=alpha_plan)
    step = _Phases(model, st, h, opts, timer, None)
    step.smooth()
    return step.finish(time.perf_counter())


def smooth_phases(model, st: State, h: float, opts: RunSettings, timer: PhaseTimer):
    """The NSGA step from ``st`` over ``h`` (s) after its smooth step: its ``q`` and ``v``
    are q̃ and ṽ; ``g_tilde`` may be set to the gaps at q̃ (else the correction computes
    them), and ``finish(clock)`` makes the rest of the step and returns its end state."""
    step = _Phases(model, st, h, opts, timer, None)
    step.smooth()
    return step


def decoupled_step(
    model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer, smooth_step=None
) -> tuple[State, np.ndarray]:
    """The NSGA step with step 1 made by ``smooth_step`` (default: generalized-α), and the
    positions q̃ it reached before the correction."""
    opts = run_settings(model, opts, plan=alpha_plan)
    step = _Phases(model, st, h, opts, timer, smooth_step)
    q_smooth = step.smooth()
    return step.finish(time.perf_counter()), q_smooth


class _Phases:
    """One NSGA step from ``st`` over ``h`` (s) as it is made: the smooth step, the position
    correction, the velocity jump, and the accelerations' follow-up of the correction; the
    attributes are what the phases hand each other."""

    # the attributes (slots: every access of the step's hot loop is cheaper)
    __slots__ = (
        "Gb P a c cand closed corrected force forces g_tilde gaps grip h held impulse "
        "iters kept lam m model nu opts q q_tilde record release smooth_step st st_s step t "
        "timer tol_gap together v v_tilde vd works"
    ).split()

    def __init__(self, model, st: State, h: float, opts, timer: PhaseTimer, smooth_step):
        self.model, self.st, self.h, self.opts, self.timer = model, st, h, opts, timer
        self.smooth_step = smooth_step
        # another step 1 (:mod:`.energy_step`) corrects in the metric of the trapezoidal rule
        self.c = coefficients(1.0 if smooth_step else opts.rho_inf, h)
        self.t, self.m = st.t + h, model.contacts.size
        self.record = self.forces = self.works = None  # friction, smooth forces, jump's works
        self.grip = None  # (λ_N, λ_T) of the smooth step with friction
        self.nu = self.impulse = self.gaps = self.cand = self.together = None
        self.corrected = None  # (q̃, the metric's solve) after a correction (decoupled scheme)
        self.q_tilde = self.kept = None  # q̃ after a correction moved q, Δv of its hold (ledger)
        self.g_tilde = None  # the gaps at q̃, when known before the correction
        self.release = 0.0  # what a retake without released contacts' forces put in (J)

    def smooth(self) -> np.ndarray:
        """Step 1 (taken again without the contacts it releases) and the records of its
        forces; returns q̃."""
        model, st, opts, c, t = self.model, self.st, self.opts, self.c, self.t
        P = None
        if opts.smooth:
            P = persistent_contacts(model, st, opts.detection_margin * model.length)
        self.st_s = st  # the state the smooth step starts from
        step = (self.smooth_step or alpha_smooth_step)(model, st, t, c, opts, self.timer, P)
        if opts.smooth:  # (taken again without the contacts it releases)
            self.st_s, step, self.release = _releases(model, st, step, P, opts, (t, c, self.timer))
        self.P, self.step, self.Gb, self.force = P, step, step.Gb, step.force
        self.q, self.v, self.vd, self.a, self.lam = step.q, step.v, step.vd, step.a, step.lam
        self.iters = {"smooth": step.iterations, "position": 0, "velocity": 0}
        if (opts.friction or opts.smooth) and (self.m or model.joints.size):
            self._records()
        return step.q

    def _records(self) -> None:
        model, m, step = self.model, self.m, self.step
        force = step.force
        if self.opts.friction:
            self.record = FrictionRecord.start(self.st.friction, m, model.dim)
        # (in flight, nothing to record: a record of zeros is made where a phase needs it)
        if self.opts.smooth and (force is not None or not _nothing_carried(self.st_s, self.opts)):
            normal, tangential = np.zeros(m) if force is None else force, None
            if self.opts.friction:
                tangential = np.zeros((m, model.dim - 1)) if force is None else step.friction_force
                self.record.work += step.friction_work
            shares = force_shares(model, self.st_s, self.c, force, step.friction_force)
            self.forces = SmoothForces(normal, tangential, *shares)
        # (λ_N, λ_T) of the smooth step (N): the corrections hold the step's total in the cone
        if step.friction_force is not None:
            self.grip = np.column_stack([force, step.friction_force])

    def correct(self) -> None:
        """Step 2 on the working set: the penetrating candidates and those active in the
        previous step, then any other candidate that the correction pushes below the plane
        of its gap; the work follows the contact zone, not the detection margin (a long body
        has hundreds of candidates, a few in contact)."""
        model, st, opts, m, q = self.model, self.st, self.opts, self.m, self.q
        model.contacts.set_time(self.t)
        if self.g_tilde is None:
            self.g_tilde = model.contacts.gaps(q)
        g_tilde = self.g_tilde
        if opts.depth_check:  # (decided once: without solid pairs no node can enter)
            check_predictor(model, q, g_tilde, st.q)
        cand = candidates(model.contacts, q, g_tilde, opts.detection_margin * model.length)
        self.nu, self.impulse, self.gaps, self.cand = np.zeros(m), np.zeros(m), g_tilde, cand
        if not cand.size:  # (most steps: nothing to correct, and no gap tolerance to use)
            self.tol_gap, self.closed = 0.0, cand
            return
        self.tol_gap = opts.tol_gap * length_scale(model, q)
        g_cand = g_tilde[cand]
        short = g_cand < 0.0
        if self.force is not None:  # the persistent contacts the smooth step closed are not short
            persistent = np.zeros(m, bool)  # (a mask: np.isin costs 15 µs on a few contacts)
            persistent[self.P] = True
            short &= ~(persistent[cand] & (g_cand >= -self.tol_gap))
        # (count_nonzero: a third of the time of any() on a few contacts)
        if not np.count_nonzero(short):  # (closed: the contacts closed where the step ends)
            self.closed = _closed(cand, g_tilde, self.tol_gap, self.together)
            return
        was_active = st.nu[cand] > 0.0 if st.nu.size == m else False
        if self.force is not None:  # contacts pressed by the smooth step stay closed (held)
            was_active = was_active | (self.force[cand] > 0.0)
        work = cand[short | was_active]
        q_tilde = self.q_tilde = q
        metric = correction_metric(model, q_tilde, self.step.S, self.c, opts.metric)
        while True:
            U, nu_w, friction = self._corrected(q_tilde, work, metric)
            self.q = q = plus(model, q_tilde, U)
            self.gaps = model.contacts.gaps(q)
            pushed = _pushed(cand, self.gaps[cand], self.tol_gap, opts.stats.contact.minimum_norm)
            pushed = pushed[~np.isin(pushed, work)] if pushed.size else pushed  # (most: none)
            if pushed.size == 0:
                break
            work = np.union1d(work, pushed)
        if model.inverted(q):
            raise StepFailure("the position correction inverts an element (det F <= 0)", np.nan)
        self.v, self.kept = momentum_held(opts.momentum, model, q_tilde, q, self.v, work)
        self.nu[work] = nu_w[: work.size]
        if friction is not None:
            nu_t, U_t = friction
            self.record.nu[work] = nu_t
            # the work of the positional friction against the forces at q̃, the loads at the
            # instant their work through the drift is its rate's (``Coefficients.drift_load``)
            f = model.external(st.t + self.c.drift_load * self.h)
            self.record.work += (f - model.internal(q_tilde, tangent=False)[1])[model.free] @ U_t
        self.Gb = None  # the joints' gradient moved with q
        self.corrected = None if opts.restarts else (q_tilde, metric[1])
        self.closed = _closed(cand, self.gaps, self.tol_gap, self.together)

    def _corrected(self, q_tilde, work, metric):
        """(U, k ν_N, (k ν_T, U_T) with friction else None) of the correction on ``work``."""
        model, st, opts, c = self.model, self.st, self.opts, self.c
        if opts.friction:
            pre = None if self.grip is None else self.grip[work] / c.bp  # positional multipliers
            U, nu_w, nu_t, U_t, its = frictional_correction(
                model, st, q_tilde, work, metric[1], opts, self.tol_gap, self.t, pre
            )
            self.iters["position"] += its
            return U, nu_w, (nu_t, U_t)
        nu0 = st.nu[work] / opts.multiplier_scale  # warm start: the previous step's
        held = _held(self.force, work, opts.restarts)
        U, nu_w, its = position_correction(
            model, q_tilde, work, metric, c, opts, self.tol_gap, nu0, held
        )
        self.iters["position"] += its
        return U, nu_w, None

    def jump(self) -> None:
        """Step 3 on the contacts closed at q_{n+1} and on the joints."""
        model, closed, tol_gap = self.model, self.closed, self.tol_gap
        self.v = self.v.copy() if self.v is self.v_tilde else self.v  # (in place: ṽ kept apart)
        force, grip = self.force, self.grip
        self.held = held = (
            None if force is None else held_together(model.contacts, closed, force[closed] > 0.0)
        )
        preload = None if grip is None else self.h * grip[closed]  # the smooth forces' impulse
        W, Lam, self.iters["velocity"], tangential, self.works = velocity_jump(
            model, self.st, self.q, self.v, closed, self.g_tilde, self.opts, self.t, tol_gap,
            self.Gb, held, preload, pressed=None if force is None else self.h * force[closed],
            rest=None if self.opts.smooth else (self.step.S, self.c),
        )  # fmt: skip
        state = (self.q, self.v, self.v_tilde)  # (v̇ and a follow ṽ, before a momentum hold)
        jumped(self.opts.spins, model, state, W, Lam[: closed.size], (self.vd, self.a))
        if closed.size:
            self.impulse[closed] = Lam[: closed.size]
        struck = _struck(self.impulse[closed], force, self.h, self.opts.tol_residual)
        if self.opts.restarts and _impact(self.nu, struck, held):
            self._restart()
        if tangential is not None:
            lam_t, status, work = tangential
            self.record.impulse[closed] = lam_t
            self.record.status[closed] = status
            self.record.work += work

    def _restart(self) -> None:
        """Restart the acceleration variable from the post-impact state."""
        model, closed, rate = self.model, self.closed, self.tol_gap / self.h
        fint = self.step.fint if self.q_tilde is None else None  # (at q, where not corrected)
        stats = self.opts.stats.contact
        restart = restarted_acceleration(
            model,
            self.q,
            self.v,
            self.v_tilde,
            self.t,
            closed,
            rate,
            stats,
            fint,
            tol_acc=rate / self.h,
        )
        if restart is not None:
            self.vd[model.free_slice] = self.a[model.free_slice] = restart[0]
            step = self.step
            shares = force_shares(
                model, self.st_s, self.c, step.force, step.friction_force, restart[1]
            )
            _carried(self, shares)

    def follow(self) -> None:
        """v̇, a (v without friction) follow the correction of an impact (:mod:`.position_jump`)."""
        st, closed = self.st, self.closed
        if self.corrected is None:  # (tested first: it decides most steps at no cost)
            return
        # (settling beams: also a contact closed at t_n, whose smooth force starts next step)
        if not (self.opts.settle or np.count_nonzero(_closing(self))):
            return
        model, c, opts, F = self.model, self.c, self.opts, self.model.free_slice
        q_tilde, solve_H = self.corrected
        if opts.metric != "stiffness":  # the update is always in the step's own S_t
            solve_H = correction_metric(model, q_tilde, self.step.S, c, "stiffness")[1]
        dvd, hold = acceleration_jump(
            model,
            self.q,
            q_tilde,
            self.v,
            closed,
            solve_H,
            self.tol_gap / self.h,
            stats=opts.stats.contact,
        )
        if not self.smooth_step:  # (the energy-decaying step's v̇ stays its smooth Δv/h)
            self.vd[F] += dvd
            self.a[F] += (1.0 - c.af) / (1.0 - c.am) * dvd
        if opts.smooth:
            _carried(self, held_shares(_carried(self), closed, hold, c))
        if not opts.friction:
            rows = (closed, self.g_tilde, self.Gb, self.held)
            self.v, self.impulse[closed], its = velocity_follows(
                model,
                st,
                self.q,
                self.v,
                self.v_tilde if self.kept is None else self.v_tilde + self.kept,
                dvd,
                hold,
                self.impulse[closed],
                c,
                opts,
                self.t,
                self.tol_gap,
                rows,
            )
            self.iters["velocity"] += its

    def finish(self, clock: float) -> State:
        """Steps 2 and 3 after the smooth step (``clock``: when the contact phase started),
        and the state they end in."""
        if self.m == 0 and self.model.joints.size == 0:
            return _end_state(self)
        self.v_tilde = self.v  # ṽ, the smooth step's velocity (a correction replaces self.v)
        with rows_held(self.model.contacts, self.q):  # (from q̃; a closed row stays in 3.)
            self.correct()  # 2., only if a contact candidate penetrates (joints already hold)
            if self.closed.size or self.model.joints.size:  # (else nothing to jump or follow)
                self.jump()  # 3.
                self.follow()
        if (self.opts.settle or not self.opts.positional_friction) and self.m:  # (below)
            _mark_closing(self)
        self.timer.add("contact", clock)
        return _end_state(self)


def _carried(step: _Phases, shares=None) -> SmoothForces:
    """The smooth forces' record of the ``step``, made of zeros where its smooth step had
    none to record; with ``shares`` = (in v̇, in a) (m, dim) (N), those set in it."""
    if step.forces is None:
        m, dim = step.m, step.model.dim
        step.forces = SmoothForces(np.zeros(m), None, np.zeros((m, dim)), np.zeros((m, dim)))
    if shares is not None:
        step.forces.in_vd, step.forces.in_a = shares
    return step.forces


def _mark_closing(step: _Phases) -> None:
    """Settling beams: mark in the ``step``'s record the contacts that closed within it
    (their smooth force starts a step later; in the decoupled step of the same models, their
    slip rows: a contact struck in the last step has none in the next correction); no
    record where none closed and none was made."""
    closing = step.closed[_closing(step)] if step.closed.size else step.closed
    if step.forces is not None or closing.size:
        forces = _carried(step)
        forces.closing = np.zeros(step.m)
        forces.closing[closing] = 1.0


def _nothing_carried(st: State, opts) -> bool:
    """Whether ``st`` carries no smooth force in v̇ and a (its record absent or zero), and the
    run has no friction, whose record a step keeps: a step without a smooth force then has
    nothing to record."""
    carried = st.smooth
    if opts.friction:
        return False
    return carried is None or not (carried.in_vd.any() or carried.in_a.any())


def _closing(step: _Phases) -> np.ndarray:
    """Which of the ``step``'s closed contacts were open at its start (mask)."""
    st = step.st
    if st.gaps.size != step.m:
        return np.zeros(step.closed.size, bool)
    return st.gaps[step.closed] > step.tol_gap


def _end_state(step: _Phases) -> State:
    """The state at the end of the NSGA ``step`` (ṽ left out of the ledger's record where v
    is it)."""
    at = (step.t, step.q, step.v, step.vd, step.a)
    if step.nu is None:  # no contacts, no joints: the smooth step alone
        return State(*at, h=step.h, lam=step.lam, iterations=step.iters)
    joints, cand = step.model.joints.size, step.cand
    phase = cand.size + joints  # a correction or a jump may follow (else no record)
    record = None
    if phase:
        moved = step.q_tilde is not None or step.closed.size or joints
        args = (step.v_tilde if moved else None, step.q_tilde, step.step.friction_work)
        record = pending_record(step.model, phase, *args, step.works, step.release, step.kept)
    return State(
        *at,
        h=step.h,
        lam=step.lam,
        iterations=step.iters,
        gaps=step.gaps,
        candidates=cand,
        # (uncorrected: the candidates' gaps are ≥ 0 unless a smooth force holds them, the
        # others' above the detection margin)
        outside=step.q_tilde is None and (step.force is None or not cand.size),
        nu=step.nu,
        impulse=step.impulse,
        smooth=step.forces,
        friction=step.record,
        ledger=record,
    )


def _releases(model, st, step, P, opts, at):
    """(start state, ``step``, energy put in (J)): taken again (:func:`_retake`, ``at`` = (t,
    c, timer)) without the contacts of ``P`` it releases (redundant ones closed are held)."""
    closed = (step.q, opts.tol_gap * model.length) if opts.stats.contact.minimum_norm else None
    rows = released(model, st, P, step.force, opts.tol_residual, closed)
    if not rows.size:
        return st, step, 0.0
    t, c, timer = at
    return _retake(model, st, step, rows, opts, (t, c, P, timer))


def _retake(model, st, step, rows, opts, at):
    """The smooth step from ``st`` taken again without the forces of the contacts ``rows``
    it released (:func:`without_released`; ``at`` = (t_{n+1}, coefficients, P, timer)): the
    state it starts from, the step, and the energy (J) it ends with over the first ``step``."""
    t, c, P, timer = at
    # S_t at the step's end, as its Newton's own factors are where they are a metric (on a
    # group, or with bordered rows, they are not): S_t at its start takes another share of
    # the released force out of a (the floor pendulum in space left its planar twin by
    # 3e-4 m at the first release, measured)
    solve_H = correction_metric(model, step.q, step.S, c, "stiffness")[1]
    st_s = without_released(model, st, rows, solve_H)
    opts.stats.releases += 1
    retake = alpha_smooth_step(model, st_s, t, c, opts, timer, P)
    retake = retake._replace(iterations=retake.iterations + step.iterations)
    return st_s, retake, _energy(model, retake.q, retake.v) - _energy(model, step.q, step.v)


def _energy(model, q, v) -> float:
    """T + V_strain + V_gravity (J) at (q, v)."""
    return model.kinetic_energy(v) + model.strain_energy(q) + model.potential_energy(q)


def _closed(cand, gaps, tol_gap: float, together) -> np.ndarray:
    """The candidates ``cand`` the velocity jump closes (``gaps``: every contact's): those
    within ``tol_gap``, and the rows a located impact takes together, ``together`` = (rows,
    reach (m): how far each closes within the window of rows taken together; None: none),
    within ``tol_gap`` + reach. The correction that puts back the earlier of two rows that
    close at one instant can lift the later a few tolerances out (a neighbouring node, moved
    with it); left open, it closed again picoseconds later, in a smooth step too short to
    determine its contact forces, whose signs then followed k (``two_balls.md``)."""
    closed = cand[gaps[cand] <= tol_gap]
    if together is None:
        return closed
    rows, reach = together
    return np.union1d(closed, rows[gaps[rows] <= tol_gap + reach])


def _pushed(cand, gaps, tol_gap: float, redundant: bool) -> np.ndarray:
    """The candidates the correction left below −tol_gap, and, where rows can be redundant,
    those it left touching within the tolerance (g ≤ tol_gap): a box face's fourth corner
    lands with the other three, and whether it shares their load must not depend on the
    round-off of its gap."""
    return cand[gaps <= tol_gap] if redundant else cand[gaps < -tol_gap]


def _held(force, work, restarts: bool):
    """The mask over ``work`` of the contacts that the correction holds as equalities: those a
    smooth ``force`` presses, where the acceleration ``restarts`` after an impact (solids,
    rigid bodies), whose restart keeps their force; None elsewhere. On beams two rows at a
    node (the elements each side of a disk pressed into the strip's kink) held so took
    opposite impulses of 6.6e3 N·s (docs/explanation/energy_ledger.md, *Lasting contact of
    beams*)."""
    return None if force is None or not restarts else force[work] > 0.0


def _impact(nu, struck, held) -> bool:
    """Whether the step stopped a contact that was not held by a smooth force: a position
    correction, or an impulse (``struck``: mask) on a contact outside the held ones
    (``held``: mask or None)."""
    if np.count_nonzero(nu > 0.0):
        return True
    return bool(np.count_nonzero(struck if held is None else struck & ~held))


def _struck(impulse, force, h: float, rtol: float) -> np.ndarray:
    """The contacts whose impulse (N s) is above ``rtol`` (the smooth Newton's relative
    tolerance) of the step's smooth impulse h max λ (``force``: the smooth forces (N), or
    None: any positive impulse). Below it an impulse is zero within the solves: round-off on
    rows redundant with the held ones (1e-17 N s beside 0.08 N s, an elastic ball pressed on
    a box beside its edge) decided whether the acceleration restarted, and the path with it."""
    floor = 0.0 if force is None else rtol * h * float(np.maximum.reduce(force, initial=0.0))
    return impulse > floor
