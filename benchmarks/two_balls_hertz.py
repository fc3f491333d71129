"""Two identical elastic balls head-on against Hertz: t_c, F_max and δ_max under mesh refinement.

``cases/two_balls.py`` (R = 0.05 m, E = 10 MPa, ν = 0.3, ρ = 1000 kg/m³, linear elastic, no
gravity): each ball moves at v toward the other, pole to pole; the right ball's mesh is the
left one's turned by 30° about the impact axis (no node meets a node), one dual mortar
interface. By symmetry each ball meets the other as it would meet a rigid plane at x = 0 at
v (``against="plane"``, the same ball alone), so Hertz's ball on a plane applies to each
ball, with E* = E/(1 − ν²) and m the finite element mass of one ball:

    δ_max = (15 m v² / (16 E* √R))^{2/5},   F_max = 4/3 E* √R δ_max^{3/2},
    t_c = 2.87 (m² / (R E*² v))^{1/5}.

The step is h = t_c/50. Measured on the left ball, per step: the contact force F = −Δp/h
(its momentum along x lost over the step, N: the mean force of the step), its peak F_max;
t_c, the steps with F > 0 times h (so resolved to 2 % of t_c); δ_max, the largest approach
of the centre of mass toward x = 0 beyond first contact. Meshes: quadratic isoparametric
tetrahedra (P2) graded toward the pole (``graded_ball_mesh``: scikit-fem's ball refined
twice, cells of ``spacing`` × R at the pole growing by 0.5 × the distance from it).

At v = 1 m/s the contact radius is a fifth of the ball's (a_max/R = 0.20): the finite ball's
own quasi-static answer is then t_c −7.6 %, F_max +11.3 %, δ_max −6.6 % from Hertz
(``benchmarks/hertz.py``, ``finite_ball``) and meshes converge to it, not to Hertz. At
v = 0.01 m/s (a_max/R = 0.032, a_max = 1.6 mm) Hertz is the limit (finite ball −1.2 %,
+1.5 %, −1.0 %): the refinement series runs there.

    python benchmarks/two_balls_hertz.py            # the series (about half an hour)
    python benchmarks/two_balls_hertz.py --quick    # one coarse P1 mesh at 1 m/s (seconds)
"""

from __future__ import annotations

import time

import numpy as np
from _common import case, parser, publish_report

from fecontact import simulate

TWO_BALLS = case("two_balls")
R, E, NU = 0.05, 1e7, 0.3
SLOW = 0.01  # m/s
# (v, partner, spacing / R): the plane series, the pair at three meshes, the plane at 1 m/s
SERIES = [(SLOW, "plane", s) for s in (0.08, 0.06, 0.04, 0.03)]
SERIES += [(SLOW, "ball", s) for s in (0.08, 0.04, 0.03)]
SERIES += [(1.0, "plane", 0.08)]


def hertz(mass: float, v: float) -> dict:
    """Hertz's t_c (s), F_max (N) and δ_max (m) of the ball of ``mass`` (kg) on a rigid plane
    at ``v`` (m/s)."""
    e_star = E / (1.0 - NU**2)
    delta = (15.0 * mass * v**2 / (16.0 * e_star * np.sqrt(R))) ** 0.4
    return {
        "t_c": 2.87 * (mass**2 / (R * e_star**2 * v)) ** 0.2,
        "F_max": 4.0 / 3.0 * e_star * np.sqrt(R) * delta**1.5,
        "delta": delta,
    }


def impact(v: float, against: str, params: dict) -> dict:
    """One impact at h = t_c/50: the errors of t_c, F_max and δ_max against Hertz (%)."""
    gap = 0.0004 if v < 0.1 else 0.004  # the start: gap × R between the balls
    ball = TWO_BALLS.build(velocity=v, against="plane", gap=gap, **params).model.bodies[0]
    ref = hertz(ball.mass, v)
    t_end = 0.5 * gap * R / v + 1.3 * ref["t_c"]
    sim = TWO_BALLS.build(velocity=v, against=against, gap=gap, t_end=t_end, **params)
    model, h = sim.model, ref["t_c"] / 50.0
    left = model.bodies[0]
    s = model.body_slice(0)
    # M times the rigid translation along x: its product with v is the momentum along x
    mx = left.mass_matrix() @ left.translation_field((1.0, 0.0, 0.0))
    p_prev, force, delta, steps = float(mx @ sim.v0[s]), [], 0.0, 0
    start = time.perf_counter()
    for st in simulate(model, h, t_end, sim.options, v0=sim.v0):
        p = float(mx @ st.v[s])
        force.append((p_prev - p) / h)
        p_prev, steps = p, steps + 1
        # the centre of mass's displacement along x beyond first contact (gap R / 2)
        delta = max(delta, float(mx @ st.q[s]) / left.mass - 0.5 * gap * R)
    f = np.array(force)
    on = np.flatnonzero(f > 1e-6 * f.max())
    t_c = (on[-1] - on[0] + 1) * h
    return {
        "v (m/s)": v,
        "partner": against if against == "plane" else "ball (mortar, turned 30°)",
        "element": params.get("element", "P1"),
        "spacing / R": params.get("spacing", np.nan) if params.get("graded", 1) else np.nan,
        "dofs": model.n,
        "steps": steps,
        "t_c error (%)": 100.0 * (t_c / ref["t_c"] - 1.0),
        "F_max error (%)": 100.0 * (f.max() / ref["F_max"] - 1.0),
        "δ_max error (%)": 100.0 * (delta / ref["delta"] - 1.0),
        "wall (s)": time.perf_counter() - start,
    }


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    if args.quick:
        coarse = {"graded": 0, "base": 2, "element": "P1"}
        rows = [impact(1.0, partner, coarse) for partner in ("plane", "ball")]
    else:
        rows = []
        for v, partner, spacing in SERIES:
            rows.append(impact(v, partner, {"element": "P2", "spacing": spacing}))
            print(rows[-1], flush=True)
    publish_report(
        args.out, "two_balls_hertz", args.quick, "Two elastic balls head-on against Hertz", rows,
        ("Each ball's t_c, F_max and δ_max against Hertz's ball on a plane, h = t_c/50.", rows),
    )  # fmt: skip


if __name__ == "__main__":
    main()
