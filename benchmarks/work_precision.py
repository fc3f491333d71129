"""Work–precision: run time against error for NSGA and the baselines, side by side.

For each case the step h is swept and every run is repeated with the three integrators of
``IntegratorOptions.integrator`` on the same model, interleaved (h by h, repeat by repeat) so
that the load of the machine affects them alike:

- ``nsga``: nonsmooth generalized-α with exact contact (ρ∞ = 0.5, the default);
- ``moreau``: Moreau–Jean, θ = ½, impact law at velocity level only;
- ``penalty``: penalty contact (automatic stiffness) in the smooth generalized-α step.

Time is the time loop of ``fecontact.run`` without frames or checkpoints, minus its output
phase (history rows): ``wall_time_s − phase_times_s["output"]``, the median of repeated runs.
Errors:

- bouncing ball (e = 0.8, h₀ = 1 m, 2.7 s, five impacts): max |gap − exact gap| (m);
- rigid pendulum (uniform bar, e = 0.5, 2.5 s): max |θ − θ_exact| (rad), Jacobi sn;
- impacting bar (L = 1, c = 1, v₀ = 0.1, 2.5 s): relative error of the rebound velocity; the
  case ties the step to the mesh (h = Δx/2c), so the sweep refines both (n = L/(2ch));
- flexible pendulum (e = 0, 1.5 s): max tip position error (m) against NSGA with a much
  smaller step.

Energy error: |ΔE(t_end) − ΔE_exact| relative to the initial energy scale (ball, pendulum:
m g h₀, m g L/2; bar: E₀; flexible pendulum: against the reference, relative to its peak
kinetic energy). Max penetration: the summary's ``max_penetration`` (m).

    python benchmarks/work_precision.py [--quick]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import math
import statistics
import time

import numpy as np

try:
    from . import _common as common
except ImportError:
    import _common as common

METHODS = ("nsga", "moreau", "penalty")
COLUMNS = [
    "case",
    "method",
    "h",
    "steps",
    "time_s",
    "time_per_step_us",
    "output_s",
    "error",
    "error_unit",
    "max_penetration_m",
    "energy_error",
    "extra",
    "status",
    "message",
    "repeats",
]


class Case:
    """A work–precision case: ``build(h)`` gives the simulation, ``measure(history, h)``
    its (error, energy error, extra text)."""

    name = ""
    unit = ""
    t_end = math.inf

    def __init__(self, quick: bool):
        self.quick = quick
        if quick:  # through the first impacts only
            self.t_end = min(self.t_end, 1.0)


class Ball(Case):
    name, unit = "bouncing ball", "m"
    e, h0, t_end = 0.8, 1.0, 2.7

    def steps(self):
        if self.quick:
            return [2e-3, 1e-3]
        return [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5]

    def build(self, h):
        sim = common.case("bouncing_ball").build(height=self.h0, restitution=self.e)
        return sim.replace(dt=h, t_end=self.t_end)

    def measure(self, hist, h):
        t = hist["t"]
        err = np.abs(hist["gap"] - common.ball_exact_gap(t, self.h0, self.e)).max()
        k = np.sum(common.ball_impact_times(50, self.h0, self.e) <= t[-1])
        scale = common.G * self.h0  # m g h₀ with m = 1 kg
        d_exact = scale * (self.e ** (2 * k) - 1.0)
        energy = abs(hist["total_energy"][-1] - hist["total_energy"][0] - d_exact) / scale
        return err, energy, ""


class Pendulum(Case):
    name, unit = "rigid pendulum", "rad"
    e, t_end = 0.5, 2.5

    def steps(self):
        if self.quick:
            return [2e-3, 1e-3]
        return [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4]

    def build(self, h):
        sim = common.case("rigid_pendulum").build(restitution=self.e)
        return sim.replace(dt=h, t_end=self.t_end)

    def measure(self, hist, h):
        t = hist["t"]
        exact, t_imp = common.pendulum_exact(t, e=self.e)
        err = np.abs(hist["theta"] - exact).max()
        k = np.sum(t_imp <= t[-1])
        scale = 0.5 * common.G  # m g L/2 with m = 1 kg, L = 1 m
        d_exact = scale * (self.e ** (2 * k) - 1.0)
        energy = abs(hist["total_energy"][-1] - hist["total_energy"][0] - d_exact) / scale
        return err, energy, ""


class Bar(Case):
    name, unit = "impacting bar", "-"
    t_end = 2.5

    def steps(self):
        ns = [25, 50] if self.quick else [25, 50, 100, 200, 400]
        return [0.5 / n for n in ns]  # h = Δx/2c with L = c = 1

    def build(self, h):
        n = round(0.5 / h)
        sim = common.case("impacting_bar").build(n_elements=n)
        return sim.replace(t_end=self.t_end)

    def measure(self, hist, h):
        on = np.flatnonzero(hist["n_active"] > 0)
        duration = hist["t"][on[-1]] if on.size else math.nan
        err = abs(hist["v_mean"][-1] - 0.1) / 0.1
        energy = abs(hist["total_energy"][-1] / hist["total_energy"][0] - 1.0)
        return err, energy, f"n = {round(0.5 / h)}, contact {duration:.4g} (exact 2)"


class Flexible(Case):
    name, unit = "flexible pendulum", "m"

    def __init__(self, quick):
        super().__init__(quick)
        self.t_end = 0.35 if quick else 1.5
        self.h_ref = 1e-3 / (4 if quick else 64)
        self.ref = None

    def steps(self):
        return [2e-3, 1e-3] if self.quick else [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]

    def build(self, h):
        return common.case("flexible_pendulum").build().replace(dt=h, t_end=self.t_end)

    def reference(self):
        if self.ref is None:
            t0 = time.perf_counter()
            self.ref = common.trace(self.build(self.h_ref))
            print(
                f"  flexible pendulum reference: h = {self.h_ref:.3g} s, "
                f"{time.perf_counter() - t0:.0f} s, {self.ref['status']}",
                flush=True,
            )
        return self.ref

    def measure(self, hist, h):
        ref = self.reference()
        idx = np.rint(hist["t"] / self.h_ref).astype(int)
        ok = idx < len(ref["t"])
        err = np.hypot(
            hist["tip_x"][ok] - ref["tip_x"][idx[ok]], hist["tip_y"][ok] - ref["tip_y"][idx[ok]]
        ).max()
        energy = abs(hist["total_energy"][-1] - ref["total"][-1]) / ref["kinetic"].max()
        return err, energy, ""


def sweep(cases, repeats):
    rows = []
    for c in cases:
        print(f"{c.name}:", flush=True)
        if isinstance(c, Flexible):
            c.reference()
        for h in c.steps():
            runs = {m: [] for m in METHODS}
            for _ in range(repeats):
                for m in METHODS:
                    if runs[m] and runs[m][0]["status"] != "completed":
                        continue  # a failed run is not repeated
                    sim = common.with_options(c.build(h), integrator=m)
                    runs[m].append(common.timed_run(sim, repeats=1))
            for m in METHODS:
                r = runs[m][0]
                hist = r["history"]
                done = r["status"] == "completed"
                err, energy, extra = c.measure(hist, h) if done else (math.nan, math.nan, "")
                compute = statistics.median(x["compute"] for x in runs[m])
                row = {
                    "case": c.name,
                    "method": m,
                    "h": h,
                    "steps": r["steps"],
                    "time_s": compute,
                    "time_per_step_us": 1e6 * compute / max(r["steps"], 1),
                    "output_s": statistics.median(x["phases"].get("output", 0.0) for x in runs[m]),
                    "error": float(err),
                    "error_unit": c.unit,
                    "max_penetration_m": r["summary"]["max_penetration"],
                    "energy_error": float(energy),
                    "extra": extra,
                    "status": r["status"],
                    "message": r["message"][:200],
                    "repeats": len(runs[m]),
                }
                rows.append(row)
                print(
                    f"  h={h:.3g} {m:8s} {row['status']:9s} time {compute:8.3f} s "
                    f"({row['time_per_step_us']:7.1f} us/step) error {err:.3e} "
                    f"pen {row['max_penetration_m']:.2e} energy {energy:.2e} {extra}",
                    flush=True,
                )
    return rows


def time_to_reach(rows, case, method, level):
    """Time of the cheapest completed run of ``method`` whose error is ≤ level (nan if none)."""
    t = [
        r["time_s"]
        for r in rows
        if r["case"] == case and r["method"] == method and r["error"] <= level
    ]
    return min(t) if t else math.nan


def reach_table(rows):
    """For each error level reached by NSGA: the time each method needs and the ratio."""
    out = []
    for case in dict.fromkeys(r["case"] for r in rows):
        nsga = [r for r in rows if r["case"] == case and r["method"] == "nsga"]
        for level in sorted({r["error"] for r in nsga if np.isfinite(r["error"])}, reverse=True):
            t = {m: time_to_reach(rows, case, m, level) for m in METHODS}
            out.append(
                {
                    "case": case,
                    "error level": level,
                    "nsga (s)": t["nsga"],
                    "moreau (s)": t["moreau"],
                    "penalty (s)": t["penalty"],
                    "moreau / nsga": t["moreau"] / t["nsga"],
                    "penalty / nsga": t["penalty"] / t["nsga"],
                }
            )
    return out


def equal_step_ratios(rows):
    """Medians over h of (time, error, penetration) ratios of each baseline to NSGA."""
    out = []
    for case in dict.fromkeys(r["case"] for r in rows):
        for m in METHODS[1:]:
            ratios = {"time": [], "error": []}
            pen = []
            for r in rows:
                if r["case"] != case or r["method"] != m or r["status"] != "completed":
                    continue
                ref = next(
                    x
                    for x in rows
                    if x["case"] == case and x["method"] == "nsga" and x["h"] == r["h"]
                )
                if ref["status"] != "completed":
                    continue
                ratios["time"].append(r["time_s"] / ref["time_s"])
                ratios["error"].append(r["error"] / ref["error"])
                pen.append(r["max_penetration_m"] / r["h"])
            out.append(
                {
                    "case": case,
                    "method": m,
                    "time / nsga time (same h)": _median(ratios["time"]),
                    "error / nsga error (same h)": _median(ratios["error"]),
                    "penetration / h (m/s)": _median(pen),
                    "runs": len(pen),
                }
            )
    return out


def _median(x):
    return statistics.median(x) if x else math.nan


def summary_lines(rows, reach, ratios):
    """Plain sentences with the measured ratios."""
    lines = []
    for case in dict.fromkeys(r["case"] for r in rows):
        levels = [r for r in reach if r["case"] == case]
        if not levels:
            continue
        tight = levels[-1]
        parts = [f"NSGA reaches {tight['error level']:.3g} in {tight['nsga (s)']:.3g} s"]
        for m in METHODS[1:]:
            reached = [r for r in levels if np.isfinite(r[f"{m} (s)"])]
            if not reached:
                parts.append(f"{m} reaches none of the NSGA error levels")
                continue
            best = reached[-1]
            ratio = best[f"{m} / nsga"]
            own = min(
                (
                    r["error"]
                    for r in rows
                    if r["case"] == case and r["method"] == m and np.isfinite(r["error"])
                ),
                default=math.nan,
            )
            parts.append(
                f"the tightest NSGA level {m} reaches is {best['error level']:.3g}, in "
                f"{ratio:.2g}x the NSGA time (its smallest error in the sweep: {own:.3g})"
            )
        for r in ratios:
            if r["case"] == case:
                parts.append(
                    f"same h: {r['method']} takes {r['time / nsga time (same h)']:.2g}x the "
                    f"NSGA time with {r['error / nsga error (same h)']:.2g}x its error and "
                    f"penetrates {r['penetration / h (m/s)']:.2g}·h m"
                )
        failed = [
            f"{r['method']} at h = {r['h']:g}"
            for r in rows
            if r["case"] == case and r["status"] != "completed"
        ]
        if failed:
            parts.append("failed: " + ", ".join(failed))
        pens = [
            r["max_penetration_m"]
            for r in rows
            if r["case"] == case and r["method"] == "nsga" and r["status"] == "completed"
        ]
        parts.append(f"NSGA max penetration over the sweep: {max(pens, default=math.nan):.2g} m")
        lines.append(f"- {case}: " + "; ".join(parts) + ".")
    return lines


def plot(rows, path):
    import matplotlib.pyplot as plt

    cases = list(dict.fromkeys(r["case"] for r in rows))
    fig, axes = plt.subplots(2, len(cases), figsize=(4.0 * len(cases), 6.6), squeeze=False)
    styles = {"nsga": ("C0", "o"), "moreau": ("C1", "s"), "penalty": ("C2", "^")}
    for j, case in enumerate(cases):
        ax, axp = axes[0, j], axes[1, j]
        for m in METHODS:
            runs = [r for r in rows if r["case"] == case and r["method"] == m]
            sel = [r for r in runs if np.isfinite(r["error"])]
            color, marker = styles[m]
            if sel:
                t = [r["time_s"] for r in sel]
                e = [max(r["error"], 1e-16) for r in sel]
                ax.loglog(t, e, marker + "-", color=color, label=m)
                h = [r["h"] for r in sel]
                p = [max(r["max_penetration_m"], 1e-16) for r in sel]
                axp.loglog(h, p, marker + "-", color=color, label=m)
            failed = [r for r in runs if r["status"] != "completed"]
            if failed:
                h = [r["h"] for r in failed]
                p = [max(r["max_penetration_m"], 1e-16) for r in failed]
                axp.loglog(h, p, "x", color=color, ms=8, label=f"{m} (failed)")
        unit = next(r["error_unit"] for r in rows if r["case"] == case)
        ax.set_title(case, fontsize=9)
        ax.set_xlabel("time loop (s), median")
        ax.set_ylabel(f"error ({unit})")
        axp.set_xlabel("h (s)")
        axp.set_ylabel("max penetration (m); 0 drawn at 1e-16")
        for a in (ax, axp):
            common.tidy_log_axes(a)
            a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv=None):
    args = common.parser(__doc__.splitlines()[0], from_csv=True).parse_args(argv)
    out = common.Path(args.out)
    note = common.machine_note()
    t0 = time.perf_counter()
    repeats = 1 if args.quick else 3
    if args.from_csv:
        rows = common.read_csv(args.from_csv)
        repeats = max(r["repeats"] for r in rows)
        note = common.previous_note(args.from_csv)
    else:
        cases = [Ball(args.quick), Pendulum(args.quick), Bar(args.quick), Flexible(args.quick)]
        rows = sweep(cases, repeats)
    reach = reach_table(rows)
    ratios = equal_step_ratios(rows)
    cols = [
        "case",
        "method",
        "h",
        "steps",
        "time_s",
        "time_per_step_us",
        "error",
        "error_unit",
        "max_penetration_m",
        "energy_error",
        "status",
    ]
    main_md = common.markdown_table(rows, cols)
    reach_md = common.markdown_table(reach, list(reach[0]) if reach else [])
    ratio_md = common.markdown_table(ratios, list(ratios[0]) if ratios else [])
    lines = "\n".join(summary_lines(rows, reach, ratios))
    if not args.from_csv:
        note += (
            f"; {time.perf_counter() - t0:.0f} s; time = median of {repeats} run(s) of the time "
            "loop without output."
        )
    text = (
        f"# Work–precision\n\n{note}\n\n## Measured ratios\n\n{lines}\n\n"
        f"## Time to reach an error level\n\nThe cheapest run of each method whose error is at "
        f"most the level (levels: the NSGA errors of the sweep; – : not reached).\n\n{reach_md}"
        f"\n\n## Same step: baseline / NSGA (medians over h)\n\n{ratio_md}\n\n"
        f"## All runs\n\n{main_md}\n"
    )
    common.publish(
        out / ("work_precision_quick" if args.quick else "work_precision"),
        rows,
        COLUMNS,
        text,
        plot,
    )
    print(main_md + "\n\n" + reach_md + "\n\n" + ratio_md + "\n\n" + lines)
    return rows


if __name__ == "__main__":
    main()
