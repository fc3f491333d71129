"""Energy created where planar beams close a contact, at the smooth force's defaults: the disk
dropped on the beam (`disk_on_beam`, 42 elements, and e_N = 1 at 21) and the founding strip
striking a floor under its pin (e_N = 0, ``benchmarks/stress_2d.py``). Three tables:

- created / scale against the step (h to h/8, the floor to h/16), with the step and the
  phase the run's warning names;
- the impact located at its instant (``localize=1``): created / scale and the largest
  distance of the probes from the run at h/8 (over each probe's range), against the default;
- one free mode of frequency ω under generalized-α (ρ∞ = 0.5), started at unit energy with
  its consistent acceleration: the ledger's ``created`` reading of T + V (the largest fall
  of the energy lost below its running maximum), the worst over the mode's initial phase.

    python benchmarks/beam_closing_energy.py [--quick]
"""

from __future__ import annotations

import dataclasses
import math
import re
import tempfile
import warnings
from pathlib import Path

import numpy as np
from _common import case, markdown_table, parser, write_csv, write_markdown
from stress_2d import pendulum

from fecontact import run
from fecontact.io.output import read_history
from fecontact.time.generalized_alpha import coefficients

RUNS = {
    "disk on beam, 42 elements": lambda: case("disk_on_beam").build(n_elements=42),
    "disk on beam, e_N 1": lambda: case("disk_on_beam").build(restitution=1.0),
    "floor pendulum, e_N 0": lambda: pendulum("floor", 0.0)[0],
}
T_END = {"disk on beam, 42 elements": 0.15, "disk on beam, e_N 1": 0.15}
NAMED = re.compile(r"t = ([0-9.e-]+) s, step \d+, in the ([a-z ]+)")


def measured(name: str, div: int, quick: bool, **options) -> dict:
    """created / scale, the warning's time and phase, the history and the CPU time of a run
    of ``name`` at the step / ``div``."""
    sim = RUNS[name]()
    t_end = T_END.get(name, sim.t_end)
    if quick:
        t_end = 0.105 if name.startswith("disk") else 0.26
    sim = sim.replace(dt=sim.dt / div, t_end=t_end)
    sim = sim.replace(options=dataclasses.replace(sim.options, **options))
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        summary = run(sim, tmp, frames=False, checkpoint_every=0)
        history = read_history(Path(tmp) / "history.csv")
    ledger = summary["energy_ledger"]
    found = NAMED.search(" ".join(summary.get("warnings", [])))
    return {
        "created": ledger["created"] / ledger["scale"],
        "where": f"t = {found[1]} s, {found[2]}" if found else "",
        "history": history,
        "probes": list(sim.probes),
    }


def distances(run_h: dict, run_fine: dict) -> str:
    """The largest distance of each probe of ``run_h`` from ``run_fine`` over the run, over
    the probe's range in the fine run."""
    h, fine = run_h["history"], run_fine["history"]
    out = []
    for p in run_h["probes"]:
        ref = np.interp(h["t"], fine["t"], fine[p])
        out.append(f"{p} {np.abs(h[p] - ref).max() / (np.ptp(fine[p]) or 1.0):.2g}")
    return ", ".join(out)


def mode_created(omega_h: float, rho_inf: float = 0.5, steps: int = 40) -> float:
    """The ledger's created / E(0) of one undamped linear mode (x'' = −ω²x, h = 1) under
    generalized-α, started at unit energy with v̇ = a = −ω²x: the worst over 13 initial
    phases."""
    c = coefficients(rho_inf, 1.0)
    am, af, g, b = c.am, c.af, c.gamma, c.beta
    w2, k = omega_h**2, b / (1.0 - am)
    worst = 0.0
    for phase in np.linspace(0.0, math.pi, 13):
        x, v = math.cos(phase) / omega_h, -math.sin(phase)  # ½v² + ½ω²x² = ½
        vd = a = -w2 * x
        lost, peak, fall = 0.0, 0.0, 0.0
        for _ in range(steps):
            vd1 = -w2 * (x + v + (0.5 - b) * a + k * (af * vd - am * a)) / (1 + w2 * k * (1 - af))
            a1 = ((1 - af) * vd1 + af * vd - am * a) / (1 - am)
            x, v = x + v + (0.5 - b) * a + b * a1, v + (1 - g) * a + g * a1
            vd, a = vd1, a1
            lost = 0.5 - (0.5 * v * v + 0.5 * w2 * x * x)
            peak = max(peak, lost)
            fall = max(fall, peak - lost)
        worst = max(worst, fall / 0.5)
    return worst


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    quick, out = args.quick, Path(args.out)
    names = list(RUNS)
    divs = {name: (1,) if quick else (1, 2, 4, 8) for name in names}
    if not quick:
        divs["floor pendulum, e_N 0"] = (1, 2, 4, 8, 16)
    step_rows, runs = [], {}
    for name in names:
        row = {"run": name}
        for div in divs[name]:
            runs[name, div] = m = measured(name, div, quick)
            row[f"h/{div}"] = m["created"]
            row[f"h/{div} where"] = m["where"]
        step_rows.append(row)
    located_rows = []
    for name in names[:2]:
        fine = runs.get((name, 8)) or runs[name, 1]
        for label, options in (("default", {}), ("localize=1", {"localize": 1})):
            m = runs[name, 1] if not options else measured(name, 1, quick, **options)
            located_rows.append({
                "run": name, "impacts": label, "created / scale": m["created"],
                "distance from h/8": distances(m, fine),
            })  # fmt: skip
    modes = (1.0, 16.0) if quick else (1.0, 3.0, 8.0, 16.0, 50.0)
    mode_rows = [{"omega h": w, "created / E(0)": mode_created(w)} for w in modes]
    columns = ["run"] + [c for d in divs[names[-1]] for c in (f"h/{d}", f"h/{d} where")]
    stem = "beam_closing_energy_quick" if quick else "beam_closing_energy"
    text = [
        "# Energy created where planar beams close a contact",
        "`python benchmarks/beam_closing_energy.py`; docs/explanation/energy_ledger.md reads it.",
        "## created / scale against the step (where: the step the warning names)",
        markdown_table(step_rows, columns),
        "## The impact located at its instant",
        markdown_table(located_rows, list(located_rows[0])),
        "## One free mode under generalized-alpha (rho_inf 0.5): the ledger's reading",
        markdown_table(mode_rows, list(mode_rows[0])),
    ]
    write_csv(out / f"{stem}.csv", step_rows, columns)
    write_markdown(out / f"{stem}.md", "\n\n".join(text))
    print("\n\n".join(text))


if __name__ == "__main__":
    main()
