"""Releases located inside the step: the solids' releasing step split at the release its
sub-steps read (``fecontact/time/release_split.py``), against whole steps.

1. Hertz's uniform balls at 1 m/s (``hertz.py``, closing 0.37 of a step into the third step)
   at t_c/20 and t_c/50: the rebound speed of the ball's centre of mass less the finest
   step's (2^-15 s, ``localize=1``), over the approach speed, and the contact duration read
   from the located closing and release against the finest step's.
2. ``ball_drop``, ``disk_drop`` and ``two_disks`` at their defaults: the first body's
   centre-of-mass velocity at the end less that of the same run at h/8 (``localize=1``), over
   the largest speed of the reference; created over the ledger's scale; CPU of the run
   (median of three, whole and split alternated).

docs/validation/localization.md, *Releases located inside the step*.
"""

from __future__ import annotations

import contextlib
import dataclasses
import statistics
import tempfile
import time

import hertz
import numpy as np
from _common import parser, publish_report

from fecontact import Probe, run
from fecontact.testing import case
from fecontact.time import substeps

WHOLE = substeps.Releases.__init__


@contextlib.contextmanager
def split(on: bool):
    """Runs whose releasing steps are split (``on``) or taken whole."""

    def init(self, model, split=False):
        WHOLE(self, model, split and on)

    substeps.Releases.__init__ = init
    try:
        yield
    finally:
        substeps.Releases.__init__ = WHOLE


def hertz_run(element, refinements, steps, localize):
    """(rebound speed (m/s), contact duration (s)) of Hertz's ball at t_c/``steps`` (None:
    the finest step)."""
    ball, st, stats, _, _ = hertz.located_impact(element, refinements, steps, localize)
    w = ball.mass_matrix() @ ball.translation_field(np.array([0.0, 0.0, 1.0])) / ball.mass
    span = stats.localization
    return float(w @ st.v[: ball.ndof]), span.last_release - span.first_closing


def hertz_rows(quick):
    balls = (("P1", 1),) if quick else (("P1", 1), ("P1", 2), ("P2", 1))
    rows = []
    for element, refinements in balls:
        speed, span = hertz_run(element, refinements, None, True)
        for steps in (20,) if quick else (20, 50):
            with split(False):
                whole = hertz_run(element, refinements, steps, "auto")
            with split(True):
                both = hertz_run(element, refinements, steps, "auto")
            rows.append({
                "ball": f"{element}, refinements {refinements}", "h": f"t_c/{steps}",
                "finest rebound (m/s)": speed,
                "rebound error, whole": (whole[0] - speed) / hertz.V,
                "rebound error, split": (both[0] - speed) / hertz.V,
                "t_c error (%), whole": 100 * (whole[1] / span - 1),
                "t_c error (%), split": 100 * (both[1] / span - 1),
            })  # fmt: skip
    return rows


def case_run(name, params, divide=1, localize="auto"):
    """(trace (t, v_cm of the first body), created / scale, CPU (s), summary) of a case."""
    sim = case(name).build(**params)
    options = dataclasses.replace(sim.options, localize=localize)
    sim = sim.replace(dt=sim.dt / divide, options=options)
    body, trace = sim.model.bodies[0], []
    w = [body.mass_matrix() @ body.translation_field(e) / body.mass for e in np.eye(body.dim)]
    s = sim.model.body_slice(0)

    def probe(model, st):
        trace.append([st.t, *(float(x @ st.v[s]) for x in w)])
        return 0.0

    sim = sim.replace(probes={**sim.probes, "v_cm_trace": Probe(probe, "m/s")})
    with tempfile.TemporaryDirectory(prefix="release_split_") as tmp:
        clock = time.process_time()
        summary = run(sim, tmp, frames=False, checkpoint_every=0)
        cpu = time.process_time() - clock
    ledger = summary["energy_ledger"]
    return np.array(trace), ledger["created"] / ledger["scale"], cpu, summary


def case_rows(quick):
    runs = [("ball_drop", {"refinements": 1})] if quick else [
        ("ball_drop", {}), ("disk_drop", {}), ("two_disks", {})
    ]  # fmt: skip
    rows = []
    for name, params in runs:
        ref = case_run(name, params, 8, True)[0]
        speed = float(np.max(np.abs(ref[:, 1:])))
        out = {False: [], True: []}
        for _ in range(1 if quick else 3):
            for on in (False, True):
                with split(on):
                    out[on].append(case_run(name, params))
        row = {"case": name}
        for on, label in ((False, "whole"), (True, "split")):
            trace, created, _, summary = out[on][0]
            at = [np.interp(trace[-1, 0], ref[:, 0], ref[:, k]) for k in range(1, ref.shape[1])]
            cost = summary["localization_cost"]
            row[f"end error, {label}"] = float(np.max(np.abs(trace[-1, 1:] - at))) / speed
            row[f"created, {label}"] = created
            row[f"CPU (s), {label}"] = statistics.median(r[2] for r in out[on])
            row[f"splits, {label}"] = cost["release_splits"]
        rows.append(row)
    return rows


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    balls, cases = hertz_rows(args.quick), case_rows(args.quick)
    keys = list(dict.fromkeys(k for r in balls + cases for k in r))
    publish_report(
        args.out, "release_split", args.quick, "Releases located inside the step",
        [{k: r.get(k, "") for k in keys} for r in balls + cases],
        ("Hertz's balls: rebound speed and t_c against the finest step", balls),
        ("Cases at their defaults against h/8", cases),
    )  # fmt: skip


if __name__ == "__main__":
    main()
