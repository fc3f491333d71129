"""How far p and k move a trajectory, and how far it is from the same run at a fine step.

Each row runs its simulation at the default augmentation, at p × 1e-3 and × 1e3 and at
k ÷ 100 and × 100, and at h/8 (and h/16 where cheap). The trajectory is each body's centre
of mass (position over the model's length, velocity over the largest centre speed), read at
the coarse steps. Printed: the largest change of the p and k variants from the default, and
the default's distance to the h/8 and h/16 runs.

    python benchmarks/pk_active_set.py [--rows NAME ...] [--quick] [--out DIR]

Writes the printed lines to ``pk_active_set.md`` in the output folder.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import parser, write_markdown  # noqa: E402

from fecontact import SolverError  # noqa: E402
from fecontact.testing import load_case  # noqa: E402
from fecontact.time.simulate import simulate  # noqa: E402

VARIANTS = (
    ("p x1e-3", {"penalty_scale": 1e-3}),
    ("p x1e3", {"penalty_scale": 1e3}),
    ("k /100", {"multiplier_scale": 1e-2}),
    ("k x100", {"multiplier_scale": 1e2}),
)


def oblique_disks():
    from stress_2d import cell_speed, two_disks

    sim, _ = two_disks(speed=cell_speed(1, 8), courant=8, offset=0.05 * 0.3)
    return sim


def corner_drop():
    from stress_3d import box_on_slab

    return box_on_slab(1.0).sim


def box_on_box():
    from stress_3d import box_on_box as build

    return build().sim


def frictional_disks():
    from stress_2d import two_disks

    sim, _ = two_disks(offset=0.05 * 0.3, e=0.5, mu=0.3)
    return sim


ROWS = {
    "oblique disks 8 dx/c": (oblique_disks, (8, 16)),
    "corner-first drop": (corner_drop, (8,)),
    "two_disks": (lambda: load_case("two_disks").build(), (8, 16)),
    "ball_drop": (lambda: load_case("ball_drop").build(), (8, 16)),
    "box on box": (box_on_box, (8,)),
    "frictional disks": (frictional_disks, (8,)),
}


def centres(model):
    """(weights (bodies × dim, n)) of each body's centre of mass along each axis."""
    M = model.M_full
    rows = []
    for b in model.bodies:
        for axis in np.eye(model.dim):
            t = model.translation(b, axis)
            rows.append(M @ t / float(t @ M @ t))
    return np.array(rows)


def trajectory(sim, refine=1, **options):
    """(centre positions, velocities) at the coarse steps, completed, step halvings."""
    opts = dataclasses.replace(sim.options, **options)
    W = centres(sim.model)
    xs, vs, halvings, done = [], [], 0, True
    try:
        states = simulate(sim.model, sim.dt / refine, sim.t_end, opts, q0=sim.q0, v0=sim.v0)
        for i, st in enumerate(states):
            halvings += st.halvings
            if i % refine == 0:
                xs.append(W @ st.q)
                vs.append(W @ st.v)
    except SolverError:
        done = False
    return np.array(xs), np.array(vs), done, halvings


def distance(a, b, length, speed):
    n = min(len(a[0]), len(b[0]))
    dx = np.max(np.abs(a[0][:n] - b[0][:n]), initial=0.0) / length
    dv = np.max(np.abs(a[1][:n] - b[1][:n]), initial=0.0) / speed
    return dx, dv, n


def main(argv=None):
    ap = parser("p, k and the fine step on the smooth step's active set")
    ap.add_argument("--rows", nargs="*", default=list(ROWS))
    ap.add_argument("--no-fine", action="store_true")
    ap.add_argument("--no-pk", action="store_true")
    args = ap.parse_args(argv)
    lines = []

    def say(line):
        print(line, flush=True)
        lines.append(line)

    if args.quick:  # (a check that the script runs: one cheap row, no fine step)
        args.rows, args.no_fine = ["ball_drop"], True
    for name in args.rows:
        build, fines = ROWS[name]
        sim = build()
        t0 = time.time()
        base = trajectory(sim)
        length, speed = sim.model.length, max(np.max(np.abs(base[1])), 1e-300)
        say(f"{name}: {len(base[0])} states, completed {base[2]}, "
            f"{base[3]} halvings, {time.time() - t0:.0f} s")  # fmt: skip
        if not args.no_pk:
            for label, opts in VARIANTS:
                other = trajectory(sim, **opts)
                dx, dv, n = distance(base, other, length, speed)
                say(f"  {label:8s} dq/L {dx:.2e} dv/v {dv:.2e} ({n} states, "
                    f"completed {other[2]}, {other[3]} halvings)")  # fmt: skip
        if not args.no_fine:
            for r in fines:
                fine = trajectory(sim, refine=r)
                dx, dv, n = distance(base, fine, length, speed)
                say(f"  h/{r:<6d} dq/L {dx:.2e} dv/v {dv:.2e} ({n} states, "
                    f"completed {fine[2]}, {fine[3]} halvings)")  # fmt: skip

    text = "# p, k and the smooth step's active set\n\n```\n" + "\n".join(lines) + "\n```"
    write_markdown(Path(args.out) / "pk_active_set.md", text)


if __name__ == "__main__":
    main()
