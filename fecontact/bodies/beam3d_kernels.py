r"""Kernels of the spatial Simo–Reissner beam of :class:`~fecontact.bodies.beam3d.Beam3D`:
two-node elements with the one-point rule, vectorised over the elements.

A node a carries its position x_a = X_a + u_a and the rotation R_a = exp(ψ̃_a) from the
reference configuration; the section frame of element e at node a is Λ_a = R_a Λ₀ with Λ₀ the
element's reference triad (columns: tangent E₁, section axes 2 and 3). Rotation increments act
on the right, R_a exp(δθ̃_a), δθ_a in the frame R_a (the dofs of the 3D contract).

Strains (Crisfield & Jelenić, Proc. R. Soc. Lond. A 1999): the relative rotation
ρ = log(R₀ᵀR₁) is interpolated from node 0, R(s) = R₀ exp((s/ℓ) ρ̃), which for two nodes is the
midpoint rotation R_m = R₀ exp(½ρ̃) at the quadrature point, the same from either end: the
strains are objective and path-independent. With x′ = (x₁ − x₀)/ℓ,

    Γ = Λ₀ᵀ R_mᵀ x′ − E₁,    K = Λ₀ᵀ ρ / ℓ,

Γ (axial, shear 2, shear 3) and K (torsion, bending 2, bending 3, 1/m) in the section frame,
and W = ½ ℓ (Γᵀ C_Γ Γ + Kᵀ C_K K), C_Γ = diag(EA, GA₂, GA₃), C_K = diag(GJ, EI₂, EI₃).

Variations in the frame R (hats): γ̂ = R_mᵀ x′, n̂ = Λ₀ C_Γ Γ, m̂ = Λ₀ C_K K,
δρ = T(ρ)⁻¹(δθ₁ − exp(−ρ̃)δθ₀), δγ̂ = γ̂~ (exp(−½ρ̃)δθ₀ + ½T(½ρ)δρ) + R_mᵀ(δx₁ − δx₀)/ℓ,
with T the right tangent of :mod:`fecontact.rotations`. So, with p = ℓ n̂ × γ̂ and
t = T(ρ)⁻ᵀ(m̂ + ½T(½ρ)ᵀp), the element force is

    f_x₀ = −R_m n̂,  f_x₁ = R_m n̂,  f_θ₀ = exp(½ρ̃) p − exp(ρ̃) t,  f_θ₁ = t.

Its tangent ∂f(q ⊕ Δ)/∂Δ is the complex-step derivative of this force (Squire & Trapp, SIAM
Rev. 1998): every function below is analytic in its arguments (the rotation coefficients are
series or closed forms of θ², the logarithm goes through tan(θ/2)), so one complex evaluation
per element dof gives each column exactly, to round-off, with no step to choose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..rotations import exp as rotation_exp
from ..rotations import hat

__all__ = ["Beam3DElements", "beam3d_internal", "beam3d_strains", "reference_triads"]

_E1 = np.array([1.0, 0.0, 0.0])
# θ² below which the closed forms lose digits: their series (error below θ⁸ ~ 1e-24)
_SMALL2 = 1e-6
_STEP = 1e-30  # complex step: far below round-off of any first-order term


@dataclass(frozen=True)
class Beam3DElements:
    """Per-element data, computed once: end nodes ``n0``, ``n1``, ``dofs`` (E, 12), length
    ``ell`` (m), reference triads ``L0`` (E, 3, 3; columns E₁, axis 2, axis 3) and the
    rigidities ``C`` (6,) = (EA, GA₂, GA₃, GJ, EI₂, EI₃)."""

    n0: np.ndarray
    n1: np.ndarray
    dofs: np.ndarray
    ell: np.ndarray
    L0: np.ndarray
    C: np.ndarray

    @classmethod
    def of(cls, X: np.ndarray, triads: np.ndarray, rigidities) -> Beam3DElements:
        n0 = np.arange(len(X) - 1)
        n1 = n0 + 1
        pairs = np.stack([n0, n1], axis=1)
        return cls(
            n0=n0,
            n1=n1,
            dofs=(6 * pairs[:, :, None] + np.arange(6)).reshape(len(n0), 12),
            ell=np.linalg.norm(X[n1] - X[n0], axis=1),
            L0=triads,
            C=np.asarray(rigidities, dtype=float),
        )


def reference_triads(X: np.ndarray, orientation) -> np.ndarray:
    """(E, 3, 3) triads of the chords of the polyline X (n, 3): E₁ along the chord, axis 2 the
    part of ``orientation`` (a 3-vector, or None: e_z × E₁, else e_x for a chord along z)
    normal to E₁, axis 3 = E₁ × axis 2. Raises ValueError where the two are parallel."""
    e1 = np.diff(X, axis=0)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    if orientation is None:
        v = np.cross([0.0, 0.0, 1.0], e1)
        along_z = np.linalg.norm(v, axis=1) < 1e-8
        v[along_z] = [1.0, 0.0, 0.0]
    else:
        v = np.broadcast_to(np.asarray(orientation, dtype=float), e1.shape)
    e2 = v - np.sum(v * e1, axis=1, keepdims=True) * e1
    norm = np.linalg.norm(e2, axis=1)
    if np.any(norm < 1e-8 * np.linalg.norm(v, axis=1)):
        raise ValueError("orientation is parallel to an element")
    e2 /= norm[:, None]
    return np.stack([e1, e2, np.cross(e1, e2)], axis=2)


# -- SO(3) functions analytic in their argument (real or complex) ---------------------------
def _series_or(t2, series, closed):
    """series(t2) where Re θ² < _SMALL2, closed(θ) elsewhere, θ = √θ²."""
    small = np.real(t2) < _SMALL2
    safe = np.sqrt(np.where(small, 1.0, t2))
    return np.where(small, series(t2), closed(safe))


def _coefficients(v):
    """sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³ and 1/θ² − (1 + cos θ)/(2θ sin θ) of v."""
    t2 = np.sum(v * v, axis=-1)
    a = _series_or(t2, lambda x: 1 - x / 6 * (1 - x / 20 * (1 - x / 42)), lambda t: np.sin(t) / t)
    b = _series_or(
        t2, lambda x: 0.5 - x / 24 * (1 - x / 30 * (1 - x / 56)), lambda t: (1 - np.cos(t)) / t**2
    )
    c = _series_or(
        t2,
        lambda x: 1 / 6 - x / 120 * (1 - x / 42 * (1 - x / 72)),
        lambda t: (t - np.sin(t)) / t**3,
    )
    d = _series_or(
        t2,
        lambda x: 1 / 12 + x / 720 + x * x / 30240 + x**3 / 1209600,
        lambda t: 1 / t**2 - (1 + np.cos(t)) / (2 * t * np.sin(t)),
    )
    return a, b, c, d


def _exp(v):
    a, b, _, _ = _coefficients(v)
    P = hat_any(v)
    return np.eye(3) + a[..., None, None] * P + b[..., None, None] * (P @ P)


def _tangent(v):
    _, b, c, _ = _coefficients(v)
    P = hat_any(v)
    return np.eye(3) - b[..., None, None] * P + c[..., None, None] * (P @ P)


def _tangent_inverse(v):
    d = _coefficients(v)[3]
    P = hat_any(v)
    return np.eye(3) + 0.5 * P + d[..., None, None] * (P @ P)


def _log(R):
    """Rotation vector of R (θ < π), through θ = 2 atan(s/(1 + c)), s = sin θ, c = cos θ."""
    a = 0.5 * np.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]],
        axis=-1,
    )
    c1 = 0.5 * (np.trace(R, axis1=-2, axis2=-1) + 1.0)  # 1 + cos θ
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
    return np.einsum("...ij,...j->...i", A, x)


def _mtv(A, x):
    return np.einsum("...ji,...j->...i", A, x)


# -- strains and forces ---------------------------------------------------------------------
def _kinematics(el, R0, R1, x0, x1):
    """ρ, exp(½ρ̃), R_m, γ̂, Γ and K of the elements (any leading axes)."""
    ell = el.ell.reshape(el.ell.shape + (1,) * (x0.ndim - 2))[..., None]
    L0 = el.L0.reshape(el.L0.shape[:1] + (1,) * (x0.ndim - 2) + (3, 3))
    rho = _log(np.swapaxes(R0, -1, -2) @ R1)
    Rh = _exp(0.5 * rho)
    Rm = R0 @ Rh
    gh = _mtv(Rm, (x1 - x0) / ell)
    Gam = _mtv(L0, gh) - _E1
    Kap = _mtv(L0, rho) / ell
    return rho, Rh, Rm, gh, Gam, Kap, L0, ell


def _force(el, R0, R1, x0, x1):
    """Element forces (…, 12) on (x₀, θ₀, x₁, θ₁) and the strain energies (…) (docstring)."""
    rho, Rh, Rm, gh, Gam, Kap, L0, ell = _kinematics(el, R0, R1, x0, x1)
    N, M = el.C[:3] * Gam, el.C[3:] * Kap
    n, m = _mv(L0, N), _mv(L0, M)
    p = ell * np.cross(n, gh)
    t = _mtv(_tangent_inverse(rho), m + 0.5 * _mtv(_tangent(0.5 * rho), p))
    fx = _mv(Rm, n)
    f = np.concatenate([-fx, _mv(Rh, p) - _mv(_exp(rho), t), fx, t], axis=-1)
    W = 0.5 * ell[..., 0] * (np.sum(N * Gam, axis=-1) + np.sum(M * Kap, axis=-1))
    return f, W


def _nodal(el, q):
    Q = q.reshape(-1, 6)
    R = rotation_exp(Q[:, 3:])
    return R[el.n0], R[el.n1], Q[el.n0, :3], Q[el.n1, :3]


def beam3d_strains(el: Beam3DElements, X: np.ndarray, q: np.ndarray):
    """Γ (E, 3) and K (E, 3, 1/m) in the section frames at the element midpoints."""
    R0, R1, u0, u1 = _nodal(el, q)
    _, _, _, _, Gam, Kap, _, _ = _kinematics(el, R0, R1, X[el.n0] + u0, X[el.n1] + u1)
    return Gam, Kap


def _complex_step_tangent(el, R0, R1, x0, x1):
    """∂f(q ⊕ Δ)/∂Δ (E, 12, 12): column k from the force at q ⊕ ihe_k."""
    E = len(el.ell)
    R = np.stack([R0, R1], axis=1).astype(complex)  # (E, 2, 3, 3)
    x = np.stack([x0, x1], axis=1).astype(complex)  # (E, 2, 3)
    Rk = np.broadcast_to(R[:, None], (E, 12, 2, 3, 3)).copy()
    xk = np.broadcast_to(x[:, None], (E, 12, 2, 3)).copy()
    for k in range(12):
        a, c = divmod(k, 6)
        if c < 3:
            xk[:, k, a, c] += 1j * _STEP
        else:  # R exp(ih ẽ_c) = R (I + ih ẽ_c) + O(h²), the O(h²) below round-off
            Rk[:, k, a] += 1j * _STEP * (R[:, a] @ hat(np.eye(3)[c - 3]))
    f, _ = _force(el, Rk[:, :, 0], Rk[:, :, 1], xk[:, :, 0], xk[:, :, 1])
    return np.swapaxes(f.imag / _STEP, 1, 2)


def beam3d_internal(el: Beam3DElements, X: np.ndarray, q: np.ndarray, ndof: int, tangent: bool):
    """Strain energy W (J), internal force (N, N·m; moments in the nodes' frames R) and the
    element tangents ∂f(q ⊕ Δ)/∂Δ (E, 12, 12) with respect to the right increments."""
    R0, R1, u0, u1 = _nodal(el, q)
    x0, x1 = X[el.n0] + u0, X[el.n1] + u1
    f_e, W_e = _force(el, R0, R1, x0, x1)
    f = np.bincount(el.dofs.ravel(), f_e.ravel(), minlength=ndof)
    K_e = _complex_step_tangent(el, R0, R1, x0, x1) if tangent else None
    return float(W_e.sum()), f, K_e
