"""A simulation (model, step, end time, probes) and the driver that runs it to disk.

``run`` steps the integrator and writes, in the output folder, the VTU frames with their
``.pvd`` collection, ``history.csv`` (one row per step) and ``summary.json``. Frames are written
at the output interval only; the ``.pvd`` is rewritten atomically at most every
``PVD_INTERVAL`` seconds of wall time, at checkpoints and when the run stops (an error, Ctrl-C),
so that it then lists every frame written so far.
"""

from __future__ import annotations

import dataclasses
import math
import platform
import sys
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__
from .contact.friction import COULOMB
from .contact.laws import ALART_CURNIER, LEAST_SQUARES
from .energy import EnergyBalance
from .errors import InputError, SolverError, check_positive
from .io.frames import bodies_box, frame_parts, friction_totals, static_parts
from .io.output import FRICTION_COLUMNS, STANDARD_COLUMNS
from .io.run_folder import (
    CHECKPOINT,
    clear_earlier_run,
    jsonable,
    load_checkpoint,
    save_checkpoint,
)
from .linalg import ITERATIVE, SPARSE_FACTORIZATIONS
from .linalg.sparse_solvers import finish_run, start_run
from .time import (
    FOLLOW_UPS,
    NEWTON,
    RELEASES,
    IntegratorOptions,
    PhaseTimer,
    State,
    initial_state,
    simulate,
    uses_smooth_contact,
)

__all__ = ["Probe", "Simulation", "node_probe", "run", "HISTORY_COLUMNS"]

HISTORY_COLUMNS = STANDARD_COLUMNS
PVD_INTERVAL = 1.0  # s of wall time between rewrites of the .pvd index during a run


@dataclass(frozen=True)
class Probe:
    """A scalar recorded every step: ``fn(model, state)`` in ``unit``."""

    fn: Callable
    unit: str
    description: str = ""


_NODE_QUANTITIES = {
    "x": ("m", "position x", lambda b, q, v: b.positions(q)[:, 0]),
    "y": ("m", "position y", lambda b, q, v: b.positions(q)[:, 1]),
    "ux": ("m", "displacement x", lambda b, q, v: b.point_data(q, v)["displacement"][:, 0]),
    "uy": ("m", "displacement y", lambda b, q, v: b.point_data(q, v)["displacement"][:, 1]),
    "vx": ("m/s", "velocity x", lambda b, q, v: b.point_data(q, v)["velocity"][:, 0]),
    "vy": ("m/s", "velocity y", lambda b, q, v: b.point_data(q, v)["velocity"][:, 1]),
    "rotation": ("rad", "rotation", lambda b, q, v: b.point_data(q, v)["rotation"]),
}


def node_probe(model, body, node: int, quantity: str) -> Probe:
    """Probe of one node of ``body``: ``quantity`` in x, y (m), ux, uy (m), vx, vy (m/s),
    rotation (rad, counter-clockwise)."""
    if quantity not in _NODE_QUANTITIES:
        raise InputError(f"quantity must be one of {', '.join(_NODE_QUANTITIES)}, got {quantity!r}")
    if quantity == "rotation" and "theta" not in body.components:
        kind = type(body).__name__
        raise InputError(f"quantity 'rotation': a {kind} node has none; use x, y, ux, uy, vx, vy")
    unit, text, get = _NODE_QUANTITIES[quantity]
    i = body.node_index(node)
    s = model.body_slice(model.bodies.index(body))
    return Probe(lambda m, st: float(get(body, st.q[s], st.v[s])[i]), unit, f"{text} of node {i}")


