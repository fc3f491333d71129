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

The predictor extrapolates the acceleration at constant v̇_n, h²/2 · v̇_n at ρ∞ = 1, and a
strip's v̇_n holds its rotation modes (0.46-0.79 MHz on the founding strip of four elements,
hω up to 5e4 at h = 1e-2) wherever generalized-α leaves them undamped: consistent with
M v̇ = f_ext − f_int(q) to 1e-7 N, micro-radians of turn, but up to 1.2e8 rad/s², which the
predictor at h = 1e-2 extrapolates to 1.05e3 rad. Halving divides that by four a level, and
the halves at ρ∞ = 1 keep the modes: six halvings do not reach the bound. So in a run whose
steps the energy guard checks (:mod:`.energy_guard`), a step refused for a turn is first
taken as the guard's retakes are, at ρ∞ = 0, which annihilates those modes within the step,
and its predictor, only Newton's first iterate, where it still turns a node too far, is
started again at constant velocity, q_n + h v_n (D = h v_n in space), with (v, v̇, a)
moved as by a Newton update, the step's equations kept. That step is halved where it fails
(a node spinning at 1.55e4 rad/s at h = 0.1 ms turns by 1.55 rad at constant velocity).
Started at constant velocity but left at ρ∞ = 1, the modes grow: the pendulum at e_N = 1,
h = 1e-3 reached 2.2e10 rad/s² and 1.5e3 rad/s at 13.7 s and failed. Without the guard the
step is halved as before: there the halvings are what bounds the ringing strip at ρ∞ ≥ 0.9.

The same bound holds each Newton update that rows border (persistent contacts, joints). The
energy descent of :mod:`.descent` tests the updates with S_t alone; those with rows are taken
whole, and where S_t is indefinite (a struck strip's geometric stiffness) one of them can turn
a node by radians: a disk leaving a strip's node at 100 m/s, the kink's two rows bordering
S_t, took updates of 4, 18 and 107 rad, its active set cycling, and ended on a root that
turns the struck nodes by 80 rad (1.8e7 J of strain from 49 J). The kinematics linearized at
the iterate say nothing a quarter turn away, so such an update, with its multipliers, is cut
to turn no node by more than π/2: a damped Newton update, whose direction is kept.

All are counted in ``summary.json`` (``beam_turns``: the predictors and smooth steps
refused, the halvings this caused and the steps that had any, the updates cut, the refused
steps taken at ρ∞ = 0, ``damped_steps``, and the predictors started again at constant
velocity, ``velocity_predictors``).
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

    def start(self, form, q: np.ndarray, group: bool, opts) -> None:
        """Newton's first iterate of the smooth step ``form`` (the acceleration form of
        :mod:`~fecontact.time.acceleration_form` from the positions ``q``): its predictor, or,
        where that turns a beam node by more than :data:`TURN_BOUND` and the run's settings
        ``opts`` coast (the energy guard's), the predictor at constant velocity
        (``form.coast()``, counted in ``opts.stats``); the step fails where the one kept
        turns a node too far (module docstring)."""
        dofs = self._dofs
        x = form.step.X[0]
        if opts.coasts and self._largest(x[dofs] if group else x[dofs] - q[dofs]) > TURN_BOUND:
            opts.stats.turns.velocity_predictors += 1
            form.coast()
        self.check(form.step.X[0], q, group, "the predictor", opts.stats)

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
