"""Whether a change of the code changed a result: the same runs on two checkouts, step by step.

A refactor must leave every number as it was. This script runs a list of cases under every
integrator and scheme the package has (NSGA with Newton's and Poisson's law, Moreau–Jean at
θ = ½, 0.51 and 1 and with Poisson's law, penalty, the energy-decaying step; with joints,
Rayleigh damping, friction, smooth contact, rotations in space) on this checkout and on an
earlier revision (``--baseline``, exported into a temporary folder), each checkout in its own
interpreter. Per step it hashes the positions q, velocities v, accelerations v̇ and a, the
joints' multipliers λ, the contact impulses and k ν, the gaps, the Newton, correction and
jump iterations, the halvings, and the frictional impulses and status; at the end the run's
counts (``StepStats.summary``, without its wall times). A run is identical when every step's
hash and the counts both checkouts record agree bit for bit (a count only one of them records
is not compared); otherwise the table names the first step that differs.

    python benchmarks/bit_identity.py [--quick] [--baseline REV] [--out DIR]

``--quick`` runs one case of each integrator and scheme for five steps and always exits 0 (CI:
it shows the script works, while the physics may since have changed on purpose); the full
runs are a refactor's evidence, and exit 1 where a run differs.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import export
from stepper_speed import write_table

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"

NSGA = {}
MOREAU = {"integrator": "moreau"}
PENALTY = {"integrator": "penalty"}
ENERGY = {"scheme": "energy-decaying"}
POISSON = {"impact_law": "poisson"}

# (case, its parameters, the options changed, end time in s; None: the case's own)
RUNS = [
    ("flexible_pendulum", {}, NSGA, 0.6),
    ("flexible_pendulum", {"restitution": 0.5}, {**MOREAU, "theta": 0.51}, 0.6),
    ("flexible_pendulum", {}, {**MOREAU, "theta": 1.0}, 0.6),
    ("flexible_pendulum", {}, PENALTY, 0.6),
    ("flexible_pendulum", {}, ENERGY, 0.6),
    ("flexible_pendulum", {"friction": 0.3}, NSGA, 0.6),
    ("flexible_pendulum", {"restitution": 0.5}, POISSON, 0.6),
    ("bouncing_ball", {}, NSGA, 1.5),
    ("bouncing_ball", {}, MOREAU, 1.5),
    ("bouncing_ball", {}, {**MOREAU, "theta": 1.0}, 1.5),
    ("bouncing_ball", {}, {**MOREAU, **POISSON}, 1.5),
    ("bouncing_ball", {}, PENALTY, 1.5),
    ("bouncing_ball", {}, {"localize": True}, 1.5),
    ("rigid_pendulum", {}, NSGA, 1.5),
    ("rigid_pendulum", {}, MOREAU, 1.5),
    ("rigid_pendulum", {}, {**MOREAU, "theta": 0.51}, 1.5),
    ("rigid_pendulum", {}, {**MOREAU, **POISSON}, 1.5),
    ("rigid_pendulum", {}, PENALTY, 1.5),
    ("rigid_pendulum", {}, POISSON, 1.5),
    ("kane_chain", {}, NSGA, 0.5),
    ("kane_chain", {}, MOREAU, 0.5),
    ("kane_chain", {}, POISSON, 0.5),
    ("kane_chain", {}, {**MOREAU, **POISSON}, 0.5),
    ("rocking_block", {}, NSGA, 0.8),
    ("rocking_block", {"friction": 0.5}, NSGA, 0.8),
    ("rocking_block", {"friction": 0.5}, MOREAU, 0.8),
    ("rocking_block", {}, PENALTY, 0.8),
    ("sliding_block", {}, NSGA, 0.3),
    ("sliding_block", {}, MOREAU, 0.3),
    ("rolling_disk", {}, NSGA, 0.5),
    ("rolling_disk", {}, MOREAU, 0.5),
    ("elastic_block", {"damping": 1e-4, "friction": 0.3}, NSGA, 0.004),
    ("elastic_block", {"damping": 1e-4}, MOREAU, 0.004),
    ("two_disks", {}, NSGA, 0.006),
    ("two_disks", {}, {"smooth_contact": "off"}, 0.006),
    ("two_disks", {"friction": 0.3}, NSGA, 0.006),
    ("two_disks", {}, MOREAU, 0.006),
    ("two_disks", {}, PENALTY, 0.006),
    ("disk_drop", {"friction": 0.3, "slide_velocity": 1.0}, NSGA, 0.006),
    ("impacting_bar", {}, NSGA, None),
    ("impacting_bar", {}, MOREAU, None),
    ("impacting_bar", {"kinematics": "exact"}, ENERGY, None),
    ("two_bars", {}, NSGA, None),
    ("disk_on_beam", {}, NSGA, 0.3),
    ("disk_on_beam", {}, MOREAU, 0.3),
    ("heavy_top", {}, NSGA, 0.05),
    ("tumbling_box", {}, NSGA, 0.4),
    ("spatial_pendulum", {"out_of_plane_velocity": 0.5}, NSGA, 0.6),
    ("rod_drop", {"yaw_rate": 20.0}, NSGA, 0.01),
    # (the solids whose impacts "auto" locates inside their steps, and a pair with localize=1)
    ("ball_drop", {}, NSGA, None),
    ("disk_drop", {}, NSGA, None),
    ("ball_on_slab", {}, NSGA, None),
    ("two_disks", {}, {"localize": True}, 0.006),
]
QUICK = [RUNS[i] for i in (0, 4, 9, 11, 15, 20, 33, 45)]
"""One run of each integrator and scheme, and of joints, friction, smooth contact and rotations."""

# runs every case of ``runs`` (JSON in argv) with the package this interpreter imports and
# prints, per run, the hash of every step and the run's counts
WORKER = """
import dataclasses, hashlib, json, sys
import numpy as np
from fecontact.cli.cases import load_case
from fecontact.time import simulate
from fecontact.time.stats import StepStats

