"""What every stepper shares: the integrator options, the state of a step, the phase timer,
and the initial state with its consistent acceleration."""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..contact.contact_set import admissible_gaps
from ..errors import (
    InputError,
    check_count,
    check_positive,
    check_range,
    check_vector,
)
from ..linalg import factorize
from .constraints import bordered
from .generalized_alpha import alpha_coefficients
from .lie import inertial_forces
from .records import FrictionRecord, PenaltyRecord, SmoothForces

__all__ = [
    "IntegratorOptions",
    "JointTolerance",
    "PhaseTimer",
    "State",
    "deferred_ledger",
    "initial_state",
    "length_scale",
]

METRICS = ("stiffness", "mass")
IMPACT_VELOCITIES = ("interpolated", "step_start")
INTEGRATORS = ("nsga", "moreau", "penalty")
SWITCH = ("auto", "on", "off")
SCHEMES = ("generalized-alpha", "energy-decaying")
IMPACT_LAWS = ("newton", "poisson")


# the options that name one of a few choices, in the order they are checked
_CHOICES = {
    "metric": METRICS,
    "impact_velocity": IMPACT_VELOCITIES,
    "integrator": INTEGRATORS,
    "smooth_contact": SWITCH,
    "scheme": SCHEMES,
    "impact_law": IMPACT_LAWS,
}


# the options that only some integrators read, and those integrators: any other value than
# the default given to another integrator is refused (IntegratorOptions), since its step
# would not read it. The options every step reads (the tolerances, max_iterations,
# max_halvings, detection_margin) and ``integrator`` itself are not listed.
READERS = {
    "rho_inf": ("nsga", "penalty"),  # the generalized-α (and energy-decaying) smooth step
    "metric": ("nsga",),  # the position correction
    "penalty_scale": ("nsga", "moreau"),  # the augmented Lagrangian of the contact solves
    "multiplier_scale": ("nsga", "moreau"),
    "impact_velocity": ("nsga",),  # the velocity jump's ġ⁻ (Moreau–Jean: ġ(q_n, v_n))
    "theta": ("moreau",),
    "penalty_stiffness": ("penalty",),
    "penalty_damping": ("penalty",),
    "smooth_contact": ("nsga",),
    "scheme": ("nsga",),
    "impact_law": ("nsga", "moreau"),
    "localize": ("nsga",),
    "rtol": ("nsga", "penalty"),
    "energy_retakes": ("nsga",),
}


