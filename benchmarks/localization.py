"""Impact localization: accuracy, robustness and cost of impacts applied at their own instant.

Every run is made twice on the same model, ``localize`` on and off (the NSGA step with the
impact at the end of its step), side by side in one process. Tables:

1. exact cases at h = 1e-3 over 3 s: the bouncing ball (h₀ = 1 m, m = 1 kg, e = 0.8; max
   |gap − exact piecewise parabola| over the history rows) and the rigid pendulum (a uniform
   bar of 1.5 m, e = 0.5: a point mass on a 1 m rod; max |θ − θ_exact|, Jacobi's sn); the
   smallest gap of any row (zero penetration: ≥ −1e-12 m);
2. work–precision on the ball: error and time loop (median of repeats) over a sweep of h for
   NSGA with and without localization and for Moreau–Jean; the time to reach 1e-6 m, read
   from the sweep or, for the first-order schemes that do not reach it, extrapolated along
   their measured order (marked so);
3. accumulation: the ball bouncing to rest (e = 0.8, 6 s, h = 1e-3) and the rocking block:
   steps, located impacts, fallbacks by reason, the final gap and speed;
4. the founding case (flexible pendulum, h = 1e-3, 1.5 s): max tip distance from its own run
   at h/8 with the same setting;
5. solids: the excess of the total energy over its initial value in the first contact step,
   in % of the kinetic energy just before it, for ``disk_drop`` and ``ball_drop`` with the
   drop height moved by fractions of a step;
6. cost: the time per step of steps without an impact (the ball before its first impact),
   the extra time of a located impact in units of a step, and the default runs of
   ``two_disks`` and of the founding case (their "auto" leaves localization off: the rows
   with it on say what it would cost).

    python benchmarks/localization.py            # about 2 minutes
    python benchmarks/localization.py --quick    # seconds
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import copy
import math
import statistics
import time

import numpy as np

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact.time import IntegratorOptions, StepStats, simulate

TARGET = 1e-6  # m: the ball's error to reach


def options(sim, **kw):
    return common.with_options(sim, **kw)


def ball(t_end=3.0, e=0.8):
    return common.case("bouncing_ball").build(height=1.0, mass=1.0, restitution=e)


def pendulum():
    return common.case("rigid_pendulum").build(length=1.5, mass=1.0, restitution=0.5)


def counted(sim, h, t_end, **kw):
    """Step ``sim`` (options ``kw``) and return (trace-like rows, statistics, wall)."""
    stats = StepStats()
    opts = IntegratorOptions(**{**vars(sim.options), **kw})
    clock = time.perf_counter()
    rows = {"t": [], "min_gap": [], "v": [], **{p: [] for p in sim.probes}}
    for st in simulate(sim.model, h, t_end, opts, q0=sim.q0, v0=sim.v0, stats=stats):
        rows["t"].append(st.t)
        rows["min_gap"].append(float(np.min(st.gaps, initial=np.inf)))
        rows["v"].append(float(np.max(np.abs(st.v))))
        for name, probe in sim.probes.items():
            rows[name].append(probe.fn(sim.model, st))
    wall = time.perf_counter() - clock
    return {k: np.array(v) for k, v in rows.items()}, stats.localization, wall


def exact_cases(quick):
    t_end = 1.0 if quick else 3.0
    out = []
    for name, sim, error in (
        ("bouncing ball", ball(), lambda r: np.abs(r["gap"] - common.ball_exact_gap(r["t"]))),
        (
            "rigid pendulum",
            pendulum(),
            lambda r: np.abs(r["theta"] - common.pendulum_exact(r["t"], 0.5, 1.5)[0]),
        ),
    ):
        for loc in (False, True):
            r, stats, wall = counted(sim, 1e-3, t_end, localize=loc)
            out.append(
                {
                    "case": name,
                    "localize": loc,
                    "max error": float(error(r).max()),
                    "min gap over the rows (m)": float(r["min_gap"].min()),
                    "located impacts": stats.impacts,
                    "refining smooth steps": stats.smooth_steps,
                    "wall (s)": wall,
                }
            )
    return out


def work_precision(quick, repeats):
    steps = [2e-3, 1e-3] if quick else [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]
    t_end = 1.0 if quick else 2.7
    methods = {
        "nsga, localized": {"localize": True},
        "nsga": {"localize": False},
        "moreau": {"integrator": "moreau"},  # (localize is an nsga option)
    }
    rows = []
    for h in steps:
        runs = {m: [] for m in methods}
        for _ in range(repeats):
            for m, kw in methods.items():
                sim = options(ball().replace(dt=h, t_end=t_end), **kw)
                runs[m].append(common.timed_run(sim, repeats=1))
        for m in methods:
            first = runs[m][0]
            hist = first["history"]
            err = float(np.abs(hist["gap"] - common.ball_exact_gap(hist["t"])).max())
            rows.append(
                {
                    "method": m,
                    "h": h,
                    "steps": first["steps"],
                    "time (s)": statistics.median(x["compute"] for x in runs[m]),
                    "error (m)": err,
                    "max penetration (m)": first["summary"]["max_penetration"],
                }
            )
    return rows


def time_to_target(rows):
    """Per method: the time of the cheapest run within TARGET, or, where none is, the time
    extrapolated along the measured order to the step that would reach it."""
    out = []
    for m in dict.fromkeys(r["method"] for r in rows):
        runs = [r for r in rows if r["method"] == m]
        ok = [r for r in runs if r["error (m)"] <= TARGET]
        if ok:
            best = min(ok, key=lambda r: r["time (s)"])
            out.append(
                {"method": m, "h": best["h"], "time (s)": best["time (s)"], "how": "measured"}
            )
            continue
        h = np.array([r["h"] for r in runs])
        err = np.array([r["error (m)"] for r in runs])
        order = common.observed_order(h, err)
        finest = runs[-1]
        if not order > 0.5:  # (no convergence to extrapolate along)
            out.append({"method": m, "h": math.nan, "time (s)": math.nan, "how": "not reached"})
            continue
        h_need = finest["h"] * (TARGET / finest["error (m)"]) ** (1.0 / order)
        time_need = finest["time (s)"] * finest["h"] / h_need
        out.append(
            {
                "method": m,
                "h": h_need,
                "time (s)": time_need,
                "how": f"extrapolated (order {order:.2f})",
            }
        )
    return out


def accumulation(quick):
    out = []
    t_end = 2.0 if quick else 6.0
    for name, sim, h, t in (
        ("ball to rest", ball(e=0.8), 1e-3, t_end),
        ("rocking block", common.case("rocking_block").build(), None, None),
    ):
        h = h or sim.dt
        t = t or sim.t_end
        for loc in (False, True):
            r, stats, wall = counted(sim, h, t, localize=loc)
            out.append(
                {
                    "case": name,
                    "localize": loc,
                    "steps": len(r["t"]) - 1,
                    "located impacts": stats.impacts,
                    "refining smooth steps": stats.smooth_steps,
                    "fallbacks": ", ".join(f"{k} {v}" for k, v in stats.fallbacks.items() if v)
                    or "none",
                    "final min gap (m)": float(r["min_gap"][-1]),
                    "final max speed": float(r["v"][-1]),
                    "wall (s)": wall,
                }
            )
    return out


def founding(quick):
    t_end = 0.35 if quick else 1.5
    sim = common.case("flexible_pendulum").build()
    out = []
    for loc in (False, True):
        fine, _, _ = counted(sim, 1e-3 / 8, t_end, localize=loc)
        r, stats, wall = counted(sim, 1e-3, t_end, localize=loc)
        f = {k: v[::8] for k, v in fine.items()}
        d = np.hypot(r["tip_x"] - f["tip_x"], r["tip_y"] - f["tip_y"])
        out.append(
            {
                "localize": loc,
                "max tip distance from h/8 (mm)": 1e3 * float(d.max()),
                "at 1.5 s (mm)": 1e3 * float(d[-1]),
                "located impacts": stats.impacts,
                "refining smooth steps": stats.smooth_steps,
                "min gap (m)": float(r["min_gap"].min()),
            }
        )
    return out


def solids(quick):
    fractions = (0.0, 0.5) if quick else (0.0, 0.25, 0.5, 0.75)
    out = []
    for name, ref in (("disk_drop", 2 if quick else 3), ("ball_drop", 1)):
        dt = common.case(name).build(refinements=ref).dt
        for frac in fractions:
            row = {"case": f"{name} (refinements {ref})", "fraction of a step": frac}
            for loc in (False, True):
                sim = common.case(name).build(refinements=ref, drop_height=0.002 + frac * dt)
                r = common.trace(options(sim, localize=loc), t_end=0.004 if quick else None)
                first = np.flatnonzero(r["active"])[0]
                k0 = r["kinetic"][first - 1]
                key = "on" if loc else "off"
                row[f"impact step excess, {key} (%)"] = (
                    100 * (r["total"][first] - r["total"][0]) / k0
                )
                row[f"max excess, {key} (%)"] = 100 * (r["total"].max() - r["total"][0]) / k0
                row[f"min gap, {key} (m)"] = float(r["min_gap"].min())
            out.append(row)
    return out


def step_cost(sim, before: int, localize, repeats: int) -> tuple[float, float]:
    """CPU time (s, median of ``repeats``; CPU time is what the load of a shared machine
    disturbs least) of the step that follows step ``before`` of ``sim`` (the impact step
    when it holds one), and of the step before it."""
    from fecontact.time import PhaseTimer, initial_state, make_stepper

    opts = IntegratorOptions(**{**vars(sim.options), "localize": localize})
    stepper = make_stepper(sim.model, opts, StepStats(), before + 1)
    sim.model.contacts.detect_within(opts.detection_margin * sim.model.length)
    timer = PhaseTimer()
    states = [initial_state(sim.model, sim.q0, sim.v0, opts.tol_gap)]
    for _ in range(before):
        states.append(stepper.step(copy.deepcopy(states[-1]), sim.dt, timer))
    out = []
    for start in (states[-1], states[-2]):
        walls = []
        for _ in range(repeats):
            st = copy.deepcopy(start)
            clock = time.process_time()
            stepper.step(st, sim.dt, timer)
            walls.append(time.process_time() - clock)
        out.append(statistics.median(walls))
    return out[0], out[1]


def cost(quick, repeats):
    """A step without impact and a step with one, localize on against off (the same step
    from the same state), and the default runs' time loops."""
    out = []
    n = 30 if quick else 300
    # the step before the first impact (ball: t_1 = 0.4515 s; pendulum: 0.5917 s)
    for name, sim, before in (("ball", ball(), 451), ("pendulum", pendulum(), 591)):
        on, on_free = step_cost(sim, before, True, n)
        off, off_free = step_cost(sim, before, False, n)
        out.append(
            {"what": f"{name}: a step without impact, on / off", "ratio": on_free / off_free}
        )
        out.append({"what": f"{name}: the impact step, on / off", "ratio": on / off})
        out.append({"what": f"{name}: the impact step on / a step without", "ratio": on / off_free})
    for name in ("two_disks", "flexible_pendulum"):
        sim = common.case(name).build()
        if quick:
            sim = sim.replace(t_end=min(sim.t_end, 0.35 if name == "flexible_pendulum" else 0.002))
        walls = {"auto": [], True: []}
        for _ in range(repeats):
            for loc in walls:
                walls[loc].append(common.timed_run(options(sim, localize=loc), 1)["compute"])
        auto, on = statistics.median(walls["auto"]), statistics.median(walls[True])
        out.append({"what": f"{name}: localize on / default (auto: off)", "ratio": on / auto})
    return out


