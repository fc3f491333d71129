r"""Steps of beams that create energy, taken again with generalized-α's most damping.

A beam struck with the obstacle's normal partly along its axis (the founding strip's tip on a
floor or a tilted wall) rings in its axial mode, the tip mass on the last element, far above
the step (hω ≈ 16 at h = 1 ms). Generalized-α at ρ∞ = 0.5 damps that mode by about half a
step on a linear model, but the strip's geometric stiffness couples it to the bending and the
nearly massless rotations, and the step's energy T + V swings by tens of millijoules from
one step to the next: over the strike, the floor pendulum at e_N = 1 creates 13 % of its scale
and the tilted wall 12 %, the flexible pendulum hitting at 24.7 m/s all of its kinetic
energy (docs/validation/stress_2d.md, docs/explanation/stability.md).

The rule, a property of the step rather than of the model: with fixed obstacles and no loads
but gravity, contacts, friction, joints and damping do no positive work, so a step of the
NSGA integrator whose total energy E = T + V_strain + V_gravity rises by more than ``GAIN``
of the run's scale (the largest T + V_strain so far, the energy ledger's scale; ``GAIN`` is
its warning level) made that energy itself. Such a step is taken again from the same state

- at ρ∞ = 0 (α_m = −1, α_f = 0, γ = 3/2, β = 1: the unresolved modes annihilated in one step,
  still second order in the resolved ones), and
- located at the instant a contact closes within it (:func:`~.localize.localized_step`): a
  closing taken at the step's end is corrected in the step's metric, which on a strip struck
  along its axis leaves strain the impact did not have (7 % of the floor pendulum's scale).

The ρ∞ = 0 step is no energy-decaying scheme on a nonlinear strip: a retake that still raises
the energy above the level is taken once more as two halves at ρ∞ = 0, and of the two the end
that holds less energy is kept (``energy_retake_halves``; the floor pendulum at e_N = 1 with
``localize=1``: 7.3 % of its scale created with the whole retake, 0.19 % so).

The retake keeps the state the step started from (q, v, v̇ and the acceleration variable a:
the recursion of a at ρ∞ = 0, a_{n+1} = (v̇_{n+1} + a_n)/2, takes a_n as it is), and the run
goes on at its own ρ∞ from the retake's end. A retaken step is counted
(``energy_retakes`` in ``summary.json``), and what the retake still creates stays in the
ledger. Steps that create nothing are never retaken: runs without such a step are the same
to the bit.

The level is never below the gravity potential's round-off (:func:`round_off`, ε times the
model's weight times its size, decided once): the scale holds T + V_strain, but E holds
V_gravity, which a beam lying at rest on a plane moves by 1e-41 to 5e-38 J a step
(displacements of 1e-38 m) against a scale of 1e-61 J; such steps were retaken.

A closing along a beam (a rod's far end slapping onto the floor, a disk dropped on a strip)
is the other such step: the smooth step carries the node through the obstacle, and the
correction that pushes it out at the step's end strains the beam by more than the impact
takes from the motion (``rod_drop`` at e_N = 1: +27.3 mJ of strain against 18.1 mJ of
kinetic energy, 2.0 % of the run's scale); located at its closing, the retake leaves no
such strain.

So is a beam's node closing on a solid's face: a steel strip pressed by an elastic disk onto
a block of 10 cm cells rocks on the two segments of its face, and the corrections of its
nodes' closings created 0.90 % of the run's scale; retaken, 1.9e-4
(docs/validation/stress_2d.md). In space, solids beside beams are left as they were: a block
settling from rest on two clamped rods took 5 retakes, and its slide along them afterwards
dissipated its launch energy to 1.5e-3 instead of 1.5e-6 (docs/explanation/energy_ledger.md).

Decided once (:func:`guards`, option ``energy_retakes``): models with beams (planar or in
space: the strip struck against a floor as a ``Beam3D`` takes the planar one's path, and
its retakes; planar solids beside them or not), contacts on fixed obstacles or between the bodies,
no loads besides gravity, the generalized-α scheme at any ρ∞ (at ρ∞ = 0 the retake is the
step located at its closing, and its halves); under "auto" (the default) also the smooth
contact force (the default of beams; the decoupled step is left as it is, for comparison);
``energy_retakes=0`` turns it off.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..energy import StateEnergies
from ..errors import InputError
from .localize import localized_step
from .settings import RunSettings
from .state import State, length_scale

__all__ = ["GAIN", "EnergyGuard", "check_retakes", "guards", "round_off"]

GAIN = 1e-3
"""Fraction of the run's scale: a step whose energy rises by more is taken again (the energy
ledger's warning level, :data:`fecontact.ledger.CREATED`). The founding case (e_N = 0) has
no step above it; the strikes along the axis have gains of 2-13 % of the scale in a step."""


def round_off(model) -> float:
    """The round-off of the gravity potential V_gravity = −f_gᵀq of ``model`` (J), decided
    once per run: ε times its weight W (the gravity loads on its translations) times the
    length its positions are resolved against (the model's size, or its coordinates' extent
    where larger: :func:`~.state.length_scale`), as a node at x = X + u is resolved to ε|x|.
    The 200-element strip lying on a plane (W = 7.7 N, 1 m): 1.7e-15 J."""
    ones = np.ones(model.dim)
    moves = np.concatenate([b.translation_field(ones) for b in model.bodies]) != 0
    weight = float(np.abs(model.f_gravity[moves]).sum())
    return float(np.finfo(float).eps) * weight * length_scale(model, np.zeros(model.n))


def guards(model, settings: RunSettings) -> bool:
    """Whether the steps of a run of ``model`` with ``settings`` are checked for the energy
    they create (module docstring)."""
    chosen = settings.energy_retakes
    if not chosen or settings.integrator != "nsga" or settings.scheme != "generalized-alpha":
        return False
    # (ρ∞ = 0 too: its retake differs from the step by locating the closing, and the
    # founding pendulum at h = 1e-2 creates 11 times its peak kinetic energy without it)
    if not model.slender or _solids_in_space(model):
        return False
    contacts = model.contacts
    if not contacts.size or contacts.moving or model.loads:
        return False
    if chosen is True:
        return True
    # "auto": not the decoupled step, whose lasting contacts create energy that falls with h
    # (docs/explanation/energy_ledger.md), kept for comparison; a beam struck at its end
    # (its axial ringing) and a beam met along its length, whose closing corrected at the
    # step's end strains it (rod_drop at e_N = 1: 2.0 % of its scale → 0.041 %)
    return settings.smooth


def _solids_in_space(model) -> bool:
    # a beam's closings on a planar solid are judged (the strip on a coarse block); in space
    # the block settling on rods is not improved by them (module docstring)
    return model.continuum and model.dim == 3


def check_retakes(model, options) -> None:
    """``InputError`` where ``energy_retakes`` is true (on) but the rule cannot judge the
    steps of ``model`` with ``options``: another integrator or scheme, a model without
    beams or with solids in space, moving obstacles or loads (whose work raises the
    energy). "auto" and off are taken as they are: "auto" decides for the model (:func:`guards`)."""
    if options.energy_retakes is not True:
        return
    why = None
    if options.integrator != "nsga" or options.scheme != "generalized-alpha":
        why = f"not integrator {options.integrator!r} with scheme {options.scheme!r}"
    elif not model.slender or _solids_in_space(model):
        why = "the model must have beams, and no solid unless it is planar"
    elif model.contacts.moving or model.loads:
        why = "moving obstacles and loads do work that raises the energy"
    if why:
        raise InputError(
            "energy_retakes = true applies to the nsga integrator's generalized-alpha step on "
            f"models of beams with contacts on fixed obstacles and no loads: {why} (set "
            "energy_retakes=auto or 0)"
        )


class EnergyGuard:
    """The energy check of one run's steps: ``held(stepper, st, end, h, timer, depth)`` returns
    ``end``, the step from ``st`` over ``h`` (s), or, where it raised the energy by more than
    ``GAIN`` of the scale, the step taken again by ``stepper`` with ``settings`` (ρ∞ = 0)
    and ``kind`` (located at its closings)."""

    def __init__(self, model, settings: RunSettings):
        self.measure = StateEnergies(model)
        # (the same statistics, plan and traits: only the coefficients change)
        # (and a predictor that turns a beam node too far starts at constant velocity)
        self.settings = dataclasses.replace(settings, rho_inf=0.0, coasts=True)
        self.kind = localized_step
        self.scale = 0.0  # J: the largest T + V_strain of the run's states
        self.floor = round_off(model)  # J: the least gain judged (module docstring)
        self.last: tuple[State, float] | None = None  # the last state measured, its E (J)

    def energy(self, st: State) -> float:
        """E = T + V_strain + V_gravity of ``st`` (J); the state keeps the three energies
        (``State.energies``) for the run's recorder."""
        if self.last is not None and self.last[0] is st:
            return self.last[1]
        kinetic, strain, gravity = st.energies = self.measure(st.q, st.v)
        self.last = (st, kinetic + strain + gravity)
        return self.last[1]

    def accepted(self, st: State) -> State:
        """``st`` as a state of the run: the scale takes its T + V_strain, and the state the
        scale so far (``State.energy_scale``, which a checkpoint keeps: a resumed run's
        first state carries that of the states before it)."""
        kinetic, strain, _ = st.energies
        self.scale = st.energy_scale = max(self.scale, st.energy_scale, kinetic + strain)
        return st

    def reach(self, end: State) -> float:
        """The scale with the end of the step measured (J), as the ledger's own scale holds
        every state it judges: a run started from rest has a scale of 0 before its first
        step, and a first step at ρ∞ = 0 whose energy rose by 3e-9 J against the 7e-6 J of
        kinetic energy it ends with was retaken, and halved."""
        kinetic, strain, _ = end.energies
        return max(self.scale, kinetic + strain)

    def level(self, end: State) -> float:
        """The gain (J) above which the step to ``end`` created energy: ``GAIN`` of the scale
        with ``end`` measured (:meth:`reach`), and never below the round-off ``floor``."""
        return max(GAIN * self.reach(end), self.floor)

    def held(
        self, stepper, st: State, end: State, h: float, timer, depth: int = 0, damped=False
    ) -> State:
        """``end``, or the step from ``st`` taken again where ``end`` created energy (with the
        halvings left below ``depth``); an ``end`` taken ``damped`` already (a step refused for
        a turn: module turns) is its own retake, the same computation."""
        before = self.energy(st)
        self.accepted(st)  # (the run's first state, or a resumed run's)
        if self.energy(end) - before <= self.level(end):
            return self.accepted(end)
        stats = self.settings.stats
        stats.energy_retakes += 1
        retake = end if damped else stepper.step(st, h, timer, depth, damped=True)
        after = self.energy(retake)
        if after - before > self.level(retake) and depth < self.settings.max_halvings:
            # (still gaining: two halves at ρ∞ = 0, and the end that holds less energy)
            stats.energy_retake_halves += 1
            halves = stepper.halves(st, h, timer, depth, damped=True)
            if self.energy(halves) < after:
                retake = halves
            else:
                self.energy(retake)  # (its energies again the last measured)
        return self.accepted(retake)
