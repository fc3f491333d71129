"""The time loop: steps of the run's stepper, halved when they fail, as a generator of states."""

from __future__ import annotations

import math
from collections.abc import Iterator

from ..errors import check_positive
from ..linalg.legacy import record_run
from .adaptive import adaptive_steps, failure_error, ladder_depth
from .constraints import StepFailure
from .generalized_alpha import coefficients
from .impacts import impact_start
from .smooth_contact import resting_start
from .state import IntegratorOptions, PhaseTimer, State, initial_state, length_scale
from .stats import StepStats
from .stepper import STEPPERS, make_stepper

__all__ = ["STEPPERS", "simulate"]


def simulate(
    model,
    dt: float,
    t_end: float,
    options: IntegratorOptions | None = None,
    timer: PhaseTimer | None = None,
    q0=None,
    v0=None,
    start: State | None = None,
    stats: StepStats | None = None,
) -> Iterator[State]:
    """Yield the state at t = 0 and after every step of size ``dt`` (s) up to ``t_end`` (s).

    ``q0`` and ``v0`` are the initial dof vectors (default: rest in the reference state).
    ``start`` continues from a stored state (a checkpoint) instead: its step is not yielded.

    A step whose Newton iterations fail is retried as two half steps, recursively up to
    ``options.max_halvings`` times; then ``SolverError`` reports the time, step and residual.

    The run's counts (fallbacks, Newton globalization, solver work) go to ``stats`` (default:
    new :class:`StepStats`); the stepper is made once (:func:`make_stepper`), and with it a
    linear solver of the run's own for the model.
    """
    dt = check_positive("dt", dt)
    t_end = check_positive("t_end", t_end)
    timer = PhaseTimer() if timer is None else timer
    n_steps = max(1, math.ceil(t_end / dt - 1e-9))
    steps = n_steps - (0 if start is None else start.step)  # (for the cost of "auto")
    stepper = make_stepper(model, options or IntegratorOptions(), stats, steps)
    choice = model.solver.choice
    opts = stepper.settings
    model.contacts.detect_within(opts.detection_margin * model.length)
    try:
        if start is None:
            state = initial_state(model, q0, v0, opts.tol_gap)
            if opts.integrator == "nsga" and opts.smooth:
                tol = opts.tol_gap * length_scale(model, state.q)
                given = state.v  # (the damping of the restart is taken before an impact at 0)
                state = impact_start(model, state, opts, tol, dt)
                first = coefficients(opts.rho_inf, dt)
                state = resting_start(model, state, tol, tol / dt, opts.stats.contact, given, first)
            yield state
        else:
            state = start
        if opts.rtol is not None:
            yield from _controlled(stepper, state, n_steps, dt, t_end, timer)
            return
        for n in range(state.step + 1, n_steps + 1):
            t_next = min(n * dt, t_end)
            h = t_next - state.t
            # n·dt − (n − 1)·dt differs from dt in its last bits: take the nominal step, so that
            # what is cached per step size (factorizations of linear models) is built once
            if abs(h - dt) <= 1e-9 * dt:
                h = dt
            try:
                state = stepper.step(state, h, timer)
            except StepFailure as err:
                tried = f"{opts.max_halvings} step halvings"
                raise failure_error(err, state.t, n, tried, opts.stats) from None
            state.t = t_next
            state.step = n
            if choice is not None:  # the rates per step that "auto" weighs count this one
                choice.note_step()
            yield state
    finally:  # (the deprecated counter names read it: fecontact.linalg.legacy)
        record_run(stepper.stats)


def _controlled(stepper, state, n_steps, dt, t_end, timer) -> Iterator[State]:
    """The steps of a run with ``rtol`` (:func:`adaptive_steps`), a failure as the run's
    error."""
    choice = stepper.model.solver.choice
    steps = adaptive_steps(stepper, state, n_steps, dt, t_end, timer, stepper.stats.control)
    try:
        for state in steps:
            if choice is not None:
                choice.note_step()
            yield state
    except StepFailure as err:
        tried = f"rejections down to the step {dt / 2 ** ladder_depth(stepper.settings):.3g} s"
        raise failure_error(err, state.t, state.step + 1, tried, stepper.stats) from None
