"""The smooth contact force on the rigid cases: ``smooth_contact="off"`` (the decoupled step)
against ``"on"`` (persistent contacts carry a force in the smooth step), each against an h/8
run of the same setting.

Rows: every bundled case with rigid bodies and contacts at its defaults and at the variants
that stress a lasting contact (Newton's coefficient 1, friction, a steeper tilt, a slower
knock), and the rigid runs of the localization acceptance: the ball dropped from 1 m at
e_N = 0.8 to 3 s (the exact parabolas) and to rest over 6 s, the 1.5 m bar at e_N = 0.5 to
3 s (the exact angle). Per row and setting:

- ``created``/``scale``: the ledger's creation over its scale (1e-3: the ledger's warning);
- ``err_end``, ``err_max``: the largest difference of the dofs from the h/8 run's at the end
  and over the history rows (positions, m or rad; ``verr_end``, ``verr_max``: velocities);
- ``exact``: the largest error of the height or the angle from the exact solution (the two
  acceptance rows);
- ``newton``: Newton iterations of the step (smooth, position and velocity); ``halvings``,
  ``fallbacks`` (localization fallbacks, shortened follow-ups, line-search cuts), the status;
- ``cpu``: CPU seconds of the run at h (``time.process_time``, output included).

    python benchmarks/rigid_smooth_contact.py            # every row (about 20 min on one core)
    python benchmarks/rigid_smooth_contact.py --quick    # one short row (seconds)
    python benchmarks/rigid_smooth_contact.py --row "rocking_block e_N=1" --setting on
    python benchmarks/rigid_smooth_contact.py --curvature   # the decoupled step's gain

``--curvature``: the rocking block pivoting on its corner before it lands (t < 0.077 s,
decoupled step), the energy each step gains against −½h²cκ/D: with G the corner's gap
gradient, D = G M⁻¹Gᵀ, κ = vᵀ∇²g v (the corner's normal acceleration from the rotation
alone) and c = G M⁻¹f + κ (the normal acceleration of the free motion), the correction lifts
the body back by the gap ½h²c the free step lost, along M⁻¹Gᵀ, against gravity:
(G M⁻¹f) ½h²c/D; the jump takes the normal velocity hc: ½h²c²/D. Their difference is the
curvature's share, which no force works against.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import (
    ball_exact_gap,
    case,
    markdown_table,
    parser,
    pendulum_exact,
    read_csv,
    with_options,
    write_csv,
    write_markdown,
)
from scipy import sparse

FINE = 8  # the reference run's step divisor
SETTINGS = ("off", "on")
# label: (case, parameters, t_end or None for the case's own[, the reference's step divisor])
ROWS = {
    "rocking_block": ("rocking_block", {}, None),
    "rocking_block e_N=1": ("rocking_block", {"restitution": 1.0}, None),
    "rocking_block mu=0.5": ("rocking_block", {"friction": 0.5}, None),
    "rocking_block angle=0.4": ("rocking_block", {"angle": 0.4}, None),
    # (the reference is h/2: at 5e-4 s and below both settings failed at 0.084 s before the
    # convex pairs took a face normal at a touch to round-off; see docs/explanation/rotations.md)
    "box_stack": ("box_stack", {}, None, 2),
    "box_stack knock=0.1": ("box_stack", {"knock": 0.1}, None, 2),
    "tumbling_box": ("tumbling_box", {}, None),
    "tumbling_box e_N=0.5": ("tumbling_box", {"restitution": 0.5}, None),
    "kane_chain": ("kane_chain", {}, None),
    "sliding_block": ("sliding_block", {}, None),
    "rolling_disk": ("rolling_disk", {}, None),
    "ball 1 m e_N=0.8 (exact)": ("bouncing_ball", {"height": 1.0, "restitution": 0.8}, 3.0),
    "ball to rest e_N=0.8": ("bouncing_ball", {"height": 1.0, "restitution": 0.8}, 6.0),
    "bar 1.5 m e_N=0.5 (exact)": ("rigid_pendulum", {"length": 1.5, "restitution": 0.5}, 3.0),
}
QUICK = {"rocking_block short": ("rocking_block", {}, 0.1)}
COLUMNS = [
    "row",
    "setting",
    "status",
    "steps",
    "created_rel",
    "created",
    "err_end",
    "err_max",
    "verr_end",
    "verr_max",
    "exact",
    "newton",
    "halvings",
    "fallbacks",
    "max_penetration",
    "cpu",
    "cpu_fine",
    "fine",
]
SHOWN = [c for c in COLUMNS if c not in ("created", "cpu_fine")]


def one_run(name: str, params: dict, t_end, setting: str, divisor: int, tmp: Path) -> dict:
    """Run case ``name`` with ``params`` to ``t_end`` at its step over ``divisor``: the
    summary's counts, the CPU time and the state (t, q, v) of every history row."""
    from fecontact import Probe, SolverError, run
    from fecontact.io.output import read_json

    sim = with_options(case(name).build(**params), smooth_contact=setting)
    sim = sim.replace(dt=sim.dt / divisor, t_end=t_end or sim.t_end)
    rows = []

    def keep(model, st):
        rows.append((st.t, st.q.copy(), st.v.copy()))
        return 0.0

    sim = sim.replace(probes={**sim.probes, "kept": Probe(keep, "-")})
    clock = time.process_time()
    try:
        summary = run(sim, tmp, frames=False, checkpoint_every=0)
        status = "completed"
    except SolverError:
        summary, status = read_json(Path(tmp) / "summary.json"), "failed"
    cpu = time.process_time() - clock
    return {"summary": summary, "status": status, "cpu": cpu, "rows": rows, "dt": sim.dt}


