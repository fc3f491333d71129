"""Work against precision with Coulomb friction: the NSGA step and the Moreau–Jean baseline.

Cases: the founding case with friction μ = 0.3 between tip and stop (0.6 s: the first impact
and the tip rubbing along the stop), and the rigid disk thrown along a plane (μ = 0.3, 0.5 s:
slipping, then rolling at 4/3 m/s). Per method and step h: the wall time of the run and the
largest error of the probes (tip position; disk position and speed) against the NSGA run at
h_ref = h_min/8 (``--quick``: h_min/2), over the coarse run's times.

    python benchmarks/friction_work_precision.py [--quick]
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, case, markdown_table, parser, trace, write_csv, write_markdown

CASES = {
    "flexible_pendulum": ({"friction": 0.3}, 0.6, ("tip_x", "tip_y")),
    "rolling_disk": ({}, 0.5, ("x", "vx")),
}
STEPS = (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4)
METHODS = ("nsga", "moreau")
COLUMNS = ["case", "method", "h", "wall_s", "error", "status"]


def run(name, method, h):
    params, t_end, _ = CASES[name]
    sim = case(name).build(**params)
    sim = sim.replace(options=dataclasses.replace(sim.options, integrator=method))
    start = time.perf_counter()
    tr = trace(sim, dt=h, t_end=t_end)
    return tr, time.perf_counter() - start


def error(tr, ref, probes):
    """Largest |probe − reference| at the run's times (the reference grid contains them)."""
    idx = np.searchsorted(ref["t"], tr["t"] - 1e-12)
    return max(float(np.max(np.abs(tr[p] - ref[p][idx]))) for p in probes)


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    steps = STEPS[:2] if args.quick else STEPS
    fine = 2 if args.quick else 8  # the reference's step: h_min / fine
    rows = []
    for name, (_, _, probes) in CASES.items():
        ref, _ = run(name, "nsga", steps[-1] / fine)
        for h in steps:
            for method in METHODS:
                tr, wall = run(name, method, h)
                err = error(tr, ref, probes)
                rows.append(
                    {"case": name, "method": method, "h": h, "wall_s": wall, "error": err}
                    | {"status": tr["status"]}
                )
                print(rows[-1], flush=True)
    table = markdown_table(rows, COLUMNS)
    print(table)
    out = Path(args.out or RESULTS)
    suffix = "_quick" if args.quick else ""
    write_csv(out / f"friction_work_precision{suffix}.csv", rows, COLUMNS)
    head = f"# Work against precision with friction\n\nReference: NSGA at h_min/{fine}.\n\n"
    write_markdown(out / f"friction_work_precision{suffix}.md", head + table)


if __name__ == "__main__":
    main()
