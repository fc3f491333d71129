"""2D mortar with its pointwise safeguard: how deep nodes sink, and what it costs.

Two elastic disks (``cases/two_disks.py``, refinements 2, mortar) thrown at each other at 5, 10
and 30 m/s each, stepped at 1, 2, 4 and 8 Δx/c, and the shipped head-on impact (1 m/s) at the
case's step. Each run is made in a child process, alternating this source tree and a
``--baseline`` tree (another version of fecontact, e.g. ``git archive`` of the previous commit
unpacked in a folder), so that both versions meet the same machine load. Per run: the deepest
boundary node of the slave disk inside the master disk, and of the master's inside the slave,
over the local boundary edge (an inside/outside test by ray parity on the boundary polygons,
independent of the solver), the largest energy excess over the initial one, the steps and the CPU
time per step (ms, of the time loop; the mean of the repeats), and the CPU ratio to the
baseline.

    python benchmarks/mortar_safeguard.py --baseline /tmp/base      # 3 repeats
    python benchmarks/mortar_safeguard.py --quick                   # one run, this tree alone
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from _common import ROOT, parser, publish_report

RUNS = [(v, c) for v in (5.0, 10.0, 30.0) for c in (1, 2, 4, 8)] + [(1.0, 0)]

CHILD = """
import json, sys, time
import numpy as np
from fecontact import simulate
from fecontact.scenes import wave_step
from fecontact.testing import case

def depth_over_edge(p, a, b):
    x, y = p[:, None, 0], p[:, None, 1]
    straddle = (a[None, :, 1] > y) != (b[None, :, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (y - a[None, :, 1]) / (b[None, :, 1] - a[None, :, 1])
    inside = np.sum(straddle & (a[None, :, 0] + t * (b[None, :, 0] - a[None, :, 0]) > x), 1) % 2
    d, w = b - a, p[:, None, :] - a[None]
    xi = np.clip(np.einsum("pei,ei->pe", w, d) / np.sum(d * d, axis=1), 0.0, 1.0)
    dist = np.linalg.norm(w - xi[:, :, None] * d[None], axis=2)
    e = np.argmin(dist, axis=1)
    return np.where(inside == 1, dist[np.arange(len(p)), e], 0.0) / np.linalg.norm(d[e], axis=1)

velocity, courant = float(sys.argv[1]), int(sys.argv[2])
if courant:
    sim = case("two_disks").build(velocity=velocity, refinements=2, t_end=0.006)
    dt = wave_step(sim.model.bodies[0], courant)
else:  # the shipped impact at its own step
    sim = case("two_disks").build(refinements=2)
    dt = sim.dt
model = sim.model
cpu = time.process_time()
states = list(simulate(model, dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0))
cpu = time.process_time() - cpu
deepest = [0.0, 0.0]
for st in states:
    for n, (i, j) in enumerate(((0, 1), (1, 0))):
        bi, bj = model.bodies[i], model.bodies[j]
        xi = bi.positions(st.q[model.body_slice(i)])[bi.boundary_nodes()]
        xj = bj.positions(st.q[model.body_slice(j)])
        s = bj.boundary_facets()
        deepest[n] = max(deepest[n], float(np.max(depth_over_edge(xi, xj[s[:, 0]], xj[s[:, 1]]))))
energy = [model.kinetic_energy(s.v) + model.strain_energy(s.q) for s in states]
print(json.dumps({"slave": deepest[0], "master": deepest[1], "energy": max(energy) / energy[0],
                  "steps": len(states) - 1, "cpu": cpu}))
"""


def child(tree: Path, velocity: float, courant: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", CHILD, str(velocity), str(courant)], env=env,
                         cwd=tree, capture_output=True, text=True, check=True)  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", help="source tree of the version to compare (default: none)")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    runs = [(30.0, 1)] if args.quick else RUNS
    repeats = 1 if args.quick else args.repeats
    trees = (("this", ROOT),)
    if args.baseline:
        trees = (("baseline", Path(args.baseline).resolve()), *trees)
    rows = []
    for velocity, courant in runs:
        cpu = {name: [] for name, _ in trees}
        result = {}
        for _ in range(repeats):
            for name, tree in trees:  # alternated: both versions under the same load
                result[name] = child(tree, velocity, courant)
                cpu[name].append(result[name]["cpu"])
        base = sum(cpu[trees[0][0]]) / repeats
        for name, _ in trees:
            r, mean = result[name], sum(cpu[name]) / repeats
            rows.append(
                {
                    "speed (m/s)": velocity,
                    "step (dx/c)": courant or "case",
                    "version": name,
                    "slave in master / edge": r["slave"],
                    "master in slave / edge": r["master"],
                    "max E / E_0 - 1": r["energy"] - 1.0,
                    "steps": r["steps"],
                    "CPU ms per step": 1e3 * mean / r["steps"],
                    "CPU ratio": mean / base,
                }
            )
            print(rows[-1], flush=True)
    publish_report(
        args.out, "mortar_safeguard", args.quick,
        "2D mortar and its pointwise safeguard, against a baseline", rows,
        ("Two elastic disks thrown at each other (cases/two_disks.py, refinements 2).", rows),
    )  # fmt: skip


if __name__ == "__main__":
    main()
