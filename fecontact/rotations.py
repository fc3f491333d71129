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

__all__ = [
    "RightIncrements",
    "compose",
    "compose_quaternions",
    "cross",
    "exp",
    "hat",
    "log",
    "quaternions",
    "tangent",
    "tangent_inverse",
    "vee",
]

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


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b over the last axis of 3-vectors, broadcast over the leading axes.

    The products and differences of ``numpy.cross``, in its order (the same bits), without
    its axis handling, which costs three times the arithmetic on the small arrays of one
    contact pair or body.
    """
    a, b = np.asarray(a), np.asarray(b)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=-1)


def vee(W: np.ndarray) -> np.ndarray:
    """The vectors (…, 3) of the skew parts of the matrices ``W`` (…, 3, 3)."""
    W = np.asarray(W, dtype=float)
    return 0.5 * np.stack(
        [W[..., 2, 1] - W[..., 1, 2], W[..., 0, 2] - W[..., 2, 0], W[..., 1, 0] - W[..., 0, 1]],
        axis=-1,
    )


# (θ − sin θ)/θ³ = Σ_k (−1)^k θ^2k/(2k + 3)!: its series below θ² = 1/16, where the closed
# form loses up to 1e-14 to cancellation and the first term left out is below 1e-15 of it
_C_SERIES = np.array([1 / 6, -1 / 120, 1 / 5040, -1 / 362880, 1 / 39916800])
_C_SMALL = 0.0625


def _coefficients(psi: np.ndarray):
    """θ², sin θ/θ, (1 − cos θ)/θ² and (θ − sin θ)/θ³ of the vectors ``psi`` (…, 3): the
    first two from the half angle, sin θ/θ = s cos(θ/2) and (1 − cos θ)/θ² = ½s² with
    s = sin(θ/2)/(θ/2), free of cancellation (the angle offset as in :func:`quaternions`).
    Every operation is on arrays of one shape: numpy broadcasts small arrays ~10× slower."""
    x, y, z = psi[..., 0], psi[..., 1], psi[..., 2]
    t2 = x * x + y * y + z * z
    half = 0.5 * np.sqrt(t2) + _OFFSET
    sh = np.sin(half) / half
    a, b = sh * np.cos(half), 0.5 * sh * sh
    k4, k3, k2, k1, k0 = _C_SERIES[::-1].tolist()
    c = (((k4 * t2 + k3) * t2 + k2) * t2 + k1) * t2 + k0
    if t2.max(initial=0.0) >= _C_SMALL:
        c = np.where(t2 < _C_SMALL, c, (1.0 - a) / np.maximum(t2, _C_SMALL))
    return t2, a, b, c


def _combination_table() -> np.ndarray:
    """(13, 9): the features (k0, k1 ψ, k2 ψψᵀ flattened) @ it is k0 I + k1 ψ̃ + k2 ψψᵀ
    flattened row by row. Every entry of the table is 0 or ±1, so each matrix entry is the
    sum of its two nonzero products exactly as written out (k2ψ_iψ_j + k0, k2ψ_iψ_j ± k1ψ_k),
    whatever the order or fusion of the product's sums."""
    table = np.zeros((13, 3, 3))
    table[0] = np.eye(3)
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):  # ψ̃: (i, j) = −ψ_k, (j, i) = +ψ_k
        table[1 + k, i, j], table[1 + k, j, i] = -1.0, 1.0
    for i in range(3):
        for j in range(3):
            table[4 + 3 * i + j, i, j] = 1.0
    return table.reshape(13, 9)


_COMBINATION = _combination_table()


def _combination(psi: np.ndarray, k0, k1, k2) -> np.ndarray:
    """k0 I + k1 ψ̃ + k2 ψψᵀ (…, 3, 3) of the vectors ``psi`` (…, 3), coefficients (…): the
    products (k2 ψ_i) ψ_j and k1 ψ_k, then one product with a fixed table of 0 and ±1
    (:func:`_combination_table`: the same sums as entry by entry, in few array operations)."""
    lead = psi.shape[:-1]
    kpsi = k2[..., None] * psi
    features = np.concatenate(
        [
            k0[..., None],
            k1[..., None] * psi,
            (kpsi[..., :, None] * psi[..., None, :]).reshape(lead + (9,)),
        ],
        axis=-1,
    )
    return (features @ _COMBINATION).reshape(lead + (3, 3))


