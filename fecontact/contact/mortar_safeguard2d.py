r"""The pointwise safeguard rows of 2D solids: a smooth maximum of the segments around a vertex.

A 2D node held by its safeguard row (:mod:`fecontact.contact.mortar_safeguard`) read the
line gap of its closest master segment alone. Under a vertex where the two segments tie (a
corner of one solid pressed onto a vertex of the other's face, which it dents into a V) one
of them was taken, by the search's order, and its tilted normal pushed the node sideways:
the corner of a square 0.1 mm under the vertex of a 0.3 mm dent of 8 mm segments was pushed
by 0.0375 of its force, the sign flipping across the vertex
(``tests/test_mortar_safeguard2d.py``).

:class:`DeepNodeRows2D` is the 2D form of
:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows3D`: the row of a deep node is the
smooth maximum of the line gaps of the (two) segments around the master vertex nearest to
it, each less the excess of the node's foot beyond its segment's ends,

    g_s = ε ln Σ_k exp((g_k − P_k) / ε) + δ,   P_k = r(e_a) + r(e_b),

e_a, e_b the distances of the foot beyond the ends a, b of segment k along its line
(negative within), r the continuous-slope ramp of width δ. Under the tie the row's gradient
is the segments' mean normal, along the V's axis; off it the push turns continuously toward
the vertex (at most 0.15 of the force, 10 µm off in the case above, where the excess's
ramp weighs the segment the node has passed the end of), and a node under one segment reads
that segment's line gap, as before. Measured runs: docs/validation/stress_2d.md ("Corners,
rings, rotated scenes and rolling").
"""

from __future__ import annotations

import numpy as np

from .facet_excess import end_excess, end_excess_jet
from .geometry import facet_plane_gap
from .mortar_safeguard import DeepNodeRows3D

__all__ = ["DeepNodeRows2D"]


class DeepNodeRows2D(DeepNodeRows3D):
    """:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows` of 2D P1 solids: a deep
    node's row is the smooth maximum of the line gaps of the master segments around the
    vertex nearest to it, each less its foot's excess beyond the segment's ends
    (:func:`~fecontact.contact.facet_excess.end_excess`; module docstring). Its gradient on
    the node, Σ_k w_k n_k, is the row's normal (the direction a slip row is orthogonal to)."""

    plane_gaps = staticmethod(facet_plane_gap)
    excess = staticmethod(end_excess)
    excess_jet = staticmethod(end_excess_jet)

    def _may_be_deep(self, x: np.ndarray, tri: np.ndarray) -> np.ndarray:
        # every node with a facet in reach reads its real row, not only those the 3D bound
        # lets through: a located closing brackets the row's gap from the step's start, where
        # the node was still shallow (in 2D the two segments around a vertex cost little)
        return np.ones(len(x), dtype=bool)
