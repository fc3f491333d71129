r"""The energy ledger of a run: where the energy went, step by step.

With E = T + V_strain + V_gravity (J) of the bodies, every step closes

    E(t) − E(0) = W_loads + W_obstacles − D_damping − D_friction − D_impact − D_numerical,

- W_loads: the work of the external loads other than gravity (trapezoidal in q, exact for
  constant loads; gravity is in V_gravity);
- W_obstacles (models with moving obstacles only): the work the contact forces and
  impulses do through the obstacles' motion, −Σ x_N ∂g/∂t + Σ x_T·T ḋ
  (:func:`fecontact.ledger_works.obstacle_work`): the impulses' of NSGA's velocity jump
  and of Moreau–Jean's step, the smooth forces' impulse of NSGA's step (as it moves v) and
  the penalty forces over the gaps' change that the bodies do not make;
- D_damping: the mean of C v at both ends of the step times h times the mean velocity,
  C = αM + βK(q) (Rayleigh);
- D_friction: the energy the tangential forces and impulses take, as each stepper measures
  it (force × slip of the step; for the impulses of a jump or of a Moreau–Jean step, the
  work along a process in which friction opposes the slip,
  :func:`fecontact.contact.restitution.friction_dissipation`);
- D_impact: the rest of what the contact phase of a step changes. NSGA: the energy change
  of the position correction and of the velocity jump (with the acceleration follow-ups)
  that friction and the obstacles' work in the jump do not explain, and the change of T of
  the velocities that hold the angular momentum through the correction
  (:mod:`fecontact.time.momentum_rigid`; named ``momentum_hold``); Moreau–Jean: −P·G v_mid
  of the normal and tangential impulses that friction does not explain (rates relative to
  the obstacles); penalty: −½(λ_n + λ_{n+1})·Δg, the contact forces' work;
- D_numerical: the term that closes the identity, the time integrator's own dissipation (for
  NSGA: that of the smooth step, ρ∞ < 1).

D(t) = E(0) + W_loads(t) + W_obstacles(t) − E(t) is everything lost; it may only grow, up
to the discrete energy's own oscillation (and, for the penalty baseline, less the energy
½ k δ² its contact springs hold for the rebound). ``created`` is its largest fall below
its running maximum, ``scale`` the largest T + V_strain of the run: a creation above 1e-3
of the scale is a warning naming the time, step and phase of the step whose own fall of D
was the largest (the phase: that step's with the largest gain). Friction that does
positive work beyond 1e-6 of the scale is one too, naming the contacts. A moving obstacle
that meets a pair that does not measure its ∂g/∂t would carry the body by the position
correction alone, a work no impulse shows: such runs report the ledger but no creation
warning (:func:`fecontact.ledger_works.unmeasured_motion`).
"""

from __future__ import annotations

import math

import numpy as np

from .ledger_works import (
    closing_contacts,
    damping_force,
    damping_step_work,
    gripping,
    jump_gripping,
    moreau_works,
    obstacle_work,
    penalty_obstacle_work,
    smooth_obstacle_work,
    spring_step_work,
    unmeasured_motion,
)
from .time.generalized_alpha import alpha_coefficients

__all__ = ["EnergyLedger"]

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


