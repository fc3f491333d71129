"""Newton's updates in space and in the plane, and what skipping the last tangent would buy:
spatial_pendulum (Beam3D on the Lie group) against flexible_pendulum (Beam2D).

1. Convergence per update: every update's size (``Model.update_size``, max |dq_i|/s_i) over a
   whole run, grouped by how many updates the step took; the medians of the first, second and
   third update and the quadratic constant |dq_(k+1)|/|dq_k|² (Newton converges quadratically
   where it is bounded).
2. The last update by the chord: where the previous update was below ``--bound`` (1e-4), the
   iterate's forces are evaluated without their tangent and the update is solved with the
   factors of the previous iteration matrix; if that update is below the increment tolerance
   it is taken and ends the step (as Newton's own would), else the tangent is evaluated after
   all and Newton's update is made. Both cases, alternated run by run with the default loop
   (so that every variant sees the same load on a shared machine), process CPU per step; then
   each chord run's history against its default run's: the largest difference of a column over
   its scale, before the first impact and over the whole run.
3. The same with v̇ extrapolated in the predictor (the heavy top's predictor), in both cases:
   whether a closer first iterate saves updates.

The chord is a variant of the loop measured here, not the project's step: its update differs
from Newton's by about C |dq_(k)| |dq_(k+1)| (C the quadratic constant), well inside the
increment tolerance but not round-off.
"""

from __future__ import annotations

import contextlib
import math
import os
import statistics
import time

import numpy as np
from _common import RESULTS, case, markdown_table, parser, timed_run, write_csv, write_markdown

from fecontact.time.acceleration_form import AccelerationForm
from fecontact.time.lie import predict_increment
from fecontact.time.stepper import PLANS
from fecontact.time.terms import Damping

CASES = ("flexible_pendulum", "spatial_pendulum")
COUNTS = {"chord updates": 0, "tangents after all": 0}


class ChordForm(AccelerationForm):
    """The acceleration form whose last update may reuse the previous iteration matrix
    (module docstring); ``bound``: the previous update's size below which it is tried."""

    __slots__ = ("lean", "last", "at")
    bound = 1e-4

    def begin(self, st, c, t, P, law=None):
        super().begin(st, c, t, P, law)
        self.lean, self.last, self.at = False, math.inf, 0

    def residual(self, it):
        newton, stats = self.newton, self.opts.stats.newton
        cuts = stats.line_search_cuts
        lean = (
            self.plain
            and self.last <= self.bound
            and newton.joints is None
            and not any(isinstance(term, Damping) for term in newton.terms)
        )
        newton.elastic.assemble = not lean
        try:
            done = super().residual(it)
        finally:
            newton.elastic.assemble = True
        self.lean, self.at = lean and stats.line_search_cuts == cuts, it
        if lean and not self.lean:  # (a line search moved the iterate: Newton's update)
            newton.elastic.evaluate(self.step, it)
        return done

    def update(self):
        newton, model, step = self.newton, self.model, self.step
        if self.lean:
            self.lean = False
            rowed = newton.rowed
            touching = [term for term in rowed if term.touching()] if rowed else None
            if not touching:
                dq = -self.solve(self.r)
                if model.update_size(dq) <= self.opts.tol_increment:
                    COUNTS["chord updates"] += 1
                    if self.plan.descent:  # (counted as the descent's updates are)
                        self.opts.stats.newton.iterations += 1
                    step.X[:, model.free_slice] += np.multiply.outer(step.c.w, dq)
                    if self.lie is not None:
                        step.q = self.lie.configuration(step.X[0])
                    self.dq, self.last = dq, model.update_size(dq)
                    return all(term.settled(step) for term in rowed)
            COUNTS["tangents after all"] += 1
            newton.elastic.evaluate(step, self.at)
        done = super().update()
        self.last = model.update_size(self.dq)
        return done


class ExtrapolatedForm(AccelerationForm):
    """The default form with v̇ extrapolated in the predictor (``predict_increment``'s
    ``extrapolate``, the heavy top's predictor), in space and in the plane alike."""

    __slots__ = ()

    def begin(self, st, c, t, P, law=None):
        super().begin(st, c, t, P, law)
        step = self.step
        step.X += predict_increment(st, c, True) - predict_increment(st, c, False)
        if self.lie is not None:
            step.q = self.lie.configuration(step.X[0])


@contextlib.contextmanager
def loop_form(form):
    """Runs built inside take the smooth step's Newton loop in ``form`` (None: the default)."""
    default = PLANS["nsga"]

    def plan(*args, **kwargs):
        p = default(*args, **kwargs)
        if form is not None:
            p.form = form
        return p

    PLANS["nsga"] = plan
    try:
        yield
    finally:
        PLANS["nsga"] = default


class UpdateLog(AccelerationForm):
    """The default form, logging every update's size and whether it ended the step."""

    __slots__ = ()
    log: list = []

    def update(self):
        done = super().update()
        self.log.append((self.model.update_size(self.dq), done))
        return done


