"""The washboard of the solid's rows of the tube mortar on fine faces, and what the beam's rows
do on a soft fine face.

1. ``stand-off``: a straight rod (r = 2 cm) over the top face of a block of square cells of
   edge H (H/r = 1, 0.5, 0.25), its axis along the mesh's lines or turned 0.3 rad from them,
   placed at y0 (a fraction of H) off a line of nodes: the centreline's height h at which the
   least row of the face's inner nodes is zero, h − r (m), for the solid's rows
   (``MortarBeam3D``, the dual-weighted distance to the tube) and for a candidate form of
   them, rows only (no gradient, not in the package): each row blended, by the node's angle
   under the axis, toward the node's gap from the tube's tangent plane facing it,

       g_j ← g_j + w_j (ν'_j·(p_j − x_j) − r − g_j),

   ν'_j the node's face normal turned across the axis, p_j its closest centreline point,
   w_j = smoothstep of c_j = ν'_j·(p_j − x_j)/|p_j − x_j| from cos 60° (0) to cos 45° (1).
   On a flat face the tangent-plane gap is linear, so rows with w_j = 1 are exact wherever
   the tube lies; rows with w_j < 1 lie more than r to the side and read above zero. The
   spread of h − r over the placements is the washboard a rolling rod rides.
2. ``beam rows on a soft face``: the beam's rows (``TubeLineMortar``) on the rod drop across a
   block's edges (r = 1 cm, 1.25 cm cells, 1 m/s, h = 0.1 ms, 3 ms) for the block's Young's
   modulus E: the status, and the solid's node closest to the tube at the last step done.

    python benchmarks/tube_plane_rows.py           # about two minutes
    python benchmarks/tube_plane_rows.py --quick   # one H/r, one stiff drop of 1 ms
"""

from __future__ import annotations

import numpy as np
from _common import parser, publish_report
from scipy.optimize import brentq

from fecontact import Model, Solid, simulate
from fecontact.bodies import Beam3D, LinearElastic, Material, Section
from fecontact.contact.mortar_beam3d import (
    MortarBeam3D,
    across_axis,
    facing_normals,
    row_triangles,
)
from fecontact.contact.polyline_distance import closest_on_polyline
from fecontact.contact.tube_line_mortar import TubeLineMortar
from fecontact.errors import SolverError
from fecontact.time.settings import IntegratorOptions

STEEL = Material(210e9, nu=0.3, rho=7850.0)
RUBBER = LinearElastic(1e7, 0.3, rho=1000.0)
FULL, NONE = np.cos(np.radians(45.0)), np.cos(np.radians(60.0))


def plane_rows(pair: MortarBeam3D, model: Model, q: np.ndarray) -> np.ndarray:
    """The candidate rows (module docstring) of ``pair`` at q: values only."""
    g = pair.gaps(q)
    block, bar = pair.body, pair.beam
    x = block.positions(q[: block.ndof])
    ends = bar.positions(q[model.offset_of(bar) :])[pair.segments]
    xj = x[pair.nodes]
    seg, xi, d = closest_on_polyline(xj, ends)
    t = np.clip(xi, 0.0, 1.0)[:, None]
    u = (1.0 - t) * ends[seg, 0] + t * ends[seg, 1] - xj
    tris = row_triangles(pair.element_rows, pair.size)
    nu = across_axis(facing_normals(x, pair.facets, tris, u), ends[seg], xi)
    c = np.einsum("mi,mi->m", nu, u) / d
    s = np.clip((c - NONE) / (FULL - NONE), 0.0, 1.0)
    w = s * s * (3.0 - 2.0 * s)
    return np.where(np.isfinite(g), g + w * (c * d - pair.clearance - g), g)


def stand_off(H: float, y0: float, angle: float, candidate: bool, r=0.02) -> float:
    """h − r (m) where the least row of the face's inner nodes is zero."""
    n = int(round(0.1 / H))
    block = Solid.box([0.0, -0.05, -0.02], [0.1, 0.05, 0.0], (n, n, 1), RUBBER)
    e, c = np.array([np.cos(angle), np.sin(angle), 0.0]), np.array([0.05, y0, 0.0])
    bar = Beam3D.straight(c - 0.1 * e, c + 0.1 * e, 6, STEEL, Section.circle(r))
    pair = MortarBeam3D(block, bar, clearance=r, margin=1.0)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))
    X = block.X[pair.nodes]
    inner = np.all((X[:, :2] > [1e-9, -0.05 + 1e-9]) & (X[:, :2] < [0.1 - 1e-9, 0.05 - 1e-9]),
                   axis=1) & (X[:, 2] > -1e-9)  # fmt: skip

    def least(h):
        q = np.zeros(model.n)
        q[block.ndof :].reshape(-1, 6)[:, 2] = h
        rows = plane_rows(pair, model, q) if candidate else pair.gaps(q)
        return rows[inner].min()

    return brentq(least, 0.5 * r, r + 2 * H + 0.02, xtol=1e-14) - r


def stand_off_rows(ratios) -> list[dict]:
    rows = []
    for angle in (0.0, 0.3):
        for ratio in ratios:
            for candidate in (False, True):
                h = [stand_off(ratio * 0.02, f * ratio * 0.02, angle, candidate)
                     for f in (0.0, 0.1, 0.25, 0.4, 0.5)]  # fmt: skip
                rows.append({"H/r": ratio, "turn (rad)": angle,
                             "rows": "tangent-plane blend" if candidate else "weighted distance",
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


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    ratios = (0.5,) if args.quick else (1.0, 0.5, 0.25)
    standoff = stand_off_rows(ratios)
    drops = [soft_drop(E, 1e-3 if args.quick else 3e-3)
             for E in ((1e9,) if args.quick else (1e9, 1e8, 1e7))]  # fmt: skip
    publish_report(
        args.out, "tube_plane_rows", args.quick,
        "The tube mortar on fine faces: the washboard, a tangent-plane form, the beam's rows",
        standoff,
        ("Rest height of a straight rod on a fine face: the solid's rows and the candidate",
         standoff),
        ("The beam's rows on the rod drop across a block's edges, by the block's stiffness",
         drops),
    )  # fmt: skip


if __name__ == "__main__":
    main()
