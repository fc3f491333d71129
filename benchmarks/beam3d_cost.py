"""What a step costs in space: spatial_pendulum (Beam3D) against flexible_pendulum (Beam2D),
the same strip, mass, elements, step and options, run side by side in one process.

Measured: the compute time per step of each run through the driver (no frames, median of
repeated runs) and its ratio, and the time of one evaluation of the beam's internal force with
and without its tangent (median of repeats). The runs move in the x–y plane
(out_of_plane_velocity = 0), where the two give the same history.
"""

from __future__ import annotations

import statistics
import timeit

import numpy as np
from _common import RESULTS, case, markdown_table, parser, timed_run, write_csv, write_markdown


def kernel_times(sim, repeats: int) -> dict:
    """Median times (µs) of the beam's internal force with and without the tangent."""
    beam = sim.model.bodies[0]
    q = np.random.default_rng(0).normal(size=beam.ndof) * 1e-3
    out = {}
    for label, tangent in (("force + tangent (µs)", True), ("force (µs)", False)):
        times = timeit.repeat(lambda t=tangent: beam.internal(q, t), number=100, repeat=repeats)
        out[label] = 1e6 * statistics.median(times) / 100
    return out


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    t_end, repeats = (0.05, 1) if args.quick else (0.5, 5)
    rows = []
    for name in ("flexible_pendulum", "spatial_pendulum"):
        sim = case(name).build().replace(t_end=t_end)
        run = timed_run(sim, repeats=repeats)
        row = {"case": name, "steps": run["steps"], "status": run["status"]}
        row |= {"compute per step (ms)": 1e3 * run["compute"] / run["steps"]}
        rows.append(row | kernel_times(sim, repeats))
    ratio = rows[1]["compute per step (ms)"] / rows[0]["compute per step (ms)"]
    for r in rows:
        r["ratio to flexible_pendulum"] = (
            r["compute per step (ms)"] / rows[0]["compute per step (ms)"]
        )
    columns = list(rows[0])
    table = markdown_table(rows, columns)
    print(table)
    out = args.out or RESULTS
    stem = "beam3d_cost_quick" if args.quick else "beam3d_cost"
    write_csv(f"{out}/{stem}.csv", rows, columns)
    note = f"A step of spatial_pendulum costs {ratio:.2f}× one of flexible_pendulum."
    write_markdown(f"{out}/{stem}.md", f"# The cost of a step in space\n\n{table}\n\n{note}")


if __name__ == "__main__":
    main()
