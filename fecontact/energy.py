"""The energy balance of a run: the energy the initial state and the loads supply, and any
gain beyond it.

With obstacles at rest, contacts, joints, friction and damping do no positive work, so the
total energy E = T + V_strain + V_gravity (J) can rise only by the work W of the loads
(gravity excepted: it is in V_gravity). A gain G = E − E_0 − W > 0 is made by the time
integration. The budget B = E_0 + W − V_gravity = T + V_strain − G is the kinetic plus strain
energy the motion may hold. G > B means that the motion holds more than twice that: the
integration went unstable (the generalized-α step on a stiff nonlinear structure at large
ρ∞, docs/explanation/stability.md). Moving obstacles do work the balance does not
see: for them no gain is reported.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["EnergyBalance", "StateEnergies"]

# A gain of ten budgets is a blow-up under way. The largest gain measured in a run that did
# not blow up is 3.7 budgets: the decoupled scheme on two disks at 4 Δx/c, whose contact is
# then 50 % too long (benchmarks/results/smooth_contact.md)
RUNAWAY = 10.0
# round-off of E − E_0 − W, relative to the energies summed in it
ROUND_OFF = 1e-9
# a gain below this fraction of the weight times the model's size is no sign of instability,
# whatever the budget: a body resting at t = 0 has a budget of zero
SLACK = 1e-3


class EnergyBalance:
    """The work of the loads and the energy gain, step by step (J).

    ``gain`` is the largest E − E_0 − W so far, ``budget`` the largest E_0 + W − V_gravity,
    ``work`` the loads' work (trapezoidal over each step: exact for constant loads).
    """

    FIELDS = ("initial", "work", "gain", "budget", "scale")

    def __init__(self, model):
        self.model = model
        self.checked = not model.contacts.moving
        self.initial = math.nan
        self.work = 0.0
        self.gain = -math.inf
        self.budget = 0.0
        self.scale = 0.0  # the largest T + V_strain + |V_gravity|, for the round-off
        self.now = 0.0  # the current E − E_0 − W
        self.slack = SLACK * float(np.abs(model.f_gravity).sum()) * model.length
        self._q = None
        self._f = None

    def _loads(self, t: float) -> np.ndarray | None:
        if not self.model.loads:
            return None
        return self.model.external(t) - self.model.f_gravity

    def start(self, t: float, q: np.ndarray) -> None:
        """Measure the loads' work from the state (t, q) on (a run's start, a resumed run)."""
        self._f = self._loads(t)
        self._q = None if self._f is None else q.copy()

    def add(self, t: float, q: np.ndarray, kinetic: float, strain: float, gravity: float):
        """Account for the state at time t (s) with its energies (J)."""
        total = kinetic + strain + gravity
        if math.isnan(self.initial):  # the run's first state
            self.start(t, q)
            self.initial = total
        elif self._f is not None:  # (models without loads keep no copy of q)
            f = self._loads(t)
            self.work += 0.5 * float((self._f + f) @ (q - self._q))
            self._q, self._f = q.copy(), f
        self.now = total - self.initial - self.work
        self.gain = max(self.gain, self.now)
        self.budget = max(self.budget, self.initial + self.work - gravity)
        self.scale = max(self.scale, kinetic + strain + abs(gravity), abs(self.work))

    def _limit(self, factor: float) -> float:
        return factor * self.budget + self.slack + ROUND_OFF * self.scale

    def unstable(self) -> bool:
        """The gain exceeded the budget at some state: the energy of the motion doubled."""
        return self.checked and self.gain > self._limit(1.0)

    def runaway(self) -> bool:
        """The current gain exceeds ten budgets: a blow-up under way."""
        return self.checked and self.now > self._limit(RUNAWAY)

    def describe(self) -> str:
        return (
            f"the total energy rose {self.gain:.3g} J above what the initial state and the "
            f"loads supply ({self.budget:.3g} J of kinetic and strain energy): the time "
            "integration is unstable for this model and step (docs: explanation/"
            "stability; a smaller rho_inf or dt)"
        )

    def state(self) -> dict:
        return {k: getattr(self, k) for k in self.FIELDS}

    def restore(self, values: dict) -> None:
        for k in self.FIELDS:
            if k in values:
                setattr(self, k, float(values[k]))

    def summary(self) -> dict:
        """``summary.json``'s ``energy_balance``: gain and budget (J), None when a moving
        obstacle does work the balance does not see."""
        if not self.checked:
            return {"gain": None, "budget": None, "load_work": self.work, "unstable": None}
        gain = max(self.gain, 0.0)
        return {"gain": gain, "budget": self.budget, "load_work": self.work,
                "unstable": self.unstable()}  # fmt: skip


class StateEnergies:
    """The energies of a state (J): kinetic T = ½ vᵀMv, strain V_strain and gravity
    V_gravity = −f_gᵀq, the same floats as the model's ``kinetic_energy``,
    ``strain_energy`` and ``potential_energy``, with what a run keeps constant resolved
    once: the bodies that hold strain energy (those with elements, as the model's internal
    force has it) and, where the mass matrix is diagonal (point masses, lumped masses), its
    diagonal, whose product with v is the sparse product's floats without its cost."""

    def __init__(self, model):
        self.M = model.M_full
        self.diagonal = _diagonal(model.M_full)
        bodies = enumerate(model.bodies)
        self.strained = [(b.energy, model.body_slice(i)) for i, b in bodies if b.element_dofs.size]
        self.f_gravity = model.f_gravity

    def kinetic(self, v: np.ndarray) -> float:
        if self.diagonal is None:
            return 0.5 * float(v @ (self.M @ v))  # (Model.kinetic_energy)
        # + 0.0 as the sparse product's sums, which start from +0: a −0.0 product gives +0.0
        Mv = self.diagonal * v
        Mv += 0.0
        return 0.5 * float(v @ Mv)

    def strain(self, q: np.ndarray) -> float:
        # a body without elements adds 0.0: leaving it out changes no float of the sum (the
        # model's, which is Python's own: compensated from Python 3.12)
        return float(sum(energy(q[s]) for energy, s in self.strained))

    def __call__(self, q: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
        """(T, V_strain, V_gravity) of the state (q, v), J."""
        return self.kinetic(v), self.strain(q), -float(self.f_gravity @ q)


def _diagonal(M) -> np.ndarray | None:
    """The diagonal of the CSR matrix ``M`` where it stores exactly one entry per row, on the
    diagonal; else None."""
    n = M.shape[0]
    if M.nnz != n or not np.array_equal(M.indptr, np.arange(n + 1)):
        return None
    return M.data.copy() if np.array_equal(M.indices, np.arange(n)) else None
