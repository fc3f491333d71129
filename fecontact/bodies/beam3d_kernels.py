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

__all__ = [
    "Beam3DElements",
    "beam3d_energy",
    "beam3d_internal",
    "beam3d_strains",
    "reference_triads",
]

_E1 = np.array([1.0, 0.0, 0.0])
# θ² below which the closed forms lose digits: their series (error below θ⁸ ~ 1e-24)
_SMALL2 = 1e-6
_STEP = 1e-30  # complex step: far below round-off of any first-order term
# x below which the slopes of the coefficients are taken from their series (module text)
_SLOPE_SERIES = 0.25
_I3 = np.eye(3)
_DIAG = np.arange(3)


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


def beam3d_strains(el: Beam3DElements, X: np.ndarray, q: np.ndarray):
    """Γ (E, 3) and K (E, 3, 1/m) in the section frames at the element midpoints."""
    R0, R1, x0, x1 = _nodal(el, X, q)
    rho, xp, L0, ell = _kinematics(el, R0, R1, x0, x1)
    Rm = R0 @ _rotation_functions(rho)[2]
    return _mtv(L0, _mtv(Rm, xp)) - _E1, _mtv(L0, rho) / ell


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


# -- the force and its analytic tangent in real arithmetic -----------------------------------
def _slopes(x1, x2, co):
    """d′(θ²) of T⁻¹'s coefficient and b′, c′ of T's at θ²/4 (derivatives with respect to
    their argument x: d′ = ((1 + a)/(4b) − 1)/x², b′ = (a/2 − b)/x, c′ = (b − 3c)/(2x)), by
    their series where x < _SLOPE_SERIES (error below 1e-11 relative), whose closed forms
    cancel there."""
    (a1, b1, _, _), (a2, b2, c2, _) = co[:, 0], co[:, 1]
    if np.all(x1 < _SLOPE_SERIES):
        return _slope_series(x1, x2)
    with np.errstate(divide="ignore", invalid="ignore"):
        closed = ((1 + a1) / (4 * b1) - 1) / x1**2, (0.5 * a2 - b2) / x2, (b2 - 3 * c2) / (2 * x2)
    series = _slope_series(x1, x2)
    return tuple(np.where(x1 < _SLOPE_SERIES, s, c) for s, c in zip(series, closed, strict=True))


def _slope_series(x1, x2):
    d = 1 / 720 + x1 * (
        1 / 15120 + x1 * (1 / 403200 + x1 * (1 / 11975040 + x1 * 691 / 261534873600))
    )
    b = -1 / 24 + x2 * (1 / 360 - x2 * (1 / 13440 - x2 * (1 / 907200 - x2 / 95800320)))
    c = -1 / 120 + x2 * (1 / 2520 - x2 * (1 / 120960 - x2 * (1 / 9979200 - x2 / 1245404160)))
    return d, b, c


def _matrix_slope(P, phi, v, alpha, beta, alpha1, beta1):
    """∂(M v)/∂φ (E, 3, 3) of M = I + α φ̃ + β φ̃², α and β functions of x = |φ|² with slopes
    α′, β′; P = φ̃:  −α ṽ + β (φ vᵀ + (φ·v) I − 2 v φᵀ) + 2 (α′ φ×v + β′ φ×(φ×v)) φᵀ."""
    w1 = _mv(P, v)
    w2 = _mv(P, w1)
    G = beta[:, None, None] * (
        phi[:, :, None] * v[:, None, :] - 2 * v[:, :, None] * phi[:, None, :]
    )
    G -= np.reshape(alpha, (-1, 1, 1)) * hat(v)  # α, α′: per element, or one number
    G += (2 * (np.reshape(alpha1, (-1, 1)) * w1 + beta1[:, None] * w2))[:, :, None] * phi[
        :, None, :
    ]
    G[:, _DIAG, _DIAG] += (beta * np.sum(phi * v, axis=1))[:, None]
    return G