@dataclass
class IntegratorOptions:
    """Settings of the nonsmooth generalized-α integrator.

    Options that only some integrators read (:data:`READERS`) are refused, with any value
    other than their default, by the others: ``theta`` with "nsga", ``rho_inf`` with
    "moreau", ``localize=False`` with "penalty".

    rho_inf : spectral radius at infinite frequency, in [0, 1] (1: no numerical damping);
        nsga and penalty.
    metric : position-correction metric, "stiffness" (H = S_t/β′) or "mass" (H = M).
    penalty_scale, multiplier_scale : factors (> 0) on the automatic p and k; they change the
        path of the contact Newton iterations, never the converged result.
    tol_residual : relative tolerance of the smooth Newton residual.
    tol_increment : Newton also stops when an update is below this fraction of the model size
        (rotations: of 1 rad), where round-off bounds the residual of very stiff models.
    tol_gap : gap (and joint) tolerance relative to the length scale of the model: the larger
        of its size and the magnitude of its coordinates, since a gap computed from
        coordinates x carries a round-off of about ε|x| (see :func:`length_scale`).
    max_iterations : Newton iterations per step before the step is halved.
    max_halvings : how many times a failing step is halved before the run stops.
    detection_margin : contacts with g(q̃) below this fraction of the model size are candidates.
    impact_velocity : the pre-impact normal velocity ġ⁻ of Newton's law ġ⁺ = −e ġ⁻ on a
        contact that closes inside a step: "interpolated" (default) takes ġ at the instant the
        gap crosses zero, found on the chord from g(q_n) to g(q̃_{n+1}); "step_start" takes
        ġ(q_n, v_n) as in Brüls, Acary & Cardona (2014). The first loses e g̈ δ of rebound
        speed only at O(h²) (δ: time from the step start to the impact), the second at O(h).
    integrator : "nsga" (this module), or the baselines of :mod:`fecontact.time` for
        side-by-side comparisons: "moreau" (Moreau–Jean θ-method, impact law at velocity
        level only) and "penalty" (penalty contact in the smooth generalized-α step).
    theta : θ ∈ (0, 1] of Moreau–Jean.
    penalty_stiffness : N/m of the penalty baseline (None: automatic, ten steps per contact
        period).
    penalty_damping : damping ratio ζ ≥ 0 of the penalty baseline (None: from e_N).
    smooth_contact : NSGA only. "on": contacts that stay closed carry a contact force λ in
        the smooth step (:mod:`fecontact.time.smooth_contact`); "off": the fully decoupled
        scheme, where only the position correction and the velocity jump act on contacts;
        "auto" (default): on for models with an elastic continuum (``Solid``), whose
        lasting contacts it lets take steps of Δx/c and more (docs/explanation/stability.md),
        and for models with beams, whose lasting contacts the decoupled scheme makes create
        energy (docs/explanation/energy_ledger.md); off for rigid bodies and point masses,
        which it does not change measurably, and with the energy-decaying scheme.
    scheme : NSGA only. The smooth step: "generalized-alpha" (default) or "energy-decaying"
        (:mod:`fecontact.time.energy_step`: planar geometrically exact beams, whose energy it
        cannot let grow; ``rho_inf`` ∈ [1/3, 1] sets its dissipation, 1 conserves energy).
    impact_law : nsga and moreau. "newton" (default): ġ⁺ ≥ −e_N ġ⁻, kinematic restitution;
        "poisson": a compression impulse, then a decompression impulse at least e_N times
        it, each under Coulomb's law (:mod:`fecontact.time.poisson`), which cannot make a
        single frictional contact gain energy where Newton's law can.
    localize : NSGA only. True (or 1, "on"): a step in which a gap open at its start closes
        is split at the instant it closes, where the impact law acts
        (:mod:`fecontact.time.localize`); False (0, "off"): the impact acts at the end of
        the step; "auto" (default): on for models of rigid bodies and point masses with
        contacts on fixed obstacles or between them, frictionless or frictional, and for
        models of undamped solids
        (rigid bodies beside them) on fixed obstacles or between them, frictionless or
        frictional (whole steps, no chattering sub-steps; decided per run).
    rtol : None (default): fixed steps of the run's dt. A number in (0, 1): steps chosen by
        this relative tolerance on the local error of the smooth step, with an absolute
        tolerance of rtol times the model size, from dt (the first and largest) down to
        dt/1024 (:mod:`fecontact.time.adaptive`); nsga and penalty, generalized-alpha only.
    energy_retakes : NSGA with generalized-α, beams. "auto" (default): on models with beams
        (struck at an end or met along their length; planar solids beside them or not) with the
        smooth contact force, contacts
        on fixed obstacles or between the bodies and no loads, a step whose energy T + V
        rises by more than 1e-3 of the run's scale is taken again at ρ∞ = 0, located at its
        closing (:mod:`fecontact.time.energy_guard`); True (1, "on"): the decoupled step
        too (refused on a model or integrator the rule cannot judge:
        :func:`~fecontact.time.energy_guard.check_retakes`); False (0, "off"): no step is
        taken again.
    """

    rho_inf: float = 0.5
    metric: str = "stiffness"
    penalty_scale: float = 1.0
    multiplier_scale: float = 1.0
    tol_residual: float = 1e-8
    tol_increment: float = 1e-8
    tol_gap: float = 1e-12
    max_iterations: int = 30
    max_halvings: int = 6
    detection_margin: float = 0.05
    impact_velocity: str = "interpolated"
    integrator: str = "nsga"
    theta: float = 0.5
    penalty_stiffness: float | None = None
    penalty_damping: float | None = None
    smooth_contact: str = "auto"
    scheme: str = "generalized-alpha"
    impact_law: str = "newton"
    localize: bool | str = "auto"
    rtol: float | None = None
    energy_retakes: bool | str = "auto"

    def __post_init__(self):
        alpha_coefficients(self.rho_inf)
        self.localize = _switch("localize", self.localize)
        self.energy_retakes = _switch("energy_retakes", self.energy_retakes)
        if self.localize is True and (self.integrator, self.scheme) != ("nsga", SCHEMES[0]):
            raise InputError(
                f"localize = true needs integrator 'nsga' with scheme {SCHEMES[0]!r}, got "
                f"integrator {self.integrator!r}, scheme {self.scheme!r}"
            )
        for name, allowed in _CHOICES.items():
            value = getattr(self, name)
            if not isinstance(value, str) or value not in allowed:
                raise InputError(f"{name} must be one of {', '.join(allowed)}, got {value!r}")
        if self.impact_law != "newton" and self.integrator == "penalty":
            raise InputError(
                f"impact_law = {self.impact_law!r} needs integrator nsga or moreau: the penalty "
                "baseline has no impact law (its dashpot sets the restitution)"
            )
        _check_integrator_choices(self)
        self.theta = check_range("theta", self.theta, 0.0, 1.0, (False, True))
        if self.penalty_stiffness is not None:
            self.penalty_stiffness = check_positive("penalty_stiffness", self.penalty_stiffness)
        if self.penalty_damping is not None:
            self.penalty_damping = check_positive(
                "penalty_damping", self.penalty_damping, allow_zero=True
            )
        for name in (
            "penalty_scale",
            "multiplier_scale",
            "tol_residual",
            "tol_increment",
            "tol_gap",
        ):
            setattr(self, name, check_positive(name, getattr(self, name)))
        self.detection_margin = check_positive(
            "detection_margin", self.detection_margin, allow_zero=True
        )
        self.max_iterations = check_count("max_iterations", self.max_iterations, 1, 10**4)
        # beyond 50 halvings the step is below the round-off of the time
        self.max_halvings = check_count("max_halvings", self.max_halvings, 0, 50)
        if self.rtol is not None:
            self.rtol = check_range("rtol", self.rtol, 0.0, 1.0, (False, False))
            if self.integrator not in ("nsga", "penalty") or self.scheme != SCHEMES[0]:
                raise InputError(
                    "rtol needs the generalized-alpha step (integrator nsga or penalty, "
                    f"scheme generalized-alpha), got integrator {self.integrator!r}, "
                    f"scheme {self.scheme!r}"
                )
        _check_readers(self)


