r"""Persistent contacts whose slip turns against the friction force the smooth step started
with.

The smooth step carries the persistent contacts' friction forces λ_T in v̇ and a: λ_T,n,
which opposed the slip of step n, acts in step n + 1 too (the predictor and the recursion
of a, as :mod:`.smooth_contact` says of the normal forces). Where the slip of step n + 1
turns back, λ_T,n points along it: the step pushes the contact along its new slip with
the force that opposed the old one, and the kinetic energy it changes, the mean of λ_T,n
and λ_T,n+1 times the slip at ρ∞ = 1, can be a gain Coulomb's law cannot give. A rod
caught on a box's edge (μ = 1) gained 4.9e-3 J so in one step, λ_T,n = 216 N along the
new slip against λ_T,n+1 = 29 N opposing it (``docs/explanation/friction.md``).

Such a step is taken again as one that releases a contact is, with that contact's
tangential share taken out of v̇_n (through M⁻¹) and a_n (through H⁻¹, H = S_t/β′ the
step's iteration matrix): the slip turns at t_n, where the step can no longer tell when
within it, and the force that opposes it is the new step's λ_T,n+1 alone, whose work over
the slip is ≥ 0. The normal force stays: the contact is still pressed.
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["reversing", "without_tangential"]


def reversing(sc) -> np.ndarray:
    """The contacts (indices of every contact) of the smooth friction ``sc``
    (:class:`fecontact.time.coulomb.SmoothFriction`) whose slip over the step, longer than
    its inner solve's tolerance, turns against λ_T,n: λ_T,n·w_T > 0."""
    lam_n = np.asarray(sc.lam_n)
    if lam_n.ndim < 2 or not lam_n.size:  # (no force carried from t_n)
        return np.zeros(0, dtype=int)
    along = np.einsum("mt,mt->m", lam_n, sc.slip) > 0.0
    moved = np.linalg.norm(sc.slip, axis=1) > sc.tolerance
    return sc.P[along & moved]


def without_tangential(model, st, rows: np.ndarray, solve_H):
    """``st`` with the tangential forces of the contacts ``rows`` taken out of v̇_n (through
    M⁻¹) and a_n (through ``solve_H``) and out of the forces that warm-start the step (as
    :func:`fecontact.time.smooth_contact.without_released` takes a released contact's)."""
    F = model.free_slice
    smooth = st.smooth
    GT, _ = model.contacts.tangent_jacobian(st.q, rows)
    f_vd = np.einsum("mtn,mt->n", GT, smooth.in_vd[rows, 1:])
    f_a = np.einsum("mtn,mt->n", GT, smooth.in_a[rows, 1:])
    vd, a = st.vd.copy(), st.a.copy()
    vd[F] -= model.solve_M(f_vd)
    a[F] -= solve_H(f_a)
    in_vd, in_a = smooth.in_vd.copy(), smooth.in_a.copy()
    in_vd[rows, 1:] = 0.0
    in_a[rows, 1:] = 0.0
    tangential = None if smooth.tangential is None else smooth.tangential.copy()
    if tangential is not None:
        tangential[rows] = 0.0
    smooth = dataclasses.replace(smooth, tangential=tangential, in_vd=in_vd, in_a=in_a)
    return dataclasses.replace(st, vd=vd, a=a, smooth=smooth)
