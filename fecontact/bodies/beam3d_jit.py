r"""The Beam3D element kernel compiled with numba (optional): the internal force, its tangent
and the strain energy of :mod:`.beam3d_kernels`, the same formulas element by element over
plain arrays.

With a handful of elements the numpy kernel's time is that of its few dozen numpy calls, each
at numpy's least cost per call, not of its arithmetic; compiled, a call costs its arithmetic.
The formulas are those of :mod:`.beam3d_kernels` (its docstring and ``_tangent``): the nodes'
unit quaternions, ρ = 2 atan(|v|/w) v/|v| of r = q̄₀ ⊗ q₁ = (w, v), exp(½ρ̃), T(ρ)⁻¹ and ½T(½ρ)
from the same coefficient functions (their Taylor series in θ² where θ² < 1, else the closed
forms), the force f = B (n̂, p, t, t) and the tangent B (C Z) with the same blocks. Only the
order of the sums differs: the results agree to round-off (``tests/test_beam3d_jit.py``).

numba is imported here only, and this module only by a Beam3D that runs it
(:func:`~fecontact.bodies.beam3d.kernel_choice`): ``import fecontact`` does not pay numba's
import (0.24 s of CPU time). The functions are compiled on their first call and cached on
disk (``cache=True``): a process pays the cache's load once, a machine the compilation once
(``docs/validation/beam3d.md``, Cost).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.special

try:
    import numba
except ImportError:  # the numpy kernel runs: numba is the optional extra "jit"
    numba = None

__all__ = ["AVAILABLE", "jit_energy", "jit_internal"]

AVAILABLE = numba is not None

_N_TERMS = 12  # as the numpy kernel: at θ² < 1 the first neglected term is below 1e-20
_TINY = 1e-300  # as :mod:`.beam3d_quaternions`: changes a ratio only at 0, to its limit


def _jit(f):
    """``f`` compiled (cached on disk) where numba imports, else as it is (never called)."""
    return numba.njit(cache=True)(f) if AVAILABLE else f


def _series() -> np.ndarray:
    """(6, N): the Taylor coefficients in x of a = sin θ/θ, b = (1 − cos θ)/θ²,
    c = (θ − sin θ)/θ³ (x = θ²) and of d = 1/θ² − (1 + cos θ)/(2θ sin θ), then the
    slopes' coefficients of d and b, c (row 4 that of d′, row 5 of b′; c′ from row 2 below)."""
    k = np.arange(_N_TERMS + 1)
    fact = np.array([math.factorial(int(n)) for n in range(2 * _N_TERMS + 6)], dtype=float)
    sign = (-1.0) ** k
    B = scipy.special.bernoulli(2 * _N_TERMS + 2)
    d = -((-1.0) ** (k + 1)) * B[2 * k + 2] / fact[2 * k + 2]
    rows = [sign / fact[2 * k + 1], sign / fact[2 * k + 2], sign / fact[2 * k + 3], d]
    return np.array([r[:_N_TERMS] for r in rows])


_COEFFS = _series()


@_jit
def _poly(c, x):
    """Σₖ c_k x^k (Horner) and its slope Σₖ k c_k x^(k−1)."""
    v, s = 0.0, 0.0
    for k in range(len(c) - 1, -1, -1):
        s = s * x + v
        v = v * x + c[k]
    return v, s


