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

Its tangent ∂f(q ⊕ Δ)/∂Δ is the chain rule through these intermediates in real arithmetic
(:func:`_tangent`), with the derivatives of T(½ρ)ᵀ and T(ρ)⁻ᵀ as matrix functions of ρ; it
equals the complex-step derivative of the same force (:mod:`.beam3d_complex_step`) to
round-off. With a handful of elements a kernel's time is that of its numpy calls, not of its
arithmetic, so the code keeps their number small: vectors as columns; ρ from the nodes'
quaternions (:mod:`.beam3d_quaternions`); the strains and stresses in the frame R,
(n̂, m̂) = (Λ₀C_ΓΛ₀ᵀ, Λ₀C_KΛ₀ᵀ/ℓ)(γ̂ − Λ₀E₁, ρ) as one product with a block-diagonal matrix;
the three rotation matrices of an element from one product, the rotation coefficients and
their slopes from one product with a table of Taylor coefficients; the force as one product
f = B (n̂, p, t, t) with a (12, 12) matrix B whose blocks are R_m, exp(½ρ̃), exp(ρ̃) and I,
which also ends the tangent; and the places of the rotation matrices in B and in the
derivatives as one gather.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.special

from .beam3d_gathers import coefficient_sources, element_gather
from .beam3d_quaternions import (
    node_quaternions,
    quaternion_matrices,
    relative_rotations,
    rotation_matrices,
)

__all__ = [
    "Beam3DElements",
    "beam3d_energy",
    "beam3d_internal",
    "beam3d_strains",
    "reference_triads",
    "rotation_matrices",
]

_E1_COLUMN = np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])  # (E₁, 0): Γ = L0ᵀR_mᵀx′ − E₁
_I3 = np.eye(3)
_HALF0, _ONE0 = np.array(0.5), np.array(1.0)  # (0-d arrays: cheaper operands than floats)


