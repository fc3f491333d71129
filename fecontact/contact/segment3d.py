r"""Distance in space between a segment and a point or a second segment, with its exact first
and second derivatives: the kinematics of tubes (beams of radius r about their centrelines).

A segment (a, b) has the points x₁(ξ) = (1 − ξ)a + ξb, ξ ∈ [0, 1]; its partner is a point c
(k = 1) or a segment x₂(η) = (1 − η)c + ηd (k = 2). The distance of the closest points,

    f(y) = min_{s ∈ [0, 1]^k'} |r(s, y)|,  r = x₁(ξ) − x₂(η),  s = (ξ, η),

is taken with respect to the end points y = (a, b, c[, d]) (3(2 + k) coordinates). With
e = r/f and K = (I − e eᵀ)/f, ∂r/∂y = A and ∂r/∂s = B (constant in y and s):

    ∂f/∂y = Aᵀe,
    ∇²f = AᵀKA − F_syᵀ F_ss⁻¹ F_sy,  F_ss = BᵀKB,  F_sy = BᵀKA + eᵀ ∂²r/∂s∂y,

the second term over the parameters strictly inside [0, 1] only (a parameter at a bound is
held there: the classical beam-to-beam point contact of Wriggers & Zavarise, Commun. Numer.
Meth. Engng 1997, whose parameters make the distance stationary). Two parallel segments have
no single closest pair: the overlap of their projections is taken at its middle, and F_ss,
singular there (the points can slide together along the overlap at no change of f), is
inverted in the least-squares sense. The derivatives hold where f > 0.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["closest_parameters", "closest_segments", "tube_distance"]

_EYE = np.eye(3)
PARALLEL = 1e-12
"""sin² of the angle below which two segments are parallel (their overlap's middle is taken)."""


def closest_parameters(P: np.ndarray, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The parameters ξ (m,) on the segments P (m, 2, 3) and η (m,) on the partners Q
    (m, k, 3; η = 0 for a point) of their closest points."""
    a, d1 = P[:, 0], P[:, 1] - P[:, 0]
    A = np.einsum("mi,mi->m", d1, d1)
    if Q.shape[1] == 1:
        xi = np.clip(np.einsum("mi,mi->m", Q[:, 0] - a, d1) / A, 0.0, 1.0)
        return xi, np.zeros(len(P))
    c, d2 = Q[:, 0], Q[:, 1] - Q[:, 0]
    r0 = a - c
    B, C = np.einsum("mi,mi->m", d1, d2), np.einsum("mi,mi->m", d1, r0)
    E, F = np.einsum("mi,mi->m", d2, d2), np.einsum("mi,mi->m", d2, r0)
    den = A * E - B * B
    parallel = den <= PARALLEL * A * E
    xi = np.empty(len(P))
    ok = ~parallel
    xi[ok] = np.clip((B[ok] * F[ok] - C[ok] * E[ok]) / den[ok], 0.0, 1.0)
    if parallel.any():  # the middle of the overlap of Q's projection on P's line
        tc = -C[parallel] / A[parallel]
        td = (B[parallel] - C[parallel]) / A[parallel]
        lo = np.maximum(0.0, np.minimum(tc, td))
        hi = np.minimum(1.0, np.maximum(tc, td))
        xi[parallel] = np.clip(0.5 * (lo + hi), 0.0, 1.0)
    eta = (B * xi + F) / E
    low, high = eta < 0.0, eta > 1.0
    eta = np.clip(eta, 0.0, 1.0)
    xi[low] = np.clip(-C[low] / A[low], 0.0, 1.0)
    xi[high] = np.clip((B[high] - C[high]) / A[high], 0.0, 1.0)
    return xi, eta


def closest_segments(P: np.ndarray, X: np.ndarray, tie: float) -> np.ndarray:
    """For each segment P (m, 2, 3), the index of the closest of the segments X (n, 2, 3).
    Distances within ``tie`` (m) of the least are ties (a segment lying along two collinear
    ones), decided by the longest overlap of the projection on P's line among partners along
    it (within ``ALONG``), else by the first index, so that round-off does not move the
    contact from one to the other between two evaluations."""
    m, n = len(P), len(X)
    Pa, Qa = np.repeat(P, n, axis=0), np.tile(X, (m, 1, 1))
    xi, eta = closest_parameters(Pa, Qa)
    x1 = Pa[:, 0] + xi[:, None] * (Pa[:, 1] - Pa[:, 0])
    x2 = Qa[:, 0] + eta[:, None] * (Qa[:, 1] - Qa[:, 0])
    dist = np.linalg.norm(x1 - x2, axis=1).reshape(m, n)
    d1 = Pa[:, 1] - Pa[:, 0]
    A = np.einsum("mi,mi->m", d1, d1)
    tc = np.einsum("mi,mi->m", Qa[:, 0] - Pa[:, 0], d1) / A
    td = np.einsum("mi,mi->m", Qa[:, 1] - Pa[:, 0], d1) / A
    lo, hi = np.clip(np.minimum(tc, td), 0.0, 1.0), np.clip(np.maximum(tc, td), 0.0, 1.0)
    d2 = Qa[:, 1] - Qa[:, 0]
    c = np.cross(d1, d2)
    sin2 = np.einsum("mi,mi->m", c, c) / (A * np.einsum("mi,mi->m", d2, d2))
    # a partner along P's line ranks by its overlap; one across it ranks after them all, the
    # first index among such ties: P crossing the two segments of a kink of X is as near to
    # both at mirrored points, their overlaps the projection of X's node, which the
    # deformation moves, and the partner taken then changed between the iterates of a
    # correction, each with its own gradient (the correction cycled)
    rank = np.where(sin2 < ALONG, 1.0 + hi - lo, 0.0).reshape(m, n)
    tied = dist <= dist.min(axis=1)[:, None] + tie
    return np.argmax(np.where(tied, rank, -1.0), axis=1)


ALONG = 1e-6
"""sin² of the angle (about 1 mrad) below which a partner lies along a segment and the
longest overlap decides a tie of distances (:func:`closest_segments`)."""


def _weights(xi: np.ndarray, eta: np.ndarray, k: int) -> np.ndarray:
    """Coefficients (m, 2 + k) of the end points in r = x₁ − x₂."""
    w = [1.0 - xi, xi, -(1.0 - eta), -eta] if k == 2 else [1.0 - xi, xi, -np.ones_like(xi)]
    return np.stack(w, axis=1)


def tube_distance(P: np.ndarray, Q: np.ndarray, hessian: bool = True):
    """Distance f (m,) of the closest points of the segments P (m, 2, 3) and the points or
    segments Q (m, k, 3), its unit direction e (m, 3) from Q's point to P's, the parameters
    (ξ, η), the gradient (m, 3(2 + k)) and the Hessian (m, 3(2 + k), 3(2 + k); None unless
    ``hessian``) with respect to the end points (P's, then Q's), as in the module docstring."""
    m, k = len(P), Q.shape[1]
    xi, eta = closest_parameters(P, Q)
    w = _weights(xi, eta, k)
    ends = np.concatenate([P, Q], axis=1)
    r = np.einsum("mj,mji->mi", w, ends)
    f = np.linalg.norm(r, axis=1)
    if np.any(f == 0.0):
        raise InputError("two beam centrelines (or a centreline and a centre) meet: no normal")
    e = r / f[:, None]
    G = (w[:, :, None] * e[:, None, :]).reshape(m, -1)
    if not hessian:
        return f, e, (xi, eta), G, None
    K = (_EYE - e[:, :, None] * e[:, None, :]) / f[:, None, None]
    A = np.einsum("mj,ik->mijk", w, _EYE).reshape(m, 3, -1)  # ∂r/∂y
    H = np.einsum("mia,mij,mjb->mab", A, K, A)
    free = np.stack([(xi > 0.0) & (xi < 1.0), (eta > 0.0) & (eta < 1.0)], axis=1)[:, :k]
    if free.any():
        H -= _held_parameters(ends, e, K, A, free)
    return f, e, (xi, eta), G, H


def _held_parameters(ends, e, K, A, free):
    """F_syᵀ F_ss⁻¹ F_sy (m, 3n, 3n) over the free parameters (module docstring)."""
    m, n, k = len(ends), ends.shape[1], free.shape[1]
    d1 = ends[:, 1] - ends[:, 0]
    B = [d1] if k == 1 else [d1, ends[:, 2] - ends[:, 3]]  # ∂r/∂ξ, ∂r/∂η
    B = np.stack(B, axis=2)  # (m, 3, k)
    # ∂²r/∂s∂y: ξ moves from a to b, η (on −x₂) from d to c
    mix = np.zeros((k, n))
    mix[0, :2] = (-1.0, 1.0)
    if k == 2:
        mix[1, 2:] = (1.0, -1.0)
    F_sy = np.einsum("mis,mij,mjy->msy", B, K, A)
    F_sy += np.einsum("sn,mi->msni", mix, e).reshape(m, k, -1)
    F_ss = np.einsum("mis,mij,mjt->mst", B, K, B)
    F_sy *= free[:, :, None]
    hold = free[:, :, None] & free[:, None, :]
    F_ss = np.where(hold, F_ss, 0.0) + np.eye(k) * (~free)[:, :, None]
    return np.einsum("msy,mst,mtz->myz", F_sy, np.linalg.pinv(F_ss, rcond=1e-10), F_sy)
