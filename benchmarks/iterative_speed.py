"""Time per step of the direct (SuperLU) and iterative (preconditioned CG, sparse solver "amg")
paths side by side, and the peak memory of a 255,552-dof ball with CG.

Series (the models of ``scaling.py``: a 0.1 m cube of P1 tetrahedra, E = 10 MPa, ν = 0.3,
ρ = 1000 kg/m³, standing on a corner and moving at 1 m/s toward the plane z = 0, h = 1e-4 s):

- ``3D solid, St Venant–Kirchhoff``: nonlinear, so the direct path factorizes S_t at every
  Newton iteration; 5 steps up to 8,232 dofs, 2 at 24,000 and 1 at 65,856;
- ``3D solid, linear``: the series of ``scaling.py`` (S factorized once per run), 5 steps;
- ``3D ball, 100 steps``: a linear ball (R = 0.05 m, same material) of 255,552 dofs, the cube
  of 43³ × 6 tetrahedra mapped radially onto the ball, touching the plane at 1 m/s, 100 steps
  of an eighth of the wave transit time across its shortest edge (the step rule of
  ``cases/ball_drop.py``), CG only (SuperLU needs hours and tens of GB here).

Every run is a fresh process (``fecontact.run`` without frames), so that its peak resident
memory (``ru_maxrss``) is its own. Per run: the dofs, the contact candidates at t = 0, the
model's construction time, ms per step (``time_per_step_s`` of ``summary.json``), Newton
iterations per step, sparse factorizations, the CG work (``iterative_solver``: solves, of
them preconditioned by the diagonal, iterations per solve, AMG setups, fallbacks), the
largest penetration, the final energy and the peak memory; per size the speed-up of CG.

    python benchmarks/iterative_speed.py [--quick]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np
import skfem

try:
    from . import _common as common
    from . import scaling
except ImportError:
    import _common as common
    import scaling

from fecontact import Contact, IntegratorOptions, Model, Plane, Simulation, run
from fecontact.bodies import LinearElastic, Solid, StVenantKirchhoff
from fecontact.linalg import use_sparse_solver
from fecontact.scenes import wave_step

H = 1e-4
RUBBER = {"E": 1e7, "nu": 0.3, "rho": 1000.0}
COLUMNS = [
    "series",
    "size",
    "solver",
    "dofs",
    "candidates",
    "steps",
    "build_s",
    "ms_per_step",
    "speedup",
    "newton_mean",
    "factorizations",
    "cg_solves",
    "diagonal_solves",
    "cg_iterations_per_solve",
    "amg_setups",
    "fallbacks",
    "max_penetration",
    "energy_final",
    "peak_rss_mb",
    "status",
]
HEADERS = {
    "build_s": "build (s)",
    "ms_per_step": "ms/step",
    "speedup": "direct / CG",
    "newton_mean": "Newton/step",
    "factorizations": "LU factorizations",
    "cg_solves": "CG solves",
    "diagonal_solves": "of which diagonal",
    "cg_iterations_per_solve": "iterations/solve",
    "amg_setups": "AMG setups",
    "max_penetration": "penetration (m)",
    "energy_final": "final energy (J)",
    "peak_rss_mb": "peak memory (MB)",
}

TITLES = [HEADERS.get(c, c) for c in COLUMNS]


def cube(n, nonlinear):
    scaling.MATERIAL = (StVenantKirchhoff if nonlinear else LinearElastic)(**RUBBER)
    model, v0, options = scaling.cube(n)
    return model, v0, options, H


def mapped_ball(n, radius=0.05):
    """A linear ball of the cube [−1, 1]³ in n³ × 6 tetrahedra, each point x moved to
    x |x|_∞ / |x|₂ (a bijection onto the unit ball), scaled to ``radius`` and resting on
    z = 0, moving down at 1 m/s; its step is an eighth of the transit time across the
    shortest edge (``cases/ball_drop.py``)."""
    axis = np.linspace(-1.0, 1.0, n + 1)
    mesh = skfem.MeshTet.init_tensor(axis, axis, axis)
    p = mesh.p
    p = p * (np.abs(p).max(axis=0) / np.maximum(np.linalg.norm(p, axis=0), 1e-300)) * radius
    p[2] += radius
    body = Solid(skfem.MeshTet(p, mesh.t), LinearElastic(**RUBBER))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * radius)
    model = Model([body], [Contact(body, floor)])
    v0 = model.translation(body, (0.0, 0.0, -1.0))
    return model, v0, IntegratorOptions(), wave_step(body, 0.125)


BUILDERS = {
    "3D solid, St Venant–Kirchhoff": lambda n: cube(n, True),
    "3D solid, linear": lambda n: cube(n, False),
    "3D ball, 100 steps": mapped_ball,
}


def one(series, size, solver, steps):
    """Run one configuration in this process and return its row."""
    use_sparse_solver(solver)
    t0 = time.perf_counter()
    model, v0, options, h = BUILDERS[series](size)
    build_s = time.perf_counter() - t0
    sim = Simulation(model, dt=h, t_end=steps * h, v0=v0, name="iterative", options=options)
    gaps = model.contacts.gaps(np.zeros(model.n))
    with tempfile.TemporaryDirectory() as out:
        s = run(sim, out, frames=False, checkpoint_every=0)
    cg = s["iterative_solver"]
    return {
        "series": series,
        "size": size,
        "solver": solver,
        "dofs": model.n,
        "candidates": int(np.sum(gaps <= sim.options.detection_margin * model.length)),
        "steps": s["steps"],
        "build_s": build_s,
        "ms_per_step": 1e3 * s["time_per_step_s"],
        "newton_mean": s["newton_iterations_mean"],
        "factorizations": s["sparse_factorizations"]["count"],
        "cg_solves": cg["solves"],
        "diagonal_solves": cg["diagonal"],
        "cg_iterations_per_solve": cg["iterations"] / max(cg["solves"], 1),
        "amg_setups": cg["setups"],
        "fallbacks": cg["fallbacks"],
        "max_penetration": s["max_penetration"],
        "energy_final": s["energy_final"],
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "status": s["status"],
    }


def in_process(series, size, solver, steps):
    """``one`` in a fresh Python process (its own peak memory, no cached hierarchies)."""
    cmd = [sys.executable, __file__, "--one", json.dumps([series, size, solver, steps])]
    env = os.environ | {"PYTHONPATH": str(common.ROOT)}  # this checkout's fecontact
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=common.ROOT, env=env)
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or ["no output"]
        return {"series": series, "size": size, "solver": solver, "status": tail[0][:80]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def plan(quick):
    nonlinear = [(4, 2)] if quick else [(6, 5), (9, 5), (13, 5), (19, 2), (27, 1)]
    linear = [(4, 2)] if quick else [(6, 5), (9, 5), (13, 5), (19, 5), (27, 5)]
    runs = [("3D solid, St Venant–Kirchhoff", n, s) for n, s in nonlinear]
    runs += [("3D solid, linear", n, s) for n, s in linear]
    return runs, ("3D ball, 100 steps", 4 if quick else 43, 3 if quick else 100)


def main():
    parser = common.parser(__doc__)
    parser.add_argument("--one", help=argparse.SUPPRESS)  # one run, in a child process
    args = parser.parse_args()
    if args.one:
        print(json.dumps(one(*json.loads(args.one))))
        return
    clock = time.perf_counter()
    rows = []
    runs, ball = plan(args.quick)
    for series, size, steps in runs:
        pair = [in_process(series, size, solver, steps) for solver in ("superlu", "amg")]
        if "ms_per_step" in pair[0] and "ms_per_step" in pair[1]:
            pair[1]["speedup"] = pair[0]["ms_per_step"] / pair[1]["ms_per_step"]
        rows += pair
        print(common.markdown_table(pair, COLUMNS, TITLES), flush=True)
    rows.append(in_process(ball[0], ball[1], "amg", ball[2]))
    name = "iterative_quick" if args.quick else "iterative"
    out = common.Path(args.out)
    common.write_csv(out / f"{name}.csv", rows, COLUMNS)
    note = (
        f"{platform.machine()}, 2 cores, Python {platform.python_version()}; "
        f"`iterative_speed.py{' --quick' if args.quick else ''}`; "
        f"{time.perf_counter() - clock:.0f} s in all.\n\n{__doc__.split(chr(10) + chr(10))[1]}"
    )
    text = common.markdown_table(rows, COLUMNS, TITLES)
    common.write_markdown(out / f"{name}.md", f"# Direct and iterative solvers\n\n{note}\n\n{text}")
    print(text)


if __name__ == "__main__":
    main()
