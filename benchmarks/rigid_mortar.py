"""Mortar against node-to-surface contact between a 3D solid and a RigidBody3D (Ball, Box).

Both methods side by side in one process, on the same meshes and steps:

1. ``flat``: the elastic ball of ``ball_drop`` (P1, ``refinements``) at 1 m/s onto a rigid
   box 1000 times its mass, fixed, its pole over the middle of the top face; ``edge``: the
   same with the box's edge (along y) 0, 0.5, 1, 1.5 and 2 cm from the pole (Hertz's contact
   radius at the peak is 1.00 cm). Per run: the ball's vertical centre-of-mass velocity at
   the end (the rebound), its lateral centre-of-mass velocity along x at the end (signed:
   > 0 toward the box's middle) and its largest lateral speed, over the approach speed, the
   deepest node inside the box (from the nodes' own coordinates in the box's frame) over the
   ball's shortest edge, the energy ledger's ``created`` over its ``scale``, halvings and the
   CPU time per step.
2. ``slab``: a rigid ball (5 cm, 1000 kg/m³) at 1 m/s on an elastic slab 0.1 × 0.1 × 0.04 m
   (``divisions`` × ``divisions`` × 3 cells, clamped at its base), at the slab's Δx/c: the
   contact duration t_c (first to last step with a contact force), the time of the first
   contact (the ball starts 1 mm above: the sphere reaches the slab's flat top at 1.00 ms and
   its nearest node at 1.13 ms; earlier is a stand-off), the instant the ball turns, the
   deepest point of the slab's surface inside the sphere (over its triangles' integration
   points, between the nodes), the ball's rebound speed, ``created``/``scale``, halvings and
   the CPU time per step.
3. ``pressed``: a block (3 × 4 × 2 cells) loaded by 1 kPa on its top face, resting on a box:
   the largest |z_j/p − 1| over its bottom nodes at rest.
4. The integration of one triangle straddling a box edge, ∫ Φ_i D dA / |e| (m) with the
   degree-5 rule on s² sub-triangles, against s = 256.
5. ``box laid on slab``: a rigid box 2 × 2 × 1 cm laid at rest on a clamped slab 12 × 8 × 1
   cm (6 × 4 × 1 cells) under gravity, 20 steps (5 with ``--quick``): the CPU time per step,
   Newton's iterations, the located trials and release probes (docs/validation/solid_sweep.md);
   the same box thrown along the slab at 0.5 m/s with μ 0.3, and the Coulomb solver's work.

    python benchmarks/rigid_mortar.py           # refinements 2 and 3, divisions 8 and 16
    python benchmarks/rigid_mortar.py --quick   # refinement 1, divisions 8, short runs

Refinements 4 (18,051 dofs, about 10 min a run on one core) were run with ``ball_on_box``
from this module for the edge at 0.5 and 1 cm (docs/explanation/mortar_rigid.md).
"""

from __future__ import annotations

import tempfile
import time

import numpy as np
from _common import parser, publish_report

from fecontact import Model, Probe, SolverError, run
from fecontact.bodies import LinearElastic, RigidBody3D, Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.bodies.shapes3d import Ball, Box
from fecontact.contact import Contact
from fecontact.contact.rigid_distance import shape_distance, triangle_rule
from fecontact.io.output import read_history, read_json
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation
from fecontact.testing import block_on_rigid_box
from fecontact.time.settings import IntegratorOptions

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
NEO_HOOKEAN = NeoHookean(1e7, 0.3, 1000.0)
METHODS = ("mortar", "node-to-surface")


def measured(sim, body, extra):
    """Run ``sim`` (no frames) and return its summary, history and CPU time per step."""
    with tempfile.TemporaryDirectory(prefix="fecontact_rigid_mortar_") as tmp:
        cpu = time.process_time()
        try:
            summary = run(sim, tmp, frames=False, checkpoint_every=0)
        except SolverError:  # (a box's edge deep in the ball: the run stops and says so)
            summary = read_json(f"{tmp}/summary.json")
        cpu = time.process_time() - cpu
        history = read_history(f"{tmp}/history.csv")
    if summary["status"] != "completed":
        summary["status"] = f"failed at {1e3 * history['t'][-1]:.3g} ms"
    ledger = summary["energy_ledger"]
    return {
        **extra,
        "status": summary["status"],
        "halvings": int(summary.get("step_halvings", 0)),
        "least squares": int(summary.get("least_squares_multipliers", 0)),
        "max_penetration (m)": float(summary.get("max_penetration", np.nan)),
        "created/scale": ledger["created"] / ledger["scale"],
        "CPU ms per step": 1e3 * cpu / max(len(history["t"]) - 1, 1),
    }, history


