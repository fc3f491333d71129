"""fecontact against GetFEM on the ball impact of ``large_solids.py``, same mesh, same step.

The linear-elastic ball (R = 0.05 m, E = 10 MPa, ν = 0.3, ρ = 1000 kg/m³; the cube [−1, 1]³ of
n³ × 6 P1 tetrahedra mapped radially onto the ball) touches the rigid plane z = 0 at 0.1 m/s,
no gravity. The mesh is written once to a Gmsh 2.2 file that both codes read; both step with
h = t_c/20 (t_c Hertz's contact duration of the finite element mass) for 25 steps (1.25 t_c:
the whole impact and the first steps of free flight).

- fecontact, in this process: the nonsmooth generalized-α integrator (ρ∞ = 0.5), Signorini
  and Newton's impact law (e_N = 0) on the nodes of the ball, its default sparse solver
  (``--solver``).
- GetFEM 5.4 (Debian's ``python3-getfem``, for the system Python), in a subprocess of
  ``/usr/bin/python3`` running ``_getfem_ball_driver.py``: Newmark's average acceleration, the
  nodal Alart–Curnier contact with a rigid obstacle, Newton with MUMPS.

The two alternate (fecontact, GetFEM, fecontact, ... ``--repeats`` times a size). Per run: the
set-up (reading the mesh, assembling) and the time loop, wall and CPU seconds (every library on
one thread), ms per step of the loop, Newton iterations, and the impact's answers measured
alike for both codes from the z-momentum p and the centre of mass's approach of every step:
t_c (the end of the last step with a node touching), F_max (the peak of Δp/Δt over one step,
t_c/20) and δ_max (the largest approach), beside Hertz's values.

    python benchmarks/getfem_ball.py [--quick] [--sizes 10,18,27] [--repeats 2]
        [--solver direct,superlu] [--no-getfem] [--steps 25]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import json
import math
import os
import platform
import resource
import subprocess
import tempfile
import time
from pathlib import Path

import meshio
import numpy as np
import skfem

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact import Contact, IntegratorOptions, Model, Plane, simulate
from fecontact.bodies import LinearElastic, Solid
from fecontact.linalg import use_sparse_solver
from fecontact.linalg.cholesky import cholesky_available

RADIUS, SPEED = 0.05, 0.1
RUBBER = {"E": 1e7, "nu": 0.3, "rho": 1000.0}
PER_TC, STEPS = 20, 25
SYSTEM_PYTHON = "/usr/bin/python3"
DRIVER = Path(__file__).with_name("_getfem_ball_driver.py")
NEWTON_TOL = 1e-8  # N: GetFEM's residual norm, 1e-9 of the ball's peak force (≈ 20 N)
COLUMNS = [
    "code",
    "dofs",
    "setup_s",
    "loop_s",
    "loop_cpu_s",
    "ms_per_step",
    "cpu_ms_per_step",
    "newton",
    "t_c_ms",
    "F_max_N",
    "delta_um",
    "vs_getfem",
    "vs_getfem_cpu",
]
TITLES = [
    "code",
    "dofs",
    "set-up (s)",
    "time loop (s)",
    "loop CPU (s)",
    "ms/step",
    "CPU ms/step",
    "Newton its",
    "t_c (ms)",
    "F_max (N)",
    "δ_max (µm)",
    "/ GetFEM (wall)",
    "/ GetFEM (CPU)",
]


def ball_mesh(n: int) -> meshio.Mesh:
    """The cube [−1, 1]³ of n³ × 6 tetrahedra mapped radially onto the ball resting on z = 0."""
    axis = np.linspace(-1.0, 1.0, n + 1)
    mesh = skfem.MeshTet.init_tensor(axis, axis, axis)
    p = mesh.p
    p = p * (np.abs(p).max(axis=0) / np.maximum(np.linalg.norm(p, axis=0), 1e-300)) * RADIUS
    p[2] += RADIUS
    return meshio.Mesh(p.T, [("tetra", mesh.t.T)])


def hertz(mass: float) -> dict:
    """Hertz's impact of a sphere of ``mass`` (kg) at ``SPEED``: t_c (s), F_max (N), δ_max (m)."""
    e_star = RUBBER["E"] / (1.0 - RUBBER["nu"] ** 2)
    delta = (15.0 * mass * SPEED**2 / (16.0 * e_star * math.sqrt(RADIUS))) ** 0.4
    return {
        "t_c": 2.87 * (mass**2 / (RADIUS * e_star**2 * SPEED)) ** 0.2,
        "F_max": 4.0 / 3.0 * e_star * math.sqrt(RADIUS) * delta**1.5,
        "delta": delta,
    }


