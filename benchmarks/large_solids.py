"""Large 3D solids: time per step of every sparse solver path side by side, and memory.

The ball impact of ``hertz.py`` at 0.1 m/s (R = 0.05 m, E = 10 MPa, ν = 0.3, ρ = 1000 kg/m³,
no gravity, touching the plane z = 0 at t = 0, ρ∞ = 0.5), on the ball of
``iterative_speed.py`` (the cube [−1, 1]³ in n³ × 6 P1 tetrahedra mapped radially onto the
ball: n = 10, 18, 27, 43 give 3,993, 20,577, 65,856 and 255,552 dofs), linear elastic and
Neo-Hookean, at h = t_c/20 and t_c/50 (t_c Hertz's contact duration of the finite element
mass, 9.7 ms), over one contact duration (20 and 50 steps; fewer where a row says so: a
nonlinear step costs about the same at every step of the impact). Every run is a fresh
process (``fecontact.run`` without frames), so that its peak memory is its own.

Paths: ``superlu`` (SciPy's SuperLU for every system: the default before the sparse Cholesky
path), ``direct`` (the default: sparse Cholesky, MKL PARDISO, for the symmetric systems),
``amg`` (AMG-preconditioned CG) and ``auto`` (the cost-based choice; the paths it ended on are
in the "auto chose" column). Per row: ms per step (``time_per_step_s``, wall) and CPU ms per
step (the run's CPU time over its steps: what the comparisons use), Newton iterations per
step, factorizations and their time, CG solves, the factor's memory (PARDISO's report) and
the process's peak (``ru_maxrss``), the largest penetration, the initial and final energy
(T + V_strain) and the energy the ledger finds created (``summary.json`` ``energy_ledger``;
its warning, naming the step and phase, follows the status) (the paths agree on them to the
solver tolerance). Per group: each path's CPU time over the fastest
one's. Below the table: the default's growth exponent from the smallest to the largest ball,
per material and step.

One thread for every library (OPENBLAS_NUM_THREADS=1, MKL sequential), on a machine shared by
other jobs: the rows of a group run back to back, and CPU time counts a run's own work where
wall time adds the other jobs' (wall ms/step of one row varied 2.5x between two runs).

    python benchmarks/large_solids.py [--quick] [--sizes 10,18,27,43] [--cap 10]
        [--materials linear,Neo-Hookean] [--steps 20,50] [--name large_solids]
    python benchmarks/large_solids.py --factorizations [--sizes 10,18,27]  # the bindings
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import argparse
import json
import math
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import skfem

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact import Contact, IntegratorOptions, Model, Plane, Simulation, run
from fecontact.bodies import LinearElastic, NeoHookean, Solid
from fecontact.linalg import use_sparse_solver

RADIUS, SPEED = 0.05, 0.1
RUBBER = {"E": 1e7, "nu": 0.3, "rho": 1000.0}
MATERIALS = {"linear": LinearElastic, "Neo-Hookean": NeoHookean}
SOLVERS = ("superlu", "direct", "amg", "auto")
COLUMNS = [
    "material",
    "step",
    "dofs",
    "solver",
    "steps",
    "ms_per_step",
    "cpu_ms_per_step",
    "auto_path",
    "newton_mean",
    "factorizations",
    "factor_s",
    "cg_solves",
    "factor_mb",
    "peak_mb",
    "max_penetration",
    "energy_initial",
    "energy_final",
    "created",
    "vs_fastest",
    "status",
    "sweep",
]
HEADERS = {
    "ms_per_step": "ms/step",
    "cpu_ms_per_step": "CPU ms/step",
    "auto_path": "auto chose",
    "newton_mean": "Newton/step",
    "factor_s": "factorizing (s)",
    "factor_mb": "factor (MB)",
    "peak_mb": "peak memory (MB)",
    "max_penetration": "penetration (m)",
    "energy_initial": "initial energy (J)",
    "energy_final": "final energy (J)",
    "created": "created (J)",
    "vs_fastest": "/ fastest",
}
TITLES = [HEADERS.get(c, c) for c in COLUMNS]


def ball(n: int, material: str):
    """(model, v0, t_c): the mapped ball of n³ × 6 tetrahedra resting on z = 0, moving down
    at ``SPEED``, and Hertz's contact duration (s) of its mass."""
    axis = np.linspace(-1.0, 1.0, n + 1)
    mesh = skfem.MeshTet.init_tensor(axis, axis, axis)
    p = mesh.p
    p = p * (np.abs(p).max(axis=0) / np.maximum(np.linalg.norm(p, axis=0), 1e-300)) * RADIUS
    p[2] += RADIUS
    body = Solid(skfem.MeshTet(p, mesh.t), MATERIALS[material](**RUBBER))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * RADIUS)
    model = Model([body], [Contact(body, floor, restitution=0.0)], gravity=(0.0, 0.0, 0.0))
    ez = model.translation(body, (0.0, 0.0, 1.0))
    mass = float(ez @ (model.M_full @ ez))
    e_star = RUBBER["E"] / (1.0 - RUBBER["nu"] ** 2)
    t_c = 2.87 * (mass**2 / (RADIUS * e_star**2 * SPEED)) ** 0.2
    return model, -SPEED * ez, t_c


