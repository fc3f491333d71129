"""Shared pieces of the benchmark scripts: case loading, runs, exact solutions, tables.

Every benchmark is a plain script (``python benchmarks/NAME.py [--quick] [--out DIR]``) that
prints a Markdown table and writes CSV, Markdown and PNG files into ``benchmarks/results/``
(or ``--out``). ``--quick`` runs a tiny problem in seconds and writes ``*_quick`` files: the
test suite runs every script so (``tests/test_benchmarks.py``), so that none of them rots. Timing
lives here and never in the tests: ``timed_run`` runs the driver without frames and takes the
median of repeated runs; ``trace`` steps ``fecontact.simulate`` and keeps what the error and
stability measures need, one row per step.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import dataclasses
import io
import math
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

import fecontact
from fecontact import SolverError, run
from fecontact.testing import (
    G,
    ball_exact_gap,
    ball_impact_times,
    case,
    episode_starts,
    observed_order,
    pendulum_exact,
    trace,
)
from fecontact.threads import USER_SETTINGS

os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"

__all__ = [
    "G",
    "alternated",
    "RESULTS",
    "ROOT",
    "ball_exact_gap",
    "ball_impact_times",
    "baseline_trees",
    "case",
    "episode_starts",
    "export",
    "fmt",
    "map_runs",
    "markdown_table",
    "observed_order",
    "parser",
    "pendulum_exact",
    "previous_note",
    "read_csv",
    "report",
    "tidy_log_axes",
    "timed_run",
    "trace",
    "versions_parser",
    "versions_row",
    "with_options",
    "publish",
    "write_csv",
    "write_markdown",
]

# the benchmarks step small models outside ``run`` too (``trace``): one BLAS thread, as a run
# has, unless the environment sets a thread count
if not any(os.environ.get(name) for name in USER_SETTINGS):
    threadpool_limits(limits=1, user_api="blas")


def with_options(sim, **options):
    """A copy of ``sim`` with some ``IntegratorOptions`` fields changed."""
    return sim.replace(options=dataclasses.replace(sim.options, **options))


# -- runs ---------------------------------------------------------------------------------------


def run_or_failure(sim, folder) -> tuple[dict, str, str]:
    """Run ``sim`` into ``folder`` (no frames, no checkpoints): its summary, "completed" or
    "failed" (a ``SolverError``: the summary the failed run wrote) and the error's message."""
    try:
        return run(sim, folder, frames=False, checkpoint_every=0), "completed", ""
    except SolverError as err:
        return fecontact.io.output.read_json(Path(folder) / "summary.json"), "failed", str(err)


def timed_run(sim, repeats=3):
    """Run ``sim`` through ``fecontact.run`` (no frames, no checkpoints) ``repeats`` times.

    Returns the medians of ``compute`` (``wall_time_s`` − output phase, s), ``wall`` and each
    phase, ``steps``, the summary and the history (from ``history.csv``) of the first run, and
    ``status``/``message`` ("failed" on ``SolverError``: then a single run)."""
    from fecontact.io.output import read_history

    walls, computes, phases = [], [], {}
    first = None
    for i in range(repeats):
        with tempfile.TemporaryDirectory(prefix="fecontact_bench_") as tmp:
            summary, status, message = run_or_failure(sim, tmp)
            if i == 0:
                first = {
                    "summary": summary,
                    "history": read_history(Path(tmp) / "history.csv"),
                    "status": status,
                    "message": message,
                }
        ph = summary["phase_times_s"]
        walls.append(summary["wall_time_s"])
        computes.append(summary["wall_time_s"] - ph.get("output", 0.0))
        for k, v in ph.items():
            phases.setdefault(k, []).append(v)
        if status != "completed":
            break
    first.update(
        wall=statistics.median(walls),
        compute=statistics.median(computes),
        phases={k: statistics.median(v) for k, v in phases.items()},
        steps=first["summary"]["steps"],
        repeats=len(walls),
    )
    return first


