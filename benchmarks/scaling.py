"""Time per step against the number of dofs, split into phases.

Series (each body starts with its lowest point on the plane y = 0 (z = 0 in 3D), moving toward
it at 1 m/s under gravity, so that every step has a contact to resolve; h = 1e-4 s, e_N = 0):

- ``beam``: a steel Beam2D (1 m, 20 mm × 10 mm) at 45° with 10 … 10⁴ elements, every node a
  contact candidate, default options (detection margin 5 % of the model size);
- ``beam, margin 1e-3``: the same with ``detection_margin=1e-3``, so that only the nodes near
  the contact end are candidates;
- ``2D solid``: a linear elastic disk (plane strain, P1 triangles, E = 10 MPa, ρ = 1000 kg/m³,
  R = 0.1 m, ``Solid.disk`` refined 1 … 7 times), boundary nodes against the plane;
- ``3D solid``: a linear elastic cube (0.1 m, same material, P1 tetrahedra) standing on a
  corner, its boundary nodes against the plane;
- ``3D ball, 100 steps``: ``cases/ball_drop.py`` (R = 0.05 m, same material, P1 tetrahedra,
  refinements 2, 3, 4) touching the plane at t = 0 at 1 m/s, 100 steps of the case's own step
  (an eighth of the transit time across the shortest edge), as
  ``python cases/ball_drop.py --set refinements=N --set drop_height=0 --dt DT --t-end 100DT``;
  the summary of the largest is kept in ``results/scaling_ball.json``.

Per size: the dofs, the contact candidates at t = 0, the model's construction time, and the
time per step of ``fecontact.run`` (no frames, no checkpoints) from ``summary.json``: total
(``time_per_step_s``: the time loop without output, over the steps), the part of it spent in
sparse factorizations (``sparse_factorizations``: once per run for the linear solids), the
steady time per step without them, and each ``phase_times_s`` entry (assembly, solve,
contact, output) / steps; medians of three runs, each on a freshly built model, when a run is
short. ``factor`` and ``fwd/bwd`` time one factorization of the iteration matrix
S = β′M + K through ``fecontact.linalg.factorize`` and one solve with its factors (median of
five), in the same process; ``steady / solve`` is their ratio. A series stops growing once a
size takes more than ``--max-step`` s per step.

    python benchmarks/scaling.py [--quick]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import json
import math
import statistics
import time

import numpy as np
import skfem

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact import (
    Beam2D,
    Contact,
    IntegratorOptions,
    Material,
    Model,
    Plane,
    Section,
    Simulation,
)
from fecontact.bodies.materials import LinearElastic
from fecontact.bodies.solid import Solid
from fecontact.linalg import factorize
from fecontact.time import alpha_coefficients

H = 1e-4
COLUMNS = [
    "series",
    "size",
    "dofs",
    "candidates",
    "steps",
    "build_s",
    "ms_per_step",
    "factorize_ms",
    "steady_ms",
    "assembly_ms",
    "solve_ms",
    "contact_ms",
    "output_ms",
    "other_ms",
    "newton_mean",
    "factor_ms",
    "fwd_bwd_ms",
    "steady_per_solve",
    "repeats",
    "status",
]
HEADERS = {
    "ms_per_step": "total ms/step",
    "factorize_ms": "of which factorizations",
    "steady_ms": "steady ms/step",
    "steady_per_solve": "steady / solve",
    "assembly_ms": "assembly",
    "solve_ms": "solve",
    "contact_ms": "contact",
    "output_ms": "output",
    "other_ms": "other",
    "newton_mean": "Newton/step",
    "factor_ms": "factor S (ms)",
    "fwd_bwd_ms": "fwd/bwd (ms)",
    "build_s": "build (s)",
}


def beam(n, margin=0.05):
    d = np.array([1.0, 1.0]) / math.sqrt(2.0)
    body = Beam2D.straight(
        [0.0, 0.0],
        list(d),
        n,
        Material(E=210e9, nu=0.3, rho=7850.0),
        Section.rectangle(0.02, 0.01),
    )
    model = Model([body], [Contact(body, Plane([0.0, 0.0], [0.0, 1.0]))])
    v0 = model.translation(body, (0.0, -1.0))
    return model, v0, IntegratorOptions(detection_margin=margin)


MATERIAL = LinearElastic(E=1e7, nu=0.3, rho=1000.0)


def disk(refinements):
    body = Solid.disk([0.0, 0.1], 0.1, refinements, MATERIAL)
    model = Model([body], [Contact(body, Plane([0.0, 0.0], [0.0, 1.0]))])
    return model, model.translation(body, (0.0, -1.0)), IntegratorOptions()


def cube(n):
    """A 0.1 m cube of n³ × 6 P1 tetrahedra standing on a corner (its diagonal vertical)."""
    axis = np.linspace(-0.05, 0.05, n + 1)
    mesh = skfem.MeshTet.init_tensor(axis, axis, axis)
    d = np.ones(3) / math.sqrt(3.0)  # rotate d onto e_z (Rodrigues)
    k = np.cross(d, [0.0, 0.0, 1.0])
    s, c = np.linalg.norm(k), d[2]
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]]) / s
    R = np.eye(3) + s * K + (1.0 - c) * K @ K
    p = R @ mesh.p
    p[2] -= p[2].min()
    body = Solid(skfem.MeshTet(p, mesh.t), MATERIAL)
    model = Model([body], [Contact(body, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]))])
    return model, model.translation(body, (0.0, 0.0, -1.0)), IntegratorOptions()


def ball(refinements):
    """``cases/ball_drop.py`` touching the plane at 1 m/s: (model, v0, options, dt)."""
    sim = common.case("ball_drop").build(refinements=refinements, drop_height=0.0)
    return sim.model, sim.v0, sim.options, sim.dt


def series(quick: bool):
    """(name, builder, sizes, steps(size), dofs(size)): the sizes are elements (beams),
    refinements (2D disk) and divisions per side (3D cube); dofs(size) estimates the model
    size before it is built."""
    beams = [10, 30] if quick else [10, 30, 100, 300, 1000, 3000, 10000]
    ball_steps = 10 if quick else 100

    def beam_steps(n):
        return 50 if n <= 1000 else 10

    def beam_dofs(n):
        return 3 * (n + 1)

    return [
        ("beam", beam, beams, beam_steps, beam_dofs),
        ("beam, margin 1e-3", lambda n: beam(n, 1e-3), beams, beam_steps, beam_dofs),
        (
            "2D solid",
            disk,
            [1] if quick else [1, 2, 3, 4, 5, 6, 7],
            lambda r: 20 if r < 6 else 5,
            lambda r: 4 * 4**r + 2 ** (r + 2),
        ),
        (
            "3D solid",
            cube,
            [2] if quick else [2, 4, 6, 9, 13, 19, 27],
            lambda n: 20 if n < 13 else 5,
            lambda n: 3 * (n + 1) ** 3,
        ),
        (
            "3D ball, 100 steps",
            ball,
            [2] if quick else [2, 3, 4],
            lambda r: ball_steps,
            lambda r: {2: 387, 3: 2499, 4: 18051}[r],
        ),
    ]


def factor_times(model, options, h):
    """(ms to factorize S = β′M + K at q = 0 as the integrator does, ms of one forward/backward
    solve with its factors: median of five)."""
    am, af, _, be = alpha_coefficients(options.rho_inf)
    bp = (1.0 - am) / (be * h * h * (1.0 - af))
    _, _, K = model.internal(np.zeros(model.n))
    S = model.iteration_sum(bp, K)
    t0 = time.perf_counter()
    solve = factorize(S, symmetric=True)
    t1 = time.perf_counter()
    b = np.ones(model.n_free)
    solves = []
    for _ in range(5):
        t2 = time.perf_counter()
        solve(b)
        solves.append(time.perf_counter() - t2)
    return 1e3 * (t1 - t0), 1e3 * statistics.median(solves)


def measure(name, build, size, steps):
    def make():
        made = build(size)
        model, v0, options = made[:3]
        h = made[3] if len(made) > 3 else H
        return Simulation(model, dt=h, t_end=steps * h, options=options, v0=v0, name="scaling")

    t0 = time.perf_counter()
    sim = make()
    build_s = time.perf_counter() - t0
    model, options = sim.model, sim.options
    gaps = model.contacts.gaps(np.zeros(model.n))
    candidates = int(np.sum(gaps <= options.detection_margin * model.length))
    runs = [common.timed_run(sim, repeats=1)]
    while len(runs) < 3 and runs[-1]["status"] == "completed" and runs[0]["wall"] < 5.0:
        runs.append(common.timed_run(make(), repeats=1))  # a fresh model: factors anew
    n = max(runs[0]["steps"], 1)

    def per_step(key):
        return 1e3 * statistics.median(r["phases"].get(key, 0.0) for r in runs) / n

    def factorizing(r):
        return r["summary"]["sparse_factorizations"]["seconds"]

    total = 1e3 * statistics.median(r["compute"] for r in runs) / n
    factorize_ms = 1e3 * statistics.median(factorizing(r) for r in runs) / n
    steady = 1e3 * statistics.median(r["compute"] - factorizing(r) for r in runs) / n
    phases = {k: per_step(k) for k in ("assembly", "solve", "contact", "output")}
    factor_ms, fwd_ms = factor_times(model, options, sim.dt)
    return {
        "series": name,
        "size": size,
        "dofs": model.n,
        "candidates": candidates,
        "steps": n,
        "build_s": build_s,
        "ms_per_step": total,
        "factorize_ms": factorize_ms,
        "steady_ms": steady,
        **{f"{k}_ms": v for k, v in phases.items()},
        "other_ms": total + phases["output"] - sum(phases.values()),
        "newton_mean": runs[0]["summary"]["newton_iterations_mean"],
        "factor_ms": factor_ms,
        "fwd_bwd_ms": fwd_ms,
        "steady_per_solve": steady / fwd_ms,
        **({"summary": runs[0]["summary"]} if name.startswith("3D ball") else {}),
        "repeats": len(runs),
        "status": runs[0]["status"],
    }


def plot(rows, path):
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(r["series"] for r in rows))
    fig, axes = plt.subplots(1, 1 + len(names), figsize=(3.8 * (1 + len(names)), 3.8))
    for name in names:
        sel = [r for r in rows if r["series"] == name]
        x = [r["dofs"] for r in sel]
        (line,) = axes[0].loglog(x, [r["ms_per_step"] for r in sel], "o-", label=name, ms=3)
        steady = [r["steady_ms"] for r in sel]
        axes[0].loglog(x, steady, "--", color=line.get_color(), lw=0.8)
    ref = np.array([1e2, 1e5])
    axes[0].loglog(ref, 1e-2 * ref, "k:", lw=0.8, label="∝ dofs")
    axes[0].set_title("time per step (dashed: without factorizations)", fontsize=9)
    for ax, name in zip(axes[1:], names, strict=True):
        sel = [r for r in rows if r["series"] == name]
        x = [r["dofs"] for r in sel]
        for key in ("assembly_ms", "solve_ms", "contact_ms", "output_ms", "factor_ms"):
            y = [max(r[key], 1e-4) for r in sel]
            style = "--" if key == "factor_ms" else "o-"
            label = "one factorization of S" if key == "factor_ms" else key[:-3]
            ax.loglog(x, y, style, label=label, ms=3)
        ax.set_title(name, fontsize=9)
    for ax in axes:
        ax.set_xlabel("dofs")
        ax.set_ylabel("ms per step")
        common.tidy_log_axes(ax)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=85)
    plt.close(fig)


def report(rows, note, path_stem):
    cols = [c for c in COLUMNS if c not in ("steps", "repeats")]
    md = common.markdown_table(rows, cols, [HEADERS.get(c, c) for c in cols])
    text = (
        f"# Time per step against dofs\n\n{note}\n\n"
        f"h = {H:g} s (the ball: its case's step); total = `time_per_step_s` of `summary.json` "
        "(the time loop without output, over the steps), of which sparse factorizations "
        "(`sparse_factorizations`); steady = total − factorizations; phases in ms per step "
        "(`phase_times_s` / steps; the factorizations fall in solve or contact); other = total "
        "− assembly − solve − contact (integrator bookkeeping, initial state); factor S and "
        "fwd/bwd: one factorization of S = β′M + K and one solve with it, timed in the same "
        "process; steady / solve: the ratio of the two; candidates: contacts within the "
        "detection margin at t = 0; a size is skipped when the previous one, scaled by dofs², "
        "predicts more than `--max-step` s per step.\n\n" + md
    )
    common.write_csv(f"{path_stem}.csv", rows, COLUMNS)
    balls = [r for r in rows if "summary" in r]
    if balls:  # the largest ball's summary.json, as the case writes it
        common.Path(f"{path_stem}_ball.json").write_text(
            json.dumps(balls[-1]["summary"], indent=1) + "\n"
        )
    common.write_markdown(f"{path_stem}.md", text)
    plot([r for r in rows if r["status"] == "completed"], f"{path_stem}.png")
    return md


def main(argv=None):
    p = common.parser(__doc__.splitlines()[0])
    p.add_argument(
        "--max-step", type=float, default=30.0, help="skip sizes predicted slower (s per step)"
    )
    p.add_argument("--series", action="append", help="run only these series (repeatable)")
    p.add_argument(
        "--update", action="store_true", help="replace those series' rows in the existing files"
    )
    args = p.parse_args(argv)
    out = common.Path(args.out)
    stem = out / ("scaling_quick" if args.quick else "scaling")
    note = common.machine_note()
    t0 = time.perf_counter()
    keep = []
    if args.update:
        keep = [r for r in common.read_csv(f"{stem}.csv") if r["series"] not in args.series]
        note += f"; series {', '.join(args.series)} re-run with `--update`"
    rows = []
    for name, build, sizes, steps, dofs in series(args.quick):
        if args.series and name not in args.series:
            continue
        prev = None
        for size in sizes:
            if prev is not None:
                guess = prev["ms_per_step"] * (dofs(size) / prev["dofs"]) ** 2 / 1e3
                if guess > args.max_step:
                    rows.append(
                        {
                            "series": name,
                            "size": size,
                            "dofs": dofs(size),
                            "status": f"skipped (predicted {guess:.0f} s/step)",
                        }
                    )
                    print(f"{name}: size {size} skipped, predicted {guess:.0f} s per step")
                    break
            row = measure(name, build, size, steps(size))
            rows.append(row)
            prev = row
            print(
                f"{name:18s} size {size:6d} dofs {row['dofs']:7d} cand {row['candidates']:5d} "
                f"{row['ms_per_step']:10.2f} ms/step (assembly {row['assembly_ms']:.2f}, solve "
                f"{row['solve_ms']:.2f}, contact {row['contact_ms']:.2f}, output "
                f"{row['output_ms']:.2f}) factor {row['factor_ms']:.1f} ms, build "
                f"{row['build_s']:.2f} s {row['status']}",
                flush=True,
            )
        elapsed = f"; {time.perf_counter() - t0:.0f} s so far."
        md = report(keep + rows, note + elapsed, stem)  # after every series: nothing lost
    print(md)
    return rows


if __name__ == "__main__":
    main()
