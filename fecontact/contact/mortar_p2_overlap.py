r"""The overlap of a master face's image with a slave face, in the slave's parameter plane.

The master's corners projected onto the slave surface (their feet, (s, t)) span a triangle; its
intersection with the reference triangle s, t ≥ 0, s + t ≤ 1 is a convex polygon whose vertices
are feet inside the reference triangle, reference corners inside the feet's triangle, or
crossings of the two triangles' edges. :func:`polygon` finds them and their order from the
values; :func:`vertex_jets` rebuilds each from what it is in
:class:`~fecontact.contact.dual_numbers.Jet` arithmetic, so that the overlap's motion enters
the derivatives of the integrals over it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["polygon", "vertex_jets"]

_TOL = 1e-12  # points this close to an edge (in the parameter plane) count as on it


# -- the overlap polygon in the slave's parameter plane --------------------------------------
def _lines(p):
    """The reference triangle's edge functions (t, 1 − s − t, s) at points p (..., 2)."""
    return np.stack([p[..., 1], 1.0 - p[..., 0] - p[..., 1], p[..., 0]], axis=-1)


_CORNERS = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])


def _candidates(F):
    """The 15 candidate vertices (B, 15, 2) of the feet triangles F (B, 3, 2) clipped to the
    reference triangle and whether each is one: the feet 0-2, the reference corners 3-5 and
    the crossings 6 + 3 i + r of the feet's edge (i, i + 1) with reference edge r."""
    B = len(F)
    inside_f = np.all(_lines(F) >= -_TOL, axis=2)
    e1, e2 = F[:, 1] - F[:, 0], F[:, 2] - F[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = _CORNERS[None] - F[:, :1]  # (B, 3, 2)
        b1 = (r[..., 0] * e2[:, None, 1] - r[..., 1] * e2[:, None, 0]) / det[:, None]
        b2 = (e1[:, None, 0] * r[..., 1] - e1[:, None, 1] * r[..., 0]) / det[:, None]
    tol = _TOL
    inside_c = (b1 >= -tol) & (b2 >= -tol) & (1.0 - b1 - b2 >= -tol) & (np.abs(det) > 0)[:, None]
    hF = _lines(F)  # (B, 3 feet, 3 lines)
    cross_p, cross_ok = [], []
    for i in range(3):
        j = (i + 1) % 3
        hi, hj = hF[:, i], hF[:, j]
        with np.errstate(divide="ignore", invalid="ignore"):
            sigma = hi / (hi - hj)  # (B, 3 lines)
        p = F[:, i, None] + sigma[..., None] * (F[:, j] - F[:, i])[:, None]
        ok = (hi * hj < 0.0) & np.all(_lines(p) >= -tol, axis=2)
        cross_p.append(np.where(ok[..., None], p, 0.0))
        cross_ok.append(ok)
    points = np.concatenate([F, np.broadcast_to(_CORNERS, (B, 3, 2)), *cross_p], axis=1)
    valid = np.concatenate([inside_f, inside_c, *cross_ok], axis=1)
    return points, valid


def polygon(F):
    """The overlap polygons of the feet triangles F (B, 3, 2) with the reference triangle:
    the candidate index (B, K) of each vertex in counter-clockwise order and their count (B,)
    (near duplicates dropped, the feet before the corners before the crossings)."""
    with np.errstate(all="ignore"):  # degenerate feet triangles: their candidates fail
        points, valid = _candidates(F)
    for c in range(1, 15):  # a point within round-off of an earlier one is that one
        near = np.linalg.norm(points[:, :c] - points[:, c, None], axis=2) < 1e-12
        valid[:, c] &= ~np.any(near & valid[:, :c], axis=1)
    count = valid.sum(axis=1)
    centre = (points * valid[..., None]).sum(1) / np.maximum(count, 1)[:, None]
    d = points - centre[:, None]
    angle = np.where(valid, np.arctan2(d[..., 1], d[..., 0]), np.inf)
    order = np.argsort(angle, axis=1, kind="stable")[:, : max(int(count.max(initial=0)), 3)]
    return order, count, points


def vertex_jets(feet, order, points):
    """The polygon's vertices as Jets ((s, t) per slot) from their candidates: feet, constant
    corners, or crossings Fi + σ (Fj − Fi), σ = h_r(Fi) / (h_r(Fi) − h_r(Fj))."""
    s0 = feet[0][0]
    cand = list(feet) + [(s0.constant_like(c[0]), s0.constant_like(c[1])) for c in _CORNERS]
    for i in range(3):
        (si, ti), (sj, tj) = feet[i], feet[(i + 1) % 3]
        for r in range(3):
            hi, hj = [(t_, 1.0 - s_ - t_, s_)[r] for s_, t_ in ((si, ti), (sj, tj))]
            ok = np.abs(hi.v - hj.v) > 0.0
            sigma = hi / (hi - hj).where(ok, 1.0)
            cand.append((si + sigma * (sj - si), ti + sigma * (tj - ti)))
    slots = []
    for k in range(order.shape[1]):
        s, t = cand[0]
        for c in range(1, 15):
            at = order[:, k] == c
            if at.any():
                s, t = s.where(~at, cand[c][0]), t.where(~at, cand[c][1])
        slots.append((s, t))
    return slots
