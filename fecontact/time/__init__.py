"""Time stepping: the nonsmooth generalized-α step and its baselines behind one signature,
``step(model, state, h, options, timer) -> State``, chosen by name in :mod:`.simulate`.
``NEWTON``, ``FOLLOW_UPS`` and ``RELEASES`` are deprecated
(:mod:`fecontact.linalg.legacy`)."""

import dataclasses

from ..linalg.legacy import LastRunCounts, deprecated
from .generalized_alpha import alpha_coefficients
from .records import (
    FrictionRecord,
    PenaltyRecord,
    SmoothForces,
    record_arrays,
    records_from_arrays,
)
from .settings import RunSettings, run_settings, uses_smooth_contact
from .simulate import STEPPERS, simulate
from .state import IntegratorOptions, PhaseTimer, State, initial_state, length_scale
from .stats import StepStats
from .stepper import Stepper, check_options, make_stepper
from .terms import ForceTerm, StepContext

__all__ = [
    "uses_smooth_contact",
    "FOLLOW_UPS",
    "NEWTON",
    "RELEASES",
    "ForceTerm",
    "FrictionRecord",
    "PenaltyRecord",
    "STEPPERS",
    "IntegratorOptions",
    "PhaseTimer",
    "RunSettings",
    "SmoothForces",
    "State",
    "StepContext",
    "StepStats",
    "Stepper",
    "alpha_coefficients",
    "check_options",
    "initial_state",
    "length_scale",
    "make_stepper",
    "record_arrays",
    "records_from_arrays",
    "run_settings",
    "simulate",
]

# the deprecated counter names: the counts of the calling thread's latest run, by their old keys
_COUNTERS = {
    "NEWTON": lambda stats: dataclasses.asdict(stats.newton),
    "FOLLOW_UPS": lambda stats: dataclasses.asdict(stats.follow_ups),
    "RELEASES": lambda stats: {"steps": stats.releases},
}


def __getattr__(name: str):
    read = _COUNTERS.get(name)
    if read is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    deprecated(f"fecontact.time.{name}", "read the run's StepStats (simulate's stats)")
    return LastRunCounts(name, lambda stats: read(StepStats() if stats is None else stats))