def main(argv=None):
    args = common.parser(__doc__.splitlines()[0]).parse_args(argv)
    out = common.Path(args.out)
    repeats = 1 if args.quick else 3
    note = common.machine_note()
    t0 = time.perf_counter()
    sections = [
        (
            "Exact cases at h = 1e-3 (max error over the history rows: m, rad).",
            exact_cases(args.quick),
        ),
    ]
    wp = work_precision(args.quick, repeats)
    sections += [
        ("Work–precision on the bouncing ball (time loop, median).", wp),
        (f"Time to reach {TARGET:g} m on the ball.", time_to_target(wp)),
        ("Accumulation and resting contact.", accumulation(args.quick)),
        ("Founding case at h = 1e-3 against its own h/8 run.", founding(args.quick)),
        ("Solids: energy excess of the first contact step.", solids(args.quick)),
        ("Cost (time ratios measured side by side, interleaved).", cost(args.quick, repeats)),
    ]
    text = common.report("Impact localization", *sections)
    text = text.replace("\n", f"\n\n{note}; {time.perf_counter() - t0:.0f} s.\n", 1)
    stem = out / ("localization_quick" if args.quick else "localization")
    rows = [dict(section=caption, **row) for caption, table in sections for row in table]
    columns = list(dict.fromkeys(k for row in rows for k in row))
    common.publish(stem, rows, columns, text)
    print(text)


if __name__ == "__main__":
    main()
