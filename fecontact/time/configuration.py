"""The configuration space of the steppers: every update of the positions goes through
:func:`plus`, q ⊕ Δq, so that coordinates that do not add (rotations in SO(3)) change only
here."""

from __future__ import annotations

import numpy as np

from ..rotations import compose

__all__ = ["minus", "plus"]


def plus(model, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
    """q ⊕ Δq: the positions ``q`` (all dofs) moved by the update ``dq`` of the free dofs,
    as a new array. Displacements and planar rotations add, q + Δq; the rotation vectors ψ of
    the model's ``rotations`` (free-dof triples) compose on the right, exp(ψ̃) exp(Δ̃), with Δ
    the body-frame rotation of the update."""
    out = q.copy()
    out[model.free_slice] += dq
    R = model.rotations
    if R.size:  # (decided by the model once: planar models never come here)
        F = model.free[R]
        if len(R) == 1:  # one body: the single-vector path of ``compose``
            out[F[0]] = compose(q[F[0]], dq[R[0]])
        else:
            out[F] = compose(q[F], dq[R])
    return out


def minus(model, q1: np.ndarray, q0: np.ndarray) -> np.ndarray:
    """q₁ ⊖ q₀ (all dofs): the update Δ with q₀ ⊕ Δ = q₁, the inverse of :func:`plus`.
    Displacements subtract; on the model's ``rotations`` it is the body-frame rotation
    log(exp(−ψ̃₀) exp(ψ̃₁)), which the step's h v + O(h²) approximates (the difference of
    the rotation vectors does so only for a turn about a fixed axis)."""
    out = q1 - q0
    R = model.rotations
    if R.size:
        F = model.free[R]
        out[F] = compose(-q0[F], q1[F])
    return out
