"""Impact localization on the cases with elastic solids: on against off, row by row.

For every bundled case with a solid body, at its defaults and at the case matrix's variations
(``benchmarks/case_matrix.py``: speed, restitution, friction, obliquity, mesh, step), each row
is run with ``localize`` off, on in whole steps (what "auto" does on solids whose contacts are
all on fixed obstacles) and on with the flexible bodies' chattering sub-steps (what
``localize=1`` does), and at an eighth of its
step with localization on and sub-steps (the reference). For each run: status, steps,
created energy over the ledger's scale, the recorded penetration (``max_penetration``; and
``mortar_depth`` for mortar interfaces, in edges), the located impacts, subdivided steps and
fallbacks, the time of the run itself (each in its own process, one after the other) and the
error: the largest difference over the run's steps of the first body's centre-of-mass
velocity from the reference's at the same instants, over the approach speed.

    python benchmarks/solid_localization.py                  # every solid case, ~10 min
    python benchmarks/solid_localization.py --case ball_drop # one case
    python benchmarks/solid_localization.py --quick          # seconds
    python benchmarks/solid_localization.py --step-cost      # the impact step's cost, ~1 min

``--step-cost``: the first impact step of ``disk_drop`` and ``ball_drop`` (defaults and one
refinement less), localized ("auto", whole steps) against the end-of-step impact
(``localize`` off) from the same state: the CPU time of that step, medians of alternated
repeats in one process; and of the impact step with the step after it (the off run's next
step takes the impact's elastic response, which the localized step takes in its rest).
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import copy
import dataclasses
import json
import math
import statistics
import tempfile
import time
from pathlib import Path

import case_matrix as cm
import numpy as np
from _common import markdown_table, parser, write_csv, write_markdown

SOLID_CASES = ("ball_drop", "disk_drop", "ball_on_slab", "two_disks", "two_balls")
SKIPPED = ("p x1000", "k /100", "localize on", "localize off")  # not this question
FINE = 8  # the reference's step: the row's over FINE
# (name, localize, sub-steps): whole steps is what "auto" does on solids on obstacles
VARIANTS = (("off", False, 8), ("whole", True, 1), ("sub-steps", True, 8))
QUICK = (("disk_drop", "coarse"),)

COLUMNS = [
    "case",
    "row",
    "run",
    "status",
    "steps",
    "time",
    "created_rel",
    "max_penetration",
    "mortar_depth",
    "error",
    "impacts",
    "subdivided",
    "fallbacks",
    "command",
]


def rows_of(names) -> list[cm.Row]:
    """The case matrix's rows of the cases ``names``, without its p/k and localize rows."""
    return [r for r in cm.all_rows(names) if r.label not in SKIPPED]


def run_one(row: cm.Row, substeps: int) -> dict:
    """Run ``row`` here, flexible models' chattering sub-steps set to ``substeps``: the
    measurements and the trace (t, v_cm) of the first body's centre of mass."""
    from fecontact import Probe, SolverError, run
    from fecontact.cli.cases import load_case
    from fecontact.io.output import read_json
    from fecontact.time import substeps as chatter

    chatter.CHATTER = substeps
    sim = load_case(row.case).build(**row.params)
    options = dataclasses.replace(sim.options, **row.options)
    sim = sim.replace(dt=sim.dt * row.dt_factor, t_end=row.t_end, options=options)
    body, trace = sim.model.bodies[0], []
    w = [body.mass_matrix() @ body.translation_field(e) for e in np.eye(body.dim)]
    s = sim.model.body_slice(0)

    def probe(model, st):
        trace.append([st.t, *(float(x @ st.v[s]) / body.mass for x in w)])
        return 0.0

    sim = sim.replace(probes={**sim.probes, "v_cm_trace": Probe(probe, "m/s")})
    out = {"status": "completed", "dt": sim.dt}
    with tempfile.TemporaryDirectory(prefix="solid_loc_") as tmp:
        clock = time.process_time()
        try:
            summary = run(sim, tmp, frames=False, checkpoint_every=0)
        except SolverError:
            summary = read_json(Path(tmp) / "summary.json")
            out["status"] = "failed"
        out["time"] = time.process_time() - clock
    ledger = summary.get("energy_ledger", {})
    cost = summary.get("localization_cost", {})
    out.update(
        steps=summary.get("steps"),
        created_rel=ledger.get("created", math.nan) / (ledger.get("scale") or math.nan),
        max_penetration=summary.get("max_penetration", math.nan),
        mortar_depth=summary.get("mortar_depth", 0.0),
        impacts=summary.get("localized_impacts", 0),
        subdivided=cost.get("subdivided_steps", 0),
        fallbacks=cm.fallbacks(summary),
        trace=trace,
    )
    return out


