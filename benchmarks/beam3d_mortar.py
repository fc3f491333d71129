"""Mortar against node-to-surface contact between a 3D solid and a Beam3D's tube.

Both methods side by side in one process, on the same meshes and steps:

1. ``stand-off``: a straight rod (r = 1 cm) over a block's top face of square cells of edge H,
   above a line of nodes and halfway between two: the centreline's height h at which the least
   weighted gap is zero, and h − r in units of H²/r (the mortar stand-off: > 0 the tube rests
   above the face, < 0 it dips into it between the nodes), for H/r from 2.5 to 0.31.
2. ``drop``: a steel rod (r = 1 cm, 8 elements) falling at 1 m/s under gravity from 3 mm
   above a rubber block 0.1 × 0.1 × 0.03 m (``divisions`` × ``divisions`` × 2 cells, base
   clamped), at 30° across it, h = 0.1 ms: ``across`` the rod is 16 cm long and overhangs
   the block's top edges; ``within`` it is 6 cm long and lies over the face. Node-to-surface
   takes the rod's nodes against the boundary (plus, ``+edges``, its segments against the
   block's convex edges). Per run: status (a run that fails names the step), the steps done,
   Newton iterations and CPU time per step (the stepping alone), the deepest block node
   inside the tube and the deepest rod node below the block's boundary (from the
   coordinates: a node's distance to the centreline polyline, and a rod node's signed
   distance to the plane of the closest boundary triangle) and the rod's mean vertical speed
   at the last step over the approach speed. The mortar drop across the block is run again
   through ``run``: its energy ledger's ``created`` over ``scale``.
3. ``rule``: the rows of a bent rod pressed into a block (the derivative test's set-up) with
   the degree-5 rule on s² sub-triangles of every triangle crossing a region boundary,
   against s = 32.

    python benchmarks/beam3d_mortar.py           # divisions 8 and 12
    python benchmarks/beam3d_mortar.py --quick   # divisions 6, short runs
"""

from __future__ import annotations

import tempfile
import time

import numpy as np
from _common import parser, publish_report
from scipy.optimize import brentq

from fecontact import Model, Solid, run, simulate
from fecontact.bodies import Beam3D, LinearElastic, Material, Section
from fecontact.contact import Contact, SolidEdges
from fecontact.contact.geometry import closest_facet_distance
from fecontact.contact.mortar_beam3d import MortarBeam3D
from fecontact.contact.polyline_distance import closest_on_polyline
from fecontact.errors import SolverError
from fecontact.simulation import Simulation
from fecontact.time.settings import IntegratorOptions

STEEL = Material(210e9, nu=0.3, rho=7850.0)
RUBBER = LinearElastic(1e7, 0.3, rho=1000.0)
R = 0.01


def stand_off(n: int, between: bool) -> dict:
    H = 0.1 / n
    block = Solid.box([0.0, -0.05, -0.02], [0.1, 0.05, 0.0], (4, n, 1), RUBBER)
    y0 = 0.5 * H if between else 0.0
    bar = Beam3D.straight([0.0, y0, 0.0], [0.1, y0, 0.0], 3, STEEL, Section.circle(R))
    pair = MortarBeam3D(block, bar, clearance=R, margin=1.0)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))

    def at(h):
        q = np.zeros(model.n)
        q[block.ndof :].reshape(-1, 6)[:, 2] = h
        return q

    h = brentq(lambda h: pair.gaps(at(h)).min(), 0.5 * R, R + 2 * H + 0.02, xtol=1e-14)
    return {
        "H/r": H / R,
        "rod": "between node lines" if between else "over a node line",
        "h - r (m)": h - R,
        "(h - r) r/H^2": (h - R) * R / H**2,
        "deepest node in tube (m)": max(0.0, -float(pair.node_distances(at(h)).min())),
    }


