"""The decoupled step's acceleration after a velocity jump, where the smooth forces depend on
the velocity: the gyroscopic forces of bodies in space and the joints' reactions.

The decoupled step (no smooth contact force) keeps v̇ and a of the smooth step through an
impact. Where the smooth forces depend on v, the jump W changes them: a rod struck with
friction leaves the impact spinning at 20.8 rad/s about its axis, and the next step
integrated Ω × JΩ of the new spin from the pre-impact acceleration, moving its angular
momentum by 1.0e-2 of it, halving with h (docs/validation/multibody.md). A chain's joints hold
G_b v̇ = −vᵀ∇²g_b v, whose right side (the centripetal pull of each link on the next) the jump
changes too: three pinned bars struck at e_N = 1 took 5.3e-3 J in the step after a strike,
started from the pre-impact v̇ (docs/explanation/energy_ledger.md). The jump's change of
those forces is added to v̇ and a,

    [M  G_bᵀ] [Δv̇]   [f_gyr(q, v⁻) − f_gyr(q, v⁺)        ]
    [G_b  0 ] [Δλ] = [−(v⁺ᵀ∇²g_b v⁺ − v⁻ᵀ∇²g_b v⁻)        ]   (M Δv̇ = the first row alone
                                                            without joints),

the velocity-dependent share of the restart a = v̇(q_{n+1}, v_{n+1}) of the smooth-contact
step; the rest of a (the generalized-α recurrence of the position-dependent forces) is kept,
so a body with no such force (planar rigid bodies without joints) steps as before, bit for
bit.
"""

from __future__ import annotations

import numpy as np

from ..linalg import factorize
from .constraints import bordered
from .lie import inertial_forces

__all__ = ["jumped", "velocity_forces"]


def velocity_forces(model) -> bool:
    """Whether ``model``'s smooth forces depend on the velocity (gyroscopic forces or the
    joints' quadratic terms): decided once per run."""
    return bool(model.inertial_bodies) or bool(model.joints.size)


def jumped(follows: bool, model, state, W, impulses, accelerations) -> None:
    """v (all dofs; ``state`` = (q, v, ṽ)) += W (free dofs), in place; where the run
    ``follows`` the velocity's forces (decided once: :func:`velocity_forces`, the decoupled
    step's) and a contact takes an impulse (``impulses``, N s, of the closed contacts), their
    change from ṽ, the smooth step's velocity that v̇ and a follow (v before a momentum hold
    moved it, :mod:`.momentum_rigid`), added to each array of ``accelerations`` (v̇, a; all
    dofs; in place). A jump of the joints alone (their velocity projection, each step of the
    heavy top) leaves v̇ and a as they are."""
    q, v, v_smooth = state
    F = model.free_slice
    if not follows or not np.any(impulses > 0.0):
        v[F] += W
        return
    before = _rate_terms(model, q, v_smooth)
    v[F] += W
    after = _rate_terms(model, q, v)
    force, pull = before[0] - after[0], after[1] - before[1]
    if model.joints.size:
        Gb = model.joints.jacobian(q, model.joints.all)[1]
        solve = factorize(bordered(model.M, Gb), solver=model.solver)
        change = solve(np.r_[force, -pull])[: force.size]
    else:
        change = model.solve_M(force)
    for x in accelerations:
        x[F] += change


def _rate_terms(model, q, v):
    """(f_gyr(q, v) (free dofs), vᵀ∇²g_b v of the joints (rows))."""
    nf = len(model.free)
    gyroscopic = (
        inertial_forces(model, q, v, tangent=False)[0] if model.inertial_bodies else np.zeros(nf)
    )
    joints = model.joints
    return gyroscopic, joints.quadratic(q, v) if joints.size else np.zeros(0)