class _Forces:
    """The element force f (E, 12) and energy W (E) at the nodes' R₀, R₁, x₀, x₁, and the
    intermediate quantities of the module docstring that the tangent reuses."""

    def __init__(self, el, R0, R1, x0, x1):
        ell = el.ell[:, None]
        self.A = np.swapaxes(R0, 1, 2) @ R1  # exp(ρ̃)
        self.rho = rho = _log(self.A)
        self.t2 = t2 = np.sum(rho * rho, axis=1)
        self.co = co = _coefficients(np.stack([t2, 0.25 * t2]))
        (_, _, _, d1), (a2, b2, c2, _) = co[:, 0], co[:, 1]
        self.P = P = hat(rho)
        P2 = P @ P
        self.H = _I3 + (0.5 * a2)[:, None, None] * P + (0.25 * b2)[:, None, None] * P2
        self.Ti = _I3 + 0.5 * P + d1[:, None, None] * P2  # T(ρ)⁻¹
        self.Th = _I3 - (0.5 * b2)[:, None, None] * P + (0.25 * c2)[:, None, None] * P2
        self.Rm = R0 @ self.H
        self.gh = gh = _mtv(self.Rm, (x1 - x0) / ell)
        L0 = el.L0
        Gam, Kap = _mtv(L0, gh) - _E1, _mtv(L0, rho) / ell
        N, M = el.C[:3] * Gam, el.C[3:] * Kap
        self.n, m = _mv(L0, N), _mv(L0, M)
        self.Nh, self.Gh = hat(self.n), hat(gh)
        self.p = p = ell * _mv(self.Nh, gh)
        self.u = m + 0.5 * _mtv(self.Th, p)
        self.t = t = _mtv(self.Ti, self.u)
        fx = _mv(self.Rm, self.n)
        self.f = np.concatenate([-fx, _mv(self.H, p) - _mv(self.A, t), fx, t], axis=1)
        self.W = 0.5 * el.ell * (np.sum(N * Gam, axis=1) + np.sum(M * Kap, axis=1))


def _tangent(el, s: _Forces) -> np.ndarray:
    r"""∂f(q ⊕ Δ)/∂Δ (E, 12, 12), Δ = (δx₀, δθ₀, δx₁, δθ₁), by the chain rule through the
    force's intermediates, each a (E, 3, 12) derivative D·:

        Dφ = (0, −exp(−ρ̃), 0, I),  Dρ = T(ρ)⁻¹ Dφ,  Dψ_m = (0, exp(−½ρ̃), 0, 0) + ½ T(½ρ) Dρ,
        Dγ̂ = γ̂~ Dψ_m + R_mᵀ (−I, 0, I, 0)/ℓ,  Dn̂ = Λ₀C_ΓΛ₀ᵀ Dγ̂,  Dm̂ = Λ₀C_KΛ₀ᵀ Dρ/ℓ,
        Dp = ℓ (n̂~ Dγ̂ − γ̂~ Dn̂),  Du = Dm̂ + ½ (T(½ρ)ᵀ Dp + ½ ∂(T(φ)ᵀp)/∂φ Dρ),
        Dt = T(ρ)⁻ᵀ Du + ∂(T(ρ)⁻ᵀu)/∂ρ Dρ,

    (δφ the right variation of exp(ρ̃) = R₀ᵀR₁, ψ_m that of R_m, u = m̂ + ½T(½ρ)ᵀp), and, with
    ∂(exp(φ̃)v)/∂φ = −exp(φ̃) ṽ T(φ),

        Df_x₁ = R_m (Dn̂ − n̂~ Dψ_m) = −Df_x₀,  Df_θ₁ = Dt,
        Df_θ₀ = exp(½ρ̃) (Dp − ½ p̃ T(½ρ) Dρ) − exp(ρ̃) (Dt − t̃ Dφ).

    The derivatives of T's matrices are :func:`_matrix_slope` with the coefficients' slopes."""
    E, ell = len(el.ell), el.ell[:, None, None]
    At, Ht = np.swapaxes(s.A, 1, 2), np.swapaxes(s.H, 1, 2)
    Dphi = np.zeros((E, 3, 12))
    Dphi[:, :, 3:6] = -At
    Dphi[:, :, 9:] = _I3
    Drho = s.Ti @ Dphi
    Dpsi = 0.5 * (s.Th @ Drho)
    Dpsi[:, :, 3:6] += Ht
    Dg = s.Gh @ Dpsi
    B = np.swapaxes(s.Rm, 1, 2) / ell
    Dg[:, :, :3] -= B
    Dg[:, :, 6:9] += B
    L0 = el.L0
    L0t = np.swapaxes(L0, 1, 2)
    Dn = (L0 * el.C[:3]) @ (L0t @ Dg)
    Dm = (L0 * el.C[3:]) @ (L0t @ Drho) / ell
    Dp = ell * (s.Nh @ Dg - s.Gh @ Dn)
    (a2, b2, c2, _) = s.co[:, 1]
    d1p, b2p, c2p = _slopes(s.t2, 0.25 * s.t2, s.co)
    phi = 0.5 * s.rho
    Gp = _matrix_slope(0.5 * s.P, phi, s.p, b2, c2, b2p, c2p)
    Du = Dm + 0.5 * (np.swapaxes(s.Th, 1, 2) @ Dp + 0.5 * (Gp @ Drho))
    Gu = _matrix_slope(s.P, s.rho, s.u, -0.5, s.co[3, 0], 0.0, d1p)
    Dt = np.swapaxes(s.Ti, 1, 2) @ Du + Gu @ Drho
    Dfx = s.Rm @ (Dn - s.Nh @ Dpsi)
    Df0 = s.H @ (Dp - 0.5 * (hat(s.p) @ (s.Th @ Drho))) - s.A @ (Dt - hat(s.t) @ Dphi)
    return np.concatenate([-Dfx, Df0, Dfx, Dt], axis=1)


