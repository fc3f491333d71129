"""The statistics of one run: every count of fallbacks, globalizations and solver work that
``summary.json`` reports, in one object the time loop owns and hands to what counts."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from ..contact.stats import ContactStats
from ..linalg import Factorizations, IterativeStats, LinearSolver
from ..linalg.choice import RunPlan, SolverChoice

__all__ = [
    "FailedStep",
    "FollowUps",
    "Localization",
    "NewtonStats",
    "StepControl",
    "StepStats",
    "TurnCounts",
]


@dataclass
class NewtonStats:
    """Smooth Newton updates (:mod:`fecontact.time.descent`): all of them, the halvings of
    their length by the line search, and the directions recomputed with a mass shift (not
    descending); ``roundoff_accepts`` the lengths whose decrease test passed only within
    the round-off of the strain energy's change (:func:`fecontact.time.descent.energy_roundoff`)."""

    iterations: int = 0
    line_search_cuts: int = 0
    shifted_directions: int = 0
    roundoff_accepts: int = 0


@dataclass
class FollowUps:
    """Velocity follow-ups of an impact's correction
    (:func:`fecontact.time.position_jump.velocity_follows`), and those taken short of the
    full hγΔa because the rest would have raised the kinetic energy."""

    steps: int = 0
    shortened: int = 0


@dataclass
class Localization:
    """Impacts located inside their step (:mod:`fecontact.time.localize`): the impacts
    applied at their own instant, the extra smooth steps that found those instants and their
    Newton iterations (``smooth_iterations``), the factorizations made for the split steps'
    sizes (linear models), the ``ladder``'s solves of those sizes without one
    (:class:`fecontact.linalg.ladder.Ladder`: PCG solves, their
    iterations, those refactorized, eigendecompositions made), and the steps
    left to the end-of-step impact, by reason: ``accumulation`` (the step already split
    ``max_impacts`` times, or too little of it left), ``persistent`` (a contact was already
    pressed at the step's start), ``grazing`` (the gap closes with ġ ≈ 0), ``unrefined``
    (no instant found to the gap tolerance), ``failed`` (a smooth step of the split step did
    not converge: the step taken whole); ``subdivided`` counts the steps of a flexible
    model taken in sub-steps while a contact chattered, ``release_probes`` the steps of solids
    also taken aside in sub-steps to read a release (:class:`fecontact.time.substeps.Releases`),
    ``release_splits`` the steps split where those read it (:mod:`fecontact.time.release_split`)
    and ``release_split_fallbacks`` those taken whole instead (the part held to the release
    ended with no force, the rest with one, or a part failed); ``retakes_kept_whole`` the
    whole steps that left a closing unrefined whose retake in sub-steps left a deeper one
    unrefined, kept whole (:meth:`fecontact.time.substeps.Releases._retaken`), and
    ``unrefined_depth`` (m) the deepest gap a step left ``unrefined`` had at its end.
    ``first_closing`` is the earliest
    located closing instant (s) and ``last_release`` the end of the last (sub-)step of a
    flexible model in which a contact carried a force before one in which none did (s; for
    the solids "auto" localizes, that of the sub-steps taken aside where the run releases):
    a single impact's duration is their difference (None: not seen)."""

    impacts: int = 0
    smooth_steps: int = 0
    smooth_iterations: int = 0
    factorizations: int = 0
    subdivided: int = 0
    release_probes: int = 0
    release_splits: int = 0
    release_split_fallbacks: int = 0
    retakes_kept_whole: int = 0
    unrefined_depth: float = 0.0
    first_closing: float | None = None
    last_release: float | None = None
    fallbacks: dict = field(
        default_factory=lambda: dict.fromkeys(
            ("accumulation", "persistent", "grazing", "unrefined", "failed"), 0
        )
    )
    ladder: dict = field(
        default_factory=lambda: dict.fromkeys(
            (
                "pcg_solves",
                "pcg_iterations",
                "pcg_refactorized",
                "spectral",
                "rungs_remade",
                "curvature_factorizations",
                "curvature_reuses",
                "curvature_reuse_fallbacks",
            ),
            0,
        )
    )

    def fall_back(self, reason: str, gaps) -> None:
        """Count a step left to the end-of-step impact for ``reason``; an ``unrefined`` one
        notes the deepest of the ``gaps`` (m) at its trial's end in ``unrefined_depth``."""
        self.fallbacks[reason] += 1
        if reason == "unrefined" and gaps.size:
            self.unrefined_depth = max(self.unrefined_depth, -float(gaps.min()))


@dataclass
class TurnCounts:
    """The bound on the turn of beam nodes (:mod:`fecontact.time.turns`): the predictors and
    smooth steps refused because they turned a node by more than π/2 (each one a halving of
    the step, a rejection of rtol's control or a localized split taken whole), and the
    smooth Newton updates bordered by rows cut to that turn. The halvings the refusals caused
    and the steps that had any are counted with the states
    (:class:`fecontact.recorder.Recorder`)."""

    refused: int = 0
    cut_updates: int = 0
    velocity_predictors: int = 0
    damped_steps: int = 0


@dataclass
class StepControl:
    """What rtol's control did in a run: steps rejected for their error estimate, steps
    rejected because they failed (Newton or penetration; retaken a rung lower), and steps
    accepted with an estimate above the tolerance because they were on the lowest rung."""

    rejected_error: int = 0
    rejected_failure: int = 0
    over_tolerance: int = 0

    @property
    def rejected(self) -> int:
        return self.rejected_error + self.rejected_failure