def ball_on_box(inside, method: str, refinements: int, t_end: float, v: float = 1.0, **options):
    """The ball at ``v`` (m/s) onto the box's face centre (``inside`` None) or with the box's
    edge ``inside`` (m) from the pole; ``options`` of the integrator (``IntegratorOptions``)."""
    R = 0.05
    ball = Solid.ball([0.0, 0.0, R + 0.002], R, refinements, RUBBER)
    x0 = 0.0 if inside is None else 0.15 - inside
    box = RigidBody3D.uniform(1000 * ball.mass, [x0, 0.0, -0.025], Box(0.3, 0.3, 0.05)).fix()
    model = Model([ball, box], [Contact(ball, box, method=method)], (0.0, 0.0, -9.81))
    w = [ball.mass_matrix() @ ball.translation_field(e) / ball.mass for e in np.eye(3)]
    n = ball.ndof
    probes = {
        f"v{c}": Probe(lambda m, st, w=w[k]: float(w @ st.v[:n]), "m/s", c)
        for k, c in enumerate("xyz")
    }
    half = 0.5 * box.shape.sides

    def depth(m, st):  # the deepest node inside the box, from the nodes' own coordinates
        rho = ball.positions(st.q[:n]) - box.position
        inside = np.all(np.abs(rho) < half, axis=1)
        return float(np.max(np.min(half - np.abs(rho[inside]), axis=1), initial=0.0))

    probes["depth"] = Probe(depth, "m", "deepest node inside the box")
    v0 = model.translation(ball, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes,
                     name="ball_on_box", v0=v0, output_interval=t_end,
                     options=IntegratorOptions(**options))  # fmt: skip
    case = "flat" if inside is None else f"edge {100 * inside:g} cm"
    extra = {"case": case, "method": method, "refinements": refinements, "v (m/s)": v}
    row, h = measured(sim, ball, extra | options)
    row["rebound vz/v0"] = float(h["vz"][-1]) / v
    row["vx/v0"] = float(h["vx"][-1]) / v
    row["lateral max/v0"] = float(np.max(np.hypot(h["vx"], h["vy"]))) / v
    row["deepest/edge"] = max(0.0, float(np.max(h["depth"]))) / ball.min_edge_length
    return row


def rigid_ball_on_slab(method: str, divisions: int, t_end: float):
    width, thick, radius = 0.1, 0.04, 0.05
    slab = Solid.box([-width / 2, -width / 2, -thick], [width / 2, width / 2, 0.0],
                     (divisions, divisions, 3), RUBBER)  # fmt: skip
    slab.fix(slab.nodes_where(lambda x: x[2] <= -thick * (1.0 - 1e-9)))
    ball = RigidBody3D.of_density(1000.0, [0.003, -0.002, radius + 0.001], Ball(radius))
    model = Model([slab, ball], [Contact(slab, ball, method=method)], (0.0, 0.0, -9.81))
    o = slab.ndof
    facets, (lam, _) = slab.contact_facets(), triangle_rule(2)

    def between(m, st):  # the deepest point of the slab's triangles inside the sphere
        t = slab.positions(st.q[:o])[facets]
        points = np.einsum("pk,tkd->tpd", lam, t).reshape(-1, 3) - ball.center(st.q[o : o + 6])
        return float(max(0.0, -np.min(np.linalg.norm(points, axis=1) - radius)))

    probes = {
        "vz": Probe(lambda m, st: float(st.v[o + 2]), "m/s", "ball"),
        "force": Probe(lambda m, st: float(st.mean_force().sum()), "N", "contact"),
        "between": Probe(between, "m", "deepest point of the slab's surface in the sphere"),
    }
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    sim = Simulation(model, dt=wave_step(slab, 1.0), t_end=t_end, probes=probes,
                     name="rigid_ball_on_slab", v0=v0, output_interval=t_end)  # fmt: skip
    row, h = measured(sim, slab, {"case": "slab", "method": method, "divisions": divisions})
    t, on = np.asarray(h["t"]), np.flatnonzero(np.asarray(h["force"]) > 0.0)
    dt = t[1] - t[0]
    row["first contact (ms)"] = 1e3 * (t[on[0]] - dt) if len(on) else np.nan
    row["t_c (ms)"] = 1e3 * (t[on[-1]] - t[on[0]] + dt) if len(on) else np.nan
    vz = np.asarray(h["vz"])
    turn = np.flatnonzero((vz[:-1] < 0.0) & (vz[1:] >= 0.0))
    i = turn[0] if len(turn) else -1
    row["turns (ms)"] = 1e3 * (t[i] - vz[i] * dt / (vz[i + 1] - vz[i])) if len(turn) else np.nan
    row["deepest between nodes (mm)"] = 1e3 * float(np.max(h["between"]))
    row["rebound vz/v0"] = float(h["vz"][-1])
    return row


