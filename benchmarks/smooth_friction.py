"""Coulomb friction in the smooth step against the decoupled scheme: elastic solids.

1. ``cases/disk_drop.py`` (2 refinements, Neo-Hookean) thrown at 2 m/s along and 1 m/s onto
   the plane with μ = 0.1 (every contact node slips) and μ = 1 (nodes grip), at steps from
   Δx/16c to 4 Δx/c, with ``smooth_contact="on"`` (pressed nodes carry a normal and a
   tangential force in the generalized-α Newton, ``fecontact/time/coulomb.py``,
   ``SmoothFriction``) and ``"off"`` (corrections and velocity jumps only), side by side.
   Per run: the energy excess (the largest total energy above the initial one, % of the
   initial kinetic energy), the errors of the centre of mass's velocity along and normal to
   the plane and of the spin at the end (after the rebound), against the finest run of the
   smooth scheme, the smallest gap, halvings, Newton iterations and wall time.
   Time to solution at equal accuracy: the cheapest run of each scheme with an excess
   ≤ 0.3 % and every error ≤ 0.5 %, timed again side by side (median of 3).
2. ``cases/elastic_block.py`` (3D, the disk cone) at its step Δx/c: a block held on a 20°
   incline with μ = 0.5 (stiffness damping 1e-4 s lets it settle): the largest motion of a
   bottom node along the plane over the last 0.05 s; and a block thrown down a 30° incline
   at 0.5 m/s with μ = 0.2: the largest departure from v + μ v_n = v₀ + g(sin α − μ cos α) t,
   which holds while every pressed node slips down the slope.

    python benchmarks/smooth_friction.py            # about 1 minute
    python benchmarks/smooth_friction.py --quick    # coarse meshes, short runs: seconds
"""

from __future__ import annotations

import statistics
import time

import numpy as np
from _common import RESULTS, case, markdown_table, parser, publish, trace, with_options

from fecontact.scenes import wave_step
from fecontact.testing import G
from fecontact.time import simulate

STEPS = {"on": (1 / 16, 1 / 4, 1 / 2, 1, 2, 4), "off": (1 / 16, 1 / 8, 1 / 4, 1 / 2, 1)}
TARGET = {"excess_pct": 0.3, "error_pct": 0.5}
PROBES = ("vx_center", "vy_center", "omega")
COLUMNS = [
    "friction",
    "scheme",
    "h_per_transit",
    "status",
    "excess_pct",
    "vx_error_pct",
    "vy_error_pct",
    "omega_error_pct",
    "min_gap",
    "halvings",
    "iterations",
    "wall_s",
]


DISK = {"refinements": 2}
"""The disk's mesh (and, with --quick, a shorter run); BLOCK likewise for the block."""
BLOCK = {}


def throw(mu: float, scheme: str, fraction: float):
    sim = case("disk_drop").build(slide_velocity=2.0, friction=mu, **DISK)
    sim = with_options(sim, smooth_contact=scheme)
    return sim.replace(dt=fraction * wave_step(sim.model.bodies[0], 1.0))


def measure(mu: float, scheme: str, fraction: float) -> dict:
    r = trace(throw(mu, scheme, fraction))
    e0, k0 = r["total"][0], r["kinetic"][0]
    row = {"friction": mu, "scheme": scheme, "h_per_transit": fraction, "status": r["status"]}
    row |= {p: r[p][-1] for p in PROBES}
    return row | {
        "excess_pct": 100 * (r["total"].max() - e0) / k0,
        "min_gap": r["min_gap"].min(),
        "halvings": int(r["halvings"].sum()),
        "iterations": int(r["iterations"].sum()),
        "wall_s": r["wall"],
    }


def accurate(row) -> bool:
    errors = [abs(row[f"{p.split('_')[0]}_error_pct"]) for p in PROBES]
    return row["excess_pct"] <= TARGET["excess_pct"] and max(errors) <= TARGET["error_pct"]


