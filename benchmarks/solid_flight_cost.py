"""The located free-flight step of solids against the non-localized one, side by side.

``ball_drop`` (drop height 0.05 m: a few hundred steps in flight) and ``disk_drop`` (drop
height 0.05 m) are stepped from their third step in batches of 50 free-flight steps, with
``localize="auto"`` (whole steps, the release read aside: :class:`fecontact.time.substeps.
Releases`), with :func:`fecontact.time.localize.localized_step` alone (the located step
without the release's bookkeeping) and with ``localize`` off (the NSGA step), alternated
in one process; each batch starts from the same state. The table gives CPU medians per step
and the ratios to the off step (issue: a step without an impact costs ≤ 5 % more).

    python benchmarks/solid_flight_cost.py [--batches 30] [--steps 50]
    python benchmarks/solid_flight_cost.py --quick
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import copy
import statistics
import time
from pathlib import Path

import numpy as np
from _common import markdown_table, parser, write_markdown

CASES = (("ball_drop", {"drop_height": 0.05}), ("disk_drop", {"drop_height": 0.05}))
VARIANTS = ("auto", "step", "off")  # Releases, localized_step alone, the NSGA step


def steppers(name: str, params: dict, start: int = 3):
    """{variant: (stepper, the state after ``start`` steps, timer, dt)} of ``name``."""
    from fecontact.cli.cases import load_case
    from fecontact.time import IntegratorOptions, PhaseTimer, initial_state, make_stepper
    from fecontact.time.localize import localized_step

    out = {}
    for variant in VARIANTS:
        sim = load_case(name).build(**params)
        localize = False if variant == "off" else "auto"
        opts = IntegratorOptions(**{**vars(sim.options), "localize": localize})
        stepper = make_stepper(sim.model, opts, None, 1 << 20)
        if variant == "step":
            stepper.kind = localized_step
        sim.model.contacts.detect_within(opts.detection_margin * sim.model.length)
        timer = PhaseTimer()
        st = initial_state(sim.model, sim.q0, sim.v0, opts.tol_gap)
        for _ in range(start):
            st = stepper.step(st, sim.dt, timer)
        out[variant] = (stepper, st, timer, sim.dt)
    return out


def batch(stepper, st, timer, h: float, steps: int) -> float:
    """CPU s per step of ``steps`` steps from a copy of ``st`` (none may touch a contact)."""
    cur = copy.deepcopy(st)
    clock = time.process_time()
    for _ in range(steps):
        cur = stepper.step(cur, h, timer)
    spent = time.process_time() - clock
    assert not (cur.impulse.any() or cur.pressed().any()), "a contact closed in flight"
    return spent / steps


def flight_cost(name: str, params: dict, batches: int, steps: int) -> dict:
    """Medians over ``batches`` alternated batches of the CPU µs of a free-flight step."""
    runs = steppers(name, params)
    ends = {v: batch(*runs[v], steps) for v in VARIANTS}  # (warm; the same states after)
    assert all(np.array_equal(runs[v][1].q, runs["off"][1].q) for v in VARIANTS), name
    del ends
    times: dict = {v: [] for v in VARIANTS}
    for i in range(batches):
        order = VARIANTS if i % 2 == 0 else VARIANTS[::-1]
        for v in order:
            times[v].append(batch(*runs[v], steps))
    med = {v: statistics.median(times[v]) for v in VARIANTS}
    return {
        "case": name,
        "off_us": 1e6 * med["off"],
        "auto_us": 1e6 * med["auto"],
        "step_us": 1e6 * med["step"],
        "auto / off": med["auto"] / med["off"],
        "step / off": med["step"] / med["off"],
    }


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--batches", type=int, default=30)
    p.add_argument("--steps", type=int, default=50)
    args = p.parse_args()
    batches, steps = (3, 5) if args.quick else (args.batches, args.steps)
    rows = [flight_cost(name, params, batches, steps) for name, params in CASES]
    table = markdown_table(rows, list(rows[0]))
    print(table)
    stem = "solid_flight_cost" + ("_quick" if args.quick else "")
    title = f"# Located free-flight step of solids ({batches} batches of {steps} steps, CPU)\n\n"
    write_markdown(Path(args.out) / f"{stem}.md", title + table)


if __name__ == "__main__":
    main()
