"""Why the flexible pendulum with e_N = 1 blows up at ρ∞ = 0.8 and 0.9 (h = 1e-3), measured.

Two studies (``benchmarks/results/axial_pumping.md``):

1. Free flight from a post-impact state. The case runs with its stop to ``--start`` (10 ms after
   the first impact), then only the smooth generalized-α step is taken (no contact at all).
   Per step: the energy change, the axial force N = EA Γ of every element against the Euler
   load π²EI/L² of the strip, and the smooth Newton iterations.
2. 100 s runs at ρ∞ = 0.5, 0.8, 0.9 of the nominal strip and of two diagnostic strips: the
   axial rigidity EA / 100 (the tip mass on the axial spring drops from hω = 7.9 to 0.79) and
   the rotary inertia ρI × 100 (the rotations' modes drop from hω ≈ 5000 to ≈ 500). They are
   diagnostics, not models: they tell which mode the instability lives in.
3. How robust the nominal result is: the strip's modes about the hanging configuration with
   their generalized-α phase per step and amplification; 5 s runs over a grid of steps h and
   ρ∞; and runs at ρ∞ = 0.8, h = 1e-3 with the tip mass, E or the length changed by about 1 %.

    python benchmarks/axial_pumping.py --workers 2   # about 8 minutes
    python benchmarks/axial_pumping.py --quick       # seconds: short runs, one grid point
"""

from __future__ import annotations

import dataclasses
import math
from contextlib import contextmanager

import numpy as np
import scipy.linalg
from _common import map_runs, parser, report, write_markdown

from fecontact import Contact, Model
from fecontact.bodies import beam as beam_module
from fecontact.bodies.beam_kernels import BeamElements, beam_internal
from fecontact.testing import case, trace
from fecontact.time import State, simulate
from fecontact.time.generalized_alpha import coefficients


@contextmanager
def rotary_inertia(factor: float):
    """Beams built inside scale their rotational mass by ``factor``."""
    original = beam_module.Beam2D.mass_matrix

    def scaled(self):
        M = original(self).tolil()
        for i in range(2, M.shape[0], 3):
            M[i, :] = M[i, :] * factor
        return M.tocsr()

    beam_module.Beam2D.mass_matrix = scaled if factor != 1.0 else original
    try:
        yield
    finally:
        beam_module.Beam2D.mass_matrix = original


class AxiallySoftBeam(beam_module.Beam2D):
    """A copy of ``beam`` (nodes, material, section, supports, point masses) whose axial
    rigidity EA alone is scaled by ``axial``: a diagnostic, not a model. Its internal force and
    strain energy come from the beam kernels with the scaled rigidities."""

    def __init__(self, beam, axial: float):
        super().__init__(beam.X, beam.material, beam.section)
        self.fixed = set(beam.fixed)
        self.point_masses = beam.point_masses.copy()
        m, s = beam.material, beam.section
        rigidities = (axial * m.E * s.area, m.G * s.area * s.shear_factor, m.E * s.inertia)
        self.scaled = BeamElements.of(self.X, self.segments().T, rigidities)

    def internal(self, q, tangent=True):
        return beam_internal(self.scaled, q, self.ndof, tangent)

    def energy(self, q):
        return beam_internal(self.scaled, q, self.ndof, False)[0]


def axially_soft(sim, axial: float):
    """The pendulum ``sim`` with its strip's EA scaled by ``axial`` (the same stop, probes)."""
    beam = AxiallySoftBeam(sim.model.bodies[0], axial)
    stop = sim.model.contacts.pairs[0]
    pair = Contact(
        beam, stop.obstacle, nodes=stop.nodes, restitution=stop.restitution, friction=stop.friction
    )
    return sim.replace(model=Model([beam], [pair], gravity=sim.model.gravity))


def build(rho_inf: float, axial: float = 1.0, rotary: float = 1.0, **params):
    with rotary_inertia(rotary):
        sim = case("flexible_pendulum").build(restitution=1.0, **params)
        if axial != 1.0:
            sim = axially_soft(sim, axial)
    return sim.replace(options=dataclasses.replace(sim.options, rho_inf=rho_inf))


def energy(model, st) -> float:
    return model.kinetic_energy(st.v) + model.potential_energy(st.q) + model.strain_energy(st.q)