def _check_integrator_choices(opts: IntegratorOptions) -> None:
    """``InputError`` for a choice of one integrator given to another, which would not read
    it: ``smooth_contact="on"`` (the NSGA step's), ``penalty_stiffness`` and
    ``penalty_damping`` (the penalty baseline's)."""
    if opts.smooth_contact == "on" and opts.integrator != "nsga":
        raise InputError(
            f"smooth_contact = 'on' is a choice of the nsga integrator's step, not of "
            f"integrator {opts.integrator!r}"
        )
    given = [n for n in ("penalty_stiffness", "penalty_damping") if getattr(opts, n) is not None]
    if given and opts.integrator != "penalty":
        raise InputError(
            f"{given[0]} is an option of integrator 'penalty', not of {opts.integrator!r}"
        )


def _check_readers(opts: IntegratorOptions) -> None:
    """``InputError`` for an option of :data:`READERS` set off its default while the run's
    integrator does not read it; the more specific checks of ``__post_init__`` come first."""
    for name, readers in READERS.items():
        if opts.integrator in readers:
            continue
        value = getattr(opts, name)
        if value != getattr(IntegratorOptions, name):
            raise InputError(
                f"{name} = {value!r} is read by integrator {' and '.join(readers)} only, not "
                f"integrator {opts.integrator!r}: its step would ignore it (leave {name} "
                "at its default)"
            )


def _switch(name: str, value) -> bool | str:
    """An on/off option that may also be "auto": True, False or "auto". The words "true" and
    "false" count as the booleans: ``--set localize=true`` gives a string, which the error
    offered ("must be true, false ...") and then refused."""
    words = {"on": True, "true": True, "off": False, "false": False, "auto": "auto"}
    if isinstance(value, str) and value.lower() in words:
        return words[value.lower()]
    if isinstance(value, bool | int | np.integer) and value in (0, 1):
        return bool(value)
    raise InputError(f"{name} must be true, false (1, 0, on, off) or auto, got {value!r}")


