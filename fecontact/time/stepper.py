"""A run's stepper, configured once: every option and model trait a step acts on is decided
when the run starts (:func:`make_stepper`), not again in every step."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import InputError
from ..ledger_records import joined_record
from ..linalg.choice import RunPlan
from ..linalg.legacy import registered_modes
from .alpha_step import alpha_plan
from .constraints import StepFailure
from .energy_guard import EnergyGuard, check_retakes, guards
from .energy_step import check_energy_scheme, energy_nsga_step
from .generalized_alpha import resized
from .lie import check_group
from .localize import joined, localizes
from .moreau import moreau_plan, moreau_step
from .nsga import nsga_step
from .penalty import penalty_plan, penalty_step
from .penetration import PenetrationFailure, hold_penetration
from .settings import RunSettings, run_settings
from .state import IntegratorOptions, PhaseTimer, State
from .stats import StepStats
from .substeps import localized_stepper
from .turns import TurnFailure

__all__ = ["PLANS", "STEPPERS", "TAKES_TERMS", "Stepper", "check_options", "make_stepper"]

STEPPERS = {"nsga": nsga_step, "moreau": moreau_step, "penalty": penalty_step}
"""Every stepper, ``step(model, state, h, options, timer) -> State``, by the name of the
``integrator`` option."""

PLANS = {"nsga": alpha_plan, "moreau": moreau_plan, "penalty": penalty_plan}
"""The Newton loop of each stepper, by the name of the ``integrator`` option:
``plan(model, smooth, friction, extra_terms) -> NewtonPlan`` lists its force terms
(:mod:`fecontact.time.terms`) and configures the loop (:mod:`fecontact.time.newton`)."""

TAKES_TERMS = ("nsga", "penalty")
"""The steppers whose loop takes extra force terms: those of the generalized-α step, whose
iteration matrix is S_t = β′M + Σ (∂f/∂q + γ′ ∂f/∂v)."""


class Stepper:
    """The step of one run: ``step(state, h, timer)`` takes ``state`` over ``h`` (s) with the
    step function ``kind`` chosen for the run, halving a step that fails, penetration
    included (:func:`hold_penetration`). ``settings`` are the run's :class:`RunSettings` (its
    options, the traits decided once, its statistics); ``guard`` checks each step's energy
    and has a step that created some taken again (:class:`EnergyGuard`; None: no check)."""

    def __init__(self, model, settings: RunSettings, kind: Callable, guard=None):
        self.model, self.settings, self.kind = model, settings, kind
        self.guard = guard
        self.turned: State | None = None  # the last step taken whole at ρ∞ = 0 for a turn
        contacts = model.contacts
        # (decided once: pairs that search ahead of a step; a model without contacts has no
        # penetration to record)
        self.looks = any(pair.looks_ahead for pair in contacts.pairs)
        self.holds = contacts.size > 0
        # an NSGA step whose end is outside every body (State.outside) and where no node can
        # enter a solid has nothing to measure: its record is the 0 m its state starts with
        self.trusts = settings.integrator == "nsga" and not settings.depth_check
        # the generalized-α steps, whose variable a belongs to the size of the step that made
        # it: a step of another size (the last one, cut to end on t_end; a rung of the rtol
        # ladder) starts from a taken to its own size (generalized_alpha.resized)
        self.resizes = settings.scheme == "generalized-alpha" and settings.integrator != "moreau"

    @property
    def stats(self) -> StepStats:
        return self.settings.stats

    def step(
        self, st: State, h: float, timer: PhaseTimer, depth: int = 0, damped: bool = False
    ) -> State:
        """The state after ``h`` (s) from ``st``: one step, or, where it fails, two of h/2,
        recursively down to ``max_halvings`` levels (then the failure propagates). A step
        retaken because it left a point too deep inside a body counts in ``retakes``, one
        whose predictor or smooth step turned a beam node too far in ``turn_halvings`` (in a
        run the guard checks, such a step is first taken at ρ∞ = 0: :mod:`.turns`). A
        whole step that created energy is taken again ``damped``, by the guard's settings
        and step function (:mod:`.energy_guard`). A generalized-α step of another size than
        the one that made ``st`` starts from its a taken to ``h`` (:func:`.resized`); the
        halves of a failed step keep that of ``h``, as they did."""
        start = resized(st, h) if self.resizes else st
        self.turned = None
        end = self._taken(start, h, timer, depth, damped)
        if damped or self.guard is None:
            return end
        return self.guard.held(self, st, end, h, timer, depth, end is self.turned)

    def _taken(self, st: State, h: float, timer: PhaseTimer, depth: int, damped: bool) -> State:
        model, settings, kind = self.model, self.settings, self.kind
        if damped:
            settings, kind = self.guard.settings, self.guard.kind
        if self.looks:
            model.contacts.look_ahead(st.q, st.v, h)
        try:
            return self._attempt(model, st, h, settings, timer, kind)
        except StepFailure as err:
            turn = isinstance(err, TurnFailure)
            err.shortest = min(err.shortest, h)
            # (a step refused for a turn, in a run the guard checks: taken at ρ∞ = 0 first)
            damps = turn and not damped and self.guard is not None
            if depth >= self.settings.max_halvings and not damps:
                raise
            retake = isinstance(err, PenetrationFailure)
        if damps:  # (the undamped modes that turned the node taken out: module turns)
            self.stats.turns.damped_steps += 1
            # (the whole step at ρ∞ = 0 is the guard's retake of it: kept, not taken again)
            self.turned = self._taken(st, h, timer, depth, True)
            return self.turned
        try:
            second = self.halves(st, h, timer, depth, damped)
        except StepFailure as failure:  # (this halving counted where the run stops)
            failure.carries(1, retake, turn)
            raise
        second.halvings += 1
        second.retakes += retake
        second.turn_halvings += turn
        return second

    def _attempt(self, model, st: State, h: float, settings, timer: PhaseTimer, kind) -> State:
        """One try of the step; a LAPACK error in it (a decomposition that did not converge,
        a singular matrix no solver caught) is the step's failure, halved as any."""
        try:
            end = kind(model, st, h, settings, timer)
            if not self.holds or (self.trusts and end.outside):
                return end
            return hold_penetration(model, end, settings, timer)
        except np.linalg.LinAlgError as err:
            raise StepFailure(f"linear algebra: {err}", np.nan) from None

    def halves(self, st: State, h: float, timer: PhaseTimer, depth: int, damped: bool) -> State:
        """The step from ``st`` over ``h`` (s) as two of h/2 (each halved in turn where it
        fails), joined; the halves are parts of this step, which the energy guard checks
        whole."""
        first = self._taken(st, 0.5 * h, timer, depth + 1, damped)
        try:
            second = self._taken(first, 0.5 * h, timer, depth + 1, damped)
        except StepFailure as failure:  # (the first half's halvings are the failed step's)
            failure.carries(first.halvings, first.retakes, first.turn_halvings)
            raise
        second.ledger = joined_record(self.model, first, second)  # both halves' contact phases
        least = min(first.h_least or first.h, second.h_least or second.h)
        second = joined(first, second, h)
        second.h_least = least
        return second


