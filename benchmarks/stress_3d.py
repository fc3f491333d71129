"""Body-to-body contact in 3D beyond the cases: a sweep of impacts, each run to its end.

Groups (each row one run, at the step given in its ``step`` column):

- ``balls``: two elastic balls (R = 5 cm unless said, E = 10 MPa, ν = 0.3, ρ = 1000 kg/m³, no
  gravity, graded P1 meshes, the right one turned 30° about the line of centres) meeting at
  0.1-5 m/s each, head-on and off-centre (the right ball's centre moved sideways by b R, b =
  0, 0.3, 0.7), unequal sizes and meshes, e_N = 0, 0.5, 1, and fast approaches (a step that
  closes 1-3 of the contact zone's cells).
- ``slab``: an elastic ball on an elastic slab clamped at its base (``cases/ball_on_slab.py``)
  at speeds and offsets, mortar and node-to-surface; a rigid ball (``RigidBody3D``) on the
  slab, and a rigid box dropped on it corner first and edge first; the elastic ball on a
  fixed ``RigidBody3D`` box: face, 5 mm inside an edge, on an edge, a corner; an elastic box
  sliding with friction over the slab, its mesh aligned with the motion and turned 17°.
- ``rigid``: ``RigidBody3D`` boxes and balls tumbling and bouncing on a plane and on each
  other with Coulomb friction, and free pairs in space.
- ``rod``: a ``Beam3D`` steel rod (``cases/rod_drop.py``) dropped obliquely on an elastic
  block (mortar tube contact) and on a fixed ``RigidBody3D`` box.

Per run: status (and where it stopped), the smallest constraint gap over the run
(``min gap``, m; weighted gaps for mortar), the run's own penetration record
(``max_penetration`` in summary.json) and, independently, the deepest point found inside the
partner by an inside/outside test on the coordinates (``depth``, m: boundary nodes inside the
other solid's discretized surface, nodes inside a rigid shape, rigid shapes' own exact gaps),
over the shortest boundary edge where a mesh is involved; for free pairs (no gravity, nothing
fixed) the largest change of the total linear and angular momentum (about the origin) over
the run, over m v R (mass, approach speed, radius); for symmetric head-on impacts the largest
lateral centre-of-mass speed over the approach speed; the energy ledger's ``created`` over
its ``scale``; the fallbacks summary.json counts (step halvings, penetration retakes,
least-squares multipliers, line-search cuts, rejected steps, localization fallbacks); and, on
a few rows, the largest change of the bodies' centres when the run is repeated with p ×1000
and with k ÷100, over R (the converged answer does not depend on them).

    python benchmarks/stress_3d.py            # the whole sweep (about 20 min on one core)
    python benchmarks/stress_3d.py --quick    # five small rows (under a minute)
    python benchmarks/stress_3d.py --row "box's edge"   # the rows whose label holds the text
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import parser, publish_report, run_or_failure

from fecontact import InputError, Model, Probe
from fecontact.bodies import Beam3D, LinearElastic, Material, RigidBody3D, Section, Solid
from fecontact.bodies.meshes import graded_ball_mesh
from fecontact.bodies.shapes3d import Ball, Box
from fecontact.contact import Contact, Plane
from fecontact.contact.inside import Surface
from fecontact.contact.rigid_distance import FeatureDepths, shape_distance
from fecontact.io.output import read_history
from fecontact.rotations import exp
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
STEEL = Material(210e9, nu=0.3, rho=7850.0)
R = 0.05  # m, the elastic ball's radius


@dataclasses.dataclass
class Spec:
    """One run of the sweep: the simulation, what to measure on it, and its table columns."""

    group: str
    label: str
    sim: Simulation
    length: float  # m: the scale of the momentum and p/k measures (a radius)
    edge: float  # m: the shortest boundary edge (nan: no mesh)
    speed: float  # m/s: the approach speed
    free: bool = False  # no gravity, nothing fixed: momentum is kept
    pk: bool = False  # repeated with p x1000 and k /100
    step: str = ""


# -- what every run measures --------------------------------------------------------------------


def momentum(model, st) -> np.ndarray:
    """Total linear and angular momentum (about the origin) of the model's bodies (6,):
    Σ_a (M v)_a and Σ_a x_a × (M v)_a for a solid (the consistent mass: exact for the
    interpolated motion), m v and c × m v + R J Ω for a rigid body."""
    out = np.zeros(6)
    for i, body in enumerate(model.bodies):
        q, v = st.q[model.body_slice(i)], st.v[model.body_slice(i)]
        if isinstance(body, RigidBody3D):
            M = body.mass_matrix().toarray()
            p = M[:3, :3] @ v[:3]
            out[:3] += p
            out[3:] += np.cross(body.center(q), p) + body.rotation(q) @ (M[3:, 3:] @ v[3:])
        else:
            p = body.nodal(body.mass_matrix() @ v)
            out[:3] += p.sum(axis=0)
            out[3:] += np.cross(body.positions(q), p).sum(axis=0)
    return out


def momentum_probes(model) -> dict:
    return {
        f"{kind}{c}": Probe(
            lambda m, st, k=3 * j + i: float(momentum(m, st)[k]), unit, f"total {kind} momentum"
        )
        for j, (kind, unit) in enumerate((("P", "kg m/s"), ("L", "kg m^2/s")))
        for i, c in enumerate("xyz")
    }


def centre_probes(model, body, name: str) -> dict:
    """The displacement of the centre of mass of ``body`` (m) and its velocity (m/s), as probes
    ``<c><name>``, ``v<c><name>``."""
    s = model.body_slice(model.bodies.index(body))
    if isinstance(body, RigidBody3D):
        pos = [lambda m, st, i=i: float(st.q[s][i]) for i in range(3)]
        vel = [lambda m, st, i=i: float(st.v[s][i]) for i in range(3)]
    else:
        w = [body.mass_matrix() @ body.translation_field(e) / body.mass for e in np.eye(3)]
        pos = [lambda m, st, w=w[i]: float(w @ st.q[s]) for i in range(3)]
        vel = [lambda m, st, w=w[i]: float(w @ st.v[s]) for i in range(3)]
    out = {}
    for i, c in enumerate("xyz"):
        out[f"{c}{name}"] = Probe(pos[i], "m", "centre of mass")
        out[f"v{c}{name}"] = Probe(vel[i], "m/s", "centre of mass velocity")
    return out


def solid_depth(a: Solid, b: Solid, sa: slice, sb: slice):
    """The deepest boundary node of either solid inside the other's discretized boundary, by
    the inside/outside test alone: (m, and over the longest edge of the facet it is under)."""
    facets = [body.contact_facets() for body in (a, b)]
    surfaces = [Surface(f) for f in facets]
    nodes = [np.unique(f) for f in facets]

    def depth(st):
        x = [a.positions(st.q[sa]), b.positions(st.q[sb])]
        deepest, ratio = 0.0, 0.0
        for i in (0, 1):
            s, f = surfaces[1 - i].signed_distance(x[1 - i], x[i][nodes[i]], outside=False)
            inside = np.flatnonzero(s < 0.0)
            if inside.size:
                tri = x[1 - i][facets[1 - i][f[inside]]]  # (k, 3, 3)
                edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
                deepest = max(deepest, float(-s[inside].min()))
                ratio = max(ratio, float(np.max(-s[inside] / edge)))
        return deepest, ratio

    return depth


def rigid_points_depth(rigid: RigidBody3D, sr: slice, points, pad: float = 0.0):
    """The deepest of the points ``points(st)`` (P, 3) inside the rigid shape grown by ``pad``
    (m), from their coordinates in its frame (its exact distance function)."""

    def depth(st):
        q = st.q[sr]
        rho = (points(st) - rigid.center(q)) @ rigid.rotation(q)
        return max(0.0, -float(np.min(shape_distance(rigid.shape, rho, False)[0])) + pad)

    return depth


def with_features(depth, pair):
    """``depth`` and the deepest corner or edge point of a rigid box inside the solid of
    ``pair`` (:class:`fecontact.contact.rigid_distance.FeatureDepths`): the larger (m)."""
    features = FeatureDepths(pair)
    return lambda st: max(depth(st), features.depth(st.q)[0])


def own_gaps_depth(st) -> float:
    """Rigid pairs: the deepest of the pairs' own gaps (exact distances of the shapes)."""
    return max(0.0, -float(np.min(st.gaps, initial=np.inf)))


