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

    python benchmarks/axial_pumping.py            # about 6 minutes
    python benchmarks/axial_pumping.py --quick    # 20 s runs
"""

from __future__ import annotations

import dataclasses
import math
from contextlib import contextmanager

import numpy as np
from _common import markdown_table, parser, write_markdown

from fecontact.bodies import beam as beam_module
from fecontact.testing import case, trace
from fecontact.time import simulate
from fecontact.time.generalized_alpha import coefficients
from fecontact.time.nsga import _smooth_step
from fecontact.time.state import PhaseTimer, State


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


def build(rho_inf: float, axial: float = 1.0, rotary: float = 1.0):
    with rotary_inertia(rotary):
        sim = case("flexible_pendulum").build(restitution=1.0)
    if axial != 1.0:  # the beam's kernel data: scale EA only
        beam = sim.model.bodies[0]
        C = beam._el.C.copy()
        C[0] *= axial
        beam._el = dataclasses.replace(beam._el, C=C)
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
    EA, _, EI = beam._el.C
    euler = math.pi**2 * EI / beam.length**2
    c = coefficients(rho_inf, h)
    e0, ke = energy(model, st), model.kinetic_energy(st.v)
    rows = []
    for _ in range(steps):
        step = _smooth_step(model, st, st.t + h, c, sim.options, PhaseTimer())
        q, v, vd, a, lam, it = step.q, step.v, step.vd, step.a, step.lam, step.iterations
        st = State(st.t + h, q, v, vd, a, h=h, lam=lam)
        N = EA * beam.strains(q)[0]
        e = energy(model, st)
        rows.append(
            {
                "t": f"{st.t:.3f}",
                "dE": f"{100 * (e - e0) / ke:+.2f} %",
                "N": " ".join(f"{x:+.0f}" for x in N),
                "max abs N / Euler": float(np.abs(N).max() / euler),
                "iterations": it,
            }
        )
        if not math.isfinite(e) or e - e0 > 0.1 * ke:
            break
    return rows, ke, euler


def long_run(rho_inf, t_end, axial=1.0, rotary=1.0):
    sim = build(rho_inf, axial, rotary)
    peak = [0.0]

    def abort(row):
        peak[0] = max(peak[0], row["kinetic"])
        return row["total"] > 0.5 * max(peak[0], 1e-3)

    r = trace(sim, dt=1e-3, t_end=t_end, abort=abort)
    E = r["total"]
    return {
        "ρ∞": rho_inf,
        "EA": f"× {axial:g}",
        "ρI": f"× {rotary:g}",
        "status": r["status"],
        "end (s)": float(r["t"][-1]),
        "growth (% of peak KE)": float(100 * (E.max() - E[0]) / r["kinetic"].max()),
    }


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--rho-inf", type=float, default=0.9, help="of the free flight")
    p.add_argument("--start", type=float, default=0.33, help="s, start of the free flight")
    args = p.parse_args()
    rows, ke, euler = free_flight(args.rho_inf, args.start, 40)
    t_end = 20.0 if args.quick else 100.0
    runs = []
    for rho in (0.5, 0.8, 0.9):
        for axial, rotary in ((1.0, 1.0), (0.01, 1.0), (1.0, 100.0)):
            runs.append(long_run(rho, t_end, axial, rotary))
            print(runs[-1], flush=True)
    text = [
        "# Flexible pendulum, e_N = 1, h = 1e-3: where the energy grows",
        "",
        f"Free flight from t = {args.start} s at ρ∞ = {args.rho_inf} (stop removed), kinetic "
        f"energy at the start {ke:.3f} J, Euler load of the strip {euler:.1f} N. N per element "
        "(N), pivot to tip:",
        "",
        markdown_table(rows, list(rows[0])),
        "",
        f"{t_end:g} s runs with the stop (growth: max total energy − initial, % of the peak "
        "kinetic energy; 'diverged': above half the peak kinetic energy):",
        "",
        markdown_table(runs, list(runs[0])),
    ]
    name = "axial_pumping_quick.md" if args.quick else "axial_pumping.md"
    print(write_markdown(f"{args.out}/{name}", "\n".join(text)))


if __name__ == "__main__":
    main()
