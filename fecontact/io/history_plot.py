"""``history.png``: the probes of a run's ``history.csv`` against time, one panel per unit,
the total energy, the energy ledger (where the energy went), and the impacts marked."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .output import (
    HISTORY_FILE,
    LEDGER_COLUMNS,
    OBSTACLE_COLUMNS,
    STANDARD_COLUMNS,
    SUMMARY_FILE,
    read_history,
    read_json,
)

__all__ = ["history_panels", "ledger_layers", "plot_history"]


_QUANTITY = {
    "m": "length",
    "m/s": "velocity",
    "m/s^2": "acceleration",
    "rad": "rotation",
    "rad/s": "angular velocity",
    "N": "force",
    "N m": "moment",
    "N·m": "moment",
    "N s": "impulse",
    "N·s": "impulse",
    "J": "energy",
}


def history_panels(columns: list[str], probes: dict) -> list[tuple[str, list[str]]]:
    """(y label, probe columns) per panel: one panel per unit, else one per probe."""
    groups: dict[object, list[str]] = {}
    for name in columns:
        unit = (probes.get(name) or {}).get("unit")
        groups.setdefault(unit if unit else ("probe", name), []).append(name)
    panels = []
    for key, names in groups.items():
        if isinstance(key, tuple):
            panels.append((names[0], names))
            continue
        # the probes' own words when they agree (a position is no displacement), else the
        # quantity of the unit
        texts = {(probes.get(n) or {}).get("description") for n in names}
        text = texts.pop() if len(texts) == 1 and None not in texts else None
        text = text if text and len(text) <= 32 else None  # an axis label, not a sentence
        panels.append((f"{text or _QUANTITY.get(key, names[0])} ({key})", names))
    return panels


# the ledger panel's layers, bottom up: (label, history column(s)); dissipations after the
# energies, each cumulative since t = 0 (fecontact.ledger)
_LAYERS = (
    ("kinetic", ("kinetic_energy",)),
    ("strain", ("strain_energy",)),
    ("gravity − its least", ("potential_energy",)),
    ("damping", ("damping_dissipation",)),
    ("friction", ("friction_dissipation",)),
    ("impact", ("impact_dissipation",)),
    ("numerical", ("numerical_dissipation",)),
)


def ledger_layers(history: dict) -> tuple[list[tuple[str, np.ndarray]], np.ndarray] | None:
    """The energy ledger of a history as layers (label, J against time) that stack to the
    energy supplied, E(0) + W_loads(t) (+ W_obstacles(t), with moving obstacles) less the
    least gravity energy of the run (returned second): the energies the bodies hold, then
    what damping, friction, impacts and the time integrator took since t = 0. The gravity
    energy is counted from its least value so that every energy layer is ≥ 0. None when the
    history has no ledger columns."""
    if any(k not in history for k in LEDGER_COLUMNS):
        return None
    gravity = history["potential_energy"]
    low = float(np.min(gravity)) if gravity.size else 0.0
    layers = []
    for label, (column,) in _LAYERS:
        y = history[column] - low if column == "potential_energy" else history[column]
        layers.append((label, np.asarray(y, dtype=float)))
    supply = history["total_energy"][:1] + history["load_work"] - low
    if "obstacle_work" in history:  # (moving obstacles supply energy as the loads do)
        supply = supply + history["obstacle_work"]
    return layers, supply


def plot_history(out_dir, path=None) -> Path:
    """Plot the probes of ``history.csv`` against time (s), grouped by unit, the total energy
    and, where the history has them, the ledger's layers (:func:`ledger_layers`) stacked.

    Impacts listed in ``summary.json`` are marked by thin vertical lines. Writes
    ``history.png`` in the run folder unless ``path`` is given; returns the path.
    """
    from matplotlib.figure import Figure

    folder = Path(out_dir)
    folder = folder.parent if folder.suffix == ".pvd" else folder
    history, summary, panels, energy = _history_panels(folder)
    ledger = ledger_layers(history) if energy else None
    heights = [2.0] * len(panels) + [1.2] * energy + [2.0] * (ledger is not None)
    # Figure without pyplot: the Agg canvas, and no global backend state touched
    fig = Figure(figsize=(7.0, sum(heights) + 0.8), dpi=150, layout="constrained")
    axes = fig.subplots(len(heights), 1, sharex=True, squeeze=False, height_ratios=heights)[:, 0]
    t = history["t"]
    for ax, (label, names) in zip(axes, panels, strict=False):
        for name in names:
            ax.plot(t, history[name], lw=1.0, label=name)
        ax.set_ylabel(label)
        ax.legend(loc="best", fontsize="small", frameon=False)
    if energy:
        axes[len(panels)].plot(t, history["total_energy"], lw=1.0, color="black")
        axes[len(panels)].set_ylabel("total energy (J)")
    if ledger is not None:
        _plot_ledger(axes[-1], t, *ledger)
    _mark_impacts(axes, summary.get("impacts") or [], t)
    indices = sorted([*folder.glob("*.pvd"), *folder.glob("*.frames.json")])
    title = indices[0].name.split(".")[0] if len(indices) == 1 else folder.name
    axes[0].set_title(title, fontsize="medium")
    path = Path(path) if path is not None else folder / "history.png"
    fig.savefig(path)
    return path


def _plot_ledger(ax, t, layers, supply) -> None:
    """The ledger's layers stacked, and the energy supplied as a dashed line on top."""
    ax.stackplot(t, *(y for _, y in layers), labels=[k for k, _ in layers], alpha=0.8, lw=0)
    ax.plot(t, supply, color="black", lw=0.8, ls="--", label="supplied")
    ax.set_ylabel("where the energy went (J)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="x-small", frameon=False)


def _history_panels(folder: Path):
    """The history and summary of a run folder, the probe panels and whether the total energy
    is there to plot."""
    history = read_history(folder / HISTORY_FILE)
    summary = read_json(folder / SUMMARY_FILE) if (folder / SUMMARY_FILE).is_file() else {}
    if "t" not in history:
        raise ValueError(f"{folder / HISTORY_FILE} has no column 't'")
    ledger = LEDGER_COLUMNS + OBSTACLE_COLUMNS
    probes = [c for c in history if c not in STANDARD_COLUMNS and c not in ledger]
    panels = history_panels(probes, summary.get("probes") or {})
    energy = "total_energy" in history
    if not panels and not energy:
        raise ValueError(f"{folder / HISTORY_FILE} has no probe or energy columns")
    return history, summary, panels, energy


def _mark_impacts(axes, impacts, t: np.ndarray) -> None:
    """Dashed lines at the impact times, a grid, the time axis over the run."""
    for ax in axes:
        for impact in impacts:
            ax.axvline(float(impact["time"]), color="0.6", lw=0.6, ls="--", zorder=0)
        ax.grid(True, lw=0.3, alpha=0.5)
    if t.size:
        axes[-1].set_xlim(t[0], t[-1])
    axes[-1].set_xlabel("time (s)")
