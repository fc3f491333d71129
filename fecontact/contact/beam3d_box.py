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
middle of that stretch. The gap of the segment is g = s(x(ξ*)) − r.
"""

from __future__ import annotations

import numpy as np

__all__ = ["box_signed_distance", "closest_to_box"]

TIE = 1e-12
"""Signed distances within this fraction of the box's half diagonal of the least are equal
(round-off of coordinates of the box's size)."""


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