def free_flight(rho_inf: float, start: float, steps: int, h: float = 1e-3):
    sim = build(rho_inf)
    model = sim.model
    st = None
    for st in simulate(model, h, start, sim.options):  # noqa: B007 (the last state)
        pass
    beam = model.bodies[0]
    EA, EI = beam.material.E * beam.section.area, beam.material.E * beam.section.inertia
    euler = math.pi**2 * EI / beam.length**2
    e0, ke = energy(model, st), model.kinetic_energy(st.v)
    # the stop removed: every step is the smooth generalized-α step alone
    free = Model([beam], [], gravity=model.gravity)
    resume = State(st.t, st.q, st.v, st.vd, st.a, step=st.step, h=h)
    rows = []
    for now in simulate(free, h, st.t + steps * h, sim.options, start=resume):
        q, it = now.q, now.iterations["smooth"]
        N = EA * beam.strains(q)[0]
        e = energy(free, now)
        rows.append(
            {
                "t": f"{now.t:.3f}",
                "dE": f"{100 * (e - e0) / ke:+.2f} %",
                "N": " ".join(f"{x:+.0f}" for x in N),
                "max abs N / Euler": float(np.abs(N).max() / euler),
                "iterations": it,
            }
        )
        if not math.isfinite(e) or e - e0 > 0.1 * ke:
            break
    return rows, ke, euler


def runaway():
    """An ``abort`` for ``trace``: the total energy above half the peak kinetic energy so far
    (1 mJ at least)."""
    peak = [1e-3]

    def abort(row) -> bool:
        peak[0] = max(peak[0], row["kinetic"])
        return row["total"] > 0.5 * peak[0]

    return abort


def growth_run(rho_inf, t_end, h=1e-3, axial=1.0, rotary=1.0, **params):
    """Run to ``t_end``, stopped once the energy passes half the peak kinetic energy; returns
    (status, end time (s), growth: max total energy − initial, % of the peak kinetic energy)."""
    r = trace(build(rho_inf, axial, rotary, **params), dt=h, t_end=t_end, abort=runaway())
    E = r["total"]
    growth = float(100 * (E.max() - E[0]) / r["kinetic"].max())
    return r["status"], float(r["t"][-1]), growth


def long_run(rho_inf, t_end, axial=1.0, rotary=1.0):
    status, end, growth = growth_run(rho_inf, t_end, 1e-3, axial, rotary)
    return {
        "ρ∞": rho_inf,
        "EA": f"× {axial:g}",
        "ρI": f"× {rotary:g}",
        "status": status,
        "end (s)": end,
        "growth (% of peak KE)": growth,
    }


def long_item(item):
    return long_run(*item)


def phase_per_step(h_omega: float, rho_inf: float) -> tuple[float, float]:
    """Phase (rad) and modulus of the generalized-α step's oscillating eigenvalue for an
    undamped mode at hω, from the step's map of (q, v, v̇, a) on one linear dof."""
    c = coefficients(rho_inf, 1.0)
    A = np.empty((4, 4))
    for j in range(4):
        X = c.P[:, j].copy()
        dq = -(X[2] + h_omega**2 * X[0]) / (c.bp + h_omega**2)
        A[:, j] = X + c.w * dq
    lam = np.linalg.eigvals(A)
    top = lam[np.argmax(np.abs(lam))]
    return abs(float(np.angle(top))), float(abs(top))


def hanging_modes(h, rhos, count=6):
    """The strip's lowest modes about the hanging configuration (tangent stiffness, no
    gravity) with the phase per step θ/π and |λ| of each at ``h`` for each ρ∞."""
    model = build(0.5).model
    beam = model.bodies[0]
    q = np.zeros(model.n)  # the strip turned to hang along −y from the pin
    q[0::3], q[1::3], q[2::3] = -beam.X[:, 0], -beam.X[:, 0], -math.pi / 2
    K = model.internal(q)[2]
    K, M = (x.toarray() if hasattr(x, "toarray") else np.asarray(x) for x in (K, model.M))
    omega = np.sqrt(np.abs(scipy.linalg.eigh(K, M, eigvals_only=True)))[:count]
    rows = []
    for w in omega:
        row = {"f (Hz)": f"{w / (2 * math.pi):.1f}", "hω": f"{h * w:.3g}"}
        for rho in rhos:
            theta, mod = phase_per_step(h * w, rho)
            row[f"θ/π, |λ| at ρ∞ = {rho}"] = f"{theta / math.pi:.3f}, {mod:.3f}"
        rows.append(row)
    return rows


