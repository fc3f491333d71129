"""Mortar against node-to-surface contact: the patch test and the head-on disks.

1. Patch test: two blocks [0, 1] × [0, 0.5] and [0, 1] × [0.5, 1] m (E = 1e7 and 3e7 Pa,
   ν = 0.3, plane strain, non-matching meshes of n_lower and n_upper cells along x), the
   upper one pressed by p = 1e5 Pa, solved statically with small displacements
   (``fecontact.statics.solve_static_contact``). Per method: the largest displacement error
   against the linear solution (relative to the largest displacement) and the spread of the
   contact pressure, max |z_j/p − 1| over the contact nodes (node-to-surface: nodal force over
   the node's tributary length; its corner nodes are left out, where the closest facet is a
   tie between the face and the side of the lower block).
2. ``cases/two_disks.py`` head-on, both methods side by side in one process (two passes for
   node-to-surface, one interface for mortar), at each refinement: the largest sideways
   centre-of-mass speed |v_y| over the impact speed, the final energy over the initial one,
   the exit speed, steps, the wall time per step (ms, median of the repeats), the CPU time
   per step (ms, mean of the repeats; less sensitive to other processes on the machine) and
   its ratio to node-to-surface's, the step halvings, and the share of the time loop (the
   run's wall time less its output) spent in the contact phase and in the smooth step's
   assembly (which carries the smooth contact force, and with it the mortar integrals of
   persistent contacts). Then the same disks 10 cm apart for 20 ms (no contact: a free
   flight), both methods alternating: the CPU time per step and its ratio.

3. ``cases/two_balls.py`` (3D, graded P1 balls): the mortar interface with the right mesh
   turned by 30° about the impact axis (no node meets a node) and unturned (node on node),
   node-to-surface both ways, and the same ball against the rigid plane of symmetry, at the
   case's step Δx/c and at h = t_c/50 (Hertz's contact duration). Per run: the largest
   lateral centre-of-mass speed of the left ball over its approach speed, its exit speed (the
   normal restitution) against the plane's, the contact duration t_c (from the first to the
   end of the last step with a contact force) and the peak of the per-step contact force
   Σ λ_j + k Λ_j / h, both against Hertz's (a ball on a rigid plane at the impact speed of
   each ball), and the wall time.

4. P2 (quadratic) faces: the patch tests on P2 blocks (7/5 cells) and boxes (4/3 cells) with
   mortar on the curved faces ("quadratic": ``MortarContactP2``, ``MortarContact3DP2``), on
   the faces split into linear pieces ("split") and node-to-surface; then the cost of a P2
   mortar step against a split one: two P2 disks (refinements 2) head-on for 6 ms, the two
   alternating (CPU ms per step, the largest sideways speed), one evaluation of the rows
   with their gradients on the graded P2 balls of ``two_balls`` at their start (ms), and one
   Newton iterate's evaluation of a P2 rubber box (2 × 2 × 1 cm, 2 × 2 × 1 cells) laid on a
   P2 slab (12 × 8 × 1 cm, 6 × 4 × 1 cells) with every dof moved at random by 1e-6 m: its
   rows, gradients and the Hessians of its rows (ms, the least of three).

    python benchmarks/mortar.py            # refinements 1–5, the default balls (an hour)
    python benchmarks/mortar.py --quick    # refinements 1–3, the coarsest uniform balls
    python benchmarks/mortar.py --refinements 1 2 3 4 --coarse-balls   # (20 minutes)
"""

from __future__ import annotations

import time

import numpy as np
from _common import case, parser, publish_report, timed_run

from fecontact import Model, simulate
from fecontact.bodies import Solid
from fecontact.contact.mortar import MortarContact
from fecontact.contact.mortar3d import MortarContact3D
from fecontact.contact.mortar3d_p2 import MortarContact3DP2
from fecontact.contact.mortar_p2_segments import MortarContactP2
from fecontact.scenes import solid_material, wave_step
from fecontact.testing import pressed_blocks, pressed_p2_blocks, pressed_p2_boxes

PATCH_MESHES = ((7, 4), (4, 7), (5, 5), (13, 6))


