"""Contact forces in the smooth step against the fully decoupled scheme: two elastic disks.

``cases/two_disks.py`` (refinements 3, 580 dofs, Neo-Hookean, e_N = 0 at the nodes, ρ∞ = 0.5)
at steps from Δx/16c to 64 Δx/c (Δx/c: the dilatational wave's transit time across the
shortest edge), with ``smooth_contact="off"`` (the decoupled scheme: the contact acts only
through position corrections and velocity jumps) and ``"on"`` (persistent contacts carry a
smooth force λ in the generalized-α Newton, ``fecontact/time/smooth_contact.py``), side by
side in one process. Per run:

- energy excess: the largest total energy during the run above the initial one, in % of the
  initial kinetic energy (no gravity, no other work: any excess is the scheme's);
- final energy: the same at the end (after separation; e_N = 0 and ρ∞ take energy out);
- contact duration: from the step before the first contact force to the last step with one;
- exit speed: the right disk's centre-of-mass speed at the end, and its error against the
  finest run of the new scheme;
- the smallest gap of any contact at any step (m) and the largest |total momentum| over one
  disk's initial momentum;
- halvings, Newton iterations and wall time (s, one run, the history only).

Time to solution at equal accuracy: the cheapest run of each scheme whose energy excess is
≤ 0.3 % and whose exit speed is within 0.1 % of the reference (the accuracy of the decoupled
scheme at the case's former step Δx/16c); those two runs are then timed again side by side,
alternating, three times each, and the median walls compared.

    python benchmarks/smooth_contact.py            # about 1 minute
    python benchmarks/smooth_contact.py --quick    # refinements 1, two steps: seconds
"""

from __future__ import annotations

import statistics
import time

import numpy as np
from _common import (
    RESULTS,
    case,
    markdown_table,
    parser,
    trace,
    with_options,
    write_csv,
    write_markdown,
)

from fecontact.scenes import wave_step

STEPS = (1 / 16, 1 / 4, 1, 2, 4, 8, 16, 64)  # × Δx/c
TARGET = {"excess_pct": 0.3, "exit_error_pct": 0.1}
COLUMNS = [
    "scheme",
    "h_per_transit",
    "steps",
    "status",
    "excess_pct",
    "final_pct",
    "duration_ms",
    "exit_speed",
    "exit_error_pct",
    "min_gap",
    "momentum",
    "halvings",
    "iterations",
    "wall_s",
]


QUICK = {"refinements": 1, "t_end": 0.003}
"""The case's parameters in --quick."""


def sim_at(scheme: str, fraction: float, params=None):
    sim = with_options(case("two_disks").build(**(params or {})), smooth_contact=scheme)
    return sim.replace(dt=fraction * wave_step(sim.model.bodies[0], 1.0))


def measure(scheme: str, fraction: float, params=None) -> dict:
    sim = sim_at(scheme, fraction, params)
    r = trace(sim)
    e0, k0 = r["total"][0], r["kinetic"][0]
    on = np.flatnonzero(r["active"])
    p0 = abs(sim.model.bodies[0].mass * r["v_left"][0])
    return {
        "scheme": scheme,
        "h_per_transit": fraction,
        "steps": len(r["t"]) - 1,
        "status": r["status"],
        "excess_pct": 100 * (r["total"].max() - e0) / k0,
        "final_pct": 100 * (r["total"][-1] - e0) / k0,
        "duration_ms": 1e3 * (r["t"][on[-1]] - r["t"][on[0] - 1]) if on.size else 0.0,
        "exit_speed": r["v_right"][-1],
        "min_gap": r["min_gap"].min(),
        "momentum": np.abs(r["momentum"]).max() / p0,
        "halvings": int(r["halvings"].sum()),
        "iterations": int(r["iterations"].sum()),
        "wall_s": r["wall"],
    }


def accurate(row) -> bool:
    return row["excess_pct"] <= TARGET["excess_pct"] and (
        abs(row["exit_error_pct"]) <= TARGET["exit_error_pct"]
    )


def time_to_solution(rows, params=None) -> list[dict]:
    """The cheapest accurate run of each scheme, timed again side by side."""
    chosen = {}
    for scheme in ("off", "on"):
        ok = [r for r in rows if r["scheme"] == scheme and accurate(r)]
        if ok:
            chosen[scheme] = max(ok, key=lambda r: r["h_per_transit"])
    walls = {s: [] for s in chosen}
    for _ in range(3):
        for scheme, row in chosen.items():
            start = time.perf_counter()
            trace(sim_at(scheme, row["h_per_transit"], params))
            walls[scheme].append(time.perf_counter() - start)
    out = []
    for scheme, row in chosen.items():
        wall = statistics.median(walls[scheme])
        out.append({"scheme": scheme, "h_per_transit": row["h_per_transit"], "wall_s": wall})
    if len(out) == 2:
        for row in out:
            row["speedup"] = out[0]["wall_s"] / row["wall_s"]
    return out


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    params = QUICK if args.quick else None
    steps = (1 / 4, 1) if args.quick else STEPS  # quick: halvings at 1, none at 1/4
    rows = [measure(s, f, params) for f in steps for s in ("off", "on")]
    finest = min((r for r in rows if r["scheme"] == "on"), key=lambda r: r["h_per_transit"])
    for row in rows:
        row["exit_error_pct"] = 100 * (row["exit_speed"] / finest["exit_speed"] - 1.0)
    table = markdown_table(rows, COLUMNS)
    speed = time_to_solution(rows, params)
    speed_table = markdown_table(speed, ["scheme", "h_per_transit", "wall_s", "speedup"])
    print(table + "\n\n" + speed_table)
    out = args.out or RESULTS
    stem = "smooth_contact_quick" if args.quick else "smooth_contact"
    write_csv(f"{out}/{stem}.csv", rows, COLUMNS)
    text = (
        "# Smooth contact force against the decoupled scheme: two elastic disks\n\n"
        + table
        + "\n\nTime to solution at equal accuracy (energy excess ≤ 0.3 %, exit speed within "
        "0.1 %: the cheapest run of each scheme, timed again side by side, median of 3):\n\n"
        + speed_table
    )
    write_markdown(f"{out}/{stem}.md", text)


if __name__ == "__main__":
    main()
