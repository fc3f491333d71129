r"""The frame in which a force spread over a step enters a rigid body's angular velocity.

A rigid body in space carries its angular velocity in the body frame, Ω, so a spatial torque
τ acting over a step changes it by J⁻¹∫R(t)ᵀτ dt = h J⁻¹R_{n+½}ᵀτ + O(h³). The velocity
jump's rows are taken at q_{n+1}, and applied there they give h J⁻¹R_{n+1}ᵀτ, off by
h²/2 · J⁻¹(Ω × Rᵀτ) every step: the friction that holds a sliding ball back while it spins
about the normal then leaves its (ω_x, ω_y) off by O(h) (docs/validation/multibody.md). The
tangential impulse of a contact is such a force (the decoupled smooth step carries none), so
its rows enter M⁻¹ through the step's mean frame R_n exp(Θ/2) = R_{n+1} exp(−Θ/2),
Θ = log(R_nᵀR_{n+1}): the rotation block of their transpose is multiplied by exp(Θ̃/2). The
law itself (the slip rate G_T(q_{n+1}) v_{n+1}) stays at the end of the step.
"""

from __future__ import annotations

import numpy as np

from ..rotations import exp, log

__all__ = ["MeanFrames"]


class MeanFrames:
    """The rigid bodies in space of a model whose rotation is free (decided once): their
    rotation vectors in global and in free numbering."""

    def __init__(self, model):
        glob, free = [], []
        for b, o in zip(model.bodies, model.offsets, strict=False):
            t = model.free_index[o + np.arange(3, 6)] if b.rigid_frame and b.dim == 3 else None
            if t is not None and (t >= 0).all():
                glob.append(o + np.arange(3, 6))
                free.append(t)
        self.glob = np.array(glob, dtype=int).reshape(-1, 3)
        self.free = np.array(free, dtype=int).reshape(-1, 3)

    def rows(self, GT: np.ndarray, q_n: np.ndarray, q: np.ndarray) -> np.ndarray:
        """The slip rows ``GT`` (m, nt, free dofs) at q with each body's rotation block
        taken in the step's mean frame: (rows) exp(Θ̃/2)ᵀ."""
        if not len(self.glob):
            return GT
        out = GT.copy()
        for g, f in zip(self.glob, self.free, strict=True):
            half = exp(0.5 * log(exp(q_n[g]).T @ exp(q[g])))
            out[:, :, f] = GT[:, :, f] @ half.T
        return out
