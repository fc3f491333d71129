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
metric S_t (:func:`fecontact.contact.solve_velocity_jump`). The correction U itself, the
velocity jump and everything they enforce are unchanged: the update acts on v̇ and a only,
which the next step's predictor reads.
"""

from __future__ import annotations

import numpy as np

from ..contact import solve_velocity_jump
from .constraints import Constraints, StepFailure, augmentation

__all__ = ["acceleration_jump"]


def acceleration_jump(model, q, q_tilde, v, closed, solve_H, tol_rate: float) -> np.ndarray:
    """Δv̇ on the free dofs after the correction q̃ → q (see the module docstring).
    ``solve_H`` solves with H = S_t/β′ (the stiffness metric of the position correction),
    ``closed`` are the contacts closed at q, ``tol_rate`` (m/s) the rate below which a
    closed contact does not separate."""
    F = model.free
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
    if rows.size == 0 and not model.joints.size:
        return x
    cons = Constraints(model, rows)
    _, G = cons.jacobian(q)
    Y = solve_H(G.T).reshape(len(F), -1)
    try:
        dx, _, _ = solve_velocity_jump(
            G,
            G @ x,
            solve_H,
            augmentation(1.0, G, Y),
            1.0,
            rows.size + 2,
            bilateral=cons.bilateral,
            Y=Y,
        )
    except RuntimeError:
        raise StepFailure("acceleration jump: the active set did not settle", np.nan) from None
    return x + dx
