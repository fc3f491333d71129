"""What the pointwise rows of 3D mortar interfaces cost a contact step, against baselines.

Runs ``two_balls`` to 1.5 ms (two elastic balls head-on, at the case's step: 67 steps, every
one with contact candidates) and the ``stress_3d`` row of the elastic ball on the slab at
1 m/s (mortar), each in a child process, alternating this source tree and each ``--baseline``
tree (another version of fecontact, e.g. ``git archive`` of an earlier commit unpacked in a
folder, named by its folder), so that every version meets the same machine load. Per run, CPU
time (``time.process_time``) of the time loop per step, and of it the time spent in the
pointwise rows (:class:`~fecontact.contact.mortar_safeguard.DeepNodeRows` ``evaluate``), split
into the two passes (the slave's nodes, the master's nodes) and, within them, the
closest-facet search (``closest_facets``) and the planes (``_planes``); medians over the
repeats, and the ratio of the medians to the first baseline's.

    python benchmarks/safeguard_cost.py --baseline /tmp/base      # 5 repeats
    python benchmarks/safeguard_cost.py --baseline /tmp/a --baseline /tmp/b
    python benchmarks/safeguard_cost.py --quick                   # a few steps, this tree alone
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from _common import ROOT, parser, publish_report

RUNS = ("two_balls", "ball_on_slab")

CHILD = """
import json, sys, time
sys.path.insert(1, sys.argv[3])  # (after the tree: its fecontact, this stress_3d)
from fecontact import simulate
from fecontact.contact import mortar_safeguard as ms

spent = {}

def timed(cls, name, key):
    inner = getattr(cls, name)
    def wrapper(self, *args, **kwargs):
        t = time.process_time()
        try:
            return inner(self, *args, **kwargs)
        finally:
            part = key + (" master" if self.twin is None else " slave")
            spent[part] = spent.get(part, 0.0) + time.process_time() - t
    setattr(cls, name, wrapper)

timed(ms.DeepNodeRows, "evaluate", "rows")
timed(ms.DeepNodeRows, "closest_facets", "search")
timed(ms.DeepNodeRows3D, "_planes", "planes")
which, quick = sys.argv[1], sys.argv[2] == "1"
if which == "two_balls":
    from fecontact.testing import case
    sim = case("two_balls").build(t_end=1.5e-3)
else:
    import stress_3d
    sim = stress_3d.ball_on_slab(1.0).sim
t_end = 4 * sim.dt if quick else sim.t_end
cpu = time.process_time()
steps = sum(1 for _ in simulate(sim.model, sim.dt, t_end, sim.options, q0=sim.q0, v0=sim.v0))
cpu = time.process_time() - cpu
print(json.dumps({"steps": steps - 1, "cpu": cpu, "tree": ms.__file__, **spent}))
"""

PARTS = ("rows master", "search master", "planes master", "rows slave", "search slave",
         "planes slave")  # fmt: skip


def child(tree: Path, which: str, quick: bool) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    # (in the tree, whose package comes first; this tree's stress_3d: both build the same row)
    args = [sys.executable, "-c", CHILD, which, "1" if quick else "0", str(ROOT / "benchmarks")]
    out = subprocess.run(args, env=env, cwd=tree, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", action="append", default=[],
                   help="source tree of a version to compare (repeatable)")  # fmt: skip
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    repeats = 1 if args.quick else args.repeats
    trees = tuple((Path(b).name, Path(b).resolve()) for b in args.baseline) + (("this", ROOT),)
    rows = []
    for which in RUNS:
        runs = {name: [] for name, _ in trees}
        for _ in range(repeats):
            for name, tree in trees:  # alternated: both versions under the same load
                runs[name].append(child(tree, which, args.quick))
        base = None
        for name, _ in trees:
            steps = runs[name][0]["steps"]
            per_step = {k: 1e3 * float(np.median([r.get(k, 0.0) for r in runs[name]])) / steps
                        for k in ("cpu", *PARTS)}  # fmt: skip
            base = base or per_step["cpu"]
            rows.append({"run": which, "version": name, "steps": steps,
                         "CPU ms per step": per_step["cpu"], "CPU ratio": per_step["cpu"] / base,
                         **{f"{k} (ms)": per_step[k] for k in PARTS}})  # fmt: skip
            print(rows[-1], flush=True)
    publish_report(
        args.out, "safeguard_cost", args.quick,
        "The pointwise rows of 3D mortar interfaces: CPU per step, against a baseline", rows,
        (f"CPU ms per step, medians of {repeats} alternated runs; the parts are within the "
         "rows' evaluations.", rows),
    )  # fmt: skip


if __name__ == "__main__":
    main()