@dataclass
class FailedStep:
    """The step that stopped a run: its number ``step`` (the row it would have ended on,
    as every step's) and the halvings it made before it failed, of them those for a
    penetration (``retakes``) and for a beam node's turn (``turn_halvings``), and the
    shortest sub-step it tried (``shortest``, s)."""

    step: int
    halvings: int = 0
    retakes: int = 0
    turn_halvings: int = 0
    shortest: float = math.inf


@dataclass
class StepStats:
    """Counts of one run (each starts at zero)."""

    newton: NewtonStats = field(default_factory=NewtonStats)
    follow_ups: FollowUps = field(default_factory=FollowUps)
    control: StepControl = field(default_factory=StepControl)  # rtol's rejections
    releases: int = 0  # smooth steps taken again without the force of a contact they released
    energy_retakes: int = 0  # beam steps that created energy, taken again (.energy_guard)
    energy_retake_halves: int = 0  # of those, retakes taken again in two halves
    turns: TurnCounts = field(default_factory=TurnCounts)
    failed: FailedStep | None = None  # the step that stopped the run, if one did
    localization: Localization = field(default_factory=Localization)
    contact: ContactStats = field(default_factory=ContactStats)
    factorizations: Factorizations = field(default_factory=Factorizations)
    iterative: IterativeStats = field(default_factory=IterativeStats)
    # the sparse solver's record: its backend, factorizations and memory, the choices of "auto"
    sparse: SolverChoice | None = None

    def solver(self, model, plan: RunPlan | None = None) -> LinearSolver:
        """A linear solver for ``model`` (the process default sparse solver, the model's rigid
        modes as AMG's near-null space) that counts its work here; with the run's ``plan``,
        its record (``sparse``) is kept for the summary."""
        out = LinearSolver(None, model.rigid_modes, self.factorizations, self.iterative, plan)
        self.sparse = out.choice if out.choice is not None else self.sparse
        return out

    def summary(self, frictional: bool) -> dict:
        """The entries of ``summary.json`` these counts make (``friction_solver`` only for a
        ``frictional`` model)."""
        asdict = dataclasses.asdict
        out = {
            "sparse_factorizations": asdict(self.factorizations),
            # redundant active constraints whose multipliers came from least squares
            "least_squares_multipliers": self.contact.least_squares,
            # active rows merged into their duplicate (a node's row from two clipped segments)
            "duplicate_rows": self.contact.duplicate_rows,
            # smooth-step updates on an independent subset of redundant bordering rows
            "redundant_row_updates": self.contact.redundant_row_updates,
            # ... and those whose persistent rows were solved whole as the linearised law
            "complementary_smooth_updates": self.contact.complementary_smooth_updates,
            # position corrections whose cycling active set was frozen at its best
            "frozen_active_sets": self.contact.frozen_active_sets,
            # ... and those settled by complementarity updates on every row at once
            "complementary_corrections": self.contact.complementary_corrections,
            # ... and those whose held rows froze the law unsettled, solved with them unilateral
            "released_corrections": self.contact.released_corrections,
            # frictionless jumps on redundant rows solved by the proximal point method
            "redundant_jumps": {
                "solves": self.contact.redundant_jumps,
                "proximal_steps": self.contact.redundant_jump_steps,
            },
            # the globalization of the smooth Newton (fecontact.time.descent)
            "smooth_newton": asdict(self.newton),
            # the velocity's follow-ups of an impact's correction (fecontact.time.position_jump)
            "velocity_follow_ups": asdict(self.follow_ups),
            "contact_releases": self.releases,
            # steps of beams that raised the energy, taken again at rho_inf = 0, located
            "energy_retakes": self.energy_retakes,
            "energy_retake_halves": self.energy_retake_halves,
            # beam nodes turned by more than π/2: (sub-)steps refused, row-bordered updates cut
            "beam_turns": asdict(self.turns),
            # impacts at their own instant inside a step, and the steps left to the step's end
            "localized_impacts": self.localization.impacts,
            "localization_fallbacks": dict(self.localization.fallbacks),
            "localization_cost": {
                "smooth_steps": self.localization.smooth_steps,
                "smooth_iterations": self.localization.smooth_iterations,
                "factorizations": self.localization.factorizations,
                # the split steps' sizes solved without their own factorization
                "ladder": dict(self.localization.ladder),
                "subdivided_steps": self.localization.subdivided,
                "release_probes": self.localization.release_probes,
                # releasing steps split at the release the probes read, and those left whole
                "release_splits": self.localization.release_splits,
                "release_split_fallbacks": self.localization.release_split_fallbacks,
                # retakes in sub-steps that left a deeper gap unrefined: the whole step kept
                "retakes_kept_whole": self.localization.retakes_kept_whole,
            },
            "localized_contact_span_s": [
                self.localization.first_closing,
                self.localization.last_release,
            ],
            # rtol's control (fecontact.time.adaptive): steps taken again smaller
            "steps_rejected": self.control.rejected,
            # the step that failed and stopped the run (None: none did)
            "failed_step": None if self.failed is None else self.failed.step,
            "step_control": asdict(self.control),
            # the largest Alart–Curnier residual a converged correction left, over its tolerance
            "final_residuals": asdict(self.contact.final_residuals),
            # AMG-preconditioned CG (sparse solver "amg"): solves, iterations, setups, fallbacks
            "iterative_solver": asdict(self.iterative),
        }
        if self.sparse is not None:  # the sparse solver: the direct path, the choices of "auto"
            out["sparse_solver"] = self.sparse.record()
        if frictional:  # the frictional solves and their fallbacks
            out["friction_solver"] = asdict(self.contact.coulomb)
        return out
