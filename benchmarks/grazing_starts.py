"""The box dropped spinning on a box (``tests/test_frictional_stack.py``) from its start and
from starts with the upper box's spin ω_z shifted: how far the default, p × 1000 and k ÷ 100
part at 128 ms and at the run's end, where the jump meets a nearly grazing corner (127 ms).

    python benchmarks/grazing_starts.py [--t-end 0.13] [--shifts 0,1e-3,-1e-3,...] [--out DIR]
    python benchmarks/grazing_starts.py --quick   # the first 10 ms: checks it runs
"""

import dataclasses
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from _common import parser, publish_report  # noqa: E402
from test_frictional_stack import box_on_box  # noqa: E402

from fecontact import simulate  # noqa: E402
from fecontact.time.settings import IntegratorOptions  # noqa: E402

SHIFTS = (0.0, 1e-3, -1e-3, 3e-3, -3e-3, 5e-3, -5e-3, 1e-2, -1e-2)
OPTIONS = ({}, {"penalty_scale": 1e3}, {"multiplier_scale": 1e-2})


def parting(shift: float, t_end: float, probe: float = 0.128):
    """(largest parting of q from the default's at ``probe``, at the run's end) over p, k."""
    model, q0, v0 = box_on_box()
    v0 = v0.copy()
    v0[11] += shift
    runs = []
    for option in OPTIONS:
        opts = dataclasses.replace(IntegratorOptions(), **option)
        states = list(simulate(model, 1e-3, t_end, opts, q0=q0, v0=v0))
        times = np.array([st.t for st in states])
        at = int(np.argmin(np.abs(times - probe)))
        runs.append((states[at].q, states[-1].q))
    probe_gap = max(np.max(np.abs(r[0] - runs[0][0])) for r in runs[1:])
    end_gap = max(np.max(np.abs(r[1] - runs[0][1])) for r in runs[1:])
    return float(probe_gap), float(end_gap)


def main():
    p = parser(__doc__.split("\n\n")[0])
    p.add_argument("--t-end", type=float, default=0.135)
    p.add_argument("--shifts", default=",".join(map(str, SHIFTS)))
    args = p.parse_args()
    # quick: the test's start over the first 10 ms (the fall), to check the script runs
    shifts, t_end = (
        ([0.0], 0.01) if args.quick else (map(float, args.shifts.split(",")), args.t_end)
    )
    rows = []
    for shift in shifts:
        at_probe, at_end = parting(shift, t_end)
        rows.append({"shift (rad/s)": shift, "at 128 ms (m)": at_probe, "at the end (m)": at_end})
    caption = (
        f"Largest |Δq| of p × 1000 and k ÷ 100 against the default, to t = {t_end:g} s, with "
        "the upper box's start spin ω_z shifted."
    )
    publish_report(args.out, "grazing_starts", args.quick, "Grazing starts", rows, (caption, rows))


if __name__ == "__main__":
    main()
