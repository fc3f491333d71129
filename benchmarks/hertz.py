"""Elastic ball on a rigid plane against Hertz's theory: a mesh convergence study.

``cases/ball_drop.py`` without gravity: the ball (R = 0.05 m, E = 10 MPa, ν = 0.3,
ρ = 1000 kg/m³, linear elastic) touches the plane at t = 0 moving at v = 1 m/s toward it.
Quadratic isoparametric tetrahedra (P2, the boundary curved onto the sphere) at three
refinements, and the linear tetrahedra (P1, a polyhedral ball) of the same node counts for
comparison. Hertz (quasi-static, frictionless, rigid plane): with E* = E/(1 − ν²) and the
ball's mass m,

    δ_max = (15 m v² / (16 E* √R))^{2/5},   F_max = 4/3 E* √R δ_max^{3/2},
    t_c = 2.87 (m² / (R E*² v))^{1/5},      v_out / v = 1.

m is the finite element mass (P2: −1.5 %, −0.10 %, −0.007 % from the sphere's at
refinements 1, 2, 3; P1: −8.9 %, −2.3 %, −0.59 % at 2, 3, 4). The theory is quasi-static: it
assumes the ball's inertia acts as on a rigid body and no energy is left in vibrations. Here
the contact lasts about three periods of the ball's lowest vibration mode (t_c ≈ 6 ms against
2R/c = 0.86 ms for the dilatational wave), a/R ≈ 0.2 at the peak, and the ball's bulk
compliance under its own decelerating inertia (order F/(E R) ≈ 0.6 mm against δ_max = 2.1 mm)
is outside the half-space solution: agreement to a few per cent is what the theory supports,
not its limit.

Measured per mesh, with no other force than the plane's acting (total momentum p changes only
by the impulses Σ_j k Λ_j):

- t_c: the end of the last step with an active contact (the contact starts at t = 0);
- F_max: the peak of the mean force Δp/Δt over a window of t_c/20 (Hertz's t_c; whole steps,
  0.3 ms). The mean of the Hertz pulse over such a window at its peak is 0.15 % below F_max.
  The per-step force Σ k Λ_j / h is also listed ("per step"): it is noisy, since a ring of
  nodes entering contact takes its momentum in one step;
- δ_max: the largest approach of the ball's centre of mass toward the plane;
- v_out / v: the rebound speed of the centre of mass over the impact speed;
- δ_static: the same ball resting on the plane under a uniform body force of total Hertz's
  F_max (the inertia of a rigidly decelerating ball), solved to equilibrium by damped
  dynamics (mass-proportional damping 1500 1/s, 30 ms; the last tenth of the run moves the
  centre by the "settled" amount), against Hertz's static approach (3F/(4E*√R))^{2/3}: the
  quasi-static problem of the same mesh, without the impact's dynamics;
- how well the contact zone is resolved: Δx, the shortest distance between nodes, against
  Hertz's largest contact radius a_max = √(R δ_max) ≈ 10 mm, and the largest number of nodes
  in contact at once.

Graded P1 balls ("P1 graded", ``graded_mesh``): the uniform P1 ball of refinement 2 or 3,
its tetrahedra within 2 a_max of the pole bisected 1–6 times (scikit-fem's conforming
adaptive bisection, the new boundary vertices projected onto the sphere), resolve the contact
patch with up to 37 nodes at a few thousand dofs; the bulk keeps the base mesh (mass −6 to
−7 % and −2 % from the sphere's).

The step is the largest power of two (in s) below 0.15 of the dilatational transit time across
the shortest distance between nodes (the shortest edge, half of it for P2): every step then has
the same h to the last bit. The "h/2" rows halve it. The detection margin is 1 % of the model
size.

    python benchmarks/hertz.py            # P2 1, 2, 3 (and h/2), P1 2, 3, 4, P1 graded
    python benchmarks/hertz.py --quick    # P2 refinements 1 and 2 only
    python benchmarks/hertz.py --graded-only   # the graded series into the existing table
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import skfem
from _common import (
    case,
    machine_note,
    markdown_table,
    parser,
    read_csv,
    write_csv,
    write_markdown,
)

from fecontact import Contact, IntegratorOptions, LinearElastic, Model, Plane, Solid, simulate

RADIUS, E, NU, RHO, V = 0.05, 1e7, 0.3, 1000.0, 1.0
WINDOW = 1.0 / 20.0  # of Hertz's contact duration
CAP = 2.0  # of Hertz's a_max: the graded meshes' refined region around the pole


def hertz(mass: float) -> dict:
    """Hertz's contact duration (s), peak force (N) and approach (m) for the ball."""
    e_star = E / (1.0 - NU**2)
    delta = (15.0 * mass * V**2 / (16.0 * e_star * math.sqrt(RADIUS))) ** 0.4
    return {
        "t_c": 2.87 * (mass**2 / (RADIUS * e_star**2 * V)) ** 0.2,
        "F_max": 4.0 / 3.0 * e_star * math.sqrt(RADIUS) * delta**1.5,
        "delta": delta,
    }