def lateral_probe(model, bodies) -> Probe:
    """The largest centre-of-mass speed across the x axis of ``bodies`` (m/s)."""
    idx = [model.bodies.index(b) for b in bodies]
    w = [(b.mass_matrix() @ b.translation_field(e) / b.mass) for b in bodies for e in np.eye(3)]

    def lateral(m, st):
        out = 0.0
        for k, i in enumerate(idx):
            v = st.v[m.body_slice(i)]
            out = max(out, float(np.hypot(w[3 * k + 1] @ v, w[3 * k + 2] @ v)))
        return out

    return Probe(lateral, "m/s", "largest lateral centre-of-mass speed")


def depth_probes(depth, local: bool = False) -> dict:
    """``depth`` (m) from ``depth(st)``; with ``local``, ``depth(st)`` gives (depth, ratio) and
    the probe ``local`` holds the ratio (the depth over the longest edge of its facet)."""
    if not local:
        return {"depth": Probe(lambda m, st: depth(st), "m", "deepest point inside the partner")}
    last = {}

    def both(st):  # one evaluation for the two probes of a row
        if last.get("key") != (st.t, st.step):
            last["key"], last["value"] = (st.t, st.step), depth(st)
        return last["value"]

    return {
        "depth": Probe(lambda m, st: both(st)[0], "m", "deepest point inside the partner"),
        "local": Probe(lambda m, st: both(st)[1], "-", "that depth over its facet's longest edge"),
    }


FALLBACKS = (
    ("step_halvings",),
    ("penetration_retakes",),
    ("least_squares_multipliers",),
    ("duplicate_rows",),
    ("smooth_newton", "line_search_cuts"),
    ("velocity_follow_ups", "shortened"),
    ("steps_rejected",),
    ("localization_fallbacks", "accumulation"),
    ("localization_fallbacks", "persistent"),
    ("localization_fallbacks", "grazing"),
    ("localization_fallbacks", "unrefined"),
)


