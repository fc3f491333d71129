r"""The energy ledger of a run: where the energy went, step by step.

With E = T + V_strain + V_gravity (J) of the bodies, every step closes

    E(t) − E(0) = W_loads − D_damping − D_friction − D_impact − D_numerical,

- W_loads: the work of the external loads other than gravity (trapezoidal in q, exact for
  constant loads; gravity is in V_gravity);
- D_damping: the mean of C v at both ends of the step times h times the mean velocity,
  C = αM + βK(q) (Rayleigh);
- D_friction: the energy the tangential forces and impulses take, as each stepper measures
  it (force × slip of the step; for the impulses of a jump or of a Moreau–Jean step, the
  work along a process in which friction opposes the slip,
  :func:`fecontact.contact.restitution.friction_dissipation`);
- D_impact: the rest of what the contact phase of a step changes. NSGA: the energy change
  of the position correction and of the velocity jump (with the acceleration follow-ups)
  that friction does not explain, and the change of T of the velocities that hold the
  angular momentum through the correction (:mod:`fecontact.time.momentum_rigid`; named
  ``momentum_hold``); Moreau–Jean: −P·G v_mid of the normal and tangential impulses that
  friction does not explain; penalty: −½(λ_n + λ_{n+1})·Δg, the contact forces' work;
- D_numerical: the term that closes the identity, the time integrator's own dissipation (for
  NSGA: that of the smooth step, ρ∞ < 1).

D(t) = E(0) + W_loads(t) − E(t) is everything lost; it may only grow, up to the discrete
energy's own oscillation (and, for the penalty baseline, less the energy ½ k δ² its
contact springs hold for the rebound). ``created`` is its largest fall below its running
maximum, ``scale`` the largest T + V_strain of the run: a creation above 1e-3 of the scale
is a warning naming the time, step and phase of the step whose own fall of D was the
largest (the phase: that step's with the largest gain). Friction that does positive work
beyond 1e-6 of the scale is one too, naming the contacts. Moving obstacles do work that
lands in D_impact: their runs report the ledger but no creation warning.
"""

from __future__ import annotations

import math

import numpy as np

from .ledger_works import damping_force, damping_step_work, moreau_works, spring_step_work

__all__ = [
    "EnergyLedger",
    "JoinedRecord",
    "SmoothRecord",
    "joined_record",
    "pending_record",
    "smooth_end",
    "smooth_record",
]

# a creation above this fraction of the scale is a warning (the gains measured on the shipped
# cases before the ledger were 0.3 % and more); friction's positive work above FRICTION of it
CREATED = 1e-3
FRICTION = 1e-6
# ... and above the round-off of the energies summed (a body at rest has a scale of zero):
# this fraction of the largest of the scale, |E(0)| and the weight times the model's size
ROUND_OFF = 1e-9
TERMS = ("load_work", "damping", "friction", "impact", "numerical")
NO_WORK = np.zeros(3)  # a step without impulses: (normal, tangential, joints) works
NO_WORK.flags.writeable = False
# the record of a step whose contact phase moved neither q nor v and did no work
NOTHING_MOVED = np.array([math.nan, math.nan, 0.0, 0.0, 0.0, 0.0])
NOTHING_MOVED.flags.writeable = False
JUMPS = ("velocity jump", "impact")  # the phases that are velocity jumps (NSGA, Moreau–Jean)
# what a creation in the position correction of contacts that closed within the step adds
CLOSING = (
    ", of {} that closed within the step: the strain the correction leaves pushing them out "
    "of the obstacle is energy the impact did not have (localize=1 takes a closing at its "
    "instant)"
)
# the phase of a smooth step taken again without the forces of the contacts it releases
RELEASE = "smooth step's retake without the forces of the contacts it releases"
# the phase of the velocities that hold the angular momentum through the correction
HOLD = "momentum hold"


