"""Redundant contacts in space: more closed rows than the dofs they move.

1. ``cases/tumbling_box.py`` (its impacts land on up to four coplanar corners) with
   ``smooth_contact`` "off" and "on", and p, k × 10, × 0.1 (``penalty_scale``,
   ``multiplier_scale``): the largest difference over the history of q and v against the run
   at p = k = 1, the smallest gap, the height of the centre at the end (0.05 m: on its
   largest face) and the largest velocity there.
2. The same case's cost with "off" and "on", side by side (median of 3, ``fecontact.run``
   without frames): compute time and the counts of the frictional solves (Gauss–Seidel
   fallbacks, least-norm moves, solves with one contact opened, distinct solutions found).
3. An elastic ball dropped at 1 m/s on a box 1000× its mass resting on its four bottom
   corners on a plane, against the same ball on a fixed box: the largest difference of the
   ball's momentum per unit mass over the run.

    python benchmarks/redundant_contacts.py            # about half a minute
    python benchmarks/redundant_contacts.py --quick    # short runs: seconds
"""

from __future__ import annotations

import numpy as np
from _common import case, parser, publish_report, timed_run, with_options

from fecontact import Box, Contact, IntegratorOptions, Model, Plane, RigidBody3D, Solid
from fecontact.bodies import LinearElastic
from fecontact.scenes import wave_step
from fecontact.time import simulate
from fecontact.time.stats import StepStats

SCALES = ((10.0, 1.0), (0.1, 1.0), (1.0, 10.0), (1.0, 0.1))


def tumbling(mode: str, p: float, k: float, t_end: float):
    sim = case("tumbling_box").build(t_end=t_end)
    opts = IntegratorOptions(smooth_contact=mode, penalty_scale=p, multiplier_scale=k)
    return list(simulate(sim.model, sim.dt, t_end, opts, q0=sim.q0, v0=sim.v0)), sim


def independence(t_end: float) -> list[dict]:
    rows = []
    for mode in ("off", "on"):
        base, sim = tumbling(mode, 1.0, 1.0, t_end)
        box = sim.model.bodies[0]
        for p, k in SCALES:
            run, _ = tumbling(mode, p, k, t_end)
            pairs = list(zip(base, run, strict=True))
            rows.append(
                {
                    "smooth_contact": mode,
                    "p": p,
                    "k": k,
                    "max_dq": max(np.abs(a.q - b.q).max() for a, b in pairs),
                    "max_dv": max(np.abs(a.v - b.v).max() for a, b in pairs),
                    "min_gap_m": min(float(np.min(s.gaps)) for s in run[1:]),
                    "z_end_m": float(box.center(run[-1].q)[2]),
                    "v_end": float(np.abs(run[-1].v).max()),
                }
            )
    return rows


def cost(t_end: float, repeats: int) -> list[dict]:
    rows = []
    for mode in ("off", "on"):
        sim = with_options(case("tumbling_box").build(t_end=t_end), smooth_contact=mode)
        r = timed_run(sim, repeats)
        solver = r["summary"]["friction_solver"]
        rows.append(
            {"smooth_contact": mode, "status": r["status"], "compute_s": r["compute"]}
            | {
                key: solver[key]
                for key in (
                    "solves",
                    "gauss_seidel_solves",
                    "least_norm_moves",
                    "opened_contact_solves",
                    "distinct_solutions",
                )
            }
        )
    rows[1]["on_over_off"] = rows[1]["compute_s"] / rows[0]["compute_s"]
    rows[0]["on_over_off"] = 1.0
    return rows


def ball_on_box(on_plane: bool, t_end: float) -> np.ndarray:
    rubber = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
    ball = Solid.ball([0.0, 0.0, 0.052], 0.05, 2, rubber)
    box = RigidBody3D.uniform(1000.0 * ball.mass, [0.0, 0.0, -0.025], Box(0.3, 0.3, 0.05))
    if on_plane:
        floor = Contact(box, Plane([0, 0, -0.05], [0, 0, 1]))
        model = Model([ball, box], [Contact(ball, box), floor], (0.0, 0.0, -9.81))
    else:
        model = Model([ball, box.fix()], [Contact(ball, box)], (0.0, 0.0, -9.81))
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    stats = StepStats()
    p = [
        (model.M_full @ st.v)[: ball.ndof].reshape(-1, 3).sum(axis=0) / ball.mass
        for st in simulate(model, wave_step(ball, 1.0, None), t_end, v0=v0, stats=stats)
    ]
    return np.array(p)


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    t_end, t_ball, repeats = (0.05, 0.001, 1) if args.quick else (0.5, 0.008, 3)
    rows = independence(t_end)
    costs = cost(min(t_end, 0.4), repeats)
    four, fixed = ball_on_box(True, t_ball), ball_on_box(False, t_ball)
    ball = [{"run": "four corners on a plane vs fixed box", "steps": len(four)}]
    ball[0]["max_momentum_diff_m_s"] = float(np.abs(four - fixed).max())
    ball[0]["ball_vz_end_m_s"] = float(four[-1, 2])
    publish_report(
        args.out,
        "redundant_contacts",
        args.quick,
        "Redundant contacts in space",
        rows,
        (f"Tumbling box, {t_end} s: p and k against p = k = 1", rows),
        (f"Tumbling box, first {min(t_end, 0.4)} s: cost side by side", costs),
        (f"Ball on a heavy box, {t_ball} s", ball),
    )


if __name__ == "__main__":
    main()