def convergence(sim) -> list[dict]:
    """Per number of updates a step took: steps, and the medians of the first three updates'
    sizes and of |dq_(k+1)|/|dq_k|²."""
    UpdateLog.log = []
    with loop_form(UpdateLog):
        timed_run(sim, repeats=1)
    steps, now = {}, []
    for size, done in UpdateLog.log:
        now.append(size)
        if done:
            steps.setdefault(len(now), []).append(now)
            now = []
    rows = []
    for n in sorted(steps):
        a = np.array(steps[n])
        row = {"updates": n, "steps": len(a)}
        for k in range(min(n, 3)):
            row[f"size dq{k + 1}, median"] = float(np.median(a[:, k]))
        for k in range(1, min(n, 3)):
            row[f"dq{k + 1}/dq{k}², median"] = float(np.median(a[:, k] / a[:, k - 1] ** 2))
        rows.append(row)
    return rows


def differences(a: dict, b: dict) -> tuple[float, str, float, str]:
    """(largest |a − b|/scale of a column before the first impact, its column, the same over
    the run, its column); the scale of a column is its largest magnitude, that of an energy
    (J: energies, works, dissipations) the largest of them all."""
    joules = [k for k in a if any(w in k for w in ("energy", "work", "dissipation"))]
    energy_scale = max(float(np.nanmax(np.abs(np.asarray(a[k], float)))) for k in joules)
    active = np.nonzero(np.asarray(a["n_active"], float) > 0)[0]
    first = int(active[0]) if active.size else len(a["t"])
    out = []
    for stop in (first, len(a["t"])):
        worst = (0.0, "")
        for key in a:
            if key in ("t", "newton_iterations", "dt"):
                continue
            x, y = np.asarray(a[key], float)[:stop], np.asarray(b[key], float)[:stop]
            ok = np.isfinite(x) & np.isfinite(y)
            scale = np.max(np.abs(np.asarray(a[key], float)[np.isfinite(a[key])]), initial=0.0)
            if key in joules:
                scale = energy_scale
            if ok.any() and scale > 0.0:
                d = float(np.max(np.abs(x[ok] - y[ok]))) / scale
                worst = max(worst, (d, key))
        out += list(worst)
    return tuple(out)


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--bound", type=float, default=1e-4, help="previous update below which")
    args = p.parse_args()
    t_end, repeats = (0.05, 1) if args.quick else (1.5, 5)
    ChordForm.bound = args.bound
    sims = {name: case(name).build().replace(t_end=t_end) for name in CASES}
    conv = []
    for name, sim in sims.items():
        conv += [{"case": name, **row} for row in convergence(sim)]
    load = [os.getloadavg()[0]]
    variants = {"Newton": None, "chord": ChordForm, "extrapolated predictor": ExtrapolatedForm}
    cpu = {(n, v): [] for n in CASES for v in variants}
    first = {}
    for _ in range(repeats):
        for name, sim in sims.items():
            for variant, form in variants.items():
                with loop_form(form):
                    t = time.process_time()
                    run = timed_run(sim, repeats=1)
                    cpu[(name, variant)].append(1e3 * (time.process_time() - t) / run["steps"])
                first.setdefault((name, variant), run)
    load.append(os.getloadavg()[0])
    rows = []
    for name in CASES:
        for variant in variants:
            run, base = first[(name, variant)], first[(name, "Newton")]
            d0, k0, d1, k1 = differences(base["history"], run["history"])
            rows.append(
                {
                    "case": name,
                    "loop": variant,
                    "status": run["status"],
                    "CPU per step (ms)": statistics.median(cpu[(name, variant)]),
                    "updates": run["summary"]["newton_iterations_total"],
                    "before impact: max Δ/scale": d0,
                    "column": k0,
                    "whole run: max Δ/scale": d1,
                    "column ": k1,
                }
            )
    space, plane = CASES[1], CASES[0]
    ratios = {
        f"{space} {a} / {plane} {b}": [
            x / y for x, y in zip(cpu[(space, a)], cpu[(plane, b)], strict=True)
        ]
        for a, b in (
            ("Newton", "Newton"),
            ("chord", "Newton"),
            ("chord", "chord"),
            ("extrapolated predictor", "extrapolated predictor"),
        )
    }
    note = "Step CPU ratios, median (min–max) of the alternated rounds: " + "; ".join(
        f"{k} {statistics.median(v):.2f} ({min(v):.2f}–{max(v):.2f})" for k, v in ratios.items()
    )
    note += f". Chord counts (all runs): {COUNTS}. Load average (1 min) {load[0]:.1f} before the"
    note += f" timed runs, {load[1]:.1f} after."
    conv_cols = ["case", "updates", "steps"] + [
        c for c in max(conv, key=len) if c not in ("case", "updates", "steps")
    ]
    tables = (markdown_table(conv, conv_cols), markdown_table(rows, list(rows[0])))
    for t in tables:
        print(t)
    print(note)
    out = args.out or RESULTS
    stem = "newton_last_update_quick" if args.quick else "newton_last_update"
    write_csv(f"{out}/{stem}.csv", rows, list(rows[0]))
    write_markdown(
        f"{out}/{stem}.md",
        f"# Newton's updates in space and in the plane\n\n## Update sizes\n\n{tables[0]}\n\n"
        f"## The last update by the chord (bound {args.bound:g})\n\n{tables[1]}\n\n{note}",
    )


if __name__ == "__main__":
    main()