def smooth_record(
    model, contact_phase, v_tilde, q_tilde=None, friction_work=0.0, works=None, release=0.0,
    held=None,
) -> np.ndarray | None:  # fmt: skip
    """What a stepper leaves in its state (``State.ledger``) for the ledger after its smooth
    step, when a ``contact_phase`` (correction or jump) may follow: the kinetic energy of
    ṽ (NaN when ``v_tilde`` is None: no correction and no jump moved v, then it is that of
    the step's end), the potential (strain + gravity) energy of q̃ (NaN when no correction
    moved q: then it is that of the step's end), the work the smooth step's friction forces
    dissipated, the velocity jump's ``works`` (normal, tangential, joints;
    :func:`fecontact.ledger_works.jump_work`) and the energy the smooth step's retake
    without the forces of the contacts it releases added over its first try (``release``)
    and the momentum hold's change of T, T(ṽ + ``held``) − T(ṽ) (J). Without a contact
    phase, None."""
    if not contact_phase:
        return None
    V = math.nan
    if q_tilde is not None:
        V = model.strain_energy(q_tilde) + model.potential_energy(q_tilde)
    works = (0.0, 0.0, 0.0) if works is None else works
    T = math.nan if v_tilde is None else model.kinetic_energy(v_tilde)
    record = [T, V, friction_work, *works]
    hold = 0.0 if held is None else model.kinetic_energy(v_tilde + held) - T
    tail = [release, hold] if hold else [release] if release else []
    return np.array(record + tail)


class SmoothRecord:
    """The record of :func:`smooth_record` for the state of one step, made when it is first
    read (``State.ledger`` calls it): the energies of ṽ and q̃ are sparse products and
    element sums that a run which never reads the ledger (``simulate`` without the recorder)
    need not pay for. q̃ and ṽ are the step's own arrays, which no later phase changes, and
    a body's energy is a function of its q alone, so the values are the same numbers at
    whatever time they are made."""

    __slots__ = ("model", "v_tilde", "q_tilde", "friction_work", "works", "release", "held")

    def __init__(self, model, v_tilde, q_tilde, friction_work: float, works, release, held):
        self.model, self.v_tilde, self.q_tilde = model, v_tilde, q_tilde
        self.friction_work, self.works, self.release = friction_work, works, release
        self.held = held

    def __call__(self) -> np.ndarray:
        return smooth_record(
            self.model,
            True,
            self.v_tilde,
            self.q_tilde,
            self.friction_work,
            self.works,
            self.release,
            self.held,
        )


def pending_record(
    model, contact_phase, v_tilde, q_tilde=None, friction_work=0.0, works=None, release=0.0,
    held=None,
):  # fmt: skip
    """:func:`smooth_record` of the same arguments, its energies made when it is first read:
    a :class:`SmoothRecord` where it has an energy to compute, else the record itself (None
    without a contact phase)."""
    if not contact_phase or (v_tilde is None and q_tilde is None):
        # (a +0.0 friction work: a −0.0 the record keeps)
        plus_zero = friction_work == 0.0 and math.copysign(1.0, friction_work) > 0.0
        if contact_phase and works is None and not release and plus_zero:
            return NOTHING_MOVED  # (most steps with candidates: shared, read-only)
        return smooth_record(model, contact_phase, None, None, friction_work, works, release)
    return SmoothRecord(model, v_tilde, q_tilde, friction_work, works, release, held)


def smooth_end(record) -> tuple | None:
    """(q̃ or None, ṽ) of a step's ledger record not yet made (``deferred_ledger``), where a
    correction or a jump moved v after the smooth step; None where it does not keep them."""
    if isinstance(record, SmoothRecord) and record.v_tilde is not None:
        return record.q_tilde, record.v_tilde
    return None


