r"""The turn of a beam's nodes, bounded over one step and over one Newton update.

A node's rotation over a step, θ_{n+1} − θ_n in the plane and the increment D = ψ_{n+1} ⊖
ψ_n in space, is one of the smooth step's unknowns. In space a rotation vector represents a
turn up to π: a predictor that turns a node by 5.8 rad (a strip struck at 300 m/s, its nodes
spinning at 1.55e4 rad/s, h = 0.1 ms) is read as the same turn less 2π (−0.45 rad), and the
smooth Newton starts from 2.6e7 J of strain and ends on another root. In the plane every
angle is representable, but a turn of that size is far beyond what one step of the
generalized-α method resolves. So a step whose predictor or whose converged smooth step
turns a beam node by more than π/2 fails before its correction, and the stepper halves it
(:class:`~fecontact.time.stepper.Stepper`): π/2 is a quarter turn, half the turn a rotation
vector can represent, a geometric bound and the same rule in the plane and in space.

The same bound holds each Newton update that rows border (persistent contacts, joints). The
energy descent of :mod:`.descent` tests the updates with S_t alone; those with rows are taken
whole, and where S_t is indefinite (a struck strip's geometric stiffness) one of them can turn
a node by radians: a disk leaving a strip's node at 100 m/s, the kink's two rows bordering
S_t, took updates of 4, 18 and 107 rad, its active set cycling, and ended on a root that
turns the struck nodes by 80 rad (1.8e7 J of strain from 49 J). The kinematics linearized at
the iterate say nothing a quarter turn away, so such an update, with its multipliers, is cut
to turn no node by more than π/2: a damped Newton update, whose direction is kept.

Both are counted in ``summary.json`` (``beam_turns``: the predictors and smooth steps
refused, the halvings this caused and the steps that had any, the updates cut).
"""

from __future__ import annotations

import math

import numpy as np

from .constraints import StepFailure

__all__ = ["TURN_BOUND", "TurnBound", "TurnFailure", "beam_turns"]

TURN_BOUND = 0.5 * math.pi
"""The largest turn (rad) of a beam node over one step or one update: a quarter turn."""


class TurnFailure(StepFailure):
    """A predictor or smooth step refused before its correction for turning a beam node by
    more than :data:`TURN_BOUND`: no Newton iteration ran, so it has no residual (nan)."""

    def __init__(self, message: str):
        super().__init__(message, math.nan)


class TurnBound:
    """The beams' nodal rotations of a model, decided once per run: ``dofs`` in all dofs'
    numbering, (k, 1) in the plane and (k, 3) in space, and ``free`` those no support holds
    in the free dofs' numbering (a rotation vector is held whole or not at all)."""

    def __init__(self, dofs: np.ndarray, free_index: np.ndarray):
        self.dofs = dofs
        free = free_index[dofs]
        self.free = free[(free >= 0).all(axis=1)]
        # (flat, with the largest turn of a flat array: |Δθ| in the plane, the rotation
        # triples' norms in space; a few µs a step)
        self._dofs, self._free = dofs.ravel(), self.free.ravel()
        self._largest = _largest_angle if dofs.shape[1] == 1 else _largest_rotation

    def check(self, x: np.ndarray, q: np.ndarray, group: bool, what: str, stats) -> None:
        """Fail the step where ``x`` turns a beam node by more than :data:`TURN_BOUND` from
        the positions ``q`` at the step's start: ``x`` is the positions, or on a Lie group
        (``group``) the increment D, whose rotation triples are the turns. ``what`` names
        the iterate (the predictor, the smooth step) in the failure, which ``stats``
        (:class:`~fecontact.time.stats.StepStats`) counts."""
        dofs = self._dofs
        turn = self._largest(x[dofs] if group else x[dofs] - q[dofs])
        if turn > TURN_BOUND:
            stats.turns.refused += 1
            raise TurnFailure(
                f"{what} turns a beam node by {turn:.3g} rad (more than a quarter turn)"
            )

    def cut(self, dq: np.ndarray, stats) -> float:
        """The fraction (≤ 1) of the update ``dq`` (free dofs) that turns no beam node by
        more than :data:`TURN_BOUND`; a cut counted in ``stats``."""
        turn = self._largest(dq[self._free])
        if turn <= TURN_BOUND:
            return 1.0
        stats.turns.cut_updates += 1
        return TURN_BOUND / turn


def _largest_angle(d: np.ndarray) -> float:
    """The largest |d_i| of planar angles ``d`` (rad)."""
    return float(np.abs(d).max(initial=0.0))


def _largest_rotation(d: np.ndarray) -> float:
    """The largest norm of the rotation vectors of ``d`` (rad; three components each)."""
    d = d.reshape(-1, 3)
    return math.sqrt(float(np.einsum("ij,ij->i", d, d).max(initial=0.0)))


def beam_turns(model) -> TurnBound | None:
    """The :class:`TurnBound` of ``model``'s beams; None on a model without beams."""
    ones = np.ones(model.dim)
    width = 1 if model.dim == 2 else 3
    rows = []
    for i, body in enumerate(model.bodies):
        if body.slender:  # (a beam: every dof that no translation moves is a rotation)
            dofs = np.flatnonzero(body.translation_field(ones) == 0)
            rows.append(model.body_slice(i).start + dofs.reshape(-1, width))
    return TurnBound(np.vstack(rows), model.free_index) if rows else None
