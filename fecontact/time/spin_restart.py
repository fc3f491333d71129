"""The decoupled step's acceleration after a velocity jump of bodies with gyroscopic forces.

The decoupled step (no smooth contact force) keeps v̇ and a of the smooth step through an
impact. Where the smooth forces depend on v, the jump W changes them: a rod struck with
friction leaves the impact spinning at 20.8 rad/s about its axis, and the next step
integrated Ω × JΩ of the new spin from the pre-impact acceleration, moving its angular
momentum by 1.0e-2 of it, halving with h (docs/validation/multibody.md). The jump's change
of the gyroscopic forces, M⁻¹(f_gyr(q, v⁻) − f_gyr(q, v⁺)), is added to v̇ and a, the
velocity-dependent share of the restart a = v̇(q_{n+1}, v_{n+1}) of the smooth-contact step;
the rest of a (the generalized-α recurrence of the position-dependent forces) is kept, so a
body with no such force (planar rigid bodies) steps as before, bit for bit.
"""

from __future__ import annotations

import numpy as np

from .lie import inertial_forces

__all__ = ["jumped"]


def jumped(spins: bool, model, state, W, impulses, accelerations) -> None:
    """v (all dofs; ``state`` = (q, v, ṽ)) += W (free dofs), in place; where the run ``spins``
    (decided once: :attr:`~fecontact.time.settings.RunSettings.spins`) and a contact takes
    an impulse (``impulses``, N s, of the closed contacts), the gyroscopic forces' change
    from ṽ, the smooth step's velocity that v̇ and a follow (v before a momentum hold moved
    it, :mod:`.momentum_rigid`), added to each array of ``accelerations`` (v̇, a; all dofs;
    in place). A jump of the joints alone (their velocity projection, each step of the
    heavy top) leaves v̇ and a as they are."""
    q, v, v_smooth = state
    F = model.free_slice
    if not spins or not np.any(impulses > 0.0):
        v[F] += W
        return
    before = inertial_forces(model, q, v_smooth, tangent=False)[0]
    v[F] += W
    change = model.solve_M(before - inertial_forces(model, q, v, tangent=False)[0])
    for x in accelerations:
        x[F] += change
