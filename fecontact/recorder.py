"""What a run records every step: the history rows, the impacts, the energy balance and
ledger, and the statistics of ``summary.json``."""

from __future__ import annotations

import dataclasses
import math
import platform
from pathlib import Path

import numpy as np

from .contact.watch import BOUND
from .energy import EnergyBalance, StateEnergies
from .io.frames import friction_totals
from .io.output import FRICTION_COLUMNS, LEDGER_COLUMNS, OBSTACLE_COLUMNS, STANDARD_COLUMNS
from .io.run_folder import jsonable
from .ledger import EnergyLedger
from .ledger_records import smooth_end
from .probes import probe_value
from .time import State, uses_smooth_contact
from .time.state import deferred_ledger
from .version import __version__

__all__ = ["Recorder"]


def _pressed(st: State) -> np.ndarray:
    """Per contact, whether any force acted in the step: ``State.pressed`` without its array
    of zero smooth forces where the step had none."""
    if st.smooth is not None:
        return st.pressed()
    out = st.impulse > 0.0
    if st.nu.size == out.size:
        out |= st.nu > 0.0
    return out


class Recorder:
    """History rows, impact detection and summary statistics over a run."""

    STATS = (
        "impacts",
        "iter_total",
        "iter_max",
        "halvings",
        "halved_steps",
        "retakes",
        "turn_halvings",
        "turn_halved_steps",
        "max_penetration",
        "mortar_depth",
        "mortar_deepest",
        "mortar_held_steps",
        "min_gap",
        "energy_initial",
        "energy_final",
        "energy_max",
        "steps",
        "dt_min",
        "dt_max",
        "dt_substep_min",
    )

    def __init__(self, sim, out: Path, keep_rows=None):
        from .io.output import HistoryWriter

        self.sim = sim
        self.model = sim.model
        self.friction = self.model.contacts.frictional
        self.friction_work = 0.0
        extra = FRICTION_COLUMNS if self.friction else ()
        ledger = (*LEDGER_COLUMNS, *(OBSTACLE_COLUMNS if self.model.contacts.moving else ()))
        self.columns = [*STANDARD_COLUMNS, *extra, *ledger, *sim.probes]
        self.history = HistoryWriter(out / "history.csv", self.columns, keep_rows=keep_rows)
        self.impacts: list[dict] = []
        self.closed = np.zeros(self.model.contacts.size, dtype=bool)
        self.n_closed, self.closing = 0, False
        self.impact_frame = False  # the first impact's frame is written
        self.iter_total = 0
        self.iter_max = 0
        self.halvings, self.halved_steps = 0, 0  # halvings, and the steps that had any
        self.retakes = 0
        # of the halvings, those for a beam node turned too far (fecontact.time.turns)
        self.turn_halvings, self.turn_halved_steps = 0, 0
        self.max_penetration = 0.0  # m, from the inside/outside test at every step's end
        # the deepest mortar node over its edge, and (t, step, depth in m) where it was
        self.mortar_depth, self.mortar_deepest = 0.0, None
        self.mortar_held_steps = 0  # steps ending with a mortar node held by its own gap
        self.min_gap = math.inf
        self.energy_initial = math.nan
        self.energy_final = math.nan
        self.energy_max = -math.inf
        self.balance = EnergyBalance(self.model)
        self.measure = StateEnergies(self.model)
        self.ledger = EnergyLedger(self.model, sim.options)
        self.energies = (math.nan, math.nan, math.nan)  # T, V_strain, V_gravity of the last
        self.steps = 0
        self.dt_min, self.dt_max = math.inf, 0.0  # s: the smallest and largest step taken
        self.dt_substep_min = math.inf  # s: the shortest sub-step of a halved step
        # what every row uses, resolved once: the gaps' reach (m) and the probes
        self.reach = self.model.length * sim.options.detection_margin
        self.probes = list(sim.probes.items())

    def count_failed(self, failed) -> None:
        """Count the halvings of the step that stopped the run (a
        :class:`~fecontact.time.stats.FailedStep`; None: none did) with those of its steps."""
        if failed is None:
            return
        self._count_halvings(failed.halvings, failed.retakes, failed.turn_halvings)
        self.dt_substep_min = min(self.dt_substep_min, failed.shortest)

    def _count_halvings(self, halvings: int, retakes: int, turn_halvings: int) -> None:
        """Add one step's halvings, energy retakes and halvings for a beam node's turn."""
        self.halvings += halvings
        self.halved_steps += halvings > 0
        self.retakes += retakes
        self.turn_halvings += turn_halvings
        self.turn_halved_steps += turn_halvings > 0

    def record(self, st: State) -> None:
        """Account for the state ``st``; write its history row unless it is a step between
        two rows (``st.substep``, with rtol)."""
        m = self.model
        # (the energy guard's measure of the state, where it made one: the same floats)
        ke, se, pe = st.energies or self.measure(st.q, st.v)
        total = ke + se + pe
        self.balance.add(st.t, st.q, ke, se, pe)
        end = smooth_end(deferred_ledger(st)) if self.ledger.damped else None
        self.ledger.add(st, ke, se, pe, self.balance.work, end)
        self.energies = (ke, se, pe)
        min_gap = self._min_gap(st)
        active = _pressed(st)
        n_active = int(np.count_nonzero(active))
        if n_active:  # the impacts: contacts pressed now, not in the state before
            for j in np.flatnonzero(active > self.closed):
                self.impacts.append({"time": st.t, "contact": int(j), "impulse": st.impulse[j]})
        self.closed = active
        # more contacts pressed than in the state before (the driver's first-impact frame)
        self.closing, self.n_closed = n_active > self.n_closed, n_active
        its = st.newton_iterations
        row = [st.t, ke, se, pe, total, min_gap, n_active, float(st.impulse.sum()), its, st.h]
        if self.friction:
            row += friction_totals(st)
            self.friction_work = row[-1]
        if not st.substep:
            row += self.ledger.row()
            row += [probe_value(name, p, m, st) for name, p in self.probes]
            self.history.write(row)
        if st.step == 0:
            self.energy_initial = self.ledger.initial  # (before an impact at t = 0)
        else:
            self.steps += 1
            self.iter_total += its
            self.iter_max = max(self.iter_max, its)
            self._count_halvings(st.halvings, st.retakes, st.turn_halvings)
            self.max_penetration = max(self.max_penetration, st.penetration)
            if st.mortar_depth > self.mortar_depth:
                self.mortar_depth, self.mortar_deepest = st.mortar_depth, (st.t, st.step)
            self.mortar_held_steps += st.mortar_held > 0
            self.dt_min, self.dt_max = min(self.dt_min, st.h), max(self.dt_max, st.h)
            self.dt_substep_min = min(self.dt_substep_min, st.h_least or st.h)
        self.energy_final = total
        self.energy_max = max(self.energy_max, total)
        self.min_gap = min(self.min_gap, min_gap)

    def _min_gap(self, st: State) -> float:
        """The smallest gap (m) among the contacts within the detection margin (the step's
        candidates), inf without any."""
        if st.step > 0:
            if not st.candidates.size:  # (a step far from every obstacle)
                return math.inf
            near = st.gaps[st.candidates]
        elif st.gaps.size:
            near = st.gaps
        else:
            return math.inf
        near = near[near <= self.reach]
        return float(near.min()) if near.size else math.inf

    def penetration_warnings(self) -> list[str]:
        """A warning when a watched body went deeper into another than the discretization's
        own amount (:data:`fecontact.contact.watch.BOUND`): a node of a mortar interface in
        the other solid, a rigid circle between a solid's boundary nodes or a beam's, or a
        strip's node in a strip pair declared one way."""
        if self.mortar_depth <= BOUND:
            return []
        t, step = self.mortar_deepest
        return [
            f"penetration: a watched body ends {100 * self.mortar_depth:.2g} % of the "
            f"shortest boundary edge inside another at t = {t:.6g} s (step {step}) (a node of "
            "a mortar interface in the other solid, a rigid circle between a solid's "
            "boundary nodes or a beam's, or a strip's node that only the reversed strip pair "
            "would hold), "
            f"beyond the {100 * BOUND:.0f} % the contact rows allow; refine the "
            "mesh or the step, or declare the reversed pair"
        ]

    def stats(self) -> dict:
        extra = {"closed": self.closed.tolist(), "impact_frame": self.impact_frame}
        extra["energy_balance"] = self.balance.state()
        extra["energy_ledger"] = self.ledger.state()
        return {k: getattr(self, k) for k in self.STATS} | extra

    def restore(self, stats: dict) -> None:
        for k in self.STATS:
            setattr(self, k, stats.get(k, getattr(self, k)))
        self.closed = np.array(stats["closed"], dtype=bool)
        self.n_closed = int(np.count_nonzero(self.closed))
        self.impact_frame = bool(stats.get("impact_frame", True))
        self.balance.restore(stats.get("energy_balance", {}))
        self.ledger.restore(stats.get("energy_ledger", {}))

    def summary(self, status: str, wall: float, timer: dict, message: str, counts: dict) -> dict:
        """The run's ``summary.json``: ``time_per_step_s`` is the wall time of the time loop
        without frame and history output, over the steps; ``counts`` are the run's
        statistics (:meth:`fecontact.time.StepStats.summary`), among them
        ``sparse_factorizations``, the sparse LU factorizations of the run and their time
        (included in the phases), the one-time cost of a linear model."""
        sim = self.sim
        import scipy
        import skfem

        return {
            "case": sim.name,
            "status": status,
            "message": message,
            "steps": self.steps,
            "dt": sim.dt,
            # the steps taken: dt but for the last one, or, with rtol, those the control chose
            "dt_min": self.dt_min if self.steps else None,
            "dt_max": self.dt_max if self.steps else None,
            # the shortest step actually taken: a halved step's shortest sub-step, else dt_min
            "dt_substep_min": None if math.isinf(self.dt_substep_min) else self.dt_substep_min,
            "t_end": sim.t_end,
            "wall_time_s": wall,
            "time_per_step_s": (wall - timer.get("output", 0.0)) / max(self.steps, 1),
            "phase_times_s": dict(timer),
            "sparse_factorizations": counts.pop("sparse_factorizations"),
            "newton_iterations_total": self.iter_total,
            "newton_iterations_max": self.iter_max,
            "newton_iterations_mean": self.iter_total / max(self.steps, 1),
            "step_halvings": self.halvings,
            "halved_steps": self.halved_steps,
            "penetration_retakes": self.retakes,
            "max_penetration": max(self.max_penetration, -self.min_gap),
            # the deepest node of a mortar interface inside the other solid, over that solid's
            # shortest boundary edge (0 without mortar interfaces)
            "mortar_depth": self.mortar_depth,
            # steps that end with a node of a 2D mortar interface held by its own gap
            # (contact.mortar_safeguard)
            "mortar_held_steps": self.mortar_held_steps,
            "min_gap": self.min_gap,
            "energy_initial": self.energy_initial,
            "energy_final": self.energy_final,
            "energy_max": self.energy_max,
            "energy_balance": self.balance.summary(),
            "energy_ledger": self.ledger.summary(*self.energies),
            "impact_work": self.ledger.impact_works(),
            "impacts": self.impacts,
            "parameters": jsonable(sim.parameters),
            "case_file": sim.origin,
            "options": dataclasses.asdict(sim.options),
            # what smooth_contact="auto" chose for this model (NSGA only)
            "smooth_contact_force": sim.options.integrator == "nsga"
            and uses_smooth_contact(self.model, sim.options),
            "probes": {
                k: {"unit": p.unit, "description": p.description} for k, p in sim.probes.items()
            },
            "n_dofs": self.model.n,
            "versions": {
                "fecontact": __version__,
                "python": platform.python_version(),
                "numpy": np.__version__,
                "scipy": scipy.__version__,
                "scikit-fem": getattr(skfem, "__version__", "unknown"),
            },
        }


def halving_warnings(rec: Recorder, dt: float) -> list[str]:
    """A warning when steps of ``dt`` (s) were halved: the halvings and the steps that had
    any, the shortest sub-step, and the halvings by cause (counted in ``summary.json``)."""
    if not rec.halvings:
        return []
    turn, retake = rec.turn_halvings, rec.retakes
    causes = {
        "a beam node turned by more than a quarter turn": turn,
        "a penetration retaken": retake,
        "a solve that did not converge": rec.halvings - turn - retake,
    }
    why = ", ".join(f"{n} for {cause}" for cause, n in causes.items() if n)
    return [
        f"halvings: {rec.halved_steps} step(s) of dt = {dt:g} s were halved {rec.halvings} "
        f"time(s), down to sub-steps of {rec.dt_substep_min:.3g} s: {why} (summary.json: "
        "step_halvings, halved_steps, beam_turns, penetration_retakes, dt_substep_min)"
    ]
