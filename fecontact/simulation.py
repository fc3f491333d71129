"""A simulation (model, step, end time, probes) and the driver that runs it to disk.

``run`` steps the integrator and writes, in the output folder, the VTU frames with their
``.pvd`` collection, ``history.csv`` (one row per step dt: with rtol, the steps the control
chooses land on the rows' times) and ``summary.json``. Frames are written
at the output interval only; the ``.pvd`` is rewritten atomically at most every
``PVD_INTERVAL`` seconds of wall time, at checkpoints and when the run stops (an error, Ctrl-C),
so that it then lists every frame written so far.
"""

from __future__ import annotations

import dataclasses
import os
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .bodies.beam3d import Beam3D
from .errors import InputError, SolverError, check_count, check_kind, check_positive
from .io.output import FRICTION_COLUMNS, LEDGER_COLUMNS, OBSTACLE_COLUMNS, STANDARD_COLUMNS
from .io.progress import RunProgress
from .io.run_folder import (
    CHECKPOINT,
    clear_earlier_run,
    load_checkpoint,
    save_checkpoint,
)
from .io.run_frames import RunFrames
from .io.run_lock import hold_folder
from .io.run_summary import RunSummary
from .io.termination import Terminated, terminate_as_interrupt
from .model import Model
from .probes import Probe, node_probe
from .recorder import Recorder, halving_warnings
from .threads import blas_threads
from .time import (
    IntegratorOptions,
    PhaseTimer,
    State,
    StepStats,
    check_options,
    initial_state,
    simulate,
)

__all__ = ["Probe", "Simulation", "node_probe", "run", "HISTORY_COLUMNS"]

HISTORY_COLUMNS = STANDARD_COLUMNS
PVD_INTERVAL = 1.0  # s of wall time between rewrites of the .pvd index during a run


@dataclass
class Simulation:
    """What to run: the model, the step ``dt`` (s), the end time ``t_end`` (s), probes,
    integrator options, the output interval (s of simulated time), the case's name and
    parameters (recorded in ``summary.json``) and the initial dof vectors ``q0``, ``v0``
    (default: rest in the reference configuration). ``origin`` identifies the case file it
    was built from (``file``, ``sha256``; the command line sets it): recorded in
    ``summary.json`` as ``case_file``, and a checkpoint continues only the same one."""

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
    origin: dict = field(default_factory=dict)

    def __post_init__(self):
        self.check()

    def check(self) -> None:
        """``InputError`` for a field of the wrong kind or range: at construction, and again
        when :func:`run` starts (fields set after construction, in a notebook, are checked
        before the folder is touched)."""
        check_kind("model", self.model, Model, "a Model(bodies, contacts, ...)")
        check_kind("options", self.options, IntegratorOptions, "an IntegratorOptions(...)")
        check_kind("probes", self.probes, dict, "a dict {name: Probe}")
        for key, probe in self.probes.items():
            check_kind(f"probes[{key!r}]", probe, Probe, "a Probe(fn, unit) or node_probe(...)")
        self.dt = check_positive("dt", self.dt)
        self.t_end = check_positive("t_end", self.t_end)
        self.output_interval = check_positive("output_interval", self.output_interval)
        name = self.name
        if not isinstance(name, str) or not name.replace("_", "").replace("-", "").isalnum():
            raise InputError(f"name must be letters, digits, '_' or '-', got {self.name!r}")
        for probe in self.probes:
            # history.csv columns: no clash with the time column, no separator inside
            ok = isinstance(probe, str) and probe.replace("_", "").isalnum()
            if (
                not ok
                or probe in HISTORY_COLUMNS + FRICTION_COLUMNS + LEDGER_COLUMNS + OBSTACLE_COLUMNS
            ):
                raise InputError(
                    f"probe names must be letters, digits or '_' and differ from the history "
                    f"columns ({', '.join(HISTORY_COLUMNS)}), got {probe!r}"
                )

    def __repr__(self) -> str:
        # (a notebook shows it: what runs, not the probes' functions and the model's address)
        m = self.model
        kinds = ", ".join(sorted({type(b).__name__ for b in m.bodies}))
        return (
            f"Simulation({self.name!r}: dt = {self.dt:g} s, t_end = {self.t_end:g} s, "
            f"integrator {self.options.integrator}; {_count(m.bodies, 'body', 'bodies')} "
            f"({kinds}), {_count(m.contacts.pairs, 'contact')}, {_count(m.joints.pairs, 'joint')}, "
            f"{m.n} dofs; "
            f"probes: {', '.join(self.probes) or 'none'})"
        )

    def warnings(self) -> list[str]:
        """Settings that the stability study (benchmarks/stability.py) found unsafe here, a
        step that the run cannot take, friction that the penalty baseline leaves out, and moving
        obstacles that the baselines (moreau, penalty) keep in place."""
        out = []
        if self.dt > self.t_end:
            out.append(
                f"dt = {self.dt:g} s is longer than the run (t_end = {self.t_end:g} s): "
                f"it takes one step of {self.t_end:g} s"
            )
        if any(not b.linear or b.element_dofs.size for b in self.model.bodies):
            out += _flexible_warnings(self.options, self.model.contacts.restitution)
            out += _left_to_itself(self.options, self.model)
        if self.options.integrator == "penalty" and self.model.contacts.frictional:
            out.append(
                "integrator = 'penalty' has no friction: its contact forces are normal only, "
                "and the contacts' friction coefficients act with integrator nsga or moreau"
            )
        if self.options.integrator != "nsga" and self.model.contacts.moving:
            # the baselines' steps never set the obstacles' time: their rows read the
            # velocity, but the gaps are measured against the place at t = 0
            out.append(
                f"integrator = {self.options.integrator!r} keeps moving obstacles where they "
                "are at t = 0 (only their velocity acts on the contacts); they move with "
                "integrator nsga"
            )
        return out

    def replace(self, **changes) -> Simulation:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)