def fallbacks(summary: dict) -> str:
    """The nonzero fallback counts of summary.json, as 'name n' joined by commas."""
    out = []
    for path in FALLBACKS:
        value = summary
        for key in path:
            value = value.get(key, 0) if isinstance(value, dict) else 0
        if value:
            out.append(f"{path[-1]} {value}")
    return ", ".join(out) or "none"


def executed(sim):
    """Run ``sim`` (no frames); its summary, history, status, message and CPU time (s)."""
    with tempfile.TemporaryDirectory(prefix="fecontact_stress3d_") as tmp:
        cpu = time.process_time()
        try:
            summary, status, message = run_or_failure(sim, tmp)
        except InputError as err:  # refused before the first step
            return {}, {}, "refused", str(err), time.process_time() - cpu
        cpu = time.process_time() - cpu
        history = read_history(Path(tmp) / "history.csv")
    return summary, {k: np.asarray(v) for k, v in history.items()}, status, message, cpu


def centres(history) -> np.ndarray:
    """The centre probes of a history (rows, k)."""
    keys = sorted(k for k in history if k[0] in "xyz" and k[1:].isalpha() and len(k) > 1)
    return np.column_stack([history[k] for k in keys])


def measure(spec: Spec) -> dict:
    """Run ``spec`` and return its table row."""
    summary, h, status, message, cpu = executed(spec.sim)
    if status == "refused":
        return {"group": spec.group, "run": spec.label, "step": spec.step, "status": status,
                "fallbacks": "", "message": message.splitlines()[0][:160]}  # fmt: skip
    t = h["t"]
    ledger = summary.get("energy_ledger") or {}
    scale = ledger.get("scale") or np.nan
    row = {
        "group": spec.group,
        "run": spec.label,
        "step": spec.step,
        "status": status if status == "completed" else f"failed at {1e3 * t[-1]:.3g} ms",
        "steps": len(t) - 1,
        "min gap (m)": float(np.min(h["min_gap"])),
        "max_penetration (m)": float(summary.get("max_penetration", np.nan)),
        "depth (m)": float(np.max(h["depth"])),
        "depth / edge": float(np.max(h["depth"])) / spec.edge,
        "depth / local edge": float(np.max(h["local"])) if "local" in h else np.nan,
        "created / scale": ledger.get("created", np.nan) / scale,
        "fallbacks": fallbacks(summary),
        "CPU (s)": cpu,
    }
    if spec.free:
        P = np.column_stack([h[f"P{c}"] for c in "xyz"])
        L = np.column_stack([h[f"L{c}"] for c in "xyz"])
        mass = sum(b.mass for b in spec.sim.model.bodies)
        ref = mass * spec.speed
        row["dP / (m v)"] = float(np.max(np.linalg.norm(P - P[0], axis=1))) / ref
        row["dL / (m v R)"] = float(np.max(np.linalg.norm(L - L[0], axis=1))) / (ref * spec.length)
    if "lateral" in h:
        row["lateral / v"] = float(np.max(h["lateral"])) / spec.speed
    if spec.pk:
        base = centres(h)
        for name, option in (
            ("p x1000", {"penalty_scale": 1e3}),
            ("k /100", {"multiplier_scale": 1e-2}),
        ):
            sim = spec.sim.replace(options=dataclasses.replace(spec.sim.options, **option))
            other = executed(sim)[1]
            n = min(len(base), len(other["t"]))
            row[f"{name}: d centre / R"] = (
                float(np.max(np.abs(centres(other)[:n] - base[:n]))) / spec.length
            )
    if message:
        row["message"] = message.splitlines()[0][:160]
    return row


# -- the scenarios ------------------------------------------------------------------------------


