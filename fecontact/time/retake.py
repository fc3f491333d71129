"""The smooth step taken again from a start without the forces that would push a contact
the step lets go: a released contact's (:func:`fecontact.time.smooth_contact.released`,
both its forces) and a contact's whose slip turned against its tangential force
(:mod:`.slip_reversal`, that force alone)."""

from __future__ import annotations

import numpy as np

from .alpha_step import alpha_smooth_step
from .correction import correction_metric
from .slip_reversal import without_tangential
from .smooth_contact import released, without_released

__all__ = ["retaken"]


def retaken(model, st, step, P, opts, at):
    """(start state, ``step``, energy put in (J)): taken again (:func:`_retake`, ``at`` = (t,
    c, timer)) without the contacts of ``P`` it releases (redundant ones closed are held)
    and without the tangential forces of those whose slip turned against them
    (:mod:`.slip_reversal`)."""
    closed = (step.q, opts.tol_gap * model.length) if opts.stats.contact.minimum_norm else None
    rows = released(model, st, P, step.force, opts.tol_residual, closed)
    turned = rows[:0] if step.reversing is None else np.setdiff1d(step.reversing, rows)
    if not (rows.size or turned.size):
        return st, step, 0.0
    t, c, timer = at
    return _retake(model, st, step, (rows, turned), opts, (t, c, P, timer))


def _retake(model, st, step, rows, opts, at):
    """The smooth step from ``st`` taken again without the forces of the contacts ``rows`` =
    (released, turned) it released (:func:`without_released`) or whose slip turned against
    their tangential force (:func:`without_tangential`; ``at`` = (t_{n+1}, coefficients, P,
    timer)): the state it starts from, the step, and the energy (J) it ends with over the
    first ``step``."""
    t, c, P, timer = at
    # S_t at the step's end, as its Newton's own factors are where they are a metric (on a
    # group, or with bordered rows, they are not): S_t at its start takes another share of
    # the released force out of a (the floor pendulum in space left its planar twin by
    # 3e-4 m at the first release, measured)
    solve_H = correction_metric(model, step.q, step.S, c, "stiffness")[1]
    (rows, turned), st_s = rows, st
    if rows.size:
        st_s = without_released(model, st, rows, solve_H)
        opts.stats.releases += 1
    if turned.size:
        st_s = without_tangential(model, st_s, turned, solve_H)
        opts.stats.slip_reversals += 1
    retake = alpha_smooth_step(model, st_s, t, c, opts, timer, P)
    retake = retake._replace(iterations=retake.iterations + step.iterations)
    return st_s, retake, _energy(model, retake.q, retake.v) - _energy(model, step.q, step.v)


def _energy(model, q, v) -> float:
    """T + V_strain + V_gravity (J) at (q, v)."""
    return model.kinetic_energy(v) + model.strain_energy(q) + model.potential_energy(q)
