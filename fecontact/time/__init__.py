"""Time stepping: the nonsmooth generalized-α step and its baselines behind one signature,
``step(model, state, h, options, timer) -> State``, chosen by name in :mod:`.simulate`."""

from .generalized_alpha import alpha_coefficients
from .settings import RunSettings, run_settings
from .simulate import STEPPERS, simulate
from .smooth_contact import uses_smooth_contact
from .state import IntegratorOptions, PhaseTimer, State, initial_state, length_scale
from .stats import StepStats

__all__ = [
    "uses_smooth_contact",
    "STEPPERS",
    "IntegratorOptions",
    "PhaseTimer",
    "RunSettings",
    "State",
    "StepStats",
    "alpha_coefficients",
    "initial_state",
    "length_scale",
    "run_settings",
    "simulate",
]
