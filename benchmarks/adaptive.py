"""Steps chosen by a tolerance (``IntegratorOptions.rtol``): error against exact solutions,
step counts, the founding case against its own h/8 run, and the cost of rtol=None.

Sections:
- thrown ball without a floor (exact parabola): the estimate on impact-free flight;
- a linear cantilever released from its first mode (exact q = φ cos ωt): error against
  rtol and against fixed steps, and the observed order of the error in the mean step;
- the bouncing ball (h₀ = 1 m, e = 0.8, 3 s) and the rigid pendulum (L = 1.5 m, e = 0.5, 3 s)
  at dt = 1e-3 with and without rtol (with impact localization where the package has it);
- the founding case (flexible pendulum, 1.5 s): the largest tip distance from its own h/8
  run, with fixed steps and with rtol;
- the cost of a step with rtol=None against the revision ``--baseline`` (a ``git archive`` of
  it, run in fresh processes, alternating, fastest of ``--rounds``).

    python benchmarks/adaptive.py --baseline main     # a few minutes
    python benchmarks/adaptive.py --quick             # seconds: checks the script runs
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import time
from io import BytesIO
from pathlib import Path

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
from _common import (
    ROOT,
    G,
    ball_exact_gap,
    case,
    machine_note,
    markdown_table,
    parser,
    pendulum_exact,
    publish,
)

from fecontact import Model
from fecontact.bodies import Disk, RigidBody2D
from fecontact.bodies.beam import Beam2D, Material, Section
from fecontact.time import IntegratorOptions, StepStats, simulate

LOCALIZE = "localize" in {f.name for f in dataclasses.fields(IntegratorOptions)}
ON = {"localize": True} if LOCALIZE else {}


def stepped(model, dt, t_end, opts, q0=None, v0=None, every=None):
    """(rows (t, q) at the history rows, or every ``every`` s, steps, wall time (s), the
    control's counts)."""
    stats, rows, steps = StepStats(), [], 0
    start = time.perf_counter()
    for st in simulate(model, dt, t_end, opts, q0=q0, v0=v0, stats=stats):
        steps += 1
        keep = not st.substep
        if keep and every is not None:
            keep = abs(st.t / every - round(st.t / every)) < 1e-6
        if keep:
            rows.append((st.t, st.q.copy()))
    wall = time.perf_counter() - start
    return rows, steps - 1, wall, stats.control


def free_flight(quick: bool) -> list[dict]:
    """A ball thrown up at 3 m/s, no floor: generalized-α is exact for a constant
    acceleration, so the estimate is round-off and the steps stay at dt."""
    ball = RigidBody2D.uniform(1.0, [0.0, 0.0], Disk(0.1))
    model = Model([ball], [], (0.0, -G))
    v0 = np.array([0.5, 3.0, 0.0])
    out = []
    for rtol in (None, 1e-6, 1e-9):
        rows, steps, wall, control = stepped(
            model, 1e-3, 0.1 if quick else 0.6, IntegratorOptions(rtol=rtol), v0=v0
        )
        err = max(abs(q[1] - (3.0 * t - 0.5 * G * t * t)) for t, q in rows)
        out.append({"rtol": rtol, "steps": steps, "rejected": control.rejected, "error_m": err})
    return out


def cantilever():
    """A linear steel cantilever (1 m, 4 elements) in its first mode (tip 1 mm)."""
    section = Section(area=1e-4, inertia=1e-8 / 12.0)
    beam = Beam2D.straight([0, 0], [1, 0], 4, Material(2e11, rho=7800), section, True).clamp(0)
    model = Model([beam], [], (0.0, 0.0))
    K = model.internal(np.zeros(model.n))[2]
    w2, modes = sl.eigh(*[x.toarray() if sp.issparse(x) else x for x in (K, model.M)])
    phi = np.zeros(model.n)
    phi[model.free] = 1e-3 * modes[:, 0] / np.max(np.abs(modes[:, 0]))
    return model, phi, float(np.sqrt(w2[0]))


def oscillator(quick: bool) -> list[dict]:
    """Error of q (m, max over rows and dofs) against the exact modal motion, two periods."""
    model, phi, omega = cantilever()
    period = 2 * np.pi / omega
    runs = [(20, None), (40, None), (80, None), (160, None), (320, None)]
    runs += [(20, r) for r in (1e-5, 1e-6, 1e-7, 1e-8)]
    out = []
    for per, rtol in runs[:2] + runs[5:7] if quick else runs:
        model.iteration_cache.clear()
        opts = IntegratorOptions(rtol=rtol)
        rows, steps, wall, control = stepped(model, period / per, 2 * period, opts, q0=phi)
        err = max(np.max(np.abs(q - phi * np.cos(omega * t))) for t, q in rows)
        out.append(
            {
                "dt": f"T/{per}",
                "rtol": rtol,
                "steps": steps,
                "rejected": control.rejected,
                "factorizations": len(model.iteration_cache),
                "error_m": err,
                "wall_s": wall,
            }
        )
    return out


def rigid_cases(quick: bool) -> list[dict]:
    """Bouncing ball and rigid pendulum at dt = 1e-3 against their exact height and angle."""
    t_end = 0.6 if quick else 3.0
    ball = case("bouncing_ball").build(height=1.0, mass=1.0, restitution=0.8)
    pend = case("rigid_pendulum").build(length=1.5, mass=1.0, restitution=0.5)
    theta = pend.probes["theta"].fn
    out = []
    for rtol in (None, 1e-6, 1e-9):
        opts = IntegratorOptions(rtol=rtol, **ON)
        rows, steps, wall, control = stepped(ball.model, 1e-3, t_end, opts, ball.q0, ball.v0)
        t = np.array([r[0] for r in rows])
        y = np.array([r[1][1] for r in rows])
        err = np.max(np.abs(1.0 + y - ball_exact_gap(t)))
        out.append(_rigid_row("bouncing ball (m)", rtol, steps, control, err, wall))
        rows, steps, wall, control = stepped(pend.model, 1e-3, t_end, opts, pend.q0, pend.v0)
        t = np.array([r[0] for r in rows])
        th = np.array([theta(pend.model, _Q(q)) for _, q in rows])
        err = np.max(np.abs(th - pendulum_exact(t, e=0.5, length=1.5)[0]))
        out.append(_rigid_row("rigid pendulum (rad)", rtol, steps, control, err, wall))
    return out


@dataclasses.dataclass
class _Q:
    """What a position probe reads of a state: q."""

    q: np.ndarray


def _rigid_row(name, rtol, steps, control, err, wall) -> dict:
    return {"case": name, "localize": LOCALIZE, "rtol": rtol, "steps": steps,
            "rejected": control.rejected, "max_error": err, "wall_s": wall}  # fmt: skip


def founding(quick: bool) -> list[dict]:
    """The flexible pendulum's tip against its own h/8 run, every 1 ms over 1.5 s."""
    sim = case("flexible_pendulum").build()
    tip = [sim.probes[k].fn for k in ("tip_x", "tip_y")]
    t_end = 0.1 if quick else 1.5
    runs = [(1.25e-4, None), (1e-3, None), (5e-4, None), (2.5e-4, None)]
    runs += [(1e-3, r) for r in (1e-4, 1e-5, 1e-6)]
    out, ref = [], None
    for dt, rtol in runs[:2] + runs[4:5] if quick else runs:
        opts = dataclasses.replace(sim.options, rtol=rtol, **ON)
        states, steps, wall, control = [], 0, time.perf_counter(), StepStats()
        for st in simulate(sim.model, dt, t_end, opts, sim.q0, sim.v0, stats=control):
            steps += 1
            if not st.substep and abs(st.t * 1e3 - round(st.t * 1e3)) < 1e-6:
                states.append([f(sim.model, st) for f in tip])
        wall = time.perf_counter() - wall
        xy = np.array(states)
        ref = xy if ref is None else ref
        dist = np.hypot(*(xy - ref).T)
        out.append({"dt_s": dt, "rtol": rtol, "localize": LOCALIZE, "steps": steps - 1,
                    "rejected": control.control.rejected, "max_tip_mm": 1e3 * dist.max(),
                    "end_tip_mm": 1e3 * dist[-1], "wall_s": wall})  # fmt: skip
    return out


TIMER = """
import json, sys, tempfile, time
from fecontact import run
from fecontact.testing import case
name, kw, t_end, dt = sys.argv[1], json.loads(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
sim = case(name).build(**kw).replace(t_end=t_end, dt=dt)
best = float("inf")
for _ in range(3):
    with tempfile.TemporaryDirectory() as tmp:
        s = run(sim, tmp, frames=False, checkpoint_every=0)
    assert s["impacts"] == [], "a contact closed"
    best = min(best, s["wall_time_s"] / s["steps"])
print(best)
"""

# what rtol=None adds is in the recorder (the dt cell, the smallest and largest step): its
# time per state, the fastest of 300 batches of 100 states (short batches: some run unhindered
# by other jobs on the machine)
RECORDER = """
import tempfile, time, pathlib
from fecontact.recorder import Recorder
from fecontact.testing import case
from fecontact.time import simulate
sim = case("bouncing_ball").build().replace(t_end=0.05, dt=1e-4)
states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options))
best = float("inf")
with tempfile.TemporaryDirectory() as tmp:
    rec = Recorder(sim, pathlib.Path(tmp))
    rec.record(states[0])
    for _ in range(300):
        start = time.perf_counter()
        for st in states[1:101]:
            rec.record(st)
        best = min(best, (time.perf_counter() - start) / 100)
    rec.history.close()
print(best)
"""

# (case, parameters, t_end, dt): flight before the first impact
COST_RUNS = [
    ("bouncing_ball", {}, 0.4, 1e-4),
    ("flexible_pendulum", {}, 0.25, 2.5e-4),
    ("two_disks", {"gap": 0.05, "refinements": 1}, 1e-2, 2e-5),
]


def _timed(tree: Path, run) -> float:
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    if run is None:
        args = [sys.executable, "-c", RECORDER]
    else:
        name, kw, t_end, dt = run
        args = [sys.executable, "-c", TIMER, name, json.dumps(kw), str(t_end), str(dt)]
    done = subprocess.run(args, env=env, cwd=tree, capture_output=True, text=True, check=True)
    return float(done.stdout.split()[-1])


def cost(baseline: str | None, rounds: int, quick: bool) -> list[dict]:
    """Wall time per step of ``run`` with rtol=None here and in ``baseline`` (fastest of
    ``rounds``, alternating); ``quick``: this checkout against itself, tiny runs."""
    runs = [(n, kw, t / 10, dt) for n, kw, t, dt in COST_RUNS] if quick else COST_RUNS
    runs = [*runs, None]  # None: the recorder alone
    with tempfile.TemporaryDirectory(prefix="fecontact_base_") as tmp:
        base = ROOT
        if baseline:
            base = Path(tmp)
            blob = subprocess.run(["git", "-C", str(ROOT), "archive", baseline],
                                  capture_output=True, check=True).stdout  # fmt: skip
            tarfile.open(fileobj=BytesIO(blob)).extractall(base, filter="data")
        out = []
        for run in runs:
            now, then = [], []
            for _ in range(rounds):
                then.append(_timed(base, run))
                now.append(_timed(ROOT, run))
            a, b = min(now), min(then)
            name, steps = ("recorder, per state", 100) if run is None else (run[0], run[2] / run[3])
            out.append({"case": name, "steps": round(steps), "this_us": 1e6 * a,
                        "baseline_us": 1e6 * b, "ratio": a / b})  # fmt: skip
    return out


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", help="git revision for the cost of rtol=None (default: none)")
    p.add_argument("--rounds", type=int, default=7)
    args = p.parse_args()
    sections = [
        ("Thrown ball, no floor (exact parabola), dt = 1e-3 s", free_flight(args.quick)),
        ("Cantilever in its first mode, 2 periods: max error of q", oscillator(args.quick)),
        (
            "Rigid cases at dt = 1e-3 s (max error of the height or angle against the exact one)",
            rigid_cases(args.quick),
        ),
        ("Founding case: tip distance from its own h/8 run", founding(args.quick)),
    ]
    if args.baseline or args.quick:
        rows = cost(None if args.quick else args.baseline, 1 if args.quick else args.rounds,
                    args.quick)  # fmt: skip
        sections.append((f"Cost per step, rtol=None, against {args.baseline or 'itself'}", rows))
    text = [f"# Steps chosen by a tolerance{' (quick)' if args.quick else ''}", "", machine_note()]
    for caption, rows in sections:
        text += ["", caption, "", markdown_table(rows, list(rows[0]))]
        print(text[-3], "\n", text[-1], flush=True)
    stem = f"{args.out}/adaptive{'_quick' if args.quick else ''}"
    founding_rows = sections[3][1]
    publish(stem, founding_rows, list(founding_rows[0]), "\n".join(text))


if __name__ == "__main__":
    main()
