r"""Dual shape functions of a slave segment that the master covers in part (2D mortar).

On a segment ξ ∈ [−1, 1] with N_1 = (1 − ξ)/2, N_2 = (1 + ξ)/2, the dual functions
Φ_j = Σ_k A_jk N_k are biorthogonal to the N_k over the part [a, b] of the segment that the
master covers (Popp, Seitz, Gee & Wall, CMAME 2013, for partially projecting slave elements):

    ∫_a^b Φ_j N_k dξ = δ_jk ∫_a^b N_k dξ,   A = D M⁻¹,
    D = diag(∫_a^b N_k dξ),   M_kl = ∫_a^b N_k N_l dξ.

On the whole segment, A = [[2, −1], [−1, 2]]: Φ = ½ ∓ 3ξ/2. Where only a part is covered,
these functions keep the weighted gap of a gap field linear on the segment equal to its nodal
value times ∫_a^b N_j dξ J, a positive weight; the functions of the whole segment would weigh
the covered part alone with their lobes of both signs, and a slave node sticking out of the
zone the master covers (a coarse boundary, a vertex meeting a vertex) would read a gap that
is neither its own nor of its sign. The Jacobian J cancels in A.

The covered part of a slave segment is the union of its overlaps with all master segments;
its ends a, b are either ∓1 or the projections of master nodes. Each (slave segment, master
segment) entry computes a, b itself, from its own overlap or from the master node that
bounds the union (carried in its local coordinates), so that the gradients and Hessians of
the weighted gaps through A stay those of one entry.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STANDARD", "covered_ends", "dual_coefficients"]

STANDARD = np.array([[2.0, -1.0], [-1.0, 2.0]])
"""A of the whole segment."""

CLAMPED, OWN, FOREIGN = 0, 1, 2
"""How an entry finds an end of its slave segment's covered part: the segment's own end
(∓1), its own overlap's end, or the projection of a master node of another entry."""


def dual_coefficients(a, b):
    """A = D M⁻¹ (module docstring) over [a, b] ⊂ [−1, 1], a < b: (A11, A12, A21, A22), Jets
    (or arrays) like a and b."""
    u, U, v, V = 1.0 - a, 1.0 - b, 1.0 + b, 1.0 + a
    u2, U2, v2, V2 = u * u, U * U, v * v, V * V
    D11, D22 = (u2 - U2) * 0.25, (v2 - V2) * 0.25
    M11 = (u2 * u - U2 * U) * (1.0 / 12.0)
    M12 = D11 - M11  # M11 + M12 = ∫ N_1 (N_1 + N_2) = D11
    M22 = D22 - M12
    inv = (M11 * M22 - M12 * M12).reciprocal()
    e, f = D11 * inv, D22 * inv
    return e * M22, -(e * M12), -(f * M12), f * M11


def covered_ends(e, lo, hi, lo_node, hi_node, n_elements: int):
    """How each of P entries (slave segments ``e``) finds the ends of its segment's covered
    part: ``lo``, ``hi`` (P,) its own overlap's ends, ``lo_node``, ``hi_node`` (P,) the
    master node (0: y_1, 1: y_2) whose projection each is (−1: the segment's end ∓1).

    Returns (kind_lo, kind_hi) ∈ {CLAMPED, OWN, FOREIGN} per entry and, for FOREIGN, the
    entry (src_lo, src_hi) whose master node bounds the union."""
    P = len(e)
    src = []
    for values, sign in ((lo, 1.0), (hi, -1.0)):
        order = np.lexsort((sign * values, e))
        first = np.unique(e[order], return_index=True)[1]
        owner = np.full(n_elements, -1)
        owner[e[order][first]] = order[first]
        src.append(owner[e])
    kinds = []
    for owner, node in zip(src, (lo_node, hi_node), strict=True):
        kind = np.where(owner == np.arange(P), OWN, FOREIGN)
        kinds.append(np.where(node[owner] < 0, CLAMPED, kind))
    return kinds[0], kinds[1], src[0], src[1]