def _flexible_warnings(opts: IntegratorOptions, restitution: np.ndarray) -> list[str]:
    """The settings found unsafe on a flexible body (beams, solids), with the contacts'
    coefficients of ``restitution``."""
    out = []
    alpha = opts.integrator == "nsga" and opts.scheme == "generalized-alpha"
    if alpha and np.any(restitution > 0) and opts.rho_inf > 0.5:
        out.append(
            f"rho_inf = {opts.rho_inf:g} with restitution > 0 on a flexible body: the "
            "vibration an impact leaves can make the generalized-alpha step blow up "
            "(measured from rho_inf = 0.7 on, at some steps; docs: explanation/"
            "stability); rho_inf = 0.5 is the stable default, and beams can take "
            "scheme = 'energy-decaying', which cannot blow up"
        )
    if opts.scheme == "energy-decaying" and opts.rho_inf > 0.95:
        out.append(
            f"rho_inf = {opts.rho_inf:g} with scheme = 'energy-decaying': the step barely "
            "damps the beam's nearly massless rotations, whose ringing makes Newton halve "
            "steps (14-33 halvings in 1.5 s of the founding pendulum at rho_inf = 1; none "
            "at 0.8)"
        )
    if alpha and np.any(restitution == 0) and opts.rho_inf > 0.9:
        out.append(
            f"rho_inf = {opts.rho_inf:g} with restitution 0 on a flexible body: the "
            "founding pendulum at rho_inf = 1 turns its nodes by more than a quarter turn "
            "a step from the first impact on (it blew up there before such steps were "
            "halved; now 8,823 halvings in 1.5 s; docs: explanation/stability)"
        )
    if opts.integrator == "nsga" and opts.metric == "mass":
        out.append(
            "metric = mass on a flexible body: each position correction injects strain "
            "energy (docs: explanation/stability); the default metric = stiffness "
            "spreads the correction over the structure"
        )
    return out


def _left_to_itself(opts: IntegratorOptions, model) -> list[str]:
    """The warning of a flexible ``model`` that neither contacts nor loads act on, at a
    nearly undamped generalized-α step (``opts``)."""
    alpha = opts.integrator == "nsga" and opts.scheme == "generalized-alpha"
    if not alpha or model.contacts.size or model.loads or opts.rho_inf <= 0.9:
        return []
    # (with contacts the warnings of _flexible_warnings speak; the growth needs no contact: a
    # stiff spring between two masses turning at 30 rad/s grows the same way under the
    # bare trapezoidal rule, docs/validation/beam3d.md. Not where loads drive the body:
    # Simo & Vu-Quoc's right-angle cantilever, tumbling after its pulse at rho_inf = 1,
    # holds its energy to 1e-3 over 8 s)
    return [
        f"rho_inf = {opts.rho_inf:g} on a flexible body left to itself (no contact, no "
        "load): the nearly undamped step is "
        "not stable where the body turns, its unresolved stiff modes grow with the "
        "turn, the faster the less damped (a free steel rod, dt = 1 ms: at 30 rad/s "
        "and rho_inf = 1, 183 step halvings from 0.3 s on and 2.3 % of its energy "
        "created, none at dt = 0.5 ms; at 60 rad/s, 38 halvings at rho_inf = 0.95, none "
        "at 0.9; docs: validation/beam3d)"
    ]


