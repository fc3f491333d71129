"""What friction costs the frictionless runs: the same cases timed on two revisions, side by
side in one run.

Revisions (default): the last one before friction and the one that added it. Each is checked
out into a temporary git worktree and imported in its own process; the cases alternate
between the two, ``--repeats`` times, and each process keeps the fastest of three passes, so
that the machine's noise hits both alike. Reported: the fastest time of each revision and
their ratio.

    python benchmarks/friction_cost.py [--before REV] [--after REV] [--repeats N]
    python benchmarks/friction_cost.py --quick   # this checkout against itself, tiny runs
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import RESULTS, ROOT, markdown_table, parser, write_markdown

CASES = [
    ("flexible_pendulum", {}, 3.0),
    ("rocking_block", {}, 2.0),
    ("two_disks", {"refinements": 2}, 0.006),
    ("bouncing_ball", {}, 2.0),
]
QUICK_CASES = [
    ("flexible_pendulum", {}, 0.01),
    ("rocking_block", {}, 0.01),
    ("two_disks", {"refinements": 1}, 2e-4),
    ("bouncing_ball", {}, 0.01),
]
TIMER = """
import json, sys, time
from fecontact.testing import case
from fecontact.time import simulate
name, kw, t_end = sys.argv[1], json.loads(sys.argv[2]), float(sys.argv[3])
sim = case(name).build(**kw)
best = float("inf")
for _ in range(3):
    start = time.perf_counter()
    for st in simulate(sim.model, sim.dt, t_end, sim.options, q0=sim.q0, v0=sim.v0):
        pass
    best = min(best, time.perf_counter() - start)
print(best)
"""


def timed(tree: Path, name: str, kw: dict, t_end: float) -> float:
    env = {"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin", "OPENBLAS_NUM_THREADS": "1"}
    out = subprocess.run(
        [sys.executable, "-c", TIMER, name, json.dumps(kw), str(t_end)],
        cwd=tempfile.gettempdir(),
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    return float(out.stdout.strip().splitlines()[-1])


def compare(trees: dict, cases, repeats: int) -> list[dict]:
    """The fastest time of each case with each tree, alternating ``repeats`` times."""
    rows = []
    for name, kw, t_end in cases:
        best = {"before": float("inf"), "after": float("inf")}
        for _ in range(repeats):
            for label, tree in trees.items():
                best[label] = min(best[label], timed(tree, name, kw, t_end))
        rows.append({"case": name, **best, "after / before": best["after"] / best["before"]})
        print(rows[-1], flush=True)
    return rows


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--before", default="b8e245b", help="revision without friction")
    p.add_argument("--after", default="391885c", help="revision with friction")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    if args.quick:
        args.before = args.after = "this checkout (--quick)"
        args.repeats = 1
        rows = compare({"before": ROOT, "after": ROOT}, QUICK_CASES, 1)
    else:
        with tempfile.TemporaryDirectory() as tmp:
            trees = {}
            for label in ("before", "after"):
                trees[label] = Path(tmp) / label
                rev = getattr(args, label)
                git = ["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach"]
                subprocess.run([*git, str(trees[label]), rev], check=True)
            try:
                rows = compare(trees, CASES, args.repeats)
            finally:
                for tree in trees.values():
                    git = ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)]
                    subprocess.run(git)
    table = markdown_table(rows, ["case", "before", "after", "after / before"])
    print(table)
    head = (
        f"# Cost of friction on frictionless runs\n\nRevisions {args.before} (before) and "
        f"{args.after} (after); fastest of {args.repeats} x 3 passes, in s.\n\n"
    )
    stem = "friction_cost_quick" if args.quick else "friction_cost"
    write_markdown(Path(args.out or RESULTS) / f"{stem}.md", head + table)


if __name__ == "__main__":
    main()
