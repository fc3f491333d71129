r"""The turn of a beam's nodes over one step, bounded.

A node's rotation over a step, θ_{n+1} − θ_n in the plane and the increment D = ψ_{n+1} ⊖
ψ_n in space, is one of the smooth step's unknowns. In space a rotation vector represents a
turn up to π: a predictor that turns a node by 5.8 rad (a strip struck at 300 m/s, its nodes
spinning at 1.55e4 rad/s, h = 0.1 ms) is read as the same turn less 2π (−0.45 rad), and the
smooth Newton starts from 2.6e7 J of strain and ends on another root. In the plane every
angle is representable, but a turn of that size is far beyond what one step of the
generalized-α method resolves, and the smooth step whose Newton wandered to a root that turns
the struck nodes by 80 rad (a disk leaving a strip's node at 100 m/s: 1.8e7 J of strain from
49 J) is no state of the strip. So a step whose predictor or whose converged smooth step
turns a beam node by more than π/2 fails before its correction, and the stepper halves it
(:class:`~fecontact.time.stepper.Stepper`): π/2 is a quarter turn, half the turn a rotation
vector can represent, a geometric bound and the same rule in the plane and in space. Each
such failure is counted in ``summary.json`` (``turned_steps``).
"""

from __future__ import annotations

import math

import numpy as np

from .constraints import StepFailure

__all__ = ["TURN_BOUND", "beam_turns", "check_turn"]

TURN_BOUND = 0.5 * math.pi
"""The largest turn (rad) of a beam node over one step: a quarter turn (module docstring)."""


def beam_turns(model) -> np.ndarray | None:
    """The dofs of the beams' nodal rotations (all dofs' numbering), (k, 1) in the plane and
    (k, 3) in space, decided once per run; None on a model without beams."""
    ones = np.ones(model.dim)
    width = 1 if model.dim == 2 else 3
    rows = []
    for i, body in enumerate(model.bodies):
        if body.slender:  # (a beam: every dof that no translation moves is a rotation)
            dofs = np.flatnonzero(body.translation_field(ones) == 0)
            rows.append(model.body_slice(i).start + dofs.reshape(-1, width))
    return np.vstack(rows) if rows else None


def check_turn(turns: np.ndarray, x: np.ndarray, q: np.ndarray, group: bool, what: str, stats):
    """Fail the step where ``x`` turns a beam node (``turns``: :func:`beam_turns`) by more
    than :data:`TURN_BOUND` from the positions ``q`` at the step's start: ``x`` is the
    positions, or on a Lie group (``group``) the increment D, whose rotation triples are the
    turns. ``what`` names the iterate (the predictor, the smooth step) in the failure, which
    ``stats`` (:class:`~fecontact.time.stats.StepStats`) counts in ``turned``."""
    d = x[turns] if group else x[turns] - q[turns]
    turn = float(np.sqrt(np.einsum("ij,ij->i", d, d)).max(initial=0.0))
    if turn > TURN_BOUND:
        stats.turned += 1
        raise StepFailure(
            f"{what} turns a beam node by {turn:.3g} rad (more than a quarter turn)", math.nan
        )