def time_to_solution(rows, mu) -> list[dict]:
    """The cheapest accurate run of each scheme at friction ``mu``, timed side by side."""
    chosen = {}
    for scheme in ("off", "on"):
        ok = [r for r in rows if r["friction"] == mu and r["scheme"] == scheme and accurate(r)]
        if ok:
            chosen[scheme] = max(ok, key=lambda r: r["h_per_transit"])["h_per_transit"]
    walls = {s: [] for s in chosen}
    for _ in range(3):
        for scheme, fraction in chosen.items():
            start = time.perf_counter()
            trace(throw(mu, scheme, fraction))
            walls[scheme].append(time.perf_counter() - start)
    out = [
        {"friction": mu, "scheme": s, "h_per_transit": f, "wall_s": statistics.median(walls[s])}
        for s, f in chosen.items()
    ]
    for row in out:
        row["speedup"] = out[0]["wall_s"] / row["wall_s"]
    return out


def held_creep(scheme: str) -> dict:
    sim = case("elastic_block").build(incline=20.0, friction=0.5, damping=1e-4, **BLOCK)
    sim = with_options(sim, smooth_contact=scheme)
    block, s = sim.model.bodies[0], sim.model.body_slice(0)
    bottom = sim.model.contacts.pairs[0].nodes
    start = time.perf_counter()
    states = simulate(sim.model, sim.dt, sim.t_end, sim.options)
    xs = [block.positions(st.q[s])[bottom, :2] for st in states if st.t >= 0.5 * sim.t_end]
    creep = float(np.max(np.linalg.norm(np.array(xs) - xs[0], axis=2)))
    wall = time.perf_counter() - start
    return {"run": "held, 20°, μ = 0.5", "scheme": scheme, "measure": creep, "wall_s": wall}


def sliding_departure(scheme: str) -> dict:
    mu, a, v0 = 0.2, np.radians(30.0), 0.5
    sim = case("elastic_block").build(incline=30.0, friction=mu, velocity=v0, **BLOCK)
    r = trace(with_options(sim, smooth_contact=scheme))
    exact = v0 + G * (np.sin(a) - mu * np.cos(a)) * r["t"]
    departure = float(np.abs(r["v"] + mu * r["vn"] - exact).max())
    return {"run": "sliding, 30°, μ = 0.2", "scheme": scheme, "measure": departure,
            "wall_s": r["wall"]}  # fmt: skip


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    steps, mus = STEPS, (0.1, 1.0)
    if args.quick:
        DISK.update(refinements=1, t_end=0.003)
        BLOCK.update(divisions=2, t_end=0.01)
        steps, mus = {"on": (1, 4), "off": (1,)}, (0.1,)
    rows = [measure(mu, s, f) for mu in mus for s in steps for f in steps[s]]
    for mu in mus:
        finest = min(
            (r for r in rows if r["friction"] == mu and r["scheme"] == "on"),
            key=lambda r: r["h_per_transit"],
        )
        for row in (r for r in rows if r["friction"] == mu):
            for p in PROBES:
                row[f"{p.split('_')[0]}_error_pct"] = 100 * (row[p] / finest[p] - 1.0)
    table = markdown_table(rows, COLUMNS)
    speed = [r for mu in mus for r in time_to_solution(rows, mu)]
    speed_table = markdown_table(speed, ["friction", "scheme", *COLUMNS[2:3], "wall_s", "speedup"])
    block = [f(s) for f in (held_creep, sliding_departure) for s in ("on", "off")]
    block_table = markdown_table(block, ["run", "scheme", "measure", "wall_s"])
    text = (
        "# Smooth friction force against the decoupled scheme: elastic solids\n\n"
        "## An elastic disk thrown at an angle onto a plane\n\n" + table + "\n\n"
        "Time to solution at equal accuracy (energy excess ≤ 0.3 %, errors ≤ 0.5 %: the "
        "cheapest run of each scheme, timed again side by side, median of 3):\n\n"
        + speed_table
        + "\n\n## A 3D elastic block on an incline, at Δx/c\n\n"
        "The measure: held, the largest motion of a bottom node along the plane over the last "
        "0.05 s (m); sliding, the largest |v + μ v_n − v₀ − g(sin α − μ cos α) t| (m/s).\n\n"
        + block_table
    )
    print(text)
    stem = "smooth_friction_quick" if args.quick else "smooth_friction"
    publish(f"{args.out or RESULTS}/{stem}", rows, COLUMNS, text)


if __name__ == "__main__":
    main()