@dataclass(frozen=True)
class Beam3DElements:
    """Per-element data, computed once: end nodes ``n0``, ``n1``, ``dofs`` (E, 12), length
    ``ell`` (m), reference triads ``L0`` (E, 3, 3; columns E₁, axis 2, axis 3), the
    rigidities ``C`` (6,) = (EA, GA₂, GA₃, GJ, EI₂, EI₃) and, in the frame R, the section
    stiffnesses ``CG`` = Λ₀C_ΓΛ₀ᵀ (N) and ``CK`` = Λ₀C_KΛ₀ᵀ/ℓ (N·m), (E, 3, 3) each."""

    n0: np.ndarray
    n1: np.ndarray
    dofs: np.ndarray
    ell: np.ndarray
    L0: np.ndarray
    C: np.ndarray
    CG: np.ndarray
    CK: np.ndarray
    # The per-element constants repeated to the shapes they meet, (E, 3, k) or gathered by
    # index: numpy combines small arrays of one shape ~10× faster than it broadcasts them.
    ell31: np.ndarray
    ell312: np.ndarray
    inv_ell312: np.ndarray  # 1/ℓ (E, 3, 12)
    scale: np.ndarray  # (1, 1/ℓ) as columns (E, 3, 2): the strains of (L0ᵀγ̂, L0ᵀρ)
    E1: np.ndarray  # (E₁, 0) (E, 3, 2)
    ones: np.ndarray  # (E, 1)
    one_zero: np.ndarray  # (1, 0) (E, 2)
    t0: np.ndarray  # Λ₀E₁ (E, 3, 1)
    CGK: np.ndarray  # the block diagonal (CG, CK) (E, 6, 6)
    ell6: np.ndarray  # (ℓ, ℓ, ℓ, 1, 1, 1) (E, 6, 1)
    basis0: np.ndarray  # I flattened (E, 1, 9)
    chord: np.ndarray  # X₁ − X₀ (E, 3)
    slope: np.ndarray  # (E, n): @ the nodal (n, k) values it is their (v₁ − v₀)/ℓ
    chord_slope: np.ndarray  # (X₁ − X₀)/ℓ (E, 3, 1)
    C32ell: np.ndarray  # ℓ (C_Γ, C_K) (E, 3, 2)
    # the places of the rotation matrices in the tangent's derivatives (4, E, 3, 12) and in
    # f's matrix B (E, 12, 12), as one gather from the elements' flattened inputs (E, 47)
    # with its signs: each result contiguous in the layout it is used in
    gather: np.ndarray
    gather_signs: np.ndarray
    ell33: np.ndarray  # ℓ (E, 3, 3)
    zero33: np.ndarray  # 0 (E, 3, 3)
    CG_ell0: np.ndarray  # (CG/ℓ flattened, 0) (E, 10): the tangent's constant block and its 0
    coefficients: np.ndarray  # the tangent's (12, 12) coefficient matrix as a gather (E, 144)

    @classmethod
    def of(cls, X: np.ndarray, triads: np.ndarray, rigidities) -> Beam3DElements:
        n0 = np.arange(len(X) - 1)
        n1 = n0 + 1
        pairs = np.stack([n0, n1], axis=1)
        C = np.asarray(rigidities, dtype=float)
        ell = np.linalg.norm(X[n1] - X[n0], axis=1)
        E = len(n0)

        def full(a, k):
            return np.repeat(a, 3 * k).reshape(E, 3, k)

        CG = (triads * C[:3]) @ triads.mT
        gather, gather_signs = element_gather(E)

        return cls(
            n0=n0,
            n1=n1,
            dofs=(6 * pairs[:, :, None] + np.arange(6)).reshape(len(n0), 12),
            ell=ell,
            L0=triads,
            C=C,
            CG=CG,
            CK=(triads * C[3:]) @ triads.mT / ell[:, None, None],
            ell31=full(ell, 1),
            ell312=full(ell, 12),
            inv_ell312=1 / full(ell, 12),
            scale=np.concatenate([np.ones((E, 3, 1)), 1 / full(ell, 1)], axis=2),
            E1=np.repeat(_E1_COLUMN[None], E, axis=0),
            ones=np.ones((E, 1)),
            one_zero=np.repeat([[1.0, 0.0]], E, axis=0),
            t0=triads[:, :, :1].copy(),
            CGK=_block_diagonal(
                (triads * C[:3]) @ triads.mT, (triads * C[3:]) @ triads.mT / ell[:, None, None]
            ),
            ell6=np.concatenate([full(ell, 1), np.ones((E, 3, 1))], axis=1),
            basis0=np.repeat(_I3.reshape(1, 1, 9), E, axis=0),
            chord=X[n1] - X[n0],
            slope=(np.eye(len(X))[n1] - np.eye(len(X))[n0]) / ell[:, None],
            chord_slope=((X[n1] - X[n0]) / ell[:, None])[:, :, None],
            C32ell=ell[:, None, None] * _rigidity_columns(C),
            gather=gather,
            gather_signs=gather_signs,
            ell33=full(ell, 3),
            zero33=np.zeros((E, 3, 3)),
            CG_ell0=np.concatenate([(CG / ell[:, None, None]).reshape(E, 9), np.zeros((E, 1))], 1),
            coefficients=91 * np.arange(E)[:, None] + coefficient_sources(),
        )


