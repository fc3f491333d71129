r"""Quadratic polynomials of the integration points (s, t) of curved 6-node triangles, as Jets.

At a point of the slave face's parameter plane the shape functions, the transformed basis
Ñ = T N and the slave surface x(s, t) with its tangents are quadratic polynomials in (s, t),

    f_j = Σ_m a_mj (1, s, t, s², s t, t²)_m,

whose partials are known in closed form. The points (s, t) are Jets over the pair's 36
coordinates z (through the overlap's vertices), so by the chain rule

    ∂²f = f_s ∂²s + f_t ∂²t + f_ss ∂s ∂sᵀ + f_st (∂s ∂tᵀ + ∂t ∂sᵀ) + f_tt ∂t ∂tᵀ,

five (B, n, n) arrays shared by every polynomial of the point, combined with each one's own
five coefficients in one batched product: the same derivatives as the products of Jets
that multiply out the monomials, with a fraction of their passes over the Hessians. The
slave surface also moves with its nodes x_k (the first 18 of z, ∂x/∂x_k = N_k), which adds
the terms N_k's gradient puts in the rows and columns of x_k (:func:`slave_surface`).
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet

__all__ = ["polynomials", "slave_surface"]

# ∂/∂s and ∂/∂t of the monomials (1, s, t, s², s t, t²) as rows of coefficients on them
_DS = np.zeros((6, 6))
_DS[1, 0], _DS[3, 1], _DS[4, 2] = 1.0, 2.0, 1.0
_DT = np.zeros((6, 6))
_DT[2, 0], _DT[4, 1], _DT[5, 2] = 1.0, 1.0, 2.0


def _partials(A):
    """The coefficients of f_s and f_t of polynomials with coefficients A (..., 6, J)."""
    return np.einsum("nm,...mj->...nj", _DS.T, A), np.einsum("nm,...mj->...nj", _DT.T, A)


def _values(A, s, t):
    mono = np.stack([np.ones_like(s), s, t, s * s, s * t, t * t], axis=1)  # (B, 6)
    return np.einsum("bm,...mj->bj", mono, A) if A.ndim == 2 else np.einsum("bm,bmj->bj", mono, A)


def polynomials(A, s: Jet, t: Jet, hessian: bool = True):
    """The Jets (B, J) of f_j = Σ_m A[m, j] monomial_m at the points (s, t) (Jets, B): A
    (6, J) the same at every point, or (B, 6, J) each point's own. Returns (values (B, J),
    gradients (B, J, n) or None, Hessians (B, J, n, n) or None: also without ``hessian``)."""
    v = _values(A, s.v, t.v)
    if s.g is None:
        return v, None, None
    As, At = _partials(A)
    fs, ft = _values(As, s.v, t.v), _values(At, s.v, t.v)
    g = fs[:, :, None] * s.g[:, None, :] + ft[:, :, None] * t.g[:, None, :]
    if s.h is None or not hessian:
        return v, g, None
    B, n = s.g.shape
    ss = s.g[:, :, None] * s.g[:, None, :]
    st = s.g[:, :, None] * t.g[:, None, :]
    basis = np.stack(
        [s.h, t.h, ss, st + st.transpose(0, 2, 1), t.g[:, :, None] * t.g[:, None, :]], 1
    )
    second = np.broadcast_to(
        np.stack([2.0 * A[..., 3, :], A[..., 4, :], 2.0 * A[..., 5, :]], -1), (B, A.shape[-1], 3)
    )
    coef = np.concatenate([fs[..., None], ft[..., None], second], axis=2)  # (B, J, 5)
    h = np.matmul(coef, basis.reshape(B, 5, n * n)).reshape(B, -1, n, n)
    return v, g, h


def slave_surface(C, X, s: Jet, t: Jet):
    """x, x_s and x_t (3-tuples of Jets) of the slave faces with nodes X (B, 6, 3) (the first
    18 of the n variables, node k's coordinate d the variable 3k + d) at the points (s, t);
    ``C`` (6, 6) the shape functions' monomial coefficients."""
    c = np.einsum("mk,bkd->bmd", C, X)  # x = Σ_m c_m monomial_m
    cs, ct = _partials(c)
    v, g, h = polynomials(np.concatenate([c, cs, ct], axis=2), s, t)  # (B, 9 = 3 × d)
    if g is not None:
        Cs, Ct = _partials(C)
        # ∂x/∂x_k = N_k, ∂x_s/∂x_k = ∂N_k/∂s, ∂x_t/∂x_k = ∂N_k/∂t: (B, 3 functions, 6 nodes)
        phi = polynomials(np.concatenate([C, Cs, Ct], axis=1), s, t, hessian=False)
        fv, fg = phi[0].reshape(-1, 3, 6), phi[1].reshape(len(v), 3, 6, -1)
        for d in range(3):
            cols = 3 * np.arange(6) + d
            g[:, d::3][:, :, cols] += fv
            if h is not None:
                h[:, d::3][:, :, cols, :] += fg
                h[:, d::3][:, :, :, cols] += fg.transpose(0, 1, 3, 2)
    jets = [
        Jet(v[:, j], None if g is None else g[:, j], None if h is None else h[:, j])
        for j in range(9)
    ]
    return tuple(jets[0:3]), tuple(jets[3:6]), tuple(jets[6:9])