def _unit(x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return x / np.linalg.norm(x)


def _turned_about(mesh, centre, axis, angle: float):
    """The mesh turned by ``angle`` (rad) about ``axis`` through ``centre``."""
    k = _unit(axis)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    rot = np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K
    c = np.asarray(centre, dtype=float)[:, None]
    return dataclasses.replace(mesh, doflocs=c + rot @ (mesh.doflocs - c))


def hertz_time(v: float, radius: float) -> float:
    """t_c (s) of a ball of ``radius`` (m) of the sweep's rubber against its mirror image at
    ``v`` (m/s) each (Hertz: the ball on a rigid plane at v)."""
    E_star = RUBBER.E / (1.0 - RUBBER.nu**2)
    m = RUBBER.rho * 4.0 / 3.0 * np.pi * radius**3
    return 2.87 * (m**2 / (radius * E_star**2 * v)) ** 0.2


def two_balls(v, b=0.0, e=0.0, cells=None, r2=R, spacing=0.16, spacing2=None, base=2):
    """Two elastic balls at ``v`` (m/s) each, the right one (radius ``r2``) moved sideways by
    ``b`` R; ``cells``: the step closes that many contact-zone cells (None: Δx/c)."""
    gap = 0.02 * R  # 1 mm: the coarsest meshes read their weighted gaps below it
    y = b * R
    dx = np.sqrt((R + r2 + gap) ** 2 - y**2)
    cl, cr = np.array([-0.5 * dx, 0.0, 0.0]), np.array([0.5 * dx, y, 0.0])
    n = _unit([np.sqrt((R + r2) ** 2 - y**2), y, 0.0])  # the line of centres at contact
    meshes = []
    for c, rad, sp, sign in ((cl, R, spacing, 1.0), (cr, r2, spacing2 or spacing, -1.0)):
        meshes.append(graded_ball_mesh(c, rad, sp * rad, c + sign * rad * n, 0.5, base))
    meshes[1] = _turned_about(meshes[1], cr, n, np.radians(30.0))
    left, right = (Solid(m, RUBBER) for m in meshes)
    model = Model([left, right], [Contact(left, right, restitution=e)], gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(left, (v, 0.0, 0.0)) + model.translation(right, (-v, 0.0, 0.0))
    sl, sr = model.body_slice(0), model.body_slice(1)
    probes = (
        momentum_probes(model) | centre_probes(model, left, "l") | centre_probes(model, right, "r")
    )
    probes |= depth_probes(solid_depth(left, right, sl, sr), local=True)
    if b == 0.0:
        probes["lateral"] = lateral_probe(model, (left, right))
    edge = min(left.min_edge_length, right.min_edge_length)
    wave = wave_step(left, 1.0, edge)
    dt = wave if cells is None else cells * spacing * R / (2.0 * v)
    t_end = gap / (2.0 * v) + 1.4 * hertz_time(v, min(R, r2))
    sim = Simulation(model, dt=dt, t_end=t_end, probes=probes, v0=v0, name="two_balls",
                     output_interval=t_end)  # fmt: skip
    parts = [f"{v:g} m/s", f"b {b:g}", f"e_N {e:g}"]
    if r2 != R:
        parts.append(f"right R {100 * r2:g} cm, spacing {spacing2 or spacing:g}")
    step = "dx/c" if cells is None else f"{dt / wave:.3g} dx/c ({cells:g} cells)"
    return Spec("balls", ", ".join(parts), sim, R, edge, v, free=True, step=step)


def _slab(width, thick, divisions, layers):
    half = 0.5 * width
    slab = Solid.box([-half, -half, -thick], [half, half, 0.0], (divisions, divisions, layers),
                     RUBBER)  # fmt: skip
    slab.fix(slab.nodes_where(lambda x: x[2] <= -thick * (1.0 - 1e-9)))
    return slab


def ball_on_slab(v, offset=(0.0, 0.0), method="mortar", refinements=2, divisions=10):
    """The elastic ball of ``cases/ball_on_slab.py`` landing at ``v`` (m/s), its pole over
    ``offset`` (m) on the slab."""
    slab = _slab(0.2, 0.04, divisions, 2)
    z0 = R + 0.001
    ball = Solid.ball([offset[0], offset[1], z0], R, refinements, RUBBER)
    pairs = [Contact(ball, slab, method=method)]
    if method == "node-to-surface":
        top = slab.nodes_where(lambda x: x[2] >= -1e-9)
        pairs.append(Contact(slab, ball, nodes=top, method=method))
    model = Model([ball, slab], pairs, (0.0, 0.0, -9.81))
    probes = centre_probes(model, ball, "b")
    probes |= depth_probes(
        solid_depth(ball, slab, model.body_slice(0), model.body_slice(1)), local=True
    )
    t_end = 0.001 / v + 1.5 * hertz_time(v, R)
    v0 = model.translation(ball, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="ball_on_slab", output_interval=t_end)  # fmt: skip
    edge = min(ball.min_edge_length, slab.min_edge_length)
    label = (
        f"elastic ball {v:g} m/s, pole over ({100 * offset[0]:g}, {100 * offset[1]:g}) cm, {method}"
    )
    return Spec("slab", label, sim, R, edge, v, step="dx/c")


def rigid_ball_on_slab(v, offset=(0.003, -0.002), method="mortar", divisions=8):
    """A rigid ball (R, 1000 kg/m³) at ``v`` (m/s) onto a 0.1 m slab (``divisions`` cells)."""
    slab = _slab(0.1, 0.04, divisions, 3)
    ball = RigidBody3D.of_density(1000.0, [offset[0], offset[1], R + 0.001], Ball(R))
    model = Model([slab, ball], [Contact(slab, ball, method=method)], (0.0, 0.0, -9.81))
    ss, sb = model.body_slice(0), model.body_slice(1)
    top = np.unique(slab.contact_facets())
    probes = centre_probes(model, ball, "b")
    depth = rigid_points_depth(ball, sb, lambda st: slab.positions(st.q[ss])[top])
    probes |= depth_probes(depth)
    t_end = 0.001 / v + 12e-3 * v**-0.2
    v0 = model.translation(ball, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(slab, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="rigid_ball_on_slab", output_interval=t_end)  # fmt: skip
    label = f"rigid ball {v:g} m/s on a {divisions}x{divisions} slab, {method}"
    return Spec("slab", label, sim, R, slab.min_edge_length, v, pk=True, step="dx/c")


def box_on_slab(v=1.0, tilt=(0.4, 0.3, 0.0), friction=0.0, divisions=8, method="mortar",
                first="corner"):  # fmt: skip
    """A rigid box 4 × 3 × 2 cm (1000 kg/m³) dropped at ``v`` (m/s) ``first`` ("corner" or
    "edge") first, turned by the rotation vector ``tilt`` (rad), onto the 0.1 m slab, with
    Coulomb ``friction``."""
    slab = _slab(0.1, 0.04, divisions, 3)
    half = 0.5 * np.array([0.04, 0.03, 0.02])
    box = RigidBody3D.of_density(1000.0, [0.003, -0.002, 0.0], Box(*(2 * half)))
    model = Model([slab, box], [Contact(slab, box, method=method, friction=friction)],
                  (0.0, 0.0, -9.81))  # fmt: skip
    ss, sb = model.body_slice(0), model.body_slice(1)
    q0 = np.zeros(model.n)
    rot = exp(np.asarray(tilt, dtype=float))
    corners = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]) * half
    q0[sb][:3] = [0.0, 0.0, 0.001 - np.min(corners @ rot.T, axis=0)[2]]
    q0[sb][3:6] = tilt
    top = np.unique(slab.contact_facets())
    surface = Surface(slab.contact_facets())
    s = np.linspace(0.0, 1.0, 9)[:, None, None]
    edges = [
        (a, b) for a in range(8) for b in range(a + 1, 8) if np.sum(corners[a] != corners[b]) == 1
    ]
    ends = np.array(edges)
    in_box = rigid_points_depth(box, sb, lambda st: slab.positions(st.q[ss])[top])

    def depth(st):  # slab nodes in the box, and the box's edges (9 points each) in the slab
        q = st.q[sb]
        x = corners @ exp(q[3:6]).T + box.center(q)
        pts = ((1 - s) * x[ends[:, 0]] + s * x[ends[:, 1]]).reshape(-1, 3)
        inside = -float(np.min(surface.signed_distance(slab.positions(st.q[ss]), pts)[0]))
        return max(in_box(st), inside, 0.0)

    probes = centre_probes(model, box, "b") | depth_probes(depth)
    t_end = 0.001 / v + 0.02
    v0 = model.translation(box, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(slab, 1.0), t_end=t_end, probes=probes, q0=q0,
                     v0=v0, name="box_on_slab", output_interval=t_end)  # fmt: skip
    label = f"rigid box {v:g} m/s {first} first on a {divisions}x{divisions} slab, mu {friction:g}"
    label += f", {method}"
    pk = method == "mortar" and friction == 0.0
    return Spec("slab", label, sim, 0.02, slab.min_edge_length, v, pk=pk, step="dx/c")


def box_slide(angle: float, v=1.0, friction=0.3, t_end=0.05):
    """An elastic box 4 × 4 × 2 cm (2 cells a side) sliding at ``v`` (m/s) along x with
    Coulomb ``friction`` over an elastic slab 0.3 × 0.3 × 0.02 m (8 × 8 × 1 cells, clamped
    at its base) whose mesh is turned by ``angle`` (deg) about z, the box 0.3 mm above it."""
    slab = Solid.box([-0.15, -0.15, -0.02], [0.15, 0.15, 0.0], (8, 8, 1), RUBBER)
    base = slab.nodes_where(lambda x: x[2] <= -0.02 + 1e-9)
    a = np.radians(angle)
    turn = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0, 0, 1.0]])
    slab = Solid(dataclasses.replace(slab.mesh, doflocs=turn @ slab.mesh.doflocs), RUBBER)
    slab.fix(base)
    box = Solid.box([-0.06, -0.02, 0.0003], [-0.02, 0.02, 0.0203], 2, RUBBER)
    model = Model([box, slab], [Contact(box, slab, friction=friction)], (0.0, 0.0, -9.81))
    probes = centre_probes(model, box, "b")
    probes |= depth_probes(
        solid_depth(box, slab, model.body_slice(0), model.body_slice(1)), local=True
    )
    v0 = model.translation(box, (v, 0.0, 0.0))
    dt = min(wave_step(box, 1.0), wave_step(slab, 1.0))
    sim = Simulation(model, dt=dt, t_end=t_end, probes=probes, v0=v0, name="box_slide",
                     output_interval=t_end)  # fmt: skip
    edge = min(box.min_edge_length, slab.min_edge_length)
    label = f"elastic box sliding {v:g} m/s over a slab whose mesh is turned {angle:g} deg"
    label += f", mu {friction:g}"
    return Spec("slab", label, sim, 0.02, edge, v, step="dx/c")


