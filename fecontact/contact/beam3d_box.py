r"""The closest point of a segment to a box, for the segments of a beam (tubes of radius r)
against a rigid ``Box`` (:class:`~fecontact.contact.beam3d_pairs.TubeBoxContact`).

In the box frame (half sides h, centre at the origin) a segment has the points
x(ξ) = A + ξ(B − A), ξ ∈ [0, 1]. The signed distance of a point from the box,

    s(x) = |x − clamp(x, −h, h)| outside,  s(x) = −min_k (h_k − |x_k|) inside,

is convex (the box is), and so is s(x(ξ)). Its minimum over [0, 1] lies at an end, at a
breakpoint x_k(ξ) = ±h_k, at the stationary point of the squared distance Σ (|x_k| − h_k)²
over the clamped axes on one piece between breakpoints, or, inside, where two of the six
depths h_k ∓ x_k(ξ) are equal: all are candidates, and the least s among them is exact. A
segment parallel to a face is equally near along its stretch over the face: ξ* is then the
middle of that stretch, and tilted it jumps to an end: :func:`box_rows` gives the contact rows
at both ends of such a stretch, over a face or along an edge, each continuous in the segment.
"""

from __future__ import annotations

import numpy as np

__all__ = ["box_rows", "box_signed_distance", "closest_to_box"]

TIE = 1e-12
"""Signed distances within this fraction of the box's half diagonal of the least are equal
(round-off of coordinates of the box's size)."""

ALONG = np.cos(0.1)
"""A segment whose least distance's normal lies within 0.1 rad of a face's, or whose direction
lies within 0.1 rad of an edge's, has rows at both ends of its stretch over that face or
along that edge (tilted by 0.1 rad, the far end's row is 0.1 × the stretch's length apart:
off the active set where the rows change)."""


def box_signed_distance(x: np.ndarray, half: np.ndarray):
    """Signed distances s (...,) of points x (..., 3) from the box of half sides ``half`` about
    the origin and the outward unit normals n_b (..., 3) at their closest points."""
    d = x - np.clip(x, -half, half)
    dist = np.linalg.norm(d, axis=-1)
    out = dist > 0.0
    n = np.where(out[..., None], d / np.where(out, dist, 1.0)[..., None], 0.0)
    depth = half - np.abs(x)
    k = np.argmin(depth, axis=-1)
    inside = np.take_along_axis(depth, k[..., None], axis=-1)[..., 0]
    face = np.eye(3)[k] * np.where(np.take_along_axis(x, k[..., None], -1) >= 0.0, 1.0, -1.0)
    return np.where(out, dist, -inside), np.where(out[..., None], n, face)


