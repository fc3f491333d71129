"""Beams and beam contacts beyond the bundled cases' rows: contact from the other side, bodies
of different lengths, elements and materials, 3D beams with contact and friction, adaptive
steps, localization, extreme parameters, and p × 1000 / k ÷ 100 on the new configurations.

Each run is a subprocess (``--worker``, the case matrix's worker protocol) that records, at
every step, an independent penetration measured from the positions alone on the beams'
centrelines, not only their nodes: the chords between nodes (the element's centreline) sampled
at ``SAMPLES`` points each, against the obstacle or the other body, less the radius or half
thickness. A disk against a strip is measured by its centre's distance to the chord polyline,
signed by the side it started on (a disk through the strip reads reach + distance). The
founding pendulums' stop holds the tip node alone by definition: their depth is the tip's.

    python benchmarks/explore_beams.py            # every row (90), about 5 min
    python benchmarks/explore_beams.py --quick    # a few cheap rows
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from _common import markdown_table, parser, write_csv, write_markdown
from case_matrix import measurements, run_measured, run_worker, segment_distance, state_difference

SAMPLES = 17  # points per chord of the penetration measure (ends included)
CREATED = 1e-3  # ledger's created over its scale beyond which a row is flagged
PEN_REL = 1e-6  # depth over the configuration's length beyond which a row is flagged
PK_REL = 1e-6  # change of the final state under p × 1000 or k ÷ 100 beyond which it is flagged
R_ROD = 0.005
# a mirror of a Beam3D's dofs (u, ψ), y → −y or z → −z: ψ is an axial vector
MIRRORS = {"y": np.array([1, -1, 1, -1, 1, -1.0]), "z": np.array([1, 1, -1, -1, -1, 1.0])}


# -- independent depth measures ------------------------------------------------------------------


def chord_points(x: np.ndarray) -> np.ndarray:
    """``SAMPLES`` points on each chord of the polyline through the nodes ``x`` (n, d)."""
    t = np.linspace(0.0, 1.0, SAMPLES)[None, :, None]
    return (x[:-1, None] + t * (x[1:] - x[:-1])[:, None]).reshape(-1, x.shape[1])


def plane_depth(points: np.ndarray, point, normal, clearance: float, extent=None) -> float:
    """Deepest of ``points`` behind the plane, less ``clearance`` (m; 0 outside), within
    ``extent`` of ``point`` along the plane."""
    d = points - np.asarray(point)
    h = d @ np.asarray(normal)
    if extent is not None:
        h = h[np.linalg.norm(d - h[:, None] * normal, axis=1) <= extent]
    return float(max(0.0, np.max(clearance - h, initial=-np.inf)))


def side_of(c: np.ndarray, x: np.ndarray) -> tuple[float, float]:
    """Distance of point ``c`` to the polyline ``x`` (2D) and the side of its nearest chord
    (+1 left of the chord's direction, −1 right)."""
    a, b = x[:-1], x[1:]
    d = segment_distance(c[None], a, b)[0]
    t = b - a
    w = c - a
    s = np.clip(np.sum(w * t, 1) / np.sum(t * t, 1), 0.0, 1.0)
    k = int(np.argmin(np.linalg.norm(w - s[:, None] * t, axis=1)))
    return float(d), float(np.sign(t[k, 0] * w[k, 1] - t[k, 1] * w[k, 0]) or 1.0)


def disk_strip_depth(beam, disk, reach: float, sl_beam, sl_disk):
    """Depth of a rigid disk in a strip (m): reach − distance on its first side, reach +
    distance on the other."""
    start = {}

    def depth(q):
        x = beam.positions(q[sl_beam])
        c = disk.positions(q[sl_disk]).mean(0)
        d, side = side_of(c, x)
        s0 = start.setdefault("side", side)
        return max(0.0, reach - d) if side == s0 else reach + d

    return depth


def tube_depth(x: np.ndarray, a: np.ndarray, b: np.ndarray, reach: float) -> float:
    """Deepest of the chord points of the polyline ``x`` within ``reach`` of segments a→b."""
    return float(max(0.0, reach - np.min(segment_distance(chord_points(x), a, b))))


# -- the configurations --------------------------------------------------------------------------


def case_sim(name: str, params: dict):
    from fecontact.cli.cases import load_case

    return load_case(name).build(**params)


def node_depth(sim, nodes_only: bool):
    """Depth of the first body's centreline (or its tip node) against the pair's plane."""
    model = sim.model
    pair, beam = model.contacts.pairs[0], model.bodies[0]
    plane, sl = pair.obstacle, model.body_slice(0)
    clearance = pair.clearance or 0.0

    def depth(q):
        x = beam.positions(q[sl])
        pts = x[-1:] if nodes_only else chord_points(x)
        return plane_depth(pts, plane.point, plane.normal, clearance, plane.extent)

    return depth


def pendulum(params: dict, case: str = "flexible_pendulum"):
    sim = case_sim(case, params)
    return sim, node_depth(sim, nodes_only=True), 0.3


def rod_drop(params: dict):
    sim = case_sim("rod_drop", params)
    return sim, node_depth(sim, nodes_only=False), 0.5


def rod_on_post(params: dict):
    sim = case_sim("rod_on_post", params)
    rod, post = sim.model.bodies[:2]
    full = {"post_distance": 0.325, "post_azimuth": 60.0, "post_radius": 0.02}
    full.update({"post_bottom": -0.5, "post_top": 0.2, **params})
    az = math.radians(full["post_azimuth"])
    foot = full["post_distance"] * np.array([math.cos(az), math.sin(az)])
    a = np.array([[*foot, full["post_bottom"]]])
    b = np.array([[*foot, full["post_top"]]])
    reach = full["post_radius"] + R_ROD
    sl = sim.model.body_slice(0)
    return sim, lambda q: tube_depth(rod.positions(q[sl]), a, b, reach), 0.5


def disk_on_beam(params: dict):
    sim = case_sim("disk_on_beam", params)
    beam, disk = sim.model.bodies
    reach = disk.shape.radius + sim.model.contacts.pairs[0].clearance
    m = sim.model
    return sim, disk_strip_depth(beam, disk, reach, m.body_slice(0), m.body_slice(1)), 1.0


def disk_under_beam(params: dict):
    """The strip of ``disk_on_beam``, the disk below it thrown up at ``speed``."""
    from fecontact import Model, Simulation
    from fecontact.bodies import Beam2D, Disk, Material, RigidBody2D, Section
    from fecontact.contact import Contact

    p = {"n_elements": 21, "E": 210e9, "speed": 2.0, "restitution": 0.0, "position": 0.5}
    p.update({"friction": 0.0, "vx": 0.0, "spin": 0.0, **params})
    t, r = 0.01, 0.05
    beam = Beam2D.straight(
        [0.0, 0.0], [1.0, 0.0], p["n_elements"], Material(p["E"], rho=7850.0),
        Section.rectangle(0.05, t),
    ).pin(0).pin(-1)  # fmt: skip
    disk = RigidBody2D.uniform(1.0, [p["position"], -(0.5 * t + 0.02 + r)], Disk(r))
    e, mu = p["restitution"], p["friction"]
    hit = Contact(disk, beam, restitution=e, clearance=t / 2, friction=mu)
    model = Model([beam, disk], [hit])
    v0 = model.translation(disk, (p["vx"], p["speed"]))
    v0[model.body_slice(1)][2] = p["spin"]
    sim = Simulation(model, dt=2e-4, t_end=0.1, v0=v0, name="disk_under_beam")
    depth = disk_strip_depth(beam, disk, r + t / 2, model.body_slice(0), model.body_slice(1))
    return sim, depth, 1.0


def bars(params: dict):
    """Two axial bars on the x axis: the left one from −L₁ to 0, the right one from ``gap`` to
    ``gap`` + L₂; ``v_left``, ``v_right`` their speeds; ``swap`` names the pair right first."""
    from fecontact import Model, Simulation
    from fecontact.contact import Contact
    from fecontact.scenes import axial_bar

    p = {"L1": 1.0, "L2": 1.0, "n1": 100, "n2": 100, "E1": 1.0, "E2": 1.0, "restitution": 0.0}
    p.update({"v_left": 0.1, "v_right": 0.0, "swap": False, **params})
    left = axial_bar([-p["L1"], 0.0], [0.0, 0.0], p["n1"], p["E1"], 1.0, 1.0)
    right = axial_bar([0.0, 0.0], [p["L2"], 0.0], p["n2"], p["E2"], 1.0, 1.0)
    pair = (
        Contact(right, left, nodes=(0, -1), restitution=p["restitution"])
        if p["swap"]
        else Contact(left, right, nodes=(-1, 0), restitution=p["restitution"])
    )
    model = Model([left, right], [pair], gravity=(0.0, 0.0))
    v0 = model.translation(left, (p["v_left"], 0.0)) + model.translation(right, (p["v_right"], 0))
    dt = 0.5 * min(p["L1"] / p["n1"], p["L2"] / p["n2"] / math.sqrt(p["E2"]))
    sim = Simulation(model, dt=dt, t_end=2.5 * max(p["L1"], p["L2"]), v0=v0, name="bars")
    s0, s1 = model.body_slice(0), model.body_slice(1)

    def depth(q):
        xl, xr = left.positions(q[s0])[:, 0], right.positions(q[s1])[:, 0]
        return max(0.0, float(np.max(xl) - np.min(xr)))

    return sim, depth, max(p["L1"], p["L2"])


def crossing_rods(params: dict):
    """Rod a (along x) meets rod b (60° to it, horizontal) at their middles, from above
    (``side`` +1) or below (−1), at 1 m/s, with ``slide`` m/s along x; ``held``: b clamped."""
    from fecontact import Model, Simulation
    from fecontact.bodies import Beam3D, Material, Section
    from fecontact.contact import Contact

    p = {"side": 1.0, "slide": 0.0, "friction": 0.0, "restitution": 0.0, "n": 5, "held": False}
    p.update({"speed": 1.0, **params})
    steel = Material(210e9, nu=0.3, rho=7850.0)
    d = np.array([math.cos(math.pi / 3), math.sin(math.pi / 3), 0.0])
    z = p["side"] * (2 * R_ROD + 0.001)
    a = Beam3D.straight([-0.15, 0, z], [0.15, 0, z], p["n"], steel, Section.circle(R_ROD))
    b = Beam3D.straight(-0.15 * d, 0.15 * d, p["n"], steel, Section.circle(R_ROD))
    if p["held"]:
        b.clamp(0).clamp(-1)
    pair = Contact(a, b, clearance=2 * R_ROD, restitution=p["restitution"], friction=p["friction"])
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(a, (p["slide"], 0.0, -p["side"] * p["speed"]))
    sim = Simulation(model, dt=1e-5, t_end=0.004, v0=v0, name="crossing_rods")
    s0, s1 = model.body_slice(0), model.body_slice(1)

    def depth(q):
        xb = b.positions(q[s1])
        return tube_depth(a.positions(q[s0]), xb[:-1], xb[1:], 2 * R_ROD)

    return sim, depth, 0.3


def cantilever_wall(params: dict):
    """The right-angle cantilever with a plane at height ``z`` (normal ``up``) on every node
    (``friction``): the elbow swings into it."""
    from fecontact import Model
    from fecontact.contact import Contact, Plane

    p = {"z": -2.0, "up": 1.0, "friction": 0.0, "restitution": 0.0, "t_end": 12.0}
    p.update({"rho_inf": 1.0, "n_per_leg": 4, **params})
    case = {k: p[k] for k in ("t_end", "rho_inf", "n_per_leg")}
    sim = case_sim("right_angle_cantilever", case)
    beam = sim.model.bodies[0]
    wall = Plane([0.0, 0.0, p["z"]], [0.0, 0.0, p["up"]])
    hit = Contact(beam, wall, restitution=p["restitution"], friction=p["friction"])
    model = Model([beam], [hit], loads=sim.model.loads, gravity=(0.0, 0.0, 0.0))
    sim = sim.replace(model=model)

    def depth(q):
        return plane_depth(chord_points(beam.positions(q)), wall.point, wall.normal, 0.0)

    return sim, depth, 10.0


BUILDERS = {
    "flexible_pendulum": pendulum,
    "spatial_pendulum": lambda p: pendulum(p, "spatial_pendulum"),
    "rod_drop": rod_drop,
    "rod_on_post": rod_on_post,
    "disk_on_beam": disk_on_beam,
    "disk_under_beam": disk_under_beam,
    "bars": bars,
    "crossing_rods": crossing_rods,
    "cantilever_wall": cantilever_wall,
}


# -- the rows ------------------------------------------------------------------------------------


@dataclasses.dataclass
class Row:
    """One run: configuration ``config`` (of ``BUILDERS``), its ``params``, integrator
    ``options``, the step × ``dt_factor``, ``t_end`` (s, None: the builder's); ``ref``: the
    label of the row whose final state it must reproduce (p/k), ``mirror``: mirrored in y."""

    config: str
    label: str
    params: dict = dataclasses.field(default_factory=dict)
    options: dict = dataclasses.field(default_factory=dict)
    dt_factor: float = 1.0
    t_end: float | None = None
    ref: str = ""
    mirror: str = ""
    quick: bool = False


PK = ({"penalty_scale": 1e3}, {"multiplier_scale": 1e-2})
E1MU1 = {"restitution": 1.0, "friction": 1.0}
YAW_MU = {"yaw_rate": 20.0, "friction": 0.3}
LOC = {"localize": True}
SLIDE = {"friction": 0.3, "slide": 0.5}
HELD = {"side": -1.0, "slide": 0.5, "friction": 0.3, "held": True}


def pk_rows(config: str, label: str, params: dict, t_end=None, quick=False) -> list[Row]:
    """The configuration ``label`` and its p × 1000, k ÷ 100 twins."""
    out = [Row(config, label, params, t_end=t_end, quick=quick)]
    for tag, opt in zip(("p x1000", "k /100"), PK, strict=True):
        out.append(Row(config, f"{label}, {tag}", params, opt, t_end=t_end, ref=label))
    return out


def pendulum_rows() -> list[Row]:
    fp, sp = "flexible_pendulum", "spatial_pendulum"
    out = pk_rows(fp, "e_N=1 mu=1", {"restitution": 1.0, "friction": 1.0}, 0.6)
    for n in (1, 2, 64):
        out.append(Row(fp, f"{n} elements", {"n_elements": n}, t_end=0.6, quick=n == 2))
    out += [
        Row(fp, "E/100", {"E": 0.7e9}, t_end=0.6),
        Row(fp, "E x100", {"E": 7e12}, t_end=0.6),
        Row(fp, "dt x4", {}, dt_factor=4.0, t_end=0.6),
        Row(fp, "rtol 1e-4", {}, {"rtol": 1e-4}, t_end=0.6),
        Row(fp, "localize on, mu=1", {"friction": 1.0}, {"localize": True}, t_end=0.6),
    ]
    oop = {"out_of_plane_velocity": 0.5}
    out += pk_rows(sp, "out of plane 0.5, mu=0.3", {**oop, "friction": 0.3}, 0.6)
    out += [
        Row(sp, "out of plane 0.5, e_N=1 mu=1", {**oop, **E1MU1}, t_end=0.6),
        Row(sp, "out of plane 0.5, dt x4", oop, dt_factor=4.0, t_end=0.6),
        Row(sp, "out of plane 0.5, rtol 1e-4", oop, {"rtol": 1e-4}, t_end=0.6),
        Row(sp, "out of plane 0.5, localize on", oop, {"localize": True}, t_end=0.6),
        Row(sp, "out of plane 2", {"out_of_plane_velocity": 2.0}, t_end=0.6),
        Row(sp, "out of plane 2, mu=1", {"out_of_plane_velocity": 2.0, "friction": 1.0}, t_end=0.6),
    ]
    return out


def rod_rows() -> list[Row]:
    rd, rp = "rod_drop", "rod_on_post"
    out = [Row(rd, f"{n} elements", {"n_elements": n}, t_end=0.02, quick=n == 1) for n in (1, 2)]
    out += [
        Row(rd, "64 elements", {"n_elements": 64}, t_end=0.01),
        Row(rd, "E/1000", {"E": 210e6}, t_end=0.02),
        Row(rd, "E x1000", {"E": 210e12}, t_end=0.02),
        Row(rd, "dt x4", {}, dt_factor=4.0, t_end=0.02),
        Row(rd, "rtol 1e-4", {}, {"rtol": 1e-4}, t_end=0.02),
        Row(rd, "yaw 20, e_N=1 mu=1", {"yaw_rate": 20.0, **E1MU1}, t_end=0.02),
        Row(rd, "yaw 20, mu=0.3, localize on", YAW_MU, {"localize": True}, t_end=0.02),
        Row(rd, "64 elements, mu=0.3, localize on", {"n_elements": 64, "friction": 0.3}, LOC),
        Row(rd, "nearly upright 89, e_N=1", {"angle": 89.0, "restitution": 1.0}, t_end=0.02),
    ]
    out[-2].t_end = 0.02
    out += pk_rows(rd, "upright 80, mu=1", {"angle": 80.0, "friction": 1.0}, 0.02)
    out += pk_rows(
        rp, "falls on the cap", {"spin": 0.0, "post_azimuth": 0.0, "post_top": -0.03}, 0.08
    )
    out += [
        Row(rp, "default", {}, t_end=0.13),
        Row(
            rp,
            "mirrored",
            {"spin": -10.0, "post_azimuth": -60.0},
            t_end=0.13,
            ref="default",
            mirror="y",
        ),
        Row(rp, "2 elements", {"n_elements": 2}, t_end=0.13),
        Row(rp, "64 elements", {"n_elements": 64}, t_end=0.13),
        Row(rp, "rtol 1e-4", {}, {"rtol": 1e-4}, t_end=0.13),
        Row(rp, "dt x4", {}, dt_factor=4.0, t_end=0.13),
    ]
    cr = "crossing_rods"
    out += [
        Row(cr, "from above", {}),
        Row(cr, "from below", {"side": -1.0}, ref="from above", mirror="z", quick=True),
        Row(cr, "from above, localize on", {}, {"localize": True}),
        Row(cr, "from above, 30 m/s, dt x10", {"speed": 30.0}, dt_factor=10.0),
        Row(cr, "from above, sliding, mu=0.3, rtol 1e-4", SLIDE, {"rtol": 1e-4}),
        Row(cr, "from below, held, sliding, mu=0.3, localize on", HELD, LOC),
    ]
    out += pk_rows(cr, "from below, held, sliding, mu=0.3", HELD)
    out.append(
        Row(cr, "from above, e_N=1 mu=1", {"restitution": 1.0, "friction": 1.0, "slide": 1.0})
    )
    out.append(Row(cr, "1 element, from below", {"n": 1, "side": -1.0}))
    cw = "cantilever_wall"
    out += pk_rows(cw, "floor z=-2, mu=0.3", {"friction": 0.3})
    out.append(Row(cw, "ceiling z=3", {"z": 3.0, "up": -1.0, "t_end": 5.0}))
    mu = {"friction": 0.3}
    out.append(Row(cw, "floor z=-2, mu=0.3, rho_inf 0.5", {**mu, "rho_inf": 0.5}))
    out.append(Row(cw, "floor z=-2, mu=0.3, dt x0.5", mu, dt_factor=0.5))
    out.append(Row(cw, "floor z=-2, mu=0.3, 10 per leg", {**mu, "n_per_leg": 10}))
    rtol = {"rtol": 1e-3}
    out.append(Row(cw, "floor z=-2, mu=0.3, rho_inf 0.5, rtol 1e-3", {**mu, "rho_inf": 0.5}, rtol))
    return out


def strip_rows() -> list[Row]:
    db, du = "disk_on_beam", "disk_under_beam"
    t = 0.15
    out = [Row(db, f"{n} elements", {"n_elements": n}, t_end=t, quick=n == 2) for n in (1, 2, 64)]
    out += [
        Row(db, "E/1000", {"E": 210e6}, t_end=t),
        Row(db, "E x1000", {"E": 210e12}, t_end=t),
        Row(db, "e_N=1, dt x4", {"restitution": 1.0}, dt_factor=4.0, t_end=t),
        Row(db, "rtol 1e-4", {}, {"rtol": 1e-4}, t_end=t),
        Row(db, "near the support", {"position": 0.03}, t_end=t),
    ]
    out += pk_rows(du, "from below", {}, quick=True)
    out += [
        Row(du, "from below, e_N=1", {"restitution": 1.0}),
        Row(du, "from below, 2 elements", {"n_elements": 2}),
        Row(du, "from below, E/1000", {"E": 210e6}),
        Row(du, "from below, localize on", {}, {"localize": True}),
        Row(du, "from below, 64 elements", {"n_elements": 64}),
        Row(du, "from below, near the support", {"position": 0.03}),
        Row(du, "from below, oblique, spin, mu=0.5", {"friction": 0.5, "vx": 1.0, "spin": 30.0}),
    ]
    b = "bars"
    out += [
        Row(b, "lengths 1 and 0.5", {"L2": 0.5, "n2": 50}, quick=True),
        Row(b, "target 4x stiffer", {"E2": 4.0}),
        Row(b, "elements 100 and 37", {"n2": 37}),
        Row(b, "right bar strikes", {"v_left": 0.0, "v_right": -0.1}),
        Row(b, "pair named right first", {"swap": True}),
        Row(b, "head-on, e_N=1", {"v_right": -0.1, "restitution": 1.0}),
        Row(b, "2 and 1 elements", {"n1": 2, "n2": 1}),
    ]
    out += pk_rows(b, "lengths 1 and 0.5, stiffer", {"L2": 0.5, "n2": 50, "E2": 4.0})
    return out


def all_rows() -> list[Row]:
    return strip_rows() + pendulum_rows() + rod_rows()


# -- the worker ----------------------------------------------------------------------------------


def run_row(row: Row) -> dict:
    """Run ``row`` in this process: the case matrix's measurements and this script's depth."""
    from fecontact import InputError

    out = {"status": "crash", "message": "", "wall": math.nan}
    clock = time.perf_counter()
    last = {}
    try:
        sim, measure, length = BUILDERS[row.config](row.params)
        options = dataclasses.replace(sim.options, **row.options)
        t_end = row.t_end or sim.t_end
        sim = sim.replace(dt=sim.dt * row.dt_factor, t_end=t_end, options=options)
        out.update(dt=sim.dt, length=length)
        summary = run_measured(sim, measure, out, last, "explore_depth")
        out.update(measurements(summary, last, True))
        out["rejected"] = summary.get("steps_rejected", 0)
    except InputError as err:
        out.update(status="input", message=str(err)[:300])
    except Exception as err:  # what the probe looks for: a crash deep inside
        out.update(message=f"{type(err).__name__}: {str(err)[:250]}")
    out["wall"] = time.perf_counter() - clock
    return out


# -- flags and tables ----------------------------------------------------------------------------


def flags(entry: dict) -> list[str]:
    if entry["status"] != "completed":
        return [entry["status"]]
    out = []
    if entry["created_rel"] > CREATED and entry["created"] > 1e-12:
        out.append("created")
    if max(entry["max_penetration"], np.nan_to_num(entry["depth"])) > PEN_REL * entry["length"]:
        out.append("penetration")
    if entry.get("final_residual", 0.0) > 1.0:
        out.append("residual")
    if entry.get("ref_diff", math.nan) > PK_REL:
        out.append("mirror" if entry.get("mirror") else "p/k")
    if entry.get("warnings"):
        out.append("warning")
    return out


def compared(res: dict, ref: dict, row: Row) -> float:
    """The row's final state against its reference's (mirrored in y for ``mirror``)."""
    if row.mirror:
        res = dict(res)
        sign = np.resize(MIRRORS[row.mirror], len(res["q"]))
        res["q"], res["v"] = list(sign * res["q"]), list(sign * res["v"])
    return state_difference(res, ref, res["length"])


COLUMNS = [
    "config", "row", "status", "flags", "wall", "steps", "rejected", "halvings",
    "least_squares", "fallbacks", "final_residual", "max_penetration", "depth", "created_rel",
    "ref_diff", "warning", "message", "command", "created",
]  # fmt: skip
SHOWN = COLUMNS[: COLUMNS.index("warning")]


def command(row: Row) -> str:
    return f"python benchmarks/explore_beams.py --only '{row.config}/{row.label}'"


def explore(rows: list[Row], timeout: float, csv_path=None) -> list[dict]:
    table, finals = [], {}
    for row in rows:
        res = run_worker(Path(__file__), json.dumps(dataclasses.asdict(row)), timeout)
        finals[(row.config, row.label)] = res
        entry = {
            "config": row.config,
            "row": row.label,
            "command": command(row),
            "mirror": row.mirror,
        }
        entry.update({k: v for k, v in res.items() if k not in ("q", "v")})
        ref = finals.get((row.config, row.ref))
        if row.ref and ref and ref.get("q") is not None and res.get("q") is not None:
            entry["ref_diff"] = compared(res, ref, row)
        entry["flags"] = " ".join(flags(entry))
        table.append(entry)
        if csv_path is not None:
            write_csv(csv_path, table, COLUMNS)
        print(f"{row.config:16s} {row.label:36s} {res['status']:9s} {res.get('wall', 0):6.1f} s "
              f"{entry['flags']}", flush=True)  # fmt: skip
    return table


def flag_line(e: dict) -> str:
    why = e.get("message") or e.get("warning", "")
    return f"- {e['config']} / {e['row']}: `{e['command']}` — {why}"


def main() -> None:
    if len(sys.argv) > 2 and sys.argv[1] == "--worker":
        res = run_row(Row(**json.loads(sys.argv[2])))
        print(
            json.dumps(
                {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in res.items()}
            )
        )
        return
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--only", default="", help="config/label of the rows to run (and references)")
    p.add_argument("--timeout", type=float, default=300.0)
    args = p.parse_args()
    rows = all_rows()
    if args.only:
        keep = [r for r in rows if f"{r.config}/{r.label}".startswith(args.only)]
        refs = {(r.config, r.ref) for r in keep if r.ref}
        rows = [r for r in rows if r in keep or (r.config, r.label) in refs]
    elif args.quick:
        rows = [r for r in rows if r.quick]
    stem = "explore_beams_quick" if args.quick else "explore_beams"
    out = Path(args.out)
    table = explore(rows, args.timeout, out / f"{stem}.csv")
    flagged = [e for e in table if e["flags"]]
    text = (
        f"# Beams beyond the cases\n\n{len(table)} runs, {len(flagged)} flagged. Flags: not "
        f"completed; created > {CREATED:g} of the scale; a centreline point deeper than "
        f"{PEN_REL:g} of the configuration's length; residual above tolerance; p/k or mirror: "
        f"the final state moved by more than {PK_REL:g}; warning: summary.json warns.\n\n"
        + markdown_table(table, SHOWN)
        + "\n\n## Flagged rows\n\n"
        + "\n".join(flag_line(e) for e in flagged)
        + "\n"
    )  # fmt: skip
    write_markdown(out / f"{stem}.md", text)


if __name__ == "__main__":
    main()