BALL_ON_BOX = {"refinements": 2}  # the ball's mesh in the ball-on-box rows (--refinements)


def ball_and_box(where: str, refinements: int, **contact):
    """The elastic ball 1 mm over a fixed rigid box 0.3 × 0.3 × 0.05 m, its pole over the
    face's middle, 5 mm inside an edge, on an edge ("on edge") or over a corner; ``contact``:
    the options of ``Contact``. Returns (ball, model, probes of its centre and depth)."""
    ball = Solid.ball([0.0, 0.0, R + 0.001], R, refinements, RUBBER)
    x0, y0 = {"face": (0.0, 0.0), "edge": (0.145, 0.0), "on edge": (0.15, 0.0),
              "corner": (0.15, 0.15)}[where]  # fmt: skip
    box = RigidBody3D.uniform(1000 * ball.mass, [x0, y0, -0.025], Box(0.3, 0.3, 0.05)).fix()
    model = Model([ball, box], [Contact(ball, box, **contact)], (0.0, 0.0, -9.81))
    sb, sx = model.body_slice(0), model.body_slice(1)
    nodes = ball.boundary_nodes()
    probes = centre_probes(model, ball, "b")
    nodes_in = rigid_points_depth(box, sx, lambda st: ball.positions(st.q[sb])[nodes])
    probes |= depth_probes(with_features(nodes_in, model.contacts.pairs[0]))
    return ball, model, probes


