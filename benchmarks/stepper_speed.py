"""Time per step of the stepper against an earlier version of the package, side by side.

The earlier versions (``--baseline``, git revisions of this repository separated by commas;
default 21d058e, the stepper before it was configured once per run) are exported into a
temporary folder. Each case then runs in fresh interpreters, alternately on every baseline
and on this checkout (and, with ``--noise``, on this checkout a second time: the ratio of the
two copies is the noise of the measurement), so that a change of load on the machine hits
all of them. A process steps the case with
``fecontact.simulate`` (no output), a model built anew for each run, and reports the CPU
time per step (``time.process_time``, which the other processes of a loaded machine disturb
far less than the wall clock), the least of its runs. Per case: the median and the minimum
over the processes of each version, the ratio of the medians (this checkout over each
other), and whether the positions and velocities of every step are bit-identical in all
runs of every version (a refactor must not change a result).

Cases: the founding flexible pendulum (1.5 s, 1500 steps), the bouncing ball (5 s, 5000
steps of a point mass) and two elastic disks colliding (580 dofs, smooth contact,
node-to-surface contact as in the baseline), each with its defaults otherwise, impacts at
the end of their step (``localize=False``, the baseline's only way;
``benchmarks/localization.py`` measures the cost of localization).

A full run exits 1 where a history differs; ``--quick`` (a few steps, one process of each
version) always exits 0.

``--single`` adds the CPU time of one step repeated from stored states of each case (a step
in flight, near the floor and resting for the ball; steps of the swing and of the contact for
the others), every version loaded in one interpreter and alternated batch by batch: far less
noisy on a loaded machine than whole runs in separate processes.

    python benchmarks/stepper_speed.py [--quick] [--repeats N] [--baseline REV[,REV...]]
        [--noise] [--single] [--out DIR]
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from functools import partial
from pathlib import Path

from _common import alternated, baseline_trees, versions_parser, versions_row

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
CASES = ("flexible_pendulum", "bouncing_ball", "two_disks")
# two_disks with node-to-surface contact, the baseline's (mortar became the default later)
BASELINE_PARAMS = {"two_disks": {"method": "node-to-surface"}}

# runs in a fresh interpreter: the CPU time per step of the time loop (``simulate``, a
# model built anew for each run, so that every run makes its own factorizations), the least
# of ``inner`` runs, and a digest of the positions of every step
WORKER = """
import dataclasses, hashlib, json, sys, time
from pathlib import Path
try:
    from fecontact.cli.cases import load_case
except ImportError:  # (a baseline from before the command line had its own layer)
    from fecontact.io.cli import load_case
