"""An elastic ball dropped on an elastic slab clamped at its base: mortar and node-to-surface.

``cases/ball_on_slab.py``: a ball (R = 0.05 m) lands at 1 m/s (2 mm of fall under gravity) on
a 0.2 × 0.2 × 0.04 m slab clamped at its base, both linear elastic (E = 10 MPa, ν = 0.3,
ρ = 1000 kg/m³), e_N = 0, at the ball's step Δx/c, over 12 ms (the contact lasts about
6.5 ms). Per run: the status (and the failure's message), the dofs, steps, step halvings,
steps retaken for penetration, the deepest penetration the run measured (``max_penetration``:
with mortar, its watch of every boundary node), the deepest boundary node of either body
inside the other at any step (the case's
``penetration`` probe, an inside/outside test alone) over the shortest edge, the energy the
ledger finds created (its largest fall of the dissipation below its running maximum) over
the scale (the largest kinetic plus strain energy), the landing and leaving speeds of the
ball's centre of mass (m/s; the speed at the first step with an active contact, and at
12 ms) and the wall time.

    python benchmarks/ball_on_slab.py            # the table (a few minutes)
    python benchmarks/ball_on_slab.py --quick    # the smallest mesh, mortar (seconds)
"""

from __future__ import annotations

import numpy as np
from _common import case, parser, publish_report, timed_run

BALL_ON_SLAB = case("ball_on_slab")
# (method, passes, element, ball refinements, slab divisions, step / Δx/c)
RUNS = [
    ("mortar", 2, "P1", 2, 10, 1.0),
    ("mortar", 2, "P1", 3, 10, 1.0),
    ("mortar", 2, "P1", 3, 10, 0.5),
    ("mortar", 2, "P1", 3, 16, 1.0),
    ("mortar", 2, "P2", 1, 10, 1.0),
    ("node-to-surface", 2, "P1", 2, 10, 1.0),
    ("node-to-surface", 1, "P1", 2, 10, 1.0),
    ("node-to-surface", 1, "P1", 2, 11, 1.0),
]


def row(method, passes, element, refinements, divisions, fraction) -> dict:
    sim = BALL_ON_SLAB.build(method=method, passes=passes, element=element, t_end=0.012,
                             refinements=refinements, divisions=divisions)  # fmt: skip
    sim = sim.replace(dt=fraction * sim.dt)
    r = timed_run(sim, repeats=1)
    edge = min(body.min_edge_length for body in sim.model.bodies)
    s, h = r["summary"], r["history"]
    ledger = s["energy_ledger"]
    vz, active = np.asarray(h["vz_center"]), np.asarray(h["n_active"]) > 0
    landed = np.flatnonzero(active)
    return {
        "method": method if method == "mortar" else f"{method}, {passes} pass(es)",
        "element": element,
        "ball refinements": refinements,
        "slab cells": f"{divisions}x{divisions}x2",
        "dofs": s["n_dofs"],
        "step (dx/c)": fraction,
        "status": r["status"],
        "message": r["message"][:90],
        "steps": s["steps"],
        "halvings": s["step_halvings"],
        "retakes": s["penetration_retakes"],
        "max penetration (m)": s["max_penetration"],
        "deepest node / edge": float(np.max(h["penetration"])) / edge,
        "created / scale": ledger["created"] / ledger["scale"],
        "landing speed (m/s)": -float(vz[landed[0]]) if landed.size else np.nan,
        "leaving speed (m/s)": float(vz[-1]) if r["status"] == "completed" else np.nan,
        "wall (s)": r["wall"],
    }


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    runs = RUNS[:1] if args.quick else RUNS
    rows = []
    for spec in runs:
        rows.append(row(*spec))
        print(rows[-1], flush=True)
    publish_report(
        args.out, "ball_on_slab", args.quick, "Elastic ball on an elastic slab", rows,
        ("cases/ball_on_slab.py, 1 m/s, 12 ms, e_N = 0.", rows),
    )  # fmt: skip


if __name__ == "__main__":
    main()