@_jit
def _functions(t2, out):
    """The rotation coefficients of x = θ² into ``out`` (7,): d, d′ of θ² and a, b, c, b′, c′
    of θ²/4 (the half angle): by their series where θ² < 1, else by the closed forms
    d′ = ((1 + a)/(4b) − 1)/x², b′ = (a/2 − b)/x, c′ = (b − 3c)/(2x)."""
    if t2 < 1.0:
        x2 = 0.25 * t2
        out[0], out[1] = _poly(_COEFFS[3], t2)
        out[2], _ = _poly(_COEFFS[0], x2)
        out[3], out[5] = _poly(_COEFFS[1], x2)
        out[4], out[6] = _poly(_COEFFS[2], x2)
        return
    t = math.sqrt(t2)
    x2, h = 0.25 * t2, 0.5 * t
    s1, c1, s2, c2 = math.sin(t), math.cos(t), math.sin(h), math.cos(h)
    a1, b1 = s1 / t, (1.0 - c1) / t2
    a2, b2, cc2 = s2 / h, (1.0 - c2) / x2, (h - s2) / (x2 * h)
    out[0] = 1.0 / t2 - (1.0 + c1) / (2.0 * t * s1)
    out[1] = ((1.0 + a1) / (4.0 * b1) - 1.0) / (t2 * t2)
    out[2], out[3], out[4] = a2, b2, cc2
    out[5], out[6] = (0.5 * a2 - b2) / x2, (b2 - 3.0 * cc2) / (2.0 * x2)


@_jit
def _quaternion(psi, q):
    """The unit quaternion q (4,) of the rotation vector ψ (3,), as ``node_quaternions``."""
    h = math.sqrt(0.25 * (psi[0] * psi[0] + psi[1] * psi[1] + psi[2] * psi[2])) + _TINY
    s = 0.5 * math.sin(h) / h
    q[0] = math.cos(h)
    for i in range(3):
        q[i + 1] = s * psi[i]


@_jit
def _rotation(q, R):
    """R (3, 3) = (w² − u·u) I + 2w ũ + 2uuᵀ of the quaternion q = (w, u); s² R if |q| = s."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    d = w * w - x * x - y * y - z * z
    R[0, 0], R[1, 1], R[2, 2] = d + 2 * x * x, d + 2 * y * y, d + 2 * z * z
    R[0, 1], R[1, 0] = 2 * (x * y - w * z), 2 * (x * y + w * z)
    R[0, 2], R[2, 0] = 2 * (x * z + w * y), 2 * (x * z - w * y)
    R[1, 2], R[2, 1] = 2 * (y * z - w * x), 2 * (y * z + w * x)


@_jit
def _relative(p, d, rho):
    """ρ (3,) of p̄ ⊗ d = (w, v), 2 atan(|v|/w) v/|v| (the shorter arc); returns θ sign(w) and w."""
    w = p[0] * d[0] + p[1] * d[1] + p[2] * d[2] + p[3] * d[3]
    v0 = p[0] * d[1] - d[0] * p[1] - (p[2] * d[3] - p[3] * d[2])
    v1 = p[0] * d[2] - d[0] * p[2] - (p[3] * d[1] - p[1] * d[3])
    v2 = p[0] * d[3] - d[0] * p[3] - (p[1] * d[2] - p[2] * d[1])
    s = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    theta = 2.0 * math.atan(s / w)
    f = theta / (s + _TINY)
    rho[0], rho[1], rho[2] = f * v0, f * v1, f * v2
    return theta, w


@_jit
def _hat(w, W):
    W[0, 0], W[0, 1], W[0, 2] = 0.0, -w[2], w[1]
    W[1, 0], W[1, 1], W[1, 2] = w[2], 0.0, -w[0]
    W[2, 0], W[2, 1], W[2, 2] = -w[1], w[0], 0.0


@_jit
def _mm(A, B, C, transpose_a):
    """C = A B, or Aᵀ B with ``transpose_a`` (3, 3)."""
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += (A[k, i] if transpose_a else A[i, k]) * B[k, j]
            C[i, j] = s


@_jit
def _mv(A, v, out, transpose_a):
    """out = A v, or Aᵀ v with ``transpose_a`` (3,)."""
    for i in range(3):
        s = 0.0
        for k in range(3):
            s += (A[k, i] if transpose_a else A[i, k]) * v[k]
        out[i] = s


@_jit
def _combination(k0, k1, k2, P, PP, M):
    """M = k0 I + k1 ρ̃ + k2 ρ̃² (P = ρ̃, PP = ρ̃²)."""
    for i in range(3):
        for j in range(3):
            M[i, j] = k1 * P[i, j] + k2 * PP[i, j]
        M[i, i] += k0


@_jit
def _slope(m_alpha, beta, alpha1, beta1, P, rho, v, G):
    """∂(M v)/∂ρ (3, 3) of M = I + α ρ̃ + β ρ̃², α and β of x = |ρ|² with slopes α′, β′
    (as ``_matrix_slopes``): w ρᵀ + β ρ vᵀ − α ṽ + β (ρ·v) I, w = 2(α′ ρ×v + β′ ρ×(ρ×v) − β v);
    the arguments −α, β, 2α′, 2β′ as the numpy kernel's."""
    Pv, PPv, w = np.empty(3), np.empty(3), np.empty(3)
    _mv(P, v, Pv, False)
    _mv(P, Pv, PPv, False)
    for i in range(3):
        w[i] = alpha1 * Pv[i] + beta1 * PPv[i] - 2.0 * beta * v[i]
    rv = rho[0] * v[0] + rho[1] * v[1] + rho[2] * v[2]
    _hat(v, G)
    for i in range(3):
        for j in range(3):
            G[i, j] = w[i] * rho[j] + beta * rho[i] * v[j] + m_alpha * G[i, j]
        G[i, i] += beta * rv