def patch_rows():
    rows = []
    for n_low, n_up in PATCH_MESHES:
        for method in ("mortar", "node-to-surface"):
            p = 1e5
            pair, parts, lam, exact = pressed_blocks(n_low, n_up, p, method=method)
            scale = max(np.max(np.abs(u)) for u in exact)
            err = max(np.max(np.abs(u - ue)) for u, ue in zip(parts, exact, strict=True))
            active = lam > 0
            if method == "mortar":
                z = pair.nodal_pressure(lam)[1]
            else:
                x = pair.body.X[pair.nodes, 0]
                order = np.argsort(x)
                trib = np.zeros(len(x))
                trib[order[:-1]] += 0.5 * np.diff(x[order])
                trib[order[1:]] += 0.5 * np.diff(x[order])
                # the face's corners carry half a cell more (they are not slave nodes)
                trib[order[0]] += 0.5 * (x[order[0]] - 0.0)
                trib[order[-1]] += 0.5 * (1.0 - x[order[-1]])
                z = lam / trib
            rows.append(
                {
                    "cells lower/upper": f"{n_low}/{n_up}",
                    "method": method,
                    "active nodes": int(active.sum()),
                    "displacement error": err / scale,
                    "pressure spread": float(np.max(np.abs(z[active] / p - 1.0))),
                }
            )
    return rows


def disk_rows(refinements, repeats):
    rows = []
    for ref in refinements:
        for method in ("node-to-surface", "mortar"):
            sim = case("two_disks").build(refinements=ref, method=method)
            cpu = time.process_time()
            r = timed_run(sim, repeats=repeats)
            cpu = (time.process_time() - cpu) / repeats  # less sensitive to a loaded machine
            h, s = r["history"], r["summary"]
            v0 = 1.0
            ph = r["phases"]
            rows.append(
                {
                    "refinements": ref,
                    "method": method,
                    "status": r["status"],
                    "sideways |vy|/v0": float(
                        max(np.max(np.abs(h["vy_left"])), np.max(np.abs(h["vy_right"]))) / v0
                    ),
                    "E_end/E_0": s["energy_final"] / s["energy_initial"],
                    "exit speed (m/s)": float(h["v_right"][-1]),
                    "steps": r["steps"],
                    "ms per step": 1e3 * r["wall"] / r["steps"],
                    "CPU ms per step": 1e3 * cpu / r["steps"],
                    "halvings": int(s.get("step_halvings", 0)),
                    "contact share": ph.get("contact", 0.0) / r["compute"],
                    "assembly share": ph.get("assembly", 0.0) / r["compute"],
                }
            )
            print(rows[-1], flush=True)
        node = rows[-2]["CPU ms per step"]
        for row in rows[-2:]:
            row["CPU ratio"] = row["CPU ms per step"] / node
    return rows


def free_rows(refinements, repeats, t_end=0.02):
    """CPU time per step of the disks in free flight (10 cm apart, ``t_end`` s: 20 ms, 4 ms in
    the quick run), the two methods alternating ``repeats`` times: the median of each and
    their ratio."""
    rows = []
    for ref in refinements:
        cpu = {"node-to-surface": [], "mortar": []}
        for _ in range(repeats):
            for method in cpu:
                sim = case("two_disks").build(refinements=ref, method=method, gap=0.1, t_end=t_end)
                start = time.process_time()
                r = timed_run(sim, repeats=1)
                cpu[method].append(1e3 * (time.process_time() - start) / r["steps"])
        node, mortar = (float(np.median(cpu[m])) for m in cpu)
        rows.append({"refinements": ref, "steps": r["steps"], "node-to-surface CPU ms": node,
                     "mortar CPU ms": mortar, "ratio": mortar / node})  # fmt: skip
        print(rows[-1], flush=True)
    return rows


RADIUS, E_STAR, RHO = 0.05, 1e7 / (1.0 - 0.3**2), 1000.0


def hertz(v: float = 1.0) -> dict:
    """Hertz's duration (s) and peak force (N) of the ball on a rigid plane at ``v`` (m/s)."""
    mass = RHO * 4.0 / 3.0 * np.pi * RADIUS**3
    delta = (15.0 * mass * v**2 / (16.0 * E_STAR * np.sqrt(RADIUS))) ** 0.4
    return {
        "t_c": 2.87 * (mass**2 / (RADIUS * E_STAR**2 * v)) ** 0.2,
        "F_max": 4.0 / 3.0 * E_STAR * np.sqrt(RADIUS) * delta**1.5,
    }