def run_isolated(row: cm.Row, substeps: int, timeout: float) -> dict:
    """``run_one`` in a subprocess of this script, at most ``timeout`` s."""
    payload = json.dumps([dataclasses.asdict(row), substeps])
    return cm.run_worker(Path(__file__), payload, timeout)


def velocity_error(res: dict, ref: dict, speed: float) -> float:
    """Largest |v_cm − v_cm of ``ref``| over the rows of ``res`` (the reference read at the
    same instants, linearly between its rows), over ``speed``."""
    if not res.get("trace") or not ref.get("trace"):
        return math.nan
    a, b = np.array(res["trace"]), np.array(ref["trace"])
    b_at = np.column_stack([np.interp(a[:, 0], b[:, 0], b[:, k]) for k in range(1, b.shape[1])])
    return float(np.max(np.abs(a[:, 1:] - b_at)) / speed)


def measure(row: cm.Row, speed: float, timeout: float) -> list[dict]:
    """The runs of ``row`` (``VARIANTS``) with their errors from the fine reference."""
    fine = dataclasses.replace(row, dt_factor=row.dt_factor / FINE)
    ref = run_isolated(
        dataclasses.replace(fine, options={**row.options, "localize": True}), 8, timeout
    )
    out = []
    for name, loc, sub in VARIANTS:
        r = dataclasses.replace(row, options={**row.options, "localize": loc})
        res = run_isolated(r, sub, timeout)
        entry = {
            "case": row.case,
            "row": row.label,
            "run": name,
            "command": r.command(res.get("dt")),
        }
        entry.update({k: res.get(k, math.nan) for k in COLUMNS if k in res and k != "trace"})
        entry["error"] = velocity_error(res, ref, speed)
        out.append(entry)
    return out


def approach_speed(row: cm.Row, default: dict) -> float:
    """The row's approach speed (m/s): its case's speed parameter."""
    spec = cm.CASES[row.case]
    value = row.params.get(spec.speed, default.get(spec.speed))
    return abs(float(value)) if value else 1.0


COST_CASES = (
    ("disk_drop", {}),
    ("disk_drop", {"refinements": 2}),
    ("ball_drop", {}),
    ("ball_drop", {"refinements": 1}),
)
COST_COLUMNS = ["case", "params", "on_ms", "off_ms", "ratio", "pair_ratio", "refinements"]


def before_impact(name: str, params: dict, localize):
    """(stepper, the state at the start of the first step that ends with a contact impulse,
    the run's timer, the run's statistics) of the case ``name`` with ``params``."""
    from fecontact.cli.cases import load_case
    from fecontact.time import IntegratorOptions, PhaseTimer, initial_state, make_stepper

    sim = load_case(name).build(**params)
    opts = IntegratorOptions(**{**vars(sim.options), "localize": localize})
    stepper = make_stepper(sim.model, opts, None, 1 << 20)
    sim.model.contacts.detect_within(opts.detection_margin * sim.model.length)
    timer = PhaseTimer()
    st = initial_state(sim.model, sim.q0, sim.v0, opts.tol_gap)
    while True:
        end = stepper.step(copy.deepcopy(st), sim.dt, timer)
        if np.any(end.impulse > 0.0):
            return stepper, st, timer, sim.dt
        st = end


