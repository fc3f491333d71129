"""The excess of a point's foot on a triangle's plane beyond the triangle's edges, with its
derivatives: how far a point lies beside a facet rather than over it (the pointwise rows of
:mod:`fecontact.contact.mortar_safeguard` read each plane gap deeper by it); in 2D, of the
foot on a segment's line beyond the segment's ends."""

from __future__ import annotations

import numpy as np

from .jets import Jet, dot, variables

__all__ = ["edge_excess", "edge_excess_jet", "end_excess", "end_excess_jet"]


def _ramp(e: np.ndarray, eps: float):
    """r(e) = 0 (e ≤ 0), e²/2ε (0 < e < ε), e − ε/2 (e ≥ ε), with r′ and r″: a ramp with a
    continuous slope."""
    band = (e > 0.0) & (e < eps)
    r = np.where(e >= eps, e - 0.5 * eps, np.where(band, 0.5 * e * e / eps, 0.0))
    first = np.where(e >= eps, 1.0, np.where(band, e / eps, 0.0))
    return r, first, np.where(band, 1.0 / eps, 0.0)


def edge_excess(x: np.ndarray, tri: np.ndarray, eps: float) -> np.ndarray:
    """Σ over the three edges of the triangles ``tri`` (m, 3, 3) of r(e), e (m) the distance
    of the foot of x (m, 3) on the triangle's plane beyond the edge's line (negative inside),
    r the ramp of width ``eps`` (m): zero where the foot lies in the triangle."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1)[:, None]
    total = np.zeros(len(x))
    for p, q in ((a, b), (b, c), (c, a)):
        m = np.cross(q - p, n) / np.linalg.norm(q - p, axis=1)[:, None]  # (outward)
        total += _ramp(np.einsum("mk,mk->m", x - p, m), eps)[0]
    return total


def _cross(u: Jet, v: Jet) -> Jet:
    """u × v of two vector jets (m, 3)."""
    parts = [
        u.column(j) * v.column(k) - u.column(k) * v.column(j) for j, k in ((1, 2), (2, 0), (0, 1))
    ]
    return Jet(*(np.stack([getattr(p, f) for p in parts], axis=1) for f in ("val", "grad", "hess")))


def edge_excess_jet(x: np.ndarray, tri: np.ndarray, eps: float):
    """:func:`edge_excess` with its gradient (m, 12) and Hessian (m, 12, 12) over
    (x, a, b, c)."""
    X, A, B, C = variables([x, tri[:, 0], tri[:, 1], tri[:, 2]], 12)
    N = _cross(B - A, C - A)
    n = N / dot(N, N).sqrt().scalar()
    total = None
    for p, q in ((A, B), (B, C), (C, A)):
        u = q - p
        e = dot(X - p, _cross(u, n)) / dot(u, u).sqrt()
        r = e.apply(*_ramp(e.val, eps))
        total = r if total is None else total + r
    return total.val, total.grad, total.hess


def end_excess(x: np.ndarray, seg: np.ndarray, eps: float) -> np.ndarray:
    """r(e_a) + r(e_b) (m) of points x (m, 2) and segments ``seg`` (m, 2, 2): e_a, e_b the
    distances of the foot of x on the segment's line beyond its ends a and b (negative
    within), r the ramp of width ``eps`` (m): zero where the foot lies on the segment."""
    a, b = seg[:, 0], seg[:, 1]
    u = b - a
    t = u / np.linalg.norm(u, axis=1)[:, None]
    beyond_a = np.einsum("mk,mk->m", a - x, t)
    beyond_b = np.einsum("mk,mk->m", x - b, t)
    return _ramp(beyond_a, eps)[0] + _ramp(beyond_b, eps)[0]


_PLANAR = np.array([0, 1, 3, 4, 6, 7])  # (x, a, b) in the plane among their 3D jets' columns


def end_excess_jet(x: np.ndarray, seg: np.ndarray, eps: float):
    """:func:`end_excess` with its gradient (m, 6) and Hessian (m, 6, 6) over (x, a, b)."""
    lift = [np.pad(p, ((0, 0), (0, 1))) for p in (x, seg[:, 0], seg[:, 1])]
    X, A, B = variables(lift, 9)  # (the plane z = 0 of 3-vector jets)
    u = B - A
    length = dot(u, u).sqrt()
    total = None
    for e in (dot(A - X, u) / length, dot(X - B, u) / length):
        r = e.apply(*_ramp(e.val, eps))
        total = r if total is None else total + r
    return total.val, total.grad[:, _PLANAR], total.hess[:, _PLANAR][:, :, _PLANAR]