# the balls' meshes: the case's, --coarse-balls', and --quick's (the coarsest, seconds a run)
BALLS = {"default": {}, "coarse": {"spacing": 0.16}, "quick": {"graded": 0, "base": 1}}


def ball_rows(mesh: dict):
    ref = hertz()
    runs = [("mortar", "ball", 30.0), ("mortar", "ball", 0.0), ("node-to-surface", "ball", 30.0),
            ("-", "plane", 0.0)]  # fmt: skip
    rows, plane_exit = [], {}
    for step in ("dx/c", "t_c/50"):
        for method, against, rotate in runs:
            options = {"method": method} if method != "-" else {}
            sim = case("two_balls").build(against=against, rotate=rotate, **options, **mesh)
            if step == "t_c/50":
                sim = sim.replace(dt=ref["t_c"] / 50)
            cpu = time.process_time()
            r = timed_run(sim, repeats=1)
            cpu = time.process_time() - cpu
            h = r["history"]
            force = np.asarray(h["contact_force"])
            on = np.flatnonzero(force > 0.0)
            dt = sim.dt
            t_c = (on[-1] - on[0] + 1) * dt if on.size else np.nan
            lateral = np.hypot(h["vy_left"], h["vz_left"]).max()
            exit_speed = -float(h["vx_left"][-1])
            if against == "plane":
                plane_exit[step] = exit_speed
            rows.append(
                {
                    "step": step,
                    "partner": against if against == "plane" else f"ball, {method}",
                    "turned (deg)": rotate,
                    "status": r["status"],
                    "dofs": sim.model.n,
                    "lateral / v": float(lateral),
                    "exit speed / v": exit_speed,
                    "t_c error (%)": 100.0 * (t_c / ref["t_c"] - 1.0),
                    "F_max error (%)": 100.0 * (force.max() / ref["F_max"] - 1.0),
                    "steps": r["steps"],
                    "wall (s)": r["wall"],
                    "CPU ms per step": 1e3 * cpu / r["steps"],
                }
            )
            print(rows[-1], flush=True)
    for row in rows:
        row["restitution vs plane (%)"] = 100.0 * (
            row["exit speed / v"] / plane_exit[row["step"]] - 1.0
        )
    return rows


def p2_patch_rows():
    rows = []
    for dim, test, cells in ((2, pressed_p2_blocks, (7, 5)), (3, pressed_p2_boxes, (4, 3))):
        for method in ("quadratic", "split", "node-to-surface"):
            _, lam, pressure, error = test(*cells, method=method)
            spread = np.nan if pressure is None else float(np.max(np.abs(pressure - 1.0)))
            rows.append({"dim": dim, "cells lower/upper": "/".join(map(str, cells)),
                         "method": method, "active nodes": int(np.count_nonzero(lam > 0)),
                         "displacement error": error, "pressure spread": spread})  # fmt: skip
    return rows


def p2_disk_run(quadratic: bool, t_end: float):
    """Two P2 disks (refinements 2) head-on at 1 m/s each: CPU s per step and the largest
    sideways speed of the left disk (m/s)."""
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    a = Solid.disk([-0.101, 0.0], 0.1, 2, mat, element="P2")
    b = Solid.disk([0.101, 0.0], 0.1, 2, mat, element="P2")
    pair = (MortarContactP2 if quadratic else MortarContact)(a, b)
    model = Model([a, b], [pair], gravity=(0.0, 0.0))
    v0 = model.translation(a, (1.0, 0.0)) + model.translation(b, (-1.0, 0.0))
    wy = a.mass_matrix() @ a.translation_field((0.0, 1.0))
    options = case("two_disks").build(refinements=1).options
    cpu, steps, lateral = time.process_time(), 0, 0.0
    for st in simulate(model, wave_step(a, 1.0, a.min_edge_length / 2), t_end, options, v0=v0):
        steps += 1
        lateral = max(lateral, abs(float(wy @ st.v[model.body_slice(0)])) / a.mass)
    return (time.process_time() - cpu) / steps, lateral


