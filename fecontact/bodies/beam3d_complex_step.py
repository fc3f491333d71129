r"""The complex-step reference for the tangent of :mod:`.beam3d_kernels`: the same element
force written with functions analytic in their arguments (the rotation coefficients as series
or closed forms of θ², the logarithm through tan(θ/2)), evaluated in complex arithmetic at q
and at q ⊕ ih e_k for each element dof (Squire & Trapp, SIAM Rev. 1998). Each column of the
tangent is then exact to round-off with no step to choose. It is slow (numpy calls on complex
arrays); the tests check the analytic tangent of :func:`.beam3d_kernels.beam3d_internal`
against it."""

from __future__ import annotations

import numpy as np

from ..rotations import exp as rotation_exp
from ..rotations import hat
from .beam3d_kernels import Beam3DElements

__all__ = ["complex_step_internal"]

_E1 = np.array([1.0, 0.0, 0.0])
# θ² below which the closed forms lose digits: their series (error below θ⁸ ~ 1e-24)
_SMALL2 = 1e-6
_STEP = 1e-30  # complex step: far below round-off of any first-order term


def _coefficients(t2):
    """(4, …): sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³, 1/θ² − (1 + cos θ)/(2θ sin θ) of θ²,
    by their series where Re θ² < _SMALL2 (only the branch some entry needs is evaluated)."""
    small = np.real(t2) < _SMALL2
    if small.all():
        return _series(t2)
    safe = np.where(small, 1.0, t2)
    t = np.sqrt(safe)
    s, c = np.sin(t), np.cos(t)
    closed = np.stack(
        [s / t, (1 - c) / safe, (t - s) / (safe * t), 1 / safe - (1 + c) / (2 * t * s)]
    )
    return np.where(small, _series(t2), closed) if small.any() else closed


def _series(x):
    """The series of the four coefficients in x = θ² (error below x⁴/10⁵)."""
    return np.stack(
        [
            1 - x / 6 * (1 - x / 20 * (1 - x / 42)),
            0.5 - x / 24 * (1 - x / 30 * (1 - x / 56)),
            1 / 6 - x / 120 * (1 - x / 42 * (1 - x / 72)),
            1 / 12 + x / 720 + x * x / 30240 + x**3 / 1209600,
        ]
    )


def _rotation_functions(rho):
    """exp(ρ̃), T(ρ)⁻¹, exp(½ρ̃) and T(½ρ) (each …, 3, 3), from one skew matrix and its square."""
    t2 = np.sum(rho * rho, axis=-1)
    (a1, b1, _, d1), (a2, b2, c2, _) = np.moveaxis(_coefficients(np.stack([t2, 0.25 * t2])), 1, 0)
    P = hat_any(rho)
    P2 = P @ P
    I3 = np.eye(3)

    def combine(x, y):
        return I3 + np.asarray(x)[..., None, None] * P + y[..., None, None] * P2

    return (
        combine(a1, b1),
        combine(0.5, d1),
        combine(0.5 * a2, 0.25 * b2),
        combine(-0.5 * b2, 0.25 * c2),
    )


def _log(R):
    """Rotation vector of R (θ < π), through θ = 2 atan(s/(1 + c)), s = sin θ, c = cos θ."""
    a = 0.5 * np.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]],
        axis=-1,
    )
    c1 = 0.5 * (np.trace(R, axis1=-2, axis2=-1) + 1.0)  # 1 + cos θ
    # an element turned by π over its length (a Newton iterate far from any motion) gives
    # NaN here, which the caller's convergence checks report
    with np.errstate(divide="ignore", invalid="ignore"):
        x2 = np.sum(a * a, axis=-1) / (c1 * c1)  # tan²(θ/2)
        # atan(x)/x by its series where x² is small
        small = np.real(x2) < _SMALL2
        safe = np.sqrt(np.where(small, 1.0, x2))
        ratio = np.where(small, 1 - x2 / 3 + x2 * x2 / 5 - x2**3 / 7, np.arctan(safe) / safe)
        return (2.0 * ratio / c1)[..., None] * a