def _block_diagonal(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(E, 6, 6) with the (E, 3, 3) ``a`` and ``b`` on the diagonal."""
    out = np.zeros((len(a), 6, 6))
    out[:, :3, :3], out[:, 3:, 3:] = a, b
    return out


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


# -- SO(3) in few array operations -----------------------------------------------------------
def _skew_basis() -> np.ndarray:
    """(3, 9): w @ it is w̃ (w̃ a = w × a) flattened row by row."""
    B = np.zeros((3, 3, 3))
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        B[k, i, j], B[k, j, i] = -1.0, 1.0  # w̃_ij = −ε_ijk w_k
    return B.reshape(3, 9)


def _series_table() -> np.ndarray:
    """(2, N, 5): Taylor coefficients in x of d(x), d′(x), 0, 0, 0 (row 0) and of a, b, c, b′, c′
    (row 1), with a = sin θ/θ, b = (1 − cos θ)/θ², c = (θ − sin θ)/θ³,
    d = 1/θ² − (1 + cos θ)/(2θ sin θ) = −Σₙ (−1)ⁿ B₂ₙ x^(n−1)/(2n)!, x = θ²."""
    k = np.arange(_N_TERMS + 1)
    fact = np.array([math.factorial(int(n)) for n in range(2 * _N_TERMS + 6)], dtype=float)
    sign = (-1.0) ** k
    a, b, c = sign / fact[2 * k + 1], sign / fact[2 * k + 2], sign / fact[2 * k + 3]
    B = scipy.special.bernoulli(2 * _N_TERMS + 2)
    d = -((-1.0) ** (k + 1)) * B[2 * k + 2] / fact[2 * k + 2]

    def slope(s):
        return k[1:] * s[1:]

    T = np.zeros((2, _N_TERMS, 5))
    T[0, :, 0], T[0, :, 1] = d[:-1], slope(d)
    for col, s in enumerate((a[:-1], b[:-1], c[:-1], slope(b), slope(c))):
        T[1, :, col] = s
    return T


_N_TERMS = 12  # at θ² < _SERIES_MAX the first neglected term is below 1e-20 of each function
_SERIES_MAX = 1.0
_SKEW, _SERIES = _skew_basis(), _series_table()
_POWERS = np.arange(_N_TERMS)


def _hat(w: np.ndarray) -> np.ndarray:
    return (w @ _SKEW).reshape(w.shape[:-1] + (3, 3))


def _coefficients(t2: np.ndarray) -> np.ndarray:
    """(E, 39): the weights (1, w₁, w₂) of (I, ρ̃, ρ̃²) in exp(½ρ̃), T(ρ)⁻¹ and ½T(½ρ), then
    the slopes' coefficients of T(½ρ)ᵀ and of T(ρ)⁻ᵀ (:func:`_maps`), from d, d′ of x = θ² and a, b,
    c, b′, c′ of x = θ²/4: by their series where θ² < _SERIES_MAX (one product of the powers of
    x with a table), else by the closed forms d′ = ((1 + a)/(4b) − 1)/x², b′ = (a/2 − b)/x,
    c′ = (b − 3c)/(2x) (of θ², resp. θ²/4)."""
    X = t2[:, None] ** _POWERS
    if max(t2.tolist()) < _SERIES_MAX:  # (a reduction of a few floats costs more in numpy)
        return X @ _SERIES_MAPS
    small = t2 < _SERIES_MAX
    x1 = np.where(small, 1.0, t2)
    t = np.sqrt(x1)
    x2, h = 0.25 * x1, 0.5 * t
    s1, c1, s2, c2 = np.sin(t), np.cos(t), np.sin(h), np.cos(h)
    a1, b1 = s1 / t, (1 - c1) / x1
    a2, b2, cc2 = s2 / h, (1 - c2) / x2, (h - s2) / (x2 * h)
    d = 1 / x1 - (1 + c1) / (2 * t * s1)
    closed = np.stack(
        [d, ((1 + a1) / (4 * b1) - 1) / x1**2, d, d, d]
        + [a2, b2, cc2, (0.5 * a2 - b2) / x2, (b2 - 3 * cc2) / (2 * x2), np.ones_like(t2)],
        axis=-1,
    )
    return np.where(small[:, None], X @ _SERIES_MAPS, closed @ _MAPS)


# -- strains, force and tangent ---------------------------------------------------------------
def _nodal(el, X, q):
    """The nodes' quaternions N and rotations R (the elements' first and second nodes are
    the polyline's nodes e and e + 1, ``Beam3DElements.of``: views rather than gathers) and
    x′ = (x₁ − x₀)/ℓ (E, 3, 1)."""
    Q = q.reshape(-1, 6)
    N = node_quaternions(Q[:, 3:])
    return N, quaternion_matrices(N), (el.slope @ Q)[:, :3, None] + el.chord_slope


def _maps():
    """Fixed linear map from the coefficients (E, 11) = (d, d′, 0, 0, 0, a, b, c, b′, c′, 1)
    to the weights (1, w₁, w₂) of (I, ρ̃, ρ̃²) in exp(½ρ̃), T(ρ)⁻¹ and ½T(½ρ) (columns 0–8),
    and to (α, β, α′, β′) of T(½ρ)ᵀ (times ½, as the tangent takes its slope) and of T(ρ)⁻ᵀ
    as functions of ρ, as :func:`_matrix_slopes` takes them (columns 9–38); the last row
    carries the constants. (The factors ½ are exact: powers of two.)"""
    M = np.zeros((11, 39))
    M[10, [0, 3, 6]] = 1.0  # the weights of I
    M[5, 1], M[6, 2] = 0.5, 0.25  # exp(½ρ̃) = I + ½a ρ̃ + ¼b ρ̃²  (a, b of θ²/4)
    M[10, 4], M[0, 5] = 0.5, 1.0  # T(ρ)⁻¹ = I + ½ρ̃ + d ρ̃²
    M[6, 7], M[7, 8] = -0.5, 0.25  # T(½ρ) = I − ½b ρ̃ + ¼c ρ̃², halved below
    M[:, 6:9] *= 0.5
    # T(½ρ)ᵀ = I + (b/2) ρ̃ + (c/4) ρ̃², slopes in |ρ|² = 4x: b′/8, c′/16
    S = np.zeros((11, 2, 4))  # (α, β, α′, β′) of each matrix
    S[6, 0, 0], S[7, 0, 1], S[8, 0, 2], S[9, 0, 3] = 0.5, 0.25, 0.125, 1 / 16
    S[10, 1, 0], S[0, 1, 1], S[1, 1, 3] = -0.5, 1.0, 1.0  # T(ρ)⁻ᵀ = I − ½ρ̃ + d ρ̃²
    S[:, 0] *= 0.5
    # as :func:`_matrix_slopes` takes them: −α, β, 2α′, 2β′, −2β (5, 3, 2), down the rows
    S = S[:, :, [0, 1, 2, 3, 1]] * np.array([-1.0, 1.0, 2.0, 2.0, -2.0])
    M[:, 9:] = np.repeat(S.transpose(0, 2, 1)[:, :, None, :], 3, axis=2).reshape(11, 30)
    return M


def _series_maps() -> np.ndarray:
    """(N, 39): the powers x⁰ … x^(N−1) of x = θ² @ it is :func:`_coefficients`' result by
    the series (the series table composed with the map, the constants on the power x⁰; the
    series in θ²/4 with their coefficients divided by 4ᵏ)."""
    S = np.zeros((_N_TERMS, 11))
    S[:, :5], S[:, 5:10] = _SERIES[0], _SERIES[1] * 0.25 ** _POWERS[:, None]
    S[0, 10] = 1.0
    return S @ _MAPS


_MAPS = _maps()
_SERIES_MAPS = _series_maps()


class _Strains:
    """ρ = log(R₀ᵀR₁) from the nodes' quaternions (as :func:`_strain_columns`), the rotation
    functions of the element, R_m, γ̂ = R_mᵀx′ and, in the frame R, the strains
    g = (γ̂ − t₀, ρ) (E, 6, 1), t₀ = Λ₀E₁ the reference tangent: Γ = Λ₀ᵀ(γ̂ − t₀) and
    K = Λ₀ᵀρ/ℓ. Vectors are kept as columns (E, 3, 1)."""

    def __init__(self, el, N, R, xp):
        R0 = R[:-1]
        self.A = R0.mT @ R[1:]  # exp(ρ̃)
        rho, theta, _ = relative_rotations(N)
        self.t2 = theta * theta
        self.co = co = _coefficients(self.t2)  # (E, 39)
        self.P = P = _hat(rho)
        # (1, w_k1, w_k2) @ (I, ρ̃, ρ̃²) flattened: the three matrices I + w_k1 ρ̃ + w_k2 ρ̃²
        basis = np.concatenate([el.basis0, P.reshape(-1, 1, 9), (P @ P).reshape(-1, 1, 9)], 1)
        M = co[:, :9].reshape(-1, 3, 3) @ basis
        self.H, self.Ti, self.hTh = M.reshape(-1, 3, 3, 3).transpose(1, 0, 2, 3)
        self.Rm = R0 @ self.H  # exp(½ρ̃), T(ρ)⁻¹, ½T(½ρ) above
        self.M = M
        self.rho = rho[..., None]
        self.gh = self.Rm.mT @ xp
        self.g = np.concatenate([self.gh - el.t0, self.rho], axis=1)


class _Forces(_Strains):
    """The element force f (E, 12) and energy W (J, all elements), and the quantities the
    tangent reuses: the stress resultants (n̂, m̂) = (Λ₀C_ΓΓ, Λ₀C_K K) = (CG, CK) g and
    W = ½ Σ (ℓ(γ̂ − t₀)·n̂ + ρ·m̂)."""

    def __init__(self, el, N, R, xp):
        super().__init__(el, N, R, xp)
        nm = el.CGK @ self.g
        self.n, m = nm[:, :3], nm[:, 3:]
        # n̂~ and γ̂~ from one product: (E, 2, 3, 3)
        E = len(nm)
        self.NG = _hat(np.concatenate([self.n, self.gh], axis=1).reshape(E, 2, 3)).reshape(E, 6, 3)
        self.Nh, self.Gh = self.NG[:, :3], self.NG[:, 3:]
        self.p = p = el.ell31 * (self.Nh @ self.gh)
        self.u = m + self.hTh.mT @ p
        self.t = t = self.Ti.mT @ self.u
        # the rotation matrices' places in f's matrix B and in the tangent's derivatives
        flat = np.concatenate(
            [self.A.reshape(-1, 9), self.M.reshape(-1, 27), self.Rm.reshape(-1, 9), el.one_zero],
            1,
        )
        placed = flat.take(el.gather) * el.gather_signs
        self.Z = placed[: 144 * E].reshape(E, 12, 12)  # (Dρ, Dφ, (0, exp(−½ρ̃), 0, 0), ..)
        self.B = placed[144 * E :].reshape(E, 12, 12)
        self.f = self.B @ np.concatenate([self.n, p, t, t], axis=1)
        self.W = 0.5 * float(np.vdot(nm, self.g * el.ell6))


def _rigidity_columns(C):
    """The rigidities as the columns (C_Γ, C_K) (3, 2)."""
    return C.reshape(2, 3).T


def _slope_table() -> np.ndarray:
    """(126, 18): the products a_m b_n (flattened m, n) of a = (w (3, 2), βρ (3, 2), −α (2))
    and b = (ρ, v (3, 2)), each (3, 2) flattened row by row with the columns k = p, u, @ it
    is w_k ρᵀ + β_k ρ v_kᵀ − α_k ṽ_k + β_k (ρ·v_k) I of k = p, u, flattened
    (:func:`_matrix_slopes`)."""
    T = np.zeros((14, 9, 2, 3, 3))
    for k in range(2):
        for i in range(3):
            for j in range(3):
                T[2 * i + k, j, k, i, j] += 1.0  # w ρᵀ
                T[6 + 2 * i + k, 3 + 2 * j + k, k, i, j] += 1.0  # β ρ vᵀ
                T[6 + 2 * j + k, 3 + 2 * j + k, k, i, i] += 1.0  # β (ρ·v) I
                for m in range(3):  # (−α) ṽ, ṽ = Σ_m v_m (the skew basis)_m
                    T[12 + k, 3 + 2 * m + k, k, i, j] += _SKEW[m, 3 * i + j]
    return T.reshape(126, 18)


_SLOPE_TABLE = _slope_table()


def _matrix_slopes(P, rho, V, c):
    """∂(M_k v_k)/∂ρ (E, 2, 3, 3) of M_k = I + α_k ρ̃ + β_k ρ̃², α_k and β_k functions of
    x = |ρ|² with slopes α′_k, β′_k, for the columns v_k of V (E, 3, 2); P = ρ̃, ρ (E, 3, 1),
    and c (5, E, 3, 2): −α, β, 2α′, 2β′, −2β, each repeated down the rows (so that the
    arrays combine without broadcasting):

        −α ṽ + β (ρ vᵀ + (ρ·v) I − 2 v ρᵀ) + 2 (α′ ρ×v + β′ ρ×(ρ×v)) ρᵀ

    = w ρᵀ + β ρ vᵀ − α ṽ + (β ρ·v) I with w = 2 (α′ ρ×v + β′ ρ×(ρ×v) − β v): the products
    of (w, βρ, −α) with (ρ, v), all of them from one outer product, summed by a fixed table."""
    m_alpha, beta, alpha1, beta1, m_beta = c
    PV = P @ V  # ρ × v
    w = alpha1 * PV + beta1 * (P @ PV) + m_beta * V
    E = len(V)
    a = np.concatenate([w.reshape(E, 6), (beta * rho).reshape(E, 6), m_alpha[:, 0]], axis=1)
    b = np.concatenate([rho.reshape(E, 3), V.reshape(E, 6)], axis=1)
    return ((a[:, :, None] * b[:, None, :]).reshape(E, 126) @ _SLOPE_TABLE).reshape(E, 2, 3, 3)


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

    The derivatives of T's matrices are :func:`_matrix_slopes` with the coefficients' slopes;
    T(ρ)⁻¹ exp(−ρ̃) = T(ρ)⁻ᵀ (as exp(ρ̃) T(ρ) = T(ρ)ᵀ) gives Dρ without a product.

    Every derivative is linear in Z = (Dρ, Dφ, Z₃, Z₄), Z₃ = (0, exp(−½ρ̃), 0, 0) and
    Z₄ = (−R_mᵀ, 0, R_mᵀ, 0), with (3, 3) coefficients: with Q = n̂~ − γ̂~ Λ₀C_ΓΛ₀ᵀ,
    Dp = ℓ Q Dγ̂. So the chain is carried on the coefficients, (E, 3, 3) products, and
    (dn, dp, dt, Dt) = (Dn̂ − n̂~Dψ_m, Dp − ½p̃T(½ρ)Dρ, Dt − t̃Dφ, Dt) is one product C Z
    (C placed by ``Beam3DElements.coefficients``, :mod:`.beam3d_gathers`)."""
    E = len(s.Z)
    c = np.ascontiguousarray(s.co[:, 9:].reshape(-1, 5, 3, 2).transpose(1, 0, 2, 3))
    G = _matrix_slopes(s.P, s.rho, np.concatenate([s.p, s.u], axis=2), c)
    Nh, Gh, hTh, Ti_T = s.Nh, s.Gh, s.hTh, s.Ti.mT
    # the coefficients of Dψ_m in dn, Dp and Dt (Dg = γ̂~ Dψ_m + Z₄/ℓ, Dp = ℓ Q Dg)
    Q = Nh - Gh @ el.CG
    ap = el.ell33 * (Q @ Gh)
    V = Ti_T @ hTh.mT  # T(ρ)⁻ᵀ ½T(½ρ)ᵀ
    A = np.concatenate([el.CG @ Gh - Nh, ap, V @ ap], axis=1)
    mpt = _hat(-np.concatenate([s.p, s.t], axis=1).reshape(E, 2, 3))  # −p̃, −t̃
    TK = Ti_T @ (el.CK + G[:, 0]) + G[:, 1]  # Dt's own coefficient of Dρ
    # of Dρ: through Dψ_m = ½T(½ρ) Dρ + Z₃, and directly (−p̃ ½T(½ρ) in dp, TK in Dt)
    C1 = A @ hTh + np.concatenate([el.zero33, mpt[:, 0] @ hTh, TK], axis=1)
    flat = np.concatenate(
        [C1.reshape(E, 27), A.reshape(E, 27), Q.reshape(E, 9), (V @ Q).reshape(E, 9),
         mpt[:, 1].reshape(E, 9), el.CG_ell0], axis=1,
    )  # fmt: skip
    return s.B @ (flat.take(el.coefficients).reshape(E, 12, 12) @ s.Z)


def beam3d_internal(el: Beam3DElements, X: np.ndarray, q: np.ndarray, ndof: int, tangent: bool):
    """Strain energy W (J), internal force (N, N·m; moments in the nodes' frames R) and the
    element tangents ∂f(q ⊕ Δ)/∂Δ (E, 12, 12) with respect to the right increments."""
    s = _Forces(el, *_nodal(el, X, q))
    f = np.bincount(el.dofs.ravel(), s.f.ravel(), minlength=ndof)
    return s.W, f, _tangent(el, s) if tangent else None


def _strain_columns(el: Beam3DElements, X: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The strains (Γ, K) as the columns of (E, 3, 2), as ``_Strains`` without the
    tangent's matrices, by the nodes' unit quaternions q₀, q₁: their relative rotation
    r = q̄₀ ⊗ q₁ = (w, v) gives ρ, and the midpoint rotation R_m = R₀ exp(½ρ̃) is that of
    q₀ + sign(w) q₁ (the half-way point of the shorter arc), whose squared norm is
    2(1 + |w|)."""
    Q = q.reshape(-1, 6)
    N = node_quaternions(Q[:, 3:])
    rho, _, w = relative_rotations(N)
    m = N[:-1] + np.copysign(_ONE0, w)[:, None] * N[1:]
    d = (Q[1:, :3] - Q[:-1, :3] + el.chord) * (_HALF0 / (el.ell * (_ONE0 + np.abs(w))))[:, None]
    V = np.concatenate([quaternion_matrices(m).mT @ d[..., None], rho[..., None]], axis=2)
    return el.L0.mT @ V * el.scale - el.E1


def beam3d_strains(el: Beam3DElements, X: np.ndarray, q: np.ndarray):
    """Γ (E, 3) and K (E, 3, 1/m) in the section frames at the element midpoints."""
    S = _strain_columns(el, X, q)
    return S[:, :, 0], S[:, :, 1]


def beam3d_energy(el: Beam3DElements, X: np.ndarray, q: np.ndarray) -> float:
    """Strain energy W (J)."""
    S = _strain_columns(el, X, q)
    return 0.5 * float(np.vdot(S * S, el.C32ell))
