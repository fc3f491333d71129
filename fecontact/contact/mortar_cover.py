r"""Dual functions of slave triangles that the master covers in part (3D mortar).

On a slave triangle that the master's projection covers only in part, the dual functions
Φ_j = Σ_k A_jk λ_k are made biorthogonal on the covered polygon C alone (Popp, Seitz, Gee &
Wall, CMAME 2013):

    ∫_C Φ_j λ_k dA = δ_jk ∫_C λ_k dA,   A = D Q⁻¹,   Q_ik = ∫_C λ_i λ_k dA / |e|,
    D = diag(Q 1)

(the triangle's area |e| cancels). On the whole triangle A = 4 I − 1 1ᵀ, Φ_j = 4 λ_j − 1.
A gap field linear on the triangle then enters node j's weighted gap as its nodal value times
the positive weight ∫_C λ_j dA, however small C is; the functions of the whole triangle would
weigh C alone with lobes of both signs.

C is the union of the triangle's overlaps C_p with the master triangles p projected onto it,
so A depends on every master triangle the slave triangle meets. The weighted gap of node j
is Σ_i A_ji S_i with S_i = Σ_p f_p Σ_k Q_p,ik r_p,k (the pair integrals of
:func:`~fecontact.contact.mortar_facets.facet_pair_integrals`, g_N A = f Σ_k λ_k r_k), and
its derivative through the moments splits over the pairs: with t = Q⁻¹ S and dA = (dD −
A dQ) Q⁻¹,

    ∂g̃_j ⊃ Σ_p [ Σ_i A_ji Σ_k dQ_p,ik (f_p r_p,k − t_k) + t_j Σ_k dQ_p,jk ],

each term in its own pair's 18 coordinates, dQ_p the derivative of the overlap's moments
through its clipped vertices (:func:`~fecontact.contact.mortar_facets.clipped_moments`).
So the gradients stay exact, and the rows keep the pairs' layout. The Hessians are those at
fixed A and fixed integration points (the second derivatives through the polygon are left
out).
"""

from __future__ import annotations

import numpy as np

from .mortar_facets import clipped_moments

__all__ = ["SMALLEST", "covered_duals", "triangles_taking_part"]

SMALLEST = 1e-6
"""A slave triangle covered by less than this fraction of its area counts as not covered:
the covered-part dual functions would rest on a moment matrix Q of condition ~ 1/fraction,
and the triangle's weight in its nodes' gaps, ∫_C λ_j dA, is below this fraction."""

_FULL = 1e-9  # a triangle covered to within this fraction of its area is covered fully

# the derivatives of the slave vertices x_a, x_b, x_c and master vertices y_1..y_3 (18, 6, 3)
_E = np.eye(18).reshape(18, 6, 3)
_DU, _DV = _E[:, 1] - _E[:, 0], _E[:, 2] - _E[:, 0]
_DR = _E[:, 3:] - _E[:, :1]  # (18, 3 master vertices, 3): y_k − x_a
_PLANE = np.eye(6).reshape(3, 2, 6)  # the projected master coordinates as the variables


def plane_gradients(u, v, r, plane) -> np.ndarray:
    """∂(λ₂, λ₃)/∂z (P, 3, 2, 18) of the master vertices projected orthogonally onto the slave
    triangle's plane: G (λ₂, λ₃) = (r·u, r·v), G the Gram matrix of u = x_b − x_a,
    v = x_c − x_a, r = y_k − x_a (``plane`` the values)."""
    uu, uv, vv = (np.einsum("pd,pd->p", a, b) for a, b in ((u, u), (u, v), (v, v)))
    duu, dvv = 2.0 * u @ _DU.T, 2.0 * v @ _DV.T
    duv = v @ _DU.T + u @ _DV.T
    dru = np.einsum("pd,zkd->pkz", u, _DR) + np.einsum("pkd,zd->pkz", r, _DU)
    drv = np.einsum("pd,zkd->pkz", v, _DR) + np.einsum("pkd,zd->pkz", r, _DV)
    a, b = plane[..., 0, None], plane[..., 1, None]
    R1 = dru - duu[:, None] * a - duv[:, None] * b
    R2 = drv - duv[:, None] * a - dvv[:, None] * b
    det = (uu * vv - uv * uv)[:, None, None]
    return np.stack([(vv[:, None, None] * R1 - uv[:, None, None] * R2) / det,
                     (uu[:, None, None] * R2 - uv[:, None, None] * R1) / det], axis=2)  # fmt: skip


def _pair_terms(ts, tm):
    """f = −½ N·N / N·M and r_k = (x_k − y_1)·M (P, 3) of the pairs (module docstring)."""
    N = np.cross(ts[:, 1] - ts[:, 0], ts[:, 2] - ts[:, 0])
    M = np.cross(tm[:, 1] - tm[:, 0], tm[:, 2] - tm[:, 0])
    f = -0.5 * np.einsum("pd,pd->p", N, N) / np.einsum("pd,pd->p", N, M)
    r = np.einsum("pkd,pd->pk", ts - tm[:, :1], M)
    return f, r


