"""The energy retakes of beams struck at an end (``fecontact/time/energy_guard.py``), each run
with ``energy_retakes`` "auto" (the default) and off, side by side.

1. The founding strip against a floor under its pin and a tilted wall (``stress_2d.py``'s
   pendulums), e_N = 0, 0.5, 1, 0.8 s at h = 1 ms: the ledger's ``created`` over its
   ``scale``, the retakes, the h/8 run, and the tip's largest distance from the h/8 run.
2. The flexible pendulum's rows of ``stability.py`` that created energy or failed: e_N = 1 at
   ρ∞ = 0.5, 0.9, 1 (h = 1e-3), the 24.7 m/s strike (g × 100), h = 1e-2 at ρ∞ = 0.5, 0.8, 0.9.
3. The CPU time per run of the founding case and of ``disk_on_beam``, the rule on and off
   alternated (medians).

    python benchmarks/energy_retakes.py           # about 3 minutes on one core
    python benchmarks/energy_retakes.py --quick   # seconds
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np
import stress_2d
from _common import case, parser, report, with_options, write_markdown

from fecontact import SolverError, run
from fecontact.io.output import read_json
from fecontact.simulation import Simulation
from fecontact.time import simulate

STOPS = ("floor", "tilted")


def pendulum(stop: str, e: float, t_end: float) -> Simulation:
    """The founding case's strip and tip mass against ``stop`` (``benchmarks/stress_2d.py``)."""
    return stress_2d.pendulum(stop, e, t_end=t_end)[0]


def measured(sim) -> dict:
    """The run's created / scale (%), retakes, halvings, status and CPU time."""
    with tempfile.TemporaryDirectory() as tmp:
        cpu = time.process_time()
        try:
            s, status = run(sim, tmp, frames=False, checkpoint_every=0), "completed"
        except SolverError as err:  # (the summary of the steps made)
            s, status = read_json(Path(tmp) / "summary.json"), str(err).splitlines()[0][:60]
        cpu = time.process_time() - cpu
    ledger = s.get("energy_ledger", {})
    return {
        "created (%)": 100 * ledger.get("created", math.nan) / ledger.get("scale", math.nan),
        "retakes": f"{s.get('energy_retakes', '')} / {s.get('energy_retake_halves', '')}",
        "halvings": s.get("step_halvings", ""),
        "status": status,
        "cpu (s)": cpu,
    }


def tip(sim) -> np.ndarray:
    """The tip's (x, y) displacement at every step."""
    model = sim.model
    i = model.body_slice(0).start + 3 * (model.bodies[0].X.shape[0] - 1)
    return np.array([st.q[i : i + 2] for st in simulate(model, sim.dt, sim.t_end, sim.options)])


def strike_rows(quick: bool) -> list[dict]:
    rows = []
    for stop in STOPS:
        for e in (1.0,) if quick else (0.0, 0.5, 1.0):
            sim = pendulum(stop, e, 0.35 if quick else 0.8)
            fine = with_options(sim.replace(dt=sim.dt / 8), energy_retakes=False)
            reference = tip(fine)[::8]
            row = {"stop": stop, "e_N": e, "h/8 created (%)": measured(fine)["created (%)"]}
            for value in ("auto", False):
                run_sim = with_options(sim, energy_retakes=value)
                m = measured(run_sim)
                name = "on" if value else "off"
                row[f"created {name} (%)"] = m["created (%)"]
                row[f"retakes {name}"] = m["retakes"]
                distance = np.linalg.norm(tip(run_sim) - reference, axis=1)
                row[f"tip from h/8 {name} (mm)"] = 1e3 * distance.max()
            rows.append(row)
    return rows


STABILITY = (
    ("e_N = 1", {"restitution": 1.0}, 1e-3, 1.5, {}),
    ("e_N = 1, ρ∞ = 0.9", {"restitution": 1.0}, 1e-3, 1.5, {"rho_inf": 0.9}),
    ("e_N = 1, ρ∞ = 1", {"restitution": 1.0}, 1e-3, 1.5, {"rho_inf": 1.0}),
    ("24.7 m/s, e_N = 0.5", {"restitution": 0.5, "gravity": 981.0}, 1e-3, 0.15, {}),
    ("e_N = 1, h = 1e-2", {"restitution": 1.0}, 1e-2, 1.5, {}),
    ("e_N = 0.5, ρ∞ = 0.8, h = 1e-2", {"restitution": 0.5}, 1e-2, 1.5, {"rho_inf": 0.8}),
    ("e_N = 1, ρ∞ = 0.8, h = 1e-2", {"restitution": 1.0}, 1e-2, 1.5, {"rho_inf": 0.8}),
    ("e_N = 0.5, ρ∞ = 0.9, h = 1e-2", {"restitution": 0.5}, 1e-2, 1.5, {"rho_inf": 0.9}),
)


def stability_rows(quick: bool) -> list[dict]:
    rows = []
    for name, params, h, t_end, options in STABILITY[3:5] if quick else STABILITY:
        sim = case("flexible_pendulum").build(**params).replace(dt=h, t_end=t_end)
        row = {"run": name}
        for value in ("auto", False):
            m = measured(with_options(sim, energy_retakes=value, **options))
            tag = "on" if value else "off"
            row |= {f"{k} {tag}": v for k, v in m.items() if k != "cpu (s)"}
        rows.append(row)
    return rows


# --quick: each cost run just past its first impact (s)
QUICK_COST_END = {"flexible_pendulum": 0.35, "disk_on_beam": 0.15}


def cost_rows(repeats: int, quick: bool) -> list[dict]:
    """The CPU time per run of the founding case and of ``disk_on_beam`` (a rigid disk
    dropped on a strip, whose closing along the strip the guard judges), on and off
    alternated."""
    rows = []
    for name, quick_end in QUICK_COST_END.items():
        sim = case(name).build()
        if quick:
            sim = sim.replace(t_end=quick_end)
        times, retakes = {"auto": [], False: []}, {}
        for _ in range(repeats):
            for value in times:
                out = measured(with_options(sim, energy_retakes=value))
                times[value].append(out["cpu (s)"])
                retakes[value] = out["retakes"]
        on, off = (float(np.median(times[v])) for v in times)
        rows.append({"case": name, "runs": repeats, "on (s)": on, "off (s)": off})
        rows[-1] |= {"on / off": on / off, "retakes": retakes["auto"]}
    return rows


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    text = report(
        "Energy retakes of beams struck at an end",
        (
            "The strip against a floor and a tilted wall, h = 1 ms (created: the ledger's, "
            "% of the scale; retakes: taken again / of them in two halves; the tip's largest "
            "distance from the h/8 run without the retakes):",
            strike_rows(args.quick),
        ),
        ("The flexible pendulum's rows of the stability matrix:", stability_rows(args.quick)),
        (
            "CPU time per run (medians; the retakes of the run with the rule on):",
            cost_rows(1 if args.quick else 7, args.quick),
        ),
    )
    name = "energy_retakes_quick.md" if args.quick else "energy_retakes.md"
    print(write_markdown(f"{args.out}/{name}", text))


if __name__ == "__main__":
    main()