def step_cost(name: str, params: dict, repeats: int) -> dict:
    """CPU ms (medians of ``repeats``, "auto" and off alternated) of the first impact step,
    and of it with the step after it, localized and not, from the same state."""
    runs = {loc: before_impact(name, params, loc) for loc in ("auto", False)}
    assert np.array_equal(runs["auto"][1].q, runs[False][1].q), name  # the same state
    one, two = {loc: [] for loc in runs}, {loc: [] for loc in runs}
    for _ in range(repeats):
        for loc, (stepper, st, timer, h) in runs.items():
            start = copy.deepcopy(st)
            clock = time.process_time()
            end = stepper.step(start, h, timer)
            mid = time.process_time()
            stepper.step(end, h, timer)
            one[loc].append(mid - clock)
            two[loc].append(time.process_time() - clock)
    on, off = statistics.median(one["auto"]), statistics.median(one[False])
    stats = runs["auto"][0].stats.localization
    return {
        "case": name,
        "params": json.dumps(params),
        "on_ms": 1e3 * on,
        "off_ms": 1e3 * off,
        "ratio": on / off,
        "pair_ratio": statistics.median(two["auto"]) / statistics.median(two[False]),
        "refinements": stats.smooth_steps / max(stats.impacts, 1),
    }


def cost_table(args) -> None:
    """The ``--step-cost`` table (module docstring)."""
    repeats = 5 if args.quick else 41
    cases = COST_CASES[1:2] if args.quick else COST_CASES
    table = [step_cost(name, params, repeats) for name, params in cases]
    stem = "solid_localization_step_cost" + ("_quick" if args.quick else "")
    write_csv(Path(args.out) / f"{stem}.csv", table, COST_COLUMNS)
    text = "\n".join(
        [
            "# The localized impact step against the end-of-step one, from the same state",
            "",
            f"CPU ms of the first impact step, medians of {repeats} alternated repeats; "
            "pair_ratio: the impact step with the step after it; refinements: refining "
            "smooth steps per located impact.",
            "",
            markdown_table(table, COST_COLUMNS),
        ]
    )
    print(text)
    write_markdown(Path(args.out) / f"{stem}.md", text)


def print_rows(rows: list[dict]) -> None:
    """One line for each run of ``rows`` (progress)."""
    for e in rows:
        print(
            f"{e['case']:13s} {e['row']:22s} {e['run']:7s} {e.get('status')!s:9s} "
            f"{e.get('time', math.nan):6.2f} s created {e.get('created_rel', math.nan):.3g} "
            f"err {e['error']:.3g} pen {e.get('max_penetration', math.nan):.2g} "
            f"mortar {e.get('mortar_depth', math.nan):.3g} sub {e.get('subdivided')} "
            f"{e.get('fallbacks', '')}",
            flush=True,
        )


def main() -> None:
    from fecontact.cli.cases import load_case
    from fecontact.params import declared_parameters

    p = parser(__doc__.splitlines()[0])
    p.add_argument("--case", action="append", help="only this case (repeatable)")
    p.add_argument("--row", action="append", help="only the rows of this label (repeatable)")
    p.add_argument("--timeout", type=float, default=600.0, help="per run, s (default 600)")
    p.add_argument("--worker", help=cm.argparse_hidden())
    p.add_argument("--step-cost", action="store_true", help="the impact step's cost alone")
    args = p.parse_args()
    if args.step_cost:
        cost_table(args)
        return
    if args.worker:
        row, sub = json.loads(args.worker)
        print(json.dumps(run_one(cm.Row(**row), sub), default=float))
        return
    rows = rows_of(args.case or SOLID_CASES)
    if args.row:
        rows = [r for r in rows if r.label in args.row]
    if args.quick:
        rows = [r for r in rows if (r.case, r.label) in QUICK] or rows[:1]
    stem = "solid_localization" + ("_" + "_".join(args.case) if args.case else "")
    stem += "_quick" if args.quick else ""
    table = []
    for row in rows:
        default = {k: p.default for k, p in declared_parameters(load_case(row.case).build).items()}
        table += measure(row, approach_speed(row, default), args.timeout)
        write_csv(Path(args.out) / f"{stem}.csv", table, COLUMNS)
        print_rows(table[-len(VARIANTS) :])
    text = "\n".join(
        [
            "# Impact localization on the solid cases",
            "",
            "Each row off, localized in whole steps and with 8 sub-steps; error: "
            f"the first body's centre-of-mass velocity against the row at h/{FINE} (localized, "
            "sub-steps), largest over the run's steps, over the approach speed; time: CPU s of "
            "the run.",
            "",
            markdown_table(table, COLUMNS[:-1]),
        ]
    )
    print(text)
    write_markdown(Path(args.out) / f"{stem}.md", text)


if __name__ == "__main__":
    main()
