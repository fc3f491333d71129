r"""The pointwise safeguard rows of 2D solids: a smooth maximum of the segments around a vertex.

A 2D node held by its safeguard row (:mod:`fecontact.contact.mortar_safeguard`) read the
plane gap of its closest master segment alone. Where a corner of one solid is pressed onto a
vertex of the other's face, it dents that face into a V whose two segments tie for the
closest; one was taken, and its tilted normal pushed the corner sideways for as long as the
row held it: a square turned 45° landing corner first at 2 m/s on a finer block (10 × 10
cells of 8 mm, the corner a master node over a block vertex) left at 0.109 m/s sideways,
5.4 % of the impact speed, over 26 held steps; ±2 % with the corner 0.1 mm to either side.

:class:`DeepNodeRows2D` is the 2D form of
:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows3D`: the row of a deep node is the
smooth maximum of the line gaps of the (two) segments around the master vertex nearest to
it, each less the excess of the node's foot beyond its segment's ends,

    g_s = ε ln Σ_k exp((g_k − P_k) / ε) + δ,   P_k = r(e_a) + r(e_b),

e_a, e_b the distances of the foot beyond the ends a, b of segment k along its line
(negative within), r the continuous-slope ramp of width δ. Where the V's two segments tie
the row's gradient is their weighted mean normal, along the V's axis; 0.1 mm off the
vertex (12 ε) the nearer segment's weight is e⁻¹² of the other's at the same depth.
"""

from __future__ import annotations

import numpy as np

from .geometry import facet_plane_gap
from .jets import dot, variables
from .mortar_safeguard import DeepNodeRows3D, ramp

__all__ = ["DeepNodeRows2D", "end_excess", "end_excess_jet"]


def end_excess(x: np.ndarray, seg: np.ndarray, eps: float) -> np.ndarray:
    """r(e_a) + r(e_b) (m) of points x (m, 2) and segments ``seg`` (m, 2, 2): e_a, e_b the
    distances of the foot of x on the segment's line beyond its ends a and b (negative
    within), r the ramp of width ``eps`` (m): zero where the foot lies on the segment."""
    a, b = seg[:, 0], seg[:, 1]
    u = b - a
    t = u / np.linalg.norm(u, axis=1)[:, None]
    beyond_a = np.einsum("mk,mk->m", a - x, t)
    beyond_b = np.einsum("mk,mk->m", x - b, t)
    return ramp(beyond_a, eps)[0] + ramp(beyond_b, eps)[0]


_PLANAR = np.array([0, 1, 3, 4, 6, 7])  # (x, a, b) in the plane among their 3D jets' columns


def end_excess_jet(x: np.ndarray, seg: np.ndarray, eps: float):
    """:func:`end_excess` with its gradient (m, 6) and Hessian (m, 6, 6) over (x, a, b)."""
    lift = [np.pad(p, ((0, 0), (0, 1))) for p in (x, seg[:, 0], seg[:, 1])]
    X, A, B = variables(lift, 9)  # (the plane z = 0 of 3-vector jets)
    u = B - A
    length = dot(u, u).sqrt()
    total = None
    for e in (dot(A - X, u) / length, dot(X - B, u) / length):
        r = e.apply(*ramp(e.val, eps))
        total = r if total is None else total + r
    return total.val, total.grad[:, _PLANAR], total.hess[:, _PLANAR][:, :, _PLANAR]


class DeepNodeRows2D(DeepNodeRows3D):
    """:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows` of 2D P1 solids: a deep
    node's row is the smooth maximum of the line gaps of the master segments around the
    vertex nearest to it, each less its foot's excess beyond the segment's ends
    (:func:`end_excess`; module docstring). Its gradient on the node, Σ_k w_k n_k, is the
    row's normal (the direction a slip row is orthogonal to)."""

    plane_gaps = staticmethod(facet_plane_gap)
    excess = staticmethod(end_excess)
    excess_jet = staticmethod(end_excess_jet)
