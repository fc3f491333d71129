"""What the smooth force on beams (``smooth_contact="on"``, the default of beams) does to the
shipped beam cases, planar and spatial, against the decoupled step (``"off"``): each case at
its reference parameters (tests/test_case_references.py) or those named, at h and h/8, in
both settings. Printed per probe: the
largest distance of each setting's run at h from the h/8 runs (over the probe's range), the
halvings, and the energy created (the largest rise of the total energy, over its range).

    python benchmarks/beam_smooth_default.py [CASE ...] [--quick] [--out DIR]
    python benchmarks/beam_smooth_default.py --cost N [--quick]

``--cost N``: the founding case at its defaults (1.5 s, 1000-step h), run N times in fresh
interpreters alternately with ``smooth_contact="off"`` and ``"on"`` (so that a change of load
hits both alike): the wall and CPU time (``time.process_time``) of the time loop per step,
median and least over the runs, and the ratio on / off.

Writes the printed lines to ``beam_smooth_default.md`` in the output folder.
"""

from __future__ import annotations

import dataclasses
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np
from _common import parser, write_markdown

from fecontact.testing import load_case, trace

CASES = {  # (parameters, t_end) of tests/test_case_references.py
    "disk_on_beam": ({}, 0.15),
    "flexible_pendulum": ({"restitution": 0.5}, 0.4),
    "impacting_bar": ({"n_elements": 20}, None),
    "two_bars": ({"n_elements": 20}, None),
    "flexible_pendulum (1.5 s)": ({}, None),
    "spatial_pendulum": ({"restitution": 0.5}, 0.4),
    "rod_on_post": ({}, 0.11),
    "rod_drop": ({}, 0.1),
    "rod_drop (angle 80)": ({"angle": 80.0}, 0.02),
    "spatial_pendulum (1.5 s)": ({}, None),
    "rod_on_post (0.3 s)": ({}, None),
    "flexible_pendulum (quick)": ({}, 0.02),  # (--quick: a check that the script runs)
}
DEFAULT = [name for name in CASES if "quick" not in name]

LINES = []

# runs in a fresh interpreter: the founding case at its defaults but ``smooth_contact``, the
# wall and CPU time per step of its time loop (a model built anew for the run)
WORKER = """
import dataclasses, json, sys, time
from fecontact.testing import load_case
from fecontact.time import simulate
sim = load_case("flexible_pendulum").build()
opts = dataclasses.replace(sim.options, smooth_contact=sys.argv[1])
t_end = float(sys.argv[2]) or sim.t_end
wall, cpu = time.perf_counter(), time.process_time()
n = sum(1 for _ in simulate(sim.model, sim.dt, t_end, opts, q0=sim.q0, v0=sim.v0)) - 1
print(json.dumps([(time.perf_counter() - wall) / n, (time.process_time() - cpu) / n]))
"""


def cost(repeats: int, quick: bool) -> None:
    """The founding case's time per step with the decoupled step ("off") and the smooth
    force ("on"), ``repeats`` fresh interpreters each, alternated."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    t_end = "0.3" if quick else "0"
    times = {"off": [], "on": []}
    for _ in range(repeats):
        for setting, out in times.items():
            run = [sys.executable, "-c", WORKER, setting, t_end]
            done = subprocess.run(run, check=True, capture_output=True, text=True, env=env)
            out.append(json.loads(done.stdout.strip().splitlines()[-1]))
    say(f"flexible_pendulum time per step (ms), {repeats} runs each, alternated")
    for k, clock in enumerate(("wall", "CPU")):
        med = {s: statistics.median(r[k] for r in times[s]) for s in times}
        low = {s: min(r[k] for r in times[s]) for s in times}
        say(
            f"  {clock:4s} off {1e3 * med['off']:.3f} (least {1e3 * low['off']:.3f})  "
            f"on {1e3 * med['on']:.3f} (least {1e3 * low['on']:.3f})  "
            f"on/off median {med['on'] / med['off']:.3f}, least {low['on'] / low['off']:.3f}"
        )


def say(line):
    print(line, flush=True)
    LINES.append(line)


def runs(name):
    params, t_end = CASES[name]
    sim = load_case(name.split()[0]).build(**params)
    t_end = t_end or sim.t_end
    out = {}
    for setting in ("off", "on"):
        s = sim.replace(options=dataclasses.replace(sim.options, smooth_contact=setting))
        for refine in (1, 8):
            r = trace(s, dt=sim.dt / refine, t_end=t_end)
            out[setting, refine] = r
            say(f"  {setting} h/{refine}: {r['status']}, halvings {r['halvings'].sum()}")
    return sim, out


def main(argv=None):
    ap = parser("the smooth force on the beam cases against h/8")
    ap.add_argument("cases", nargs="*")
    ap.add_argument("--cost", type=int, default=0, help="time the founding case N times")
    args = ap.parse_args(argv)
    if args.cost:
        cost(args.cost, args.quick)
        write_markdown(Path(args.out) / "beam_smooth_cost.md", "```\n" + "\n".join(LINES) + "\n```")
        return
    names = ["flexible_pendulum (quick)"] if args.quick else args.cases or DEFAULT
    for name in names:
        say(name)
        sim, out = runs(name)
        coarse_n = len(out["off", 1]["t"])
        for probe in sim.probes:
            fine = {s: out[s, 8][probe][::8] for s in ("off", "on")}
            ref = fine["off"]
            scale = max(np.max(np.abs(ref)), 1e-300)
            cells = []
            for s in ("off", "on"):
                x = out[s, 1][probe]
                n = min(len(x), len(ref), coarse_n)
                d_self = np.max(np.abs(x[:n] - fine[s][:n])) / scale
                d_auto = np.max(np.abs(x[:n] - ref[:n])) / scale
                cells.append(f"{s}: {d_self:.3e} (to off h/8 {d_auto:.3e})")
            n = min(len(fine["off"]), len(fine["on"]))
            fine_gap = np.max(np.abs(fine["off"][:n] - fine["on"][:n])) / scale
            say(f"  {probe:14s} " + "  ".join(cells) + f"  h/8 off-on {fine_gap:.3e}")
        for s in ("off", "on"):
            for r in (1, 8):
                tot = out[s, r]["total"]
                rise = np.max(tot - np.minimum.accumulate(tot))
                say(f"  energy rise {s} h/{r}: {rise:.3e} J of {np.max(np.abs(tot)):.3e}")
    text = "# The smooth force on beams against h/8\n\n```\n" + "\n".join(LINES) + "\n```"
    stem = "beam_smooth_default" + ("" if not args.cases else "_" + args.cases[0].split()[0])
    write_markdown(Path(args.out) / f"{stem}.md", text)


if __name__ == "__main__":
    main(sys.argv[1:])