def _scalars(psi: np.ndarray):
    """θ², sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³ of one rotation vector, by math (a single
    vector is the common case of a rigid body: numpy's per-call cost would dominate), as
    :func:`_coefficients`."""
    x, y, z = psi.tolist()
    t2 = x * x + y * y + z * z
    half = 0.5 * math.sqrt(t2) + _OFFSET
    sh = math.sin(half) / half
    a = sh * math.cos(half)
    if t2 < _C_SMALL:
        c = 0.0
        for k in _C_SERIES[::-1].tolist():
            c = c * t2 + k
    else:
        c = (1.0 - a) / t2
    return t2, a, 0.5 * sh * sh, c


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
    t2, a, b, _ = _coefficients(psi)
    return _combination(psi, 1.0 - b * t2, a, b)


def tangent(psi: np.ndarray) -> np.ndarray:
    """The right tangent T(ψ) (…, 3, 3) (module docstring)."""
    psi = np.asarray(psi, dtype=float)
    if psi.shape == (3,):
        t2, _, b, c = _scalars(psi)
        return _single(psi, -b, c, 1.0 - c * t2)
    t2, _, b, c = _coefficients(psi)
    return _combination(psi, 1.0 - c * t2, -b, c)


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


_OFFSET = 1e-300  # added to an angle in a denominator: changes the ratio only at 0, to its limit


def quaternions(psi: np.ndarray) -> np.ndarray:
    """Unit quaternions (…, 4), scalar first, of the rotation vectors ``psi`` (…, 3):
    (cos(θ/2), sin(θ/2)/θ ψ). sin(θ/2)/θ has no cancellation: with the angle offset by 1e-300
    it is ½ at θ = 0 and exact to round-off elsewhere."""
    psi = np.asarray(psi, dtype=float)
    x, y, z = psi[..., 0], psi[..., 1], psi[..., 2]
    half = 0.5 * np.sqrt(x * x + y * y + z * z) + _OFFSET
    out = np.empty(psi.shape[:-1] + (4,))
    out[..., 0] = np.cos(half)
    out[..., 1:] = (0.5 * np.sin(half) / half)[..., None] * psi
    return out


def _hamilton() -> np.ndarray:
    """The (4, 4, 4) table of the quaternion product: (p d)_k = Σ_ij p_i d_j H_ijk."""
    H = np.zeros((4, 4, 4))
    H[0, 0, 0] = 1.0
    for i in range(1, 4):
        H[i, i, 0], H[0, i, i], H[i, 0, i] = -1.0, 1.0, 1.0
        j, k = i % 3 + 1, (i + 1) % 3 + 1
        H[i, j, k], H[j, i, k] = 1.0, -1.0
    return H


_HAMILTON = _hamilton()


def _vector(quat: np.ndarray) -> np.ndarray:
    """Rotation vectors (…, 3) with θ ≤ π of the quaternions ``quat`` (…, 4), of any positive
    length: 2 atan2(|u|, |w|) u/|u| with the sign of w, which is the same for (w, u) scaled
    (no normalization needed) and the same rotation as −(w, u) (θ ≤ π); atan2(s, w)/s is
    accurate down to s = 0, where u = 0 (offset as in :func:`quaternions`)."""
    w, u = quat[..., 0], quat[..., 1:]
    s = np.sqrt(u[..., 0] * u[..., 0] + u[..., 1] * u[..., 1] + u[..., 2] * u[..., 2])
    return (np.copysign(2.0, w) * np.arctan2(s, np.abs(w)) / (s + _OFFSET))[..., None] * u


_HAMILTON16 = _HAMILTON.reshape(16, 4)


