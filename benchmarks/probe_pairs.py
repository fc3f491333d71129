"""Body-to-body contact on configurations no case or sweep names, each run through its impacts.

Rows (each a run at the step given in its ``step`` column; coarse meshes, short runs):

- ``3D``: two elastic balls meeting obliquely (impact parameter b = 0.5 R), frictionless and
  with μ = 0.3; unequal balls (radius 1:2, density 4:1) head-on, e_N = 0 and 1; an elastic
  cube dropped on its edge and on its corner onto an elastic slab; an elastic ball thrown
  into the inner corner of a rigid box (three planes); a rigid box landing flat on a free
  elastic cube in space.
- ``2D``: a spinning elastic disk thrown into a free elastic block with friction; Newton's
  cradle of three elastic disks and of three rigid disks (e_N = 1, small gaps); a spinning
  rigid disk and a spinning rigid pentagon thrown into a free elastic block
  (``fecontact.contact.solid_rigid2d``).

The bodies that turn (the balls, the disk and block) are Neo-Hookean; the cube and slab are
stress_3d's linear rubber.

Per run, the measures of ``benchmarks/stress_3d.py`` (status, min gap, the penetration
record, an independent depth from the coordinates, the ledger's ``created`` over its
``scale``, the fallbacks summary.json counts), the change of the total linear and angular
momentum of free pairs over m v and m v R, the lateral centre-of-mass speed of head-on pairs
over v, on some rows the change of the centres with p ×1000 and k ÷100 over R, and where an
exact rigid-body answer exists (the rigid cradle: the last disk leaves at v, the others stop)
the centre-of-mass velocities at the end against it.

    python benchmarks/probe_pairs.py            # every row (about 5 min on one core)
    python benchmarks/probe_pairs.py --quick    # the rigid cradle (a second)
    python benchmarks/probe_pairs.py --row cradle
"""

from __future__ import annotations

import dataclasses

import numpy as np
from _common import parser, publish_report
from stress_3d import (
    RUBBER,
    Spec,
    _turned_about,
    _unit,
    centre_probes,
    depth_probes,
    executed,
    hertz_time,
    lateral_probe,
    measure,
    momentum_probes,
    rigid_points_depth,
    solid_depth,
    with_features,
)

from fecontact import Model, Probe
from fecontact.bodies import RigidBody2D, RigidBody3D, Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.bodies.meshes import graded_ball_mesh
from fecontact.bodies.rigid import Disk, Polygon
from fecontact.bodies.shapes3d import Box
from fecontact.contact import Contact, Plane
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation

R = 0.05  # m: the reference radius
# the rubber of stress_3d, Neo-Hookean where bodies turn: a linear material is not invariant
# under rotation, and a spinning or off-centre pair then loses angular momentum to it
# (docs/validation/stress_3d.md: 9.6e-3 of m v R against 7.7e-6 with a nonlinear material)
SOFT = NeoHookean(RUBBER.E, RUBBER.nu, RUBBER.rho)


# -- 3D -----------------------------------------------------------------------------------------


