"""3D mortar on partly covered slave triangles: the answers and the cost against a baseline.

``cases/two_balls.py`` (mortar, 1 m/s each) is run in child processes, alternating this source
tree and a ``--baseline`` tree (another version of fecontact, e.g. ``git archive`` of the
previous commit unpacked in a folder), so that both versions meet the same machine load. Per
run: the left ball's largest lateral centre-of-mass speed and its exit speed (over the impact
speed), the final energy over the initial one, the steps and the CPU
time per step (ms, of the time loop alone; the mean of the repeats), and the ratio of this
tree's CPU time to the baseline's.

    python benchmarks/mortar_coverage.py --baseline /tmp/base          # 3 repeats
    python benchmarks/mortar_coverage.py --quick  # the coarsest balls once, this tree alone
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from _common import ROOT, parser, publish_report

T_C = 6.2e-3  # Hertz's contact duration of each ball at 1 m/s, s

RUNS = (
    ("graded P1, spacing 0.16", {"spacing": 0.16, "rotate": 30.0}, "dx/c"),
    ("uniform P1, base 2", {"graded": 0, "base": 2, "rotate": 30.0}, "t_c/50"),
    ("uniform P1, base 2", {"graded": 0, "base": 2, "rotate": 0.0}, "t_c/50"),
    ("uniform P2, base 1", {"graded": 0, "base": 1, "element": "P2", "rotate": 30.0}, "t_c/50"),
    ("uniform P1, base 1 (coarsest)", {"graded": 0, "base": 1, "rotate": 30.0}, "dx/c"),
)

CHILD = """
import json, sys, time
import numpy as np
from fecontact import simulate
from fecontact.testing import case
from fecontact.time.stats import StepStats
params, step, t_c = json.loads(sys.argv[1]), sys.argv[2], float(sys.argv[3])
sim = case("two_balls").build(t_end=1.3 * t_c, **params)
dt = sim.dt if step == "dx/c" else t_c / 50
model = sim.model
A = model.bodies[0]
w = [A.mass_matrix() @ A.translation_field(np.eye(3)[k]) for k in range(3)]
energy = lambda s: model.kinetic_energy(s.v) + model.strain_energy(s.q)
cpu = time.process_time()
stats = StepStats()
states = list(simulate(model, dt, sim.t_end, sim.options, v0=sim.v0, stats=stats))
cpu = time.process_time() - cpu
v = np.array([[float(wk @ s.v[model.body_slice(0)]) / A.mass for wk in w] for s in states])
print(json.dumps({"lateral": float(np.max(np.hypot(v[:, 1], v[:, 2]))),
                  "exit": float(-v[-1, 0]), "energy": energy(states[-1]) / energy(states[0]),
                  "steps": len(states) - 1, "cpu": cpu}))
"""


def child(tree: Path, params: dict, step: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", CHILD, json.dumps(params), step, str(T_C)], env=env,
                         cwd=tree, capture_output=True, text=True, check=True)  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", help="source tree of the version to compare (default: none)")
    p.add_argument("--repeats", type=int, help="runs of each tree (default 3; --quick: 1)")
    p.add_argument("--runs", type=int, nargs="*", help="indices of the runs (default: all)")
    args = p.parse_args()
    if args.repeats is None:  # quick: a check that the script runs, no timing to average
        args.repeats = 1 if args.quick else 3
    runs = RUNS[-1:] if args.quick else RUNS
    runs = [runs[i] for i in args.runs] if args.runs else runs
    trees = (("this", ROOT),)
    if args.baseline:
        trees = (("baseline", Path(args.baseline).resolve()), *trees)
    rows = []
    for mesh, params, step in runs:
        cpu = {name: [] for name, _ in trees}
        result = {}
        for _ in range(args.repeats):
            for name, tree in trees:  # alternated: both versions under the same load
                result[name] = child(tree, params, step)
                cpu[name].append(result[name]["cpu"])
        base = sum(cpu[trees[0][0]]) / args.repeats
        for name, _ in trees:
            r = result[name]
            mean = sum(cpu[name]) / len(cpu[name])
            rows.append(
                {
                    "mesh": mesh,
                    "turned (deg)": params["rotate"],
                    "step": step,
                    "version": name,
                    "lateral / v": r["lateral"],
                    "exit speed / v": r["exit"],
                    "E_end/E_0": r["energy"],
                    "steps": r["steps"],
                    "CPU ms per step": 1e3 * mean / r["steps"],
                    "CPU ratio": mean / base,
                }
            )
            print(rows[-1], flush=True)
    publish_report(
        args.out, "mortar_coverage", args.quick,
        "3D mortar, partly covered triangles, against a baseline", rows,
        ("Two elastic balls head-on (cases/two_balls.py), 1 m/s each.", rows),
    )  # fmt: skip


if __name__ == "__main__":
    main()