# which (3, 3) blocks of the tangent's factors B, C, Z (12, 12) are not zero
_B_BLOCKS = np.array([[1, 0, 0, 0], [0, 1, 1, 0], [1, 0, 0, 0], [0, 0, 0, 1]], dtype=np.bool_)
_C_BLOCKS = np.array([[1, 0, 1, 1], [1, 0, 1, 1], [1, 1, 1, 1], [1, 0, 1, 1]], dtype=np.bool_)
_Z_BLOCKS = np.array([[0, 1, 0, 1], [0, 1, 0, 1], [0, 1, 0, 0], [1, 0, 1, 0]], dtype=np.bool_)
_CZ_BLOCKS = (_C_BLOCKS.astype(int) @ _Z_BLOCKS.astype(int)) > 0


@_jit
def _block_product(A, a, B, b, C):
    """C = A B (12, 12) over the (3, 3) blocks that ``a`` and ``b`` (4, 4) mark non-zero."""
    C[:, :] = 0.0
    for I in range(4):
        for K in range(4):
            if not a[I, K]:
                continue
            for J in range(4):
                if not b[K, J]:
                    continue
                for i in range(3 * I, 3 * I + 3):
                    for j in range(3 * J, 3 * J + 3):
                        s = C[i, j]
                        for k in range(3 * K, 3 * K + 3):
                            s += A[i, k] * B[k, j]
                        C[i, j] = s


@_jit
def _element(chord, u0, u1, N0, N1, ell, L0, CG, CK, f, K, tangent, w, v):
    """Energy of one element; its force into f (12,) and, with ``tangent``, ∂f/∂Δ into K;
    ``w`` (18, 3, 3) and ``v`` (8, 3) hold the intermediates."""
    R0, R1, A, Rm, P, PP = w[0], w[1], w[2], w[3], w[4], w[5]
    H, Ti, hTh, Nh, Gh = w[6], w[7], w[8], w[9], w[10]
    rho, xp, gh, e, n, m, p, t = v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]
    _rotation(N0, R0)
    _rotation(N1, R1)
    _mm(R0, R1, A, True)  # exp(ρ̃) = R₀ᵀR₁
    theta, _ = _relative(N0, N1, rho)
    co = np.empty(7)
    _functions(theta * theta, co)
    _hat(rho, P)
    _mm(P, P, PP, False)
    _combination(1.0, 0.5 * co[2], 0.25 * co[3], P, PP, H)  # exp(½ρ̃)
    _combination(1.0, 0.5, co[0], P, PP, Ti)  # T(ρ)⁻¹
    _combination(0.5, -0.25 * co[3], 0.125 * co[4], P, PP, hTh)  # ½T(½ρ)
    _mm(R0, H, Rm, False)
    for i in range(3):
        xp[i] = (u1[i] - u0[i] + chord[i]) / ell  # (the chord apart: round-off of u, not of |X|)
    _mv(Rm, xp, gh, True)
    for i in range(3):
        e[i] = gh[i] - L0[i, 0]
    _mv(CG, e, n, False)
    _mv(CK, rho, m, False)
    W = 0.0
    for i in range(3):
        W += 0.5 * (ell * e[i] * n[i] + rho[i] * m[i])
    _hat(n, Nh)
    _hat(gh, Gh)
    u = xp  # (x′ no longer needed)
    _mv(Nh, gh, p, False)
    p *= ell
    _mv(hTh, p, u, True)
    u += m
    _mv(Ti, u, t, True)
    # f = B (n̂, p, t, t) = (−R_m n̂, exp(½ρ̃) p − exp(ρ̃) t, R_m n̂, t)
    for i in range(3):
        rn = Rm[i, 0] * n[0] + Rm[i, 1] * n[1] + Rm[i, 2] * n[2]
        f[i], f[6 + i], f[9 + i] = -rn, rn, t[i]
        f[3 + i] = H[i, 0] * p[0] + H[i, 1] * p[1] + H[i, 2] * p[2]
        f[3 + i] -= A[i, 0] * t[0] + A[i, 1] * t[1] + A[i, 2] * t[2]
    if tangent:
        B = np.zeros((12, 12))  # its blocks R_m, exp(½ρ̃), exp(ρ̃), I
        B[0:3, 0:3], B[6:9, 0:3] = -Rm, Rm
        B[3:6, 3:6], B[3:6, 6:9] = H, -A
        for i in range(3):
            B[9 + i, 9 + i] = 1.0
        _element_tangent(rho, p, u, t, CG, CK, ell, co, B, K, w)
    return W