def drop(method: str, divisions: int, across: bool, t_end: float) -> dict:
    block = Solid.box([-0.05, -0.05, -0.03], [0.05, 0.05, 0.0], (divisions, divisions, 2),
                      RUBBER)  # fmt: skip
    block.fix(block.nodes_where(lambda x: x[2] <= -0.03 + 1e-9))
    d = np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0)), 0.0])
    c, half = np.array([0.003, -0.002, R + 0.003]), 0.08 if across else 0.03
    bar = Beam3D.straight(c - half * d, c + half * d, 8, STEEL, Section.circle(R))
    if method == "mortar":
        pairs = [Contact(block, bar, clearance=R)]
    else:
        pairs = [Contact(bar, block, clearance=R, method="node-to-surface")]
        if method.endswith("+edges"):
            pairs.append(Contact(bar, SolidEdges(block), clearance=R))
    model = Model([block, bar], pairs, gravity=(0.0, 0.0, -9.81))
    nb, tri, segs = block.ndof, block.contact_facets(), bar.segments()
    surface = np.unique(tri)

    def in_tube(st):  # from the coordinates: a block node's distance to the centreline
        ends = bar.positions(st.q[nb:])[segs]
        return R - float(closest_on_polyline(block.positions(st.q[:nb])[surface], ends)[2].min())

    def below(st):  # a rod node's signed distance to its closest boundary triangle's plane
        xb, x = block.positions(st.q[:nb]), bar.positions(st.q[nb:])
        pairs = np.repeat(x, len(tri), 0), np.tile(xb[tri], (len(x), 1, 1))
        dist, g = closest_facet_distance(*pairs)
        k = np.argmin(dist.reshape(len(x), -1), axis=1)
        return -float(g.reshape(len(x), -1)[np.arange(len(x)), k].min())

    v0 = model.translation(bar, (0.0, 0.0, -1.0))
    row = {"case": "across" if across else "within", "method": method, "divisions": divisions}
    steps = simulate(model, 1e-4, t_end, IntegratorOptions(), v0=v0)
    cpu, n, newton, deep, low, st, status = 0.0, 0, 0, 0.0, 0.0, None, "completed"
    while True:
        clock = time.process_time()
        try:
            st = next(steps)
        except StopIteration:
            break
        except SolverError as err:
            status = f"failed at {n * 1e-4 * 1e3:.1f} ms: {str(err).split(':')[1][:50]}"
            break
        cpu += time.process_time() - clock
        n, newton = n + 1, newton + st.newton_iterations
        deep, low = max(deep, in_tube(st)), max(low, below(st))
    vz = float(st.v[nb:].reshape(-1, 6)[:, 2].mean())
    return {**row, "status": status, "steps": n - 1, "Newton per step": newton / max(n - 1, 1),
            "ms per step": 1e3 * cpu / max(n, 1), "node in tube (m)": max(0.0, deep),
            "rod node below (m)": max(0.0, low), "last vz/v0": vz}  # fmt: skip


def ledger(divisions: int, t_end: float) -> dict:
    """The mortar drop across the block through ``run``: its energy ledger."""
    block = Solid.box([-0.05, -0.05, -0.03], [0.05, 0.05, 0.0], (divisions, divisions, 2),
                      RUBBER)  # fmt: skip
    block.fix(block.nodes_where(lambda x: x[2] <= -0.03 + 1e-9))
    d = np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0)), 0.0])
    c = np.array([0.003, -0.002, R + 0.003])
    bar = Beam3D.straight(c - 0.08 * d, c + 0.08 * d, 8, STEEL, Section.circle(R))
    model = Model([block, bar], [Contact(block, bar, clearance=R)], gravity=(0.0, 0.0, -9.81))
    v0 = model.translation(bar, (0.0, 0.0, -1.0))
    sim = Simulation(model, dt=1e-4, t_end=t_end, name="rod_on_block", v0=v0,
                     output_interval=t_end)  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="fecontact_beam3d_mortar_") as tmp:
        s = run(sim, tmp, frames=False, checkpoint_every=0)
    led = s["energy_ledger"]
    return {"divisions": divisions, "status": s["status"], "halvings": s["step_halvings"],
            "max_penetration (m)": s["max_penetration"], "created (J)": led["created"],
            "scale (J)": led["scale"], "created/scale": led["created"] / led["scale"]}  # fmt: skip


def rule_rows() -> list[dict]:
    block = Solid.box([-0.1, -0.1, -0.05], [0.1, 0.1, 0.0], (6, 6, 2), RUBBER)
    nodes = np.array([[-0.09, -0.05, R + 0.002], [-0.03, -0.01, R], [0.02, 0.02, R - 0.001],
                      [0.05, 0.06, R + 0.003], [0.09, 0.07, R + 0.004]])  # fmt: skip
    bar = Beam3D.straight(nodes[0], nodes[-1], 4, STEEL, Section.circle(R))
    rows = {}
    for s in (1, 2, 4, 8, 16, 32):
        pair = MortarBeam3D(block, bar, clearance=R, margin=0.02, subdivisions=s)
        model = Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))
        q = np.zeros(model.n)
        q[block.ndof :].reshape(-1, 6)[:, :3] = nodes - bar.X
        rows[s] = pair.gaps(q)
    ref = rows[32]
    finite = np.isfinite(ref)
    return [{"s": s, "points per cut triangle": 7 * s * s,
             "error (m)": float(np.abs(rows[s][finite] - ref[finite]).max())}
            for s in (1, 2, 4, 8, 16)]  # fmt: skip


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    sizes, divisions = ((4, 8), (6,)) if args.quick else ((4, 8, 16, 32), (8, 12))
    t_end = 0.002 if args.quick else 0.006
    standoff = [stand_off(n, between) for n in sizes for between in (False, True)]
    drops = []
    for div in divisions:
        for across in (True, False):
            for method in ("mortar", "node-to-surface", "node-to-surface+edges"):
                drops.append(drop(method, div, across, t_end))
                print(drops[-1], flush=True)
    ledgers = [ledger(div, t_end) for div in divisions]
    rule = rule_rows()
    publish_report(
        args.out, "beam3d_mortar", args.quick,
        "Mortar and node-to-surface between a 3D solid and a Beam3D's tube", drops,
        ("A rod dropped on a block, across its edges and within its face", drops),
        ("The mortar drop across the block, run with its energy ledger", ledgers),
        ("Stand-off of the weighted gaps: a rod on a face of cells of edge H", standoff),
        ("The rows of a bent rod: the rule on s^2 sub-triangles against s = 32", rule),
    )  # fmt: skip


if __name__ == "__main__":
    main()
