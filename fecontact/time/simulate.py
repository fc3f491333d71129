"""The time loop: steps of the chosen stepper, halved when they fail, as a generator of states."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator

from ..errors import SolverError, check_positive
from .constraints import StepFailure
from .energy_step import check_energy_scheme, energy_nsga_step
from .moreau import moreau_step
from .nsga import nsga_step
from .penalty import penalty_step
from .settings import run_settings
from .smooth_contact import resting_start, uses_smooth_contact
from .state import IntegratorOptions, PhaseTimer, State, initial_state, length_scale
from .stats import StepStats

__all__ = ["STEPPERS", "simulate"]

STEPPERS = {"nsga": nsga_step, "moreau": moreau_step, "penalty": penalty_step}
"""Every stepper, ``step(model, state, h, options, timer) -> State``, by the name of the
``integrator`` option."""


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
    new :class:`StepStats`); the model factorizes with a solver of the run's own from the
    first step on.
    """
    opts = run_settings(options or IntegratorOptions(), stats)
    dt = check_positive("dt", dt)
    t_end = check_positive("t_end", t_end)
    timer = PhaseTimer() if timer is None else timer
    if opts.scheme == "energy-decaying":
        check_energy_scheme(model, opts)
    model.contacts.detect_within(opts.detection_margin * model.length)
    model.use_solver(opts.stats.solver(model))
    if start is None:
        state = initial_state(model, q0, v0, opts.tol_gap)
        if opts.integrator == "nsga" and uses_smooth_contact(model, opts):
            tol = opts.tol_gap * length_scale(model, state.q)
            state = resting_start(model, state, tol, tol / dt, opts.stats.contact)
        yield state
    else:
        state = start
    n_steps = max(1, math.ceil(t_end / dt - 1e-9))
    for n in range(state.step + 1, n_steps + 1):
        t_next = min(n * dt, t_end)
        h = t_next - state.t
        # n·dt − (n − 1)·dt differs from dt in its last bits: take the nominal step, so that
        # what is cached per step size (factorizations of linear models) is built once
        if abs(h - dt) <= 1e-9 * dt:
            h = dt
        try:
            state = _advance(model, state, h, opts, timer, 0)
        except StepFailure as err:
            raise SolverError(
                f"Newton did not converge at t = {state.t:.6g} s (step {n}): {err} "
                f"(residual {err.residual:.3e}) after {opts.max_halvings} step halvings",
                time=state.t,
                step=n,
                residual=err.residual,
            ) from None
        state.t = t_next
        state.step = n
        yield state


def _advance(model, st, h, opts, timer, depth):
    try:
        if opts.scheme == "energy-decaying":
            return energy_nsga_step(model, st, h, opts, timer)
        return STEPPERS[opts.integrator](model, st, h, opts, timer)
    except StepFailure:
        if depth >= opts.max_halvings:
            raise
    first = _advance(model, st, 0.5 * h, opts, timer, depth + 1)
    second = _advance(model, first, 0.5 * h, opts, timer, depth + 1)
    second.impulse = second.impulse + first.impulse
    if second.friction is not None:  # the step's tangential impulse, as the normal
        impulse = first.friction.impulse + second.friction.impulse
        second.friction = dataclasses.replace(second.friction, impulse=impulse)
    second.iterations = {k: first.iterations[k] + second.iterations[k] for k in first.iterations}
    second.halvings = first.halvings + second.halvings + 1
    second.h = h
    return second