def fallbacks(summary: dict) -> int:
    """The fallbacks summary.json counts: localization fallbacks, shortened velocity
    follow-ups, the smooth Newton's line-search cuts."""
    loc = sum((summary.get("localization_fallbacks") or {}).values())
    short = (summary.get("velocity_follow_ups") or {}).get("shortened", 0)
    cuts = (summary.get("smooth_newton") or {}).get("line_search_cuts", 0)
    return int(loc + short + cuts)


def compare(coarse: dict, fine: dict) -> dict:
    """Differences of the coarse run's history rows from the fine run's at the same times."""

    def on_grid(t):  # the number of the coarse step that ends at t, or None
        n = t / coarse["dt"]
        return round(n) if abs(n - round(n)) < 1e-6 else None

    by_time = {on_grid(t): (q, v) for t, q, v in fine["rows"] if on_grid(t) is not None}
    dq, dv = [], []
    for t, q, v in coarse["rows"]:
        ref = by_time.get(on_grid(t))
        if ref is not None:
            dq.append(float(np.max(np.abs(q - ref[0]))))
            dv.append(float(np.max(np.abs(v - ref[1]))))
    if not dq:
        return {}
    return {"err_end": dq[-1], "err_max": max(dq), "verr_end": dv[-1], "verr_max": max(dv)}


def exact_error(name: str, params: dict, coarse: dict) -> float:
    """The largest error of the ball's height or the bar's angle from the exact solution."""
    sim = case(name).build(**params)
    t = np.array([r[0] for r in coarse["rows"]])
    q = np.array([r[1] for r in coarse["rows"]])
    if name == "bouncing_ball":
        gap = np.array(
            [sim.probes["gap"].fn(sim.model, _State(r[1], r[2])) for r in coarse["rows"]]
        )
        exact = ball_exact_gap(t, params["height"], params["restitution"])
        return float(np.max(np.abs(gap - exact)))
    if name == "rigid_pendulum":
        theta = np.pi / 2 + q[:, 2]
        exact, _ = pendulum_exact(t, params["restitution"], params["length"])
        return float(np.max(np.abs(theta - exact)))
    return math.nan


class _State:
    """The (q, v) a probe reads."""

    def __init__(self, q, v):
        self.q, self.v = q, v


def measure(label: str, setting: str, rows: dict) -> dict:
    """One table row: ``label`` of ``rows`` with ``smooth_contact=setting``, at h and h/8."""
    name, params, t_end, *divisor = rows[label]
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        coarse = one_run(name, params, t_end, setting, 1, Path(a))
        fine = one_run(name, params, t_end, setting, (divisor or [FINE])[0], Path(b))
    s = coarse["summary"]
    ledger = s.get("energy_ledger") or {}
    out = {
        "row": label,
        "setting": setting,
        "status": coarse["status"] + ("" if fine["status"] == "completed" else " (h/8 failed)"),
        "steps": s.get("steps"),
        "created": ledger.get("created", math.nan),
        "created_rel": ledger.get("created", math.nan) / max(ledger.get("scale", 1.0), 1e-300),
        "exact": exact_error(name, params, coarse),
        "newton": s.get("newton_iterations_total"),
        "halvings": s.get("step_halvings", 0),
        "fallbacks": fallbacks(s),
        "max_penetration": s.get("max_penetration"),
        "cpu": coarse["cpu"],
        "cpu_fine": fine["cpu"],
        "fine": (divisor or [FINE])[0],
    }
    out.update(compare(coarse, fine))
    return out