@dataclass
class Simulation:
    """What to run: the model, the step ``dt`` (s), the end time ``t_end`` (s), probes,
    integrator options, the output interval (s of simulated time), the case's name and
    parameters (recorded in ``summary.json``) and the initial dof vectors ``q0``, ``v0``
    (default: rest in the reference configuration)."""

    model: object
    dt: float
    t_end: float
    probes: dict = field(default_factory=dict)
    options: IntegratorOptions = field(default_factory=IntegratorOptions)
    output_interval: float = 0.01
    name: str = "simulation"
    parameters: dict = field(default_factory=dict)
    q0: np.ndarray | None = None
    v0: np.ndarray | None = None

    def __post_init__(self):
        self.dt = check_positive("dt", self.dt)
        self.t_end = check_positive("t_end", self.t_end)
        self.output_interval = check_positive("output_interval", self.output_interval)
        name = self.name
        if not isinstance(name, str) or not name.replace("_", "").replace("-", "").isalnum():
            raise InputError(f"name must be letters, digits, '_' or '-', got {self.name!r}")
        for probe in self.probes:
            # history.csv columns: no clash with the time column, no separator inside
            ok = isinstance(probe, str) and probe.replace("_", "").isalnum()
            if not ok or probe in HISTORY_COLUMNS + FRICTION_COLUMNS:
                raise InputError(
                    f"probe names must be letters, digits or '_' and differ from the history "
                    f"columns ({', '.join(HISTORY_COLUMNS)}), got {probe!r}"
                )

    def warnings(self) -> list[str]:
        """Settings that the stability study (benchmarks/stability.py) found unsafe here, and
        a step that the run cannot take."""
        out = []
        if self.dt > self.t_end:
            out.append(
                f"dt = {self.dt:g} s is longer than the run (t_end = {self.t_end:g} s): "
                f"it takes one step of {self.t_end:g} s"
            )
        opts, model = self.options, self.model
        flexible = any(not b.linear or b.element_dofs.size for b in model.bodies)
        elastic_impacts = np.any(model.contacts.restitution > 0)
        alpha = opts.integrator == "nsga" and opts.scheme == "generalized-alpha"
        if alpha and flexible and elastic_impacts and opts.rho_inf > 0.5:
            out.append(
                f"rho_inf = {opts.rho_inf:g} with restitution > 0 on a flexible body: the "
                "vibration an impact leaves can make the generalized-alpha step blow up "
                "(measured from rho_inf = 0.7 on, at some steps; README, Stability and the "
                "defaults); rho_inf = 0.5 is the stable default, and beams can take "
                "scheme = 'energy-decaying', which cannot blow up"
            )
        perfectly_plastic = np.any(model.contacts.restitution == 0)
        if opts.scheme == "energy-decaying" and flexible and opts.rho_inf > 0.95:
            out.append(
                f"rho_inf = {opts.rho_inf:g} with scheme = 'energy-decaying': the step barely "
                "damps the beam's nearly massless rotations, whose ringing makes Newton halve "
                "steps (14-33 halvings in 1.5 s of the founding pendulum at rho_inf = 1; none "
                "at 0.8)"
            )
        if alpha and flexible and perfectly_plastic and opts.rho_inf > 0.9:
            out.append(
                f"rho_inf = {opts.rho_inf:g} with restitution 0 on a flexible body: an energy "
                "blow-up at the first impact was measured at rho_inf = 1 (README, Stability and "
                "the defaults)"
            )
        if opts.integrator == "nsga" and flexible and opts.metric == "mass":
            out.append(
                "metric = mass on a flexible body: each position correction injects strain "
                "energy (README, Stability and the defaults); the default metric = stiffness "
                "spreads the correction over the structure"
            )
        return out

    def replace(self, **changes) -> Simulation:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)


