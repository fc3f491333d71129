r"""Mortar integrals over slave triangles, 3D: the overlaps with the master triangles.

A slave triangle (x_a, x_b, x_c) with area coordinates λ carries, at the integration points
x = Σ λ_i x_i of its overlap with a master triangle (y_1, y_2, y_3), the gap along its unit
normal n = N/|N|, N = (x_b − x_a) × (x_c − x_a), to the master triangle's plane:

    g_N = −(x − y_1)·M / (n·M),   M = (y_2 − y_1) × (y_3 − y_1)   (m; > 0 open),

so that x + g_N n lies on the master triangle. The weighted gap contributions of the
triangle's nodes (m³) are g̃_i = Σ w Φ_i(λ) g_N A with the dual functions of the linear
triangle, Φ_i = 4λ_i − 1 (∫ Φ_i N_j dA = δ_ij A/3), A = |N|/2, and weights w (the fraction of
the slave triangle each point stands for).

The overlap (:func:`clipped_points`) is the master triangle projected onto the slave
triangle's plane along n, in the slave's area coordinates, clipped to the slave triangle
(Sutherland–Hodgman), cut into a fan of cells with a 3-point rule of degree 2 each: the
segment-based integration of Popp, Gitterle, Gee & Wall (IJNME 2010) with the slave
element's own normal as the projection direction. Gradients and Hessians over the 18
coordinates z = (x_a, x_b, x_c, y_1, y_2, y_3) are those at the fixed points, in closed
form (:func:`facet_pair_integrals`); see :mod:`fecontact.contact.mortar3d` for what that
leaves out.
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet

__all__ = ["FACING", "clipped_moments", "clipped_points", "facet_pair_integrals", "meet_triangles"]


def _cross_tensor() -> np.ndarray:
    """T (3, 9, 9): the cross product N = (x_b − x_a) × (x_c − x_a) of a triangle's
    vertices X = (x_a, x_b, x_c) (9,) as N_c = ½ Xᵀ T_c X (a homogeneous quadratic form,
    so that ∂N_c/∂X = T_c X and ∂²N_c/∂X² = T_c)."""
    eps = np.zeros((3, 3, 3))
    eps[0, 1, 2] = eps[1, 2, 0] = eps[2, 0, 1] = 1.0
    eps[0, 2, 1] = eps[2, 1, 0] = eps[1, 0, 2] = -1.0
    eye, zero = np.eye(3), np.zeros((3, 3))
    e1, e2 = np.hstack([-eye, eye, zero]), np.hstack([-eye, zero, eye])
    B = np.einsum("cjk,ja,kb->cab", eps, e1, e2)
    return (B + B.transpose(0, 2, 1)).reshape(3, 81)


_T = _cross_tensor()
_Y1 = np.hstack([np.eye(3), np.zeros((3, 6))])  # ∂y_1/∂Y


def _quadratic(c: np.ndarray, P: int, *lead) -> np.ndarray:
    """Σ_c c_c T_c: (P, *lead, 9, 9) from the weights c (P, *lead, 3)."""
    return (c @ _T).reshape(P, *lead, 9, 9)


def facet_pair_integrals(z: np.ndarray, hessian=None):
    """Jets (one per slave node a, b, c) of the weighted-gap contributions (m³) of P (slave
    triangle, master triangle) pairs: ``z`` (P, ≥ 27) holds the 18 vertex coordinates
    X = (x_a, x_b, x_c), Y = (y_1, y_2, y_3), then the moments m_ik = Σ w Φ_i λ_k (3 × 3) of
    the pair's integration points (fixed).

    With r_k = (x_k − y_1)·M the master plane's offset of slave vertex k, s = N·N and
    d = N·M, the gap at a point is g_N = −Σ_k λ_k r_k |N| / d and A = |N|/2, so that
    Σ w Φ_i g_N A = f R_i with f = −½ s/d and R_i = Σ_k m_ik r_k = w_i·M, w_i = Σ_k m_ik
    (x_k − y_1): one evaluation per pair instead of one per point. N and M are quadratic
    forms of X and Y (``_cross_tensor``), so the gradients and Hessians over z follow in
    closed form by the product and quotient rules. ``hessian``: None for values only, False
    for gradients, True for Hessians too."""
    P, X, Y = len(z), z[:, :9], z[:, 9:18]
    m = z[:, 18:27].reshape(-1, 3, 3)
    JN, JM = (
        (X @ _T.reshape(3, 9, 9)).transpose(1, 0, 2),
        (Y @ _T.reshape(3, 9, 9)).transpose(1, 0, 2),
    )
    N, M = 0.5 * np.einsum("pca,pa->pc", JN, X), 0.5 * np.einsum("pca,pa->pc", JM, Y)
    w = np.einsum("pik,pkd->pid", m, X.reshape(-1, 3, 3) - Y[:, None, :3])
    s, d = np.einsum("pc,pc->p", N, N), np.einsum("pc,pc->p", N, M)
    R = np.einsum("pid,pd->pi", w, M)
    f = -0.5 * s / d
    values = f[:, None] * R
    if hessian is None:
        return [Jet(values[:, i], None, None) for i in range(3)]
    ds = np.concatenate([2.0 * np.einsum("pca,pc->pa", JN, N), np.zeros((P, 9))], axis=1)
    dd = np.concatenate([np.einsum("pca,pc->pa", JN, M), np.einsum("pca,pc->pa", JM, N)], 1)
    mu = m.sum(axis=2)
    dR = np.concatenate([(m[:, :, :, None] * M[:, None, None, :]).reshape(P, 3, 9),
                         np.einsum("pca,pic->pia", JM, w) - mu[:, :, None] * (M @ _Y1)[:, None]],
                        axis=2)  # fmt: skip
    df = -0.5 * (ds / d[:, None] - (s / d**2)[:, None] * dd)
    grads = df[:, None, :] * R[:, :, None] + f[:, None, None] * dR
    if not hessian:
        return [Jet(values[:, i], grads[:, i], None) for i in range(3)]
    hf = _ratio_hessian(JN, JM, N, M, s, d, ds, dd)
    hR = _offset_hessians(m, JM, w, mu)
    out = []
    for i in range(3):
        fr = df[:, :, None] * dR[:, i, None, :]
        h = hf * R[:, i, None, None] + fr + fr.transpose(0, 2, 1) + f[:, None, None] * hR[:, i]
        out.append(Jet(values[:, i], grads[:, i], h))
    return out


def _ratio_hessian(JN, JM, N, M, s, d, ds, dd) -> np.ndarray:
    """∇²f (P, 18, 18) of f = −½ s/d, s = N·N, d = N·M."""
    P = len(N)
    hs, hd = np.zeros((P, 18, 18)), np.zeros((P, 18, 18))
    hs[:, :9, :9] = 2.0 * (JN.transpose(0, 2, 1) @ JN + _quadratic(N, P))
    hd[:, :9, :9] = _quadratic(M, P)
    hd[:, 9:, 9:] = _quadratic(N, P)
    hd[:, :9, 9:] = JN.transpose(0, 2, 1) @ JM
    hd[:, 9:, :9] = hd[:, :9, 9:].transpose(0, 2, 1)
    inv = (1.0 / d)[:, None, None]
    sd = ds[:, :, None] * dd[:, None, :]
    dd2 = dd[:, :, None] * dd[:, None, :]
    s_ = s[:, None, None]
    return -0.5 * (hs * inv - (sd + sd.transpose(0, 2, 1)) * inv**2 - hd * s_ * inv**2
                   + 2.0 * dd2 * s_ * inv**3)  # fmt: skip


def _offset_hessians(m, JM, w, mu) -> np.ndarray:
    """∇²R_i (P, 3, 18, 18) of R_i = Σ_k m_ik (x_k − y_1)·M."""
    P = len(m)
    hR = np.zeros((P, 3, 18, 18))
    cross = (m[:, :, :, None, None] * JM[:, None, None]).reshape(P, 3, 9, 9)
    hR[:, :, :9, 9:] = cross
    hR[:, :, 9:, :9] = cross.transpose(0, 1, 3, 2)
    y1JM = _Y1.T @ JM  # (P, 9, 9): the rows of y_1
    sym = (y1JM + y1JM.transpose(0, 2, 1))[:, None]
    hR[:, :, 9:, 9:] = _quadratic(w, P, 3) - mu[:, :, None, None] * sym
    return hR


FACING = 0.0
"""Triangles face each other when their unit normals satisfy n_s·n_m < −FACING: when the
master faces the slave at all (normals at more than 90°). The projection along n_s onto the
master's plane is defined for any n_s·n_m ≠ 0, and a pair that faces barely contributes only
where it overlaps within the depth filter, so any stricter bound would be a blind spot: the
poles of two coarse balls meshed alike meet with their triangles' normals at exactly 120°
(each tilted 30° from the axis) and passed through each other with a bound of ½."""


def meet_triangles(x, n, tri, depth: float):
    """For points x (P, 3) with unit normals n (P, 3) against candidate triangles tri
    (P, 3, 3): the signed distance t (P,) along n to each triangle's plane, the area
    coordinates μ (P, 3) of the point met, and whether the line meets the triangle, facing it
    (``FACING``) and not deeper than ``depth`` (m) behind."""
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    M = np.cross(e1, e2)
    r = x - tri[:, 0]
    nM = np.einsum("pi,pi->p", n, M)
    Mn = np.linalg.norm(M, axis=1)
    facing = nM < -FACING * Mn
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -np.einsum("pi,pi->p", r, M) / nM
        p = r + t[:, None] * n
        mu2 = np.einsum("pi,pi->p", np.cross(p, e2), M) / Mn**2
        mu3 = np.einsum("pi,pi->p", np.cross(e1, p), M) / Mn**2
    mu = np.stack([1.0 - mu2 - mu3, mu2, mu3], axis=1)
    tol = 1e-12
    meets = facing & np.all(mu >= -tol, axis=1) & (t >= -depth) & np.isfinite(t)
    return t, mu, meets


_CELL = (np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]),
         np.full(3, 1 / 3))  # fmt: skip
# the reference triangle λ₂ ≥ 0, λ₃ ≥ 0, 1 − λ₂ − λ₃ ≥ 0 as half-planes a·p + b ≥ 0
_HALF_PLANES = ((np.array([1.0, 0.0]), 0.0), (np.array([0.0, 1.0]), 0.0),
                (np.array([-1.0, -1.0]), 1.0))  # fmt: skip


def _clip(V: np.ndarray, n: np.ndarray, a: np.ndarray, b: float, dV=None):
    """Sutherland–Hodgman: the polygons V (P, K, 2) with n (P,) vertices cut by a·p + b ≥ 0.
    ``dV`` (P, K, 2, m): the vertices' derivatives, carried through the cut (None: not)."""
    P, K, _ = V.shape
    idx = np.arange(K)
    valid = idx[None, :] < n[:, None]
    nxt = (idx[None, :] + 1) % np.maximum(n[:, None], 1)
    W = V[np.arange(P)[:, None], nxt]
    hv, hw = V @ a + b, W @ a + b
    inside_v, inside_w = hv >= 0.0, hw >= 0.0
    cross = valid & (inside_v != inside_w)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(cross, hv / (hv - hw), 0.0)
    point = V + s[..., None] * (W - V)
    cand = np.stack([V, point], axis=2).reshape(P, 2 * K, 2)
    keep = np.stack([valid & inside_v, cross], axis=2).reshape(P, 2 * K)
    count = keep.sum(axis=1)
    # the kept vertices first, in their order; the slots no polygon fills are cut off
    order = np.argsort(~keep, axis=1, kind="stable")[:, : max(int(count.max(initial=0)), 1)]
    out = np.take_along_axis(cand, order[..., None], axis=1), count
    if dV is None:
        return out
    # the cut point V + s (W − V), s = h_V / (h_V − h_W): its derivative by the chain rule
    dW = dV[np.arange(P)[:, None], nxt]
    dhv = dV[:, :, 0] * a[0] + dV[:, :, 1] * a[1]
    dhw = dW[:, :, 0] * a[0] + dW[:, :, 1] * a[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        ds = np.where(cross[..., None], (dhv * (-hw)[..., None] + hv[..., None] * dhw)
                      / ((hv - hw) ** 2)[..., None], 0.0)  # fmt: skip
    dpoint = dV + s[..., None, None] * (dW - dV) + (W - V)[..., None] * ds[:, :, None, :]
    dcand = np.stack([dV, dpoint], axis=2).reshape(P, 2 * K, 2, -1)
    return (*out, np.take_along_axis(dcand, order[..., None, None], axis=1))


def clipped_points(mu_plane: np.ndarray):
    """Gauss points of the overlap of P slave triangles with the master triangles projected
    onto them, given as (λ₂, λ₃) coordinates of the slave triangle (P, 3, 2): the overlap is
    clipped (Sutherland–Hodgman), cut into a fan of triangles, each with a 3-point rule of
    degree 2. Returns the pair of each point, its area coordinates λ (·, 3) and its weight w
    (the fraction of the slave triangle's area it stands for)."""
    V, n = mu_plane.astype(float), np.full(len(mu_plane), 3)
    for a, b in _HALF_PLANES:
        V, n = _clip(V, n, a, b)
    pairs, lam, w = [], [], []
    cell, cell_w = _CELL
    for i in range(1, V.shape[1] - 1):
        has = np.flatnonzero(n > i + 1)
        if has.size == 0:
            break
        v0, v1, v2 = V[has, 0], V[has, i], V[has, i + 1]
        area = 0.5 * np.abs((v1 - v0)[:, 0] * (v2 - v0)[:, 1] - (v1 - v0)[:, 1] * (v2 - v0)[:, 0])
        tri = np.stack([v0, v1, v2], axis=1)  # (H, 3, 2)
        p = np.einsum("gk,hkd->hgd", cell, tri).reshape(-1, 2)
        pairs.append(np.repeat(has, len(cell_w)))
        lam.append(np.stack([1.0 - p[:, 0] - p[:, 1], p[:, 0], p[:, 1]], axis=1))
        w.append((area[:, None] * cell_w[None, :] / 0.5).ravel())
    if not pairs:
        return np.zeros(0, int), np.zeros((0, 3)), np.zeros(0)
    return np.concatenate(pairs), np.concatenate(lam), np.concatenate(w)


def clipped_moments(mu_plane: np.ndarray, d_plane=None):
    """Second moments Q_ik = ∫ λ_i λ_k dA / A (P, 3, 3) of the overlaps of
    :func:`clipped_points` (the same clipping, as fractions of the slave triangle's area A)
    and their derivatives (P, 3, 3, m) through the overlaps' vertices, given those of the
    projected master vertices ``d_plane`` (P, 3, 2, m; None: no derivatives). Each fan cell T
    contributes |T|/12 (Σ_a λ^a λ^aᵀ + s sᵀ), s = Σ_a λ^a (exact for the quadratic λ_i λ_k);
    the cells of all polygons at once (empty slots have no area)."""
    V, n, dV = mu_plane.astype(float), np.full(len(mu_plane), 3), d_plane
    for a, b in _HALF_PLANES:
        V, n, dV = _clip(V, n, a, b, dV) if dV is not None else (*_clip(V, n, a, b), None)
    P, K = V.shape[:2]
    if K < 3:
        Q = np.zeros((P, 3, 3))
        return Q, None if dV is None else np.zeros((P, 3, 3, dV.shape[-1]))
    # λ = (1 − p₂ − p₃, p₂, p₃) of the fan's vertices: the apex 0 and the edges (i, i + 1)
    lam = np.concatenate([1.0 - V.sum(axis=2, keepdims=True), V], axis=2)
    L1, L2 = lam[:, 1:-1], lam[:, 2:]  # (P, K − 2, 3)
    L0 = np.broadcast_to(lam[:, :1], L1.shape)
    e1, e2 = V[:, 1:-1] - V[:, :1], V[:, 2:] - V[:, :1]
    c = e1[..., 0] * e2[..., 1] - e1[..., 1] * e2[..., 0]
    filled = np.arange(1, K - 1)[None, :] < (n[:, None] - 1)
    scale = np.where(filled, np.abs(c), 0.0) / 12.0  # the cell's fraction |c|/2 / ½, over 12
    X = np.stack([L0, L1, L2, L0 + L1 + L2], axis=2)  # (P, cells, 4, 3): the corners and s
    S = np.einsum("pcai,pcak->pcik", X, X)
    Q = np.einsum("pc,pcik->pik", scale, S)
    if dV is None:
        return Q, None
    m = dV.shape[-1]
    dlam = np.concatenate([-dV.sum(axis=2, keepdims=True), dV], axis=2)
    d1 = dlam[:, 1:-1]
    dX = np.stack([np.broadcast_to(dlam[:, :1], d1.shape), d1, dlam[:, 2:]], axis=2)
    dX = np.concatenate([dX, dX.sum(axis=2, keepdims=True)], axis=2)  # (P, cells, 4, 3, m)
    de1, de2 = dV[:, 1:-1] - dV[:, :1], dV[:, 2:] - dV[:, :1]
    dc = (de1[..., 0, :] * e2[..., 1, None] + e1[..., 0, None] * de2[..., 1, :]
          - de1[..., 1, :] * e2[..., 0, None] - e1[..., 1, None] * de2[..., 0, :])  # fmt: skip
    dscale = np.where(filled, np.sign(c), 0.0)[..., None] * dc / 12.0
    # Σ_cells scale Σ_a (dX_a X_aᵀ + X_a dX_aᵀ) as one batched product over (cell, a)
    Xs = (X * scale[:, :, None, None]).reshape(P, -1, 3)
    half = (dX.reshape(P, -1, 3 * m).transpose(0, 2, 1) @ Xs).reshape(P, 3, m, 3)
    half = half.transpose(0, 1, 3, 2)
    dQ = half + half.transpose(0, 2, 1, 3)
    dQ += (S.reshape(P, K - 2, 9).transpose(0, 2, 1) @ dscale).reshape(P, 3, 3, m)
    return Q, dQ