def triangles_taking_part(rows, e, weight, covered, area, share: float) -> np.ndarray:
    """The slave triangles (bool per triangle) with a node that may take part: its covered
    weight Σ_e ∫_C λ_j dA (``covered`` (P, 3), m², of the pairs of triangles ``e``) at least
    0.9 ``share`` of the area its covered triangles give it (the interface's rule asks
    ``share``; the margin keeps every node that passes it). ``rows`` (triangles, 3): the
    nodes' rows; ``weight`` (P,) the overlaps' fractions; ``area`` (triangles,) m². The dual
    functions of the covered part are built on these triangles only: on the others no row
    takes part. A triangle covered by less than :data:`SMALLEST` counts as not covered, as
    :func:`covered_duals` drops it and the interface's rule then sees it: counted here, it
    raised a node's support by a third at the crossing of two cubes' edges, and the node,
    taking part, read its gap through the whole triangles' dual functions (+1.5 mm where its
    covered parts read −0.15 mm)."""
    size = int(rows.max(initial=-1)) + 1
    fraction = np.bincount(e, weight, len(rows))
    on = fraction >= SMALLEST
    W = sum(np.bincount(rows[e, k], np.where(on[e], covered[:, k], 0.0), size) for k in range(3))
    support = np.bincount(rows[on].ravel(), np.repeat(area[on] / 3.0, 3), size)
    node = (W > 0.0) & (W >= 0.9 * share * support)
    return node[rows].any(axis=1)


def covered_duals(e, ts, tm, u, v, plane, weight, needed, derivatives: bool = True, fade=None):
    """The pairs (slave triangles ``e``, their vertices ``ts``, the master's ``tm``, ``u``,
    ``v`` the slave edges, ``plane`` the projected master vertices, ``weight`` the overlaps'
    fractions of the slave triangle) on partly covered triangles: returns ``part`` (P,) bool,
    their dual coefficients A (Pp, 3, 3), the extra gradients (Pp, 3, 18) of the ends'
    weighted gaps through A and the overlaps (module docstring), and ``drop`` (P,) bool, the
    pairs of triangles covered by less than :data:`SMALLEST`. ``needed`` (bool per triangle):
    the triangles whose dual functions count (:func:`triangles_taking_part`); without
    ``derivatives`` the extra gradients are zeros (for the gaps' values alone). ``fade``:
    the pairs' weights (P,) and their gradients (P, 18), which scale the overlaps' moments
    (none: 1)."""
    fraction = np.bincount(e, weight, len(needed))
    drop = (fraction < SMALLEST)[e]
    part = ((fraction >= SMALLEST) & (fraction < 1.0 - _FULL) & needed)[e] & (weight > 0.0)
    if not part.any():
        return part, np.zeros((0, 3, 3)), np.zeros((0, 3, 18)), drop
    ep, tsp, tmp = e[part], ts[part], tm[part]
    # the overlaps depend on z through the 6 projected master coordinates alone: their
    # moments are differentiated in those, then chained with ∂(λ₂, λ₃)/∂z
    own = np.broadcast_to(_PLANE, (len(ep), 3, 2, 6)) if derivatives else None
    Q0, dQ = clipped_moments(plane[part], own)
    f0, df0 = (np.ones(len(e)), np.zeros((len(e), 18))) if fade is None else fade
    Q = Q0 * f0[part][:, None, None]
    tri, local = np.unique(ep, return_inverse=True)
    Qe = np.zeros((len(tri), 3, 3))
    np.add.at(Qe, local, Q)
    inv = np.linalg.inv(Qe)
    A = Qe.sum(axis=2)[:, :, None] * inv  # D Q⁻¹
    if not derivatives:
        return part, A[local], np.zeros((len(ep), 3, 18)), drop
    d_plane = plane_gradients(u[part], v[part], tmp - tsp[:, None, 0], plane[part])
    dQ = dQ.reshape(-1, 9, 6) @ d_plane.reshape(-1, 6, 18)
    dQ = dQ.reshape(-1, 3, 3, 18) * f0[part][:, None, None, None]
    dQ = dQ + Q0[..., None] * df0[part][:, None, None, :]
    f, r = _pair_terms(tsp, tmp)
    S = np.zeros((len(tri), 3))
    np.add.at(S, local, f[:, None] * np.einsum("pik,pk->pi", Q, r))
    t = np.einsum("eik,ek->ei", inv, S)[local]
    Ap = A[local]
    inner = np.einsum("pikz,pk->piz", dQ, f[:, None] * r - t)
    extra = np.einsum("pji,piz->pjz", Ap, inner) + t[:, :, None] * dQ.sum(axis=2)
    return part, Ap, extra, drop
