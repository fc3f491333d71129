r"""Releases at their own instant: the step of solids in which the sub-steps taken aside
(:class:`fecontact.time.substeps.Releases`) read the contact's release is split there.

In whole steps the smooth step holds a pressed contact to the step's end, or lets it go from
the step's start (taken again without its force, :func:`~.smooth_contact.without_released`):
the release falls at a step's end. Where the sub-steps read it at t_r inside the step from
t_n, the step is taken as a localized step of δ = t_r − t_n, the contact held to its release
(its force at the end a few % of the force at t_n: 0.2–7 N from 5–270 N on Hertz's balls,
``ball_drop`` and ``disk_drop``), and the rest of the step from there, where the smooth step
lets it go.

Both parts start with the acceleration variable restarted, a = v̇, with the smooth forces a
carries taken as v̇'s (as after an impact, :func:`~.smooth_contact.force_shares`): a is
v̇'s generalized-α lag built with the steps of h, and a step of δ that started from it made
energy (the 3,993-dof ball of ``tests/test_ball_impact_energy.py`` at t_c/10: 5.6e-6 J in
the part of h/8, 0.134 % of the run's scale; restarted both parts lose energy and the run
creates what whole steps do, 0.044 %; docs/validation/localization.md).

Where the part held to the release ends with no smooth force (the run's own dynamics let go
before the sub-steps' reading), the rest still presses a contact (they let go after it), or
a part fails or leaves a closing unrefined, the step is taken whole, as without the split,
and counted.
"""

from __future__ import annotations

import dataclasses

from ..errors import SolverError
from ..ledger_records import joined_record
from .constraints import StepFailure
from .localize import cache_keys, drop_caches, joined, localized_step
from .state import State

__all__ = ["EDGE", "restarted", "split_at_release"]

EDGE = 1e-3
"""Fraction of the step: a release read this near either end of it leaves the step whole."""


def restarted(st: State) -> State:
    """``st`` with its acceleration variable restarted, a = v̇, and the smooth forces that a
    carries set to those v̇ carries (a copy; ``st`` is left as it is)."""
    smooth = st.smooth
    if smooth is not None:
        smooth = dataclasses.replace(smooth, in_a=smooth.in_vd.copy())
    return dataclasses.replace(st, a=st.vd.copy(), smooth=smooth)


def split_at_release(model, st: State, h: float, delta: float, rows, opts, timer) -> State | None:
    """The step from ``st`` over ``h`` (s) as a localized step of ``delta`` (s) that holds
    the contacts ``rows`` to their release and the rest of the step, each from its start
    restarted (module docstring), joined; None (the model's contacts and caches as before
    it, the step's counts undone) where the first part ends with no smooth force on
    ``rows``, the rest with one of them pressed, or a part fails or leaves a closing
    unrefined (the parts' impacts and fallbacks are then not counted: the whole step counts
    its own). Counted in the localization statistics (``release_splits``,
    ``release_split_fallbacks``)."""
    stats = opts.stats.localization
    counts = (stats.impacts, stats.first_closing, dict(stats.fallbacks))
    kept = cache_keys(model, stats)
    passing, model.passing = model.passing, True  # (the parts' sizes are met once)
    parts = None
    try:
        model.contacts.look_ahead(st.q, st.v, h)
        first = localized_step(model, restarted(st), delta, opts, timer)
        if (first.force[rows] > 0.0).any():
            model.contacts.look_ahead(first.q, first.v, h - delta)
            rest = localized_step(model, restarted(first), h - delta, opts, timer)
            # (a closing a part left unrefined: the whole step, which retakes it in sub-steps)
            unrefined = stats.fallbacks["unrefined"] > counts[2]["unrefined"]
            parts = None if rest.pressed()[rows].any() or unrefined else (first, rest)
    except (StepFailure, SolverError):
        parts = None
    finally:
        model.passing = passing
        drop_caches(model, kept, stats)
    if parts is None:
        stats.release_split_fallbacks += 1
        stats.impacts, stats.first_closing, stats.fallbacks = counts
        model.contacts.look_ahead(st.q, st.v, h)
        return None
    stats.release_splits += 1
    first, rest = parts
    rest.ledger = joined_record(model, first, rest)
    return joined(first, rest, h)