def run(
    sim: Simulation,
    out_dir,
    progress: bool = False,
    frames: bool = True,
    checkpoint_every: int = 500,
    resume: bool = False,
    overwrite: bool = False,
    frame_format: str = "auto",
) -> dict:
    """Run ``sim`` and write its results into ``out_dir``; return the summary (a dict, the
    contents of ``summary.json``; a notebook shows it as a few lines: ``RunSummary``).

    ``progress`` shows a progress bar with the step, time and Newton iterations (on a
    terminal). Every ``checkpoint_every`` steps (0: never) the state is saved to
    ``checkpoint.npz``; ``resume=True`` continues from it, giving the same result as an
    uninterrupted run. On ``SolverError`` or ``KeyboardInterrupt`` (SIGTERM too, in the main
    thread: :mod:`fecontact.io.termination`) the summary records the failure, every frame
    written so far stays readable, and the exception propagates.

    Runs never mix: the run holds ``out_dir`` (a lock file) and another process's run there
    is refused; a new run removes what an earlier run of the same case left in ``out_dir``
    (frames, index, history, summary, checkpoint, pictures), and refuses a folder that holds
    another case's output unless ``overwrite``. BLAS threads are limited to one while it runs
    (:mod:`fecontact.threads`).

    ``frame_format`` "vtu" writes a ``.vtu`` per part and frame indexed by a ``.pvd``;
    "vtkhdf" one transient ``.vtkhdf`` per part (:mod:`fecontact.io.vtkhdf`, needs h5py);
    "auto" VTKHDF for 3D models where it writes faster (:func:`fecontact.io.output.
    frame_format`), else VTU. A resumed run keeps the format of the run it continues.
    """
    options = (progress, frames, checkpoint_every, resume, overwrite, frame_format)
    _check_run_arguments(sim, out_dir, options)
    with blas_threads(), hold_folder(out_dir, sim.name), terminate_as_interrupt():
        return _run(sim, Path(out_dir), *options)


def _count(items, one: str, many: str = "") -> str:
    return f"{len(items)} {one if len(items) == 1 else many or one + 's'}"


def _check_run_arguments(sim, out_dir, options) -> None:
    """``InputError`` for an argument of ``run`` of the wrong kind, before the folder is
    touched: a string "no" for a flag would read as True, a negative checkpoint interval as
    never, a missing folder as a TypeError from pathlib."""
    check_kind("sim", sim, Simulation, "a Simulation(model, dt, t_end, ...)")
    sim.check()
    check_kind("out_dir", out_dir, (str, os.PathLike), "a folder path")
    progress, frames, checkpoint_every, resume, overwrite, _ = options
    flags = {"progress": progress, "frames": frames, "resume": resume, "overwrite": overwrite}
    for name, flag in flags.items():
        check_kind(name, flag, (bool, np.bool_), "True or False")
    check_count("checkpoint_every", checkpoint_every, 0, 10**9)


