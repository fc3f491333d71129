"""Cost of a step in space: the heavy top against the planar rigid pendulum, side by side.

Both are one rigid body on a joint to the ground at h = 1 ms (``cases/heavy_top.py``: six dofs,
a ball joint of three rows, the Lie-group smooth step with its gyroscopic force;
``cases/rigid_pendulum.py``: three dofs, a pin of two rows, before its first impact). The two
run alternately in this process, ``repeats`` times each, so that a change of load on the
machine hits both; per case the least CPU time per step (``time.process_time``) over the
repeats, the Newton iterations per step, the ratio of the least times heavy top / rigid
pendulum, and the median (min–max) of the ratios of the alternating pairs.

    python benchmarks/rigid3d_speed.py [--quick] [--repeats N] [--out DIR]
"""

from __future__ import annotations

import time

import numpy as np
from _common import RESULTS, case, markdown_table, parser, write_markdown

from fecontact.time import simulate

CASES = {"heavy_top": {"dt": 1e-3}, "rigid_pendulum": {}}


def per_step(name: str, t_end: float) -> tuple[float, float]:
    """(CPU s per step, smooth Newton iterations per step) of ``name`` at h = 1 ms."""
    sim = case(name).build(**CASES[name])
    start = time.process_time()
    states = list(simulate(sim.model, 1e-3, t_end, sim.options, q0=sim.q0, v0=sim.v0))
    cost = (time.process_time() - start) / (len(states) - 1)
    return cost, float(np.mean([st.iterations["smooth"] for st in states[1:]]))


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    t_end, repeats = (0.02, 1) if args.quick else (0.35, args.repeats)
    best = {name: (np.inf, 0.0) for name in CASES}
    pairs = []
    for _ in range(repeats):
        pair = {}
        for name in CASES:
            cost, iters = per_step(name, t_end)
            best[name] = min(best[name], (cost, iters))
            pair[name] = cost
        pairs.append(pair["heavy_top"] / pair["rigid_pendulum"])
    rows = [
        {"case": n, "steps": round(t_end / 1e-3), "cpu_per_step_ms": 1e3 * c, "newton_per_step": i}
        for n, (c, i) in best.items()
    ]
    ratio = best["heavy_top"][0] / best["rigid_pendulum"][0]
    text = (
        "# Cost of a step in space: heavy top against rigid pendulum\n\n"
        f"Least CPU time per step over {repeats} alternating runs of {t_end} s at h = 1 ms.\n\n"
        + markdown_table(rows, list(rows[0]))
        + f"\n\nRatio heavy top / rigid pendulum: {ratio:.2f} (of the least times); of the "
        f"alternating pairs, median {np.median(pairs):.2f} ({min(pairs):.2f}–{max(pairs):.2f}).\n"
    )
    print(text)
    stem = "rigid3d_speed_quick" if args.quick else "rigid3d_speed"
    write_markdown(f"{args.out or RESULTS}/{stem}.md", text)


if __name__ == "__main__":
    main()