def make_stepper(
    model,
    options: IntegratorOptions,
    stats: StepStats | None = None,
    steps: int | None = None,
    terms=(),
) -> Stepper:
    """The stepper of a run of ``model`` with ``options``, counting into ``stats`` (default:
    new :class:`StepStats`): the step function of the integrator and scheme, the options'
    "auto" values and the model's traits resolved (:func:`run_settings`), the force terms of
    its smooth Newton loop (:data:`PLANS`) with ``terms`` added
    (:class:`fecontact.time.terms.ForceTerm`, for the steppers with such a loop), and a linear
    solver of the run's own for the model (the process default sparse solver, read now),
    whose ``"auto"`` weighs the costs of the ``steps`` time steps the run will take (None: it
    factorizes). Raises ``InputError`` where the energy-decaying step does not apply, or
    where ``terms`` are given to a stepper without a smooth Newton loop."""
    plan = PLANS.get(options.integrator)
    if terms and (options.integrator not in TAKES_TERMS or options.scheme != "generalized-alpha"):
        raise InputError(
            "terms: force terms enter the generalized-alpha Newton loop of the nsga and "
            f"penalty integrators, not integrator={options.integrator!r} with "
            f"scheme={options.scheme!r}"
        )
    settings = run_settings(model, options, stats, terms, plan)
    check_options(model, settings)
    kind = STEPPERS[settings.integrator]
    if settings.scheme == "energy-decaying":
        kind = energy_nsga_step
    if localizes(model, settings):  # (decided once: every step of the run splits or none)
        kind = localized_stepper(model, settings)
    plan = None if steps is None else RunPlan(max(int(steps), 1), model.linear)
    solver = settings.stats.solver(model, plan)
    # AMG's near-null space registered by this thread (deprecated set_near_null_space)
    if (modes := registered_modes(model.n_free)) is not None:
        solver.modes = modes
    model.use_solver(solver)
    _empty_caches(model)
    # (decided once: beams whose steps may create energy, module energy_guard)
    guard = EnergyGuard(model, settings) if guards(model, settings) else None
    return Stepper(model, settings, kind, guard)


def check_options(model, options: IntegratorOptions) -> None:
    """``InputError`` where ``options`` do not apply to ``model``: rotations in space off the
    NSGA generalized-α step (:func:`check_group`), the energy-decaying step on a model it is
    not built for (:func:`check_energy_scheme`), ``localize`` true with moving obstacles
    (:func:`localizes`), ``energy_retakes`` true where its rule cannot judge the steps
    (:func:`check_retakes`). :func:`make_stepper` checks them; a run checks them before it
    writes any file."""
    check_group(model, options)
    if options.scheme == "energy-decaying":
        check_energy_scheme(model, options)
    localizes(model, options)
    check_retakes(model, options)


def _empty_caches(model) -> None:
    """Empty what a linear ``model`` keeps for the run: its step sizes' factorizations and
    contact columns, and the ladder that solves the sizes met once. An earlier run's ladder
    changes how a later run solves them (PCG from a nearer rung, a rung's exact factors, the
    eigendecomposition sooner: module :mod:`fecontact.linalg.ladder`) and so its round-off;
    empty, the run computes what it does in a fresh process (tests/test_run_independence.py).
    The mass's factorization, the same for every run, is kept."""
    model.iteration_cache, model.column_cache = {}, {}
    model.ladder, model.passing = None, False
