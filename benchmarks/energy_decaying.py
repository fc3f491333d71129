"""The energy-decaying smooth step against generalized-α on the flexible pendulum, e_N = 1.

``scheme="energy-decaying"`` (fecontact/time/energy_step.py) cannot let the energy of a
smooth step grow; generalized-α at ρ∞ ≥ 0.7 blows up at some steps and strips
(``benchmarks/axial_pumping.py``). Both schemes side by side, in one run
(``benchmarks/results/energy_decaying.md``):

1. growth over a grid of steps and ρ∞ (5 s runs), and over the strip changed by about 1 %;
2. 100 s runs at h = 1e-3 (growth, energy left, wall time);
3. accuracy at h = 1e-3: the tip against each scheme's run at h/8 and against
   generalized-α's at h/8, over the first impacts, and the energy at 1.5 s;
4. cost: wall time per step over 1.5 s, timed again side by side (median of 3).

Growth: max total energy − initial, % of the peak kinetic energy ('diverged at': the energy
passed half the peak kinetic energy). Runs: ``python benchmarks/energy_decaying.py
[--quick] [--workers N]``.
"""

from __future__ import annotations

import statistics
import time

import numpy as np
from _common import case, map_runs, parser, report, trace, with_options, write_markdown
from axial_pumping import PERTURBED, runaway

SCHEMES = ("generalized-alpha", "energy-decaying")


def build(scheme, rho_inf, **params):
    sim = case("flexible_pendulum").build(restitution=1.0, **params)
    return with_options(sim, scheme=scheme, rho_inf=rho_inf)


def growth(item):
    scheme, rho, h, t_end, params = item
    r = trace(build(scheme, rho, **params), dt=h, t_end=t_end, abort=runaway())
    E, K = r["total"], r["kinetic"]
    pct = float(100 * (E.max() - E[0]) / K.max())
    return {
        "status": r["status"],
        "end": float(r["t"][-1]),
        "growth": pct,
        "left": float(100 * (E[-1] - E[0]) / K.max()),
        "halvings": int(r["halvings"].sum()),
        "iterations": float(r["iterations"][1:].mean()),
        "wall": r["wall"],
    }


def cell(res) -> str:
    if res["status"] != "completed":
        return f"diverged at {res['end']:.3g} s"
    halved = f" ({res['halvings']} halved)" if res["halvings"] else ""
    return f"{res['growth']:.2g} %{halved}"


def tip_track(item):
    scheme, rho, h, t_end = item
    r = trace(build(scheme, rho), dt=h, t_end=t_end)
    return {"t": r["t"], "x": r["tip_x"], "y": r["tip_y"], "E": r["total"], "K": r["kinetic"]}


def deviation(run, ref, until) -> float:
    """Largest distance (mm) of the tip from the reference's, for t ≤ ``until``."""
    m = run["t"] <= until + 1e-12
    x = np.interp(run["t"][m], ref["t"], ref["x"])
    y = np.interp(run["t"][m], ref["t"], ref["y"])
    return float(1e3 * np.hypot(run["x"][m] - x, run["y"][m] - y).max())


def accuracy(rhos, workers, t_end=1.5, h=1e-3):
    items = [(s, rho, hh, t_end) for s in SCHEMES for rho in rhos for hh in (h, h / 8)]
    done = dict(zip(items, map_runs(tip_track, items, workers, label=str), strict=True))
    ga_fine = done["generalized-alpha", 0.5, h / 8, t_end]
    rows = []
    for s in SCHEMES:
        for rho in rhos:
            run, own = done[s, rho, h, t_end], done[s, rho, h / 8, t_end]
            peak = run["K"].max()
            rows.append(
                {
                    "scheme": s,
                    "ρ∞": rho,
                    "tip off own h/8, to 0.8 s (mm)": deviation(run, own, 0.8),
                    "to 1.5 s (mm)": deviation(run, own, t_end),
                    "tip off generalized-α 0.5 at h/8, to 0.8 s (mm)": deviation(run, ga_fine, 0.8),
                    "energy at 1.5 s (% of peak KE)": 100 * (run["E"][-1] - run["E"][0]) / peak,
                    "at h/8": 100 * (own["E"][-1] - own["E"][0]) / own["K"].max(),
                }
            )
    return rows


