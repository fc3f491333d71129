"""``fecontact sweep``: every combination of parameter values, each run in its own folder, on
Dask.

    fecontact sweep CASE.py --set restitution=0,0.5,1 --set dt=1e-3,5e-4 [--workers N]
                            [--scheduler ADDRESS] [--out DIR] [run options]

A ``--set`` with one value is fixed, one with a comma list is swept; the runs are the
cartesian product, in the order the ``--set`` options are given (the last varies fastest).
``dt``, ``t_end`` and ``output_interval`` may be swept like case parameters and integrator
options. Each run is ``fecontact run`` with its own ``--out`` folder under the sweep's,
named by its swept values. Without ``--scheduler`` the runs go to a local cluster of worker
processes started for the sweep (one thread each: the runs are independent); with it, to an
existing ``dask.distributed`` scheduler, whose workers need fecontact installed, the case
file at the same path and the output folder on a shared file system.

``sweep.csv`` in the sweep folder has one row per run: the swept values, the scalar entries
of its ``summary.json`` (nested counters as ``key.entry``), and the minimum and maximum of
each probe over the run, floats at full round-trip precision. A run that fails is recorded
with its status and message and the others go on; calling the same sweep again runs only
what has no completed ``summary.json`` yet.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..params import assignment
from .output import FRICTION_COLUMNS, LEDGER_COLUMNS, STANDARD_COLUMNS, read_history

__all__ = ["SWEEP_FILE", "run_sweep", "sweep_axes"]

SWEEP_FILE = "sweep.csv"
RUN_OPTIONS = {"dt": "--dt", "t_end": "--t-end", "output_interval": "--output-interval"}
_UNSAFE = re.compile(r"[^A-Za-z0-9_.+\-=,]")


def sweep_axes(pairs: list[str]) -> list[tuple[str, list[str]]]:
    """``NAME=V1,V2,...`` items as (name, [values as text]), in the given order."""
    axes, seen = [], set()
    for item in pairs:
        name, text = assignment(item, "NAME=VALUE[,VALUE...]")
        if name in seen:
            raise InputError(f"--set {name} is given twice; list its values once, comma separated")
        values = [v.strip() for v in text.split(",")]
        if any(v == "" for v in values):
            raise InputError(f"--set {name}: empty value in {text!r}")
        seen.add(name)
        axes.append((name, values))
    return axes


def _folder(swept: dict[str, str]) -> str:
    """A run's folder name from its swept values: ``restitution=0.5,dt=0.001``."""
    name = ",".join(f"{k}={v}" for k, v in swept.items()) or "run"
    return _UNSAFE.sub("_", name)


def _run_argv(case: Path, values: dict[str, str], out: Path, options: list[str]) -> list[str]:
    argv = ["run", str(case), "--out", str(out), "--quiet", *options]
    for name, value in values.items():
        if name in RUN_OPTIONS:
            argv += [RUN_OPTIONS[name], value]
        else:
            argv += ["--set", f"{name}={value}"]
    return argv


def _completed(out: Path) -> bool:
    try:
        return json.loads((out / "summary.json").read_text())["status"] == "completed"
    except (OSError, ValueError, KeyError, TypeError):
        return False


def _row(swept: dict[str, str], out: Path, result: dict | None) -> dict:
    """One row of sweep.csv: swept values, summary scalars, probe extremes."""
    row = dict(swept)
    try:
        summary = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        summary = {"status": "failed"}
    for key, value in summary.items():
        if isinstance(value, dict):
            for sub, v in value.items():
                if _scalar(v):
                    row[f"{key}.{sub}"] = v
        elif _scalar(value):
            row[key] = value
    if result is not None and result["exit"] != 0:
        row["status"] = summary.get("status", "failed") if result["exit"] == 1 else "failed"
        row["message"] = summary.get("message") or result["message"]
    try:
        history = read_history(out / "history.csv")
    except (OSError, ValueError):
        history = {}
    for name, col in history.items():
        if name in STANDARD_COLUMNS or name in FRICTION_COLUMNS + LEDGER_COLUMNS or col.size == 0:
            continue
        finite = col[np.isfinite(col)]
        if finite.size:
            row[f"{name}_min"], row[f"{name}_max"] = float(finite.min()), float(finite.max())
    return row


