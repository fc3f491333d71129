"""Rigid balls in space on a floor: CPU per step with the ball pairs evaluated one by one (a
baseline revision) and together (this checkout), and the largest change of a position.

Every ball holds a contact with the floor and every two balls one (e_N 0.5, h = 1 ms, balls
of 5 cm and 1 kg): a 3 × 3 grid dropped 1 cm, columns of 6 and 12 balls 1 cm apart, a
4 × 4 × 2 heap, with μ 0.3 and without friction. Both checkouts run the same models, each in
its own interpreter with its package on PYTHONPATH, alternated run by run (so that a change of
load hits both alike; the smallest CPU of the repeats is kept). Each run keeps the positions of
every step, and the two are compared step by step: the largest |q_after − q_before| over the
steps and dofs (0: the same to the last bit) and the number of steps where any differs.

    python benchmarks/ball_batches.py [--quick] [--baseline REV] [--out DIR]

``--baseline`` defaults to the last revision whose contact set evaluated every ball pair alone.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from _common import ROOT, export, parser, publish_report

# (layout, μ, end time in s)
FULL = [
    ("grid3", 0.3, 0.3),
    ("column6", 0.3, 0.3),
    ("column12", 0.3, 0.3),
    ("heap", 0.3, 0.2),
    ("heap", 0.0, 0.2),
]
QUICK = [("grid3", 0.3, 0.02), ("column6", 0.3, 0.02)]
BASELINE = "6f14086"
REPEATS = 2

# builds a layout, steps it (timed) and keeps the positions of every step; the model is
# written here, not imported, so that any revision of the package runs it
WORKER = """
import itertools, json, sys, time
import numpy as np
from fecontact import Model
from fecontact.bodies import Ball, RigidBody3D
from fecontact.contact import Contact, Plane
from fecontact.time import simulate

def layout(kind, mu):
    r = 0.05
    rng = np.random.default_rng(0)
    if kind == "grid3":
        cells, middle = [(i, j, 0) for i in range(3) for j in range(3)], 1.0
    elif kind == "heap":
        cells, middle = [(i, j, k) for k in range(2) for i in range(4) for j in range(4)], 1.5
    else:  # a column: nearly on one vertical
        cells, middle = [(0, 0, k) for k in range(int(kind[6:]))], 0.0
    balls = []
    for i, j, k in cells:
        shift = rng.uniform(-0.005, 0.005, 2) * (0.2 if kind.startswith("column") else 1.0)
        x, y = (i - middle) * 2.3 * r + shift[0], (j - middle) * 2.3 * r + shift[1]
        balls.append(RigidBody3D.uniform(1.0, (x, y, r + 0.01 + 2.2 * r * k), Ball(r)))
    floor = Plane([0, 0, 0], [0, 0, 1])
    pairs = [(b, floor) for b in balls] + list(itertools.combinations(balls, 2))
    contacts = [Contact(a, b, restitution=0.5, friction=mu) for a, b in pairs]
    return Model(balls, contacts, (0.0, 0.0, -9.81))

(kind, mu, t_end), path = json.loads(sys.argv[1]), sys.argv[2]
model = layout(kind, mu)
start = time.process_time()
states = list(simulate(model, 1e-3, t_end))
cpu = time.process_time() - start
np.save(path, np.array([st.q for st in states]))
units = [type(u).__name__ for u in getattr(model.contacts, "units", model.contacts.pairs)]
print(json.dumps({"steps": len(states) - 1, "ms": 1e3 * cpu / (len(states) - 1),
                  "pairs": len(model.contacts.pairs), "units": len(units)}))
"""


def measure(tree: Path, case, path: Path) -> dict:
    """The worker's row for ``case`` with the package of ``tree``; positions into ``path``."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    args = [sys.executable, "-c", WORKER, json.dumps(case), str(path)]
    done = subprocess.run(args, env=env, cwd=tree, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def compared(before: Path, after: Path):
    """(max |q_after − q_before| over the steps and dofs, steps where any differs)."""
    a, b = np.load(before), np.load(after)
    if a.shape != b.shape:
        return float("nan"), -1
    diff = np.abs(b - a).max(axis=1)
    return float(diff.max()), int(np.count_nonzero(diff))


def row_of(case, tmp: Path, trees: dict, repeats: int) -> dict:
    kind, mu, t_end = case
    runs = {name: [] for name in trees}
    for k in range(repeats):  # alternated: a change of load hits both alike
        for name, tree in trees.items():
            runs[name].append(measure(tree, case, tmp / f"{name}_{kind}_{mu}_{k}.npy"))
    before, after = runs["before"][0], runs["after"][0]
    ms_b = min(r["ms"] for r in runs["before"])
    ms_a = min(r["ms"] for r in runs["after"])
    worst, steps = compared(tmp / f"before_{kind}_{mu}_0.npy", tmp / f"after_{kind}_{mu}_0.npy")
    return {
        "layout": kind,
        "mu": mu,
        "pairs": after["pairs"],
        "units after": after["units"],
        "t_end (s)": t_end,
        "steps": after["steps"] if after["steps"] == before["steps"] else -1,
        "ms/step before": ms_b,
        "ms/step after": ms_a,
        "ratio": ms_b / ms_a,
        "max |dq|": worst,
        "steps differing": steps,
    }


def main(argv=None) -> int:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", default=BASELINE, help="git revision (default: %(default)s)")
    args = p.parse_args(argv)
    cases = QUICK if args.quick else FULL
    with tempfile.TemporaryDirectory(prefix="fecontact_balls_") as tmp:
        tmp = Path(tmp)
        trees = {"before": export(args.baseline, tmp / "tree"), "after": ROOT}
        rows = [row_of(case, tmp, trees, 1 if args.quick else REPEATS) for case in cases]
    caption = (
        f"CPU ms per step (the least of {1 if args.quick else REPEATS} alternated runs) with "
        f"the ball pairs evaluated one by one ({args.baseline}) and together (this checkout); "
        "max |dq| the largest change of a position (m, rad) at any step, 0 when every step "
        "is the same to the last bit."
    )
    publish_report(args.out, "ball_batches", args.quick, "Balls in space", rows, (caption, rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