from fecontact.time import simulate
path, t_end, inner = Path(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
params = json.loads(sys.argv[4])
best, digest = float("inf"), None
for _ in range(inner):
    try:  # the baseline's discretization, where a later version changed the case's default
        sim = load_case(path).build(**params)
    except Exception:  # (a baseline without that parameter: its only discretization)
        sim = load_case(path).build()
    t_end = t_end if t_end > 0 else sim.t_end
    opts = sim.options
    # impacts at the end of their step, as in a baseline from before impact localization
    if "localize" in {f.name for f in dataclasses.fields(opts)}:
        opts = dataclasses.replace(opts, localize=False)
    start = time.process_time()
    states = list(simulate(sim.model, sim.dt, t_end, opts, q0=sim.q0, v0=sim.v0))
    best = min(best, (time.process_time() - start) / (len(states) - 1))
    h = hashlib.sha256()
    for st in states:
        h.update(st.q.tobytes())
        h.update(st.v.tobytes())
    digest = h.hexdigest()
print(json.dumps({"per_step": best, "steps": len(states) - 1, "history": digest}))
"""


# ``--single``: one interpreter loads every tree in turn (each under its own copy of the
# package's modules) and steps each case from stored states of its own run, the trees
# alternated batch by batch, so that a change of load hits all of them alike: the CPU time of
# one step (``time.process_time``) from each state, the least over the rounds
SINGLE = """
import dataclasses, gc, json, sys, time
from pathlib import Path
trees, spec = json.loads(sys.argv[1]), json.loads(sys.argv[2])
reps, rounds = int(sys.argv[3]), int(sys.argv[4])
steps = {}
for name, tree in trees.items():
    for key in [k for k in sys.modules if k.split(".")[0] == "fecontact"]:
        del sys.modules[key]
    sys.path.insert(0, tree)
    try:
        try:
            from fecontact.cli.cases import load_case
        except ImportError:
            from fecontact.io.cli import load_case
        from fecontact.time import simulate
        from fecontact.time.state import PhaseTimer
        for case, (params, picks) in spec.items():
            try:
                sim = load_case(Path(tree) / "cases" / f"{case}.py").build(**params)
            except Exception:
                sim = load_case(Path(tree) / "cases" / f"{case}.py").build()
            opts = sim.options
            if "localize" in {f.name for f in dataclasses.fields(opts)}:
                opts = dataclasses.replace(opts, localize=False)
            end = (max(picks.values()) + 1) * sim.dt
            states = list(simulate(sim.model, sim.dt, end, opts, q0=sim.q0, v0=sim.v0))
            try:  # the run's configured stepper, penetration record included
                from fecontact.time.stepper import make_stepper
                step = make_stepper(sim.model, opts).step
            except ImportError:  # (a version before it: the step function itself)
                from fecontact.time.simulate import STEPPERS
                model, kind = sim.model, STEPPERS[opts.integrator]
                def step(st, h, timer, model=model, kind=kind, opts=opts):
                    return kind(model, st, h, opts, timer)
            for pick, i in picks.items():
                steps[(case, pick, name)] = (step, states[i], sim.dt, PhaseTimer())
    finally:
        sys.path.remove(tree)
gc.collect()
gc.freeze()  # (the stored runs are not the steps' garbage)
best = dict.fromkeys(steps, float("inf"))
for _ in range(rounds):
    for key, (step, st, h, timer) in steps.items():
        start = time.process_time()
        for _ in range(reps):
            step(st, h, timer)
        best[key] = min(best[key], (time.process_time() - start) / reps)
print(json.dumps([[*key, value] for key, value in best.items()]))
"""
# the states stepped from, by case: (parameters, {name: step index})
SINGLE_STEPS = {
    "bouncing_ball": ({}, {"in flight": 10, "candidate, no contact": 449, "resting": 4900}),
    "flexible_pendulum": ({}, {"step 50": 50, "step 400": 400, "step 1000": 1000}),
    "two_disks": ({"method": "node-to-surface"}, {"step 10": 10, "step 60": 60}),
}


def single_steps(trees: dict, quick: bool) -> str:
    """The table of one step's CPU time from stored states of each case, every tree in one
    interpreter, alternated (``SINGLE``)."""
    spec = {c: v for c, v in SINGLE_STEPS.items() if not quick or c == "bouncing_ball"}
    reps, rounds = (50, 3) if quick else (100, 20)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    args = [json.dumps({n: str(t) for n, t in trees.items()}), json.dumps(spec), str(reps)]
    out = subprocess.run(
        [sys.executable, "-c", SINGLE, *args, str(rounds)],
        check=True,
        capture_output=True,
        text=True,
        env=env,
    )
    best = {(c, p, n): v for c, p, n, v in json.loads(out.stdout.strip().splitlines()[-1])}
    others = [n for n in trees if n != "new"]
    lines = [
        f"CPU time of one step from a stored state (µs), the least of {rounds} rounds of "
        f"{reps} steps, every version in one interpreter, alternated; ratio: this checkout's "
        "over the other's.",
        "",
        "| case | state | this checkout | " + " | ".join(f"{n} | ratio" for n in others) + " |",
        "| --- | --- | ---: | " + " | ".join("---: | ---:" for _ in others) + " |",
    ]
    for case, (_, picks) in spec.items():
        for pick in picks:
            new = best[(case, pick, "new")]
            cells = [
                f"{1e6 * best[(case, pick, n)]:.1f} | {new / best[(case, pick, n)]:.3f}"
                for n in others
            ]
            lines.append(f"| {case} | {pick} | {1e6 * new:.1f} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def one_run(tree: Path, case: str, t_end: float | None, inner: int) -> dict:
    """Runs of ``case`` with the package of ``tree``, in a fresh interpreter."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    path = str(tree / "cases" / f"{case}.py")
    params = json.dumps(BASELINE_PARAMS.get(case, {}))
    args = [sys.executable, "-c", WORKER, path, repr(t_end or 0.0), str(inner), params]
    out = subprocess.run(args, check=True, capture_output=True, text=True, env=env, cwd=tree)
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure(trees: dict, repeats: int, quick: bool, inner: int) -> list[dict]:
    """Per case, the CPU time per step of each tree (median and minimum over ``repeats``
    processes, alternated tree by tree) and whether every run's history is the same."""
    rows = []
    for case in CASES:
        t_end = {"flexible_pendulum": 0.3, "bouncing_ball": 1.0, "two_disks": 0.002}[case]
        t_end = t_end if quick else None
        runs = alternated(trees, repeats, partial(one_run, case=case, t_end=t_end, inner=inner))
        per = {n: [r["per_step"] for r in runs[n]] for n in runs}
        rows.append(
            {
                "case": case,
                "steps": runs["new"][0]["steps"],
                "median_us": {n: 1e6 * statistics.median(per[n]) for n in per},
                "min_us": {n: 1e6 * min(per[n]) for n in per},
                "same_history": len({r["history"] for n in runs for r in runs[n]}) == 1,
            }
        )
    return rows


def table(rows: list[dict], repeats: int, baselines: list[str], noise: bool) -> str:
    """The times of every tree and the ratios of this checkout over each baseline (and over
    its own second copy: the same code's noise)."""
    others = [*baselines, *(["same code"] if noise else [])]
    lines = [
        f"CPU time per step of the time loop (µs): median (and minimum) over {repeats} "
        "processes of each version, alternated, of the least of the runs in each process; "
        "ratio: this checkout's median over the other's. 'same code': a second copy of this "
        "checkout in the same alternation (its ratio is the noise of the measurement). Same "
        "history: the positions and velocities of every step are bit-identical in every run "
        "of every version.",
        "",
        "| case | steps | this checkout | "
        + " | ".join(f"{b} | ratio" for b in others)
        + " | same history |",
        "| --- | ---: | ---: | " + " | ".join("---: | ---:" for _ in others) + " | --- |",
    ]
    lines += [versions_row(r, "steps", "same_history", others) for r in rows]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = versions_parser(__doc__.splitlines()[0], (1, 7), "21d058e")
    parser.add_argument(
        "--noise", action="store_true", help="also time a second copy of this checkout"
    )
    parser.add_argument(
        "--single", action="store_true", help="also time single steps from stored states"
    )
    parser.add_argument("--out", default=str(RESULTS), help="output folder (default: %(default)s)")
    args = parser.parse_args(argv)
    repeats = args.repeats or (1 if args.quick else 7)
    with baseline_trees(args.baseline) as (baselines, trees):
        if args.noise:  # this checkout's own files, a second time (same code)
            trees["same code"] = ROOT
        rows = measure(trees, repeats, args.quick, 1 if args.quick else 3)
        text = table(rows, repeats, baselines, args.noise)
        if args.single:
            text += "\n" + single_steps(
                {n: t for n, t in trees.items() if n != "same code"}, args.quick
            )
    print(text)
    write_table(args.out, "stepper_speed", args.quick, "Stepper speed", text)
    # (--quick shows the script works, as bit_identity's: the physics may since have changed
    # on purpose, e.g. the two passes' minimum-norm multipliers of node-to-surface disks)
    return 0 if args.quick or all(r["same_history"] for r in rows) else 1


def write_table(out, stem: str, quick: bool, title: str, text: str) -> Path:
    """``text`` under the heading ``title`` in ``out``/``stem``.md (``stem``_quick.md for a
    quick run); the path written."""
    path = Path(out) / (f"{stem}_quick.md" if quick else f"{stem}.md")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"# {title}\n\n{text}")
    print(f"wrote {path}")
    return path


if __name__ == "__main__":
    sys.exit(main())