def dense(A) -> np.ndarray:
    return A.toarray() if sparse.issparse(A) else np.asarray(A)


def curvature_share(t_end: float = 0.077) -> tuple[float, float]:
    """(the energy the decoupled rocking block gains over its steps to ``t_end``, the sum of
    −½h²cκ/D over them) in J (module docstring)."""
    from fecontact.time import simulate
    from fecontact.time.constraints import Constraints

    sim = case("rocking_block").build()
    model, h = sim.model, sim.dt
    M = dense(model.M)
    a_free = np.linalg.solve(M, model.external(0.0))
    rows = Constraints(model, np.array([0]))

    def G_of(q):
        G = rows.jacobian(q)[1]
        return dense(G)[0]

    def energy(st):
        return model.kinetic_energy(st.v) + model.potential_energy(st.q)

    opts = with_options(sim, smooth_contact="off").options
    states = list(simulate(model, h, t_end, opts, q0=sim.q0, v0=sim.v0))
    gained = predicted = 0.0
    # (from the second step: the first takes the release at t = 0)
    for a, b in zip(states[1:-1], states[2:], strict=True):
        G, eps = G_of(a.q), 1e-7
        kappa = (G_of(a.q + eps * a.v) - G_of(a.q - eps * a.v)) @ a.v / (2 * eps)
        c = G @ a_free + kappa
        predicted -= 0.5 * h * h * c * kappa / (G @ np.linalg.solve(M, G))
        gained += energy(b) - energy(a)
    return gained, predicted


def run_worker(label: str, setting: str, quick: bool) -> dict:
    """``measure`` in its own process (a clean CPU clock, no state shared between rows)."""
    payload = json.dumps({"label": label, "setting": setting, "quick": quick})
    done = subprocess.run(
        [sys.executable, str(Path(__file__).resolve()), "--worker", payload],
        capture_output=True,
        text=True,
        cwd=Path(__file__).resolve().parent,
    )
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("{")]
    if done.returncode or not lines:
        tail = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return {"row": label, "setting": setting, "status": f"crash: {tail[:200]}"}
    return json.loads(lines[-1])


def main() -> None:
    p = parser(__doc__.splitlines()[0], from_csv=True)
    p.add_argument("--row", action="append", help="only this row (repeatable)")
    p.add_argument("--setting", action="append", choices=SETTINGS, help="only this setting")
    p.add_argument("--worker", help="(internal) one row in this process")
    p.add_argument("--curvature", action="store_true", help="the decoupled step's gain only")
    args = p.parse_args()
    if args.curvature:
        gained, predicted = curvature_share()
        print(f"rocking block to 0.077 s: gained {gained:.4g} J, -h^2 c kappa/2D {predicted:.4g} J")
        return
    if args.worker:
        w = json.loads(args.worker)
        print(json.dumps(measure(w["label"], w["setting"], QUICK if w["quick"] else ROWS)))
        return
    rows = QUICK if args.quick else ROWS
    stem = "rigid_smooth_contact" + ("_quick" if args.quick else "")
    csv_path = Path(args.out) / f"{stem}.csv"
    if args.from_csv:  # the table of an earlier run (or of runs made apart, joined)
        table = read_csv(args.from_csv)
        write_csv(csv_path, table, COLUMNS)
    else:
        table = []
        for label in args.row or rows:
            for setting in args.setting or SETTINGS:
                table.append(run_worker(label, setting, args.quick))
                write_csv(csv_path, table, COLUMNS)  # (a long run stopped keeps its rows)
                print(json.dumps(table[-1]), flush=True)
    text = "\n".join(
        [
            "# The smooth contact force on the rigid cases" + (" (quick)" if args.quick else ""),
            "",
            f"Each row at the case's step h with `smooth_contact` off and on; errors against an "
            f"h/{FINE} run of the same setting (h/`fine` where given; dofs, m or rad; "
            "velocities, m/s or rad/s); "
            "`exact`: against the exact solution; `cpu`: CPU s of the run at h (one run "
            "each; the machine was shared with other runs).",
            "",
            markdown_table(table, SHOWN),
        ]
    )
    write_markdown(Path(args.out) / f"{stem}.md", text)
    print(text)


if __name__ == "__main__":
    main()
