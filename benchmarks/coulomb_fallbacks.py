"""The Coulomb solve where its semi-smooth Newton does not converge.

1. An elastic disk (r = 5 cm) thrown at (2, −1) m/s onto a clamped steel strip (`Beam2D`,
   20 elements), μ = 1 and 0.1, no gravity, h = 0.1 ms, 12 ms: the strip's nodes' rows and
   the disk's nodes' rows meet under the disk. The counts of the frictional solves
   (`friction_solver`: Gauss–Seidel fallbacks, solves by the law's cases, line-search cuts,
   forced full steps) and the run's CPU time.
2. The Gauss–Seidel sweeps alone: eight contacts in the plane and in space on 12 dofs
   (redundant rows, random Delassus matrices), reached through ``solve_coulomb`` with no
   Newton iteration (``max_iter`` 0), at most 2000 sweeps: CPU per solve.

    python benchmarks/coulomb_fallbacks.py            # about 20 s
    python benchmarks/coulomb_fallbacks.py --quick    # seconds
"""

from __future__ import annotations

import tempfile
import time

import numpy as np
from _common import parser, publish_report

from fecontact import Beam2D, Contact, Material, Model, Section, Simulation, run
from fecontact.bodies import Solid
from fecontact.bodies.materials import LinearElastic
from fecontact.contact.friction import solve_coulomb
from fecontact.contact.stats import CoulombStats

COUNTS = ("solves", "gauss_seidel_solves", "case_solves", "line_search_cuts", "full_steps_forced")


def disk_throw(mu: float, t_end: float) -> dict:
    steel = Material(210e9, rho=7850.0)
    strip = Beam2D.straight([-0.5, 0.0], [0.5, 0.0], 20, steel, Section.rectangle(0.02, 0.01))
    for i in range(strip.n_nodes):
        strip.clamp(i)
    disk = Solid.disk([0.0, 0.005 + 0.0501], 0.05, 2, LinearElastic(1e7, 0.3, 1e3))
    pair = Contact(disk, strip, clearance=0.005, friction=mu)
    model = Model([disk, strip], [pair], gravity=(0.0, 0.0))
    sim = Simulation(model, 1e-4, t_end, v0=model.translation(disk, (2.0, -1.0)), name="throw")
    start = time.process_time()
    with tempfile.TemporaryDirectory() as out:
        summary = run(sim, out, progress=False, frames=False)
    cpu = time.process_time() - start
    solver = summary["friction_solver"]
    row = {"mu": mu, "t_end_s": t_end}
    row.update({k: solver.get(k, 0) for k in COUNTS})
    row["friction_dissipation_J"] = summary["energy_ledger"]["friction_dissipation"]
    row["cpu_s"] = cpu
    return row


def sweeps(nt: int, seeds: int) -> dict:
    """CPU of the Gauss–Seidel solves of eight contacts with ``nt`` tangents, 12 dofs."""
    cpu, count = 0.0, 0
    stats = CoulombStats()
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        m, N = 8, 8 * (1 + nt)
        G = rng.normal(size=(N, 12))
        D = G @ G.T
        c = rng.normal(size=N)
        c[:: 1 + nt] -= 1.0  # (most normals pressed)
        p = 1.0 / np.diag(D)
        start = time.process_time()
        try:
            solve_coulomb(c, D, p, 1.0, np.full(m, 0.3), nt, None, 1e-10, 0, stats)
        except RuntimeError:
            pass  # (2000 sweeps without Newton's polish: not always within the tolerance)
        cpu += time.process_time() - start
        count += 1
    return {"tangents": nt, "solves": count, "gauss_seidel_solves": stats.gauss_seidel_solves,
            "cpu_per_solve_ms": 1e3 * cpu / count}  # fmt: skip


def main(argv=None) -> None:
    args = parser(__doc__.splitlines()[0]).parse_args(argv)
    t_end = 0.003 if args.quick else 0.012
    throws = [disk_throw(mu, t_end) for mu in (1.0, 0.1)]
    seeds = 2 if args.quick else 10
    gs = [sweeps(nt, seeds) for nt in (1, 2)]
    publish_report(
        args.out,
        "coulomb_fallbacks",
        args.quick,
        "The Coulomb solve where Newton does not converge",
        throws,
        ("The disk thrown on the clamped strip (counts of `friction_solver`)", throws),
        ("Gauss–Seidel solves of eight contacts on 12 dofs (at most 2000 sweeps)", gs),
    )


if __name__ == "__main__":
    main()
