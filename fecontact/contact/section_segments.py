"""The touching point of a beam's section between two nodes: a contact at ξ on the segment
(a, b) of a ``Beam2D`` or ``Beam3D`` touches through the section, at the arm from the
centreline point x(ξ) = (1 − ξ) x_a + ξ x_b to the surface (−c n, c the half-thickness or
tube radius, n the partner's normal toward the beam). The section there turns with the
nodes' sections interpolated as the centreline is, ω(ξ) = (1 − ξ) ω_a + ξ ω_b, so the
touching point moves at ẋ(ξ) + ω(ξ) × arm: exact where the two sections turn alike (a rod
rolling), and the node's own rows at ξ = 0 or 1 (``NodeContact``)."""

from __future__ import annotations

import numpy as np


def segment_turns(body, q: np.ndarray, segments: np.ndarray, xi: np.ndarray, arms):
    """Local dofs (m, 2k) of the rotations of both ends of each segment (``segments`` (m, 2))
    and ∂ẋ_p/∂(rotation rates) (m, d, 2k) of the touching points x(ξ) + arm (``arms`` (m, d)),
    k = 1 in the plane, 3 in space."""
    dofs_a, Ba = body.section_turns(q, segments[:, 0], arms)
    dofs_b, Bb = body.section_turns(q, segments[:, 1], arms)
    B = np.concatenate([(1.0 - xi)[:, None, None] * Ba, xi[:, None, None] * Bb], axis=2)
    return np.concatenate([dofs_a, dofs_b], axis=1), B


def segment_point_moves(body, q, q_n, segments: np.ndarray, xi: np.ndarray, arms) -> np.ndarray:
    """The motion (m, d) over the step of the touching points now at x(ξ) + arm: each end's
    section point against where it was at q_n turned back with its section, interpolated in
    ξ (exact for sections turning alike)."""
    x = body.positions(q)
    moves = [
        x[nodes] + arms - body.section_points_before(q, q_n, nodes, arms)
        for nodes in (segments[:, 0], segments[:, 1])
    ]
    return (1.0 - xi)[:, None] * moves[0] + xi[:, None] * moves[1]
