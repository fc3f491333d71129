"""Time stepping: the nonsmooth generalized-α step and its baselines behind one signature,
``step(model, state, h, options, timer) -> State``, chosen by name in :mod:`.simulate`."""

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
from .stepper import Stepper, make_stepper
from .terms import ForceTerm, StepContext

__all__ = [
    "uses_smooth_contact",
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
    "initial_state",
    "length_scale",
    "make_stepper",
    "record_arrays",
    "records_from_arrays",
    "run_settings",
    "simulate",
]