def oblique_balls(b=0.5, mu=0.0, e=0.0, v=1.0, r2=R, rho2=1000.0, spacing=0.3, pk=False):
    """Two elastic balls at ``v`` (m/s) each, the right one (radius ``r2``, density ``rho2``)
    moved sideways by ``b`` R, Coulomb ``mu``, Newton's ``e``; the right mesh turned 30°."""
    gap = 0.02 * R
    y = b * R
    dx = np.sqrt((R + r2 + gap) ** 2 - y**2)
    cl, cr = np.array([-0.5 * dx, 0.0, 0.0]), np.array([0.5 * dx, y, 0.0])
    n = _unit([np.sqrt((R + r2) ** 2 - y**2), y, 0.0])
    ml = graded_ball_mesh(cl, R, spacing * R, cl + R * n, 0.5, 1)
    mr = graded_ball_mesh(cr, r2, spacing * r2, cr - r2 * n, 0.5, 1)
    mr = _turned_about(mr, cr, n, np.radians(30.0))
    left = Solid(ml, SOFT)
    right = Solid(mr, NeoHookean(SOFT.E, SOFT.nu, rho2))
    pair = Contact(left, right, restitution=e, friction=mu)
    model = Model([left, right], [pair], gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(left, (v, 0.0, 0.0)) + model.translation(right, (-v, 0.0, 0.0))
    probes = momentum_probes(model) | centre_probes(model, left, "l")
    probes |= centre_probes(model, right, "r")
    probes |= depth_probes(solid_depth(left, right, model.body_slice(0), model.body_slice(1)), True)
    if b == 0.0:
        probes["lateral"] = lateral_probe(model, (left, right))
    edge = min(left.min_edge_length, right.min_edge_length)
    dt = wave_step(left, 1.0, edge)
    t_end = gap / (2.0 * v) + 1.6 * hertz_time(v, min(R, r2))
    sim = Simulation(model, dt=dt, t_end=t_end, probes=probes, v0=v0, name="oblique_balls",
                     output_interval=t_end)  # fmt: skip
    label = f"elastic balls {v:g} m/s each, b {b:g}, mu {mu:g}, e_N {e:g}"
    if r2 != R or rho2 != 1000.0:
        label += f", right R {100 * r2:g} cm, rho {rho2:g}"
    return Spec("3D", label, sim, R, edge, v, free=True, pk=pk, step="dx/c")


def cube_on_slab(first="edge", v=1.0, friction=0.0):
    """An elastic cube (4 cm, 4 cells a side) dropped at ``v`` (m/s) ``first`` ("edge" or
    "corner") first onto an elastic slab clamped at its base, 1 mm above it."""
    from stress_3d import _slab

    slab = _slab(0.12, 0.03, 6, 2)
    a = 0.04
    mesh = Solid.box([-a / 2] * 3, [a / 2] * 3, 4, RUBBER).mesh
    if first == "edge":  # an edge along y lowest
        axis, angle = (1.0, 0.0, 0.0), np.pi / 4
    else:  # a body diagonal vertical: a corner lowest
        axis, angle = (1.0, -1.0, 0.0), np.arctan(np.sqrt(2.0))
    mesh = _turned_about(mesh, np.zeros(3), axis, angle)
    if first == "edge":  # the lowest edge turned 0.3 rad about z: skew to the slab's grid
        mesh = _turned_about(mesh, np.zeros(3), (0.0, 0.0, 1.0), 0.3)
    lift = 0.001 - mesh.doflocs[2].min()
    mesh = dataclasses.replace(mesh, doflocs=mesh.doflocs + np.array([[0.003], [-0.002], [lift]]))
    cube = Solid(mesh, RUBBER)
    model = Model([cube, slab], [Contact(cube, slab, friction=friction)], (0.0, 0.0, -9.81))
    probes = centre_probes(model, cube, "c")
    probes |= depth_probes(solid_depth(cube, slab, model.body_slice(0), model.body_slice(1)), True)
    edge = min(cube.min_edge_length, slab.min_edge_length)
    t_end = 0.001 / v + 0.012
    v0 = model.translation(cube, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(cube, 1.0, edge), t_end=t_end, probes=probes, v0=v0,
                     name="cube_on_slab", output_interval=t_end)  # fmt: skip
    label = f"elastic cube {v:g} m/s {first} first on an elastic slab, mu {friction:g}"
    return Spec("3D", label, sim, a, edge, v, pk=first == "corner", step="dx/c")


def ball_into_corner(v=1.0, e=0.5, mu=0.0):
    """The elastic ball thrown along (-1, -1, -1)/√3 at ``v`` (m/s) into the inner corner of
    a rigid box (the planes x = 0, y = 0, z = 0), 1 mm from each."""
    ball = Solid.ball([R + 0.001] * 3, R, 1, RUBBER)
    planes = [Plane(np.zeros(3), n, extent=1.0) for n in np.eye(3)]
    pairs = [Contact(ball, p, restitution=e, friction=mu) for p in planes]
    model = Model([ball], pairs, gravity=(0.0, 0.0, 0.0))
    s = model.body_slice(0)
    depth = lambda st: max(0.0, -float(ball.positions(st.q[s]).min()))  # noqa: E731
    probes = centre_probes(model, ball, "b") | depth_probes(depth)
    t_end = 0.002 / v + 1.6 * hertz_time(v, R)
    v0 = model.translation(ball, -v * np.ones(3) / np.sqrt(3.0))
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="ball_into_corner", output_interval=t_end)  # fmt: skip
    label = f"elastic ball {v:g} m/s into a rigid box's inner corner, e_N {e:g}, mu {mu:g}"
    return Spec("3D", label, sim, R, ball.min_edge_length, v, step="dx/c")


