r"""Rotations in space: SO(3) by rotation vectors, vectorised over any leading axes.

A rotation is stored as its rotation vector ψ (rad): R = exp(ψ̃), the angle θ = |ψ| ≤ π,
about the unit axis ψ/θ. ψ̃ is the skew matrix of ψ (ψ̃ a = ψ × a). Increments compose on the
right, in the body (material) frame: R ⊕ Δ = R exp(Δ̃), the update of a Lie-group integrator
whose angular velocities Ω are body-frame (Brüls & Cardona, J. Comput. Nonlinear Dyn. 2010).

The right tangent T(ψ) maps a change of the vector to the body-frame rotation it makes,
exp((ψ + δ)~) = exp(ψ̃) exp((T(ψ) δ)~) + O(δ²), with

    T(ψ) = I − (1 − cos θ)/θ² ψ̃ + (θ − sin θ)/θ³ ψ̃².

Compositions go through unit quaternions, whose product keeps the rotation orthogonal to
round-off over any number of steps; the result is brought back to θ ≤ π.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["compose", "exp", "hat", "log", "tangent", "tangent_inverse", "vee"]

# below this angle the closed forms lose digits to cancellation: their Taylor series are used
_SMALL = 1e-4


def hat(w: np.ndarray) -> np.ndarray:
    """The skew matrices w̃ (…, 3, 3) of the vectors ``w`` (…, 3): w̃ a = w × a."""
    w = np.asarray(w, dtype=float)
    if w.shape == (3,):  # one vector (a rigid body): numpy's per-call cost would dominate
        x, y, z = w.tolist()
        return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    W = np.zeros(w.shape + (3,))
    W[..., 0, 1], W[..., 0, 2], W[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    W[..., 1, 0], W[..., 2, 0], W[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    return W


def vee(W: np.ndarray) -> np.ndarray:
    """The vectors (…, 3) of the skew parts of the matrices ``W`` (…, 3, 3)."""
    W = np.asarray(W, dtype=float)
    return 0.5 * np.stack(
        [W[..., 2, 1] - W[..., 1, 2], W[..., 0, 2] - W[..., 2, 0], W[..., 1, 0] - W[..., 0, 1]],
        axis=-1,
    )


def _coefficients(theta: np.ndarray):
    """sin θ/θ, (1 − cos θ)/θ² and (θ − sin θ)/θ³, by their series near θ = 0."""
    t2 = theta * theta
    small = theta < _SMALL
    safe = np.where(small, 1.0, theta)
    a = np.where(small, 1.0 - t2 / 6.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - t2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    c = np.where(small, 1.0 / 6.0 - t2 / 120.0, (safe - np.sin(safe)) / safe**3)
    return a, b, c


def _scalars(psi: np.ndarray):
    """θ², sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³ of one rotation vector, by math (a single
    vector is the common case of a rigid body: numpy's per-call cost would dominate)."""
    x, y, z = psi.tolist()
    t2 = x * x + y * y + z * z
    if t2 < _SMALL * _SMALL:
        return t2, 1.0 - t2 / 6.0, 0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0
    t = math.sqrt(t2)
    s, c = math.sin(t), math.cos(t)
    return t2, s / t, (1.0 - c) / t2, (t - s) / (t2 * t)


def _single(psi: np.ndarray, k1: float, k2: float, k0: float) -> np.ndarray:
    """k0 I + k1 ψ̃ + k2 ψψᵀ of one vector."""
    x, y, z = psi.tolist()
    return np.array(
        [
            [k0 + k2 * x * x, k2 * x * y - k1 * z, k2 * x * z + k1 * y],
            [k2 * y * x + k1 * z, k0 + k2 * y * y, k2 * y * z - k1 * x],
            [k2 * z * x - k1 * y, k2 * z * y + k1 * x, k0 + k2 * z * z],
        ]
    )


def exp(psi: np.ndarray) -> np.ndarray:
    """R = exp(ψ̃) (…, 3, 3) of the rotation vectors ``psi`` (…, 3) (Rodrigues)."""
    psi = np.asarray(psi, dtype=float)
    if psi.shape == (3,):  # ψ̃² = ψψᵀ − θ²I
        t2, a, b, _ = _scalars(psi)
        return _single(psi, a, b, 1.0 - b * t2)
    a, b, _ = _coefficients(np.linalg.norm(psi, axis=-1))
    P = hat(psi)
    return np.eye(3) + a[..., None, None] * P + b[..., None, None] * (P @ P)


def tangent(psi: np.ndarray) -> np.ndarray:
    """The right tangent T(ψ) (…, 3, 3) (module docstring)."""
    psi = np.asarray(psi, dtype=float)
    if psi.shape == (3,):
        t2, _, b, c = _scalars(psi)
        return _single(psi, -b, c, 1.0 - c * t2)
    _, b, c = _coefficients(np.linalg.norm(psi, axis=-1))
    P = hat(psi)
    return np.eye(3) - b[..., None, None] * P + c[..., None, None] * (P @ P)


def tangent_inverse(psi: np.ndarray) -> np.ndarray:
    """T(ψ)⁻¹ (…, 3, 3) = I + ½ψ̃ + (1/θ² − (1 + cos θ)/(2θ sin θ)) ψ̃², for θ < π."""
    psi = np.asarray(psi, dtype=float)
    theta = np.linalg.norm(psi, axis=-1)
    small = theta < _SMALL
    safe = np.where(small, 1.0, theta)
    d = np.where(
        small,
        1.0 / 12.0 + theta**2 / 720.0,
        1.0 / safe**2 - (1.0 + np.cos(safe)) / (2.0 * safe * np.sin(safe)),
    )
    P = hat(psi)
    return np.eye(3) + 0.5 * P + d[..., None, None] * (P @ P)


def _quaternion(psi: np.ndarray) -> np.ndarray:
    """Unit quaternions (…, 4), scalar first, of the rotation vectors ``psi``."""
    theta = np.linalg.norm(psi, axis=-1)
    half = 0.5 * theta
    small = theta < _SMALL
    # sin(θ/2)/θ, by its series near 0
    s = np.where(small, 0.5 - theta**2 / 48.0, np.sin(half) / np.where(small, 1.0, theta))
    return np.concatenate([np.cos(half)[..., None], s[..., None] * psi], axis=-1)


def _vector(quat: np.ndarray) -> np.ndarray:
    """Rotation vectors (…, 3) with θ ≤ π of the unit quaternions ``quat`` (…, 4)."""
    quat = np.where(quat[..., :1] < 0.0, -quat, quat)  # the same rotation, θ ≤ π
    w, u = quat[..., 0], quat[..., 1:]
    s = np.linalg.norm(u, axis=-1)
    small = s < _SMALL
    safe = np.where(small, 1.0, s)
    # θ/sin(θ/2) = 2 atan2(s, w)/s, by its series 2(1 − s²/3w²)/w as s → 0 (w → 1)
    scale = np.where(small, 2.0 / w * (1.0 - s**2 / (3.0 * w**2)), 2.0 * np.arctan2(s, w) / safe)
    return scale[..., None] * u


def log(R: np.ndarray) -> np.ndarray:
    """Rotation vectors (…, 3), θ ≤ π, of the rotation matrices ``R`` (…, 3, 3).

    The quaternion comes from the largest of its four components (Shepperd 1978): each row of
    the matrix below is 4 q_i q, accurate where q_i is large, also near θ = π."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R, axis1=-2, axis2=-1)
    a, b, c = R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]
    d, e, f = R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0], R[..., 1, 2] + R[..., 2, 1]
    x, y, z = (1.0 + 2.0 * R[..., i, i] - tr for i in range(3))
    rows = np.stack(
        [
            np.stack([1.0 + tr, a, b, c], -1),
            np.stack([a, x, d, e], -1),
            np.stack([b, d, y, f], -1),
            np.stack([c, e, f, z], -1),
        ],
        -2,
    )
    k = np.argmax(np.stack([1.0 + tr, x, y, z], -1), axis=-1)
    q = np.take_along_axis(rows, k[..., None, None], axis=-2)[..., 0, :]
    return _vector(q / np.linalg.norm(q, axis=-1, keepdims=True))


def compose(psi: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """ψ ⊕ Δ: the rotation vectors (…, 3) of exp(ψ̃) exp(Δ̃), with θ ≤ π."""
    if np.shape(psi) == (3,) and np.shape(delta) == (3,):
        return _compose_single(np.asarray(psi, float), np.asarray(delta, float))
    p, d = _quaternion(np.asarray(psi, float)), _quaternion(np.asarray(delta, float))
    w = p[..., 0] * d[..., 0] - np.sum(p[..., 1:] * d[..., 1:], axis=-1)
    u = p[..., :1] * d[..., 1:] + d[..., :1] * p[..., 1:] + np.cross(p[..., 1:], d[..., 1:])
    q = np.concatenate([w[..., None], u], axis=-1)
    return _vector(q / np.linalg.norm(q, axis=-1, keepdims=True))


def _half(v: np.ndarray):
    """(cos(θ/2), sin(θ/2)/θ) of one rotation vector (series near θ = 0)."""
    x, y, z = v.tolist()
    t = math.sqrt(x * x + y * y + z * z)
    if t < _SMALL:
        return math.cos(0.5 * t), 0.5 - t * t / 48.0
    return math.cos(0.5 * t), math.sin(0.5 * t) / t


def _compose_single(psi: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """``compose`` of one pair of vectors, by math: the quaternion product and back."""
    (pw, ps), (dw, ds) = _half(psi), _half(delta)
    p, d = (ps * psi).tolist(), (ds * delta).tolist()
    w = pw * dw - (p[0] * d[0] + p[1] * d[1] + p[2] * d[2])
    u = [
        pw * d[0] + dw * p[0] + p[1] * d[2] - p[2] * d[1],
        pw * d[1] + dw * p[1] + p[2] * d[0] - p[0] * d[2],
        pw * d[2] + dw * p[2] + p[0] * d[1] - p[1] * d[0],
    ]
    n = math.sqrt(w * w + u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
    return _vector_single(w / n, [u[0] / n, u[1] / n, u[2] / n])


def _vector_single(w: float, u: list) -> np.ndarray:
    """``_vector`` of one unit quaternion (w, u), by math."""
    if w < 0.0:
        w, u = -w, [-u[0], -u[1], -u[2]]
    s = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    if s < _SMALL:
        scale = 2.0 / w * (1.0 - s**2 / (3.0 * w**2))
    else:
        scale = 2.0 * math.atan2(s, w) / s
    return np.array([scale * u[0], scale * u[1], scale * u[2]])