def ball_on_box(v, where="face", method="mortar", refinements=None):
    """The elastic ball at ``v`` (m/s) onto a fixed rigid box 0.3 × 0.3 × 0.05 m: its pole
    over the face's middle, 5 mm inside an edge, on an edge ("on edge") or over a corner."""
    refinements = refinements or BALL_ON_BOX["refinements"]
    ball, model, probes = ball_and_box(where, refinements, method=method)
    t_end = 0.001 / v + 1.5 * hertz_time(v, R)
    v0 = model.translation(ball, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="ball_on_box", output_interval=t_end)  # fmt: skip
    label = f"elastic ball {v:g} m/s on a rigid box's {where}, {method}"
    label += "" if refinements == 2 else f", refinements {refinements}"
    pk = where in ("edge", "on edge")
    return Spec("slab", label, sim, R, ball.min_edge_length, v, pk=pk, step="dx/c")


def ball_on_free_rigid(kind: str, b: float, v: float = 1.0, refinements: int = 2):
    """The elastic ball thrown at ``v`` (m/s) at a free rigid ``kind`` ("box" 0.2 × 0.15 ×
    0.1 m or "ball" of 4 cm, as heavy as the elastic ball) in space, its centre moved sideways
    by ``b`` R: a free pair, whose momentum no external force changes."""
    shape = Box(0.2, 0.15, 0.1) if kind == "box" else Ball(0.04)
    reach = 0.05 if kind == "box" else 0.04  # the rigid surface's distance from its centre
    ball = Solid.ball([-(R + reach + 0.001), b * R, 0.0], R, refinements, RUBBER)
    target = RigidBody3D.uniform(ball.mass, [0.0, 0.0, 0.0], shape)
    if kind == "box":  # the face x = -0.05 toward the ball: the box turned about z
        target = RigidBody3D.uniform(ball.mass, [0.0, 0.0, 0.0], Box(0.1, 0.15, 0.2))
    model = Model([ball, target], [Contact(ball, target)], gravity=(0.0, 0.0, 0.0))
    sb, st_ = model.body_slice(0), model.body_slice(1)
    nodes = ball.boundary_nodes()
    probes = momentum_probes(model) | centre_probes(model, ball, "b")
    probes |= centre_probes(model, target, "t")
    probes |= depth_probes(
        with_features(
            rigid_points_depth(target, st_, lambda st: ball.positions(st.q[sb])[nodes]),
            model.contacts.pairs[0],
        )
    )
    t_end = 0.001 / v + 1.5 * hertz_time(v, R)
    v0 = model.translation(ball, (v, 0.0, 0.0))
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="ball_on_free_rigid", output_interval=t_end)  # fmt: skip
    label = f"elastic ball {v:g} m/s at a free rigid {kind} in space, b {b:g}"
    return Spec("slab", label, sim, R, ball.min_edge_length, v, free=True, step="dx/c")


def tumbling_box(velocity, spin, friction=0.5, t_end=2.0):
    """``cases/tumbling_box.py`` (a 1 kg box 0.2 × 0.15 × 0.1 m thrown spinning onto a rough
    plane) at ``velocity`` (m/s) and ``spin`` (rad/s)."""
    from _common import case

    sim = case("tumbling_box").build(velocity=velocity, spin=spin, friction=friction,
                                     t_end=t_end)  # fmt: skip
    box = sim.model.bodies[0]
    s = sim.model.body_slice(0)

    def depth(st):
        return max(0.0, -float(box.point_positions(st.q[s], np.arange(8))[:, 2].min()))

    probes = dict(sim.probes) | centre_probes(sim.model, box, "b")
    probes |= depth_probes(depth)
    sim = sim.replace(probes=probes, output_interval=t_end)
    label = f"tumbling box {velocity:g} m/s, spin {spin:g} rad/s, mu {friction:g}"
    return Spec("rigid", label, sim, 0.1, np.nan, max(abs(velocity), 1.0), pk=True, step="1 ms")


def box_on_box(friction=0.3, t_end=1.0):
    """A spinning box dropped on a box lying on a plane, friction everywhere, gravity."""
    lower = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.05], Box(0.3, 0.3, 0.1))
    upper = RigidBody3D.uniform(1.0, [0.02, -0.01, 0.2], Box(0.2, 0.15, 0.1))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=1.0)
    pairs = [Contact(lower, floor, friction=friction, restitution=0.2),
             Contact(upper, floor, friction=friction, restitution=0.2),
             Contact(lower, upper, friction=friction, restitution=0.2)]  # fmt: skip
    model = Model([lower, upper], pairs, gravity=(0.0, 0.0, -9.81))
    q0 = np.zeros(12)
    q0[9:] = [0.3, -0.2, 0.1]  # tilted: a corner lands first
    v0 = np.zeros(12)
    v0[6:] = [0.5, 0.0, -1.0, 3.0, -2.0, 5.0]
    probes = centre_probes(model, upper, "u") | centre_probes(model, lower, "l")
    probes |= depth_probes(own_gaps_depth)
    sim = Simulation(model, dt=1e-3, t_end=t_end, probes=probes, q0=q0, v0=v0, name="box_on_box",
                     output_interval=t_end)  # fmt: skip
    label = f"spinning box dropped on a box on a plane, mu {friction:g}"
    return Spec("rigid", label, sim, 0.1, np.nan, 1.0, pk=True, step="1 ms")


