"""The configuration space of the steppers: every update of the positions goes through
:func:`plus`, q ⊕ Δq, so that coordinates that do not add (rotations in SO(3)) change only
here."""

from __future__ import annotations

import numpy as np

__all__ = ["plus"]


def plus(model, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
    """q ⊕ Δq: the positions ``q`` (all dofs) moved by the update ``dq`` of the free dofs,
    as a new array. The bodies here have displacements and planar rotations, whose updates
    add: q + Δq on the free dofs."""
    out = q.copy()
    out[model.free_slice] += dq
    return out
