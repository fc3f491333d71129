"""Shared pieces of the benchmark scripts: case loading, runs, exact solutions, tables.

Every benchmark is a plain script (``python benchmarks/NAME.py [--quick]``) that prints a
Markdown table and writes CSV, Markdown and PNG files into ``benchmarks/results/``. Timing
lives here and never in the tests: ``timed_run`` runs the driver without frames and takes the
median of repeated runs; ``trace`` steps ``fecontact.simulate`` and keeps what the error and
stability measures need, one row per step.
"""

from __future__ import annotations

# isort: off
import fecontact  # before numpy: it sets single-threaded OpenBLAS (see fecontact/__init__.py)

# isort: on
import argparse
import csv
import dataclasses
import math
import os
import statistics
import sys
import tempfile
import time
from functools import cache
from pathlib import Path

import numpy as np

from fecontact import SolverError, run, simulate
from fecontact.io.cli import load_case

os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
G = 9.81

__all__ = [
    "G",
    "RESULTS",
    "ROOT",
    "ball_exact_gap",
    "ball_impact_times",
    "case",
    "episode_starts",
    "fmt",
    "markdown_table",
    "observed_order",
    "parser",
    "pendulum_exact",
    "previous_note",
    "read_csv",
    "tidy_log_axes",
    "timed_run",
    "trace",
    "with_options",
    "write_csv",
    "write_markdown",
]


@cache
def case(name: str):
    """The case module ``cases/NAME.py``."""
    return load_case(ROOT / "cases" / f"{name}.py")


def with_options(sim, **options):
    """A copy of ``sim`` with some ``IntegratorOptions`` fields changed."""
    return sim.replace(options=dataclasses.replace(sim.options, **options))


# -- runs ---------------------------------------------------------------------------------------


def trace(sim, dt=None, t_end=None, max_wall=None, abort=None):
    """Step ``sim`` with ``simulate`` and return one row per step (t = 0 included) as arrays.

    Keys: ``t``, ``h``, the probes, ``kinetic``, ``total`` (energy, J), ``min_gap`` (m, over
    every contact), ``active`` (a contact with ν > 0 or Λ > 0), ``impulse`` (Σ kΛ, N·s),
    ``iterations`` (smooth + position + velocity), ``halvings``, ``vmax`` (max |v|); and
    ``status`` ("completed", "failed" on ``SolverError``, "timeout" after ``max_wall`` s,
    "diverged" when ``abort(row)`` is true), ``message`` and ``wall`` (s).
    """
    model = sim.model
    names = ["t", "h", "kinetic", "total", "min_gap", "active", "impulse"]
    names += ["iterations", "halvings", "vmax", *sim.probes]
    rows = {k: [] for k in names}
    status, message = "completed", ""
    start = time.perf_counter()
    steps = simulate(model, dt or sim.dt, t_end or sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    try:
        for st in steps:
            ke = model.kinetic_energy(st.v)
            total = ke + model.potential_energy(st.q) + model.strain_energy(st.q)
            row = {
                "t": st.t,
                "h": st.h,
                "kinetic": ke,
                "total": total,
                "min_gap": float(np.min(st.gaps, initial=np.inf)),
                "active": bool(np.any(st.nu > 0) or np.any(st.impulse > 0)),
                "impulse": float(np.sum(st.impulse)),
                "iterations": st.newton_iterations,
                "halvings": st.halvings,
                "vmax": float(np.max(np.abs(st.v))),
            }
            for name, probe in sim.probes.items():
                row[name] = probe.fn(model, st)
            for k, v in row.items():
                rows[k].append(v)
            if not math.isfinite(total):
                status, message = "diverged", f"non-finite energy at t = {st.t:.6g} s"
                break
            if abort is not None and abort(row):
                status, message = "diverged", f"stopped at t = {st.t:.6g} s (energy blow-up)"
                break
            if max_wall is not None and time.perf_counter() - start > max_wall:
                status, message = "timeout", f"stopped at t = {st.t:.6g} s after {max_wall} s"
                break
    except SolverError as err:
        status, message = "failed", str(err)
    out = {k: np.array(v) for k, v in rows.items()}
    out.update(status=status, message=message, wall=time.perf_counter() - start)
    return out


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
            try:
                summary = run(sim, tmp, frames=False, checkpoint_every=0)
                status, message = "completed", ""
            except SolverError as err:
                summary = fecontact.io.output.read_json(Path(tmp) / "summary.json")
                status, message = "failed", str(err)
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


def episode_starts(active) -> np.ndarray:
    """Indices of the steps where a contact closes after a step with none closed."""
    on = np.asarray(active, dtype=bool)
    return np.flatnonzero(on & ~np.r_[False, on[:-1]])


def observed_order(h, err) -> float:
    """Least-squares slope of log(err) against log(h) (nan with fewer than two points)."""
    h, err = np.asarray(h, float), np.asarray(err, float)
    ok = (h > 0) & (err > 0) & np.isfinite(err)
    if ok.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)[0])