def answers(momentum, approach, touching, h: float) -> dict:
    """t_c (ms), F_max (N) and δ_max (µm) from the per-step z-momentum (kg·m/s, step 0
    first), approach (m) and touching flags (steps 1...), alike for both codes."""
    p = np.asarray(momentum)
    touched = np.flatnonzero(np.asarray(touching)) + 1
    return {
        "t_c_ms": 1e3 * h * (touched[-1] if touched.size else 0),
        "F_max_N": float(np.max(np.diff(p)) / h),
        "delta_um": 1e6 * float(np.max(approach)),
    }


def cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def fecontact_run(path: Path, solver: str, steps: int = STEPS) -> dict:
    """The impact by fecontact on the mesh file, in this process."""
    use_sparse_solver(solver)
    wall, cpu = time.perf_counter(), cpu_seconds()
    read = meshio.read(path)
    tets = read.cells_dict["tetra"]
    body = Solid(skfem.MeshTet(read.points.T.copy(), tets.T.copy()), LinearElastic(**RUBBER))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * RADIUS)
    model = Model([body], [Contact(body, floor, restitution=0.0)], gravity=(0.0, 0.0, 0.0))
    ez = model.translation(body, (0.0, 0.0, 1.0))
    w = model.M_full @ ez  # z-momentum weights
    mass = float(w @ ez)
    setup_s = time.perf_counter() - wall
    h = hertz(mass)["t_c"] / PER_TC
    momentum, approach, touching, newton = [], [], [], 0
    wall, cpu = time.perf_counter(), cpu_seconds()
    options = IntegratorOptions(rho_inf=0.5)
    for st in simulate(model, h, steps * h, options, v0=-SPEED * ez):
        momentum.append(float(w @ st.v))
        approach.append(-float(w @ st.q) / mass)
        if st.step > 0:
            touching.append(bool(st.pressed().any()))
            newton += int(st.newton_iterations)
    loop_s, loop_cpu = time.perf_counter() - wall, cpu_seconds() - cpu
    return {
        "code": f"fecontact ({solver}{', PARDISO' if cholesky_available() else ''})",
        "dofs": model.n,
        "setup_s": setup_s,
        "loop_s": loop_s,
        "loop_cpu_s": loop_cpu,
        "steps": len(touching),
        "newton": newton,
        "mass": mass,
        "h": h,
    } | answers(momentum, approach, touching, h)


def getfem_available() -> bool:
    """Whether the system Python imports GetFEM (Debian's python3-getfem)."""
    try:
        proc = subprocess.run(
            [SYSTEM_PYTHON, "-c", "import getfem"], capture_output=True, timeout=60
        )
    except (OSError, subprocess.TimeoutExpired):
        return False
    return proc.returncode == 0


