"""The velocity jump of the decoupled step: Newton's impact law on the contacts closed at
q_{n+1}, the joints' velocity constraints, and Coulomb friction where the contacts have it."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..contact.restitution import impulse_work
from ..ledger_records import smooth_record
from ..ledger_works import jump_work
from ..linalg import factorize
from .constraints import Constraints, StepFailure, constraint_columns, impact_law, pulled_held_rows
from .correction import correction_metric
from .coulomb import frictional_jump
from .poisson import poisson_jump

__all__ = ["impact_start", "velocity_jump"]

_EMPTY = np.zeros(0)
_EMPTY.flags.writeable = False


def velocity_jump(
    model,
    st,
    q,
    v,
    closed,
    g_tilde,
    opts,
    t,
    tol_gap,
    Gb=None,
    held=None,
    preload=None,
    approach=None,
    pressed=None,
    rest=None,
):
    """Step 3: v = ṽ + W, M W = Σ G_jᵀ [k Λ_j − p ġ_j]_+ with
    ġ_j = G_j(q_{n+1}) v_{n+1} + e_j ġ⁻_j; joints: G_b v_{n+1} = 0 (``Gb``: their gradient
    at q, if known). The ``held`` contacts (a mask over ``closed``: pressed by a smooth
    force at the end of the step, :mod:`.smooth_contact`) neither open nor close within
    it: ġ_j = 0, an equality like a joint's, which removes the velocity drift of the
    index-3 smooth step, with an impulse of either sign.

    ġ⁻_j = (1 − τ_j) G_j(q_n) v_n + τ_j G_j(q_{n+1}) ṽ_{n+1}, with τ_j the fraction of the
    step at which the gap crosses zero (τ_j = 0 with ``impact_velocity="step_start"``).
    Warm-started from the previous step's impulses; a residual ġ below tol_gap/h closes less
    than the gap tolerance within the step. Returns (W, k Λ, iterations, friction, works)
    with friction = (k Λ_T, stick/slip status, work of Λ_T in J) of the closed contacts when
    the model has friction (:func:`fecontact.time.coulomb.frictional_jump`, whose cone holds
    the step's total impulse: ``preload`` (len(closed), 1 + nt), the impulse h(λ_N, λ_T)
    of the smooth forces), else None, and works (J) the normal, tangential and joint
    impulses' work at the mean rates (:func:`fecontact.contact.restitution.impulse_work`).
    ``pressed`` (len(closed),): the smooth forces' impulses h λ_N (N s) of the closed
    contacts of a frictionless model of rigid bodies, with which a held contact whose
    equality pulls it by more than its force pressed it is let go (:func:`_let_go`; measured
    on rigid bodies, benchmarks/rigid_smooth_contact.py: solids and beams keep their held
    equalities)."""
    F = model.free
    if closed.size == 0:
        # joints only: the M-orthogonal projection onto G_b v = 0, no active set to find
        G1 = model.joints.jacobian(q, model.joints.all)[1] if Gb is None else Gb
        Y = model.solve_M(G1.T).reshape(len(F), -1)
        rate = G1 @ v[F]
        mu = factorize(G1 @ Y, solver=model.solver)(-rate)
        W = Y @ mu
        return W, _EMPTY, 1, None, impulse_work(mu, rate, rate + G1 @ W, 0, 0)
    cons = Constraints(model, closed)
    if held is not None:
        cons.bilateral[: closed.size] = held
    _, G1 = cons.jacobian(q)
    e = model.contacts.restitution[closed]  # (a copy: the held rows' are set to zero)
    if model.joints.size:
        e = np.concatenate([e, np.zeros(model.joints.size)])
    if held is not None:
        e[: closed.size][held | _twin_held(model.contacts, closed, held)] = 0.0
    gdot = G1 @ v[F]
    contacts = model.contacts
    if contacts.moving:  # ġ = G v + ∂g/∂t at t_{n+1} and, for the impact law, at t_n
        gdot[: closed.size] += contacts.rates(q, closed)
    if np.count_nonzero(e):  # (any e ≠ 0; count_nonzero is the cheaper test)
        rows = (cons, G1, closed, g_tilde, gdot)
        gdot_n = _approach_rates(model, st, q, t, rows, opts, tol_gap, approach)
    else:
        gdot_n = np.zeros_like(gdot)
    if np.count_nonzero(np.isfinite(gdot)) < gdot.size:  # a NaN would switch every test off
        raise StepFailure("velocity jump: non-finite normal velocity of a closed contact", np.nan)
    tol = tol_gap / (t - st.t)
    if opts.impact_law == "poisson" and np.count_nonzero(e):
        return poisson_jump(
            model, st, q, v, closed, G1, gdot, e, gdot_n[: closed.size], opts, tol,
            bilateral=cons.bilateral, preload=preload, pressed=pressed,
        )  # fmt: skip
    rates = gdot.copy()  # ġ of ṽ, without the impact law's term
    gdot += e * gdot_n
    if contacts.frictional:
        solve = resting_metric(model, st, q, closed, tol_gap, rest)
        W, lam_n, lam_t, status, its, work, lam_b = _frictional_or_plastic(
            model, st, q, v, closed, G1, (gdot, rates), opts, tol, preload, solve
        )
        lam_n = _without_round_off(lam_n, preload)
        lam = np.concatenate([lam_n, lam_b])
        works = jump_work(model, q, v, W, closed, G1, rates, lam, lam_t)
        return W, lam_n, its, (lam_t, status, work), works
    Y = constraint_columns(model, ("mass",), closed, G1, model.solve_M, cons, constant=True)
    # the last step's impulses: warm start
    P0 = st.impulse[closed]
    if model.joints.size:
        P0 = np.concatenate([P0, np.zeros(model.joints.size)])
    W, P, its = impact_law(G1, gdot, model.solve_M, Y, opts, cons.bilateral, P0, tol)
    if _lets_go(model, pressed, held):
        W, P, its = _let_go(
            G1, gdot, model.solve_M, Y, opts, cons.bilateral, (W, P, its), pressed, tol
        )
    works = impulse_work(P, rates, rates + G1 @ W, closed.size, 0)
    P[: closed.size] = _without_round_off(P[: closed.size], preload)
    return W, P, its, None, works


def _twin_held(contacts, closed, held) -> np.ndarray | bool:
    """The closed rows whose twin (a mortar node's other row, ``contacts.twins``) is held: the
    node is in lasting contact, and Newton's law with e > 0 on its weighted row beside the
    held equality of its own row asks it for two velocities along almost one direction
    (two coarse balls at e = 1: +0.015 N s on the one, −0.0075 N s on the other, and the
    next step put in 0.11 J of their 0.35 J). The row stays unilateral, with e = 0."""
    if contacts.twins is None or not held.any():
        return False
    return np.isin(contacts.twins[closed], closed[held])


def resting_metric(model, st, q, closed, tol_gap: float, rest):
    """H⁻¹ = β′S_t⁻¹ of the frictional jump of a decoupled step (``rest`` = (S_t, its
    coefficients), None in the smooth scheme) that strikes nothing: every contact of
    ``closed`` was closed or pressed at t_n. Else None: M⁻¹, Newton's law as an impulse.

    Such a jump takes out the drift of a step that carried no contact force, the force's
    impulse over the step, not a strike's. Where a beam slips under its section's surface,
    c from the centreline, through M⁻¹ that impulse turned the sections (a strip's ρI is
    a third of ρA c²) rather than stop the centreline: a strip held on a 20° incline
    (μ = 0.5) left its first step at 2.5e-3 m/s down the slope with its sections spinning
    against it, a turn the shear stiffness did not let the next step take, and the
    position correction then slipped at the cone's edge: 8.7e-4 m of creep in 0.2 s. Through
    S_t⁻¹ the turn costs the strain it makes, while a rod's roll about its axis, which
    strains nothing, costs what it does through M⁻¹ (:func:`.coulomb.frictional_start`
    chooses the same metric for the start's jump)."""
    if rest is None or not closed.size or st.gaps.size != model.contacts.size:
        return None
    if not np.all((st.gaps[closed] <= tol_gap) | st.pressed()[closed]):
        return None
    return correction_metric(model, q, rest[0], rest[1], "stiffness")[1]


def _frictional_or_plastic(model, st, q, v, closed, G1, targets, opts, tol, preload, solve):
    """:func:`fecontact.time.coulomb.frictional_jump` with the rates ``targets`` = (ġ with
    the impact law's term e ġ⁻, ġ without it). Where rows can be redundant and the law with
    e ≠ 0 is not solved, the jump is solved again as a plastic one (e = 0 on every row),
    counted in ``plastic_jumps``: with friction on dependent rows the target, e ġ⁻ on the
    normal rows and nothing on the tangential ones, need not be the rates of a motion, and
    Newton's law with Coulomb's can then have no solution (the 2 × 2 pile at 0.795 s: no
    status of its seven contacts holds it to better than 6.5e-7 m/s against 3e-8,
    docs/validation/pile.md); the plastic target G ṽ is, and stops the rows."""
    gdot, rates = targets
    try:
        return frictional_jump(model, st, q, v, closed, G1, gdot, opts, tol, solve, preload)
    except StepFailure:
        if not opts.stats.contact.minimum_norm or np.array_equal(gdot, rates):
            raise
    jump = frictional_jump(model, st, q, v, closed, G1, rates, opts, tol, solve, preload)
    opts.stats.contact.coulomb.plastic_jumps += 1
    return jump


def _lets_go(model, pressed, held) -> bool:
    """Whether the jump may let a held contact go (:func:`_let_go`): with the smooth forces'
    impulses ``pressed`` and held contacts, on rigid bodies (measured there; solids and beams
    keep their held equalities)."""
    return pressed is not None and held is not None and not (model.continuum or model.slender)


def _let_go(G1, gdot, solve, Y, opts, bilateral, jump, pressed, tol):
    """The jump ``jump`` = (W, P, iterations) of the equalities ``bilateral`` again, as
    Newton's law on the step's total impulses P + h λ_N ≥ 0 (``pressed``: h λ_N of the
    closed contacts), where it pulled a held contact by more than its smooth force pressed
    it (P_j < −h λ_j beyond round-off). A held contact is an equality only to remove the
    index-3 step's velocity drift; when another contact strikes, the body may have to leave
    it, and the equality pulled it down instead: a rocking block (e_N = 1) struck on its
    second corner kept its pivot on the floor by an adhesive impulse (0.69 N s a strike)
    and gained 4.7e-3 of its scale over 1 s. As in the frictional jump
    (:func:`fecontact.time.coulomb.frictional_jump`), the contact may then open."""
    W, P, its = jump
    if (pulled := pulled_held_rows(P, pressed, bilateral)) is None:
        return W, P, its
    pre, own = pulled
    W2, P2, its2 = impact_law(G1, gdot - G1 @ (Y @ pre), solve, Y, opts, own, P + pre, tol)
    return W2 - Y @ pre, P2 - pre, its + its2


def _without_round_off(P: np.ndarray, preload=None) -> np.ndarray:
    """The normal impulses ``P`` (N s) with those within round-off of zero set to zero: a
    held contact's impulse (of either sign) that should be zero comes out as ±1e-20 N s,
    and its sign would decide whether the contact counts as pressed in the next step, so
    that the run would depend on the BLAS's summation order. Round-off: 1e-12 of the
    step's largest impulse, or of the smooth forces' impulse h λ (``preload``)."""
    scale = np.abs(P).max(initial=0.0)
    if preload is not None:
        scale = max(scale, np.abs(preload).max(initial=0.0))
    return np.where(np.abs(P) <= 1e-12 * scale, 0.0, P)


def impact_start(model, st, opts, tol_gap: float, dt: float):
    """The initial state ``st`` with the impact law applied at t = 0 to the contacts that
    touch (gap ≤ ``tol_gap``, m) while approaching (ġ < −tol_gap/``dt``): the impact of a
    body released in contact takes place at t = 0, where the jump of the first step would
    take it at t = dt. Left to that jump, a solid's contact node enters the obstacle by
    ġ dt before the position correction pushes it out, and the strain the correction
    leaves is energy the impact never had: ½ δᵀ(G H⁻¹Gᵀ)⁻¹δ with δ = ġ dt (the 3,993-dof
    ball at 0.1 m/s and dt = t_c/20: 1.3e-4 J, 5 % of its kinetic energy). After the jump
    the contacts carry its impulses, so that the smooth step holds them (they are
    persistent, :mod:`.smooth_contact`). The state keeps a ledger record of its kinetic
    energy before the jump, so that the ledger starts from the energy the run was given
    and books the jump as impact. ``opts``: the run's settings. Moving obstacles,
    friction and states without an approaching contact are left as they are."""
    touching = np.flatnonzero(st.gaps <= tol_gap)
    contacts = model.contacts
    if touching.size == 0 or contacts.moving or contacts.frictional:
        return st
    _, G = contacts.linearize(st.q, touching)[:2]
    if not np.any(G @ st.v[model.free] < -tol_gap / dt):
        return st
    W, P, _, _, works = velocity_jump(model, st, st.q, st.v, touching, st.gaps, opts, dt, tol_gap)
    v = st.v.copy()
    v[model.free_slice] += W
    impulse = st.impulse.copy()
    impulse[touching] = P[: touching.size]
    record = smooth_record(model, True, st.v, None, 0.0, works)
    return dataclasses.replace(st, v=v, impulse=impulse, candidates=touching, ledger=record)


def _approach_rates(model, st, q, t, rows, opts, tol_gap, approach) -> np.ndarray:
    """ġ⁻ of the rows (cons, G1, closed, g_tilde, gdot) of the jump (module docstring of
    :func:`velocity_jump`): from the start of the step, interpolated to the instant the gap
    crosses zero with ``impact_velocity="interpolated"`` (toward G(q_{n+1}) ``approach``,
    default the velocity ``gdot`` at the end of the step)."""
    cons, G1, closed, g_tilde, gdot = rows
    F, contacts = model.free, model.contacts
    Gn = G1 if cons.linear else cons.jacobian(st.q)[1]  # constant gradients: G(q_n) = G
    gdot_n = Gn @ st.v[F]
    if contacts.moving:
        contacts.set_time(st.t)
        gdot_n[: closed.size] += contacts.rates(st.q, closed)
        contacts.set_time(t)
    if opts.impact_velocity == "interpolated" and st.gaps.size == contacts.size:
        nc = closed.size
        tau = _crossing_fraction(st.gaps[closed], g_tilde[closed], tol_gap)
        g1 = gdot if approach is None else G1 @ approach[F]
        if approach is not None and contacts.moving:
            g1[: closed.size] += contacts.rates(q, closed)
        gdot_n[:nc] += tau * (g1[:nc] - gdot_n[:nc])
    return gdot_n


def _crossing_fraction(g_n, g_tilde, tol_gap):
    """τ ∈ [0, 1] where the chord from g_n (start of step) to g̃ (end, predicted) crosses 0;
    0 for a contact that was already closed (g_n ≤ tol_gap) or is not approaching; 1 for a
    contact that had no facet within the detection margin at t_n (g_n = +∞) and closed
    within the step: its approach velocity is the one at the end of the step."""
    far = ~np.isfinite(g_n)
    drop = g_n - g_tilde
    approach = (drop > 0.0) & (g_n > tol_gap) & ~far
    tau = np.divide(g_n, drop, out=np.zeros_like(drop), where=approach)
    tau[far] = 1.0
    return np.clip(tau, 0.0, 1.0)
