"""Cost of contact-free steps against an earlier revision, side by side.

Bodies in flight, with contacts defined but none near: the dropped 3D ball (refinements 3,
2499 dofs, linear), two disks 5 cm apart (580 dofs, Neo-Hookean) and the founding pendulum
before its first impact. Each run is timed in a fresh process (best of 3 inside it), with
this checkout, with each ``--baseline REV`` checked out into a temporary git worktree, and
with this checkout again (the noise of the same code against itself), alternating, ``--rounds``
times; the table gives the fastest of each (the cost without the machine's noise) and the
ratios this / baseline, and this / this again.

    python benchmarks/free_flight_cost.py --baseline c018344      # about a minute
    python benchmarks/free_flight_cost.py --baseline 21d058e --baseline 76a9bc8 --rounds 7
    python benchmarks/free_flight_cost.py --quick    # this checkout against itself, tiny runs
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import RESULTS, ROOT, markdown_table, parser, write_markdown

# (case, build parameters, t_end (s), step (s)): no contact within the run
RUNS = [
    ("ball_drop", {"drop_height": 10.0, "refinements": 3}, 0.3, 5e-5),
    ("two_disks", {"gap": 0.05}, 0.005, 2e-5),
    ("flexible_pendulum", {}, 0.25, 2.5e-4),
]
QUICK_RUNS = [
    ("ball_drop", {"drop_height": 10.0, "refinements": 0}, 1e-3, 5e-5),
    ("two_disks", {"gap": 0.05, "refinements": 1}, 2e-4, 2e-5),
    ("flexible_pendulum", {}, 5e-3, 2.5e-4),
]

TIMER = """
import json, sys, time
from fecontact.testing import case
from fecontact.time import simulate
name, kw, t_end, dt = sys.argv[1], json.loads(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
sim = case(name).build(**kw)
best = float("inf")
for _ in range(3):
    start = time.perf_counter()
    for st in simulate(sim.model, dt, t_end, sim.options, q0=sim.q0, v0=sim.v0):
        assert not (st.impulse.any() or st.nu.any()), "a contact closed"
    best = min(best, time.perf_counter() - start)
print(best)
"""


def timed(tree: Path, run) -> float:
    name, kw, t_end, dt = run
    env = dict(os.environ, PYTHONPATH=str(tree))
    args = [sys.executable, "-c", TIMER, name, json.dumps(kw), str(t_end), str(dt)]
    out = subprocess.run(args, env=env, cwd=tree, capture_output=True, text=True, check=True)
    return float(out.stdout.split()[-1])


def compare(bases: dict, runs, rounds: int) -> list[dict]:
    """The fastest time of each run with this checkout (twice: its noise) and with each tree
    of ``bases`` (name: path), alternating ``rounds`` times."""
    rows = []
    trees = {"this": ROOT, **bases, "this again": ROOT}
    for run in runs:
        times = {name: [] for name in trees}
        for _ in range(rounds):
            for name, tree in trees.items():
                times[name].append(timed(tree, run))
        best = {name: min(t) for name, t in times.items()}
        row = {"case": run[0], "this_s": best["this"]}
        for name in bases:
            row[f"{name}_s"] = best[name]
            row[f"this / {name}"] = best["this"] / best[name]
        row["this / this again"] = best["this"] / best["this again"]
        rows.append(row)
    return rows


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument(
        "--baseline",
        action="append",
        help="git revision to compare with (repeatable; not with --quick)",
    )
    p.add_argument("--rounds", type=int, default=3)
    args = p.parse_args()
    if args.quick:
        args.baseline, rows = ["this checkout (--quick)"], compare({}, QUICK_RUNS, 1)
    elif not args.baseline:
        p.error("--baseline REV is required (or --quick)")
    else:
        with tempfile.TemporaryDirectory(prefix="fecontact_baseline_") as tmp:
            bases = {rev: Path(tmp) / rev for rev in args.baseline}
            for rev, tree in bases.items():
                subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach",
                                str(tree), rev], check=True)  # fmt: skip
            try:
                rows = compare(bases, RUNS, args.rounds)
            finally:
                for tree in bases.values():
                    subprocess.run(
                        ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)]
                    )
    table = markdown_table(rows, list(rows[0]))
    print(table)
    title = f"# Contact-free steps against {', '.join(args.baseline)}\n\n"
    stem = "free_flight_cost_quick" if args.quick else "free_flight_cost"
    write_markdown(f"{args.out or RESULTS}/{stem}.md", title + table)


if __name__ == "__main__":
    main()