def _candidates(A: np.ndarray, d: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Parameters (m, c) where the least signed distance of the segments A + ξd can lie."""
    with np.errstate(divide="ignore", invalid="ignore"):
        planes = np.concatenate([(half - A) / d, (-half - A) / d], axis=1)  # x_k = ±h_k
        # two depths equal: h_i − σ_i x_i = h_j − σ_j x_j
        lines = np.concatenate([-d, d], axis=1)  # slopes of h_k ∓ x_k(ξ)
        level = np.concatenate([half - A, half + A], axis=1)  # their values at ξ = 0
        i, j = np.triu_indices(6, 1)
        cross = (level[:, j] - level[:, i]) / (lines[:, i] - lines[:, j])
    ends = np.zeros((len(A), 2))
    ends[:, 1] = 1.0
    bounds = np.sort(np.clip(np.nan_to_num(np.c_[planes, ends], nan=0.0), 0.0, 1.0), axis=1)
    middles = 0.5 * (bounds[:, 1:] + bounds[:, :-1])
    # on each piece the clamped axes (|x_k| > h_k) and their signs hold: D is a parabola
    x = A[:, None] + middles[..., None] * d[:, None]
    clamped = np.abs(x) > half
    sign = np.sign(x)
    dd = np.where(clamped, d[:, None] ** 2, 0.0).sum(axis=2)
    num = np.where(clamped, d[:, None] * (sign * half - A[:, None]), 0.0).sum(axis=2)
    with np.errstate(divide="ignore", invalid="ignore"):
        stationary = np.clip(num / dd, bounds[:, :-1], bounds[:, 1:])
    every = np.c_[bounds, np.nan_to_num(stationary, nan=0.0), np.nan_to_num(cross, nan=0.0)]
    return np.clip(every, 0.0, 1.0)


def closest_to_box(A: np.ndarray, B: np.ndarray, half: np.ndarray):
    """The parameter ξ* (m,) of the points of the segments (A, B) (m, 3, box frame) with the
    least signed distance from the box, that distance (m,), the point ρ = x(ξ*) (m, 3) and the
    box's outward normal n_b there (m, 3)."""
    d = B - A
    xi = _candidates(A, d, half)
    s = box_signed_distance(A[:, None] + xi[..., None] * d[:, None], half)[0]
    # a segment lying along a face is equally near over a stretch: s is convex along the
    # segment, so the candidates within round-off of the least bound that stretch, and its
    # middle is taken (a choice that moves with the segment, not with round-off)
    tied = s <= s.min(axis=1)[:, None] + TIE * np.linalg.norm(half)
    xi = 0.5 * (np.where(tied, xi, np.inf).min(axis=1) + np.where(tied, xi, -np.inf).max(axis=1))
    rho = A + xi[:, None] * d
    s, nb = box_signed_distance(rho, half)
    return xi, s, rho, nb


def _prism_planes():
    """The axes (18, 5), signs (18, 5) and bounds' factors (18, 5) of the half-spaces
    σ x_axis ≥ factor h_axis bounding the outer prisms of the faces (σ x_k ≥ h_k, |x_j| ≤ h_j
    for j ≠ k; ordered +x, +y, +z, −x, −y, −z) and of the edges (σ₁ x_k₁ ≥ h_k₁,
    σ₂ x_k₂ ≥ h_k₂, |x_j| ≤ h_j; 6 + 4j + 2[σ₁ < 0] + [σ₂ < 0], k₁ < k₂ the axes other than
    j; a fifth half-space that always holds: sign 0)."""
    axes, signs, factors = [], [], []
    for sigma in (1.0, -1.0):
        for k in range(3):
            i, j = (a for a in range(3) if a != k)
            axes.append([k, i, i, j, j])
            signs.append([sigma, 1.0, -1.0, 1.0, -1.0])
            factors.append([1.0, -1.0, -1.0, -1.0, -1.0])
    for j in range(3):
        k1, k2 = (a for a in range(3) if a != j)
        for s1 in (1.0, -1.0):
            for s2 in (1.0, -1.0):
                axes.append([k1, k2, j, j, j])
                signs.append([s1, s2, 1.0, -1.0, 0.0])
                factors.append([1.0, 1.0, -1.0, -1.0, 0.0])
    return np.array(axes), np.array(signs), np.array(factors)


PRISMS = _prism_planes()


def _stretches(A: np.ndarray, d: np.ndarray, half: np.ndarray):
    """The stretch [lo, hi] (m, 18) of each segment A + ξd in each prism (empty: lo > hi)
    and the axes (m, 18) of the planes x_axis = ±h_axis that bound it below and above (−1
    where the segment's end does)."""
    axes, signs, factors = PRISMS
    a = signs * A[:, axes] - factors * half[axes]  # a + ξ b ≥ 0 inside each half-space
    b = signs * d[:, axes]
    with np.errstate(divide="ignore", invalid="ignore"):
        root = -a / b
    never = (b == 0.0) & (a < 0.0)
    lower = np.where(b > 0.0, root, np.where(never, np.inf, -np.inf))
    upper = np.where(b < 0.0, root, np.where(never, -np.inf, np.inf))
    lo_k, hi_k = np.argmax(lower, axis=2), np.argmin(upper, axis=2)
    lo = np.take_along_axis(lower, lo_k[..., None], 2)[..., 0]
    hi = np.take_along_axis(upper, hi_k[..., None], 2)[..., 0]
    lo_axis = np.where(lo > 0.0, np.take_along_axis(axes, lo_k.T, 1).T, -1)
    hi_axis = np.where(hi < 1.0, np.take_along_axis(axes, hi_k.T, 1).T, -1)
    return np.maximum(lo, 0.0), np.minimum(hi, 1.0), lo_axis, hi_axis


def _prism(d: np.ndarray, nb: np.ndarray, empty: np.ndarray):
    """The prism (m,) whose stretch takes the rows: the face whose normal lies within 0.1 rad
    (``ALONG``) of n_b at the least distance, else the edge within 0.1 rad of the segment's
    direction on n_b's side, either with a stretch (not ``empty`` (m, 18)), and whether there
    is one (m,)."""
    lean = np.concatenate([nb, -nb], axis=1)  # n_b·(±e_k), faces as the prisms
    face = np.argmax(lean, axis=1)
    j = np.argmax(np.abs(d), axis=1)
    k1, k2 = (j == 0).astype(int), np.where(j == 2, 1, 2)
    rows = np.arange(len(d))
    edge = 6 + 4 * j + 2 * (nb[rows, k1] < 0.0) + (nb[rows, k2] < 0.0)
    along = np.abs(d[rows, j]) >= ALONG * np.linalg.norm(d, axis=1)
    on_face = (lean[rows, face] >= ALONG) & ~empty[rows, face]
    along &= ~empty[rows, edge]
    return np.where(on_face, face, edge), on_face | along


def _least_within(every, s, keep, pick, tie):
    """The candidate ξ (m,) of least s among those kept, the tied one ``pick`` chooses."""
    sk = np.where(keep, s, np.inf)
    tied = sk <= sk.min(axis=1)[:, None] + tie
    return pick(np.where(tied, every, np.nan), axis=1)


def box_rows(A: np.ndarray, B: np.ndarray, half: np.ndarray):
    """Three rows per segment (A, B) (m, 3, box frame) about its stretch [lo, hi] over a
    face, or along an edge, of the box: the least signed distance over [0, lo], over
    [hi, 1] and inside (lo, hi) where it is below both ends (else left out: +inf); without
    such a stretch the least over the segment and two rows left out.

    Returns ξ (m, 3), s (m, 3), ρ = x(ξ) (m, 3, 3), the box's outward normals n_b there
    (m, 3, 3) and the gradients' normals ν (m, 3, 3): δs = ν·δρ with δρ the motion of the
    point held at ξ, ν = n_b − e_j (n_b·d)/d_j where the row's point is the stretch's end on
    a plane x_j = ±h_j (it slides along it), else n_b."""
    d = B - A
    xi = _candidates(A, d, half)
    lo, hi, lo_axis, hi_axis = _stretches(A, d, half)
    whole, _, _, nb_whole = closest_to_box(A, B, half)
    p, over = _prism(d, nb_whole, lo > hi)
    take = np.arange(len(A)), p
    ends = np.clip(np.stack([lo[take], hi[take]], axis=1), 0.0, 1.0)
    end_axis = np.stack([lo_axis[take], hi_axis[take]], axis=1)
    every = np.concatenate([xi, ends], axis=1)
    s = box_signed_distance(A[:, None] + every[..., None] * d[:, None], half)[0]
    tie = TIE * np.linalg.norm(half)
    # below and above: the tied candidate nearest the stretch (its end, where s is level)
    below = _least_within(every, s, every <= ends[:, :1], np.nanmax, tie)
    above = _least_within(every, s, every >= ends[:, 1:], np.nanmin, tie)
    inner = (every > ends[:, :1]) & (every < ends[:, 1:])
    middle = _least_within(every, s, inner, np.nanmin, 0.0)
    xi_rows = np.stack([below, above, np.nan_to_num(middle, nan=0.0)], axis=1)
    xi_rows = np.where(over[:, None], xi_rows, whole[:, None])
    rho = A[:, None] + xi_rows[..., None] * d[:, None]
    s, nb = box_signed_distance(rho, half)
    ends_s = box_signed_distance(A[:, None] + ends[..., None] * d[:, None], half)[0]
    s[:, 1] = np.where(over, s[:, 1], np.inf)
    s[:, 2] = np.where(over & (s[:, 2] < ends_s.min(axis=1) - tie), s[:, 2], np.inf)
    at_end = over[:, None] & (xi_rows[:, :2] == ends) & (end_axis >= 0)
    j = np.maximum(end_axis, 0)
    slide = np.einsum("mri,mi->mr", nb[:, :2], d) / np.where(
        at_end, np.take_along_axis(d, j, 1), 1.0
    )
    nu = nb.copy()
    nu[:, :2] -= np.where(at_end, slide, 0.0)[..., None] * np.eye(3)[j]
    return xi_rows, s, rho, nb, nu