def joined_record(model, first, second) -> np.ndarray | None:
    """The record (:func:`smooth_record`) of one step made of the steps that end in
    ``first`` and ``second`` (a halved step, an impact located inside a step): the contact
    phases of both are the step's, so that the ledger charges them as such. With the first
    part's end energies T_1, V_1 and T̃_i, Ṽ_i the parts' smooth ends, T̃ = T̃_2 − (T_1 − T̃_1),
    Ṽ = Ṽ_2 − (V_1 − Ṽ_1); the smooth friction and the jumps' works add."""
    return _joined(model, first, second.ledger, second.v, second.q)


class JoinedRecord:
    """:func:`joined_record` of the parts ``first`` and ``second``, made when it is first
    read (``State.ledger`` calls it), as :class:`SmoothRecord`: a run that never reads the
    ledger does not pay the parts' energies. ``record``: ``second``'s record as it was set
    (a deferred one not yet made; the part's ``ledger`` becomes this one); the parts'
    arrays are kept, which no later phase changes."""

    __slots__ = ("model", "first", "record", "v", "q")

    def __init__(self, model, first, second, record):
        self.model, self.first, self.v, self.q = model, first, second.v, second.q
        self.record = record

    def __call__(self) -> np.ndarray | None:
        record = self.record
        if record is not None and not isinstance(record, np.ndarray):
            record = record()
        return _joined(self.model, self.first, record, self.v, self.q)


def _joined(model, first, r2, v2, q2) -> np.ndarray | None:
    """:func:`joined_record` of ``first`` and a second part with the record ``r2`` that
    ends at (``q2``, ``v2``)."""
    r1 = first.ledger
    if r1 is None:
        return r2
    # T_1 − T̃_1 and V_1 − Ṽ_1: zero, not evaluated, where the first part ends where its
    # smooth step does (NaN)
    dT = 0.0 if math.isnan(r1[0]) else model.kinetic_energy(first.v) - r1[0]
    dV = 0.0
    if not math.isnan(r1[1]):
        dV = model.strain_energy(first.q) + model.potential_energy(first.q) - r1[1]
    if r2 is None:  # the second part has no contact phase: it ends where its smooth step does
        r2 = smooth_record(model, True, v2, q2)
    else:  # (NaN: the smooth step's end is the part's end, and stays the step's where d = 0)
        r2 = r2.copy()
        if math.isnan(r2[0]) and dT:
            r2[0] = model.kinetic_energy(v2)
        if math.isnan(r2[1]) and dV:
            r2[1] = model.strain_energy(q2) + model.potential_energy(q2)
    out = np.zeros(max(r1.size, r2.size, 6))
    out[: r2.size] = r2
    out[0] = r2[0] - dT
    out[1] = r2[1] - dV
    out[2] = r1[2] + r2[2]
    out[3:6] += r1[3:6] if r1.size >= 6 else 0.0
    if r1.size > 6:  # the first part's release and momentum hold
        out[6 : r1.size] += r1[6:]
    return out


