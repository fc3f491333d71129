"""The tube mortar on faces finer than the tube: the washboard of the weighted-distance rows, the
tangent-plane rows that replace them, and the beam's rows on a soft fine face.

1. ``stand-off``: a straight rod (r = 2 cm) over the top face of a block of square cells of
   edge H (H/r = 1, 0.5, 0.25), its axis along the mesh's lines or turned 0.3 rad from them,
   placed at y0 (a fraction of H) off a line of nodes: the centreline's height h at which the
   least row of the face's inner nodes is zero, h − r (m), for the weighted-distance rows
   (``MortarBeam3D``) and the default on these faces, the rows blended toward the tube's
   tangent plane (``TangentPlaneRows``). The spread of h − r over the placements is the
   washboard a rolling rod rides.
2. ``beam rows on a soft face``: the beam's rows (``TubeLineMortar``) on the rod drop across a
   block's edges (r = 1 cm, 1.25 cm cells, 1 m/s, h = 0.1 ms, 3 ms) for the block's Young's
   modulus E: the status, and the solid's node closest to the tube at the last step done.

3. ``rolling``: the fine setup: a steel rod (r = 2 cm, 6 cm, 4 elements) on a rubber block of
   1 cm cells (base clamped), along the mesh's y lines, its axis at x0 off a line of nodes,
   settled at rest (ρ∞ = 0, 40 steps of 1 ms), then launched along x at v₀ = 0.1 m/s without
   spin, μ = 0.3, h = 0.1 ms, 30 ms: it slides, decelerating at μg, until it rolls at
   v₀/(1 + J/(m r²)) = 2/3 v₀ at v₀/(3μg) = 11.3 ms. Per form of the rows (the default,
   blended toward the tangent plane; the weighted distance; the beam's rows): the status, the
   rod's mean speed over v₀ at the end and its range over the last 10 ms, and the highest
   lift of the tube off the block (the least over the centreline's samples of its signed
   distance to the block's boundary less r, from the coordinates; > 0: a hop) and the deepest
   the tube went into the block (the least of that over the run, negated). The default rows
   again with the rod launched from its place at rest, unsettled (the block rings under it:
   the run that stopped at the slip-stick change before the slip rows turned continuously at
   the rod's ends).

    python benchmarks/tube_plane_rows.py           # about five minutes
    python benchmarks/tube_plane_rows.py --quick   # one H/r, one stiff drop, 2 ms rolls
"""

from __future__ import annotations

import numpy as np
from _common import parser, publish_report
from scipy.optimize import brentq

from fecontact import Model, Solid, simulate
from fecontact.bodies import Beam3D, LinearElastic, Material, Section
from fecontact.contact import Contact
from fecontact.contact.inside import Surface
from fecontact.contact.mortar_beam3d import MortarBeam3D
from fecontact.contact.tube_line_mortar import TubeLineMortar
from fecontact.contact.tube_plane import TangentPlaneRows
from fecontact.errors import SolverError
from fecontact.time.settings import IntegratorOptions

STEEL = Material(210e9, nu=0.3, rho=7850.0)
RUBBER = LinearElastic(1e7, 0.3, rho=1000.0)


def stand_off(H: float, y0: float, angle: float, candidate: bool, r=0.02) -> float:
    """h − r (m) where the least row of the face's inner nodes is zero."""
    n = int(round(0.1 / H))
    block = Solid.box([0.0, -0.05, -0.02], [0.1, 0.05, 0.0], (n, n, 1), RUBBER)
    e, c = np.array([np.cos(angle), np.sin(angle), 0.0]), np.array([0.05, y0, 0.0])
    bar = Beam3D.straight(c - 0.1 * e, c + 0.1 * e, 6, STEEL, Section.circle(r))
    pair = (TangentPlaneRows if candidate else MortarBeam3D)(block, bar, clearance=r, margin=1.0)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))
    X = block.X[pair.nodes]
    inner = np.all((X[:, :2] > [1e-9, -0.05 + 1e-9]) & (X[:, :2] < [0.1 - 1e-9, 0.05 - 1e-9]),
                   axis=1) & (X[:, 2] > -1e-9)  # fmt: skip

    def least(h):
        q = np.zeros(model.n)
        q[block.ndof :].reshape(-1, 6)[:, 2] = h
        return pair.gaps(q)[inner].min()

    return brentq(least, 0.5 * r, r + 2 * H + 0.02, xtol=1e-14) - r


def stand_off_rows(ratios) -> list[dict]:
    rows = []
    for angle in (0.0, 0.3):
        for ratio in ratios:
            for candidate in (False, True):
                h = [stand_off(ratio * 0.02, f * ratio * 0.02, angle, candidate)
                     for f in (0.0, 0.1, 0.25, 0.4, 0.5)]  # fmt: skip
                rows.append({"H/r": ratio, "turn (rad)": angle,
                             "rows": "tangent plane" if candidate else "weighted distance",
                             "h - r at y0/H = 0": h[0], "0.25": h[2], "0.5": h[4],
                             "spread over y0 (m)": float(np.ptp(h))})  # fmt: skip
    return rows


