"""What the smooth force on planar beams (``smooth_contact="on"``) does to the shipped beam
cases, against the decoupled default: each case at its reference parameters
(tests/test_case_references.py), at h and h/8, in both settings. Printed per probe: the
largest distance of each setting's run at h from the h/8 runs (over the probe's range), the
halvings, and the energy created (the largest rise of the total energy, over its range).

    python benchmarks/beam_smooth_default.py [CASE ...] [--quick] [--out DIR]

Writes the printed lines to ``beam_smooth_default.md`` in the output folder.
"""

from __future__ import annotations

import dataclasses
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
    "flexible_pendulum (quick)": ({}, 0.02),  # (--quick: a check that the script runs)
}


LINES = []


def say(line):
    print(line, flush=True)
    LINES.append(line)


def runs(name):
    params, t_end = CASES[name]
    sim = load_case(name.split()[0]).build(**params)
    t_end = t_end or sim.t_end
    out = {}
    for setting in ("auto", "on"):
        s = sim.replace(options=dataclasses.replace(sim.options, smooth_contact=setting))
        for refine in (1, 8):
            r = trace(s, dt=sim.dt / refine, t_end=t_end)
            out[setting, refine] = r
            say(f"  {setting} h/{refine}: {r['status']}, halvings {r['halvings'].sum()}")
    return sim, out


def main(argv=None):
    ap = parser("the smooth force on the planar beam cases against h/8")
    ap.add_argument("cases", nargs="*")
    args = ap.parse_args(argv)
    names = ["flexible_pendulum (quick)"] if args.quick else args.cases or list(CASES)[:-1]
    for name in names:
        say(name)
        sim, out = runs(name)
        coarse_n = len(out["auto", 1]["t"])
        for probe in sim.probes:
            fine = {s: out[s, 8][probe][::8] for s in ("auto", "on")}
            ref = fine["auto"]
            scale = max(np.max(np.abs(ref)), 1e-300)
            cells = []
            for s in ("auto", "on"):
                x = out[s, 1][probe]
                n = min(len(x), len(ref), coarse_n)
                d_self = np.max(np.abs(x[:n] - fine[s][:n])) / scale
                d_auto = np.max(np.abs(x[:n] - ref[:n])) / scale
                cells.append(f"{s}: {d_self:.3e} (to auto h/8 {d_auto:.3e})")
            n = min(len(fine["auto"]), len(fine["on"]))
            fine_gap = np.max(np.abs(fine["auto"][:n] - fine["on"][:n])) / scale
            say(f"  {probe:14s} " + "  ".join(cells) + f"  h/8 auto-on {fine_gap:.3e}")
        for s in ("auto", "on"):
            for r in (1, 8):
                tot = out[s, r]["total"]
                rise = np.max(tot - np.minimum.accumulate(tot))
                say(f"  energy rise {s} h/{r}: {rise:.3e} J of {np.max(np.abs(tot)):.3e}")
    text = "# The smooth force on planar beams against h/8\n\n```\n" + "\n".join(LINES) + "\n```"
    write_markdown(Path(args.out) / "beam_smooth_default.md", text)


if __name__ == "__main__":
    main(sys.argv[1:])
