r"""Redundant rows in the smooth step: persistent contacts that hold fewer degrees of freedom
than they have rows (a rigid face landing flat on an elastic face: the nodes under the face,
the face's corners and its edges across the ridges all hold one plane), solved as one linear
complementarity problem on every row at once.

At the iterate q, with the force term's Jacobian K (S_t and the curvature of the contact
forces), the residual r (which holds −G_Pᵀλ) and the persistent rows' gaps g and gradients G
(G T(D) as the rows move on a Lie group), Newton's update is dq = x₀ + Y Δλ with x₀ = −K⁻¹r
and Y = K⁻¹G_Pᵀ. The linearised law on the new forces λ⁺ = λ + Δλ is

    0 ≤ λ⁺ ⊥ w = c + D λ⁺ ≥ 0,   D = G Y,   c = g + G x₀ − D λ,

D the Delassus matrix of the rows in the step's metric. Where rows are redundant D is
singular: its null space holds the forces that move nothing (Gᵀz = 0 for D z = 0, K being
regular), so dq and the gaps it leaves are unique while λ⁺ is not. The primal–dual active set
of :class:`~fecontact.time.smooth_contact.SmoothContacts` changes every violating row at once;
on such rows it wanders, and nearly parallel rows (a corner's row and that of an edge ending
at it; a node's row and that of an edge crossing a ridge at it) with gaps that differ by
round-off take forces of 1e7 N of opposite signs. Here the problem is solved whole by the
proximal point method of :func:`fecontact.contact.redundant_jump.proximal_jump` (block
principal pivoting on D + εI, whose fixed point is the law's, then the least-norm multipliers
of the closed rows): the set of the answer is the law's, the multipliers are the least-norm
member of their family, and neither the augmentation p nor the scale k enters (the law is
solved without them). Newton then iterates on the rows' nonlinearity alone.

Used in runs whose model can have redundant rows and no beam (decided once per run:
``ContactStats.minimum_norm``; beams keep their updates on an independent subset), in a step
whose active set holds dependent rows or repeats a set it had left, from that update to the
step's end; every other step keeps the active-set iteration, to the bit. In those runs a row
that the smooth step unloads while its gap stays closed is not released
(:func:`fecontact.time.smooth_contact.released`): the least-norm forces handed its share to the
rows it is redundant with. Measured on a rigid box landing flat on an elastic cube:
docs/validation/stress_3d.md."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..contact.redundant_jump import proximal_jump

__all__ = ["dependent", "linearised_law", "wandering"]


def linearised_law(g, lam, x0, Y, lower, tol: float):
    """The forces λ⁺ (N) of the rows with gaps ``g`` (m) and forces ``lam`` at the iterate:
    0 ≤ λ⁺ ⊥ w = c + D λ⁺ ≥ 0 with D = ``lower`` Y (m/N), c = g + ``lower`` x₀ − D λ, x₀ =
    −K⁻¹r and Y = K⁻¹Gᵀ, ``lower`` the rows' linearization (G, or G T(D) on a group), within
    the gap tolerance ``tol`` (m): no row below −tol, the loaded rows within ±tol. None
    where the proximal steps do not settle."""
    D = lower @ Y
    c = g + lower @ x0 - D @ lam

    def settled(x, w):
        return bool(np.all(w >= -tol) and np.all(np.abs(w[x > 0.0]) <= tol))

    found = proximal_jump(D, c, np.zeros(len(c), bool), np.zeros(len(c)), settled, tol)
    return None if found is None else found[0]


def wandering(seen: list, A: np.ndarray, G) -> bool:
    """Whether the active set ``A`` (of the rows with gradients ``G``) holds dependent rows
    or repeats a set the step has left (``seen``: the step's sets so far, to which a new one
    is added): where the active-set iteration cannot settle."""
    if any((A == B).all() for B in seen[:-1]):
        return True
    if not seen or not (A == seen[-1]).all():
        seen.append(A.copy())
    GA = G[A]
    return dependent(GA.toarray() if sp.issparse(GA) else np.asarray(GA))


def dependent(G: np.ndarray, rtol: float = 1e-8) -> bool:
    """Whether the rows of ``G`` (dense) are linearly dependent up to ``rtol`` of the largest
    singular value: redundant rows, or rows nearly so, whose multipliers the active-set
    iteration cannot tell apart."""
    if G.shape[0] < 2:
        return False
    if G.shape[0] > G.shape[1]:
        return True
    s = np.linalg.svd(G, compute_uv=False)
    return bool(s[-1] <= rtol * s[0])