def compose_quaternions(p: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """ψ ⊕ Δ (…, 3) from the quaternions ``p`` (…, 4) of ψ (:func:`quaternions`, kept by a
    caller that composes the same ψ with several Δ)."""
    d = quaternions(delta)
    pd = p[..., :, None] * d[..., None, :]
    return _vector(pd.reshape(pd.shape[:-2] + (16,)) @ _HAMILTON16)


_C_POWERS = np.arange(len(_C_SERIES))
# (4, 16): a quaternion p @ it is the matrix of p ⊗ · (flattened row by row)
_LEFT = _HAMILTON.transpose(0, 2, 1).reshape(4, 16)
_QUARTER = np.full(3, 0.25)  # (ψ * ψ) @ it is θ²/4
_ONES = np.ones(3)


def _tangent_series(identity: float) -> np.ndarray:
    """(7, 3): the powers x⁰ … x⁶ of x = θ² @ it is (k₀, k₁, k₂) of T(ψ) − (1 − identity) I =
    k₀ I + k₁ ψ̃ + k₂ ψψᵀ: k₂ = c = (θ − sin θ)/θ³ = Σ (−1)ᵏ xᵏ/(2k + 3)!, k₁ = −b =
    −(1 − cos θ)/θ² = −Σ (−1)ᵏ xᵏ/(2k + 2)!, k₀ = identity − c x; below x = 1/16 the first
    term left out is below 1e-18 of each."""
    k = np.arange(7)
    fact = np.array([math.factorial(int(n)) for n in range(17)], dtype=float)
    sign = (-1.0) ** k
    S = np.zeros((7, 3))
    S[:6, 1], S[:6, 2] = -sign[:6] / fact[2 * k[:6] + 2], sign[:6] / fact[2 * k[:6] + 3]
    S[1:, 0] = -S[:6, 2]
    S[0, 0] = identity
    return S


def _combination_pairs() -> np.ndarray:
    """(39, 9): the products (k₀, k₁, k₂) ⊗ (1, ψ, ψψᵀ flattened) @ it is k₀ I + k₁ ψ̃ + k₂ ψψᵀ
    flattened (the table of :func:`_combination`, its features each times its coefficient)."""
    T = np.zeros((3, 13, 9))
    T[0, 0], T[1, 1:4], T[2, 4:] = _COMBINATION[0], _COMBINATION[1:4], _COMBINATION[4:]
    return T.reshape(39, 9)


_T_POWERS = np.arange(7)
_T_SERIES = {1.0: _tangent_series(1.0), 0.0: _tangent_series(0.0)}
# the same in the powers of θ²/4 (each row times 4ᵏ, a power of two: exact)
_T_SERIES_QUARTER = {i: S * 4.0 ** _T_POWERS[:, None] for i, S in _T_SERIES.items()}
_C_SMALL_QUARTER = _C_SMALL / 4.0  # θ²/4 below it: θ² below _C_SMALL
_PAIRS = _combination_pairs()


class RightIncrements:
    """Increments Δ (k, 3) composed on the right of fixed rotations ψ (k, 3): ψ ⊕ Δ by
    :meth:`compose`, and the right tangents T(Δ) of the last Δ by :meth:`tangent`, from the
    same half angles (a Newton iteration on the group asks for both at each of its iterates;
    ψ's quaternions are made once, and again by :meth:`start` for other ψ, the arrays kept).
    Two-dimensional arrays throughout: the paths of
    :func:`quaternions` and :func:`_vector` without their leading-axis generality, whose
    indexing costs as much as the arithmetic at a few rotations."""

    def __init__(self, psi: np.ndarray):
        k = len(psi)
        self.left = None
        self.start(psi)
        self.ones = np.ones((k, 1))
        # the angle's offset (as :func:`quaternions`) as an array: numpy adds a Python float
        # to an array in about twice the time of an array of its shape
        self.offset = np.full(k, _OFFSET)
        self.d = np.empty((k, 4))  # Δ's quaternions, filled by each composition
        self.delta = self.x = self.sh = self.ch = None

    def start(self, psi: np.ndarray) -> None:
        """Compose on the right of the rotations ``psi`` (k, 3; as many as at construction)
        from now on: the left products p ⊗ · of their quaternions as matrices (k, 4, 4)."""
        self.left = (self._quaternions(psi)[0] @ _LEFT).reshape(-1, 4, 4)
        self.delta = self.x = self.sh = self.ch = None

    @staticmethod
    def _quaternions(psi: np.ndarray):
        """(unit quaternions (k, 4), θ²/4, θ/2 offset, sin(θ/2)/θ) of ``psi`` (k, 3)."""
        x = (psi * psi) @ _QUARTER
        half = np.sqrt(x) + _OFFSET
        s = np.sin(half) / (half + half)  # sin(θ/2)/θ, free of cancellation
        out = np.empty((len(psi), 4))
        out[:, 0] = np.cos(half)
        out[:, 1:] = s[:, None] * psi
        return out, x, half, s

    def compose(self, delta: np.ndarray) -> np.ndarray:
        """ψ ⊕ Δ (k, 3), θ ≤ π (as :func:`compose`); Δ's quaternion as :meth:`_quaternions`,
        with doublings written as sums (the same values, no Python float)."""
        self.x = x = (delta * delta) @ _QUARTER
        half = np.sqrt(x) + self.offset
        self.sh = sh = np.sin(half) / (half + half)
        d = self.d
        d[:, 0] = self.ch = np.cos(half)
        d[:, 1:] = sh[:, None] * delta
        self.delta = delta
        pd = (self.left @ d[:, :, None])[:, :, 0]
        w, u = pd[:, 0], pd[:, 1:]
        s = np.sqrt((u * u) @ _ONES)
        # 2 atan(s/w) is 2 atan2(s, |w|) sign(w): −(w, u) is the same rotation, by θ ≤ π
        a = np.arctan(s / w)
        return ((a + a) / (s + self.offset))[:, None] * u

    def tangent(self, identity: float = 1.0) -> np.ndarray:
        """T(Δ) (k, 3, 3) of the last composed Δ, less (1 − ``identity``) I (``identity`` 1 or
        0). Where every θ² < 1/16 (a Newton increment), the coefficients by their series from
        one product (of the powers of θ²/4, the table scaled by 4ᵏ: exact), and T from one
        product of them with (1, Δ, ΔΔᵀ); else (1 − cos θ)/θ² = 2 (sin(θ/2)/θ)², and
        (θ − sin θ)/θ³ by its series below θ² = 1/16 (as :func:`tangent`)."""
        x, sh, D = self.x, self.sh, self.delta
        if max(x.tolist(), default=0.0) < _C_SMALL_QUARTER:  # (a numpy reduction: 5× the time)
            k = len(D)
            K = (x[:, None] ** _T_POWERS) @ _T_SERIES_QUARTER[identity]
            F = np.concatenate([self.ones, D, (D[:, :, None] * D[:, None, :]).reshape(k, 9)], 1)
            return ((K[:, :, None] * F[:, None, :]).reshape(k, 39) @ _PAIRS).reshape(k, 3, 3)
        t2 = 4.0 * x
        c = (t2[:, None] ** _C_POWERS) @ _C_SERIES
        a = 2.0 * sh * self.ch  # sin θ/θ
        c = np.where(t2 < _C_SMALL, c, (1.0 - a) / np.maximum(t2, _C_SMALL))
        return _combination(D, identity - c * t2, -2.0 * sh * sh, c)


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
    return _vector(q)


def compose(psi: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """ψ ⊕ Δ: the rotation vectors (…, 3) of exp(ψ̃) exp(Δ̃), with θ ≤ π."""
    if np.shape(psi) == (3,) and np.shape(delta) == (3,):
        return _compose_single(np.asarray(psi, float), np.asarray(delta, float))
    return compose_quaternions(quaternions(psi), np.asarray(delta, float))


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
