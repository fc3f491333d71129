r"""The accelerations after a position correction of the decoupled NSGA step.

The smooth step balances the dynamics at q̃_{n+1}; the position correction then moves q by U,
and v̇_{n+1}, a_{n+1} still balance f_int(q̃), not f_int(q̃ + U). In a mode of frequency ω the
step resolves (ωh ≲ a few) the state after an impact is then q = U, v = W with an acceleration
that lags U, and U and W point the same way (both carry the body out of the obstacle). From
such a state generalized-α overshoots: one mode at ωh = 1 to 3 started from q = U, v = ωU,
v̇ = a = 0 reaches 1.2 to 1.3 times its energy at ρ∞ = 0.8 and 0.9 (1.2 at 0.5). On the
flexible pendulum with e_N = 1 and ρ∞ = 0.8 the strain of U (0.42 % of the kinetic energy)
grows to 1.87 % two steps after the impact.

Restarting the accelerations from the corrected state, v̇ = a = M⁻¹(f_ext − f_int(q)), is the
answer in the resolved modes and a disaster in the others: a mode at ωh = 100 started from
q = U with its consistent acceleration reaches 40 times its energy at ρ∞ = 0.5 (5 times at
0.8), and the pendulum's energy grows a thousandfold in the step after the impact. Here the
accelerations take one Newton iteration of the smooth step resumed at the corrected position,
with the step's own iteration matrix S_t = β′M + γ′C + K_t, whose displacement is dropped
(q stays where the correction put it, its gaps closed):

    Δv̇ = −β′ S_t⁻¹ [f_int(q̃ + U) − f_int(q̃) − Σ G_jᵀ μ_j],   Δa = (1 − α_f)/(1 − α_m) Δv̇,

the second keeping the generalized-α recursion between a and v̇ of the step. In a mode of
frequency ω, Δv̇ = −ω²U β′/(β′ + ω²): the consistent change −ω²U where the step resolves the
mode (ω² ≪ β′ ≈ 4/h²), a bounded −β′U where it does not. The same single modes then stay
within 1.00 to 1.12 of their energy, never above the uncorrected accelerations.

The update is made in a step where a contact closed (open at t_n, closed at t_{n+1}): an
impact, whose correction is the strain the smooth step could not see coming. While a contact
stays pressed, its corrections are the O(h²) drift of its gap, and accelerations carrying
them would take part of the contact force out of the reported impulses (the bar striking a
wall would read a mean force of 0.080 instead of ρ c v₀ A = 0.1).

The closed contacts that do not separate (ġ_j ≤ tol_gap/h after the velocity jump) hold the
update, 0 ≤ G_j Δv̇ ⊥ μ_j ≥ 0: the strain U put in a pressed zone must not pull it back
into the obstacle (a strip whipped onto a cylinder then fails its smooth Newton at 12 ms).
The joints hold it as equalities, G_b Δv̇ = 0. Both are the velocity jump's problem in the
metric S_t (:func:`fecontact.contact.solve_velocity_jump`). The correction U itself and
everything it enforces are unchanged.

The velocity follows (:func:`velocity_follows`, frictionless models):
generalized-α ties it to the acceleration variable, ṽ_{n+1} = v_n + h(1 − γ)a_n + hγ a_{n+1},
so the same Newton iteration moves v by hγΔa (only its displacement is dropped), and Newton's
law is then applied again, to ṽ + hγΔa with the approach velocity still from ṽ. Without it the
strain of U was energy the motion never paid for: a disk landing on a node of a steel
cantilever with e_N = 0 (``benchmarks/node_impact.py``, x = 0.5 m, h = 2e-4 s) was put 0.0139 J
of strain by U while Newton's law took 0.0133 J of kinetic energy out, and the energy rose by
0.44 % of the impact's kinetic energy (4.9 % at h = 4e-4 s, up to 8 % with the impact
elsewhere in its step); it did not fall with h, since H = S_t/β′ scales with h⁻². The
follow-up takes 0.0168 J out of the motion in that step: in a mode of frequency ω, hγΔa =
−γ′U ω²/(β′ + ω²), whose work against the velocity that drove U in is about U's strain, and
whose own kinetic energy is at most γ²(1 − α_f)/(4β(1 − α_m)) (0.26 at ρ∞ = 0.5) of it. On
the nonlinear strip the secant strain of a large correction can make that follow-up add energy
instead (the founding pendulum at 4 h), so it is taken along s ∈ [0, 1] as far as it lowers the
kinetic energy (on the jump's active set the velocity is affine in s). The impulses the
contacts report include the forces that held Δv̇ over hγ(1 − α_f)/(1 − α_m), so the bodies'
momenta change by the reported impulses.
"""