def one(material: str, size: int, per_tc: int, solver: str, cap: int) -> dict:
    """One run in this process: its row."""
    use_sparse_solver(solver)
    model, v0, t_c = ball(size, material)
    h = t_c / per_tc
    steps = min(per_tc, cap) if cap else per_tc
    options = IntegratorOptions(rho_inf=0.5)
    sim = Simulation(model, dt=h, t_end=steps * h, v0=v0, name="large", options=options)
    cpu = _cpu_seconds()
    with tempfile.TemporaryDirectory() as out:
        s = run(sim, out, frames=False, checkpoint_every=0)
    cpu = _cpu_seconds() - cpu
    record = s["sparse_solver"]
    paths = {r["path"] for r in record.get("roles", []) if r["path"]}
    return {
        "material": material,
        "step": f"t_c/{per_tc}",
        "dofs": model.n,
        "solver": solver,
        "steps": s["steps"],
        "ms_per_step": 1e3 * s["time_per_step_s"],
        "cpu_ms_per_step": 1e3 * cpu / max(s["steps"], 1),
        "auto_path": "+".join(sorted(paths)) if solver == "auto" else "",
        "newton_mean": s["newton_iterations_mean"],
        "factorizations": sum(f["count"] for f in record["factorizations"].values()),
        "factor_s": sum(f["seconds"] for f in record["factorizations"].values()),
        "cg_solves": s["iterative_solver"]["solves"],
        "factor_mb": record["factor_memory_mb"],
        "peak_mb": record["peak_memory_mb"],
        "max_penetration": s["max_penetration"],
        "energy_initial": s["energy_initial"],
        "energy_final": s["energy_final"],
        "created": s["energy_ledger"]["created"],
        "status": s["status"] + "".join(f"; {w}" for w in s["warnings"]),
    }


