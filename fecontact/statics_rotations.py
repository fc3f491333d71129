"""Static equilibrium of models with rotation dofs (3D beams): Newton's method with load
stepping, the rotations updated on the group.

The rotation vectors ψ that bodies list in ``rotation_triples`` are updated by right
composition, ψ ← ψ ⊕ Δ (:func:`fecontact.rotations.compose`), with Δ the Newton increment of
those dofs; the other dofs are added to. The tangent is the bodies' ∂f(q ⊕ Δ)/∂Δ, so Newton
converges quadratically. Moments in the load act about the global axes (a fixed spatial moment
m): on a node of rotation R they are the generalized force Rᵀm in the node's frame, whose
change with the node's rotation, (Rᵀm)~ Δ, enters the tangent.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import SolverError
from .linalg import factorize
from .rotations import compose, exp, hat

__all__ = ["model_rotation_triples", "solve_static_rotations"]


def model_rotation_triples(model) -> np.ndarray:
    """(k, 3) global indices of the rotation vectors of the bodies of ``model``."""
    parts = [o + b.rotation_triples for b, o in zip(model.bodies, model.offsets, strict=False)]
    return np.concatenate(parts).astype(int)


def _load_terms(q, load, triples, lam):
    """The generalized load λ f (moments turned into the nodes' frames) and its tangent."""
    f = lam * load
    if len(triples) == 0:
        return f, None
    RtM = np.einsum("nji,nj->ni", exp(q[triples]), lam * load[triples])
    f = f.copy()
    f[triples] = RtM
    blocks = hat(RtM)
    rows = np.broadcast_to(triples[:, :, None], blocks.shape).ravel()
    cols = np.broadcast_to(triples[:, None, :], blocks.shape).ravel()
    return f, sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(q.size, q.size))


def plus(q: np.ndarray, dq: np.ndarray, triples: np.ndarray) -> np.ndarray:
    """q ⊕ dq: rotation vectors composed on the right, the other dofs added."""
    out = q + dq
    if len(triples):
        out[triples] = compose(q[triples], dq[triples])
    return out


def solve_static_rotations(
    model, load: np.ndarray, steps: int = 10, tol: float = 1e-10, max_iterations: int = 30
) -> tuple[np.ndarray, np.ndarray]:
    """Configuration q (full dof vector; rotation vectors on the rotation dofs) in equilibrium
    with the nodal ``load`` (N, and N·m about the global axes), applied in ``steps`` equal
    increments, each solved by Newton's method to a relative residual ``tol``; contacts and
    gravity are ignored. Returns q and the Newton iterations of each increment. Raises
    ``SolverError`` if an increment does not converge."""
    F = model.free
    triples = model_rotation_triples(model)
    q = np.zeros(model.n)
    load = np.asarray(load, dtype=float)
    scale = max(np.linalg.norm(load[F]), 1e-300)
    iterations = np.zeros(steps, dtype=int)
    for k, lam in enumerate(np.linspace(0.0, 1.0, steps + 1)[1:]):
        for it in range(max_iterations + 1):
            _, f, K = model.internal(q)
            f_ext, K_load = _load_terms(q, load, triples, lam)
            r = f[F] - f_ext[F]
            if np.linalg.norm(r) <= tol * scale:
                break
            if it == max_iterations:
                raise SolverError(
                    f"static Newton did not converge at load factor {lam:.3g}",
                    residual=float(np.linalg.norm(r) / scale),
                )
            if K_load is not None:
                K = sp.csr_matrix(K) - K_load[F][:, F]
            dq = np.zeros(model.n)
            dq[F] = -factorize(sp.csc_matrix(K))(r)
            q = plus(q, dq, triples)
        iterations[k] = it
    return q, iterations
