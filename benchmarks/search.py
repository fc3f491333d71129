"""Cost of the contact search without blind spots, against an earlier revision, side by side.

Three measurements, each run in a fresh process with this checkout and with ``--baseline REV``
(extracted by ``git archive`` into a temporary folder), alternating, ``--rounds`` times; the
tables give the fastest of each (the cost without the machine's noise) and their ratio:

- contact-free steps: two disks 5 cm apart (refinements 3, 580 dofs, Neo-Hookean, both
  node-to-surface pairs defined), the dropped 3D ball above its plane and the founding
  pendulum before its first impact: wall time of the time loop;
- the shipped ``two_disks`` through its impact (refinements 3, Δx/c, 6 ms): wall time of the
  loop and the share of its ``contact`` phase (gaps, search, corrections, jumps, and here the
  inside/outside test of every boundary node at every step);
- the fast approach: two disks (refinements 2, 0.5 mm apart) at 5, 10 and 30 m/s each with
  steps of 1, 2, 4 and 8 Δx/c (``--quick``: 10 m/s at 8 Δx/c): status, wall time, halvings,
  the deepest node inside the other disk at the end of any step (by a winding number of its
  own) and the largest energy excess.

    python benchmarks/search.py --baseline 21d058e            # a few minutes
    python benchmarks/search.py --baseline 21d058e --quick    # shorter runs, one round
    python benchmarks/search.py --quick                       # this checkout against itself
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

from _common import RESULTS, ROOT, markdown_table, parser, write_markdown

# (label, case, build parameters, t_end (s), step (s) or step in Δx/c (negative), kind)
RUNS = [
    ("disks 5 cm apart", "two_disks", {"gap": 0.05}, 0.005, 2e-5, "free"),
    ("3D ball above its plane", "ball_drop", {"drop_height": 10.0, "refinements": 2}, 0.1, 5e-5,
     "free"),
    ("pendulum before impact", "flexible_pendulum", {}, 0.25, 2.5e-4, "free"),
    ("two_disks impact", "two_disks", {}, 0.006, -1.0, "contact"),
]  # fmt: skip
# the fast approach: disks (refinements 2) 2 mm apart at 5, 10, 30 m/s each, 1..8 Δx/c (the
# case's default gap: a closer start is refused where the mortar gap stands off the surface)
FAST = [
    (f"{v:g} m/s, {f} dx/c", "two_disks", {"velocity": v, "refinements": 2, "gap": 0.002},
     0.006, -float(f), "fast")
    for v in (5.0, 10.0, 30.0) for f in (1, 2, 4, 8)
]  # fmt: skip

TIMER = """
import json, sys, time
import numpy as np
from fecontact.testing import case
from fecontact.time import PhaseTimer, simulate
from fecontact.scenes import wave_step
name, kw, t_end, dt = sys.argv[1], json.loads(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
repeats = int(sys.argv[5])
sim = case(name).build(**kw)
model = sim.model
if dt < 0:
    dt = wave_step(model.bodies[0], -dt)

def deepest(q):
    # deepest boundary node of a disk inside the other, by the winding number (2D pairs only)
    worst = 0.0
    for i, j in ((0, 1), (1, 0)):
        a, b = model.bodies[i], model.bodies[j]
        x = a.positions(q[model.body_slice(i)])[a.boundary_nodes()]
        y = b.positions(q[model.body_slice(j)])
        seg = b.boundary_facets()
        p, r = y[seg[:, 0]][None] - x[:, None], y[seg[:, 1]][None] - x[:, None]
        w = np.arctan2(p[..., 0] * r[..., 1] - p[..., 1] * r[..., 0], np.sum(p * r, -1))
        inside = w.sum(1) > np.pi
        d, e = y[seg[:, 1]] - y[seg[:, 0]], x[:, None] - y[seg[:, 0]][None]
        t = np.clip(np.einsum("pei,ei->pe", e, d) / np.sum(d * d, 1), 0, 1)
        dist = np.linalg.norm(e - t[..., None] * d[None], axis=2).min(1)
        worst = max(worst, float(np.max(np.where(inside, dist, 0.0))))
    return worst

best, out = float("inf"), {}
for _ in range(repeats):
    timer = PhaseTimer()
    start = time.perf_counter()
    halvings, depth, status, energy = 0, 0.0, "completed", []
    try:
        for st in simulate(model, dt, t_end, sim.options, timer, q0=sim.q0, v0=sim.v0):
            halvings += st.halvings
            if sys.argv[6] == "fast":
                depth = max(depth, deepest(st.q))
                energy.append(model.kinetic_energy(st.v) + model.strain_energy(st.q))
    except Exception as err:
        status = type(err).__name__
    wall = time.perf_counter() - start
    if wall < best:
        best = wall
        out = {"wall": wall, "contact": timer.get("contact", 0.0), "halvings": halvings,
               "depth": depth, "status": status,
               "excess": 100 * (max(energy) / energy[0] - 1) if energy else 0.0}
print(json.dumps(out))
"""


def timed(tree: Path, run, repeats: int) -> dict:
    _, name, kw, t_end, dt, kind = run
    env = dict(os.environ, PYTHONPATH=str(tree))
    args = [sys.executable, "-c", TIMER, name, json.dumps(kw), str(t_end), str(dt)]
    args += [str(repeats), kind]
    out = subprocess.run(args, env=env, cwd=tree, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def extract(revision: str, folder: Path) -> Path:
    """The package and cases of ``revision`` in ``folder`` (no git worktree is created)."""
    tar = subprocess.run(["git", "-C", str(ROOT), "archive", revision, "fecontact", "cases"],
                         capture_output=True, check=True).stdout  # fmt: skip
    with tarfile.open(fileobj=io.BytesIO(tar)) as t:
        t.extractall(folder, filter="data")
    return folder


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--baseline", help="git revision to compare with (--quick: this checkout)")
    p.add_argument("--rounds", type=int, default=3)
    args = p.parse_args()
    if args.baseline is None and not args.quick:
        p.error("--baseline REV is required (or --quick)")
    rounds, repeats = (1, 1) if args.quick else (args.rounds, 3)
    runs = [(*r[:3], r[3] / 5, *r[4:]) for r in RUNS] if args.quick else RUNS
    runs += [FAST[7]] if args.quick else FAST  # (10 m/s, 8 Δx/c)
    rows = {"free": [], "contact": [], "fast": []}
    with tempfile.TemporaryDirectory(prefix="fecontact_baseline_") as tmp:
        # --quick without a revision checks that the script runs: this checkout against itself
        base = ROOT if args.baseline is None else extract(args.baseline, Path(tmp))
        args.baseline = args.baseline or "this checkout"
        for run in runs:
            now, then = [], []
            for _ in range(rounds):
                then.append(timed(base, run, repeats))
                now.append(timed(ROOT, run, repeats))
            a, b = min(now, key=lambda r: r["wall"]), min(then, key=lambda r: r["wall"])
            row = {"run": run[0], "this_s": a["wall"], "baseline_s": b["wall"]}
            row["ratio"] = a["wall"] / b["wall"]
            if run[5] == "contact":
                row["this_contact_pct"] = 100 * a["contact"] / a["wall"]
                row["baseline_contact_pct"] = 100 * b["contact"] / b["wall"]
            if run[5] == "fast":
                for who, r in (("this", a), ("baseline", b)):
                    row[f"{who}_status"], row[f"{who}_halvings"] = r["status"], r["halvings"]
                    row[f"{who}_depth_m"] = r["depth"]
                    row[f"{who}_excess_pct"] = r["excess"]
            rows[run[5]].append(row)
            print(row, flush=True)
    text = [f"# Contact search against {args.baseline}" + (" (--quick)" if args.quick else "")]
    captions = {
        "free": "Contact-free steps: wall time of the time loop (s), fastest of the rounds.",
        "contact": "Through an impact: wall time (s) and the contact phase's share (%).",
        "fast": "Fast approach: wall time (s), status, halvings, the deepest node inside the "
        "other disk at the end of any step (m, winding number) and the largest energy "
        "excess over the initial energy (%).",
    }
    for kind, caption in captions.items():
        if rows[kind]:
            text += ["", caption, "", markdown_table(rows[kind], list(rows[kind][0]))]
    name = "search_quick.md" if args.quick else "search.md"
    write_markdown(f"{args.out or RESULTS}/{name}", "\n".join(text))


if __name__ == "__main__":
    main()