def p2_cost_rows(repeats: int, t_end: float):
    rows = []
    for quadratic in (True, False) * repeats:  # alternating: the same load on both
        cpu, lateral = p2_disk_run(quadratic, t_end)
        faces = "quadratic" if quadratic else "split"
        rows.append({"problem": "P2 disks head-on", "faces": faces, "CPU ms": 1e3 * cpu,
                     "what": "per step", "sideways |vy|/v0": lateral})  # fmt: skip
    sim = case("two_balls").build(element="P2")
    left, right = sim.model.bodies
    for cls, name in ((MortarContact3DP2, "quadratic"), (MortarContact3D, "split")):
        pair = cls(left, right)
        Model([left, right], [pair], gravity=(0.0, 0.0, 0.0))
        cpu = time.process_time()
        g = pair.evaluate(np.zeros(left.ndof + right.ndof))[0]
        rows.append({"problem": "graded P2 balls", "faces": name,
                     "CPU ms": 1e3 * (time.process_time() - cpu),
                     "what": f"one evaluation, {int(np.isfinite(g).sum())} rows",
                     "sideways |vy|/v0": np.nan})  # fmt: skip
    rows.append(p2_box_row())
    return rows


def p2_box_row() -> dict:
    """One Newton iterate's evaluation (rows, gradients, Hessians) of the P2 box on the P2 slab
    (CPU ms, the least of three states)."""
    mat = solid_material("neo-hookean", 1e7, 0.3, 1000.0)  # a rubber
    slab = Solid.box([-0.06, -0.04, -0.01], [0.06, 0.04, 0.0], (6, 4, 1), mat, element="P2")
    box = Solid.box([-0.01, -0.01, 0.0], [0.01, 0.01, 0.01], (2, 2, 1), mat, element="P2")
    pair = MortarContact3DP2(box, slab)
    model = Model([box, slab], [pair], gravity=(0.0, 0.0, -9.81))
    q = np.random.default_rng(0).normal(0.0, 1e-6, model.n)
    best = np.inf
    for k in range(3):  # (distinct states: an evaluation at the same q is cached)
        cpu = time.process_time()
        g = pair.evaluate(q + k * 1e-12)[0]
        pair.hessians(q + k * 1e-12, np.flatnonzero(np.isfinite(g)))
        best = min(best, time.process_time() - cpu)
    return {"problem": "P2 box on a P2 slab", "faces": "quadratic", "CPU ms": 1e3 * best,
            "what": f"one iterate with Hessians, {int(np.isfinite(g).sum())} rows",
            "sideways |vy|/v0": np.nan}  # fmt: skip


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--refinements", type=int, nargs="+", help="the disks' refinements")
    p.add_argument("--coarse-balls", action="store_true", help="graded balls of spacing 0.16")
    args = p.parse_args()
    refinements, repeats = ((1, 2, 3), 1) if args.quick else ((1, 2, 3, 4, 5), 3)
    refinements = args.refinements or refinements
    patch = patch_rows()
    disks = disk_rows(refinements, repeats)
    free = free_rows(refinements, repeats, 0.004 if args.quick else 0.02)
    balls = ball_rows(
        BALLS["quick" if args.quick else "coarse" if args.coarse_balls else "default"]
    )
    p2_patch = p2_patch_rows()
    p2_cost = p2_cost_rows(1 if args.quick else 3, 0.002 if args.quick else 0.006)
    publish_report(
        args.out, "mortar", args.quick, "Mortar and node-to-surface contact", disks,
        ("Patch test, small displacements, p = 1e5 Pa (relative errors).", patch),
        ("Two elastic disks head-on (cases/two_disks.py), 1 m/s each, side by side.", disks),
        ("The same disks in free flight (10 cm apart, 20 ms), alternating.", free),
        ("Two elastic balls head-on (cases/two_balls.py), 1 m/s each.", balls),
        ("P2 faces: patch tests, quadratic faces against faces split into linear pieces.",
         p2_patch),
        ("P2 faces: cost of a step (disks, alternating) and of an evaluation (balls).", p2_cost),
    )  # fmt: skip


if __name__ == "__main__":
    main()