def complex_step_internal(el: Beam3DElements, X: np.ndarray, q: np.ndarray):
    """Element forces (E, 12), energies (E) and tangents ∂f(q ⊕ Δ)/∂Δ (E, 12, 12) by one
    complex evaluation at the 13 points q and q ⊕ ihe_k: the real parts are f and W (to
    O(h²), nothing), the imaginary parts over h the columns. Exact to round-off and slow (its
    cost is that of numpy calls on complex arrays): the reference the analytic tangent of
    :func:`beam3d_internal` is checked against."""
    R0, R1, x0, x1 = _nodal(el, X, q)
    R = np.stack([R0, R1], axis=1)[:, None] @ _DR  # (E, 13, 2, 3, 3)
    x = np.stack([x0, x1], axis=1)[:, None] + _DX
    fk, Wk = _force(el, R[:, :, 0], R[:, :, 1], x[:, :, 0], x[:, :, 1])
    return fk[:, 0].real, Wk[:, 0].real, np.swapaxes(fk[:, 1:].imag, 1, 2) / _STEP


def beam3d_internal(el: Beam3DElements, X: np.ndarray, q: np.ndarray, ndof: int, tangent: bool):
    """Strain energy W (J), internal force (N, N·m; moments in the nodes' frames R) and the
    element tangents ∂f(q ⊕ Δ)/∂Δ (E, 12, 12) with respect to the right increments, in real
    arithmetic (:func:`_tangent`)."""
    s = _Forces(el, *_nodal(el, X, q))
    f = np.bincount(el.dofs.ravel(), s.f.ravel(), minlength=ndof)
    return float(s.W.sum()), f, _tangent(el, s) if tangent else None


def beam3d_energy(el: Beam3DElements, X: np.ndarray, q: np.ndarray) -> float:
    """Strain energy W (J)."""
    Gam, Kap = beam3d_strains(el, X, q)
    return 0.5 * float(el.ell @ (Gam**2 @ el.C[:3] + Kap**2 @ el.C[3:]))
