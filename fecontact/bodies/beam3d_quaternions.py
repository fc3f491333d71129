r"""The nodes' rotations of :class:`~fecontact.bodies.beam3d.Beam3D` as unit quaternions, in
few array operations (with a handful of nodes a kernel's time is that of its numpy calls).

A node's rotation vector ψ (rad, |ψ| ≤ π) has the unit quaternion q = (cos(θ/2), sin(θ/2)/θ ψ),
scalar first; R = exp(ψ̃) is (w² − u·u) I + 2w ũ + 2uuᵀ of q = (w, u), one product of the
products q_k q_l with a fixed table. Two consecutive nodes' relative rotation R₀ᵀR₁ is that of
r = q̄₀ ⊗ q₁ = (w, v), whose rotation vector is ρ = 2 atan(|v|/w) v/|v|: the shorter arc
whatever the sign of w (q and −q are one rotation), free of the cancellation that the
logarithm of the matrix has near θ = π.
"""

from __future__ import annotations

import numpy as np

__all__ = ["node_quaternions", "quaternion_matrices", "relative_rotations", "rotation_matrices"]

_TINY = 1e-300  # added to an angle in a denominator: changes the ratio only at 0, to its limit
# the same and ½, 1 as 0-d arrays: numpy combines an array with a Python float in about twice
# the time of a 0-d array (the same values, bit for bit)
_TINY0, _HALF0, _ONE0 = np.array(_TINY), np.array(0.5), np.array(1.0)
_QUARTER = np.full(3, 0.25)  # (ψ * ψ) @ it is θ²/4
_ONES = np.ones(3)


def _skew() -> np.ndarray:
    """(3, 3, 3): w̃ = Σ_k w_k S_k."""
    S = np.zeros((3, 3, 3))
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        S[k, i, j], S[k, j, i] = -1.0, 1.0
    return S


def _rotation_table() -> np.ndarray:
    """(16, 9): the products q_k q_l of a unit quaternion q = (w, u) (flattened k, l) @ it
    is R = (w² − u·u) I + 2w ũ + 2uuᵀ flattened row by row."""
    eye = np.eye(3)
    Q = np.zeros((4, 4, 3, 3))
    Q[0, 0] = eye
    Q[1:, 1:] -= eye[:, :, None, None] * eye  # −(u·u) I
    Q[1:, 1:] += 2.0 * np.einsum("ki,lj->klij", eye, eye)  # 2uuᵀ
    Q[0, 1:] += _skew()
    Q[1:, 0] += _skew()  # 2w ũ, split between the products w u_k and u_k w
    return Q.reshape(16, 9)


def _relative_table() -> np.ndarray:
    """(16, 4): the products p_i d_j of two quaternions (flattened i, j) @ it is p̄ ⊗ d, the
    conjugate of p times d: (p₀d₀ + p·d, p₀d − d₀p − p × d)."""
    T = np.zeros((4, 4, 4))
    T[0, 0, 0] = 1.0
    for i in range(1, 4):
        T[i, i, 0], T[0, i, i], T[i, 0, i] = 1.0, 1.0, -1.0
    T[1:, 1:, 1:] += _skew().transpose(1, 2, 0)  # −(p × d)_m = S[m, i, j] p_i d_j
    return T.reshape(16, 4)


_ROTATION, _RELATIVE = _rotation_table(), _relative_table()


def node_quaternions(psi: np.ndarray) -> np.ndarray:
    """Unit quaternions (n, 4), scalar first, of the rotation vectors ψ (n, 3; rad):
    (cos(θ/2), sin(θ/2)/θ ψ), with θ/2 = √(ψ·ψ/4) offset by 1e-300, which changes
    sin(θ/2)/θ only at 0, where it makes it ½."""
    h = np.sqrt((psi * psi) @ _QUARTER) + _TINY0
    q = np.empty((len(psi), 4))
    q[:, 0] = np.cos(h)
    q[:, 1:] = (_HALF0 * np.sin(h) / h)[:, None] * psi
    return q


def quaternion_matrices(q: np.ndarray) -> np.ndarray:
    """R (n, 3, 3) of the quaternions q (n, 4), unit, or scaled by s: then s² R."""
    return ((q[:, :, None] * q[:, None, :]).reshape(-1, 16) @ _ROTATION).reshape(-1, 3, 3)


def rotation_matrices(psi: np.ndarray) -> np.ndarray:
    """R = exp(ψ̃) (n, 3, 3) of the rotation vectors ψ (n, 3; rad), as
    :func:`fecontact.rotations.exp` to round-off."""
    return quaternion_matrices(node_quaternions(psi))


def relative_rotations(N: np.ndarray):
    """Of consecutive nodes' unit quaternions N (n, 4): the rotation vectors ρ (n − 1, 3) of
    R₀ᵀR₁, their angles times the sign of w, θ sign(w) (so θ² is the angle squared), and w,
    the scalar part of r = q̄₀ ⊗ q₁ (module docstring; NaN-free but for w = 0, an element
    turned by π)."""
    r = (N[:-1, :, None] * N[1:, None, :]).reshape(-1, 16) @ _RELATIVE
    w, v = r[:, 0], r[:, 1:]
    s = np.sqrt((v * v) @ _ONES)
    half = np.arctan(s / w)
    theta = half + half  # (2θ/2 exactly, without a Python float operand)
    return (theta / (s + _TINY0))[:, None] * v, theta, w
