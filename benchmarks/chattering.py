"""Chattering contacts of flexible bodies: steps of h against a fine run, localization off,
on with every step whole, and on with a chattering contact's steps in sub-steps (what
``localize=1`` does on beams and solids).

Tables:

1. the founding case (flexible pendulum, 1.5 s): the largest tip distance, over the rows at
   every 1 ms, from an h/64 run (localized, sub-steps) at h = 1e-3, 5e-4, 2.5e-4, and at
   h = 1e-3 from its own h/8 run; the impulse of the first contact phase (t < 0.36 s); the
   located impacts, the steps taken in sub-steps, and the wall time per step;
2. where the error at h = 1e-3 comes from: the h/8 run through the first contact phase
   (t < 0.33 s), then steps of h, against the h/8 run throughout (only the smooth steps of
   the free swing differ), and the tip's ringing at its first bending mode (amplitude and
   frequency of the tip's x velocity, 0.4–0.86 s, at h and h/8);
3. the impacting bar (L = 1, c = 1, v₀ = 0.1, 100 elements, the closing 0.37 of a step
   into a step): the largest distance of the mean velocity (momentum over mass) from an
   h/16 run and the rebound velocity's error (exact: v₀), at h, h/2, h/4 (h = Δx/2c);
4. Hertz's ball (``hertz.py``'s P1 balls of refinements 1 and 2 and its P2 ball of
   refinement 1, at 1 m/s): the contact duration from the located closing and the last
   release at t_c/20 and t_c/50 against the finest step's, and from whole steps.

    python benchmarks/chattering.py            # about 10 minutes on a loaded 2-core machine
    python benchmarks/chattering.py --quick    # a minute: shorter runs, fewer steps
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import contextlib
import time

import numpy as np

try:
    from . import _common as common
except ImportError:
    import _common as common

import fecontact.time.substeps as substeps_module
from fecontact.time import IntegratorOptions, StepStats, simulate

H = 1e-3
SETTINGS = (("off", False, None), ("on, whole steps", True, 1), ("on, sub-steps", True, None))


@contextlib.contextmanager
def substeps(count):
    """Localization's sub-steps per chattering step set to ``count`` (None: the default)
    while the block runs: the "whole steps" rows are localization as it was without them."""
    saved = substeps_module.CHATTER
    substeps_module.CHATTER = saved if count is None else count
    try:
        yield
    finally:
        substeps_module.CHATTER = saved


def pendulum_run(h, t_end, localize, count=None):
    """(t, tip x, tip y, tip vx, impulse) rows every step, statistics, wall time (s)."""
    sim = common.case("flexible_pendulum").build()
    opts = IntegratorOptions(**{**vars(sim.options), "localize": localize})
    probes = [sim.probes[k].fn for k in ("tip_x", "tip_y", "tip_vx")]
    stats, rows = StepStats(), []
    with substeps(count):
        clock = time.perf_counter()
        for st in simulate(sim.model, h, t_end, opts, q0=sim.q0, v0=sim.v0, stats=stats):
            rows.append([st.t, *(p(sim.model, st) for p in probes), float(np.sum(st.impulse))])
        wall = time.perf_counter() - clock
    return np.array(rows), stats.localization, wall


def at_ms(rows, h):
    """The rows at every 1 ms."""
    return rows[:: max(1, round(1e-3 / h))]


def tip_distance(a, b) -> float:
    """The largest tip distance (mm) between two runs' rows at the same times."""
    n = min(len(a), len(b))
    assert np.allclose(a[:n, 0], b[:n, 0], atol=1e-9)
    return 1e3 * float(np.max(np.hypot(a[:n, 1] - b[:n, 1], a[:n, 2] - b[:n, 2])))