@dataclass
class State:
    """The solution at one time: full dof vectors and what the step did to get there.

    q (m, rad) and v (m/s, rad/s) are the corrected positions and velocities, vd the smooth
    acceleration v̇ and a the generalized-α acceleration variable. ``gaps`` holds g_j(q) of
    every contact (m), ``nu`` k ν_j (kg·m) and ``impulse`` k Λ_j (N·s) of the step.
    The records a step hands the next (:mod:`fecontact.time.records`), None where the run
    has none: ``smooth`` the smooth contact forces, ``friction`` the frictional multipliers,
    status and work, ``penalty`` the penalty law, and ``strain_increment`` the energy-decaying
    step's Δε of the elements (Σ E, 3), and ``ledger`` what the energy ledger needs of the
    smooth step (:func:`fecontact.ledger_records.smooth_record`); a checkpoint of the state holds
    all of the run.
    """

    t: float
    q: np.ndarray
    v: np.ndarray
    vd: np.ndarray
    a: np.ndarray
    step: int = 0
    h: float = 0.0
    gaps: np.ndarray = field(default_factory=lambda: np.zeros(0))
    candidates: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    nu: np.ndarray = field(default_factory=lambda: np.zeros(0))
    impulse: np.ndarray = field(default_factory=lambda: np.zeros(0))
    iterations: dict = field(default_factory=lambda: {"smooth": 0, "position": 0, "velocity": 0})
    lam: np.ndarray = field(default_factory=lambda: np.zeros(0))
    halvings: int = 0
    retakes: int = 0  # of the halvings: steps retaken for a penetration
    turn_halvings: int = 0  # of the halvings: steps whose predictor turned a beam node too far
    # the shortest (sub-)step (s) the step was taken in where it was halved; None: h itself
    h_least: float | None = None
    penetration: float = 0.0  # m: the deepest contact point on the wrong side at the end
    # the deepest node of a mortar interface inside the other solid, over that solid's
    # shortest boundary edge (fecontact.contact.watch)
    mortar_depth: float = 0.0
    # nodes of mortar interfaces held by their own gaps at the end (contact.mortar_safeguard)
    mortar_held: int = 0
    # the step knows every gap is ≥ 0 at its end, so that its penetration is 0 unmeasured: a
    # position-level step that corrected nothing and held no contact by a smooth force
    outside: bool = False
    smooth: SmoothForces | None = None
    friction: FrictionRecord | None = None
    penalty: PenaltyRecord | None = None
    strain_increment: np.ndarray | None = None
    # the energy ledger's record of the smooth step (fecontact.ledger_records.smooth_record),
    # or None; given as a callable (fecontact.ledger_records.SmoothRecord), it is made when
    # first read
    ledger: np.ndarray | None = None
    # with rtol (fecontact.time.adaptive): a step between two history rows, and the step (s)
    # the control takes next (0: the run's dt)
    substep: bool = False
    h_next: float = 0.0
    # (T, V_strain, V_gravity) of (q, v) in J where the energy guard measured them
    # (fecontact.time.energy_guard), which the recorder then takes as they are; None: not
    energies: tuple[float, float, float] | None = None
    # J: the energy guard's scale so far, the largest T + V_strain of the states it measured
    # (a checkpoint keeps it: a resumed run's guard decides as the whole run's)
    energy_scale: float = 0.0

    @property
    def newton_iterations(self) -> int:
        return sum(self.iterations.values())

    @property
    def force(self) -> np.ndarray:
        """The smooth contact force λ_j of every contact at the end of the step (N; zero
        without the smooth contact of :mod:`fecontact.time.smooth_contact`)."""
        return np.zeros(self.impulse.size) if self.smooth is None else self.smooth.normal

    def pressed(self) -> np.ndarray:
        """Per contact: whether any force acted in the step (ν > 0, Λ > 0 or λ > 0)."""
        # (no candidate at the step's end: the correction gave ν to none, and no smooth force
        # acts; Λ may still sit on a contact a located impact of the step left: kept)
        if self.smooth is None and self.candidates.size == 0:
            return self.impulse > 0.0
        out = self.force > 0.0
        if self.nu.size == out.size:
            out |= self.nu > 0.0
        if self.impulse.size == out.size:
            out |= self.impulse > 0.0
        return out

    def mean_force(self) -> np.ndarray:
        """The mean contact force of every contact over the step, λ + k Λ/h (N)."""
        return self.force + (self.impulse / self.h if self.h > 0 else 0.0)


def _ledger(st: State) -> np.ndarray | None:
    record = st._ledger_record
    if record is not None and not isinstance(record, np.ndarray):
        record = st._ledger_record = record()  # (deferred: made on first read)
    return record


def _set_ledger(st: State, record) -> None:
    st._ledger_record = record


def deferred_ledger(st: State):
    """``st``'s ledger record as it was set: a deferred one (a callable) not yet made."""
    return st._ledger_record


# (after the dataclass is made: its __init__ and the fields' readers go through the property)
State.ledger = property(_ledger, _set_ledger, doc="The energy ledger's record of the step.")


class PhaseTimer(dict):
    """Accumulated wall time per phase (s)."""

    def add(self, phase: str, t0: float) -> float:
        now = time.perf_counter()
        self[phase] = self.get(phase, 0.0) + now - t0
        return now


