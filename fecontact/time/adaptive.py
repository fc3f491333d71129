"""Steps chosen by a tolerance: the time loop with ``IntegratorOptions.rtol`` set.

Every interval [t_n, t_n + dt] between two history rows is crossed by steps drawn from the
binary ladder h_k = dt · 2^(-k), k = 0 … ``depth``, each starting on a multiple of its own
size, so that the steps land exactly on the row times n·dt (no interpolated rows: the energy
balance, the ledger and the impacts see only states the integrator computed) and a linear
model factorizes its iteration matrix once per rung of the ladder.

The local error of the smooth generalized-α step is estimated as in Zienkiewicz & Xie (1991,
Earthquake Eng. Struct. Dyn. 20): the step's q_{n+1} against the third-order prediction of
a linear acceleration between v̇_n and v̇_{n+1},

    q* = q_n + h v_n + h² (v̇_n / 3 + v̇_{n+1} / 6),   e = q_{n+1} − q*  (O(h³)),

on a rotation vector ψ the body-frame increment log(exp(−ψ̃_n) exp(ψ̃_{n+1})) in place of
q_{n+1} − q_n (v is the body-frame Ω: the vectors' difference departs from h Ω at O(h) as
soon as the axis turns; docs/explanation/adaptive_steps.md), measured on the free dofs in the mixed
norm of ODE solvers, ‖e‖ = rms_i e_i / (rtol (L + max(|q_n,i|, |q_{n+1},i|))), with L the
model size (m). A step whose norm exceeds 1 is rejected and taken again smaller; the next
step is scaled by 0.9 ‖e‖^(-1/3), within one rung up and two rungs down (× 2 … × 1/4).
Steps that close a contact (an impact, a position correction) are accepted unmeasured:
their error is the impact's, not the smooth step's; the control starts again from the next
smooth step. A step that fails (Newton, penetration) is a rejection too, retaken a rung lower.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ..errors import SolverError
from .configuration import minus
from .constraints import StepFailure
from .penetration import PenetrationFailure
from .state import PhaseTimer, State
from .stats import FailedStep
from .turns import TurnFailure

__all__ = [
    "LADDER_DEPTH",
    "ladder_depth",
    "adaptive_steps",
    "failure_error",
    "local_error",
]

LADDER_DEPTH = 10  # rungs below dt at least: the smallest step is dt/1024 (or max_halvings)
SAFETY = 0.9  # the next step aims at 0.9 of the step the estimate allows
GROW, SHRINK = 1, 2  # rungs a step may climb, or fall, after the last one (× 2 … × 1/4)


def ladder_depth(opts) -> int:
    """The rungs of the ladder below dt: ``LADDER_DEPTH``, or ``max_halvings`` if more."""
    return max(LADDER_DEPTH, opts.max_halvings)


def local_error(model, before: State, after: State, h: float, rtol: float) -> float:
    """The estimate ‖e‖ of the local error of the step of ``h`` (s) from ``before`` to
    ``after`` over the tolerance (dimensionless; ≤ 1 accepts), see the module's doc. The
    supported dofs stay zero in q, v and v̇: summed over all dofs, averaged over the free."""
    q0, q1 = before.q, after.q
    e = minus(model, q1, q0) - h * before.v - (h * h) * (before.vd / 3.0 + after.vd / 6.0)
    e /= model.length + np.maximum(np.abs(q0), np.abs(q1))
    return math.sqrt(float(e @ e) / max(model.n_free, 1)) / rtol


def _impact(before: State, after: State) -> bool:
    """Whether the step closed a contact: a position correction or an impulse on a contact
    no smooth force held at its start."""
    if after.nu.size and np.any(after.nu > 0.0):
        return True
    new = after.impulse > 0.0
    if before.smooth is not None:
        new &= ~(before.smooth.normal > 0.0)
    return bool(np.any(new))


def failure_error(err: StepFailure, t: float, step: int, tried: str, stats) -> SolverError:
    """The run's error for a step that failed at ``t`` (s), row ``step``, after ``tried``:
    what failed, with the residual where a solve left one (a step refused for the turn of
    a beam node has none); the step and its halvings go to the run's ``stats``
    (:class:`~.stats.StepStats`)."""
    stats.failed = FailedStep(step, err.halvings, err.retakes, err.turn_halvings, err.shortest)
    if isinstance(err, TurnFailure):
        text = (
            f"beam turn bound at t = {t:.6g} s (step {step}): after {tried}, the last step "
            f"tried was refused before its correction: {err}"
        )
    else:
        what = (
            "penetration not held"
            if isinstance(err, PenetrationFailure)
            else "Newton did not converge"
        )
        text = f"{what} at t = {t:.6g} s (step {step}): {err}"
        if math.isfinite(err.residual):  # (nan: the solve recorded none, its message says why)
            text += f" (residual {err.residual:.3e})"
        text += f" after {tried}"
    return SolverError(text, time=t, step=step, residual=err.residual)


class _Ladder:
    """The control between two rows: the rung ``level`` of the next step and, in units of
    the lowest rung, where the steps stand in the interval."""

    def __init__(self, depth: int, level: int):
        self.depth, self.level = depth, level

    def aligned(self, pos: int, level: int) -> bool:
        """Whether a step of rung ``level`` may start at ``pos``."""
        return pos % (1 << (self.depth - level)) == 0

    def climb(self, pos: int, wanted: int) -> int:
        """The rung for a step at ``pos``: ``wanted``, or the nearest lower one aligned there."""
        level = min(max(wanted, 0), self.depth)
        while not self.aligned(pos, level):
            level += 1
        return level


def _next_level(level: int, err: float, accepted: bool) -> int:
    """The rung after a step of rung ``level`` with error estimate ``err``."""
    if not math.isfinite(err):  # (a step that produced no number: as far down as allowed)
        return level + SHRINK
    factor = SAFETY * err ** (-1.0 / 3.0) if err > 0.0 else 2.0
    change = math.floor(math.log2(factor))  # rungs up (negative: down)
    if not accepted:
        change = min(change, -1)
    return level - max(-SHRINK, min(GROW, change))


def adaptive_steps(
    stepper, state: State, n_rows: int, dt: float, t_end: float, timer: PhaseTimer, control
) -> Iterator[State]:
    """Yield every step from ``state`` to ``t_end`` (s): the rows at n·dt, n ≤ ``n_rows``, and
    the steps between them (``State.substep``), counting into ``control``
    (:class:`fecontact.time.stats.StepControl`). ``State.h_next`` carries the next rung."""
    depth = ladder_depth(stepper.settings)
    level = 0
    if state.h_next > 0.0:
        level = min(depth, max(0, round(math.log2(dt / state.h_next))))
    ladder = _Ladder(depth, level)
    for n in range(state.step + 1, n_rows + 1):
        t_next = min(n * dt, t_end)
        H = dt if abs(t_next - state.t - dt) <= 1e-9 * dt else t_next - state.t
        for st in _interval(stepper, state, H, ladder, timer, control):
            if not st.substep:
                st.t, st.step = t_next, n
                st.h_next = dt * 2.0**-ladder.level
                state = st
            yield st


def _interval(stepper, state: State, H: float, ladder: _Ladder, timer, control):
    """The steps across one interval of ``H`` (s) from ``state``, the last one the row."""
    total, pos, t0, step = 1 << ladder.depth, 0, state.t, state.step
    while pos < total:
        level = ladder.climb(pos, ladder.level)
        h = H * 2.0**-level
        after, err = _attempt(stepper, state, h, timer)
        if after is None:  # failed: a rung lower
            control.rejected_failure += 1
            if level >= ladder.depth:
                raise err
            ladder.level = level + 1
            continue
        over = err is not None and not err <= 1.0  # (NaN included)
        if over and level < ladder.depth:
            control.rejected_error += 1
            ladder.level = min(ladder.depth, _next_level(level, err, False))
            continue
        control.over_tolerance += over
        # after an impact the rung stays: the control starts again from the next smooth step
        ladder.level = level if err is None else min(ladder.depth, _next_level(level, err, True))
        pos += 1 << (ladder.depth - level)
        after.h, after.step = h, step
        after.t = t0 + H * pos / total
        after.substep = pos < total
        state = after
        yield after


def _attempt(stepper, state: State, h: float, timer):
    """One step of ``h`` (s) without halvings: (the state after it, its error estimate, None
    after an impact), or (None, the failure)."""
    try:
        after = stepper.step(state, h, timer, depth=stepper.settings.max_halvings)
    except StepFailure as err:
        return None, err
    if _impact(state, after):
        return after, None
    opts = stepper.settings
    return after, local_error(stepper.model, state, after, h, opts.rtol)