class EnergyLedger:
    """The ledger of one run (J): cumulative terms, ``created`` and ``scale``."""

    FIELDS = ("initial", "created", "scale", "peak", "lost", "positive_friction", "energy")

    def __init__(self, model, options):
        self.model = model
        self.integrator = options.integrator
        # a creation is judged unless a moving obstacle's work escapes the ledger
        self.checked = not unmeasured_motion(model)
        self.moving = model.contacts.moving  # (the obstacles' work is a term of the run's)
        # γ of NSGA's smooth step, by which a moves v (smooth_obstacle_work)
        self.gamma = alpha_coefficients(options.rho_inf)[2] if self.moving else 0.5
        self.damped = any(model.damping)
        self.terms = dict.fromkeys(
            (*TERMS, "hold", "obstacle"), 0.0
        )  # hold: the momentum hold's share
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
            self.lost = self.dissipation
        if self.damped and self.Cv is None:  # (a checkpoint keeps the force v̇ carries)
            self.Cv = damping_force(self.model, st.q, st.v)

    def add(self, st, kinetic, strain, gravity, load_work, smooth_end=None) -> None:
        """Account for the step that ended in ``st`` with its energies (J) and the loads'
        work since t = 0 (J); ``smooth_end`` (q̃ or None, ṽ), where known, the end of the
        smooth step that a velocity jump followed (:func:`fecontact.ledger_records.smooth_end`)."""
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
        supplied = W
        if self.moving:  # the obstacles' work (J), and D_impact's share of it
            obstacles, share = self._obstacles(st, gains)
            supplied, impact = W + obstacles, impact + share
            self.terms["obstacle"] += obstacles
        numerical = supplied - dE - damping - friction - impact
        for k, x in zip(TERMS, (W, damping, friction, impact, numerical), strict=True):
            self.terms[k] += x
        self.energy = E
        self.scale = max(self.scale, kinetic + strain)
        gains.setdefault("smooth step" if self.integrator == "nsga" else "time step", -numerical)
        self._track(st, E, gains, friction, float(works[1]))
        self.last = st

    def _obstacles(self, st, gains) -> tuple[float, float]:
        """The work (J) the moving obstacles did in the step ending in ``st`` through the
        contact forces (NSGA's smooth forces, the penalty forces: ``smooth_obstacle_work``,
        ``penalty_obstacle_work`` of :mod:`fecontact.ledger_works`) and impulses (NSGA's
        velocity jump, Moreau–Jean's), and the share of it that D_impact counts: NSGA's
        jump's (Moreau–Jean's D_impact reads the rates relative to the obstacles)."""
        if self.integrator == "penalty":
            smooth = penalty_obstacle_work(self.model, self.last, st)
        else:  # (Moreau–Jean: no smooth force, 0)
            smooth = smooth_obstacle_work(self.model, self.last, st, self.gamma)
        jump = 0.0
        if self.integrator != "penalty" and np.any(st.impulse):
            tangential = None if st.friction is None else st.friction.impulse
            jump = obstacle_work(self.model, st.q, st.impulse, tangential)
        if "velocity jump" not in gains:
            return smooth + jump, 0.0
        gains["velocity jump"] -= jump
        gains["smooth step"] -= smooth
        return smooth + jump, jump

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
        D = self.supplied - E - self._springs(st)
        fall = self.peak - D
        # the step's own fall of D names it: a step whose correction gains what its jump
        # loses made nothing; the phase named is the one of the step that gained the most
        step_fall, self.lost = self.lost - D, D
        if D >= self.peak:
            self.peak, self.worst = D, None
        elif fall > 0.0:
            if self.worst is None or step_fall > self.worst[0]:
                phase = max(gains, key=gains.get)
                named = jump_gripping(st) if slip_work > 0.0 else []
                if phase == "position correction":
                    named = closing_contacts(self.last, st)
                self.worst = (step_fall, st.t, st.step, phase, slip_work, named)
            if fall > self.created:
                self.created, self.where = fall, self.worst
        if friction < 0.0:
            self.positive_friction -= friction
            if self.friction_where is None or -friction > self.friction_where[0]:
                self.friction_where = (-friction, st.t, st.step, gripping(st))

    @property
    def dissipation(self) -> float:
        """D(t) = E(0) + W_loads + W_obstacles − E(t) (J)."""
        return self.supplied - self.energy

    @property
    def supplied(self) -> float:
        """E(0) + W_loads + W_obstacles (J)."""
        return self.initial + self.terms["load_work"] + self.terms["obstacle"]

    def row(self) -> list[float]:
        """The history columns ``fecontact.io.output.LEDGER_COLUMNS`` of the last state (J,
        since t = 0)."""
        row = [self.terms[k] for k in TERMS]
        return [*row, self.terms["obstacle"]] if self.moving else row

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
            **({"obstacle_work": t["obstacle"]} if self.moving else {}),
            "created": self.created,
            "scale": self.scale,
        }

    def _limit(self, fraction: float) -> float:
        return fraction * self.scale + ROUND_OFF * max(self.scale, abs(self.initial), self.slack)

    def warnings(self) -> list[str]:
        """The run's energy warnings (each begins with "energy")."""
        return _warnings(self)

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


def _warnings(self: EnergyLedger) -> list[str]:
    """:meth:`EnergyLedger.warnings` of ``self``."""
    out = []
    if self.checked and self.created > self._limit(CREATED) and self.where is not None:
        _, t, step, phase, slip_work, contacts = (*self.where, 0.0, [])[:6]
        share = f"{self.created / self.scale:.2%} of" if self.scale > 0.0 else "all beyond"
        text = (
            f"energy: the run created {self.created:.3g} J ({share}"
            f" its largest kinetic plus strain energy, {self.scale:.3g} J); the step "
            f"that made most of it: t = {t:.6g} s, step {step}, in the {phase}"
        )
        if phase in JUMPS and slip_work > self._limit(FRICTION):
            text += (
                f", where friction did positive work: its impulses P_T times the mean slip "
                f"(v_T⁻ + v_T⁺)/2 gave {slip_work:.3g} J at {_named(self.model, contacts)}; "
                "Newton's kinematic restitution with Coulomb friction is not energetically "
                'consistent, Poisson\'s law is (impact_law="poisson")'
            )
        if phase == "position correction" and contacts:
            text += CLOSING.format(_named(self.model, contacts))
        out.append(text)
    if self.positive_friction > self._limit(FRICTION):
        work, t, step, contacts = self.friction_where
        out.append(
            f"energy: friction did {self.positive_friction:.3g} J of positive work, "
            f"most ({work:.3g} J) at t = {t:.6g} s, step {step}, at contact(s) "
            f"{', '.join(map(str, contacts))}"
        )
    return out


def _named(model, contacts) -> str:
    """``contacts`` as "contact(s) j (pair i)", j over the model's contacts."""
    owner = model.contacts.owner
    named = [f"{j} (pair {owner[j]})" for j in contacts]
    return f"contact(s) {', '.join(named)}" if named else "no contact"


def _initial_jump(ledger: EnergyLedger, st, kinetic: float) -> None:
    """Book the velocity jump of a run's start (:func:`fecontact.time.impacts.impact_start`)
    in ``ledger``: E(0) is the energy before it, the jump's change is the impact's."""
    jump = kinetic - float(st.ledger[0])
    ledger.initial -= jump
    ledger.terms["impact"] -= jump
    if ledger.moving:  # (the obstacles' work in it, the impact's share: Ledger._obstacles)
        tangential = None if st.friction is None else st.friction.impulse
        work = obstacle_work(ledger.model, st.q, st.impulse, tangential)
        ledger.terms["obstacle"] += work
        ledger.terms["impact"] += work
        jump -= work
    ledger.impact_work += st.ledger[3:6]
    ledger.lost = 0.0
    ledger._track(st, ledger.energy, {"velocity jump": jump}, 0.0, float(st.ledger[4]))
