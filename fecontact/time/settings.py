"""The settings of one run: the integrator options, what the run decided once about its
model, and the statistics its steps fill."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from ..contact.contact_loops import loops_of_contacts
from .correction import MomentumKept, momentum_kept
from .dips import scans_dips
from .newton import NewtonPlan
from .spin_restart import velocity_forces
from .state import IntegratorOptions
from .stats import StepStats
from .turns import TurnBound, beam_turns

__all__ = [
    "RunSettings",
    "positional_friction",
    "run_settings",
    "settles",
    "struck",
    "uses_smooth_contact",
]


@dataclass
class RunSettings(IntegratorOptions):
    """The :class:`IntegratorOptions` of one run, the traits of its model the steps act on,
    decided once (``smooth``: persistent contacts carry a smooth force, the ``"auto"`` of
    ``smooth_contact`` resolved; ``restarts``: and the acceleration variable restarts after
    an impact, which beams do not take; ``spins``: the decoupled step's v̇ and a follow the
    gyroscopic forces and the joints' quadratic terms through a velocity jump
    (:mod:`.spin_restart`); ``settle``: on models
    with beams and no solid whose every pair is struck (at a beam's end, by a moving body
    that is no beam: :func:`settles`),
    a contact carries the smooth force only from the second step after the one in which it
    closed, and the accelerations follow the correction of the step between; ``friction``:
    the contacts have friction; ``positional_friction``: the position correction carries their
    slip rows, which the decoupled step (no smooth force) of the models that settle keeps
    only for the contacts it holds stuck: :func:`positional_friction`), its
    statistics ``stats``, which the phases of its steps fill, and ``plan``, the smooth
    Newton loop's force terms and configuration (:class:`~fecontact.time.newton.NewtonPlan`;
    None for a stepper without one), and ``momentum``, what holds the angular momentum of
    free beams in space through position corrections
    (:class:`~fecontact.time.correction.MomentumKept`; None where no body qualifies), and
    ``depth_check``: whether a solid's nodes can enter another solid (pairs tested
    inside/outside, mortar interfaces), so that the predictor's depth is checked
    (:func:`~fecontact.time.penetration.check_predictor`); ``turns``: the beams' nodal
    rotations, whose turn the smooth step bounds over the step and over each update that
    rows border (:class:`~fecontact.time.turns.TurnBound`; None without beams), and
    ``coasts``: a predictor that turns a beam node too far starts Newton at constant
    velocity instead (the energy guard's steps at ρ∞ = 0, :mod:`.turns`); ``dips``: a localized
    step also locates a gap that closes and opens again inside it (:mod:`.dips`)."""

    smooth: bool = False
    restarts: bool = False
    spins: bool = False
    settle: bool = False
    friction: bool = False
    positional_friction: bool = True
    stats: StepStats = field(default_factory=StepStats, repr=False, compare=False)
    plan: NewtonPlan | None = field(default=None, repr=False, compare=False)
    momentum: MomentumKept | None = field(default=None, repr=False, compare=False)
    depth_check: bool = field(default=True, repr=False, compare=False)
    turns: TurnBound | None = field(default=None, repr=False, compare=False)
    coasts: bool = field(default=False, repr=False, compare=False)
    dips: bool = field(default=False, repr=False, compare=False)

    def __post_init__(self):
        pass  # the values are those of options already checked, taken as they are


def uses_smooth_contact(model, opts) -> bool:
    """Whether the NSGA step gives persistent contacts a smooth force: ``smooth_contact``
    "on", or "auto" with the generalized-α smooth step on a model with an elastic continuum
    (a ``Solid``) or a beam (planar or spatial), whose lasting contacts the decoupled step
    makes create energy (each step releases the shape the contact holds, the correction
    restores its strain). The energy-decaying step has no smooth force: "auto" leaves it
    the decoupled contact phase."""
    if opts.smooth_contact != "auto":
        return opts.smooth_contact == "on"
    return opts.scheme == "generalized-alpha" and (model.continuum or model.slender)


def settles(model, smooth: bool) -> bool:
    """Whether a contact of ``model`` closed in a step takes the smooth force only from the
    second step after it (``RunSettings.settle``): on models with beams and no solid where
    every pair is struck (:func:`struck`). A node held within the step that strikes it,
    while the beam still moves into it, drives the beam's ringing (the floor pendulums,
    planar and in space, and a disk thrown at 300 m/s onto a strip fail without the step
    between); a rod met along its length by a fixed obstacle closes each of its contacts
    with a decoupled step there, which made 0.3-1.2 % of its scale (measured:
    docs/explanation/energy_ledger.md, *Lasting contact of beams*)."""
    if not (smooth and model.slender and not model.continuum):
        return False
    pairs = model.contacts.pairs
    return bool(pairs) and all(struck(model, pair) for pair in pairs)


def struck(model, pair) -> bool:
    """Whether ``pair`` of ``model`` meets a beam at its ends only (a tip, a bar's end), or
    a beam and a moving body that is no beam (a disk or a ball thrown onto a strip), or an
    obstacle that moves; planar or in space. Not a beam met along its length by a fixed
    obstacle or a held body, nor two beams met along their lengths: crossing rods settling
    created 2.6e-2 to 4.6e-2 of their scale over four drop heights a quarter step apart
    (h = 0.1 ms), 0 to 2.6e-2 not settling; two planar strips up to 3.7e-4 against 6.7e-5."""
    if pair.at_beam_ends:
        return True
    if pair.obstacle is not None:
        return pair.obstacle.moving
    if all(body.slender for body in pair.bodies):
        return False
    return all(_moves(model, body) for body in pair.bodies)


def _moves(model, body) -> bool:
    """Whether a support leaves ``body`` of ``model`` a free dof."""
    i = next(i for i, b in enumerate(model.bodies) if b is body)
    dofs = model.body_slice(i)
    return bool(((model.free >= dofs.start) & (model.free < dofs.stop)).any())


def positional_friction(model, smooth: bool) -> bool:
    """Whether the position correction of ``model``'s steps carries the slip rows of every
    contact it holds (``RunSettings.positional_friction``): not in the decoupled step
    (``smooth`` False) of the models whose contacts settle (:func:`settles`: beams struck at
    their ends, or by a moving body that is no beam). There no step carries a contact force,
    and a contact keeps its rows only where the correction holds it stuck and it was not
    struck in the last step (the step marks its closings as the settling step does); one the
    correction slips at the cone's edge is corrected again without them, its friction the
    jump's, as in the step after a strike of the smooth scheme. The rows of a slipping
    contact pulled the predictor's slip back in the correction's metric S_t/β′, which on a
    beam is not the mass the jump moves: the pull-back strained the strip near the contact,
    and the jump did not take that strain back as kinetic energy. Friction then did positive
    work: the flexible pendulum at μ = 1, 6.5e-5 J at t = 0.324 s. Without the rows of the
    stuck contacts too, a strip held on an incline crept by the predictor's drift, h² g sin
    α/2 a step (docs/explanation/energy_ledger.md, *Friction of the decoupled step*)."""
    return smooth or not settles(model, True)


def run_settings(
    model, opts: IntegratorOptions, stats: StepStats | None = None, terms=(), plan=None
) -> RunSettings:
    """``opts`` as the settings of a run of ``model`` that counts into ``stats`` (default:
    new counts), with the smooth Newton loop ``plan(model, smooth, friction, terms)`` makes
    (None: the stepper has none), the force ``terms`` added to the model's own
    (:class:`~fecontact.time.terms.ForceTerm`); settings already made are returned as they
    are."""
    if isinstance(opts, RunSettings):
        return opts
    values = {f.name: getattr(opts, f.name) for f in dataclasses.fields(IntegratorOptions)}
    smooth = uses_smooth_contact(model, opts)  # (read by the NSGA step only)
    contacts = model.contacts
    friction = contacts.frictional
    run_stats = StepStats() if stats is None else stats
    # rows that can be redundant (planes through one point, or rigid bodies closing a loop
    # of contacts) take minimum-norm multipliers
    run_stats.contact.minimum_norm = contacts.redundant_rows or loops_of_contacts(model)
    # pairs whose segments clip to a shared node give its row twice: merged in the KKT solve
    run_stats.contact.merge_duplicates = any(p.duplicate_rows for p in contacts.pairs)
    return RunSettings(
        **values,
        smooth=smooth,
        restarts=smooth and not model.slender,  # (beams: see smooth_contact, the restart)
        spins=not smooth and velocity_forces(model),
        settle=settles(model, smooth),
        friction=friction,
        positional_friction=positional_friction(model, smooth),
        stats=run_stats,
        plan=None if plan is None else plan(model, smooth, friction, terms),
        momentum=momentum_kept(model),
        depth_check=any(pair.inside_test for pair in contacts.pairs) or bool(contacts.watches),
        turns=beam_turns(model),
        dips=scans_dips(model),
    )