def free_pair(kind: str, b: float, friction: float, v: float = 2.0):
    """Two rigid bodies in space (no gravity): a ball thrown at a spinning ``kind`` ("box" or
    "ball") with impact parameter ``b`` (of the sum of the sizes), ``friction``."""
    shape = Box(0.2, 0.15, 0.1) if kind == "box" else Ball(0.06)
    size = 0.075 if kind == "box" else 0.06
    target = RigidBody3D.uniform(1.5, [0.0, 0.0, 0.0], shape)
    ball = RigidBody3D.uniform(1.0, [-0.3, b * (0.05 + size), 0.01], Ball(0.05))
    model = Model([target, ball], [Contact(target, ball, friction=friction, restitution=0.5)],
                  gravity=(0.0, 0.0, 0.0))  # fmt: skip
    v0 = np.zeros(12)
    v0[3:6] = [0.0, 0.0, 10.0]  # the target spins about a principal axis: L kept in flight
    v0[6:9] = [v, 0.0, 0.0]
    probes = (
        momentum_probes(model) | centre_probes(model, ball, "b") | centre_probes(model, target, "t")
    )
    probes |= depth_probes(own_gaps_depth)
    t_end = 0.3 / v
    sim = Simulation(model, dt=2e-4, t_end=t_end, probes=probes, v0=v0, name="free_pair",
                     output_interval=t_end)  # fmt: skip
    label = f"rigid ball {v:g} m/s at a spinning {kind} in space, b {b:g}, mu {friction:g}"
    return Spec("rigid", label, sim, 0.05, np.nan, v, free=True, pk=kind == "box", step="0.2 ms")


def rod(on: str, v=1.0, angle=30.0, t_end=0.04, divisions=20, width=0.2):
    """The steel rod of ``cases/rod_drop.py`` (0.5 m, r = 5 mm, 10 elements), inclined by
    ``angle`` (deg), dropped at ``v`` (m/s) on an elastic block (``on`` "block") or a fixed
    rigid box ("box") whose top face is z = 0 (the block ``width`` wide, ``divisions`` cells
    along a side, its middle under the rod's lower end); its lower end 2 mm above."""
    radius, length = 0.005, 0.5
    a, az = np.radians(angle), np.radians(45.0)
    axis = np.array([np.cos(a) * np.cos(az), np.cos(a) * np.sin(az), np.sin(a)])
    low = np.array([0.0, 0.0, radius + 0.002])
    beam = Beam3D.straight(low, low + length * axis, 10, STEEL, Section.circle(radius))
    if on == "block":
        block = _slab(width, 0.04, divisions, 2)
        model = Model([block, beam], [Contact(block, beam, clearance=radius)], (0.0, 0.0, -9.81))
        sb, sr = model.body_slice(0), model.body_slice(1)
        surface = np.unique(block.contact_facets())
        solid = Surface(block.contact_facets())
        segments = beam.segments()

        def depth(st):  # block nodes inside the tube, rod nodes' tube inside the block
            from fecontact.contact.polyline_distance import closest_on_polyline

            xb, xr = block.positions(st.q[sb]), beam.positions(st.q[sr])
            d = closest_on_polyline(xb[surface], xr[segments])[2]
            s = solid.signed_distance(xb, xr)[0]
            return max(0.0, radius - float(d.min()), radius - float(s.min()))

        edge = block.min_edge_length
    else:
        box = RigidBody3D.uniform(100.0, [0.0, 0.0, -0.05], Box(0.6, 0.6, 0.1)).fix()
        model = Model([box, beam], [Contact(beam, box, clearance=radius)], (0.0, 0.0, -9.81))
        sx, sr = model.body_slice(0), model.body_slice(1)
        ends = beam.segments()
        s = np.linspace(0.0, 1.0, 9)[:, None, None]

        def points(st):  # 9 points along every segment of the centreline
            x = beam.positions(st.q[sr])[ends]
            return ((1 - s) * x[:, 0] + s * x[:, 1]).reshape(-1, 3)

        depth = rigid_points_depth(box, sx, points, pad=radius)
        edge = np.nan
    v0 = model.translation(beam, (0.0, 0.0, -v))
    probes = depth_probes(depth)
    sim = Simulation(model, dt=1e-4, t_end=t_end, probes=probes, v0=v0, name="rod",
                     output_interval=t_end)  # fmt: skip
    target = "an elastic block" if on == "block" else "a rigid box"
    label = f"rod {v:g} m/s at {angle:g} deg on {target}"
    if on == "block":
        label += f" ({width:g} m, {divisions} cells a side)"
    return Spec("rod", label, sim, radius, edge, v, step="0.1 ms")


EDGE_DOWN = (0.0, np.pi / 4, 0.0)  # rad: the box's edge along y lowest, level
EDGE_SKEW = (
    -0.117791,
    0.779376,
    0.284373,
)  # rad: the same turned 0.3 rad about z (skew to the grid)