def map_runs(fn, items, workers: int = 1, label=str):
    """[fn(item) for item in items], on a local Dask cluster of ``workers`` processes (one
    thread each: the runs are independent, like those of ``fecontact sweep``) when
    ``workers`` > 1; results in the order of ``items``, each printed as ``label(item)`` when
    it arrives. ``fn`` and the items must pickle (cloudpickle takes this script's functions
    and closures by value)."""
    items = list(items)
    if workers <= 1 or len(items) <= 1:
        return [fn(item) for item in items]
    from dask.distributed import Client, LocalCluster, as_completed

    # the workers import this folder's modules (_common) as the script does
    here = str(Path(__file__).resolve().parent)
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [here, *filter(None, [os.environ.get("PYTHONPATH")])]
    )
    with (
        LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        futures = {client.submit(fn, item, pure=False): i for i, item in enumerate(items)}
        results = [None] * len(items)
        for done, future in enumerate(as_completed(futures), 1):
            i = futures[future]
            results[i] = future.result()
            print(f"[{done}/{len(items)}] {label(items[i])}", flush=True)
    return results


# -- tables and files ---------------------------------------------------------------------------


def parser(description: str, from_csv: bool = False) -> argparse.ArgumentParser:
    """--quick and --out; with ``from_csv``, --from-csv to redo tables from an earlier run."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument(
        "--quick",
        action="store_true",
        help="a tiny problem (seconds) that checks the script runs: not a measurement",
    )
    p.add_argument("--out", default=str(RESULTS), help="output folder (default: %(default)s)")
    if from_csv:
        p.add_argument("--from-csv", help="redo the tables and plot from this CSV, without runs")
    return p


def fmt(value) -> str:
    """A table cell: floats with 3 significant digits, everything else as text."""
    if isinstance(value, bool | np.bool_):
        return "yes" if value else "no"
    if isinstance(value, int | np.integer):
        return str(int(value))
    if isinstance(value, float | np.floating):
        v = float(value)
        if math.isnan(v):
            return "–"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        if v == 0.0:
            return "0"
        if 1e-3 <= abs(v) < 1e4:
            return f"{v:.3g}"
        return f"{v:.2e}"
    return str(value).replace("|", "\\|")


def markdown_table(rows, columns, headers=None) -> str:
    headers = headers or columns
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        lines.append("| " + " | ".join(fmt(r.get(c, "")) for c in columns) + " |")
    return "\n".join(lines)


def report(title: str, *sections) -> str:
    """A Markdown report: ``title``, then each (caption, rows) as a paragraph and a table of
    the rows' columns."""
    text = [f"# {title}"]
    for caption, rows in sections:
        text += ["", caption, "", markdown_table(rows, list(rows[0]))]
    return "\n".join(text)


def publish_report(out, stem: str, quick: bool, title: str, rows, *sections) -> str:
    """The report of ``sections`` (:func:`report`) under ``title``, printed and published as
    ``out``/``stem`` (``stem``_quick for a quick run) with ``rows`` as its CSV; the report's
    text."""
    suffix = "_quick" if quick else ""
    text = report(title + (" (quick)" if quick else ""), *sections)
    print(text)
    publish(Path(out) / f"{stem}{suffix}", rows, list(rows[0]), text)
    return text


def write_csv(path, rows, columns) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for r in rows:
            w.writerow([_csv_cell(r.get(c, "")) for c in columns])
    return path


def read_csv(path) -> list[dict]:
    """Rows of a CSV written by ``write_csv``, numbers converted back (int, else float)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k, v in r.items():
            for kind in (int, float):
                try:
                    r[k] = kind(v)
                    break
                except ValueError:
                    pass
    return rows


def _csv_cell(v):
    if isinstance(v, float | np.floating):
        return repr(float(v))
    if isinstance(v, bool | np.bool_):
        return int(v)
    return v


def write_markdown(path, text: str) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text.rstrip() + "\n")
    return path


def publish(stem, rows, columns, text: str, plot=None) -> None:
    """A benchmark's results: ``stem``.csv (``rows`` at full precision), ``stem``.md (``text``)
    and, given ``plot(rows, path)``, ``stem``.png."""
    write_csv(f"{stem}.csv", rows, columns)
    write_markdown(f"{stem}.md", text)
    if plot is not None:
        plot(rows, Path(f"{stem}.png"))


def tidy_log_axes(ax) -> None:
    """Log axes without the crowded minor tick labels matplotlib puts on short decades."""
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="both", lw=0.3)


def previous_note(csv_path) -> str:
    """The machine note of the run that wrote ``csv_path`` (from the Markdown file beside it),
    for tables redone from a CSV."""
    md = Path(csv_path).with_suffix(".md")
    lines = md.read_text().splitlines() if md.is_file() else []
    old = lines[2] if len(lines) > 2 else "an earlier run"
    return f"Tables redone from {Path(csv_path).name}; the runs: {old.rstrip('.')}"


def machine_note() -> str:
    import platform

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    return (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, load "
        f"{load:.2f} at start; Python {platform.python_version()}, fecontact "
        f"{fecontact.__version__}; `{' '.join([Path(sys.argv[0]).name, *sys.argv[1:]])}`"
    )


def alternated(trees: dict, repeats: int, run) -> dict:
    """``run(tree)`` ``repeats`` times for each of ``trees`` (name: tree), alternated tree by
    tree so that a change of load on the machine hits every version alike: by name, the
    results in order."""
    runs = {name: [] for name in trees}
    for _ in range(repeats):
        for name, tree in trees.items():
            runs[name].append(run(tree))
    return runs


def versions_row(row: dict, count: str, same: str, others, share: dict | None = None) -> str:
    """The Markdown row of one case timed on several versions: its name, ``row[count]``, this
    checkout's median (and minimum) time, then per other version its time and the ratio of
    this checkout's median over its, and whether all agreed (``row[same]``). ``share``: by
    version, a fraction shown after each time (None: no such column)."""
    med, low = row["median_us"], row["min_us"]

    def time(name: str) -> str:
        extra = "" if share is None else f" | {share[name]:.1%}"
        return f"{med[name]:.1f} ({low[name]:.1f}){extra}"

    cells = [f"{time(b)} | {med['new'] / med[b]:.3f}" for b in others]
    return (
        f"| {row['case']} | {row[count]} | {time('new')} | "
        + " | ".join(cells)
        + f" | {'yes' if row[same] else 'NO'} |"
    )


def versions_parser(description: str, repeats: tuple[int, int], baseline: str):
    """The command line of a script that times this checkout against earlier versions:
    ``--quick``, ``--repeats`` (default ``repeats``: (quick, full) processes of each) and
    ``--baseline`` (git revisions separated by commas, default ``baseline``)."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--quick", action="store_true", help=f"short runs, {repeats[0]} repeats")
    p.add_argument(
        "--repeats", type=int, default=None, help=f"processes of each (default {repeats[1]})"
    )
    p.add_argument(
        "--baseline",
        default=baseline,
        help="git revisions to compare with, separated by commas (default: %(default)s)",
    )
    return p


def export(revision: str, folder: Path) -> Path:
    """The package at ``revision`` of this repository, written into ``folder``."""
    tar = subprocess.run(
        ["git", "-C", str(ROOT), "archive", "--format=tar", revision],
        check=True,
        capture_output=True,
    ).stdout
    folder.mkdir(parents=True, exist_ok=True)
    with tarfile.open(fileobj=io.BytesIO(tar)) as archive:
        archive.extractall(folder, filter="data")
    return folder


@contextlib.contextmanager
def baseline_trees(revisions: str):
    """The package at each of ``revisions`` (git revisions of this repository separated by
    commas) exported into a temporary folder for the ``with`` block: (the revisions, by name
    the trees, with this checkout as "new")."""
    baselines = [b.strip() for b in revisions.split(",") if b.strip()]
    with tempfile.TemporaryDirectory(prefix="fecontact_baseline_") as tmp:
        trees = {b: export(b, Path(tmp) / b) for b in baselines}
        trees["new"] = ROOT
        yield baselines, trees