# -- exact solutions ----------------------------------------------------------------


def ball_impact_times(n, h0=1.0, e=0.8, g=G) -> np.ndarray:
    """First ``n`` impact times of a ball dropped from ``h0``: t₁ = √(2h₀/g),
    t_{k+1} = t_k + 2eᵏt₁."""
    t1 = math.sqrt(2.0 * h0 / g)
    t = [t1]
    for k in range(1, n):
        t.append(t[-1] + 2.0 * e**k * t1)
    return np.array(t)


def ball_exact_gap(t, h0=1.0, e=0.8, g=G) -> np.ndarray:
    """Exact gap of the bouncing ball (m) at times ``t``; zero after the accumulation time."""
    t = np.asarray(t, float)
    t1 = math.sqrt(2.0 * h0 / g)
    v1 = g * t1
    out = np.where(t < t1, h0 - 0.5 * g * t**2, 0.0)
    t_zeno = t1 * (1.0 + e) / (1.0 - e) if e < 1.0 else math.inf
    k, tk = 1, t1
    while tk < min(t.max(initial=0.0), t_zeno) and k < 10_000:
        vk = e**k * v1
        t_next = tk + 2.0 * vk / g
        sel = (t >= tk) & (t < t_next)
        s = t[sel] - tk
        out[sel] = vk * s - 0.5 * g * s**2
        k, tk = k + 1, t_next
    return out


def pendulum_exact(t, e=0.5, length=1.0, g=G, n_impacts=60):
    """θ(t) of the uniform rigid bar released horizontal against a stop at the vertical
    (Jacobi's sn; after each impact 1 − cos θ_{k+1} = e²(1 − cos θ_k)), and the impact times.
    With ``e=None`` there is no stop: the free swing of amplitude π/2."""
    from scipy.special import ellipj, ellipk

    t = np.asarray(t, float)
    w0 = math.sqrt(1.5 * g / length)
    k0 = math.sin(math.pi / 4)
    K0 = ellipk(k0**2)
    if e is None:
        return 2.0 * np.arcsin(k0 * ellipj(K0 - w0 * t, k0**2)[0]), np.zeros(0)
    t_imp = [K0 / w0]
    amps, theta = [], math.pi / 2
    for _ in range(n_impacts):
        theta = math.acos(1.0 - e**2 * (1.0 - math.cos(theta)))
        amps.append(theta)
        if theta < 1e-12:
            break
        t_imp.append(t_imp[-1] + 2.0 * ellipk(math.sin(theta / 2) ** 2) / w0)
    out = np.zeros_like(t)
    first = t < t_imp[0]
    out[first] = 2.0 * np.arcsin(k0 * ellipj(K0 - w0 * t[first], k0**2)[0])
    for j in range(len(t_imp) - 1):
        k = math.sin(amps[j] / 2)
        sel = (t >= t_imp[j]) & (t < t_imp[j + 1])
        out[sel] = 2.0 * np.arcsin(k * ellipj(w0 * (t[sel] - t_imp[j]), k * k)[0])
    return out, np.array(t_imp)


# -- tables and files ---------------------------------------------------------------------------


def parser(description: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=description)
    p.add_argument(
        "--quick", action="store_true", help="reduced sweep (a couple of minutes) to check it"
    )
    p.add_argument("--out", default=str(RESULTS), help="output folder (default: %(default)s)")
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