def _scalar(v) -> bool:
    return v is None or isinstance(v, bool | int | float | str)


def _cell(v) -> str:
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else str(v)
    return "" if v is None else str(v)


def write_table(path: Path, rows: list[dict]) -> None:
    columns: list[str] = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for row in rows:
            w.writerow([_cell(row.get(c)) for c in columns])


def _client(scheduler: str | None, workers: int):
    import dask
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="10s"), None
        except OSError as err:
            raise InputError(f"--scheduler: cannot reach {scheduler}: {err}") from None
    # each task is one whole run: the workers' statistical profiler (a stack sample every
    # 10 ms, for a dashboard the sweep does not start) only costs the runs 3-4 % of their time
    with dask.config.set({"distributed.worker.profile.enabled": False}):
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        )
    return Client(cluster), cluster


def run_sweep(
    case: Path,
    axes: list[tuple[str, list[str]]],
    out: Path,
    options: list[str],
    workers: int,
    scheduler: str | None = None,
    quiet: bool = False,
    check=None,
    task=None,
) -> int:
    """Run the product of ``axes`` (see the module docstring); return the exit status.

    ``options`` are ``fecontact run`` options given to every run; ``check(values)`` validates
    one combination before anything runs (raises ``InputError``); ``task(argv) -> {"exit",
    "message"}`` runs one ``fecontact run`` command line on a worker
    (:func:`fecontact.io.cli.run_one`)."""
    swept = [name for name, values in axes if len(values) > 1]
    combos = [dict(zip([n for n, _ in axes], c, strict=True)) for c in _product(axes)]
    if check is not None:
        _check_each_value(axes, check)
    out.mkdir(parents=True, exist_ok=True)
    todo, results = [], {}
    for i, values in enumerate(combos):
        folder = out / _folder({k: values[k] for k in swept})
        if not _completed(folder):
            todo.append((i, _run_argv(case, values, folder, options), _cost(values)))
    if todo:
        results = _execute(task, todo, workers, scheduler, quiet)
    rows = [
        _row({k: v[k] for k in swept}, out / _folder({k: v[k] for k in swept}), results.get(i))
        for i, v in enumerate(combos)
    ]
    write_table(out / SWEEP_FILE, rows)
    failed = sum(r.get("status") != "completed" for r in rows)
    if not quiet:
        print(f"{len(combos)} runs ({len(todo)} run now, {failed} failed) -> {out / SWEEP_FILE}")
    return 1 if failed else 0


def _product(axes):
    return itertools.product(*[values for _, values in axes])


def _check_each_value(axes, check) -> None:
    """Every value of every axis, with the first value of the others."""
    first = {name: values[0] for name, values in axes}
    check(first)
    for name, values in axes:
        for value in values[1:]:
            check({**first, name: value})


def _cost(values: dict[str, str]) -> float:
    """A run's relative cost, its number of steps t_end/dt where either is swept (1 if not)."""
    try:
        return float(values.get("t_end", 1.0)) / float(values.get("dt", 1.0))
    except (ValueError, ZeroDivisionError):
        return 1.0


def _execute(task, todo, workers, scheduler, quiet) -> dict:
    from dask.distributed import as_completed
    from tqdm import tqdm

    client, cluster = _client(scheduler, max(1, min(workers, len(todo))))
    results = {}
    try:
        # the costliest runs first, so that no long run starts last while the other workers
        # idle (longest processing time first): submitted in that order and with that priority
        ordered = sorted(todo, key=lambda item: -item[2])  # stable: ties in product order
        futures = {
            client.submit(task, argv, pure=False, priority=cost): i for i, argv, cost in ordered
        }
        bar = tqdm(total=len(todo), desc="sweep", unit="run", file=sys.stderr, disable=quiet)
        for future in as_completed(futures):
            try:
                results[futures[future]] = future.result()
            except Exception as exc:  # a worker lost mid-run
                results[futures[future]] = {"exit": 1, "message": f"{type(exc).__name__}: {exc}"}
            bar.update(1)
        bar.close()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return results