def _cpu_seconds() -> float:
    """CPU time (s) of this process: on a shared machine it counts a single-threaded run's
    own work, which wall time mixes with the other jobs' (the libraries run on one thread)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def in_process(material, size, per_tc, solver, cap, timeout):
    """``one`` in a fresh Python process (its own peak memory, nothing cached)."""
    cmd = [sys.executable, __file__, "--one", json.dumps([material, size, per_tc, solver, cap])]
    path = os.pathsep.join([str(common.ROOT), os.environ.get("PYTHONPATH", "")])
    env = os.environ | {"PYTHONPATH": path}  # this checkout's fecontact first
    base = {"material": material, "step": f"t_c/{per_tc}", "solver": solver}
    try:
        proc = subprocess.run(
            cmd, capture_output=True, text=True, cwd=common.ROOT, env=env, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        return base | {"status": f"not finished in {timeout:.0f} s"}
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or [f"exit {proc.returncode}"]
        return base | {"status": tail[0][:80]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def compare(group: list[dict]) -> None:
    """Each row's time over the fastest path's of its group (``auto`` not a path of its own)."""
    key = "cpu_ms_per_step"
    times = [r[key] for r in group if key in r and r["solver"] != "auto"]
    if not times:
        return
    for r in group:
        if key in r:
            r["vs_fastest"] = r[key] / min(times)


def growth(rows: list[dict], solver: str = "direct") -> list[str]:
    """The exponent p of ms/step ∝ n^p of ``solver`` from the smallest to the largest ball, per
    material and step."""
    lines = []
    for material in MATERIALS:
        for step in sorted({r["step"] for r in rows}):
            pts = [
                (r["dofs"], r["cpu_ms_per_step"])
                for r in rows
                if r["material"] == material
                and r["step"] == step
                and r["solver"] == solver
                and "cpu_ms_per_step" in r
            ]
            if len(pts) >= 2:
                (n0, t0), (n1, t1) = min(pts), max(pts)
                p = math.log(t1 / t0) / math.log(n1 / n0)
                lines.append(
                    f"- {material}, {step}: {solver} from {n0:,} to {n1:,} dofs, "
                    f"CPU ms/step × {t1 / t0:.3g} for n × {n1 / n0:.3g}: exponent {p:.2f}"
                )
    return lines


def plan(args) -> list[tuple]:
    """(material, size, t_c/h, solver, cap) of every run, small to large."""
    if args.quick:
        return [(m, 6, 20, s, 4) for m in MATERIALS for s in SOLVERS]
    sizes = [int(s) for s in args.sizes.split(",")]
    materials = [m for m in MATERIALS if m in args.materials.split(",")]
    runs = []
    for per_tc in [int(k) for k in args.steps.split(",")]:
        for material in materials:
            for size in sizes:
                nonlinear = material != "linear"
                cap = args.cap if nonlinear and size >= 27 else 0
                for solver in SOLVERS:
                    if solver not in args.solvers.split(","):
                        continue
                    if solver == "superlu" and size >= 43:
                        continue  # its factor would need ~11 GB (n^(4/3) from 1.9 GB at 66k)
                    if solver == "superlu" and nonlinear and size >= 27:
                        continue  # 33 s a factorization, 3 a step: beyond this budget
                    runs.append((material, size, per_tc, solver, cap))
    return runs


def factorization(size: int, backend: str) -> dict:
    """Factorization and one solve of the linear ball's S_t at h = t_c/20 by ``backend``, in
    this process: seconds, the relative residual, and the peak memory over the model's."""
    model, _, t_c = ball(size, "linear")
    h = t_c / 20
    _, _, K = model.internal(np.zeros(model.n))
    S = model.iteration_sum(1.5 / (0.4444 * h * h), K)  # β′ of ρ∞ = 0.5: β = 0.444, α_f = 1/3
    b = np.random.default_rng(0).standard_normal(S.shape[0])
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.perf_counter()
    solve = BACKENDS[backend](S)
    factor_s = time.perf_counter() - start
    start = time.perf_counter()
    x = solve(b)
    solve_s = time.perf_counter() - start
    return {
        "dofs": S.shape[0],
        "backend": backend,
        "factor_s": factor_s,
        "solve_s": solve_s,
        "residual": float(np.linalg.norm(S @ x - b) / np.linalg.norm(b)),
        "memory_mb": (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024.0,
    } | getattr(solve, "info", {})


def _superlu(S):
    import scipy.sparse.linalg as spla

    options = {"SymmetricMode": True}
    lu = spla.splu(S.tocsc(), "MMD_AT_PLUS_A", diag_pivot_thresh=1e-2, options=options)
    return lu.solve


def _pardiso(S):
    from fecontact.linalg.cholesky import cholesky_factorize

    return cholesky_factorize(S)


def _cholespy(S):
    from cholespy import CholeskySolverD, MatrixType

    A = S.tocsr()
    indptr, indices = A.indptr.astype(np.int32), A.indices.astype(np.int32)
    factor = CholeskySolverD(A.shape[0], indptr, indices, A.data, MatrixType.CSR)

    def solve(b):
        x = np.empty_like(b)
        factor.solve(b, x)
        return x

    return solve


def _pardiso_ordered(S, ordering: int):
    """PARDISO's Cholesky with the fill-reducing ``ordering`` (iparm(2): 0 minimum degree, 2
    METIS nested dissection, 3 its parallel version), reporting the factor's entries and the
    factorization's floating-point operations (iparm(18), iparm(19)): the machine-independent
    cost whose growth with n the time per step inherits."""
    import pypardiso

    upper = sp.triu(S, format="csr")
    upper.sort_indices()
    solver = pypardiso.PyPardisoSolver(mtype=2)
    solver.set_iparm(1, 1)  # the iparm given here, not MKL's defaults (those leave (19) off)
    solver.set_iparm(2, ordering)
    solver.set_iparm(18, -1)  # report the factor's entries
    solver.set_iparm(19, -1)  # and the factorization's Mflop
    solver.factorize(upper)

    def solve(b):
        return solver.solve(upper, b)

    solve.info = {
        "factor_nnz": int(solver.get_iparm(18)),
        "gflop": int(solver.get_iparm(19)) / 1e3,
    }
    return solve


BACKENDS = {
    "superlu": _superlu,
    "pardiso": _pardiso,
    "cholespy": _cholespy,
    "pardiso_metis": lambda S: _pardiso_ordered(S, 2),
    "pardiso_mmd": lambda S: _pardiso_ordered(S, 0),
    "pardiso_pmetis": lambda S: _pardiso_ordered(S, 3),
}


def factorizations(sizes, backends=tuple(BACKENDS)) -> str:
    """Every backend at every size, each in a fresh process: a Markdown table, and the
    exponent of the factorization's time and operations against n from the smallest size to
    the largest of each backend."""
    rows = []
    for size in sizes:
        for backend in backends:
            cmd = [sys.executable, __file__, "--factor", json.dumps([size, backend])]
            proc = subprocess.run(cmd, capture_output=True, text=True, cwd=common.ROOT)
            if proc.returncode:
                rows.append({"backend": backend, "status": proc.stderr.strip()[-80:]})
            else:
                rows.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    columns = ["dofs", "backend", "factor_s", "solve_s", "residual", "memory_mb"]
    columns += ["factor_nnz", "gflop", "status"]
    return common.markdown_table(rows, columns) + "\n\n" + "\n".join(factor_growth(rows))


def factor_growth(rows: list[dict]) -> list[str]:
    """Per backend, the exponent p of (factorization time, Gflop) ∝ n^p from its smallest to
    its largest matrix."""
    lines = []
    for backend in dict.fromkeys(r["backend"] for r in rows):
        pts = sorted(
            ((r["dofs"], r) for r in rows if r["backend"] == backend and "dofs" in r),
            key=lambda p: p[0],
        )
        if len(pts) < 2:
            continue
        (n0, r0), (n1, r1) = pts[0], pts[-1]
        ratios = {k: r1[k] / r0[k] for k in ("factor_s", "gflop") if r0.get(k) and r1.get(k)}
        fits = [
            f"{k} × {x:.3g} (n^{math.log(x) / math.log(n1 / n0):.2f})" for k, x in ratios.items()
        ]
        lines.append(f"- {backend}, {n0:,} → {n1:,} dofs: " + ", ".join(fits))
    return lines


def arguments():
    parser = common.parser(__doc__)
    parser.add_argument("--one", help=argparse.SUPPRESS)  # one run, in a child process
    parser.add_argument("--sizes", default="10,18,27,43", help="ball divisions n (n³ × 6 tets)")
    parser.add_argument("--cap", type=int, default=10, help="steps of nonlinear runs from n = 27")
    parser.add_argument("--materials", default=",".join(MATERIALS), help="comma-separated")
    parser.add_argument("--steps", default="20,50", help="steps per t_c, comma-separated")
    parser.add_argument("--solvers", default=",".join(SOLVERS), help="comma-separated")
    parser.add_argument("--timeout", type=float, default=3600.0, help="s per run")
    parser.add_argument("--name", default=None, help="results stem (default large_solids)")
    parser.add_argument("--factor", help=argparse.SUPPRESS)  # one factorization, a child
    parser.add_argument(
        "--factorizations", action="store_true", help="time each Cholesky binding installed"
    )
    parser.add_argument("--backends", help="comma-separated, with --factorizations")
    parser.add_argument("--from-csv", help="tabulate these CSVs (comma-separated), no runs")
    return parser.parse_args()


def sweep(args, name: str) -> list[dict]:
    """Every run of the plan, printed a group (size, material, step) at a time; the CSV is
    rewritten after each run (a long sweep cut short keeps what it measured)."""
    rows, group = [], []
    for material, size, per_tc, solver, cap in plan(args):
        row = in_process(material, size, per_tc, solver, cap, args.timeout)
        row.setdefault("dofs", 3 * (size + 1) ** 3)
        key = (row["dofs"], row["material"], row["step"])
        if group and (group[0]["dofs"], group[0]["material"], group[0]["step"]) != key:
            compare(group)
            print(common.markdown_table(group, COLUMNS, TITLES), flush=True)
            group = []
        group.append(row)
        rows.append(row)
        common.write_csv(Path(args.out) / f"{name}.csv", rows, COLUMNS)
    compare(group)
    print(common.markdown_table(group, COLUMNS, TITLES), flush=True)
    return rows


def from_csv(paths: str) -> list[dict]:
    """The rows of earlier sweeps (cells left empty dropped), each compared with its group."""
    rows = []
    for path in paths.split(","):
        for r in common.read_csv(path):
            rows.append({k: v for k, v in r.items() if v != ""})
    groups = {}
    for r in rows:
        groups.setdefault((r.get("dofs"), r["material"], r["step"]), []).append(r)
    for group in groups.values():
        compare(group)
    return rows


def main():
    args = arguments()
    if args.one:
        print(json.dumps(one(*json.loads(args.one))))
        return
    if args.factor:
        print(json.dumps(factorization(*json.loads(args.factor))))
        return
    if args.factorizations:
        backends = args.backends.split(",") if args.backends else tuple(BACKENDS)
        print(factorizations([int(s) for s in args.sizes.split(",")], backends))
        return
    clock = time.perf_counter()
    name = args.name or ("large_solids_quick" if args.quick else "large_solids")
    rows = from_csv(args.from_csv) if args.from_csv else sweep(args, name)
    common.write_csv(Path(args.out) / f"{name}.csv", rows, COLUMNS)
    note = (
        f"{platform.machine()}, 2 cores shared with other jobs, Python "
        f"{platform.python_version()}; `large_solids.py{' --quick' if args.quick else ''}`"
        + ("" if args.from_csv else f"; {time.perf_counter() - clock:.0f} s in all")
        + "."
    )
    if args.from_csv:
        note += (
            " Rows merged from several sweeps of the plan (column `sweep`): a row's paths were"
            " run back to back within a sweep; '/ fastest' compares CPU times across sweeps."
        )
    text = common.markdown_table(rows, COLUMNS, TITLES)
    exponents = "\n".join(growth(rows) + growth(rows, "superlu"))
    body = f"# Large 3D solids\n\n{note}\n\n{__doc__.split(chr(10) + chr(10))[1]}\n\n{text}\n"
    common.write_markdown(Path(args.out) / f"{name}.md", body + f"\n{exponents}\n")
    print(exponents)


if __name__ == "__main__":
    main()
