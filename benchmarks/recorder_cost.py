"""What a history row costs: the recorder's time per recorded state, against an earlier version.

A run's recorder (``fecontact.recorder.Recorder``) accounts for every state the time loop
yields: the energies, the energy balance and ledger, the contacts that closed, the probes,
and the history row. Its time is the ``output`` phase of ``summary.json`` (with frames off),
left out of ``time_per_step_s``.

Measured in fresh interpreters, alternately with the package of each ``--baseline`` (git
revisions of this repository, exported into a temporary folder) and with this checkout, so
that a change of load on the machine hits all of them: a process builds the case, steps it
once with ``fecontact.simulate`` and keeps its states, then feeds them to new recorders
(``record`` and the blow-up check of the driver, per state), ``--inner`` times; the CPU time
per row (``time.process_time``) is the least of these. Per case: the median and minimum over
the processes of each version, the ratio of the medians (this checkout over the other), and
whether every version that stepped the same states wrote the same ``history.csv`` and the
same energy summaries (byte for byte, on the keys every version writes: the recorder's savings
must not change what it reports, while a later version may report a new term; a version whose
time loop differs at round-off is compared in time only).

    python benchmarks/recorder_cost.py [--quick] [--repeats N] [--baseline REV[,REV...]]
        [--out DIR]
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
from stepper_speed import write_table

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
# the cases, with their duration in full and quick runs (s)
CASES = {
    "spatial_pendulum": (1.5, 0.1),
    "flexible_pendulum": (1.5, 0.1),
    "bouncing_ball": (5.0, 0.5),
}

# runs in a fresh interpreter: the recorder's CPU time per row over a run's states, the least
# of ``inner`` passes, and digests of what it wrote (history.csv, energy summaries)
WORKER = """
import hashlib, json, sys, tempfile, time
from pathlib import Path
from fecontact.cli import load_case
from fecontact.recorder import Recorder
from fecontact.time import simulate
path, t_end, inner = Path(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
sim = load_case(path).build().replace(t_end=t_end)
start = time.process_time()
states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0))
step = (time.process_time() - start) / (len(states) - 1)
best, digest = float("inf"), None
with tempfile.TemporaryDirectory() as tmp:
    for _ in range(inner):
        rec = Recorder(sim, Path(tmp))
        start = time.process_time()
        for st in states:
            rec.record(st)
            rec.balance.runaway()
        best = min(best, (time.process_time() - start) / len(states))
        rec.history.close()
        text = (Path(tmp) / "history.csv").read_bytes()
        summaries = [rec.ledger.summary(*rec.energies), rec.balance.summary()]
        digest = hashlib.sha256(text).hexdigest()
        energies = json.loads(json.dumps(summaries, default=str))
        counts = json.loads(json.dumps(rec.stats(), default=str))
stepped = hashlib.sha256(b"".join(st.q.tobytes() + st.v.tobytes() for st in states)).hexdigest()
print(json.dumps({"per_row": best, "per_step": step, "rows": len(states), "output": digest,
                  "energies": energies, "counts": counts, "states": stepped}))
"""


def one_run(tree: Path, case: str, t_end: float, inner: int) -> dict:
    """The recorder's time per row of ``case`` with the package of ``tree``, in a fresh
    interpreter."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    path = str(tree / "cases" / f"{case}.py")
    args = [sys.executable, "-c", WORKER, path, repr(t_end), str(inner)]
    out = subprocess.run(args, check=True, capture_output=True, text=True, env=env, cwd=tree)
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure(trees: dict, repeats: int, quick: bool, inner: int) -> list[dict]:
    """Per case: µs per row of each tree (median and minimum over ``repeats`` processes,
    alternated tree by tree) and whether all wrote the same output."""
    rows = []
    for case, durations in CASES.items():
        t_end = durations[1 if quick else 0]
        runs = alternated(trees, repeats, partial(one_run, case=case, t_end=t_end, inner=inner))
        per = {n: [1e6 * r["per_row"] for r in runs[n]] for n in runs}
        # the recorder's time over the step's, process by process
        share = {n: [r["per_row"] / r["per_step"] for r in runs[n]] for n in runs}
        rows.append(
            {
                "case": case,
                "rows": runs["new"][0]["rows"],
                "median_us": {n: statistics.median(per[n]) for n in per},
                "min_us": {n: min(per[n]) for n in per},
                "share": {n: statistics.median(share[n]) for n in share},
                "same_output": same_output(runs),
            }
        )
    return rows


def same_output(runs: dict) -> bool:
    """Whether every run that stepped the same states as this checkout (a version whose time
    loop differs at round-off steps others, and is compared in time only) wrote the same
    history, energy summaries and the recorder's counts (on the keys every version has)."""
    states = runs["new"][0]["states"]
    same = [r for n in runs for r in runs[n] if r["states"] == states]
    # (the recorder's counts and the energy summaries compared on the keys every version has:
    # a version may count more, or name another term of the ledger)
    counts = {common(r.get("counts", {}), [x.get("counts", {}) for x in same]) for r in same}
    energies = {
        tuple(common(e, [x["energies"][i] for x in same]) for i, e in enumerate(r["energies"]))
        for r in same
    }
    return len({r["output"] for r in same}) == 1 and len(counts) == 1 and len(energies) == 1


def common(d: dict, dicts: list[dict]) -> str:
    """``d`` on the keys every one of ``dicts`` has (in nested dicts too), as JSON."""
    return json.dumps(shared(d, dicts))


def shared(d: dict, dicts: list[dict]) -> dict:
    """``d`` restricted to the keys every one of ``dicts`` has, level by level."""
    keys = set.intersection(*(set(x) for x in dicts))
    return {
        k: shared(d[k], [x[k] for x in dicts])
        if all(isinstance(x[k], dict) for x in dicts)
        else d[k]
        for k in sorted(keys)
    }


def table(rows: list[dict], repeats: int, baselines: list[str]) -> str:
    lines = [
        f"The recorder's CPU time per history row (µs): median (and minimum) over {repeats} "
        "processes of each version, alternated, of the least of the passes in each process; "
        "ratio: this checkout's median over the other's; share: the median over the processes "
        "of the recorder's time per row over the CPU time of a step (one run of the time loop "
        "in the same process). Same output: history.csv and the energy summaries are "
        "byte-identical (on the keys every version writes) in every run of every version that "
        "stepped the same states.",
        "",
        "| case | rows | this checkout | share | "
        + " | ".join(f"{b} | share | ratio" for b in baselines)
        + " | same output |",
        "| --- | ---: | ---: | ---: | "
        + " | ".join("---: | ---: | ---:" for _ in baselines)
        + " | --- |",
    ]
    lines += [versions_row(r, "rows", "same_output", baselines, r["share"]) for r in rows]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    # (the default baseline: the Beam3D kernel of today, the recorder before: same output)
    parser = versions_parser(__doc__.splitlines()[0], (1, 5), "fb610ca")
    parser.add_argument("--inner", type=int, default=5, help="passes per process (default 5)")
    parser.add_argument("--out", default=str(RESULTS), help="output folder (default: %(default)s)")
    args = parser.parse_args(argv)
    repeats = args.repeats or (1 if args.quick else 5)
    with baseline_trees(args.baseline) as (baselines, trees):
        rows = measure(trees, repeats, args.quick, 2 if args.quick else args.inner)
    text = table(rows, repeats, baselines)
    print(text)
    write_table(args.out, "recorder_cost", args.quick, "The recorder's cost per row", text)
    return 0 if all(r["same_output"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