def _run(sim, out, progress, frames, checkpoint_every, resume, overwrite, frame_format) -> dict:
    from .io.output import frame_writer

    fmt = _frame_format(sim, out, frames, frame_format, resume)
    start, meta = _starting_point(sim, out, resume, overwrite)
    _import_frame_types(frames)
    _make_folder(out)
    pvd = frame_writer(fmt, out, sim.name, index_interval=PVD_INTERVAL)
    timer = PhaseTimer()
    rec = Recorder(sim, out, keep_rows=None if start is None else start.step + 1)
    output = RunFrames(sim, pvd, frames)
    if start is not None:
        _resume(start, meta, pvd, rec, output)
    bar = _progress_bar(sim, start) if progress else None
    stats = StepStats()  # the counts of this run, which its steps fill
    status, message = "completed", ""
    stop = None  # (t in s, step) where a failure names the step that stopped the run
    t_start = time.perf_counter()
    try:
        if start is None:
            output.begin()
        steps = simulate(
            sim.model, sim.dt, sim.t_end, sim.options, timer, sim.q0, sim.v0, start, stats
        )
        for st in steps:
            clock = time.perf_counter()
            _record(rec, output, st)
            _checkpoint(out, rec, output, st, checkpoint_every)
            timer.add("output", clock)
            _show(bar, st)
    except SolverError as err:
        status, message, stop = "failed", str(err), (err.time, err.step)
        if rec.balance.unstable() and not message.startswith("energy blow-up"):
            message += f"; before it, {rec.balance.describe()}"
            raise SolverError(message, err.time, err.step, err.residual) from None
        raise
    except BaseException as err:  # Ctrl-C, a failed write, any other error: never completed
        status, message = _stop_reason(err)
        raise
    finally:
        output.end(status == "completed")
        timer.add("output", _flush(pvd))
        wall = time.perf_counter() - t_start
        rec.history.close()
        _show(bar, None, status, stop)
        summary = RunSummary(_summary(sim, rec, stats, status, message, wall, timer), out)
        _write_summary(out, summary, status)
    said = sim.warnings() if start is None else []  # (warned before the run)
    for text in summary["warnings"]:
        if text not in said:
            warnings.warn(text, UserWarning, stacklevel=3)
    return summary


def _stop_reason(err: BaseException) -> tuple[str, str]:
    """The status and message of a run stopped by ``err`` (other than a ``SolverError``)."""
    if isinstance(err, Terminated):
        return "interrupted", "terminated by SIGTERM"
    if isinstance(err, KeyboardInterrupt):
        return "interrupted", "interrupted by the user"
    if isinstance(err, OSError):  # a full disk, a folder that stopped being writable
        return "failed", f"cannot write the output: {err.strerror or err}"
    return "failed", f"{type(err).__name__}: {err}"


def _frame_format(sim: Simulation, out: Path, frames: bool, frame_format: str, resume: bool):
    """The run's frame format, chosen before any work: that of the run it resumes, else
    ``frame_format`` for the model (:func:`fecontact.io.output.frame_format`)."""
    from .io.output import frame_format as choose_format

    earlier = [out / f"{sim.name}{ext}" for ext in (".pvd", ".frames.json")] if resume else []
    index = next((path for path in earlier if path.is_file()), None)
    return choose_format(frame_format, sim.model, index) if frames else "vtu"


def _resume(start: State, meta: dict, pvd, rec: Recorder, output: RunFrames) -> None:
    """Take up the frames, history and statistics of the checkpoint ``meta`` at ``start``."""
    pvd.resume(start.t)
    rec.restore(meta["stats"])
    rec.balance.start(start.t, start.q)
    rec.ledger.start(start)
    output.next_frame = meta["next_frame"]
    output.last = start  # (a frame due inside the first step is interpolated from it)


def _starting_point(sim: Simulation, out: Path, resume: bool, overwrite: bool):
    """(state, checkpoint metadata) to resume from, or (None, None) for a new run, whose
    input errors and warnings surface here, before any file exists."""
    check_options(sim.model, sim.options)  # (options the model cannot take: make_stepper's)
    if resume:
        start, meta = load_checkpoint(out / CHECKPOINT, sim)
        if start.t > sim.t_end * (1.0 + 1e-12):
            raise InputError(
                f"resume: the checkpoint is at t = {start.t:g} s, past t_end = {sim.t_end:g} s; "
                "give a later --t-end"
            )
        return start, meta
    # (the input checked; the acceleration is the run's, solved with the run's solver)
    initial_state(sim.model, sim.q0, sim.v0, sim.options.tol_gap, accelerate=False)
    for text in sim.warnings():
        warnings.warn(text, UserWarning, stacklevel=4)
    clear_earlier_run(out, sim.name, overwrite)
    return None, None


def _checkpoint(out: Path, rec: Recorder, output: RunFrames, st: State, every: int) -> None:
    """Save the checkpoint after every ``every`` steps (0: never)."""
    if every and st.step and not st.substep and st.step % every == 0:
        output.pvd.flush()  # a resumed run keeps the frames the index lists
        save_checkpoint(out / CHECKPOINT, output.sim, st, rec, output.next_frame)