def box_laid_on_slab(method: str, steps: int, friction: float = 0.0, v: float = 0.0):
    """A rigid box 2 × 2 × 1 cm (1000 kg/m³) laid at rest on a rubber slab 12 × 8 × 1 cm
    (Neo-Hookean, 6 × 4 × 1 cells, clamped at its base) under gravity, ``steps`` steps of Δx/c
    of the same box in rubber (86 µs), as in docs/validation/solid_sweep.md: the slab's
    triangles around the box are cut by the box's region planes (112 points each), and the
    contact forces ring, so that the steps are located and release probes run. With
    ``friction`` and ``v`` (m/s, along x): the box thrown along the slab, and the Coulomb
    solver's work (its Newton iterations, line-search cuts and Gauss–Seidel solves)."""
    slab = Solid.box([-0.06, -0.04, -0.01], [0.06, 0.04, 0.0], (6, 4, 1), NEO_HOOKEAN)
    slab.fix(slab.nodes_where(lambda x: x[2] <= -0.01 + 1e-9))
    like = Solid.box([-0.01, -0.01, 0.0], [0.01, 0.01, 0.01], (2, 2, 1), NEO_HOOKEAN)
    box = RigidBody3D.of_density(1000.0, [0.0, 0.0, 0.005], Box(0.02, 0.02, 0.01))
    contact = Contact(slab, box, method=method, friction=friction)
    model = Model([slab, box], [contact], (0.0, 0.0, -9.81))
    dt = wave_step(like, 1.0)
    v0 = model.translation(box, (v, 0.0, 0.0)) if v else None
    sim = Simulation(model, dt=dt, t_end=steps * dt, name="box_laid_on_slab",
                     output_interval=steps * dt, v0=v0)  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="fecontact_rigid_mortar_") as tmp:
        cpu = time.process_time()
        summary = run(sim, tmp, frames=False, checkpoint_every=0)
        cpu = time.process_time() - cpu
    cost, coulomb = summary["localization_cost"], summary.get("friction_solver") or {}
    case = f"box thrown at {v:g} m/s, mu {friction:g}" if v else "box laid on slab"
    return {
        "case": case, "method": method, "status": summary["status"],
        "steps": summary["steps"], "CPU ms per step": 1e3 * cpu / max(summary["steps"], 1),
        "Newton iterations": summary["newton_iterations_total"],
        "located trials": cost["smooth_steps"], "release probes": cost.get("release_probes"),
        "max_penetration (m)": float(summary["max_penetration"]),
        "Coulomb iterations": coulomb.get("iterations", 0),
        "line-search cuts": coulomb.get("line_search_cuts", 0),
        "Gauss-Seidel solves": coulomb.get("gauss_seidel_solves", 0),
    }  # fmt: skip


def pressed_block(method: str):
    pressure, _ = block_on_rigid_box(method)
    return {
        "case": "pressed",
        "method": method,
        "pressure spread": float(np.max(np.abs(pressure / 1e3 - 1))),
    }


def integration_rows():
    box = Box(0.1, 0.1, 0.1)
    corner = np.array([0.05, 0.0, 0.05])
    tri = corner + np.array([[-0.01, 0.0, 0.002], [0.012, 0.01, -0.001], [-0.005, 0.02, 0.008]])

    def integral(s):
        lam, w = triangle_rule(s)
        D = shape_distance(box, lam @ tri, False)[0]
        return (w[:, None] * (4 * lam - 1) * D[:, None]).sum(axis=0)

    ref = integral(256)
    return [{"s": s, "points": 7 * s * s, "error (m)": float(np.abs(integral(s) - ref).max())}
            for s in (1, 2, 4, 8, 16)]  # fmt: skip


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    refinements, divisions = ((1,), (8,)) if args.quick else ((2, 3), (8, 16))
    t_box, t_slab = (0.002, 0.002) if args.quick else (0.008, 0.0075)
    boxes, slabs = [], []
    for ref in refinements:
        for inside in (None, 0.0, 0.005, 0.01, 0.015, 0.02):
            for method in METHODS:
                boxes.append(ball_on_box(inside, method, ref, t_box))
                print(boxes[-1], flush=True)
    for div in divisions:
        for method in METHODS:
            slabs.append(rigid_ball_on_slab(method, div, t_slab))
            print(slabs[-1], flush=True)
    steps = 5 if args.quick else 20
    laid = [box_laid_on_slab(m, steps) for m in METHODS]
    laid += [box_laid_on_slab(m, steps, friction=0.3, v=0.5) for m in METHODS]
    print(*laid, sep="\n", flush=True)
    pressed = [pressed_block(m) for m in METHODS]
    rule = integration_rows()
    publish_report(
        args.out, "rigid_mortar", args.quick,
        "Mortar and node-to-surface between a 3D solid and a RigidBody3D", boxes + slabs,
        ("An elastic ball onto a heavy box (face centre, and 0-2 cm inside an edge)", boxes),
        ("A rigid ball onto an elastic slab", slabs),
        ("A rigid box laid on an elastic slab, and thrown along it: the cost of a step", laid),
        ("A block pressed by 1 kPa on a box: max |z/p - 1| at rest", pressed),
        ("One triangle across a box edge: the rule on s^2 sub-triangles", rule),
    )  # fmt: skip


if __name__ == "__main__":
    main()