def cost(rhos, repeats=3, t_end=1.5, h=1e-3):
    """Wall time per step, the schemes alternated within each repeat (median)."""
    times = {(s, rho): [] for s in SCHEMES for rho in rhos}
    for _ in range(repeats):
        for key in times:
            start = time.perf_counter()
            r = trace(build(*key), dt=h, t_end=t_end)
            times[key].append((time.perf_counter() - start) / (len(r["t"]) - 1))
    base = statistics.median(times["generalized-alpha", rhos[0]])
    return [
        {
            "scheme": s,
            "ρ∞": rho,
            "ms per step": 1e3 * statistics.median(times[s, rho]),
            "ratio": statistics.median(times[s, rho]) / base,
        }
        for s, rho in times
    ]


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--workers", type=int, default=1, help="local worker processes (Dask)")
    args = p.parse_args()
    quick = args.quick
    rhos = (0.5, 0.8) if quick else (0.5, 0.8, 0.9)
    steps = (1e-3,) if quick else (4e-4, 6e-4, 8e-4, 1e-3, 1.1e-3, 1.2e-3, 1.5e-3, 2e-3)
    t_grid = 0.1 if quick else 5.0
    grid = [(s, rho, h, t_grid, {}) for s in SCHEMES for rho in rhos for h in steps]
    perturbed = PERTURBED[:2] if quick else PERTURBED
    pert = [(s, rho, 1e-3, t_grid, p) for s in SCHEMES for rho in rhos[1:] for p in perturbed]
    t_long = 0.2 if quick else 100.0
    t_short = 0.1 if quick else 1.5  # accuracy and cost
    long = [(s, rho, 1e-3, t_long, {}) for s in SCHEMES for rho in rhos]
    items = grid + pert + long
    done = dict(
        zip(
            [repr(i) for i in items],
            map_runs(growth, items, args.workers, label=lambda i: f"{i[:3]} {i[4]}"),
            strict=True,
        )
    )
    grid_rows = [
        {
            "scheme": s,
            "ρ∞": rho,
            **{f"h = {h:g}": cell(done[repr((s, rho, h, t_grid, {}))]) for h in steps},
        }
        for s in SCHEMES
        for rho in rhos
    ]
    pert_rows = [
        {
            "scheme": s,
            "ρ∞": rho,
            **{
                (", ".join(f"{k} = {v:g}" for k, v in p.items()) or "nominal"): cell(
                    done[repr((s, rho, 1e-3, t_grid, p))]
                )
                for p in perturbed
            },
        }
        for s in SCHEMES
        for rho in rhos[1:]
    ]
    long_rows = []
    for s, rho, h, t_end, p in long:
        res = done[repr((s, rho, h, t_end, p))]
        long_rows.append(
            {
                "scheme": s,
                "ρ∞": rho,
                "status": res["status"],
                "end (s)": res["end"],
                "growth (% of peak KE)": res["growth"],
                "energy left (% of peak KE)": res["left"],
                "halvings": res["halvings"],
                "iterations per step": res["iterations"],
                "wall (s)": res["wall"],
            }
        )
    text = report(
        "The energy-decaying smooth step against generalized-α: flexible pendulum, e_N = 1",
        (f"{t_grid:g} s runs over the step h (s): growth, or where the energy ran away", grid_rows),
        (f"{t_grid:g} s runs at h = 1e-3 s, the strip changed by about 1 %", pert_rows),
        (f"{t_long:g} s runs at h = 1e-3 s", long_rows),
        (
            "Accuracy at h = 1e-3 s: largest tip distance (mm) from each scheme's own run at h/8 "
            "and from generalized-α's (ρ∞ = 0.5) at h/8; energy at 1.5 s",
            accuracy(rhos, args.workers, t_short),
        ),
        (
            f"Cost over {t_short:g} s at h = 1e-3 s, side by side (median of 3)",
            cost(rhos, 1 if quick else 3, t_short),
        ),
    )
    name = "energy_decaying_quick.md" if quick else "energy_decaying.md"
    print(write_markdown(f"{args.out}/{name}", text))


if __name__ == "__main__":
    main()