@_jit
def _element_tangent(rho, p, u, t, CG, CK, ell, co, B, K, w):
    """K = B (C Z) of ``_tangent``: the derivatives Z = (Dρ, Dφ, Z₃, Z₄) and their
    coefficients C (dn, dp, dt, Dt); ``w`` holds ``_element``'s matrices."""
    A, Rm, P, H, Ti, hTh, Nh, Gh = w[2], w[3], w[4], w[6], w[7], w[8], w[9], w[10]
    G0, G1, Q, ap, V, T1, T2 = w[11], w[12], w[13], w[14], w[15], w[16], w[17]
    # ∂(½T(½ρ)ᵀ p)/∂ρ and ∂(T(ρ)⁻ᵀ u)/∂ρ: (−α, β, 2α′, 2β′) of each
    _slope(-0.25 * co[3], 0.125 * co[4], 0.125 * co[5], 0.0625 * co[6], P, rho, p, G0)
    _slope(0.5, co[0], 0.0, 2.0 * co[1], P, rho, u, G1)
    _mm(Gh, CG, Q, False)
    Q[:, :] = Nh - Q  # Q = n̂~ − γ̂~ CG
    _mm(Q, Gh, ap, False)
    ap *= ell
    _mm(hTh, Ti, T1, False)
    V[:, :] = T1.T
    C = np.zeros((12, 12))
    _mm(CG, Gh, T1, False)
    T1 -= Nh  # A of dn
    C[0:3, 6:9] = T1
    _mm(T1, hTh, C[0:3, 0:3], False)
    C[0:3, 9:12] = CG / ell
    C[3:6, 6:9] = ap
    _hat(-p, T1)
    T1 += ap
    _mm(T1, hTh, C[3:6, 0:3], False)  # (A of dp − p̃) ½T(½ρ)
    C[3:6, 9:12] = Q
    _mm(V, ap, C[6:9, 6:9], False)  # A of dt
    T1[:, :] = CK + G0
    _mm(Ti, T1, T2, True)
    T2 += G1  # TK
    _mm(C[6:9, 6:9], hTh, T1, False)
    C[6:9, 0:3] = T1 + T2
    _hat(-t, C[6:9, 3:6])
    _mm(V, Q, C[6:9, 9:12], False)
    C[9:12, 0:3], C[9:12, 6:9], C[9:12, 9:12] = C[6:9, 0:3], C[6:9, 6:9], C[6:9, 9:12]
    Z = np.zeros((12, 12))
    Z[0:3, 3:6], Z[0:3, 9:12] = -Ti.T, Ti
    Z[3:6, 3:6], Z[6:9, 3:6] = -A.T, H.T
    Z[9:12, 0:3], Z[9:12, 6:9] = -Rm.T, Rm.T
    for i in range(3):
        Z[3 + i, 9 + i] = 1.0
    CZ = np.empty((12, 12))
    _block_product(C, _C_BLOCKS, Z, _Z_BLOCKS, CZ)
    _block_product(B, _B_BLOCKS, CZ, _CZ_BLOCKS, K)


