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

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .errors import SolverError, check_count
from .linalg import factorize
from .rotations import compose, exp, hat

__all__ = ["StaticSolution", "model_rotation_triples", "plus", "solve_static_rotations"]


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


@dataclass(frozen=True)
class StaticSolution:
    """A static solve: the configuration ``q`` (full dof vector), the load factors reached
    (``factors``, each increment's end), the Newton iterations of each increment
    (``iterations``) and the increments that did not converge and were halved (``cuts``)."""

    q: np.ndarray
    factors: np.ndarray
    iterations: np.ndarray
    cuts: int


def _newton(model, q, load, triples, lam, tol, scale, max_iterations):
    """q in equilibrium with lam × load from the guess q, and its iterations; None when the
    residual does not fall below tol × scale (or an update to the round-off of the coordinates,
    extent ε, with the residual within 1000 × that) in max_iterations or stops being finite."""
    F = model.free
    extent = max(model.coordinate_extent(q), 1.0)
    for it in range(max_iterations + 1):
        _, f, K = model.internal(q)
        f_ext, K_load = _load_terms(q, load, triples, lam)
        r = f[F] - f_ext[F]
        norm = np.linalg.norm(r)
        if norm <= tol * scale:
            return q, it
        if it == max_iterations or not np.isfinite(norm):
            return None
        if K_load is not None:
            K = sp.csr_matrix(K) - K_load[F][:, F]
        dq = np.zeros(model.n)
        try:
            dq[F] = -factorize(sp.csc_matrix(K))(r)
        except np.linalg.LinAlgError:
            return None
        q = plus(q, dq, triples)
        # an update at the round-off of the coordinates: the residual is at its floor (the
        # axial force of a chord carries EA ε |x| / ℓ of noise), if near the tolerance
        if np.max(np.abs(dq)) <= 1e-14 * extent and norm <= 1e3 * tol * scale:
            return q, it + 1
    return None


def solve_static_rotations(
    model,
    load: np.ndarray,
    steps: int = 10,
    tol: float = 1e-10,
    max_iterations: int = 30,
    max_cuts: int = 10,
) -> StaticSolution:
    """Configuration in equilibrium with the nodal ``load`` (N, and N·m about the global axes),
    applied in ``steps`` equal increments of the load factor, each solved by Newton's method to
    a relative residual ``tol``; contacts and gravity are ignored. An increment whose Newton
    iteration does not converge in ``max_iterations`` is halved and tried again from the last
    equilibrium (counted in ``cuts``), the next one doubled back toward the asked size;
    ``SolverError`` after ``max_cuts`` halvings in a row."""
    triples = model_rotation_triples(model)
    q = np.zeros(model.n)
    load = np.asarray(load, dtype=float)
    scale = max(np.linalg.norm(load[model.free]), 1e-300)
    full = 1.0 / check_count("steps", steps)
    lam, step, cuts, failed = 0.0, full, 0, 0
    factors, iterations = [], []
    while lam < 1.0 - 1e-12:
        target = min(1.0, lam + step)
        done = _newton(model, q, load, triples, target, tol, scale, max_iterations)
        if done is None:
            cuts, failed = cuts + 1, failed + 1
            if failed > max_cuts:
                raise SolverError(f"static Newton did not converge at load factor {target:.3g}")
            step *= 0.5
            continue
        # back toward the asked increment once one converges
        q, it = done
        lam, step, failed = target, min(full, 2.0 * step), 0
        factors.append(lam)
        iterations.append(it)
    return StaticSolution(q, np.array(factors), np.array(iterations, dtype=int), cuts)