def windowed_peak(p: np.ndarray, h: float, window: float) -> float:
    """max over t of (p(t + w) − p(t)) / w, w the whole number of steps nearest ``window``."""
    k = max(1, round(window / h))
    return float(np.max(p[k:] - p[:-k]) / (k * h))


def static_approach(ball, force: float, damping: float = 1500.0, duration: float = 0.03):
    """(approach of the centre of mass (m), its range over the last tenth of the run (m)) of
    ``ball`` resting on the plane z = 0 under a uniform body force of total ``force`` (N),
    by damped dynamics (mass-proportional ``damping``, 1/s) over ``duration`` (s)."""
    g = force / ball.mass
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    model = Model([ball], [Contact(ball, floor)], gravity=(0.0, 0.0, -g), damping=(damping, 0.0))
    spacing = ball.min_edge_length / (2.0 if ball.element == "P2" else 1.0)
    dt = 2.0 ** math.floor(math.log2(0.3 * spacing / ball.material.wave_speed))
    w = ball.mass_matrix() @ ball.translation_field((0.0, 0.0, 1.0))
    options = IntegratorOptions(detection_margin=0.01)
    approach = [-(w @ st.q) / ball.mass for st in simulate(model, dt, duration, options)]
    tail = approach[-max(1, len(approach) // 10) :]
    return approach[-1], max(tail) - min(tail)


def graded_mesh(bisections: int, base: int = 2, cap: float = CAP) -> skfem.MeshTet:
    """The P1 ball of refinement ``base`` (2: 12.5 mm edges, 3: 6.25 mm) centred at (0, 0, R),
    its tetrahedra whose centroid lies within ``cap`` × a_max of the pole (0, 0, 0) bisected
    ``bisections`` times (scikit-fem's conforming adaptive bisection: about three halve the
    edges), the new boundary vertices projected radially onto the sphere as ``init_ball``
    places its own."""
    centre = np.array([[0.0], [0.0], [RADIUS]])
    reach = cap * math.sqrt(RADIUS * hertz(4.0 / 3.0 * math.pi * RADIUS**3 * RHO)["delta"])
    mesh = skfem.MeshTet.init_ball(base).scaled(RADIUS).translated(centre[:, 0])
    for _ in range(bisections):
        centroids = mesh.p[:, mesh.t].mean(axis=1)
        mesh = mesh.refined(np.flatnonzero(np.linalg.norm(centroids, axis=0) < reach))
        before = _volumes(mesh)
        p, boundary = mesh.p.copy(), mesh.boundary_nodes()
        x = p[:, boundary] - centre
        p[:, boundary] = centre + RADIUS * x / np.linalg.norm(x, axis=0)
        mesh = skfem.MeshTet(p, mesh.t)
        # the projection moves a vertex by about Δx²/(8R): no cell may turn inside out
        if np.any(np.sign(_volumes(mesh)) != np.sign(before)):
            raise RuntimeError("projecting the boundary onto the sphere inverted a cell")
    return mesh


def _volumes(mesh) -> np.ndarray:
    """Signed volumes of the tetrahedra (m³; the sign is the vertex order's orientation)."""
    a, b, c = (mesh.p[:, mesh.t[i]] - mesh.p[:, mesh.t[0]] for i in (1, 2, 3))
    return np.einsum("ij,ij->j", np.cross(a, b, axis=0), c) / 6.0


def graded_case(bisections: int, base: int = 2):
    """``ball_drop``'s model (no gravity, e_N = 0, ρ∞ = 0.5) on ``graded_mesh(bisections, base)``:
    (model, ball, options, initial velocities)."""
    ball = Solid(graded_mesh(bisections, base), LinearElastic(E=E, nu=NU, rho=RHO), element="P1")
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * RADIUS)
    model = Model([ball], [Contact(ball, floor, restitution=0.0)], gravity=(0.0, 0.0, 0.0))
    return model, ball, IntegratorOptions(rho_inf=0.5), model.translation(ball, (0.0, 0.0, -V))


def measure(element: str, refinements: int, dt_factor: float = 1.0, graded=None) -> dict:
    """One impact: duration, peak force, approach and rebound, with Hertz's values. With
    ``graded`` = base the P1 ball is ``graded_mesh(refinements, base)``."""
    if graded is not None:
        model, ball, options, v0 = graded_case(refinements, graded)
    else:
        sim = case("ball_drop").build(
            radius=RADIUS, refinements=refinements, element=element, E=E, nu=NU, rho=RHO,
            drop_height=0.0, velocity=V, gravity=0.0, t_end=1.0,
        )  # fmt: skip
        model, options, v0 = sim.model, sim.options, sim.v0
        ball = model.bodies[0]
    ref = hertz(ball.mass)
    spacing = ball.min_edge_length / (2.0 if element == "P2" else 1.0)
    dt = 2.0 ** math.floor(math.log2(0.15 * spacing / ball.material.wave_speed)) * dt_factor
    options.detection_margin = 0.01
    w = ball.mass_matrix() @ ball.translation_field((0.0, 0.0, 1.0))  # z-momentum weights
    momentum, approach, per_step, touching = [], [], [], []
    t_last, after, steps = 0.0, 0, 0
    start = time.perf_counter()
    for st in simulate(model, dt, 3.0 * ref["t_c"], options, v0=v0):
        momentum.append(float(w @ st.v))
        approach.append(-float(w @ st.q) / ball.mass)
        if st.step == 0:
            continue
        steps += 1
        per_step.append(float(st.impulse.sum()) / st.h)
        touching.append(int(np.count_nonzero((st.nu > 0) | (st.impulse > 0))))
        if np.any((st.nu > 0) | (st.impulse > 0)):
            t_last, after = st.t, 0
        else:
            after += 1
            if after * dt > 0.1 * ref["t_c"]:  # left the plane for good
                break
    wall = time.perf_counter() - start
    static = (math.nan, math.nan)
    if dt_factor == 1.0:  # the body holds no state: the same ball, resting in a new model
        static = static_approach(ball, ref["F_max"])
    e_star = E / (1.0 - NU**2)
    delta_static_hertz = (3.0 * ref["F_max"] / (4.0 * e_star * math.sqrt(RADIUS))) ** (2 / 3)
    p = np.array(momentum)
    f_window = windowed_peak(p, dt, WINDOW * ref["t_c"])
    delta = max(approach)

    def error(x, exact):
        return 100.0 * (x / exact - 1.0)

    return {
        "element": element,
        "refinements": refinements,
        "dofs": model.n,
        "contact_nodes": model.contacts.size,
        "spacing_mm": 1e3 * spacing,
        "a_per_spacing": math.sqrt(RADIUS * ref["delta"]) / spacing,
        "touching_max": max(touching),
        "dt_us": 1e6 * dt,
        "steps": steps,
        "t_c_ms": 1e3 * t_last,
        "t_c_hertz_ms": 1e3 * ref["t_c"],
        "t_c_error_pct": error(t_last, ref["t_c"]),
        "F_max_N": f_window,
        "F_max_hertz_N": ref["F_max"],
        "F_max_error_pct": error(f_window, ref["F_max"]),
        "F_step_error_pct": error(max(per_step), ref["F_max"]),
        "delta_mm": 1e3 * delta,
        "delta_hertz_mm": 1e3 * ref["delta"],
        "delta_error_pct": error(delta, ref["delta"]),
        "delta_static_error_pct": error(static[0], delta_static_hertz),
        "static_settled_um": 1e6 * static[1],
        "rebound": p[-1] / (ball.mass * V),
        "wall_s": wall,
    }


COLUMNS = [
    "element", "refinements", "dofs", "contact_nodes", "spacing_mm", "a_per_spacing",
    "touching_max", "dt_us", "steps", "t_c_ms",
    "t_c_hertz_ms", "t_c_error_pct", "F_max_N", "F_max_hertz_N", "F_max_error_pct",
    "F_step_error_pct", "delta_mm", "delta_hertz_mm", "delta_error_pct",
    "delta_static_error_pct", "static_settled_um", "rebound", "wall_s",
]  # fmt: skip
HEADERS = [
    "element", "refinements", "dofs", "boundary nodes", "Δx (mm)", "a_max / Δx",
    "nodes in contact (max)", "h (µs)", "steps", "t_c (ms)",
    "Hertz t_c (ms)", "t_c error (%)", "F_max (N)", "Hertz F_max (N)", "F_max error (%)",
    "per-step F_max error (%)", "δ_max (mm)", "Hertz δ_max (mm)", "δ_max error (%)",
    "static δ error (%)", "static settled (µm)", "v_out / v", "wall (s)",
]  # fmt: skip


READING = """\
Reading (measured when this file was written). Convergence toward Hertz is not monotone, and
the finest meshes end 6–7 % from it; the table says why.

- Resolution of the contact zone. Hertz's contact radius grows to a_max ≈ 10 mm. At P2
  refinement 1 (node spacing 12.5 mm) only the pole node ever touches: a point load, soft
  (F_max −19 %). At refinement 2 (6.25 mm) the pole touches alone until 0.22 t_c, then a ring
  of four nodes enters at once; with e_N = 0 at each node the ring is stopped within a step and
  the contact stiffness jumps from one node to five, so the force overshoots (+20 %) while the
  approach stays within 3 %. Only refinement 3 (3.1 mm, a_max/Δx = 3.3, up to 17 nodes in
  contact) covers the patch with several rings. P1 meshes with the same nodes show the same
  sequence (one node, the five-node jump, then 15 nodes), stiffer at refinement 3 (+14 %).
- Time step. Halving h moves t_c, F_max and δ_max by at most 1.6 percentage points at the
  coarse meshes and 0.3 at P2 refinement 3: the remaining difference is not temporal.
- Contact enforcement. The centre-of-mass approach from the positions and from ∫v dt agree to
  0.02 % (P2, refinements 1 and 2): the position corrections do not move the ball; momentum
  changes only by the impulses, whose windowed mean is the force reported.
- Quasi-static law of the same mesh. Loaded statically by its own decelerating inertia, the
  P2 refinement-3 ball's centre approaches the plane 9.8 % less than Hertz predicts at that
  force (5.2 % at refinement 2; P1: 7.6 % and 10.5 % at refinements 3 and 4; the one-node
  meshes are soft and had not settled in 30 ms): the finite ball under a body force is
  stiffer, in this measure, than Hertz's half-space. A contact law 9.8 % stiffer in δ
  predicts δ_max −6.0 %, F_max +6.4 %, t_c −6.0 % for the impact; measured: −7.0 %, +7.1 %,
  −6.6 % (P1 refinement 4: 10.5 % predicts −6.4 %, +6.9 %, −6.4 %; measured −6.2 %, +8.8 %,
  −6.2 %). The impact is the quasi-static response of the discrete ball to about one per cent
  (the dynamics: t_c is only about three periods of the ball's lowest mode; 0.4–2.6 % of the
  impact's kinetic energy does not return to the rebound, v_out/v = 0.987–0.998, through
  vibration, the nodes' e_N = 0 and the numerical damping of ρ∞ = 0.5).
- So the finest rows measure the static F–δ law of the meshed ball, which has not converged:
  its error went from −5.2 % to −9.8 % between refinements 2 and 3 as the pole's point-load
  softness vanished. The likely cause, not tested here, is the ball's bulk deformation under
  a body force (order F/(E R) = 0.6 mm against δ_max = 2.1 mm), which the half-space solution
  leaves out. A fourth level (P2 refinement 4, 1.4e5 dofs) or a
  mesh graded toward the pole would be needed to see that law settle; the P1 and P2 balls
  agree with each other to 0.4–1.7 points at the finest level.
- Graded meshes (P1, refined within 2 a_max of the pole). With 19–37 nodes in contact
  (a_max/Δx = 7–10) at 5000–8700 dofs the base-3 series settles: its last two levels agree
  within 0.5 points (t_c −6.3 %, F_max +8.9 % and +9.4 %, δ_max −6.2 % and −6.5 %), and the
  base-2 series with 33 nodes in contact lands within a point of them (−7.0 %, +8.7 %, −7.3 %)
  despite its 12.5 mm bulk. The way there is not monotone: with 9 nodes in contact
  (a_max/Δx = 3–4) both series overshoot the force by +14–15 % as the uniform meshes do, then
  fall; t_c and δ_max stay 5.5–8.6 % short at every level. The limit is not Hertz but the
  finest uniform rows' (P1 refinement 4: −6.2 %, +8.8 %, −6.2 %), and the graded balls' static
  law is 11.6–12.5 % stiffer in δ than Hertz's (uniform P1 refinement 4: 10.5 %, with a finer
  bulk). Resolving the patch further does not close the gap: the remaining 6–7 % in t_c and
  δ_max and 9 % in F_max belong to the meshed ball's quasi-static F–δ law, not to the contact
  patch's resolution or the time step."""


def report(rows, out, stem, reading=READING) -> str:
    """Write ``stem``.csv and ``stem``.md into ``out``; return the Markdown table."""
    table = markdown_table(rows, COLUMNS, HEADERS)
    write_csv(f"{out}/{stem}.csv", rows, COLUMNS)
    write_markdown(
        f"{out}/{stem}.md",
        "# Elastic ball on a rigid plane against Hertz\n\n"
        + __doc__.split("\n\n", 1)[1].split("    python")[0].strip()
        + "\n\n"
        + table
        + "\n\n"
        + reading
        + f"\n\nMachine: {machine_note()}\n",
    )
    return table


# (base refinement, bisections toward the pole) of the graded P1 series
GRADED = [(2, 3), (2, 4), (2, 5), (2, 6), (3, 1), (3, 2), (3, 3), (3, 4)]


def main(argv=None) -> int:
    p = parser(__doc__.splitlines()[0])
    p.add_argument(
        "--graded-only",
        action="store_true",
        help="run the graded series alone and replace its rows in the existing hertz.csv/md",
    )
    args = p.parse_args(argv)
    runs = [("P2", 1, 1.0, None), ("P2", 1, 0.5, None), ("P2", 2, 1.0, None), ("P2", 2, 0.5, None)]
    if not args.quick:
        runs += [("P2", 3, 1.0, None), ("P2", 3, 0.5, None)]
        runs += [("P1", r, 1.0, None) for r in (2, 3, 4)]
        runs += [("P1 graded", b, 1.0, base) for base, b in GRADED]
    rows = []
    if args.graded_only:
        runs = [("P1 graded", b, 1.0, base) for base, b in GRADED]
        old = read_csv(f"{args.out}/hertz.csv")
        rows = [{k: str(v) if k == "refinements" else v for k, v in r.items()} for r in old]
        rows = [r for r in rows if r["element"] != "P1 graded"]
    for element, refinements, factor, base in runs:
        row = measure(element[:2], refinements, factor, graded=base)
        row["element"] = element
        row["refinements"] = f"{refinements}" + (" (h/2)" if factor != 1.0 else "")
        if base is not None:
            row["refinements"] = f"{base} + {refinements} bisections"
        rows.append(row)
        print(
            f"{element} refinements {row['refinements']}: t_c {row['t_c_error_pct']:+.1f} %, "
            f"F_max {row['F_max_error_pct']:+.1f} % (per step {row['F_step_error_pct']:+.1f} "
            f"%), delta {row['delta_error_pct']:+.1f} %, rebound {row['rebound']:.3f}, "
            f"{row['wall_s']:.0f} s",
            file=sys.stderr,
            flush=True,
        )
    print(report(rows, args.out, "hertz_quick" if args.quick else "hertz"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
