"""Eight runs one after another against ``fecontact sweep`` on two local workers.

The flexible pendulum (the founding case, 1.5 s) over e_N ∈ {0, 1/3, 2/3, 1} and two step
sizes: h ∈ {5e-4, 2.5e-4} s (runs of about 2 s) and h ∈ {2e-4, 1e-4} s (about 5 s). First
each run through ``fecontact run`` in this process, one after another, then the same eight as
one ``fecontact sweep --workers 2`` (a local cluster of two worker processes, started and
stopped inside the measured time). Reported: both wall times, their ratio, and the largest
difference between the summary figures of the same run.

    python benchmarks/sweep_speed.py           # about three minutes
    python benchmarks/sweep_speed.py --quick   # two runs of 0.05 s: the cluster's start-up
"""

from __future__ import annotations

import csv
import json
import tempfile
import time
from pathlib import Path

from _common import RESULTS, ROOT, markdown_table, parser, write_markdown

from fecontact.cli.commands import main

CASE = str(ROOT / "cases" / "flexible_pendulum.py")
RESTITUTION = ("0", "0.333", "0.667", "1")
SERIES = (("5e-4", "2.5e-4"), ("2e-4", "1e-4"))
FIGURES = ("steps", "energy_final", "max_penetration", "newton_iterations_total", "step_halvings")


EXTRA: list[str] = []
"""Options of every run (--quick: a short end time)."""


def serial(out: Path, steps) -> tuple[float, dict]:
    start = time.perf_counter()
    figures = {}
    for e in RESTITUTION:
        for dt in steps:
            folder = out / f"{e}-{dt}"
            args = ["run", CASE, "--set", f"restitution={e}", "--dt", dt, "--quiet", *EXTRA]
            assert main([*args, "--out", str(folder), "--checkpoint-every", "0"]) == 0
            summary = json.loads((folder / "summary.json").read_text())
            figures[(e, dt)] = {k: summary[k] for k in FIGURES}
    return time.perf_counter() - start, figures


def swept(out: Path, steps) -> tuple[float, dict]:
    start = time.perf_counter()
    args = ["sweep", CASE, "--set", "restitution=" + ",".join(RESTITUTION)]
    args += ["--set", "dt=" + ",".join(steps), "--workers", "2", "--quiet", *EXTRA]
    assert main([*args, "--out", str(out), "--checkpoint-every", "0"]) == 0
    wall = time.perf_counter() - start
    with open(out / "sweep.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return wall, {(r["restitution"], r["dt"]): r for r in rows}


def measure(tmp: Path, steps) -> dict:
    t_serial, one = serial(tmp / "serial", steps)
    t_sweep, rows = swept(tmp / "sweep", steps)
    worst = 0.0
    for (e, dt), fig in one.items():
        row = rows[(e, str(float(dt)))]
        for k, v in fig.items():
            worst = max(worst, abs(float(row[k]) - float(v)))
    return {
        "steps (s)": " and ".join(steps),
        "runs": len(one),
        "serial_s": t_serial,
        "sweep_s": t_sweep,
        "ratio": t_sweep / t_serial,
        "max_figure_difference": worst,
    }


def main_() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    series = SERIES
    if args.quick:
        global RESTITUTION
        RESTITUTION, series = ("0", "1"), (("1e-3",),)
        EXTRA.extend(["--t-end", "0.05"])
    result = []
    for i, steps in enumerate(series):
        with tempfile.TemporaryDirectory() as tmp:
            result.append(measure(Path(tmp) / str(i), steps))
    columns = ["steps (s)", "runs", "serial_s", "sweep_s", "ratio", "max_figure_difference"]
    table = markdown_table(result, columns)
    print(table)
    out = Path(args.out or RESULTS)
    head = "# fecontact sweep against serial runs\n\n2 workers (local cluster), 2 cores.\n\n"
    write_markdown(out / ("sweep_quick.md" if args.quick else "sweep.md"), head + table)


if __name__ == "__main__":
    main_()
