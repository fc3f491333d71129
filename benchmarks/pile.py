"""A pile of N rigid disks dropped into a box: CPU per step with the disk pairs evaluated one
by one (a baseline revision) and together (this checkout), the results side by side.

Every disk holds a contact with the floor and the two walls and every two disks one (e_N 0.5,
μ 0.3, h = 1 ms): 3N + N(N − 1)/2 pairs. Both checkouts run the same model, each in its own
interpreter with its package on PYTHONPATH, one after the other (so that they do not share the
cores): CPU ms per step, and the run's status, depth, created/scale, least-squares
multipliers and halvings. A second pass keeps the positions of every step and compares them:
the largest |q_new − q_base| over the run, relative to the largest |q|.

    python benchmarks/pile.py [--quick] [--baseline REV] [--out DIR]

``--baseline`` defaults to the last revision whose contact set evaluated every pair alone.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import ROOT, export, parser, publish_report

# (N, end time in s): the larger piles cut short, the per-pair baseline being slow
FULL = [(4, 0.5), (9, 0.5), (16, 0.5), (36, 0.2), (64, 0.1)]
QUICK = [(4, 0.02), (9, 0.02)]
BASELINE = "019fd40"

# builds the pile, runs it (timed, its summary) and steps it again to keep the positions; the
# model is written here, not imported, so that any revision of the package runs it
WORKER = """
import itertools, json, sys, time
import numpy as np
from fecontact import Model, Simulation, run
from fecontact.bodies import Disk, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.time import simulate

def pile(n, t_end):
    r = 0.05
    k = int(np.ceil(np.sqrt(n)))
    rng = np.random.default_rng(0)
    disks = []
    for i in range(n):
        x = (i % k - (k - 1) / 2) * 2.3 * r + rng.uniform(-0.005, 0.005)
        y = r + 0.02 + (i // k) * 2.3 * r
        disks.append(RigidBody2D.uniform(1.0, (x, y), Disk(r)))
    w = k * 1.3 * r + 0.02
    walls = [Plane([0, 0], [0, 1]), Plane([-w, 0], [1, 0]), Plane([w, 0], [-1, 0])]
    pairs = [(d, o) for d in disks for o in walls] + list(itertools.combinations(disks, 2))
    contacts = [Contact(a, b, restitution=0.5, friction=0.3) for a, b in pairs]
    model = Model(disks, contacts, (0.0, -9.81))
    return Simulation(model, dt=1e-3, t_end=t_end, name=f"pile{n}")

cases, folder = json.loads(sys.argv[1]), sys.argv[2]
out = []
for n, t_end in cases:
    sim = pile(n, t_end)
    start = time.process_time()
    s = run(sim, f"{folder}/run{n}", frames=False)
    cpu = time.process_time() - start
    ledger = s["energy_ledger"]
    states = simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    np.save(f"{folder}/q{n}.npy", np.array([st.q for st in states]))
    out.append({
        "pairs": len(sim.model.contacts.pairs), "steps": s["steps"],
        "ms": 1e3 * cpu / s["steps"], "status": s["status"], "depth": s["max_penetration"],
        "created": ledger["created"] / ledger["scale"],
        "least_squares": s["least_squares_multipliers"], "halvings": s["step_halvings"],
    })
print(json.dumps(out))
"""


def measure(tree: Path, cases, folder: Path) -> list:
    """The worker's rows for ``cases`` with the package of ``tree``."""
    folder.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    args = [sys.executable, "-c", WORKER, json.dumps(cases), str(folder)]
    done = subprocess.run(args, env=env, cwd=tree, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def moved(base: Path, new: Path, n: int) -> float:
    """max |q_new − q_base| over the steps and dofs, relative to max |q_base|."""
    import numpy as np

    a, b = np.load(base / f"q{n}.npy"), np.load(new / f"q{n}.npy")
    if a.shape != b.shape:
        return float("nan")
    return float(np.abs(b - a).max() / max(np.abs(a).max(), 1e-300))


def rows_of(cases, before, after, base: Path, new: Path) -> list:
    rows = []
    for (n, t_end), b, a in zip(cases, before, after, strict=True):
        rows.append(
            {
                "N": n,
                "pairs": a["pairs"],
                "t_end (s)": t_end,
                "steps": a["steps"],
                "ms/step before": b["ms"],
                "ms/step after": a["ms"],
                "ratio": b["ms"] / a["ms"],
                "status": a["status"] if a["status"] == b["status"] else "differs",
                "depth (m)": a["depth"],
                "created/scale": a["created"],
                "least squares": a["least_squares"],
                "halvings": a["halvings"],
                "positions moved (rel.)": moved(base, new, n),
            }
        )
    return rows


def main(argv=None) -> int:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", default=BASELINE, help="git revision (default: %(default)s)")
    args = p.parse_args(argv)
    cases = QUICK if args.quick else FULL
    with tempfile.TemporaryDirectory(prefix="fecontact_pile_") as tmp:
        tmp = Path(tmp)
        base_tree = export(args.baseline, tmp / "tree")
        before = measure(base_tree, cases, tmp / "base")
        after = measure(ROOT, cases, tmp / "new")
        rows = rows_of(cases, before, after, tmp / "base", tmp / "new")
    caption = (
        f"CPU ms per step of the pile with the pairs evaluated one by one ({args.baseline}) "
        "and together (this checkout); the correctness columns are this checkout's, the last "
        "the largest change of a position over the run against the baseline's."
    )
    publish_report(args.out, "pile", args.quick, "Pile of rigid disks", rows, (caption, rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
