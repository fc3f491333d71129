"""What each step of a case costs: the counts of the run's statistics that the step added
(factorizations, located impacts, smooth steps of the localization, curvature
factorizations, halvings, least squares, fallbacks) with its wall time and the phases of
the run's timer so far, one line a step. For a run too slow to profile whole: cut its end
time and read where the steps spend (``docs/validation/stress_3d.md``, the P2 balls).

    python benchmarks/step_counts.py two_balls --set element=P2 --set velocity=3 \\
        --t-end 0.00016 [--out DIR]
    python benchmarks/step_counts.py --quick   # three steps of two_balls: checks it runs

The lines are printed and kept as ``step_counts.csv`` and ``.md`` in ``--out``.
"""

from __future__ import annotations

import argparse
import time

from _common import parser, publish_report

from fecontact.cli.cases import load_case
from fecontact.cli.run import prepare
from fecontact.time.simulate import simulate
from fecontact.time.state import PhaseTimer
from fecontact.time.stats import StepStats


def flat(d: dict, prefix: str = "") -> dict:
    """The numbers of a nested summary by dotted key."""
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out |= flat(v, f"{prefix}{k}.")
        elif isinstance(v, int | float) and not isinstance(v, bool):
            out[prefix + k] = v
    return out


def main() -> None:
    p = parser(__doc__.split("\n\n")[0])
    p.add_argument("case", nargs="?", default="two_balls")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    p.add_argument("--t-end", type=float)
    p.add_argument("--dt", type=float)
    a = p.parse_args()
    args = argparse.Namespace(
        set=a.set, t_end=a.t_end, dt=a.dt, output_interval=None, rtol=None, debug=False
    )
    sim = prepare(load_case(a.case).build, args, a.case)
    if a.quick:
        sim = sim.replace(t_end=3 * sim.dt)
    timer, stats = PhaseTimer(), StepStats()
    frictional = sim.model.contacts.frictional
    before = flat(stats.summary(frictional))
    rows = []
    start = last = time.perf_counter()
    steps = simulate(sim.model, sim.dt, sim.t_end, sim.options, timer, sim.q0, sim.v0, None, stats)
    for st in steps:
        now = time.perf_counter()
        counts = flat(stats.summary(frictional))
        added = {k: v - before.get(k, 0) for k, v in counts.items() if v != before.get(k, 0)}
        phases = {k: round(v, 2) for k, v in timer.items()}
        print(f"step {st.step} t={st.t:.5g} s wall {now - last:.2f} s {added} timer {phases}")
        rows.append(
            {"step": st.step, "t": st.t, "wall_s": now - last, "added": added, "timer": phases}
        )
        before, last = counts, now
    print(f"total {time.perf_counter() - start:.1f} s")
    print({k: v for k, v in before.items() if v})
    caption = f"`{a.case}` {' '.join(a.set)}: what each step added to the run's counts."
    publish_report(a.out, "step_counts", a.quick, "Step counts", rows, (caption, rows))


if __name__ == "__main__":
    main()
