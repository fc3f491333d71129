"""The touching point of a beam's section between two nodes: a contact at ξ on the segment
(a, b) of a ``Beam2D`` or ``Beam3D`` touches through the section, at the arm from the
centreline point x(ξ) = (1 − ξ) x_a + ξ x_b to the surface (−c n, c the half-thickness or
tube radius, n the partner's normal toward the beam). The section there turns with the
nodes' sections interpolated as the centreline is, ω(ξ) = (1 − ξ) ω_a + ξ ω_b, so the
touching point moves at ẋ(ξ) + ω(ξ) × arm: exact where the two sections turn alike (a rod
rolling), and the node's own rows at ξ = 0 or 1 (``NodeContact``). Where only the spin
about a unit axis t moves the point (a tube along a box's face, whose line contact cannot
carry the moment of the other turns), it moves at ẋ(ξ) + (t·ω(ξ)) t × arm
(:func:`segment_spins`, :func:`segment_spin_moves`)."""

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


def _side(axes: np.ndarray) -> np.ndarray:
    """A unit vector (m, 3) square to each unit axis (m, 3)."""
    helper = np.where(np.abs(axes[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    side = np.cross(axes, helper)
    return side / np.linalg.norm(side, axis=1)[:, None]


def segment_spins(body, q: np.ndarray, segments: np.ndarray, xi: np.ndarray, arms, axes):
    """As :func:`segment_turns` for the sections' spin about the segments' unit ``axes`` t
    (m, 3) alone: the touching point moves at (t·ω(ξ)) t × arm. The spin's row tᵀR of a
    section is read from its turn of a unit arm a square to t, (t × a)·(ω × a) = t·ω."""
    side = _side(axes)
    along = np.cross(axes, side)
    lever = np.cross(axes, arms)
    dofs, B = [], []
    for nodes, w in ((segments[:, 0], 1.0 - xi), (segments[:, 1], xi)):
        end, turn = body.section_turns(q, nodes, side)
        dofs.append(end)
        B.append(
            w[:, None, None] * lever[:, :, None] * np.einsum("mi,mik->mk", along, turn)[:, None]
        )
    return np.concatenate(dofs, axis=1), np.concatenate(B, axis=2)


def segment_spin_moves(body, q, q_n, segments: np.ndarray, xi: np.ndarray, arms, axes):
    """The motion (m, 3) over the step of the touching points now at x(ξ) + arm, their
    sections turned back by their spins about the segments' unit ``axes`` t since q_n (the
    angle φ by which a unit arm a square to t turned about t): for each end, Δx + arm − R_t(−φ)
    arm, interpolated in ξ (exact for sections spinning about a fixed t; its derivative at
    q_n = q is :func:`segment_spins`)."""
    side = _side(axes)
    x, x_n = body.positions(q), body.positions(q_n)
    moves = []
    for nodes in (segments[:, 0], segments[:, 1]):
        back = body.section_points_before(q, q_n, nodes, side) - x_n[nodes]
        # the angle −φ from a to where it was, about t
        back_angle = np.arctan2(
            np.einsum("mi,mi->m", axes, np.cross(side, back)), np.einsum("mi,mi->m", side, back)
        )
        moves.append(x[nodes] - x_n[nodes] + arms - _turned(arms, axes, back_angle))
    return (1.0 - xi)[:, None] * moves[0] + xi[:, None] * moves[1]


def _turned(a: np.ndarray, t: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """The vectors a (m, 3) turned by ``angle`` (m,) about the unit axes t (m, 3)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    along = np.einsum("mi,mi->m", t, a)[:, None] * t
    return c * a + s * np.cross(t, a) + (1.0 - c) * along
