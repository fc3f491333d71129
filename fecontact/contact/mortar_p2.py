r"""Dual multipliers of quadratic (P2) slave faces: the basis transformation of Popp, Wohlmuth,
Gee & Wall (SIAM J. Sci. Comput. 2012).

Dual functions Φ_j = Σ_k A_jk N_k biorthogonal to the face's shape functions N_k,

    ∫_e Φ_j N_k dA = δ_jk ∫_e N_k dA,   A = D M⁻¹,
    D = diag(∫_e N_k dA),   M_kl = ∫_e N_k N_l dA,

make every multiplier a nodal unknown with its own complementarity (the rows of a mortar
interface). They need D_jj > 0. On the 6-node triangle the corner functions
N_i = λ_i (2 λ_i − 1) integrate to zero (the edge functions 4 λ_i λ_j to |e|/3 each): the
corner nodes would carry no weight and no dual function. The remedy chosen is the one of the
paper: transform the slave face's displacement basis element by element,

    Ñ_i = N_i + α Σ_{edges m at corner i} N_m   (corners),   Ñ_m = (1 − 2α) N_m   (edges),

Ñ = T N, with α = 1/5; Σ_k Ñ_k = Σ_k N_k = 1 and T is invertible for α ≠ ½, so Ñ spans the
same space and only the nodal unknowns change (d = Tᵀ d̃ for u = Σ N_k d_k = Σ Ñ_k d̃_k).
Then ∫Ñ_i = 2α|e|/3 = 2|e|/15 at a corner and (1 − 2α)|e|/3 = |e|/5 at an edge node, all
positive, and the dual functions are built on Ñ (A = D̃ M̃⁻¹, Φ̃ biorthogonal to Ñ). This
form is chosen because it keeps what the linear faces have: one multiplier per slave node
with its own complementarity (D̃ diagonal), a multiplier space of the trace's own order that
reproduces a uniform pressure (Σ_j Φ_j = 1), and nodal forces Σ_j z_j ∫Φ_j N_k = p ∫N_k for
a uniform pressure p, the consistent P2 load (corners 0, edge nodes |e|/3 on the triangle).

On the 3-node segment (2D) the corner functions (ξ(ξ ∓ 1)/2) integrate to |e|/6 > 0: the
standard quadratic dual functions exist (α = 0 is the default there); the same
transformation with α > 0 is available and gives the corner nodes more weight.

Node order: segment (a, b, m) — the two ends, then the mid node; triangle (1, 2, 3, m12,
m23, m31) — the corners, then the edge nodes opposite corners 3, 1, 2. The functions here
are those of the reference element; the Jacobian of a curved face enters through the
weights at the integration points (:func:`dual_coefficients`), exactly as the element's
measure does for a flat face (where it cancels in A).

Where they are used: the 3-node segments of two 2D P2 solids in contact
(:mod:`fecontact.contact.mortar_p2_segments`, the segment's own dual functions, α = 0).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = [
    "ALPHA",
    "QuadraticFacePairs",
    "SMALLEST",
    "counted_weights",
    "covered_part_gaps",
    "dual_coefficients",
    "reference_rule",
    "shape_functions",
    "transformation",
]

ALPHA = {"segment": 0.0, "triangle": 0.2}
"""Default α of the transformation per face kind: none needed on the segment, 1/5 on the
triangle (the paper's value)."""

_EDGES = ((0, 1), (1, 2), (2, 0))  # the triangle's edge nodes 3, 4, 5 join these corners


def _check_kind(kind: str) -> None:
    if kind not in ALPHA:
        raise InputError(f"kind must be 'segment' or 'triangle', got {kind!r}")


def transformation(kind: str, alpha: float | None = None) -> np.ndarray:
    """T (n, n) with Ñ = T N for a P2 ``kind`` face ("segment": n = 3, "triangle": n = 6),
    α in [0, ½) (default :data:`ALPHA`)."""
    _check_kind(kind)
    a = ALPHA[kind] if alpha is None else float(alpha)
    if not 0.0 <= a < 0.5:
        raise InputError(f"alpha must be in [0, 0.5), got {alpha!r}")
    if kind == "segment":
        return np.array([[1.0, 0.0, a], [0.0, 1.0, a], [0.0, 0.0, 1.0 - 2.0 * a]])
    T = np.eye(6)
    for m, (i, j) in enumerate(_EDGES):
        T[i, 3 + m] = T[j, 3 + m] = a
        T[3 + m, 3 + m] = 1.0 - 2.0 * a
    return T


def shape_functions(kind: str, points: np.ndarray) -> np.ndarray:
    """The P2 shape functions N (m, n) at reference ``points``: ξ ∈ [−1, 1] (m,) on the
    segment, (λ₂, λ₃) (m, 2) on the triangle (λ₁ = 1 − λ₂ − λ₃)."""
    _check_kind(kind)
    p = np.asarray(points, dtype=float)
    if kind == "segment":
        xi = p.reshape(-1)
        return np.stack([0.5 * xi * (xi - 1.0), 0.5 * xi * (xi + 1.0), 1.0 - xi * xi], axis=1)
    p = p.reshape(-1, 2)
    lam = np.stack([1.0 - p[:, 0] - p[:, 1], p[:, 0], p[:, 1]], axis=1)
    corners = lam * (2.0 * lam - 1.0)
    edges = np.stack([4.0 * lam[:, i] * lam[:, j] for i, j in _EDGES], axis=1)
    return np.concatenate([corners, edges], axis=1)


def reference_rule(kind: str, n: int = 5):
    """Points and weights of a Gauss rule on the reference ``kind`` face: n points on
    [−1, 1] (weights summing to 1, the fraction of the face), or n² collapsed (Duffy) points
    on the triangle (weights summing to 1); exact for polynomials of degree 2n − 2 or more
    (degree 8 at n = 5: the products of two P2 functions and a quadratic Jacobian)."""
    _check_kind(kind)
    x, w = np.polynomial.legendre.leggauss(n)
    if kind == "segment":
        return x, 0.5 * w
    u, wu = 0.5 * (x + 1.0), 0.5 * w
    U, V = np.meshgrid(u, u, indexing="ij")
    W = np.outer(wu, wu) * (1.0 - U)  # dA = (1 − u) du dv over the unit square
    points = np.stack([U.ravel(), (V * (1.0 - U)).ravel()], axis=1)
    return points, 2.0 * W.ravel()


def dual_coefficients(kind: str, alpha: float | None = None, jacobian=None):
    """(A, T): the dual functions Φ = A Ñ biorthogonal to the transformed basis Ñ = T N of a
    P2 ``kind`` face (module docstring). ``jacobian`` (m,), the face's measure density at the
    points of :func:`reference_rule` (default rule) relative to its mean (None: a flat face,
    constant); A does not depend on the face's size."""
    T = transformation(kind, alpha)
    points, w = reference_rule(kind)
    if jacobian is not None:
        jac = np.asarray(jacobian, dtype=float)
        if jac.shape != w.shape or not np.all(np.isfinite(jac)) or np.any(jac <= 0.0):
            raise InputError(f"jacobian must be {w.shape[0]} positive values at the rule's points")
        w = w * jac
    Nt = shape_functions(kind, points) @ T.T  # Ñ at the points (m, n)
    D = Nt.T @ w
    M = (Nt * w[:, None]).T @ Nt
    if np.any(D <= 1e-12 * D.max()):  # (round-off of a zero integral)
        raise InputError(f"alpha: a shape function of the {kind} integrates to {D.min():.3g}")
    return D[:, None] * np.linalg.inv(M), T


SMALLEST = 1e-6
"""A slave face covered by less than this fraction of its parameter triangle counts as not
covered (its covered-part moment matrix would be near singular)."""

_FULL = 1e-9  # a face covered to within this fraction is covered fully


def counted_weights(e, coverage, covered, n_faces: int) -> np.ndarray:
    """The entries' covered weights ``covered`` (P, n), zero on the slave faces covered by
    less than :data:`SMALLEST` in all (``coverage`` (P,) the fractions the entries cover):
    those faces contribute nothing to the weighted gaps (:func:`covered_part_gaps`), and a
    node that took part from their weight alone had a row of gap 0 and gradient 0, which
    Newton's method cannot hold (a P2 box laid on a slab, its side faces at 90°)."""
    fraction = np.bincount(e, coverage, n_faces)[e]
    return np.where((fraction >= SMALLEST)[:, None], covered, 0.0)


def covered_part_gaps(e, moments, mass_of, coverage, n_faces: int, duals: np.ndarray):
    """The Jets g̃_j = Σ_k A_jk m_k (j = 1..n) of P entries (slave faces ``e``), from the
    entries' Jets m_k = ∫ Ñ_k g_N dA over their overlaps (``moments``), ``mass_of(part)``
    giving the Jets M_kl = ∫ Ñ_k Ñ_l dA of the entries ``part`` (bool, P) alone (needed on
    faces covered in part only) and the fractions of the faces they cover (``coverage``);
    and their dual coefficients A (P, n, n): on a face covered fully those of the reference face
    (``duals``, n × n); on a face covered in part those biorthogonal on the covered part C,
    A = D M⁻¹ with M = Σ_pairs M_p the face's ∫_C Ñ Ñᵀ dA and D = diag(M 1) (Popp, Seitz,
    Gee & Wall, CMAME 2013). A depends on every pair of the face; with t = M⁻¹ S, S = Σ m_p,
    its derivative splits over the pairs, ∂(A S)_j ⊃ t_j Σ_l ∂M_p,jl − Σ_i A_ji (∂M_p t)_i,
    so the gradients stay exact in the pairs' own coordinates, and so do the Hessians
    (:func:`_covered_hessians`), with the terms coupling two pairs of a face apart
    (:func:`_coupled_hessians`). A face covered by less than :data:`SMALLEST` contributes
    nothing. Returns (jets, A, coupled): ``coupled`` None, or with Hessians (a, b, C), the
    ordered pairs of entries a ≠ b on one face covered in part and C (K, n, z, z) the
    second derivatives of their face's g̃ over a's coordinates and b's."""
    fraction = np.bincount(e, coverage, n_faces)[e]
    part = (fraction >= SMALLEST) & (fraction < 1.0 - _FULL) & (coverage > 0.0)
    n = len(duals)
    A = np.where((fraction >= SMALLEST)[:, None, None], duals, 0.0)
    t = np.zeros((len(e), n))
    mass = mass_of(part) if part.any() else None
    if part.any():
        faces, local = np.unique(e[part], return_inverse=True)
        M = np.zeros((len(faces), n, n))
        S = np.zeros((len(faces), n))
        Mp = np.stack([np.stack([j.v for j in row], 1) for row in mass], 1)
        np.add.at(M, local, Mp)
        np.add.at(S, local, np.stack([m.v[part] for m in moments], 1))
        inv = np.linalg.inv(M)
        A[part] = (M.sum(axis=2)[:, :, None] * inv)[local]
        t[part] = np.einsum("fkl,fl->fk", inv, S)[local]
    jets = [sum(moments[k] * A[:, j, k] for k in range(n)) for j in range(n)]
    coupled = None
    if part.any() and moments[0].g is not None:
        face = (M[local], inv[local], A[part], t[part], local)
        coupled = _differentiate_covered(jets, moments, mass, part, face)
    return jets, A, coupled


def _differentiate_covered(jets, moments, mass, part, face):
    """The derivatives of the Jets ``jets`` on the entries ``part`` (faces covered in part)
    through their dual coefficients: ``face`` the face's M, M⁻¹, A and t = M⁻¹ S per entry
    and the entry's face (an index). Returns the coupled Hessians of
    :func:`covered_part_gaps` (None without Hessians or where no face has two such pairs)."""
    M, inv, Ap, tp, local = face
    dM = np.stack([np.stack([j.g for j in row], 1) for row in mass], 1)  # (Pp, n, n, z)
    own = dM.sum(axis=2) * tp[:, :, None]  # t_j Σ_l ∂M_jl
    other = np.einsum("pji,pilz,pl->pjz", Ap, dM, tp)
    for j, jet in enumerate(jets):
        g = jet.g.copy()
        g[part] += own[:, j] - other[:, j]
        jet.g = g
    if moments[0].h is None:
        return None
    ddM = np.stack([np.stack([j.h for j in row], 1) for row in mass], 1)
    dS = np.stack([m.g[part] for m in moments], 1)  # (Pp, n, z)
    ddS = np.stack([m.h[part] for m in moments], 1)
    dt = np.einsum("pki,piz->pkz", inv, dS - np.einsum("pilz,pl->piz", dM, tp))
    hess = _covered_hessians(M, inv, tp, (dM, ddM), (dt, ddS))
    for j, jet in enumerate(jets):
        jet.h = jet.h.copy()
        jet.h[part] = hess[:, j]
        jet.flat = False
    coupled = _coupled_hessians(M, inv, dM, dt, local)
    if coupled is None:
        return None
    entries = np.flatnonzero(part)
    return entries[coupled[0]], entries[coupled[1]], coupled[2]


def _covered_hessians(M, inv, t, dM, dS):
    """∂²(A S)_j over one pair's coordinates (Pp, n, z, z) on faces covered in part, the
    pair's own M_p and m_p varying and the face's other pairs fixed (their cross terms:
    :func:`_coupled_hessians`): with t = M⁻¹ S and r = M 1 (A = diag(r) M⁻¹), (A S)_j =
    r_j t_j, ∂t = M⁻¹(∂S − ∂M t), ∂²t = M⁻¹(∂²S − ∂²M t − ∂M ∂t − (∂M ∂t)ᵀ); ``dS`` holds
    ∂t and ∂²S. At fixed A (A ∂²m alone) a segment covered by a sliver had 50 times its
    curvature along a Newton update (two P2 disks at 29 m/s, ``docs/explanation/mortar.md``)."""
    (dM, ddM), (dt, ddS) = dM, dS
    mix = np.einsum("pilz,ply->pizy", dM, dt)
    inner = ddS - np.einsum("pilzy,pl->pizy", ddM, t) - mix - mix.transpose(0, 1, 3, 2)
    ddt = np.einsum("pki,pizy->pkzy", inv, inner)
    r, dr, ddr = M.sum(axis=2), dM.sum(axis=2), ddM.sum(axis=2)
    cross = dr[:, :, :, None] * dt[:, :, None, :]
    return (ddr * t[:, :, None, None] + cross + cross.transpose(0, 1, 3, 2)
            + ddt * r[:, :, None, None])  # fmt: skip


def _coupled_hessians(M, inv, dM, dt, local):
    """∂²(A S)_j/∂z_a ∂z_b (K, n, z, z) of the ordered pairs (a, b), a ≠ b, of entries on
    one face covered in part (``local``: each entry's face; M, M⁻¹ its face's, ∂M and
    ∂t = M⁻¹(∂S − ∂M t) its own): the pairs' M_p and S_p are sums, so ∂_a ∂_b M = ∂_a ∂_b S
    = ∂_a ∂_b r = 0 and ∂_a ∂_b t = −M⁻¹(∂_a M ∂_b t + ∂_b M ∂_a t); (a, b, C), or None
    where no face has two entries. Left out, a box's side face tilted 5° over a slab, covered
    by slivers of four of its faces, had rows' Hessians 2.8e4 /m off their differences by
    as much (docs/explanation/mortar.md, *A face covered by several pairs*)."""
    a, b = np.nonzero((local[:, None] == local[None, :]) & ~np.eye(len(local), dtype=bool))
    if a.size == 0:
        return None
    r, dr = M.sum(axis=2), dM.sum(axis=2)
    mix = np.einsum("kilz,kly->kizy", dM[a], dt[b])
    mix += np.einsum("kily,klz->kizy", dM[b], dt[a])
    ddt = -np.einsum("kji,kizy->kjzy", inv[a], mix)
    C = dr[a][..., :, None] * dt[b][..., None, :] + dt[a][..., :, None] * dr[b][..., None, :]
    return a, b, C + r[a][:, :, None, None] * ddt


class QuadraticFacePairs:
    """The candidate pairs of a mortar interface on quadratic faces (segments or triangles),
    shared by the 2D and 3D interfaces: their overlap found by the value pass of the
    interface's own ``_integrate``, the pairs whose slave face it covers kept."""

    coupled = True  # (the dual functions of a covered part couple the face's pairs)

    def _overlapping(self, q: np.ndarray):
        """The slave nodes' positions and the candidate pairs that overlap: slave faces e,
        local coordinates z (P, the two faces' nodes × dim), global dofs and the value
        pass's integrals."""
        xs, xm = self.positions(q)
        e, f = self._near(xs, xm, *self._pairs(xs, xm))
        sn, mn = self.facets[e], self.master_facets[f]
        z = np.concatenate([xs[sn], xm[mn]], axis=1)
        z = z.reshape(len(e), z.shape[1] * z.shape[2])  # (also with no candidate pair)
        jets, coverage, covered, _ = self._integrate(e, z, None)
        keep = coverage > 0.0
        prior = ([j.take(keep) for j in jets], coverage[keep], covered[keep])
        return xs, e[keep], z[keep], self._global_dofs(sn[keep], mn[keep]), prior

    def _local(self, q: np.ndarray, derivatives: bool = True):
        xs, e, z, dofs, _ = self._overlapping(q)
        return e, z, dofs, xs

    def _values(self, q: np.ndarray):
        xs, e, _, _, (jets, coverage, covered) = self._overlapping(q)
        return e, jets, coverage, covered, xs