def getfem_run(path: Path, h: float, timeout: float, steps: int = STEPS) -> dict:
    """The impact by GetFEM on the mesh file, in a subprocess of the system Python."""
    params = {**RUBBER, "h": h, "steps": steps, "speed": SPEED, "tol": NEWTON_TOL}
    params["lsolver"] = "mumps"
    params_path = path.with_suffix(".json")
    params_path.write_text(json.dumps(params))
    threads = {k: "1" for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"} | threads
    cmd = [SYSTEM_PYTHON, str(DRIVER), str(path), str(params_path)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"code": "GetFEM", "status": f"not finished in {timeout:.0f} s"}
    if proc.returncode != 0:
        return {"code": "GetFEM", "status": (proc.stderr.strip().splitlines() or ["?"])[-1]}
    r = json.loads(proc.stdout.strip().splitlines()[-1])
    return {
        "code": "GetFEM (Newmark, MUMPS)",
        "dofs": r["dofs"],
        "setup_s": r["setup_wall_s"],
        "loop_s": r["loop_wall_s"],
        "loop_cpu_s": r["loop_cpu_s"],
        "steps": len(r["touching"]),
        "newton": sum(r["newton"]),
        "mass": r["mass"],
        "h": h,
    } | answers(r["momentum"], r["approach"], r["touching"], h)


def per_step(row: dict) -> dict:
    if "loop_s" in row:
        row["ms_per_step"] = 1e3 * row["loop_s"] / row["steps"]
        row["cpu_ms_per_step"] = 1e3 * row["loop_cpu_s"] / row["steps"]
    return row


def compare(rows: list[dict]) -> None:
    """Each fecontact run's loop time over the GetFEM run nearest after it (before it when
    there is none after)."""
    for i, r in enumerate(rows):
        if not r["code"].startswith("fecontact"):
            continue
        near = [g for g in rows[i + 1 :] + rows[:i][::-1] if "GetFEM" in g["code"]]
        if near and "loop_s" in near[0] and "loop_s" in r:
            r["vs_getfem"] = r["loop_s"] / near[0]["loop_s"]
            r["vs_getfem_cpu"] = r["loop_cpu_s"] / near[0]["loop_cpu_s"]


def size_runs(n: int, args, with_getfem: bool, folder: Path) -> list[dict]:
    """fecontact and GetFEM alternating on the ball of n divisions."""
    path = folder / f"ball_{n}.msh"
    meshio.write(path, ball_mesh(n), file_format="gmsh22", binary=False)
    rows = []
    for _ in range(args.repeats):
        for solver in args.solver.split(","):
            mine = per_step(fecontact_run(path, solver, args.steps))
            rows.append(mine)
            print(json.dumps(mine), flush=True)
        if with_getfem:
            theirs = per_step(getfem_run(path, mine["h"], args.timeout, args.steps))
            rows.append(theirs)
            print(json.dumps(theirs), flush=True)
    compare(rows)
    ref = hertz(rows[0]["mass"])
    rows.append(
        {
            "code": "Hertz",
            "dofs": rows[0]["dofs"],
            "t_c_ms": 1e3 * ref["t_c"],
            "F_max_N": ref["F_max"],
            "delta_um": 1e6 * ref["delta"],
        }
    )
    return rows


def arguments():
    parser = common.parser(__doc__)
    parser.add_argument("--sizes", default="10,18,27", help="ball divisions n (n³ × 6 tets)")
    parser.add_argument("--repeats", type=int, default=2, help="alternating runs a size")
    parser.add_argument("--solver", default="direct", help="fecontact's sparse solvers, a,b")
    parser.add_argument("--steps", type=int, default=STEPS, help="steps of each run")
    parser.add_argument("--no-getfem", action="store_true", help="fecontact's runs only")
    parser.add_argument("--timeout", type=float, default=3600.0, help="s per GetFEM run")
    parser.add_argument("--name", default=None, help="results stem (default getfem_ball)")
    return parser.parse_args()


def main():
    args = arguments()
    sizes = [6] if args.quick else [int(s) for s in args.sizes.split(",")]
    repeats = 1 if args.quick else args.repeats
    args.repeats = repeats
    with_getfem = not args.no_getfem and getfem_available()
    if not with_getfem and not args.no_getfem:
        print(f"GetFEM not importable by {SYSTEM_PYTHON}: fecontact only", flush=True)
    clock = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            rows += size_runs(n, args, with_getfem, Path(folder))
    name = args.name or ("getfem_ball_quick" if args.quick else "getfem_ball")
    common.write_csv(Path(args.out) / f"{name}.csv", rows, COLUMNS)
    note = (
        f"{platform.machine()}, 2 cores shared with other jobs, Python "
        f"{platform.python_version()}; `getfem_ball.py{' --quick' if args.quick else ''}`; "
        f"{time.perf_counter() - clock:.0f} s in all."
    )
    text = common.markdown_table(rows, COLUMNS, TITLES)
    body = f"# fecontact and GetFEM: the ball impact\n\n{note}\n\n{__doc__.split(chr(10) * 2)[1]}"
    common.write_markdown(Path(args.out) / f"{name}.md", f"{body}\n\n{text}\n")
    print(text)


if __name__ == "__main__":
    main()
