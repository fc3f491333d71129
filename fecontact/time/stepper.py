"""A run's stepper, configured once: every option and model trait a step acts on is decided
when the run starts (:func:`make_stepper`), not again in every step."""

from __future__ import annotations

from collections.abc import Callable

from ..linalg.choice import RunPlan
from .constraints import StepFailure
from .energy_step import check_energy_scheme, energy_nsga_step
from .lie import check_group
from .localize import joined, localized_step, localizes
from .moreau import moreau_step
from .nsga import nsga_step
from .penalty import penalty_step
from .penetration import PenetrationFailure, hold_penetration
from .settings import RunSettings, run_settings
from .state import IntegratorOptions, PhaseTimer, State
from .stats import StepStats

__all__ = ["STEPPERS", "Stepper", "make_stepper"]

STEPPERS = {"nsga": nsga_step, "moreau": moreau_step, "penalty": penalty_step}
"""Every stepper, ``step(model, state, h, options, timer) -> State``, by the name of the
``integrator`` option."""


class Stepper:
    """The step of one run: ``step(state, h, timer)`` takes ``state`` over ``h`` (s) with the
    step function ``kind`` chosen for the run, halving a step that fails, penetration
    included (:func:`hold_penetration`). ``settings`` are the run's :class:`RunSettings` (its
    options, the traits decided once, its statistics)."""

    def __init__(self, model, settings: RunSettings, kind: Callable):
        self.model, self.settings, self.kind = model, settings, kind

    @property
    def stats(self) -> StepStats:
        return self.settings.stats

    def step(self, st: State, h: float, timer: PhaseTimer, depth: int = 0) -> State:
        """The state after ``h`` (s) from ``st``: one step, or, where it fails, two of h/2,
        recursively down to ``max_halvings`` levels (then the failure propagates). A step
        retaken because it left a point too deep inside a body counts in ``retakes``."""
        model = self.model
        model.contacts.look_ahead(st.q, st.v, h)
        try:
            return hold_penetration(
                model, self.kind(model, st, h, self.settings, timer), self.settings, timer
            )
        except StepFailure as err:
            if depth >= self.settings.max_halvings:
                raise
            retake = isinstance(err, PenetrationFailure)
        first = self.step(st, 0.5 * h, timer, depth + 1)
        second = self.step(first, 0.5 * h, timer, depth + 1)
        second = joined(first, second, h)
        second.halvings += 1
        second.retakes += retake
        return second


def make_stepper(
    model, options: IntegratorOptions, stats: StepStats | None = None, steps: int | None = None
) -> Stepper:
    """The stepper of a run of ``model`` with ``options``, counting into ``stats`` (default:
    new :class:`StepStats`): the step function of the integrator and scheme, the options'
    "auto" values and the model's traits resolved (:func:`run_settings`), and a linear solver
    of the run's own for the model (the process default sparse solver, read now), whose
    ``"auto"`` weighs the costs of the ``steps`` time steps the run will take (None: it
    factorizes). Raises ``InputError`` where the energy-decaying step does not apply."""
    settings = run_settings(model, options, stats)
    check_group(model, settings)  # rotations in space: NSGA with generalized-α only
    kind = STEPPERS[settings.integrator]
    if settings.scheme == "energy-decaying":
        check_energy_scheme(model, settings)
        kind = energy_nsga_step
    if localizes(model, settings):  # (decided once: every step of the run splits or none)
        kind = localized_step
    plan = None if steps is None else RunPlan(max(int(steps), 1), model.linear)
    model.use_solver(settings.stats.solver(model, plan))
    return Stepper(model, settings, kind)
