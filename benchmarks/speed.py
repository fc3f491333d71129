"""Speed of small systems against the project's targets, measured side by side in one run.

- time per step of the founding cases (``cases/*.py`` with their defaults), from
  ``summary.json`` of ``fecontact.run`` without frames: (``wall_time_s`` − the output phase) /
  steps, the median of ``--repeats`` runs, against its target: flexible pendulum ≤ 1 ms,
  bouncing ball and rigid pendulum ≤ 70 µs, impacting bar (100 elements) ≤ 0.4 ms;
- frame output: the flexible pendulum writing a frame every 10 steps (its 0.01 s output
  interval) against the same run without frames, ``wall_time_s`` of both (history included):
  ≤ +20 %;
- a far obstacle: the flexible pendulum without its stop, and with the stop moved 10 m away
  (a contact pair that never becomes a candidate), 1 s: ≤ +5 %;
- import time: ``import fecontact`` against ``import skfem`` in fresh interpreters (the time
  of the import statement alone): ≤ +0.2 s.

The runs of each comparison alternate, so that a change of load on the machine hits both.

    python benchmarks/speed.py [--quick] [--repeats N]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import statistics
import subprocess
import sys
import tempfile
import time

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact import Contact, Model, Plane, run

CASES = [
    # (case, target s per step)
    ("flexible_pendulum", 1e-3),
    ("bouncing_ball", 70e-6),
    ("rigid_pendulum", 70e-6),
    ("impacting_bar", 0.4e-3),
]
FRAME_TARGET = 0.20
OBSTACLE_TARGET = 0.05
IMPORT_TARGET = 0.2  # s
COLUMNS = ["measure", "value", "unit", "target", "ratio", "met", "detail"]


def run_once(sim, frames: bool) -> dict:
    with tempfile.TemporaryDirectory(prefix="fecontact_speed_") as tmp:
        return run(sim, tmp, frames=frames, checkpoint_every=0)


def compute_per_step(summary: dict) -> float:
    """(wall_time_s − output phase) / steps, s."""
    return (summary["wall_time_s"] - summary["phase_times_s"].get("output", 0.0)) / max(
        summary["steps"], 1
    )


QUICK = 0.02
"""The share of each run that --quick takes (with one repeat): a check that the script runs."""


def alternate(runs: dict, repeats: int) -> dict:
    """Call every function of ``runs`` ``repeats`` times, interleaved; lists of results."""
    out = {k: [] for k in runs}
    for _ in range(repeats):
        for k, fn in runs.items():
            out[k].append(fn())
    return out


def case_rows(repeats: int, quick: bool) -> list[dict]:
    sims = {}
    for name, _ in CASES:
        sim = common.case(name).build()
        sims[name] = sim.replace(t_end=sim.t_end * QUICK) if quick else sim
    results = alternate({n: (lambda s=s: run_once(s, False)) for n, s in sims.items()}, repeats)
    rows = []
    for name, target in CASES:
        per_step = statistics.median(compute_per_step(s) for s in results[name])
        summary = results[name][0]
        rows.append(
            {
                "measure": f"{name}: time per step",
                "value": per_step * 1e6,
                "unit": "µs",
                "target": target * 1e6,
                "ratio": per_step / target,
                "met": per_step <= target,
                "detail": f"{summary['steps']} steps, {summary['n_dofs']} dofs, Newton "
                f"{summary['newton_iterations_mean']:.2f}/step; median of {repeats}",
            }
        )
    return rows


def frame_row(repeats: int, quick: bool) -> dict:
    sim = common.case("flexible_pendulum").build()
    sim = sim.replace(t_end=sim.t_end * QUICK) if quick else sim
    res = alternate(
        {f: (lambda f=f: run_once(sim, f)) for f in (False, True)},
        repeats,
    )
    wall = {f: statistics.median(s["wall_time_s"] / s["steps"] for s in res[f]) for f in res}
    extra = wall[True] / wall[False] - 1.0
    every = round(sim.output_interval / sim.dt)
    return {
        "measure": f"flexible_pendulum: frame every {every} steps",
        "value": 100.0 * extra,
        "unit": "%",
        "target": 100.0 * FRAME_TARGET,
        "ratio": extra / FRAME_TARGET,
        "met": extra <= FRAME_TARGET,
        "detail": f"wall per step {1e6 * wall[False]:.0f} µs without frames, "
        f"{1e6 * wall[True]:.0f} µs with (history written in both)",
    }


def obstacle_row(repeats: int, quick: bool) -> dict:
    def build(distant: bool):
        sim = common.case("flexible_pendulum").build()
        beam = sim.model.bodies[0]
        far = Contact(beam, Plane([-10.0, 0.0], [1.0, 0.0]), nodes=[-1])
        model = Model([beam], [far] if distant else [], gravity=(0.0, -9.81))
        return sim.replace(model=model, probes={}, t_end=QUICK if quick else 1.0)

    sims = {d: build(d) for d in (False, True)}
    res = alternate({d: (lambda d=d: run_once(sims[d], False)) for d in sims}, repeats)
    per = {d: statistics.median(compute_per_step(s) for s in res[d]) for d in res}
    extra = per[True] / per[False] - 1.0
    return {
        "measure": "flexible_pendulum: stop 10 m away vs none",
        "value": 100.0 * extra,
        "unit": "%",
        "target": 100.0 * OBSTACLE_TARGET,
        "ratio": abs(extra) / OBSTACLE_TARGET,
        "met": abs(extra) <= OBSTACLE_TARGET,
        "detail": f"{1e6 * per[False]:.0f} µs per step without contacts, "
        f"{1e6 * per[True]:.0f} µs with the far stop",
    }


def import_seconds(module: str) -> float:
    code = f"import time; t = time.perf_counter(); import {module}; print(time.perf_counter() - t)"
    out = subprocess.run(
        [sys.executable, "-c", code],
        cwd=common.ROOT,
        capture_output=True,
        text=True,
        check=True,
        env={**common.os.environ, "PYTHONPATH": str(common.ROOT)},
    )
    return float(out.stdout.strip().splitlines()[-1])


def import_row(repeats: int) -> dict:
    res = alternate({m: (lambda m=m: import_seconds(m)) for m in ("skfem", "fecontact")}, repeats)
    t = {m: statistics.median(v) for m, v in res.items()}
    extra = t["fecontact"] - t["skfem"]
    return {
        "measure": "import fecontact − import skfem",
        "value": extra,
        "unit": "s",
        "target": IMPORT_TARGET,
        "ratio": extra / IMPORT_TARGET,
        "met": extra <= IMPORT_TARGET,
        "detail": f"skfem {t['skfem']:.3f} s, fecontact {t['fecontact']:.3f} s (fresh "
        f"interpreters, median of {repeats})",
    }


def main(argv=None):
    p = common.parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5, help="runs per measure (median)")
    args = p.parse_args(argv)
    repeats = 1 if args.quick else args.repeats
    note = common.machine_note()
    t0 = time.perf_counter()
    rows = case_rows(repeats, args.quick)
    rows.append(frame_row(repeats, args.quick))
    rows.append(obstacle_row(repeats, args.quick))
    rows.append(import_row(1 if args.quick else max(repeats, 5)))
    for r in rows:
        print(
            f"{r['measure']:45s} {common.fmt(r['value']):>8s} {r['unit']:2s} "
            f"(target {common.fmt(r['target'])}) {'met' if r['met'] else 'NOT MET'}"
        )
    md = common.markdown_table(rows, COLUMNS)
    scope = f" (--quick: {QUICK:.0%} of each run, once)" if args.quick else ""
    text = (
        f"# Speed of small systems against the targets\n\n{note}; "
        f"{time.perf_counter() - t0:.0f} s{scope}.\n\n"
        "Time per step = (`wall_time_s` − `phase_times_s.output`) / steps of `fecontact.run` "
        "without frames; frame and obstacle rows compare runs made alternately in this "
        "script; ratio = value / target.\n\n" + md
    )
    stem = common.Path(args.out) / ("speed_quick" if args.quick else "speed")
    common.write_csv(f"{stem}.csv", rows, COLUMNS)
    common.write_markdown(f"{stem}.md", text)
    print(md)
    return rows


if __name__ == "__main__":
    main()