@_jit
def _internal(chord, q, n0, ell, L0, CG, CK, f, K, tangent):
    """Energy (J); the force into f (ndof,) (zeroed here) and the element tangents into K."""
    n = len(q) // 6
    N = np.empty((n, 4))
    for a in range(n):
        _quaternion(q[6 * a + 3 : 6 * a + 6], N[a])
    f[:] = 0.0
    fe, w, v = np.empty(12), np.empty((18, 3, 3)), np.empty((8, 3))
    W = 0.0
    for e in range(len(n0)):
        a, b = n0[e], n0[e] + 1
        W += _element(
            chord[e], q[6 * a : 6 * a + 3], q[6 * b : 6 * b + 3], N[a], N[b], ell[e],
            L0[e], CG[e], CK[e], fe, K[e if tangent else 0], tangent, w, v,
        )  # fmt: skip
        f[6 * a : 6 * a + 6] += fe[:6]
        f[6 * b : 6 * b + 6] += fe[6:]
    return W


@_jit
def _energy(chord, q, n0, ell, L0, CG, CK):
    """Strain energy (J): the strains of ``_element`` without its force."""
    n = len(q) // 6
    N = np.empty((n, 4))
    for a in range(n):
        _quaternion(q[6 * a + 3 : 6 * a + 6], N[a])
    W = 0.0
    w, v, co = np.empty((5, 3, 3)), np.empty((4, 3)), np.empty(7)
    R0, Rm, H, P, PP = w[0], w[1], w[2], w[3], w[4]
    rho, xp, g, n = v[0], v[1], v[2], v[3]
    for e in range(len(n0)):
        a, b = n0[e], n0[e] + 1
        _rotation(N[a], R0)
        theta, _ = _relative(N[a], N[b], rho)
        _functions(theta * theta, co)
        _hat(rho, P)
        _mm(P, P, PP, False)
        _combination(1.0, 0.5 * co[2], 0.25 * co[3], P, PP, H)
        _mm(R0, H, Rm, False)
        for i in range(3):
            xp[i] = (q[6 * b + i] - q[6 * a + i] + chord[e, i]) / ell[e]
        _mv(Rm, xp, g, True)
        for i in range(3):
            g[i] -= L0[e, i, 0]
        _mv(CG[e], g, n, False)
        _mv(CK[e], rho, xp, False)
        for i in range(3):
            W += 0.5 * (ell[e] * g[i] * n[i] + rho[i] * xp[i])
    return W


def jit_internal(el, X: np.ndarray, q: np.ndarray, ndof: int, tangent: bool):
    """As :func:`~fecontact.bodies.beam3d_kernels.beam3d_internal`: the strain energy W (J),
    the internal force (N, N·m in the nodes' frames R) and the element tangents (E, 12, 12)
    (None without ``tangent``)."""
    f = np.empty(ndof)
    K = np.empty((len(el.ell) if tangent else 1, 12, 12))  # (one unused without tangent)
    q = np.ascontiguousarray(q, dtype=float)
    W = _internal(el.chord, q, el.n0, el.ell, el.L0, el.CG, el.CK, f, K, tangent)
    return W, f, K if tangent else None


def jit_energy(el, X: np.ndarray, q: np.ndarray) -> float:
    """As :func:`~fecontact.bodies.beam3d_kernels.beam3d_energy`: the strain energy W (J)."""
    q = np.ascontiguousarray(q, dtype=float)
    return _energy(el.chord, q, el.n0, el.ell, el.L0, el.CG, el.CK)
