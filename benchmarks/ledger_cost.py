"""What the energy ledger costs a step: the time spent in its own calls against the step.

The ledger's work in a run is the recorder's ``EnergyLedger.add`` per step, the record
NSGA leaves after its smooth step (``pending_record``: the kinetic energy of ṽ and, after a
position correction, the potential energy of q̃, made when ``add`` first reads the record,
so inside its time) and the works of a velocity jump's
impulses (``impulse_work``, ``jump_work``). All are timed inside ordinary runs (each
call wrapped with a clock), so that the share is measured in the same run as the step and
the machine's noise cannot tilt it. Reported: the median over ``--repeats`` runs of the time
per step and of the ledger's share of it.

    python benchmarks/ledger_cost.py [--quick] [--repeats N]
"""

from __future__ import annotations

import statistics
import time

from _common import markdown_table, parser, publish, report, timed_run

import fecontact.ledger
import fecontact.time.impacts
import fecontact.time.nsga
import fecontact.time.poisson
from fecontact.testing import case

CASES = [
    ("flexible_pendulum", {}, 1.0, 0.35),
    ("two_disks", {"refinements": 2}, 0.006, 0.002),
]


class Clock:
    """Wraps a function and adds the time spent in it."""

    def __init__(self, fn):
        self.fn, self.seconds = fn, 0.0

    def __call__(self, *args, **kw):
        start = time.perf_counter()
        try:
            return self.fn(*args, **kw)
        finally:
            self.seconds += time.perf_counter() - start


# the ledger's functions a step calls, by the module that calls them
CALLS = [
    (fecontact.time.nsga, "pending_record"),
    (fecontact.time.impacts, "impulse_work"),
    (fecontact.time.impacts, "jump_work"),
    (fecontact.time.poisson, "impulse_work"),
]


def measure(name: str, kw: dict, t_end: float, repeats: int) -> dict:
    sim = case(name).build(**kw).replace(t_end=t_end)
    add = fecontact.ledger.EnergyLedger.add
    originals = [getattr(module, attr) for module, attr in CALLS]
    shares, per_step = [], []
    try:
        for _ in range(repeats):
            clock_add = Clock(add)
            clocks = [Clock(fn) for fn in originals]
            fecontact.ledger.EnergyLedger.add = lambda self, *a, c=clock_add: c(self, *a)
            for (module, attr), clock in zip(CALLS, clocks, strict=True):
                setattr(module, attr, clock)
            out = timed_run(sim, repeats=1)
            steps = out["steps"]
            ledger = clock_add.seconds + sum(c.seconds for c in clocks)
            step = out["compute"] / steps
            per_step.append(step)
            shares.append(ledger / steps / step)
    finally:
        fecontact.ledger.EnergyLedger.add = add
        for (module, attr), fn in zip(CALLS, originals, strict=True):
            setattr(module, attr, fn)
    return {
        "case": name,
        "steps": steps,
        "time_per_step_ms": 1e3 * statistics.median(per_step),
        "ledger_share": statistics.median(shares),
    }


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    rows = [
        measure(name, kw, quick if args.quick else t_end, 1 if args.quick else args.repeats)
        for name, kw, t_end, quick in CASES
    ]
    columns = ["case", "steps", "time_per_step_ms", "ledger_share"]
    table = markdown_table(rows, columns)
    print(table)
    caption = "The share of a step's time spent in the ledger's own calls (median of runs)."
    text = report("The energy ledger's cost", (caption, rows))
    publish(f"{args.out}/ledger_cost{'_quick' if args.quick else ''}", rows, columns, text)


if __name__ == "__main__":
    main()
