"""Convergence of the nonsmooth generalized-α scheme against exact solutions.

Error against the step h, log–log plots and a table of observed orders (least-squares slope
of log error against log h over the sweep):

- bouncing ball (e = 0.8, h₀ = 1 m): the first five impact times and the first four apex
  heights against t_{k+1} = t_k + 2eᵏt₁ and e^{2k}h₀;
- rigid pendulum (uniform bar, e = 0.5): max angle error over 2.5 s against the exact
  Jacobi-sn solution, and the first three impact times;
- impacting bar: contact duration against 2L/c, rebound velocity against v₀ and the final
  energy; the case ties its step to the mesh (h = Δx/2c), so h and Δx shrink together;
- contact-free swings: the rigid pendulum without its stop (max angle error over 2 s against
  the exact free swing) and the flexible pendulum before its first impact (t ≤ 0.3 s, tip
  position and velocity against NSGA with a step 16 times smaller than the smallest h).

An impact is located only to the step that contains it, so the impact errors are c·h with c
set by where each impact falls inside its step. For the ball and the pendulum the error at a
nominal h is therefore the mean of e/h over steps within ±30 % of it (times the nominal h),
which averages that phase out of the slope.

    python benchmarks/convergence.py [--quick]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import math
import time

import numpy as np

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact import Model, Pin

E_BALL, H0 = 0.8, 1.0
E_PEND = 0.5
COLUMNS = ["case", "quantity", "h", "error", "unit", "nominal_h", "runs"]


def ball_errors(h):
    """(max impact-time error over five impacts (s), max relative apex error over four)."""
    t_exact = common.ball_impact_times(5, H0, E_BALL)
    sim = common.case("bouncing_ball").build(height=H0, restitution=E_BALL)
    tr = common.trace(sim, dt=h, t_end=t_exact[-1] + 0.1)
    starts = common.episode_starts(tr["active"])
    t_imp = tr["t"][starts][:5]
    apex = [tr["gap"][starts[k - 1] : starts[k]].max() for k in range(1, 5)]
    exact_apex = E_BALL ** (2 * np.arange(1, 5)) * H0
    return (
        float(np.abs(t_imp - t_exact).max()),
        float(np.max(np.abs(np.array(apex) - exact_apex) / exact_apex)),
    )


def pendulum_errors(h, t_end=2.5):
    """(max angle error over t_end (rad), max error of the first three impact times (s))."""
    sim = common.case("rigid_pendulum").build(restitution=E_PEND)
    tr = common.trace(sim, dt=h, t_end=t_end)
    exact, t_imp = common.pendulum_exact(tr["t"], e=E_PEND)
    t_num = tr["t"][common.episode_starts(tr["active"])][:3]
    return float(np.abs(tr["theta"] - exact).max()), float(np.abs(t_num - t_imp[:3]).max())


def free_rigid_pendulum():
    """The rigid pendulum case without its stop (the same bar, pin and gravity)."""
    sim = common.case("rigid_pendulum").build()
    bar = sim.model.bodies[0]
    model = Model([bar], [], gravity=(0.0, -common.G), joints=[Pin(bar, [0.0, 0.0])])
    return sim.replace(model=model)


def jittered(fn, h, jitter):
    """Mean over the jittered steps of error/h, times the nominal h (one value per output)."""
    ratios = np.array([np.array(fn(h * j)) / (h * j) for j in jitter])
    return ratios.mean(axis=0) * h


def bar_errors(n):
    sim = common.case("impacting_bar").build(n_elements=n)
    tr = common.trace(sim, t_end=2.5)
    on = np.flatnonzero(tr["active"])
    duration = tr["t"][on[-1]]
    return sim.dt, {
        "contact duration": abs(duration - 2.0) / 2.0,
        "rebound velocity": abs(tr["v_mean"][-1] - 0.1) / 0.1,
        "energy loss": 1.0 - tr["total"][-1] / tr["total"][0],
    }


def flexible_swing(h_values, refine=16, t_end=0.3):
    """Max tip position (m) and velocity (m/s) errors before the first impact, against NSGA
    with h_ref = min(h)/refine; also returns h_ref."""
    sim = common.case("flexible_pendulum").build()
    h_ref = min(h_values) / refine
    ref = common.trace(sim, dt=h_ref, t_end=t_end)
    assert not ref["active"].any(), "the reference swing reached the stop"
    out = []
    for h in h_values:
        tr = common.trace(sim, dt=h, t_end=t_end)
        idx = np.rint(tr["t"] / h_ref).astype(int)
        dx = np.hypot(tr["tip_x"] - ref["tip_x"][idx], tr["tip_y"] - ref["tip_y"][idx])
        dv = np.hypot(tr["tip_vx"] - ref["tip_vx"][idx], tr["tip_vy"] - ref["tip_vy"][idx])
        out.append((float(dx.max()), float(dv.max())))
    return out, h_ref


def sweep(quick: bool):
    rows = []

    def add(case, quantity, h, error, unit, nominal=None, runs=1):
        rows.append(
            {
                "case": case,
                "quantity": quantity,
                "h": h,
                "error": float(error),
                "unit": unit,
                "nominal_h": nominal if nominal is not None else h,
                "runs": runs,
            }
        )

    jitter = np.ones(1) if quick else np.geomspace(1 / 1.3, 1.3, 7)
    h_ball = [2e-3, 1e-3] if quick else [2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5]
    for h in h_ball:
        t_err, apex_err = jittered(ball_errors, h, jitter)
        add("bouncing ball", "impact times (5)", h, t_err, "s", h, len(jitter))
        add("bouncing ball", "apex heights (4), relative", h, apex_err, "-", h, len(jitter))
        print(f"ball h={h:.3g}: impact {t_err:.3e} s, apex {apex_err:.3e}", flush=True)
    h_pend = [2e-3, 1e-3] if quick else [2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4]
    for h in h_pend:
        a_err, t_err = jittered(pendulum_errors, h, jitter)
        add("rigid pendulum e=0.5", "angle (max over 2.5 s)", h, a_err, "rad", h, len(jitter))
        add("rigid pendulum e=0.5", "impact times (3)", h, t_err, "s", h, len(jitter))
        print(f"pendulum h={h:.3g}: angle {a_err:.3e} rad, impact {t_err:.3e} s", flush=True)
    for n in [25, 50] if quick else [25, 50, 100, 200, 400]:
        h, errs = bar_errors(n)
        for q, e in errs.items():
            add("impacting bar, h = L/(2nc)", f"{q}, relative", h, e, "-")
        print(f"bar n={n} h={h:.3g}: {errs}", flush=True)
    h_free = [4e-3, 2e-3] if quick else [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]
    free = free_rigid_pendulum()
    for h in h_free:
        tr = common.trace(free, dt=h, t_end=2.0)
        err = np.abs(tr["theta"] - common.pendulum_exact(tr["t"], e=None)[0]).max()
        add("rigid pendulum, no stop", "angle (max over 2 s)", h, err, "rad")
        print(f"free rigid pendulum h={h:.3g}: {err:.3e} rad", flush=True)
    errs, h_ref = flexible_swing(h_free, refine=2 if quick else 16)
    for h, (dx, dv) in zip(h_free, errs, strict=True):
        label = f"flexible pendulum, t <= 0.3 s (ref. h = {h_ref:.3g})"
        add(label, "tip position", h, dx, "m")
        add(label, "tip velocity", h, dv, "m/s")
        print(f"flexible swing h={h:.3g}: {dx:.3e} m, {dv:.3e} m/s", flush=True)
    return rows


EXPECTED = {
    "impact times (5)": "1",
    "apex heights (4), relative": "2",
    "angle (max over 2.5 s)": "1",
    "impact times (3)": "1",
    "angle (max over 2 s)": "2",
    "tip position": "2",
    "tip velocity": "2",
}


def orders(rows):
    out = []
    keys = list(dict.fromkeys((r["case"], r["quantity"]) for r in rows))
    for case, quantity in keys:
        sel = [r for r in rows if r["case"] == case and r["quantity"] == quantity]
        h = np.array([r["nominal_h"] for r in sel])
        e = np.array([r["error"] for r in sel])
        out.append(
            {
                "case": case,
                "quantity": quantity,
                "h range (s)": f"{h.max():.3g} … {h.min():.3g}",
                "error at largest h": e[np.argmax(h)],
                "error at smallest h": e[np.argmin(h)],
                "unit": sel[0]["unit"],
                "observed order": common.observed_order(h, e),
                "order, 3 smallest h": common.observed_order(
                    h[np.argsort(h)[:3]], e[np.argsort(h)[:3]]
                ),
                "expected": EXPECTED.get(quantity, "1 (mesh + step)"),
            }
        )
    return out


def plot(rows, path):
    import matplotlib.pyplot as plt

    cases = list(dict.fromkeys(r["case"] for r in rows))
    ncol = 3
    nrow = math.ceil(len(cases) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.4 * nrow), squeeze=False)
    for ax, case in zip(axes.flat, cases, strict=False):
        anchor = None  # slope lines through the first quantity's smallest-h point
        for quantity in dict.fromkeys(r["quantity"] for r in rows if r["case"] == case):
            sel = [r for r in rows if r["case"] == case and r["quantity"] == quantity]
            h = np.array([r["nominal_h"] for r in sel])
            e = np.array([r["error"] for r in sel])
            p = common.observed_order(h, e)
            ok = e > 0
            ax.loglog(h[ok], e[ok], "o-", label=f"{quantity} [{sel[0]['unit']}]: {p:.2f}")
            if anchor is None and ok.any():
                i = np.argmin(np.where(ok, h, np.inf))
                anchor = (h[i], e[i])
        hs = [r["nominal_h"] for r in rows if r["case"] == case]
        hh = np.array([min(hs), max(hs)])
        for order, style in ((1, ":"), (2, "--")):
            if anchor is not None:
                ref = anchor[1] * (hh / anchor[0]) ** order
                ax.loglog(hh, ref, "k" + style, lw=0.8, label=f"slope {order}")
        ax.set_title(case, fontsize=9)
        ax.set_xlabel("h (s)")
        ax.set_ylabel("error")
        ax.legend(fontsize=6.5)
        common.tidy_log_axes(ax)
    for ax in list(axes.flat)[len(cases) :]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def read_rows(path):
    """The rows of a CSV written by this script (to redo the tables and plots)."""
    import csv

    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("h", "error", "nominal_h"):
            r[k] = float(r[k])
        r["runs"] = int(r["runs"])
    return rows


def main(argv=None):
    args = common.parser(__doc__.splitlines()[0], from_csv=True).parse_args(argv)
    out = common.Path(args.out)
    note = common.machine_note()
    if args.from_csv:
        note = common.previous_note(args.from_csv)
    t0 = time.perf_counter()
    rows = read_rows(args.from_csv) if args.from_csv else sweep(args.quick)
    table = orders(rows)
    cols = list(table[0])
    md = common.markdown_table(table, cols)
    detail = common.markdown_table(rows, COLUMNS[:5])
    if not args.from_csv:
        note += f"; {time.perf_counter() - t0:.0f} s."
    text = (
        f"# Convergence against exact solutions\n\n{note}\n\n"
        f"Observed order: least-squares slope of log(error) against log(h).\n\n{md}\n\n"
        f"## Errors\n\n{detail}\n"
    )
    common.publish(
        out / ("convergence_quick" if args.quick else "convergence"), rows, COLUMNS, text, plot
    )
    print(md)
    return rows, table


if __name__ == "__main__":
    main()
