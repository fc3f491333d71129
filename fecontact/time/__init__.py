"""Time stepping: the nonsmooth generalized-α step and its baselines behind one signature,
``step(model, state, h, options, timer) -> State``, chosen by name in :mod:`.simulate`."""

from .descent import NEWTON
from .generalized_alpha import alpha_coefficients
from .position_jump import FOLLOW_UPS
from .simulate import STEPPERS, simulate
from .smooth_contact import RELEASES, uses_smooth_contact
from .state import IntegratorOptions, PhaseTimer, State, initial_state, length_scale

__all__ = [
    "uses_smooth_contact",
    "FOLLOW_UPS",
    "NEWTON",
    "RELEASES",
    "STEPPERS",
    "IntegratorOptions",
    "PhaseTimer",
    "State",
    "alpha_coefficients",
    "initial_state",
    "length_scale",
    "simulate",
]