QUICK = [
    lambda: two_balls(1.0, base=1, spacing=0.3),
    lambda: rigid_ball_on_slab(1.0, divisions=4),
    lambda: free_pair("ball", 0.5, 0.3),
    lambda: tumbling_box(1.0, 8.0, t_end=0.4),
    lambda: box_on_slab(1.0, divisions=4),
]

FULL = [
    *(lambda v=v: two_balls(v) for v in (0.1, 1.0, 5.0)),
    *(lambda b=b: two_balls(1.0, b=b) for b in (0.3, 0.7)),
    *(lambda e=e: two_balls(1.0, b=0.3, e=e) for e in (0.5, 1.0)),
    lambda: two_balls(1.0, r2=0.03, spacing2=0.25),
    lambda: two_balls(1.0, b=0.3, r2=0.03, spacing2=0.25, e=0.5),
    *(lambda k=k: two_balls(5.0, cells=k) for k in (1, 3)),
    lambda: two_balls(5.0, b=0.7, cells=2),
    lambda: ball_on_slab(1.0),
    lambda: ball_on_slab(3.0, (0.013, 0.007)),
    lambda: ball_on_slab(1.0, (0.075, 0.0)),
    lambda: ball_on_slab(1.0, method="node-to-surface"),
    lambda: rigid_ball_on_slab(1.0),
    lambda: rigid_ball_on_slab(3.0, (0.01, 0.01)),
    lambda: box_on_slab(1.0),
    lambda: box_on_slab(1.0, friction=0.3),
    lambda: box_on_slab(1.0, method="node-to-surface"),
    *(
        lambda t=t, m=m: box_on_slab(1.0, tilt=t, method=m, first="edge")
        for t, m in ((EDGE_DOWN, "mortar"), (EDGE_SKEW, "mortar"), (EDGE_SKEW, "node-to-surface"))
    ),
    lambda: box_on_slab(1.0, tilt=EDGE_DOWN, friction=0.3, first="edge"),
    *(lambda a=a: box_slide(a) for a in (0.0, 17.0)),
    lambda: ball_on_box(1.0, "face"),
    lambda: ball_on_box(1.0, "edge"),
    lambda: ball_on_box(1.0, "corner"),
    lambda: ball_on_box(3.0, "corner"),
    lambda: ball_on_box(3.0, "edge"),
    lambda: ball_on_box(1.0, "on edge"),
    lambda: ball_on_box(3.0, "on edge"),
    lambda: tumbling_box(1.0, 8.0),
    lambda: tumbling_box(3.0, 30.0),
    lambda: box_on_box(),
    lambda: free_pair("box", 0.3, 0.3),
    lambda: free_pair("ball", 0.7, 0.5),
    lambda: ball_on_free_rigid("box", 0.0),
    lambda: ball_on_free_rigid("box", 0.5),
    lambda: ball_on_free_rigid("ball", 0.5),
    lambda: rod("block"),
    *(lambda k=k: rod("block", divisions=k, width=0.6) for k in (4, 8, 12)),
    lambda: rod("box"),
    lambda: rod("box", v=3.0, angle=10.0),
]

COLUMNS = ("group", "run", "step", "status", "min gap (m)", "max_penetration (m)", "depth / edge",
           "depth / local edge",
           "created / scale", "dP / (m v)", "dL / (m v R)", "lateral / v", "fallbacks")  # fmt: skip


def measured_rows(builds, label: str) -> list[dict]:
    """The rows of ``builds`` whose label contains ``label``, each measured (:func:`measure`)
    and printed as it ends."""
    rows = []
    for build in builds:
        spec = build()
        if label in spec.label:
            rows.append(measure(spec))
            print(rows[-1], flush=True)
    return rows


def report_tables(rows: list[dict], columns) -> tuple[list, list, list]:
    """Every column of ``rows``, their ``columns``, and the runs that stopped with a message."""
    keys = list(dict.fromkeys(k for r in rows for k in r))
    table = [{k: r.get(k, "") for k in keys} for r in rows]
    summary = [{k: r.get(k, "") for k in columns} for r in rows]
    failed = [{"run": r["run"], "status": r["status"], "message": r.get("message", "")}
              for r in rows if r.get("message")]  # fmt: skip
    return table, summary, failed


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--row", default="", help="run only the rows whose label contains this text")
    p.add_argument("--refinements", type=int, default=2,
                   help="the elastic ball's mesh refinements in the ball-on-box rows")  # fmt: skip
    args = p.parse_args()
    BALL_ON_BOX["refinements"] = args.refinements
    rows = measured_rows(QUICK if args.quick else FULL, args.row)
    table, summary, failed = report_tables(rows, COLUMNS)
    keys = list(table[0]) if table else []
    pk = [{k: r[k] for k in ("group", "run") + tuple(k for k in keys if ": d centre" in k)}
          for r in rows if any(": d centre" in k for k in r)]  # fmt: skip
    sections = [("Every run: status, gaps, depth, energy, momentum, fallbacks", summary)]
    if pk:
        sections.append(("p x1000 and k /100: the largest change of the centres over R", pk))
    if failed:
        sections.append(("Runs that stopped, and why", failed))
    publish_report(args.out, "stress_3d", args.quick, "3D body-to-body contact beyond the cases",
                   table, *sections)  # fmt: skip


if __name__ == "__main__":
    main()