def founding(quick):
    t_end = 0.36 if quick else 1.5  # quick: through the first contact phase
    steps = (H, H / 2) if quick else (H, H / 2, H / 4)
    fine_h = H / (8 if quick else 64)
    fine, _, _ = pendulum_run(fine_h, t_end, True)
    fine = at_ms(fine, fine_h)
    out = []
    for name, loc, count in SETTINGS:
        own, _, _ = pendulum_run(H / 8, t_end, loc, count)
        for h in steps:
            r, stats, wall = pendulum_run(h, t_end, loc, count)
            first = r[:, 0] < 0.36
            row = {
                "localize": name,
                "h (s)": h,
                f"max tip distance from h/{round(H / fine_h)} (mm)": tip_distance(
                    at_ms(r, h), fine
                ),
                "from its own h/8 run (mm)": (
                    tip_distance(at_ms(r, h), at_ms(own, H / 8)) if h == H else None
                ),
                "first contact impulse (N s)": float(r[first, 4].sum()),
                "located impacts": stats.impacts,
                "steps in sub-steps": stats.subdivided,
                "wall per step (ms)": 1e3 * wall / (len(r) - 1),
            }
            out.append(row)
    return out


def ringing(r, lo=0.4, hi=0.86):
    """(amplitude (m/s), frequency (Hz)) of the tip's x velocity's strongest component
    after a 20 ms moving mean is taken out, on [lo, hi]."""
    rows = (r[:, 0] > lo) & (r[:, 0] < hi)
    dt = r[1, 0] - r[0, 0]
    vx = r[rows, 3]
    w = round(0.02 / dt)
    fast = (vx - np.convolve(vx, np.ones(w) / w, mode="same"))[w:-w]
    spectrum = 2 * np.abs(np.fft.rfft(fast)) / fast.size
    k = int(np.argmax(spectrum))
    return float(spectrum[k]), float(np.fft.rfftfreq(fast.size, dt)[k])


def swing(quick):
    """The h/8 run to 0.33 s, then steps of h, against the h/8 run."""
    t_end = 0.9 if quick else 1.5
    sim = common.case("flexible_pendulum").build()
    opts = IntegratorOptions(**{**vars(sim.options), "localize": True})
    fine, _, _ = pendulum_run(H / 8, t_end, True)
    split = 0.33
    start = None
    for st in simulate(sim.model, H / 8, split, opts, q0=sim.q0, v0=sim.v0):
        start = st
    probes = [sim.probes[k].fn for k in ("tip_x", "tip_y", "tip_vx")]
    rows = [[start.t, *(p(sim.model, start) for p in probes), 0.0]]
    n0 = round(split / H)
    start.step = n0
    # (simulate continues a stored state from its step count: steps of H from 0.33 s)
    for st in simulate(sim.model, H, t_end, opts, start=start):
        rows.append([st.t, *(p(sim.model, st) for p in probes), float(np.sum(st.impulse))])
    r = np.array(rows)
    ref = at_ms(fine, H / 8)[n0:]
    coarse, _, _ = pendulum_run(H, t_end, True)
    amp_h, f_h = ringing(coarse)
    amp_f, f_f = ringing(fine)
    return [
        {
            "run": "h/8 to 0.33 s, then h",
            "max tip distance from the h/8 run (mm)": tip_distance(r, ref),
            "ringing at h: amplitude (m/s), frequency (Hz)": f"{amp_h:.3f}, {f_h:.1f}",
            "at h/8": f"{amp_f:.3f}, {f_f:.1f}",
        }
    ]


def bar_run(h, loc, count, quick):
    """(t, mean velocity) rows every step, statistics, wall time (s) of the impacting bar
    whose end closes 0.37 of a base step into its eleventh step."""
    n = 20 if quick else 100
    dt = common.case("impacting_bar").build(n_elements=n).dt
    sim = common.case("impacting_bar").build(n_elements=n, gap=0.1 * dt * 10.37)
    opts = IntegratorOptions(**{**vars(sim.options), "localize": loc})
    stats, rows = StepStats(), []
    with substeps(count):
        clock = time.perf_counter()
        for st in simulate(sim.model, h, sim.t_end, opts, q0=sim.q0, v0=sim.v0, stats=stats):
            rows.append((st.t, sim.probes["v_mean"].fn(sim.model, st)))
        wall = time.perf_counter() - clock
    return np.array(rows), stats.localization, wall


