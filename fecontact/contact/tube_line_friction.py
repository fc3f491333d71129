r"""Coulomb friction of the beam's rows of the solid–tube mortar
(:class:`~fecontact.contact.tube_line_mortar.TubeLineMortar`): one slip row per beam node.

The slip of row i is the motion of the solid's material point under the node (its closest
boundary triangle, at the node's projection on that triangle's plane, area coordinates ζ)
against the tube's material point facing it, y_i = c_i − r n (n the triangle's outward
normal), which turns with the node's section: ẏ_i = ċ_i + ω_i × (−r n), ω_i = R_i Ω_i (Ω the
body-frame velocity of the node's rotation dofs). T_i are the tangents of n; the row is scaled
by c_i = max(0, n·N_i), N_i = Σ_beam ∂g_i/∂x_b the force the row puts on the beam per unit
multiplier (1 on a flat face), so that Coulomb's bound μλ_i acts on the row's load across the
face. Over a step the slip is exact for a rigid turn of the section: the tube's point now at
y_i was at c_i,n + R_i,n R_iᵀ(−r n). A rod rolling on a face slips at no row.
"""

from __future__ import annotations

import numpy as np

from ..rotations import exp, hat
from .friction import tangent_basis

__all__ = ["line_slips", "line_tangents", "slip_frame"]


def slip_frame(pair, q: np.ndarray):
    """Per row of ``pair`` at q: the solid's nodes of its closest triangle (m, 3), the node's
    projection's area coordinates (m, 3), the arm −r n to the tube's surface (m, 3), the
    scaled tangents c_i T_i (m, 2, 3) and the unit tangents T_i."""
    x, xb = pair.frame(q)
    # (a row without a triangle near carries no load: c = 0 below)
    f = np.maximum(pair.closest(pair.node_search, xb, x), 0)
    tri = pair.facets[f]
    a, b, c = (x[tri[:, k]] for k in range(3))
    N = np.cross(b - a, c - a)
    n = N / np.linalg.norm(N, axis=1)[:, None]
    p = xb - np.einsum("mi,mi->m", xb - a, n)[:, None] * n  # projection on the plane
    area = lambda u, v, w: np.einsum("mi,mi->m", np.cross(v - u, w - u), n)  # noqa: E731
    total = area(a, b, c)
    zeta = np.stack([area(p, b, c), area(a, p, c), area(a, b, p)], axis=1) / total[:, None]
    G = pair.evaluate(q)[2]
    Nb = G[:, : pair.beam_cols].reshape(pair.size, -1, 3).sum(axis=1)
    scale = np.maximum(np.einsum("mi,mi->m", n, Nb), 0.0)
    T = tangent_basis(n)
    return tri, zeta, -pair.clearance * n, scale[:, None, None] * T, T


def line_tangents(pair, q: np.ndarray):
    """Slip rows of ``pair`` at q: dofs (m, 15), the 9 of the solid's triangle under the
    node, then the node's 6; c_i T_i ∂(x_i − y_i)/∂ (m, 2, 15) with x the solid's material
    point and y the tube's; unit tangents T_i."""
    tri, zeta, arm, cT, T = slip_frame(pair, q)
    ob = pair.offsets[1]
    R = exp(q[ob : ob + pair.beam.ndof].reshape(-1, 6)[:, 3:])  # (m, 3, 3)
    W = np.empty((pair.size, 2, 15))
    for k in range(3):
        W[:, :, 3 * k : 3 * k + 3] = zeta[:, k, None, None] * cT
    W[:, :, 9:12] = -cT
    # ẏ = ċ + ω × arm = ċ − hat(arm) R Ω
    W[:, :, 12:15] = np.einsum("mti,mij,mjk->mtk", cT, hat(arm), R)
    oa = pair.offsets[0]
    beam = ob + 6 * np.arange(pair.size)[:, None] + np.arange(6)
    dofs = np.concatenate([oa + pair.solid_dofs[tri].reshape(-1, 9), beam], axis=1)
    return dofs, W, T


def line_slips(pair, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
    """The slips c_i T_i·((x_i − y_i) − (x_i,n − y_i,n)) (m, 2) of ``pair`` over the step from
    q_n to q: the same material points
    (area coordinates on the triangle, the arm turned back with the section,
    y_n = c_n + R_n Rᵀ arm), exact for a rigid turn of the section."""
    tri, zeta, arm, cT, _ = slip_frame(pair, q)
    (oa, ob), body, beam = pair.offsets, pair.body, pair.beam
    now, before = (v[ob : ob + beam.ndof].reshape(-1, 6) for v in (q, q_n))
    R, Rn = exp(now[:, 3:]), exp(before[:, 3:])
    c, cn = beam.X + now[:, :3], beam.X + before[:, :3]
    yn = cn + np.einsum("mij,mkj,mk->mi", Rn, R, arm)
    y = c + arm
    x = np.einsum("mk,mki->mi", zeta, body.positions(q[oa : oa + body.ndof])[tri])
    xn = np.einsum("mk,mki->mi", zeta, body.positions(q_n[oa : oa + body.ndof])[tri])
    return np.einsum("mti,mi->mt", cT, (x - y) - (xn - yn))