from __future__ import annotations

import numpy as np

from ..contact import solve_velocity_jump
from .constraints import Constraints, StepFailure, augmentation
from .impacts import velocity_jump

__all__ = ["acceleration_jump", "velocity_follows"]


def acceleration_jump(
    model, q, q_tilde, v, closed, solve_H, tol_rate: float, df=None, stats=None
) -> tuple[np.ndarray, np.ndarray]:
    """Δv̇ on the free dofs after the correction q̃ → q (see the module docstring), and the
    forces (N) of the ``closed`` contacts that hold it (zero for the others).
    ``solve_H`` solves with H = S_t/β′ (the stiffness metric of the position correction),
    ``closed`` are the contacts closed at q, ``tol_rate`` (m/s) the rate below which a
    closed contact does not separate; ``stats``: the run's
    :class:`fecontact.contact.stats.ContactStats`."""
    F = model.free
    if df is None:
        df = model.internal(q, tangent=False)[1][F] - model.internal(q_tilde, tangent=False)[1][F]
    x = -solve_H(df)
    contacts = model.contacts
    rows = closed
    if closed.size:
        _, G = contacts.linearize(q, closed)[:2]
        rate = G @ v[F]
        if contacts.moving:
            rate += contacts.rates(q, closed)
        rows = closed[rate <= tol_rate]
    force = np.zeros(closed.size)
    if rows.size == 0 and not model.joints.size:
        return x, force
    cons = Constraints(model, rows)
    _, G = cons.jacobian(q)
    Y = solve_H(G.T).reshape(len(F), -1)
    try:
        dx, mu, _ = solve_velocity_jump(
            G,
            G @ x,
            solve_H,
            augmentation(1.0, G, Y),
            1.0,
            rows.size + 2,
            bilateral=cons.bilateral,
            Y=Y,
            stats=stats,
        )
    except RuntimeError:
        raise StepFailure("acceleration jump: the active set did not settle", np.nan) from None
    force[np.isin(closed, rows)] = mu[: rows.size]
    return x + dx, force


def velocity_follows(model, st, q, v0, v_tilde, dvd, hold, Lam0, c, opts, t, tol_gap, rows):
    """The velocity after the accelerations followed the correction (Δv̇ = ``dvd``, with the
    forces ``hold`` (N) of the closed contacts that held it): generalized-α moves v with a by
    hγΔa, Δa = (1 − α_f)/(1 − α_m)Δv̇, and Newton's law is applied again to ṽ + s hγΔa, with
    ġ⁻ still from ṽ (``v_tilde``). ``v0`` and ``Lam0`` are the jump without it (s = 0). Where
    the strain of the correction acts against the motion, the kinetic energy falls along
    s; the largest such fall in s ∈ [0, 1] is taken (on a fixed active set the velocity is
    affine in s and its kinetic energy quadratic), else s = 0 or 1, the lower. Returns
    (v, impulses of the closed contacts (N·s), iterations); the follow-up is counted in the
    run's statistics (``opts.stats.follow_ups``)."""
    closed, g_tilde, Gb, held = rows
    h_a = c.h * c.gamma * (1.0 - c.af) / (1.0 - c.am)
    v1 = v_tilde.copy()
    v1[model.free_slice] += h_a * dvd
    W, Lam, its, *_ = velocity_jump(
        model, st, q, v1, closed, g_tilde, opts, t, tol_gap, Gb, held, approach=v_tilde
    )
    v1[model.free_slice] += W
    Lam1 = Lam[: closed.size] + h_a * hold
    d = v1 - v0
    Md = model.M @ d[model.free_slice]
    a, b = d[model.free_slice] @ Md, v0[model.free_slice] @ Md
    if np.array_equal(Lam[: closed.size] > 0.0, Lam0 > 0.0) and a > 0.0:
        s = min(max(-b / a, 0.0), 1.0)
    else:
        s = 1.0 if b + 0.5 * a < 0.0 else 0.0
    opts.stats.follow_ups.steps += 1
    opts.stats.follow_ups.shortened += s < 1.0
    return v0 + s * d, Lam0 + s * (Lam1 - Lam0), its