def box_on_free_cube(v=1.0, friction=0.0):
    """A rigid box 3 × 3 × 1 cm (as heavy as the cube) landing flat at ``v`` (m/s) on the top
    face of a free elastic cube (4 cm, 4 cells a side) in space: a free pair."""
    a = 0.04
    cube = Solid.box([-a / 2] * 3, [a / 2] * 3, 4, RUBBER)
    box = RigidBody3D.uniform(cube.mass, [0.002, -0.001, a / 2 + 0.005 + 0.001],
                              Box(0.03, 0.03, 0.01))  # fmt: skip
    model = Model([cube, box], [Contact(cube, box, friction=friction)], (0.0, 0.0, 0.0))
    sc, sb = model.body_slice(0), model.body_slice(1)
    probes = momentum_probes(model) | centre_probes(model, cube, "c")
    probes |= centre_probes(model, box, "b")
    top = np.unique(cube.contact_facets())
    nodes_in = rigid_points_depth(box, sb, lambda st: cube.positions(st.q[sc])[top])
    probes |= depth_probes(with_features(nodes_in, model.contacts.pairs[0]))
    t_end = 0.001 / v + 0.01
    v0 = model.translation(box, (0.0, 0.0, -v))
    sim = Simulation(model, dt=wave_step(cube, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="box_on_free_cube", output_interval=t_end)  # fmt: skip
    label = f"rigid box {v:g} m/s flat on a free elastic cube, mu {friction:g}"
    return Spec("3D", label, sim, a, cube.min_edge_length, v, free=True, step="dx/c")


# -- 2D -----------------------------------------------------------------------------------------


def momentum_2d(model, st) -> np.ndarray:
    """Total linear momentum (x, y) and angular momentum about the origin (z) of a planar
    model: Σ (M v) and Σ x × (M v) over nodes, m v and c × m v + J ω for a rigid body."""
    out = np.zeros(3)
    for i, body in enumerate(model.bodies):
        q, v = st.q[model.body_slice(i)], st.v[model.body_slice(i)]
        Mv = body.mass_matrix() @ v
        if isinstance(body, RigidBody2D):
            x, p = body.center(q), Mv[:2]
            out += [p[0], p[1], x[0] * p[1] - x[1] * p[0] + Mv[2]]
        else:
            x, p = body.positions(q), body.nodal(Mv)
            out += [*p.sum(axis=0), float(np.sum(x[:, 0] * p[:, 1] - x[:, 1] * p[:, 0]))]
    return out


def probes_2d(model) -> dict:
    """Momentum probes named as the 3D ones (P z, L x, L y are 0) and each body's centre."""
    out = {}
    for j, name in enumerate(("Px", "Py", "Lz")):
        out[name] = Probe(lambda m, st, j=j: float(momentum_2d(m, st)[j]), "SI", "momentum")
    for name in ("Pz", "Lx", "Ly"):
        out[name] = Probe(lambda m, st: 0.0, "SI", "momentum (planar: 0)")
    M = model.M_full
    for i, body in enumerate(model.bodies):
        for k, c in enumerate("xy"):
            w = M @ model.translation(body, np.eye(2)[k])
            mass = float(w @ model.translation(body, np.eye(2)[k]))
            name = f"{c}b{'abcdef'[i]}"  # (letters: stress_3d's centres() reads x.., y..)
            out[name] = Probe(lambda m, st, w=w, s=mass: float(w @ st.q) / s, "m", "centre")
            out["v" + name] = Probe(lambda m, st, w=w, s=mass: float(w @ st.v) / s, "m/s",
                                    "centre velocity")  # fmt: skip
    return out


def polygon_depth_2d(model, pairs):
    """The deepest boundary node of ``a`` inside solid ``b``'s boundary polygon, or inside
    rigid disk ``b``, over ``pairs`` (a, b) (m), from the coordinates alone."""
    from stress_2d import boundary_points, polygon_depths

    slices = {id(x): model.body_slice(i) for i, x in enumerate(model.bodies)}

    def depth(st):
        out = 0.0
        for a, b in pairs:
            qa, qb = st.q[slices[id(a)]], st.q[slices[id(b)]]
            if isinstance(b, RigidBody2D):
                pts = boundary_points(a, qa)
                d = b.shape.radius - np.linalg.norm(pts - b.center(qb), axis=1)
                out = max(out, float(d.max()))
            elif isinstance(a, RigidBody2D):
                xb = b.positions(qb)[b.boundary_nodes()]
                d = a.shape.radius - np.linalg.norm(xb - a.center(qa), axis=1)
                out = max(out, float(d.max()))
            else:
                xb, f = b.positions(qb), b.boundary_facets()
                d, _ = polygon_depths(boundary_points(a, qa), xb[f[:, 0]], xb[f[:, 1]])
                out = max(out, float(d.max()))
        return max(out, 0.0)

    return depth


def disk_into_block(spin=40.0, mu=0.3, v=1.0, e=0.0):
    """A spinning elastic disk (R, ``spin`` rad/s) thrown at ``v`` (m/s) into a free elastic
    block 6 × 10 cm in the plane, Coulomb ``mu``: a free pair, its momentum and angular
    momentum kept."""
    disk = Solid.disk([-R - 0.001, 0.01], R, 2, SOFT)
    block = Solid.rectangle([0.0, -0.05], [0.06, 0.05], (6, 10), SOFT)
    model = Model([disk, block], [Contact(disk, block, friction=mu, restitution=e)], (0.0, 0.0))
    x = disk.X - [-R - 0.001, 0.01]
    w = np.column_stack([v - spin * x[:, 1], spin * x[:, 0]]).ravel()
    v0 = np.zeros(model.n)
    v0[model.body_slice(0)] = w  # the rigid motion's velocity at the nodes, (x, y) per node
    probes = probes_2d(model)
    probes |= depth_probes(polygon_depth_2d(model, [(disk, block), (block, disk)]))
    edge = min(disk.min_edge_length, block.min_edge_length)
    t_end = 0.001 / v + 0.012
    sim = Simulation(model, dt=wave_step(disk, 1.0, edge), t_end=t_end, probes=probes, v0=v0,
                     name="disk_into_block", output_interval=t_end)  # fmt: skip
    label = f"spinning elastic disk {v:g} m/s, {spin:g} rad/s, into a free block, mu {mu:g}"
    return Spec("2D", label, sim, R, edge, v, free=True, pk=True, step="dx/c")


def rigid_into_block(shape=None, spin=40.0, v=1.0, e=0.0):
    """A spinning rigid disk (R) or ``shape`` (1 kg, ``spin`` rad/s) thrown at ``v`` (m/s)
    into the free elastic block of :func:`disk_into_block`, frictionless (the block's boundary
    nodes against the body, a polygon's vertices against the block's boundary): a free pair,
    its momentum and angular momentum kept. The depth: the block's nodes inside the body and
    a polygon's vertices inside the block, from the coordinates."""
    shape = Disk(R) if shape is None else shape
    body = RigidBody2D.uniform(1.0, [-R - 0.001, 0.01], shape)
    block = Solid.rectangle([0.0, -0.05], [0.06, 0.05], (6, 10), SOFT)
    pair = Contact(body, block, restitution=e)
    model = Model([body, block], [pair], (0.0, 0.0))
    v0 = np.zeros(model.n)
    v0[model.body_slice(0)] = [v, 0.0, spin]
    if isinstance(shape, Disk):
        depth = polygon_depth_2d(model, [(block, body)])
    else:  # the pair's exact node distances and its watch of the vertices
        watch = pair.watch()
        depth = lambda st: max(0.0, -float(pair.gaps(st.q).min()), watch.depth(st.q)[0])  # noqa: E731
    probes = probes_2d(model) | depth_probes(depth)
    edge = block.min_edge_length
    t_end = 0.001 / v + 0.012
    sim = Simulation(model, dt=wave_step(block, 1.0, edge), t_end=t_end, probes=probes, v0=v0,
                     name="rigid_into_block", output_interval=t_end)  # fmt: skip
    what = "disk" if isinstance(shape, Disk) else f"{len(shape.vertices)}-gon"
    label = f"spinning rigid {what} {v:g} m/s, {spin:g} rad/s, into a free elastic block"
    return Spec("2D", label, sim, R, edge, v, free=True, pk=True, step="dx/c")


def cradle(rigid=False, e=1.0, v=1.0, gap=0.001):
    """Newton's cradle in the plane: three disks (R) in a row ``gap`` (m) apart, the left one
    thrown at the others at ``v`` (m/s); elastic (rubber) or rigid (``rigid``, 1 kg)."""
    xs = [-(2 * R + gap), 0.0, 2 * R + gap]
    if rigid:
        disks = [RigidBody2D.uniform(1.0, [x, 0.0], Disk(R)) for x in xs]
    else:
        disks = [Solid.disk([x, 0.0], R, 2, SOFT) for x in xs]
    pairs = [Contact(disks[i], disks[i + 1], restitution=e) for i in range(2)]
    model = Model(disks, pairs, gravity=(0.0, 0.0))
    v0 = model.translation(disks[0], (v, 0.0))
    probes = probes_2d(model)
    if rigid:  # the pairs' own exact gaps
        probes |= depth_probes(lambda st: max(0.0, -float(np.min(st.gaps, initial=np.inf))))
    else:
        pairs = [(disks[0], disks[1]), (disks[1], disks[2])]
        probes |= depth_probes(polygon_depth_2d(model, pairs))
    if rigid:
        dt, edge, t_end = 1e-4, np.nan, 0.01
    else:
        edge = disks[0].min_edge_length
        dt, t_end = wave_step(disks[0], 1.0), gap / v + 0.012
    sim = Simulation(model, dt=dt, t_end=t_end, probes=probes, v0=v0, name="cradle",
                     output_interval=t_end)  # fmt: skip
    label = f"Newton's cradle, three {'rigid' if rigid else 'elastic'} disks, e_N {e:g}"
    step = "0.1 ms" if rigid else "dx/c"
    return Spec("2D", label, sim, R, edge, v, free=True, pk=rigid, step=step)


# -- outcomes against rigid-body impact laws -----------------------------------------------------


def _final(h, key: str) -> float:
    return float(h[key][-1])


def cradle_outcome(h, v=1.0) -> str:
    """The disks' final speeds over v; Newton's law on each pair in turn (e_N = 1, equal
    masses): (0, 0, 1), the error the largest difference from it over v."""
    final = np.array([_final(h, f"vxb{c}") for c in "abc"]) / v
    err = float(np.max(np.abs(final - [0.0, 0.0, 1.0])))
    return f"v/v0 = ({final[0]:.4g}, {final[1]:.4g}, {final[2]:.4g}); from (0, 0, 1): {err:.2g}"


def pair_outcome(h, m1: float, m2: float, v=1.0) -> str:
    """The centres' final velocities along x against Newton's law on two rigid balls (each
    at v toward the other): the effective e = (v2' − v1')/(2 v)."""
    v1, v2 = _final(h, "vxl"), _final(h, "vxr")
    e = (v2 - v1) / (2.0 * v)
    rigid = 1.0 - 2.0 * (1.0 + 1.0) * m2 / (m1 + m2), -1.0 + 2.0 * (1.0 + 1.0) * m1 / (m1 + m2)
    return (f"v' = ({v1:.4g}, {v2:.4g}) m/s, rigid e = 1: ({rigid[0]:.4g}, {rigid[1]:.4g});"
            f" effective e {e:.4g}")  # fmt: skip


def corner_outcome(h, v=1.0) -> str:
    """The ball's final centre velocity against the incoming diagonal d = −(1, 1, 1)/√3: its
    speed back along −d over v (a rigid ball: e_N), and across d over v (0 by symmetry of a
    rigid ball; the mesh's own asymmetry here)."""
    u = np.array([_final(h, f"v{c}b") for c in "xyz"]) / v
    d = -np.ones(3) / np.sqrt(3.0)
    back = -float(u @ d)
    return f"back along the diagonal {back:.4g} v, across {np.linalg.norm(u + back * d):.2g} v"


QUICK = [(lambda: cradle(rigid=True), cradle_outcome)]

FULL = [
    (lambda: oblique_balls(0.5, 0.0), None),
    (lambda: oblique_balls(0.5, 0.3, pk=True), None),
    *((lambda e=e: oblique_balls(0.0, 0.0, e=e, r2=2 * R, rho2=250.0), "pair") for e in (0.0, 1.0)),
    (lambda: cube_on_slab("edge"), None),
    (lambda: cube_on_slab("corner"), None),
    (lambda: cube_on_slab("edge", friction=0.3), None),
    (lambda: ball_into_corner(), corner_outcome),
    (lambda: box_on_free_cube(), None),
    (lambda: disk_into_block(), None),
    (lambda: rigid_into_block(), None),
    (lambda: rigid_into_block(Polygon.regular(5, R)), None),
    (lambda: cradle(), cradle_outcome),
    (lambda: cradle(rigid=True), cradle_outcome),
]


def outcome(spec: Spec, check) -> str:
    """``check`` of the run's history (the run taken again: the rows checked are small)."""
    if check is None:
        return ""
    h = executed(spec.sim)[1]
    if check == "pair":
        m1, m2 = (b.mass for b in spec.sim.model.bodies)
        return pair_outcome(h, m1, m2)
    return check(h)


COLUMNS = ("group", "run", "step", "status", "min gap (m)", "max_penetration (m)", "depth / edge",
           "created / scale", "dP / (m v)", "dL / (m v R)", "lateral / v", "fallbacks",
           "outcome")  # fmt: skip


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--row", default="", help="run only the rows whose label contains this text")
    args = p.parse_args()
    rows = []
    for build, check in QUICK if args.quick else FULL:
        spec = build()
        if args.row not in spec.label:
            continue
        rows.append(measure(spec) | {"outcome": outcome(spec, check)})
        print(rows[-1], flush=True)
    keys = list(dict.fromkeys(k for r in rows for k in r))
    table = [{k: r.get(k, "") for k in keys} for r in rows]
    summary = [{k: r.get(k, "") for k in COLUMNS} for r in rows]
    publish_report(args.out, "probe_pairs", args.quick, "Body-to-body contact off the cases",
                   table, ("Every run", summary))  # fmt: skip


if __name__ == "__main__":
    main()