class EnergyLedger:
    """The ledger of one run (J): cumulative terms, ``created`` and ``scale``."""

    FIELDS = ("initial", "created", "scale", "peak", "lost", "positive_friction", "energy")

    def __init__(self, model, options):
        self.model = model
        self.integrator = options.integrator
        self.checked = not model.contacts.moving
        self.damped = any(model.damping)
        self.terms = dict.fromkeys((*TERMS, "hold"), 0.0)  # hold: the momentum hold's share
        self.initial = math.nan
        self.energy = math.nan  # E of the last state
        self.created = 0.0
        self.scale = 0.0
        self.peak = -math.inf  # the running maximum of D
        self.lost = math.nan  # D of the last state
        self.positive_friction = 0.0
        self.Cv = None  # the damping force the next step starts with (free dofs, N)
        # the weight times the model's size (J): an energy scale for a body that rests
        self.slack = float(np.abs(model.f_gravity).sum()) * model.length
        self.worst = None  # (fall of D, t, step, phase) since the last running maximum
        self.where = None  # ... of the largest creation
        self.friction_where = None  # (work, t, step, contacts) of friction's largest gain
        self.impact_work = np.zeros(3)  # the jumps' (normal, tangential, joints) works
        self.last = None  # the previous state

    # -- the state of a step -----------------------------------------------------------------

    def start(self, st) -> None:
        """Take ``st`` as the previous state (a run's start, or a resumed run's)."""
        self.last = st
        kinetic, strain, gravity = self._energies(st)
        self.energy = kinetic + strain + gravity
        if math.isnan(self.initial):
            self.initial = self.energy
            self.peak = 0.0
            if st.ledger is not None:  # an impact at t = 0: the run was given T(v₀⁻)
                _initial_jump(self, st, kinetic)
        if math.isnan(self.lost):
            self.lost = self.initial + self.terms["load_work"] - self.energy
        if self.damped and self.Cv is None:  # (a checkpoint keeps the force v̇ carries)
            self.Cv = damping_force(self.model, st.q, st.v)

    def add(self, st, kinetic, strain, gravity, load_work, smooth_end=None) -> None:
        """Account for the step that ended in ``st`` with its energies (J) and the loads'
        work since t = 0 (J); ``smooth_end`` (q̃ or None, ṽ), where known, the end of the
        smooth step that a velocity jump followed (:func:`smooth_end`)."""
        if self.last is None:
            self.start(st)
            self.scale = max(self.scale, kinetic + strain)
            return
        E = kinetic + strain + gravity
        dE, W = E - self.energy, load_work - self.terms["load_work"]
        damping = 0.0
        if self.damped:
            args = (self.model, self.last, st, self.Cv, smooth_end)
            damping, self.Cv = damping_step_work(*args)
        friction = self._friction(st)
        impact, gains, works = self._impact(st, kinetic, E, W, damping, friction)
        if works is not NO_WORK:
            self.impact_work += works
        numerical = W - dE - damping - friction - impact
        for k, x in zip(TERMS, (W, damping, friction, impact, numerical), strict=True):
            self.terms[k] += x
        self.energy = E
        self.scale = max(self.scale, kinetic + strain)
        gains.setdefault("smooth step" if self.integrator == "nsga" else "time step", -numerical)
        self._track(st, E, gains, friction, float(works[1]))
        self.last = st

    def _energies(self, st):
        m = self.model
        return m.kinetic_energy(st.v), m.strain_energy(st.q), m.potential_energy(st.q)

    def _springs(self, st) -> float:
        """½ k δ² of the penalty baseline's contact springs (J), 0 for the other steppers."""
        k = None if st.penalty is None else st.penalty.k
        if self.integrator != "penalty" or k is None or st.gaps.size != k.size:
            return 0.0
        delta = np.maximum(-st.gaps, 0.0)
        return float(0.5 * np.sum(np.nan_to_num(k) * delta**2))

    def _friction(self, st) -> float:
        now, before = st.friction, self.last.friction
        if now is None:
            return 0.0
        return float(now.work) - (0.0 if before is None else float(before.work))

    def _impact(self, st, kinetic, E, W, damping, friction):
        """D_impact of the step ending in ``st`` (J) and the energy gains of its phases."""
        record = st.ledger
        if record is not None:  # NSGA: the smooth step's end (ṽ, q̃)
            T_tilde, V_tilde, smooth_friction = record[:3].tolist()
            V = E - kinetic
            if math.isnan(V_tilde):
                V_tilde = V
            if math.isnan(T_tilde):
                T_tilde = kinetic
            works = record[3:6] if record.size >= 6 else NO_WORK
            correction, jump = V - V_tilde, kinetic - T_tilde
            smooth = T_tilde + V_tilde - self.energy - W + damping + smooth_friction
            release = float(record[6]) if record.size > 6 else 0.0
            hold = float(record[7]) if record.size > 7 else 0.0  # (of D_impact: its share)
            jump, self.terms["hold"] = jump - hold, self.terms["hold"] - hold
            gains = {
                "smooth step": smooth - release,
                RELEASE: release,
                "position correction": correction,
                "velocity jump": jump,
                **({HOLD: hold} if hold else {}),  # (a phase only where a hold moved v)
                "friction": -friction,
            }
            return -(correction + jump + hold) - (friction - smooth_friction), gains, works
        works = NO_WORK
        if self.integrator == "moreau" and np.any(st.impulse):
            works = moreau_works(self.model, self.last, st)
            impact = -works[0] - works[1] - friction
        elif self.integrator == "penalty" and (np.any(st.impulse) or np.any(self.last.impulse)):
            impact = spring_step_work(self.last, st)
        else:
            impact = 0.0
        return impact, {"impact": -impact, "friction": -friction}, works

    # -- creation ----------------------------------------------------------------------------

    def _track(self, st, E, gains, friction, slip_work) -> None:
        D = self.initial + self.terms["load_work"] - E - self._springs(st)
        fall = self.peak - D
        # the step's own fall of D names it: a step whose correction gains what its jump
        # loses made nothing; the phase named is the one of the step that gained the most
        step_fall, self.lost = self.lost - D, D
        if D >= self.peak:
            self.peak, self.worst = D, None
        elif fall > 0.0:
            if self.worst is None or step_fall > self.worst[0]:
                phase = max(gains, key=gains.get)
                named = _jump_gripping(st) if slip_work > 0.0 else []
                if phase == "position correction":
                    named = _closing(self.last, st)
                self.worst = (step_fall, st.t, st.step, phase, slip_work, named)
            if fall > self.created:
                self.created, self.where = fall, self.worst
        if friction < 0.0:
            self.positive_friction -= friction
            if self.friction_where is None or -friction > self.friction_where[0]:
                self.friction_where = (-friction, st.t, st.step, _gripping(st))

    @property
    def dissipation(self) -> float:
        """D(t) = E(0) + W_loads − E(t) (J)."""
        return self.initial + self.terms["load_work"] - self.energy

    def row(self) -> list[float]:
        """The history columns ``fecontact.io.output.LEDGER_COLUMNS`` of the last state (J,
        since t = 0)."""
        return [self.terms[k] for k in TERMS]

    def summary(self, kinetic: float, strain: float, gravity: float) -> dict:
        """``summary.json``'s ``energy_ledger``: the energies of the last state and the
        terms since t = 0 (J)."""
        t = self.terms
        return {
            "kinetic": kinetic,
            "strain": strain,
            "gravity": gravity,
            "load_work": t["load_work"],
            "damping_dissipation": t["damping"],
            "friction_dissipation": t["friction"],
            "impact_dissipation": t["impact"],
            "numerical_dissipation": t["numerical"],
            "momentum_hold": t["hold"],
            "created": self.created,
            "scale": self.scale,
        }

    def _limit(self, fraction: float) -> float:
        return fraction * self.scale + ROUND_OFF * max(self.scale, abs(self.initial), self.slack)

    def warnings(self) -> list[str]:
        """The run's energy warnings (each begins with "energy")."""
        out = []
        if self.checked and self.created > self._limit(CREATED) and self.where is not None:
            _, t, step, phase, slip_work, contacts = (*self.where, 0.0, [])[:6]
            text = (
                f"energy: the run created {self.created:.3g} J ({self.created / self.scale:.2%}"
                f" of its largest kinetic plus strain energy, {self.scale:.3g} J); the step "
                f"that made most of it: t = {t:.6g} s, step {step}, in the {phase}"
            )
            if phase in JUMPS and slip_work > self._limit(FRICTION):
                text += (
                    f", where friction did positive work: its impulses P_T times the mean slip "
                    f"(v_T⁻ + v_T⁺)/2 gave {slip_work:.3g} J at {self._named(contacts)}; "
                    "Newton's kinematic restitution with Coulomb friction is not energetically "
                    'consistent, Poisson\'s law is (impact_law="poisson")'
                )
            if phase == "position correction" and contacts:
                text += CLOSING.format(self._named(contacts))
            out.append(text)
        if self.positive_friction > self._limit(FRICTION):
            work, t, step, contacts = self.friction_where
            out.append(
                f"energy: friction did {self.positive_friction:.3g} J of positive work, "
                f"most ({work:.3g} J) at t = {t:.6g} s, step {step}, at contact(s) "
                f"{', '.join(map(str, contacts))}"
            )
        return out

    def _named(self, contacts) -> str:
        """``contacts`` as "contact(s) j (pair i)", j over the model's contacts."""
        owner = self.model.contacts.owner
        named = [f"{j} (pair {owner[j]})" for j in contacts]
        return f"contact(s) {', '.join(named)}" if named else "no contact"

    def impact_works(self) -> dict:
        """``summary.json``'s ``impact_work``: the impulses of the velocity jumps times the
        mean of the rates before and after each (J, since t = 0), normal, tangential and of
        the joints (:func:`fecontact.contact.restitution.impulse_work`)."""
        keys = ("normal", "tangential", "joints")
        return dict(zip(keys, map(float, self.impact_work), strict=True))

    def state(self) -> dict:
        """What a checkpoint keeps: the totals and where the creations were."""
        out = {k: getattr(self, k) for k in self.FIELDS}
        places = {k: getattr(self, k) for k in ("worst", "where", "friction_where")}
        out["impact_work"] = self.impact_work.tolist()
        out["damping_force"] = None if self.Cv is None else self.Cv.tolist()
        return out | {f"term_{k}": v for k, v in self.terms.items()} | places

    def restore(self, values: dict) -> None:
        for k in self.FIELDS:
            if k in values:
                setattr(self, k, float(values[k]))
        for k in self.terms:
            self.terms[k] = float(values.get(f"term_{k}", self.terms[k]))
        if "impact_work" in values:
            self.impact_work = np.array(values["impact_work"], dtype=float)
        if values.get("damping_force") is not None:
            self.Cv = np.array(values["damping_force"], dtype=float)
        for k in ("worst", "where", "friction_where"):
            if values.get(k) is not None:
                setattr(self, k, tuple(values[k]))