def _record(rec: Recorder, output: RunFrames, st: State) -> None:
    """Record the state ``st`` and write its frame if it is due; an energy blow-up stops
    the run."""
    rec.record(st)
    if rec.balance.runaway():
        raise SolverError(
            f"energy blow-up at t = {st.t:.6g} s (step {st.step}): " + rec.balance.describe(),
            time=st.t,
            step=st.step,
        )
    # the first impact gets a frame of its own: the bodies touching, whatever the output
    # interval (contacts closed from the first step are not an impact)
    impact = not rec.impact_frame and st.step >= 2 and rec.closing
    rec.impact_frame = rec.impact_frame or impact
    output.write(st, impact)


def _make_folder(out: Path) -> None:
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:  # a file in the way, a folder that cannot be written
        raise InputError(f"out: cannot create the output folder {out}: {err.strerror}") from None


def _show(bar: RunProgress | None, st: State | None, status: str = "", stop=None) -> None:
    """Advance the progress bar ``bar`` (None: none) past ``st``; close it with the run's
    ``status`` (``st`` None) and, for a failure, the (t, step) its error names."""
    if bar is not None and st is None:
        bar.close(status, stop)
    elif bar is not None and st.step:
        bar.advance(st)


def _import_frame_types(frames: bool) -> None:
    if frames:
        import meshio  # noqa: F401  (the frames' mesh type: imported outside the timed loop)


def _summary(sim, rec, stats, status, message, wall, timer) -> dict:
    """The run's ``summary.json``: the recorder's, the run's statistics and the warnings."""
    frictional = sim.model.contacts.frictional
    counts = stats.summary(frictional)
    friction_solver = counts.pop("friction_solver", None)
    # the turn bound's halvings, and the steps that had any, are counted with the states
    rec.count_failed(stats.failed)  # (a failed step's halvings counted as the others')
    counts["beam_turns"] |= {"halvings": rec.turn_halvings, "halved_steps": rec.turn_halved_steps}
    summary = rec.summary(status, wall, timer, message, counts) | counts
    # a run that ends with more energy than its budget is said so, not only counted
    summary["warnings"] = [rec.balance.describe()] if rec.balance.unstable() else []
    summary["warnings"] += rec.ledger.warnings()
    summary["warnings"] += rec.penetration_warnings()
    summary["warnings"] += _residual_warnings(counts)
    # every warning of the run: also the halvings and its settings' (said before it too)
    summary["warnings"] += halving_warnings(rec, sim.dt) + sim.warnings()
    if frictional:
        summary["friction_solver"] = friction_solver
        summary["warnings"] += _plastic_warnings(friction_solver["plastic_jumps"])
        summary["friction_work"] = rec.friction_work
    # the element kernel of the spatial beams, chosen at their construction
    kernels = sorted({body.kernel for body in sim.model.bodies if isinstance(body, Beam3D)})
    if kernels:
        summary["beam3d_kernel"] = kernels[0] if len(kernels) == 1 else kernels
    return summary


def _plastic_warnings(count: int) -> list[str]:
    """A warning where velocity jumps lost their restitution (``plastic_jumps``)."""
    if not count:
        return []
    return [
        f"contact: {count} velocity jump(s) solved as plastic (e = 0): the frictional law "
        "with restitution had no solution found on redundant rows (docs/validation/pile.md)"
    ]


def _residual_warnings(counts: dict) -> list[str]:
    """A warning for each level whose converged contact correction left the law's residual
    above its tolerance (the active set repeated, redundant rows solved by least squares, or
    a cycling position correction's set frozen with a row that pulls, ended the iteration):
    the constraints hold only to that residual."""
    out = []
    for level, ratio in counts["final_residuals"].items():
        if ratio > 1.0:
            out.append(
                f"contact: a {level} correction ended with its residual {ratio:.3g} times its "
                f"tolerance ({counts['least_squares_multipliers']} least-squares multipliers "
                "in the run: redundant contacts; "
                f"{counts['frozen_active_sets']} frozen active sets: cycling position "
                "corrections); the constraints hold only to that residual"
            )
    return out


def _write_summary(out: Path, summary: dict, status: str) -> None:
    from .io.output import write_json

    try:
        write_json(out / "summary.json", summary)
    except OSError:
        if status == "completed":
            raise
        # else the run's own failure is the one to report (a full disk refuses both)


def _flush(pvd) -> float:
    """Close the frames: the .pvd index lists them all; return the start time (s)."""
    clock = time.perf_counter()
    pvd.close()
    return clock


def _progress_bar(sim: Simulation, start: State | None) -> RunProgress:
    t0, step0 = (0.0, 0) if start is None else (start.t, start.step)
    return RunProgress(sim.name, sim.t_end, sim.dt, t0, step0)