PERTURBED = (
    {},
    {"tip_mass": 0.139},
    {"tip_mass": 0.141},
    {"E": 69.02e9},
    {"E": 70.98e9},
    {"length": 0.2991},
    {"length": 0.3009},
)
"""The nominal strip and its tip mass ± 0.7 %, E ± 1.4 %, length ± 0.3 %."""


def grid_run(item):
    rho, h, t_end = item
    return growth_run(rho, t_end, h)


def perturbed_run(item):
    rho, params, t_end = item
    return growth_run(rho, t_end, 1e-3, **params)


def robustness(t_end, steps, rhos, workers, perturbed=PERTURBED):
    grid = [(rho, h, t_end) for rho in rhos for h in steps]
    done = map_runs(grid_run, grid, workers, label=lambda x: f"rho_inf {x[0]}, h {x[1]:g}")
    cells = {(rho, h): res for (rho, h, _), res in zip(grid, done, strict=True)}

    def cell(status, end, growth):
        return f"{growth:.2g} %" if status == "completed" else f"{status} at {end:.3g} s"

    grid_rows = [{"ρ∞": rho, **{f"h = {h:g}": cell(*cells[rho, h]) for h in steps}} for rho in rhos]
    items = [(rho, params, t_end) for rho in (0.8, 0.9) for params in perturbed]
    done = map_runs(perturbed_run, items, workers, label=lambda x: f"{x[0]} {x[1]}")
    pert_rows = [
        {
            "ρ∞": rho,
            "change": ", ".join(f"{k} = {v:g}" for k, v in params.items()) or "nominal",
            "result": cell(*res),
        }
        for (rho, params, _), res in zip(items, done, strict=True)
    ]
    return grid_rows, pert_rows


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--rho-inf", type=float, default=0.9, help="of the free flight")
    p.add_argument("--start", type=float, default=0.33, help="s, start of the free flight")
    p.add_argument("--workers", type=int, default=1, help="local worker processes (Dask)")
    args = p.parse_args()
    rows, ke, euler = free_flight(args.rho_inf, args.start, 40)
    t_end = 0.05 if args.quick else 100.0
    items = [
        (rho, t_end, axial, rotary)
        for rho in (0.5, 0.8, 0.9)
        for axial, rotary in ((1.0, 1.0), (0.01, 1.0), (1.0, 100.0))
    ]
    runs = map_runs(long_item, items, args.workers, label=str)
    steps = (1e-3,) if args.quick else (4e-4, 6e-4, 8e-4, 9e-4, 1e-3, 1.1e-3, 1.2e-3, 1.5e-3, 2e-3)
    rhos = (0.5,) if args.quick else (0.5, 0.7, 0.8, 0.9)
    t_grid = 0.05 if args.quick else 5.0
    perturbed = PERTURBED[:2] if args.quick else PERTURBED
    grid_rows, pert_rows = robustness(t_grid, steps, rhos, args.workers, perturbed)
    text = report(
        "Flexible pendulum, e_N = 1, h = 1e-3: where the energy grows",
        (
            f"Free flight from t = {args.start} s at ρ∞ = {args.rho_inf} (stop removed), "
            f"kinetic energy at the start {ke:.3f} J, Euler load of the strip {euler:.1f} N. "
            "N per element (N), pivot to tip:",
            rows,
        ),
        (
            f"{t_end:g} s runs with the stop (growth: max total energy − initial, % of the "
            "peak kinetic energy; 'diverged': above half the peak kinetic energy):",
            runs,
        ),
        (
            "The strip's modes about the hanging configuration (tangent stiffness, no gravity) "
            "and the generalized-α step's phase θ per step and amplification |λ| at h = 1e-3:",
            hanging_modes(1e-3, (0.5, 0.8, 0.9)),
        ),
        (
            f"{t_grid:g} s runs over steps h (s) and ρ∞ (growth as above; 'diverged at' when "
            "the energy passed half the peak kinetic energy):",
            grid_rows,
        ),
        (f"{t_grid:g} s runs at h = 1e-3 with the strip changed by about 1 %:", pert_rows),
    )
    name = "axial_pumping_quick.md" if args.quick else "axial_pumping.md"
    print(write_markdown(f"{args.out}/{name}", text))


if __name__ == "__main__":
    main()