def _initial_jump(ledger: EnergyLedger, st, kinetic: float) -> None:
    """Book the velocity jump of a run's start (:func:`fecontact.time.impacts.impact_start`)
    in ``ledger``: E(0) is the energy before it, the jump's change is the impact's."""
    jump = kinetic - float(st.ledger[0])
    ledger.initial -= jump
    ledger.terms["impact"] -= jump
    ledger.impact_work += st.ledger[3:6]
    ledger.lost = 0.0
    ledger._track(st, ledger.energy, {"velocity jump": jump}, 0.0, float(st.ledger[4]))


def _closing(last, st) -> list[int]:
    """The contacts the position correction of the step ``st`` pushed out that no force
    pressed in the step before (``last``): they closed within the step."""
    if last is None or st.nu.size != st.impulse.size or last.impulse.size != st.nu.size:
        return []
    return np.flatnonzero((st.nu > 0.0) & ~last.pressed()).tolist()


def _jump_gripping(st) -> list[int]:
    """The contacts that carried a tangential impulse in the contact phase of ``st``."""
    record = st.friction
    if record is None or record.impulse is None:
        return []
    return np.flatnonzero(np.any(record.impulse != 0.0, axis=1)).tolist()


def _gripping(st) -> list[int]:
    """The contacts that carried a tangential force or impulse in the step ``st``."""
    grip = np.zeros(st.impulse.size, bool)
    friction, smooth = st.friction, st.smooth
    arrays = (
        None if friction is None else friction.impulse,
        None if friction is None else friction.nu,
        None if smooth is None else smooth.tangential,
    )
    for x in arrays:
        if x is not None and x.shape[0] == grip.size:
            grip |= np.any(x != 0.0, axis=1)
    return np.flatnonzero(grip).tolist()