def bar(quick):
    """The bar's mean velocity at h, h/2, h/4 (h = Δx/2c) against an h/16 run, and its
    rebound (exact: the impact speed, 0.1 m/s)."""
    base = common.case("impacting_bar").build(n_elements=20 if quick else 100).dt
    fine, _, _ = bar_run(base / 16, True, None, quick)
    out = []
    for name, loc, count in SETTINGS:
        for k in (1, 2, 4):
            r, stats, wall = bar_run(base / k, loc, count, quick)
            ref = fine[:: 16 // k]
            n = min(len(r), len(ref))
            out.append(
                {
                    "localize": name,
                    "h / (Δx/2c)": 1 / k,
                    "max mean velocity distance from h/16 (m/s)": float(
                        np.max(np.abs(r[:n, 1] - ref[:n, 1]))
                    ),
                    "rebound velocity error (m/s)": float(abs(r[-1, 1] - 0.1)),
                    "located impacts": stats.impacts,
                    "steps in sub-steps": stats.subdivided,
                    "wall per step (ms)": 1e3 * wall / (len(r) - 1),
                }
            )
    return out


def hertz_span(quick):
    """Hertz's ball (``hertz.py``, 1 m/s) closing 0.37 of a step into its third step: the
    contact duration from the located closing and the last release (``summary.json``'s
    ``localized_contact_span_s``) at t_c/20, t_c/50 and the finest step, against the finest
    step's (``localize=1``), with ``localize=1`` and at the defaults ("auto": whole steps,
    the release in sub-steps); and without localization (the end of the last step with a
    contact force, less the exact closing instant)."""
    import hertz

    balls = (("P1", 1),) if quick else (("P1", 1), ("P1", 2), ("P2", 1))
    out = []
    for element, refinements in balls:
        spans = {}
        for steps in ("finest", 20, 50):
            for loc in (False, True) if steps == "finest" else (False, True, "auto"):
                finest = steps == "finest"
                run = hertz.located_impact(element, refinements, None if finest else steps, loc)
                _, _, stats, last, h = run
                span = stats.localization
                spans[steps, loc] = (
                    span.last_release - span.first_closing if loc else last - 2.37 * h
                )
            if steps == "finest":
                continue
            out.append(
                {
                    "ball": f"{element}, refinements {refinements}",
                    "h": f"t_c/{steps}",
                    "t_c, finest step (ms)": 1e3 * spans["finest", True],
                    "localized (ms)": 1e3 * spans[steps, True],
                    "error (%)": 100 * (spans[steps, True] / spans["finest", True] - 1),
                    "defaults (ms)": 1e3 * spans[steps, "auto"],
                    "defaults' error (%)": 100 * (spans[steps, "auto"] / spans["finest", True] - 1),
                    "whole steps (ms)": 1e3 * spans[steps, False],
                    "whole steps' error (%)": 100
                    * (spans[steps, False] / spans["finest", False] - 1),
                }
            )
    return out


def main(argv=None):
    args = common.parser(__doc__.splitlines()[0]).parse_args(argv)
    out = common.Path(args.out)
    sections = [
        ("Founding case: tip distance from a fine run.", founding(args.quick)),
        ("Founding case: the free swing's smooth steps.", swing(args.quick)),
        ("Impacting bar: the mean velocity against a fine run.", bar(args.quick)),
        (
            "Hertz's ball: contact duration, closing to release.",
            hertz_span(args.quick),
        ),
    ]
    text = common.report("Chattering contacts", *sections)
    stem = out / ("chattering_quick" if args.quick else "chattering")
    rows = sections[0][1]
    common.publish(stem, rows, list(rows[0]), text)
    print(text)


if __name__ == "__main__":
    main()