def digest(st):
    h = hashlib.sha256()
    for x in (st.q, st.v, st.vd, st.a, st.lam, st.impulse, st.nu, st.gaps):
        h.update(np.ascontiguousarray(x, dtype=float).tobytes())
    h.update(json.dumps([st.iterations, st.halvings, st.retakes], sort_keys=True).encode())
    if st.friction is not None:
        h.update(np.ascontiguousarray(st.friction.impulse, dtype=float).tobytes())
        h.update(np.ascontiguousarray(st.friction.status).tobytes())
    return h.hexdigest()[:16]

def timeless(x):
    if isinstance(x, dict):
        return {k: timeless(v) for k, v in x.items() if "seconds" not in k}
    return x

runs, quick = json.loads(sys.argv[1]), sys.argv[2] == "1"
out = []
for case, params, changes, t_end in runs:
    sim = load_case(case).build(**params)
    opts = dataclasses.replace(sim.options, **changes)
    t_end = sim.t_end if t_end is None else t_end
    if quick:
        t_end = min(t_end, 5 * sim.dt)
    stats = StepStats()
    try:
        states = simulate(sim.model, sim.dt, t_end, opts, q0=sim.q0, v0=sim.v0, stats=stats)
        steps = [digest(st) for st in states]
        summary = timeless(stats.summary(sim.model.contacts.frictional))
        summary.pop("sparse_solver", None)
        # (numpy scalars among the counts: as plain numbers)
        counts = json.dumps(summary, sort_keys=True, default=lambda x: np.asarray(x).tolist())
        out.append({"steps": steps, "counts": counts})
    except Exception as err:
        out.append({"steps": [], "counts": "", "error": f"{type(err).__name__}: {err}"})
print(json.dumps(out))
"""


def start(tree: Path, runs: list, quick: bool) -> subprocess.Popen:
    """The worker over ``runs`` with the package of ``tree``, in a fresh interpreter."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    args = [sys.executable, "-c", WORKER, json.dumps(runs), "1" if quick else "0"]
    return subprocess.Popen(args, stdout=subprocess.PIPE, text=True, env=env, cwd=tree)


def compare(base: dict, new: dict) -> str:
    """'identical', or where the two runs part."""
    if "error" in base or "error" in new:
        return f"error: {base.get('error', 'baseline ran')} / {new.get('error', 'new ran')}"
    if len(base["steps"]) != len(new["steps"]):
        return f"step counts differ ({len(base['steps'])} against {len(new['steps'])})"
    for k, (a, b) in enumerate(zip(base["steps"], new["steps"], strict=True)):
        if a != b:
            return f"differs from step {k}"
    a, b = json.loads(base["counts"]), json.loads(new["counts"])
    # (a count one checkout has and the other has not is a new record, not a changed result)
    return "identical" if shared(a, b) == shared(b, a) else "counts differ"


def shared(a, b):
    """``a`` restricted to the keys ``b`` has too, at every level."""
    if isinstance(a, dict) and isinstance(b, dict):
        return {k: shared(v, b[k]) for k, v in a.items() if k in b}
    return a


def table(runs: list, verdicts: list, steps: list, baseline: str) -> str:
    lines = [
        f"Each run on this checkout against {baseline}: q, v, v̇, a, λ, impulses, k ν, gaps, "
        "iterations, halvings and friction of every step, and the run's counts.",
        "",
        "| case | parameters | options | steps | result |",
        "| --- | --- | --- | ---: | --- |",
    ]
    for (case, params, changes, _), verdict, n in zip(runs, verdicts, steps, strict=True):
        p = ", ".join(f"{k}={v}" for k, v in params.items()) or "-"
        o = ", ".join(f"{k}={v}" for k, v in changes.items()) or "nsga"
        lines.append(f"| {case} | {p} | {o} | {n} | {verdict} |")
    same = sum(v == "identical" for v in verdicts)
    lines += ["", f"{same} of {len(verdicts)} runs identical."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="five steps of each run")
    parser.add_argument("--baseline", default="b72420a", help="git revision to compare with")
    parser.add_argument("--out", default=str(RESULTS), help="output folder (default: %(default)s)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="fecontact_baseline_") as tmp:
        base_tree = export(args.baseline, Path(tmp))
        runs = QUICK if args.quick else RUNS
        workers = [start(tree, runs, args.quick) for tree in (base_tree, ROOT)]
        base, new = (json.loads(w.communicate()[0].strip().splitlines()[-1]) for w in workers)
    verdicts = [compare(b, n) for b, n in zip(base, new, strict=True)]
    text = table(runs, verdicts, [len(n["steps"]) - 1 for n in new], args.baseline)
    print(text)
    write_table(args.out, "bit_identity", args.quick, "Bit identity", text)
    return 0 if args.quick or all(v == "identical" for v in verdicts) else 1


if __name__ == "__main__":
    sys.exit(main())
