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
import logging
import math
import os
import re
import sys
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.output import (
    FRICTION_COLUMNS,
    LEDGER_COLUMNS,
    OBSTACLE_COLUMNS,
    STANDARD_COLUMNS,
    read_history,
)
from ..io.progress import in_notebook, is_terminal
from ..params import assignment
from .run import RUN_OPTIONS

__all__ = ["SWEEP_FILE", "run_sweep", "sweep_axes"]

SWEEP_FILE = "sweep.csv"
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


def _summary_scalars(out: Path) -> dict:
    """The scalar entries of a run's ``summary.json``, nested counters as ``key.entry``."""
    try:
        summary = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        summary = {"status": "failed"}
    row = {}
    for key, value in summary.items():
        if isinstance(value, dict):
            row |= {f"{key}.{sub}": v for sub, v in value.items() if _scalar(v)}
        elif _scalar(value):
            row[key] = value
    return row


def _probe_extremes(out: Path) -> dict:
    """The minimum and maximum of each probe of a run over its finite values."""
    try:
        history = read_history(out / "history.csv")
    except (OSError, ValueError):
        return {}
    row = {}
    for name, col in history.items():
        if name in STANDARD_COLUMNS or name in FRICTION_COLUMNS + LEDGER_COLUMNS + OBSTACLE_COLUMNS:
            continue
        finite = col[np.isfinite(col)]
        if finite.size:
            row[f"{name}_min"], row[f"{name}_max"] = float(finite.min()), float(finite.max())
    return row


def _row(swept: dict[str, str], out: Path, result: dict | None) -> dict:
    """One row of sweep.csv: swept values, summary scalars, probe extremes."""
    row = dict(swept) | _summary_scalars(out)
    if result is not None and result["exit"] != 0:
        row["status"] = row.get("status", "failed") if result["exit"] == 1 else "failed"
        row["message"] = row.get("message") or result["message"]
    return row | _probe_extremes(out)


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
    from ..extras import need

    dask = need("dask", "sweep")
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="10s"), None
        except OSError as err:
            raise InputError(f"--scheduler: cannot reach {scheduler}: {err}") from None
    # each task is one whole run: the workers' statistical profiler (a stack sample every
    # 10 ms, for a dashboard the sweep does not start) only costs the runs 3-4 % of their time
    with dask.config.set({"distributed.worker.profile.enabled": False}), _quiet_workers():
        # no dashboard; the scheduler's HTTP endpoint on a free local port, not on 8787, where
        # another cluster would make it warn
        cluster = LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address="127.0.0.1:0",
            scheduler_kwargs={"dashboard": False},
        )
    return Client(cluster), cluster


@contextmanager
def _quiet_workers():
    """Worker processes started inside log only distributed's errors: a run's failure is in
    sweep.csv and on stderr already, and a stop (Ctrl-C) cancels runs, which they would log
    as warnings. The workers read the setting from the environment when they start."""
    name = "DASK_LOGGING__DISTRIBUTED"
    before = os.environ.get(name)
    os.environ[name] = "error"
    try:
        yield
    finally:
        if before is None:
            del os.environ[name]
        else:
            os.environ[name] = before


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
    (:func:`fecontact.cli.commands.run_one`). ``case`` and ``out`` are made absolute before
    anything is submitted: the workers of a scheduler run in folders of their own. Failed
    runs are listed on stderr even when ``quiet``; Ctrl-C stops the sweep with status 130,
    keeping the runs that completed.
    """
    case, out = Path(case).resolve(), Path(out).resolve()
    swept = [name for name, values in axes if len(values) > 1]
    combos = [dict(zip([n for n, _ in axes], c, strict=True)) for c in _product(axes)]
    if check is not None:
        _check_each_value(axes, check)
    out.mkdir(parents=True, exist_ok=True)
    folders = [out / _folder({k: values[k] for k in swept}) for values in combos]
    todo = [
        (i, _run_argv(case, values, folder, options), _cost(values))
        for i, (values, folder) in enumerate(zip(combos, folders, strict=True))
        if not _completed(folder)
    ]
    results, interrupted = {}, False
    try:
        if todo:
            _execute(task, todo, workers, scheduler, quiet, results)
    except KeyboardInterrupt:
        interrupted = True
    rows = [
        _row({k: values[k] for k in swept}, folder, results.get(i))
        for i, (values, folder) in enumerate(zip(combos, folders, strict=True))
    ]
    write_table(out / SWEEP_FILE, rows)
    return _conclude(rows, folders, len(todo), out, quiet, interrupted)


def _conclude(rows, folders, ran: int, out: Path, quiet: bool, interrupted: bool) -> int:
    """Say what failed (always) and how the sweep went (unless quiet); the exit status."""
    if interrupted:
        done = sum(r.get("status") == "completed" for r in rows)
        print(
            f"fecontact: sweep interrupted; {done} of {len(rows)} runs completed in {out} "
            "(run the same sweep again to continue)",
            file=sys.stderr,
        )
        return 130
    failed = [(r, f) for r, f in zip(rows, folders, strict=True) if r.get("status") != "completed"]
    for row, folder in failed:
        why = f": {row['message']}" if row.get("message") else ""
        print(f"fecontact: {row.get('status', 'failed')} run {folder.name}{why}", file=sys.stderr)
    if not quiet:
        print(f"{len(rows)} runs ({ran} run now, {len(failed)} failed) -> {out / SWEEP_FILE}")
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


def _execute(task, todo, workers, scheduler, quiet, results: dict) -> None:
    """Run ``todo`` on Dask; each result goes into ``results`` as it arrives."""
    from dask.distributed import as_completed

    client, cluster = _client(scheduler, max(1, min(workers, len(todo))))
    try:
        # the costliest runs first, so that no long run starts last while the other workers
        # idle (longest processing time first): submitted in that order and with that priority
        ordered = sorted(todo, key=lambda item: -item[2])  # stable: ties in product order
        futures = {
            client.submit(task, argv, pure=False, priority=cost): i for i, argv, cost in ordered
        }
        report = _SweepProgress(len(todo), quiet)
        for future in as_completed(futures):
            try:
                results[futures[future]] = future.result()
            except Exception as exc:  # a worker lost mid-run
                results[futures[future]] = {"exit": 1, "message": f"{type(exc).__name__}: {exc}"}
            report.done(results[futures[future]]["exit"])
        report.close()
    except KeyboardInterrupt:
        # the nanny warns of the workers it stops mid-run: the stop is said in one line
        logging.getLogger("distributed").setLevel(logging.ERROR)
        raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


class _SweepProgress:
    """Runs done: a bar on a terminal or in a notebook, else a line per run (a log)."""

    def __init__(self, total: int, quiet: bool):
        self.total, self.count, self.failed, self.quiet = total, 0, 0, quiet
        self.bar = None
        if not quiet and (in_notebook() or is_terminal(sys.stderr)):
            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, desc="sweep", unit="run", file=sys.stderr)

    def done(self, status: int) -> None:
        self.count += 1
        self.failed += status != 0
        if self.bar is not None:
            self.bar.update(1)
        elif not self.quiet:
            print(
                f"sweep: {self.count} of {self.total} runs done, {self.failed} failed",
                file=sys.stderr,
                flush=True,
            )

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