class _Recorder:
    """History rows, impact detection and summary statistics over a run."""

    STATS = (
        "impacts",
        "iter_total",
        "iter_max",
        "halvings",
        "min_gap",
        "energy_initial",
        "energy_final",
        "energy_max",
        "steps",
    )

    def __init__(self, sim: Simulation, out: Path, keep_rows=None):
        from .io.output import HistoryWriter

        self.sim = sim
        self.model = sim.model
        self.friction = self.model.contacts.frictional
        self.friction_work = 0.0
        extra = FRICTION_COLUMNS if self.friction else ()
        self.columns = list(HISTORY_COLUMNS) + list(extra) + list(sim.probes)
        self.history = HistoryWriter(out / "history.csv", self.columns, keep_rows=keep_rows)
        self.impacts: list[dict] = []
        self.closed = np.zeros(self.model.contacts.size, dtype=bool)
        self.impact_frame = False  # the first impact's frame is written
        self.iter_total = 0
        self.iter_max = 0
        self.halvings = 0
        self.min_gap = math.inf
        self.energy_initial = math.nan
        self.energy_final = math.nan
        self.energy_max = -math.inf
        self.balance = EnergyBalance(self.model)
        self.steps = 0

    def record(self, st: State) -> None:
        m = self.model
        ke, se, pe = m.kinetic_energy(st.v), m.strain_energy(st.q), m.potential_energy(st.q)
        total = ke + se + pe
        self.balance.add(st.t, st.q, ke, se, pe)
        near = st.gaps[st.candidates] if st.step > 0 else st.gaps
        near = near[near <= m.length * self.sim.options.detection_margin]
        min_gap = float(near.min()) if near.size else math.inf
        active = st.pressed()
        for j in np.flatnonzero(active & ~self.closed):
            self.impacts.append({"time": st.t, "contact": int(j), "impulse": st.impulse[j]})
        self.closed = active
        its = st.newton_iterations
        row = [st.t, ke, se, pe, total, min_gap, int(active.sum()), float(st.impulse.sum()), its]
        if self.friction:
            row += friction_totals(st)
            self.friction_work = row[-1]
        row += [p.fn(m, st) for p in self.sim.probes.values()]
        self.history.write(row)
        if st.step == 0:
            self.energy_initial = total
        else:
            self.steps += 1
            self.iter_total += its
            self.iter_max = max(self.iter_max, its)
            self.halvings += st.halvings
        self.energy_final = total
        self.energy_max = max(self.energy_max, total)
        self.min_gap = min(self.min_gap, min_gap)

    def stats(self) -> dict:
        extra = {"closed": self.closed.tolist(), "impact_frame": self.impact_frame}
        extra["energy_balance"] = self.balance.state()
        return {k: getattr(self, k) for k in self.STATS} | extra

    def restore(self, stats: dict) -> None:
        for k in self.STATS:
            setattr(self, k, stats[k])
        self.closed = np.array(stats["closed"], dtype=bool)
        self.impact_frame = bool(stats.get("impact_frame", True))
        self.balance.restore(stats.get("energy_balance", {}))

    def summary(
        self, status: str, wall: float, timer: dict, message: str = "", factors=None
    ) -> dict:
        """The run's ``summary.json``: ``time_per_step_s`` is the wall time of the time loop
        without frame and history output, over the steps; ``sparse_factorizations`` counts
        the sparse LU factorizations of the run and their time (included in the phases), the
        one-time cost of a linear model."""
        sim = self.sim
        import scipy
        import skfem

        return {
            "case": sim.name,
            "status": status,
            "message": message,
            "steps": self.steps,
            "dt": sim.dt,
            "t_end": sim.t_end,
            "wall_time_s": wall,
            "time_per_step_s": (wall - timer.get("output", 0.0)) / max(self.steps, 1),
            "phase_times_s": dict(timer),
            "sparse_factorizations": factors or {"count": 0, "seconds": 0.0},
            "newton_iterations_total": self.iter_total,
            "newton_iterations_max": self.iter_max,
            "newton_iterations_mean": self.iter_total / max(self.steps, 1),
            "step_halvings": self.halvings,
            "max_penetration": max(0.0, -self.min_gap),
            "min_gap": self.min_gap,
            "energy_initial": self.energy_initial,
            "energy_final": self.energy_final,
            "energy_max": self.energy_max,
            "energy_balance": self.balance.summary(),
            "impacts": self.impacts,
            "parameters": jsonable(sim.parameters),
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


def run(
    sim: Simulation,
    out_dir,
    progress: bool = False,
    frames: bool = True,
    checkpoint_every: int = 500,
    resume: bool = False,
    overwrite: bool = False,
) -> dict:
    """Run ``sim`` and write its results into ``out_dir``; return the summary.

    ``progress`` shows a progress bar with the step, time and Newton iterations (on a
    terminal). Every ``checkpoint_every`` steps (0: never) the state is saved to
    ``checkpoint.npz``; ``resume=True`` continues from it, giving the same result as an
    uninterrupted run. On ``SolverError`` or ``KeyboardInterrupt`` the summary records the
    failure, every frame written so far stays readable, and the exception propagates.

    Runs never mix: a new run removes what an earlier run of the same case left in
    ``out_dir`` (frames, index, history, summary, checkpoint, pictures), and refuses a folder
    that holds another case's output unless ``overwrite``.
    """
    from .io.output import PVDWriter, write_json

    out = Path(out_dir)
    start, meta = None, None
    if resume:
        start, meta = load_checkpoint(out / CHECKPOINT, sim)
        if start.t > sim.t_end * (1.0 + 1e-12):
            raise InputError(
                f"resume: the checkpoint is at t = {start.t:g} s, past t_end = {sim.t_end:g} s; "
                "give a later --t-end"
            )
    else:
        # input errors surface before any file exists
        initial_state(sim.model, sim.q0, sim.v0, sim.options.tol_gap)
        for text in sim.warnings():
            warnings.warn(text, UserWarning, stacklevel=2)
        clear_earlier_run(out, sim.name, overwrite)
    if frames:
        import meshio  # noqa: F401  (the frames' mesh type: imported outside the timed loop)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:  # a file in the way, a folder that cannot be written
        raise InputError(f"out: cannot create the output folder {out}: {err.strerror}") from None
    pvd = PVDWriter(out, sim.name, index_interval=PVD_INTERVAL)
    timer = PhaseTimer()
    rec = _Recorder(sim, out, keep_rows=None if start is None else start.step + 1)
    next_frame = 0.0
    if start is not None:
        pvd.resume(start.t)
        rec.restore(meta["stats"])
        rec.balance.start(start.t, start.q)
        next_frame = meta["next_frame"]
    bar = _progress_bar(sim, start) if progress else None
    status, message = "completed", ""
    t_start = time.perf_counter()
    done = 0 if start is None else start.step
    solver = start_run(math.ceil(sim.t_end / sim.dt - 1e-9) - done, sim.model.linear)
    factors_start = dict(SPARSE_FACTORIZATIONS)
    iterative_start = dict(ITERATIVE)
    least_squares_start = LEAST_SQUARES["count"]
    coulomb_start = dict(COULOMB)
    newton_start = dict(NEWTON)
    follow_start = dict(FOLLOW_UPS)
    release_start = RELEASES["steps"]
    ALART_CURNIER.update(position=0.0, velocity=0.0)  # largest values of this run
    try:
        box = None  # the bodies' box over the frames, for the obstacles' outlines
        if frames and start is None:
            box = bodies_box(sim.model, np.zeros(sim.model.n) if sim.q0 is None else sim.q0)
            for part, mesh in static_parts(sim.model, box).items():
                pvd.write_static(part, mesh)
        steps = simulate(sim.model, sim.dt, sim.t_end, sim.options, timer, sim.q0, sim.v0, start)
        for st in steps:
            clock = time.perf_counter()
            closed_before = int(rec.closed.sum())
            rec.record(st)
            if st.step:  # the initial state is no step
                solver.note_step()
            if rec.balance.runaway():
                raise SolverError(
                    f"energy blow-up at t = {st.t:.6g} s (step {st.step}): "
                    + rec.balance.describe(),
                    time=st.t,
                    step=st.step,
                )
            # the first impact gets a frame of its own: the bodies touching, whatever the
            # output interval (contacts closed from the first step are not an impact)
            impact = not rec.impact_frame and st.step >= 2 and rec.closed.sum() > closed_before
            rec.impact_frame = rec.impact_frame or impact
            if frames and (
                impact or st.t >= next_frame - 1e-9 * sim.dt or st.t >= sim.t_end - 1e-12
            ):
                pvd.write_frame(st.t, frame_parts(sim.model, st))
                now = bodies_box(sim.model, st.q)
                box = (
                    now
                    if box is None
                    else np.stack([np.minimum(box[0], now[0]), np.maximum(box[1], now[1])])
                )
                interval = sim.output_interval
                next_frame = (math.floor(st.t / interval + 1e-6) + 1) * interval
            if checkpoint_every and st.step and st.step % checkpoint_every == 0:
                pvd.flush()  # a resumed run keeps the frames the index lists
                save_checkpoint(out / CHECKPOINT, sim, st, rec, next_frame)
            timer.add("output", clock)
            if bar is not None and st.step:
                bar.update(1)
                if st.step % 25 == 0:
                    bar.set_postfix(t=f"{st.t:.4f}", it=st.newton_iterations, refresh=False)
    except SolverError as err:
        status, message = "failed", str(err)
        if rec.balance.unstable() and not message.startswith("energy blow-up"):
            message += f"; before it, {rec.balance.describe()}"
            raise SolverError(message, err.time, err.step, err.residual) from None
        raise
    except KeyboardInterrupt:
        status, message = "interrupted", "interrupted by the user"
        raise
    except OSError as err:  # a full disk, a folder that stopped being writable
        status, message = "failed", f"cannot write the output: {err.strerror or err}"
        raise
    finally:
        if frames and box is not None and status == "completed":  # outlines under the motion
            for part, mesh in static_parts(sim.model, box).items():
                pvd.write_static(part, mesh)
        timer.add("output", _flush(pvd))
        wall = time.perf_counter() - t_start
        rec.history.close()
        if bar is not None:
            bar.close()
        factors = {k: SPARSE_FACTORIZATIONS[k] - factors_start[k] for k in factors_start}
        summary = rec.summary(status, wall, timer, message, factors)
        # redundant active constraints whose multipliers came from least squares
        summary["least_squares_multipliers"] = LEAST_SQUARES["count"] - least_squares_start
        # the globalization of the smooth Newton (fecontact.time.descent)
        summary["smooth_newton"] = {k: NEWTON[k] - newton_start[k] for k in NEWTON}
        # the velocity's follow-ups of an impact's correction (fecontact.time.position_jump)
        summary["velocity_follow_ups"] = {k: FOLLOW_UPS[k] - follow_start[k] for k in FOLLOW_UPS}
        # smooth steps taken again without the force of a contact they released
        summary["contact_releases"] = RELEASES["steps"] - release_start
        # the largest Alart–Curnier residual a converged correction left, over its tolerance
        summary["final_residuals"] = dict(ALART_CURNIER)
        # AMG-preconditioned CG (sparse solver "amg"): solves, iterations, setups, fallbacks
        summary["iterative_solver"] = {k: ITERATIVE[k] - iterative_start[k] for k in ITERATIVE}
        # the sparse solver: the direct path, the choices of "auto", factor and peak memory
        summary["sparse_solver"] = finish_run(solver)
        # a run that ends with more energy than its budget is said so, not only counted
        summary["warnings"] = [rec.balance.describe()] if rec.balance.unstable() else []
        if sim.model.contacts.frictional:  # the frictional solves and their fallbacks
            summary["friction_solver"] = {k: COULOMB[k] - coulomb_start[k] for k in COULOMB}
            summary["friction_work"] = rec.friction_work
        try:
            write_json(out / "summary.json", summary)
        except OSError:
            if status == "completed":
                raise
            # else the run's own failure is the one to report (a full disk refuses both)
    for text in summary["warnings"]:
        warnings.warn(text, UserWarning, stacklevel=2)
    return summary


def _flush(pvd) -> float:
    """Write the .pvd index if frames are missing from it; return the start time (s)."""
    clock = time.perf_counter()
    pvd.flush()
    return clock


def _progress_bar(sim: Simulation, start: State | None):
    from tqdm import tqdm

    total = max(1, math.ceil(sim.t_end / sim.dt - 1e-9))
    initial = 0 if start is None else start.step
    return tqdm(
        total=total, initial=initial, desc=sim.name, unit="step", disable=None, file=sys.stderr
    )
