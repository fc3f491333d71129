"""Energy created in the lasting contacts of beams: the founding strip wrapped on a peg, a
free strip pushing a rigid disk end first, the founding strip striking a floor under its pin
(``benchmarks/stress_2d.py``'s rows). Three tables:

- each phase of one step of the decoupled scheme (kinetic and strain energy, mJ): the smooth
  step releases the shape the contact holds, the correction restores it, the jump removes
  the velocity;
- created / scale of the decoupled scheme against the step (h to h/8);
- created / scale with each remedy measured (smooth force, mass metric, energy-decaying
  smooth step, ρ∞ = 0), and whether the run completed.

    python benchmarks/lasting_contact.py [--quick]
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
import warnings
from pathlib import Path

import numpy as np
from _common import markdown_table, parser, write_csv, write_markdown
from stress_2d import pendulum, strip_end_on_disk

from fecontact import SolverError, run, simulate
from fecontact.time import run_settings
from fecontact.time.alpha_step import alpha_plan
from fecontact.time.nsga import smooth_phases
from fecontact.time.state import PhaseTimer

RUNS = {
    "strip on a peg": lambda: pendulum("peg", 0.0)[0],
    "strip end-on at a rigid disk, 2 m/s": lambda: strip_end_on_disk(True, 2.0)[0],
    "strip end-on at a rigid disk, 20 m/s": lambda: strip_end_on_disk(True, 20.0)[0],
    "floor pendulum, e_N 0": lambda: pendulum("floor", 0.0)[0],
    "floor pendulum, e_N 0.5": lambda: pendulum("floor", 0.5)[0],
    "floor pendulum, e_N 1": lambda: pendulum("floor", 1.0)[0],
}
OFF = {"smooth_contact": "off"}  # (the decoupled scheme; beams default to the smooth force)
REMEDIES = {
    "decoupled (off)": {"smooth_contact": "off"},
    'smooth force ("on")': {"smooth_contact": "on"},
    "mass metric": {"metric": "mass", **OFF},
    "energy-decaying step": {"scheme": "energy-decaying"},
    "rho_inf = 0": {"rho_inf": 0.0, **OFF},
}


def created(sim, **options) -> tuple[float, str]:
    """created / scale of the run and its status."""
    sim = sim.replace(options=dataclasses.replace(sim.options, **options))
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            summary = run(sim, tmp, frames=False, checkpoint_every=0)
        except SolverError:
            summary = None
        if summary is None:
            from fecontact.io.output import read_json

            summary = read_json(Path(tmp) / "summary.json")
    ledger = summary.get("energy_ledger", {})
    return ledger.get("created", math.nan) / ledger.get("scale", 1.0), summary["status"]


def phases(sim, t: float) -> dict:
    """(ΔT, ΔW) in mJ of the smooth step, the correction and the jump of the step ending at
    ``t`` (s), the decoupled scheme: the step taken again phase by phase from the state
    before it (:func:`fecontact.time.nsga.smooth_phases`)."""
    model, h = sim.model, sim.dt
    options = dataclasses.replace(sim.options, smooth_contact="off")
    *_, st = simulate(model, h, round(t / h - 1) * h, options, v0=sim.v0)
    settings = run_settings(model, options, plan=alpha_plan)

    def energies(q, v):
        return np.array([model.kinetic_energy(v), model.strain_energy(q)])

    step = smooth_phases(model, st, h, settings, PhaseTimer())
    before, smooth = energies(st.q, st.v), energies(step.q, step.v)
    step.v_tilde = step.v  # (what the step's finish does before its correction)
    step.correct()
    corrected = energies(step.q, step.v)
    step.jump()
    jumped = energies(step.q, step.v)
    row = {"smooth": smooth - before, "correct": corrected - smooth, "jump": jumped - corrected}
    return {"t": st.t + h, **{k: 1e3 * v for k, v in row.items()}}


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    quick = args.quick
    out = Path(args.out)
    names = list(RUNS)[:1] if quick else list(RUNS)
    # one step of each phase
    steps = {"strip on a peg": 0.239, "strip end-on at a rigid disk, 2 m/s": 0.00254}
    phase_rows = []
    for name, t in steps.items():
        if quick and name not in names:
            continue
        sim = RUNS[name]()
        p = phases(sim, t if not quick else 0.239)
        phase_rows.append({
            "run": name, "t (s)": p["t"],
            **{f"{k} dT, dW (mJ)": ", ".join(f"{x:+.1f}" for x in p.get(k, (0.0, 0.0)))
               for k in ("smooth", "correct", "jump")},
        })  # fmt: skip
    # against the step
    step_rows = []
    for name in names[:3]:
        row = {"run": name}
        for div in (1,) if quick else (1, 2, 4, 8):
            sim = RUNS[name]()
            sim = sim.replace(dt=sim.dt / div)
            row[f"h/{div}"] = created(sim.replace(t_end=0.3) if quick else sim, **OFF)[0]
        step_rows.append(row)
    # remedies
    remedy_rows = []
    for name in names:
        row = {"run": name}
        for label, options in REMEDIES.items():
            if quick and options.get("scheme"):
                continue
            sim = RUNS[name]()
            c, status = created(sim.replace(t_end=0.3) if quick else sim, **options)
            row[label] = c if status == "completed" else f"{status} ({c:.2g})"
        remedy_rows.append(row)
    stem = "lasting_contact_quick" if quick else "lasting_contact"
    text = [
        "# Energy created in the lasting contacts of beams",
        "`python benchmarks/lasting_contact.py`; docs/explanation/energy_ledger.md reads it.",
        "## One step of the decoupled scheme (mJ)",
        markdown_table(phase_rows, list(phase_rows[0])),
        "## created / scale of the decoupled scheme against the step",
        markdown_table(step_rows, list(step_rows[0])),
        "## created / scale with each remedy (failed: the run stopped)",
        markdown_table(remedy_rows, list(remedy_rows[0])),
    ]
    write_csv(out / f"{stem}.csv", remedy_rows, list(remedy_rows[0]))
    write_markdown(out / f"{stem}.md", "\n\n".join(text))
    print("\n\n".join(text))


if __name__ == "__main__":
    main()