def hat_any(w):
    """Skew matrices of real or complex vectors w (…, 3)."""
    W = np.zeros(w.shape + (3,), dtype=w.dtype)
    W[..., 0, 1], W[..., 0, 2], W[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    W[..., 1, 0], W[..., 2, 0], W[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    return W


def _mv(A, x):
    return (A @ x[..., None])[..., 0]


def _mtv(A, x):
    return (x[..., None, :] @ A)[..., 0, :]


# -- strains and forces ---------------------------------------------------------------------
def _kinematics(el, R0, R1, x0, x1):
    """ρ, R_m, γ̂, Γ, K, Λ₀ and ℓ of the elements (any axes between the element's and the
    vectors')."""
    ell = el.ell.reshape(el.ell.shape + (1,) * (x0.ndim - 2))[..., None]
    L0 = el.L0.reshape(el.L0.shape[:1] + (1,) * (x0.ndim - 2) + (3, 3))
    rho = _log(np.swapaxes(R0, -1, -2) @ R1)
    gh_L0 = (x1 - x0) / ell  # x′, turned below
    return rho, gh_L0, L0, ell


def _force(el, R0, R1, x0, x1):
    """Element forces (…, 12) on (x₀, θ₀, x₁, θ₁) and the strain energies (…) (docstring)."""
    rho, xp, L0, ell = _kinematics(el, R0, R1, x0, x1)
    exp_rho, Tinv_rho, Rh, T_half = _rotation_functions(rho)
    Rm = R0 @ Rh
    gh = _mtv(Rm, xp)
    Gam, Kap = _mtv(L0, gh) - _E1, _mtv(L0, rho) / ell
    N, M = el.C[:3] * Gam, el.C[3:] * Kap
    n, m = _mv(L0, N), _mv(L0, M)
    p = ell * np.cross(n, gh)
    t = _mtv(Tinv_rho, m + 0.5 * _mtv(T_half, p))
    fx = _mv(Rm, n)
    f = np.concatenate([-fx, _mv(Rh, p) - _mv(exp_rho, t), fx, t], axis=-1)
    W = 0.5 * ell[..., 0] * (np.sum(N * Gam, axis=-1) + np.sum(M * Kap, axis=-1))
    return f, W


def _nodal(el, X, q):
    Q = q.reshape(-1, 6)
    R = rotation_exp(Q[:, 3:])
    x = X + Q[:, :3]
    return R[el.n0], R[el.n1], x[el.n0], x[el.n1]


def _perturbations():
    """(13, 2, 3) translations and (13, 2, 3, 3) rotations i h ẽ_c of the complex step: none,
    then one per element dof (x₀, θ₀, x₁, θ₁). R exp(ih ẽ) = R (I + ih ẽ) + O(h²), the O(h²)
    far below round-off."""
    dx = np.zeros((13, 2, 3), dtype=complex)
    dR = np.zeros((13, 2, 3, 3), dtype=complex)
    dR[:] = np.eye(3)
    for k in range(12):
        a, c = divmod(k, 6)
        if c < 3:
            dx[k + 1, a, c] = 1j * _STEP
        else:
            dR[k + 1, a] += 1j * _STEP * hat(np.eye(3)[c - 3])
    return dx, dR


_DX, _DR = _perturbations()


def complex_step_internal(el: Beam3DElements, X: np.ndarray, q: np.ndarray):
    """Element forces (E, 12), energies (E) and tangents ∂f(q ⊕ Δ)/∂Δ (E, 12, 12) by one
    complex evaluation at the 13 points q and q ⊕ ihe_k: the real parts are f and W (to
    O(h²), nothing), the imaginary parts over h the columns. Exact to round-off and slow (its
    cost is that of numpy calls on complex arrays): the reference the analytic tangent of
    :func:`.beam3d_kernels.beam3d_internal` is checked against."""
    R0, R1, x0, x1 = _nodal(el, X, q)
    R = np.stack([R0, R1], axis=1)[:, None] @ _DR  # (E, 13, 2, 3, 3)
    x = np.stack([x0, x1], axis=1)[:, None] + _DX
    fk, Wk = _force(el, R[:, :, 0], R[:, :, 1], x[:, :, 0], x[:, :, 1])
    return fk[:, 0].real, Wk[:, 0].real, np.swapaxes(fk[:, 1:].imag, 1, 2) / _STEP