def initial_state(
    model, q0=None, v0=None, tol_gap: float | None = None, accelerate: bool = True
) -> State:
    """State at t = 0 from q₀, v₀ (default: rest in the reference configuration), with the
    consistent acceleration M v̇₀ = f_ext − f_int(q₀) − C v₀ − f_inertial(q₀, v₀) (damping and
    gyroscopic forces where the model has them). Fixed dofs are kept at zero. A contact may
    start closed within ``tol_gap`` (relative, default the options' default) of the model
    size, the run's own tolerance on gaps. ``accelerate`` false: the input checked, v̇₀ left
    zero (no solve with M: a run solves it with its own solver, which counts the work)."""
    n = model.n
    q = np.zeros(n) if q0 is None else check_vector("q0", q0, n).copy()
    v = np.zeros(n) if v0 is None else check_vector("v0", v0, n).copy()
    fixed = model.free_index < 0
    if np.any(q[fixed] != 0.0) or np.any(v[fixed] != 0.0):
        raise InputError("q0, v0: supported (fixed) dofs must start at zero")
    model.contacts.set_time(0.0)
    g = model.contacts.gaps(q)
    tol_gap = IntegratorOptions.tol_gap if tol_gap is None else tol_gap
    tol = tol_gap * length_scale(model, q)
    admitted = admissible_gaps(model.contacts, q, g)  # a weighted gap's stand-off admits
    if np.any(admitted < -tol):
        j = int(np.argmin(admitted))
        raise InputError(
            f"initial configuration: contact {j} penetrates by {-admitted[j]:.3e} m "
            "(gap must be >= 0)"
        )
    if np.any(g < -tol):
        warnings.warn(
            f"initial configuration: weighted gaps read down to {np.min(g):.3e} m with no node "
            "inside (the discretization's stand-off): the first step moves the bodies apart "
            "by it",
            stacklevel=2,
        )
    vd = _acceleration(model, q, v, tol, accelerate)
    m = model.contacts.size
    return State(
        0.0,
        q,
        v,
        vd,
        vd.copy(),
        gaps=g,
        nu=np.zeros(m),
        impulse=np.zeros(m),
        lam=np.zeros(model.joints.size),
    )


def _acceleration(model, q, v, tol: float, accelerate: bool) -> np.ndarray:
    """v̇₀ of :func:`initial_state` (zero unless ``accelerate``), once the joints are checked
    to hold within ``tol``."""
    alpha, beta_k = model.damping
    _, fint, K = model.internal(q, tangent=bool(alpha or beta_k))
    F = model.free
    f = model.external(0.0)[F] - fint[F]
    if alpha or beta_k:
        f -= (alpha * model.M + beta_k * K) @ v[F]
    if model.inertial_bodies:  # the gyroscopic forces of rotating bodies
        f -= inertial_forces(model, q, v, tangent=False)[0]
    vd = np.zeros(model.n)
    joints = model.joints
    if joints.size:
        gb, Gb = joints.jacobian(q, joints.all)
        if np.max(np.abs(gb)) > tol or np.max(np.abs(Gb @ v[F])) > tol:
            raise InputError("initial configuration: a joint is violated by q0 or v0")
        if accelerate:  # consistent acceleration: G_b v̇ = −vᵀ ∇²g_b v
            x = factorize(bordered(model.M, Gb), solver=model.solver)
            vd[F] = x(np.r_[f, -joints.quadratic(q, v)])[: len(F)]
    elif accelerate:
        vd[F] = model.solve_M(f)
    return vd


def length_scale(model, q) -> float:
    """The length (m) gap tolerances are relative to: the model size, or the magnitude of the
    coordinates when larger (a ball dropped from 5000 m reaches the ground with q ≈ −5000 m,
    and its gap, computed from coordinates, then carries a round-off of ε·5000 m ≈ 1e-12 m)."""
    return max(model.length, model.coordinate_extent(q))


class JointTolerance:
    """The joints' tolerance tol_gap × length_scale(model, q) at the predictor q, evaluated
    only when a test is not already decided by its lower bound tol_gap × model.length
    (length_scale is at least the model size): most steps then never compute the
    coordinates' extent, and every test decides as with the exact value."""

    def __init__(self, model, q: np.ndarray, tol_gap: float):
        self.model, self.q, self.tol_gap = model, q.copy(), tol_gap
        self.low = tol_gap * model.length
        self.value = None

    def admits(self, x: float, factor: float = 1.0) -> bool:
        """Whether x ≤ factor × the tolerance."""
        if x <= factor * self.low:
            return True
        if self.value is None:
            self.value = self.tol_gap * length_scale(self.model, self.q)
        return x <= factor * self.value