def soft_drop(E: float, t_end: float, r=0.01) -> dict:
    """The beam's rows on the rod drop across the block's edges, the block's modulus E."""
    block = Solid.box([-0.05, -0.05, -0.03], [0.05, 0.05, 0.0], (8, 8, 2),
                      LinearElastic(E, 0.3, rho=1000.0))  # fmt: skip
    block.fix(block.nodes_where(lambda x: x[2] <= -0.03 + 1e-9))
    d = np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0)), 0.0])
    c = np.array([0.003, -0.002, r + 0.001])
    bar = Beam3D.straight(c - 0.08 * d, c + 0.08 * d, 8, STEEL, Section.circle(r))
    pair = TubeLineMortar(block, bar, clearance=r)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, -9.81))
    v0 = model.translation(bar, (0.0, 0.0, -1.0))
    status, last = "completed", None
    try:
        for st in simulate(model, 1e-4, t_end, IntegratorOptions(), v0=v0):
            last = st
    except SolverError as err:
        status = f"failed at {1e3 * (last.t + 1e-4):.1f} ms: {str(err)[:60]}"
    return {"E (Pa)": E, "status": status, "t done (ms)": 1e3 * last.t,
            "closest solid node to the tube (m)": float(pair.node_distances(last.q).min()),
            "deepest centreline point in the solid (m)":
                float(pair.watch().depth(last.q)[0])}  # fmt: skip


def rolling(form: str, t_end: float, x0=0.005, mu=0.3, v0=0.1, r=0.02, settle=True) -> dict:
    """The fine setup (module docstring) with the rows ``form``; without ``settle`` the rod
    is launched from its place at rest, touching the block unloaded (the block rings)."""
    block = Solid.box([-0.03, -0.04, -0.02], [0.12, 0.04, 0.0], (15, 8, 2), RUBBER)
    block.fix(block.nodes_where(lambda x: x[2] <= -0.02 + 1e-9))
    c, d = np.array([x0, 0.0, r]), np.array([0.0, 0.03, 0.0])
    bar = Beam3D.straight(c - d, c + d, 4, STEEL, Section.circle(r))
    if form == "default":
        pair = Contact(block, bar, clearance=r, friction=mu)
    else:
        pair = (MortarBeam3D if form == "weighted distance" else TubeLineMortar)(
            block, bar, clearance=r
        )
        pair.friction = mu
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, -9.81))
    ob, surface = model.offset_of(bar), Surface(block.contact_facets())
    s = np.linspace(0.0, 1.0, 9)[:, None, None]
    options = IntegratorOptions(rho_inf=0.0)
    q0, v = None, model.translation(bar, (v0, 0.0, 0.0))
    if settle:
        settled = list(simulate(model, 1e-3, 0.04, options))[-1]
        q0, v = settled.q, settled.v + v
    times, speed, lift, status = [], [], [], "completed"
    try:
        for st in simulate(model, 1e-4, t_end, options, q0=q0, v0=v):
            ends = bar.positions(st.q[ob:])[bar.segments()]
            points = ((1.0 - s) * ends[:, 0] + s * ends[:, 1]).reshape(-1, 3)
            x = block.positions(st.q[: block.ndof])
            lift.append(float(surface.signed_distance(x, points, pad=r)[0].min()) - r)
            times.append(st.t)
            speed.append(np.linalg.norm(st.v[ob:].reshape(-1, 6)[:, :2].mean(axis=0)) / v0)
    except SolverError as err:
        status = f"failed at {1e3 * (times[-1] + 1e-4):.1f} ms: {str(err)[:50]}"
    times, speed = np.array(times), np.array(speed)
    late = times >= times[-1] - 0.01
    return {"rows": form if settle else f"{form}, unsettled", "status": status,
            "v/v0 at the end": speed[-1],
            "v/v0 range, last 10 ms": f"{speed[late].min():.4f}-{speed[late].max():.4f}",
            "highest lift (m)": max(lift), "deepest (m)": -min(lift)}  # fmt: skip


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    ratios = (0.5,) if args.quick else (1.0, 0.5, 0.25)
    standoff = stand_off_rows(ratios)
    drops = [soft_drop(E, 1e-3 if args.quick else 3e-3)
             for E in ((1e9,) if args.quick else (1e9, 1e8, 1e7))]  # fmt: skip
    rolls = [rolling(form, 2e-3 if args.quick else 0.03)
             for form in ("default", "weighted distance", "beam rows")]  # fmt: skip
    rolls.append(rolling("default", 2e-3 if args.quick else 0.03, settle=False))
    publish_report(
        args.out, "tube_plane_rows", args.quick,
        "The tube mortar on fine faces: the washboard, the tangent-plane rows, the beam's rows",
        standoff,
        ("Rest height of a straight rod on a fine face: the two forms of the solid's rows",
         standoff),
        ("The beam's rows on the rod drop across a block's edges, by the block's stiffness",
         drops),
        ("Rolling on the fine setup: 2/3 v0 expected from 11.3 ms", rolls),
    )  # fmt: skip


if __name__ == "__main__":
    main()
