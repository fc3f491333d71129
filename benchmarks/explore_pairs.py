"""Every contact pair kind that no other sweep runs, on a few configurations, with a depth
measured from the positions alone.

The sweeps (``stress_2d``, ``stress_3d``, ``explore_3d``, ``explore_beams``, ``probe_pairs``,
``case_matrix``) leave these pair kinds and argument orders unrun; here each gets 2-4 rows
(head-on, oblique or off-centre, a fast approach ×10, μ 0.3 where the pair takes it, e_N 0
and 1):

- 2D: a free strip on a ``Point`` (``PointSegmentContact``); a rigid disk on a pinned strip
  named ``Contact(strip, disk)``; a rigid disk and pentagon in a circular cavity and on a
  ``Circle`` (``DiskObstacleContact``, vertices as nodes); a rigid disk against a free rigid
  square (``DiskPolygonContact``); an elastic block named first against a rigid disk or
  pentagon; an elastic disk in a circular cavity and on a peg (``Circle``, its nodes).
- P2 cells: two elastic disks P2/P2 and P2/P1 (mortar), P2/P2 node-to-surface; explore_3d's
  balls on P2 cells, mortar and node-to-surface.
- 3D: a rod on a ``Sphere`` and inside a spherical cavity; a rod on a fixed rigid ball and
  box and a free capsule named ``Contact(rigid, rod)``; a rod on an elastic block named
  ``Contact(rod, block)`` (mortar), node-to-surface with ``SolidEdges`` across the block's
  edge; rigid balls
  and capsules on a ``Plane`` (``BallsPlaneContact``); a rigid ball named first against a free
  box (``BallBoxContact``: the other order is ``ConvexContact``); a rigid box named first
  against an elastic ball (mortar) and a rigid ball against an elastic block
  (node-to-surface).

Per row, stress_3d's measures (:func:`stress_3d.measure`: status, min gap, max_penetration,
the ``depth`` probe, created/scale, the fallbacks summary.json counts, momentum of free pairs,
p ×1000 and k ÷100 on the centres) and, where both orders are allowed, the largest change of
the bodies' centres when the pair is named the other way round (``order: d centre / L``).
The depth here is the deepest point of one body inside the other from exact geometry: a
strip's or tube's centreline sampled at 9 points a segment against the exact disk, sphere,
point, plane or rigid shape (less the clearance), solid boundary nodes inside a rigid shape,
a rigid disk's or ball's centre against a solid's boundary polygon or facets.

    python benchmarks/explore_pairs.py            # every row (about 4 min on one core)
    python benchmarks/explore_pairs.py --quick    # three cheap rows
    python benchmarks/explore_pairs.py --row cavity
"""

from __future__ import annotations

import numpy as np
from _common import parser, publish_report
from probe_pairs import SOFT, probes_2d
from stress_2d import boundary_points, depth_probe, polygon_depths, polyline_distance
from stress_2d import strip as pinned_strip
from stress_3d import (
    STEEL,
    Spec,
    centres,
    depth_probes,
    executed,
    hertz_time,
    measured_rows,
    momentum_probes,
    report_tables,
    rigid_points_depth,
    with_features,
)

from fecontact import Model, Probe
from fecontact.bodies import Beam3D, RigidBody2D, RigidBody3D, Section, Solid
from fecontact.bodies.rigid import Disk, Polygon
from fecontact.bodies.shapes3d import Ball, Box, Capsule
from fecontact.contact import Circle, Contact, Plane, Point, SolidEdges, Sphere
from fecontact.contact.inside import Surface
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation

R = 0.05  # m: disks and balls
TUBE = 0.005  # m: the rod's radius (cases/rod_drop.py), the strips' half thickness


# -- generic pieces -----------------------------------------------------------------------------


def centre_probes(model) -> dict:
    """Each body's centre of mass and its velocity, named ``<c>b<letter>`` (stress_3d's
    ``centres`` reads them), in 2D or 3D."""
    M, out = model.M_full, {}
    for i, body in enumerate(model.bodies):
        for k, c in enumerate("xyz"[: model.dim]):
            t = model.translation(body, np.eye(model.dim)[k])
            w, mass = M @ t, float(t @ (M @ t))
            name = f"{c}b{'abcdef'[i]}"
            out[name] = Probe(lambda m, st, w=w, s=mass: float(w @ st.q) / s, "m", "centre")
            out["v" + name] = Probe(lambda m, st, w=w, s=mass: float(w @ st.v) / s, "m/s", "")
    return out


def spec(label, model, depth, dt, t_end, v0, length, speed, edge=np.nan, free=False, pk=False,
         group="2D"):  # fmt: skip
    """A row: ``model`` run from ``v0`` with the centre probes, momentum if ``free``, and
    ``depth(st)`` (m)."""
    probes = centre_probes(model) | depth_probes(depth)
    if free:
        probes = (probes_2d(model) if model.dim == 2 else momentum_probes(model)) | probes
    sim = Simulation(model, dt=dt, t_end=t_end, probes=probes, v0=v0, name="explore_pairs",
                     output_interval=t_end)  # fmt: skip
    step = f"{1e3 * dt:.3g} ms"
    return Spec(group, label, sim, length, edge, speed, free=free, pk=pk, step=step)


def along(x: np.ndarray, n: int = 9) -> np.ndarray:
    """``n`` points along every segment of the polyline through the rows of x."""
    s = np.linspace(0.0, 1.0, n)[None, :, None]
    return ((1 - s) * x[:-1, None] + s * x[1:, None]).reshape(-1, x.shape[1])


def edge_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance (m) of points p (P, 2) to the nearest of the segments a → b (E, 2)."""
    d, w = b - a, p[:, None] - a[None]
    t = np.clip(np.einsum("pei,ei->pe", w, d) / np.sum(d * d, axis=1), 0.0, 1.0)
    return np.linalg.norm(w - t[..., None] * d[None], axis=2).min(axis=1)


def convex_distance(p: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """Signed distance (m) of points p (P, 2) to the convex polygon through ``verts``
    (counter-clockwise), negative inside."""
    nxt = np.roll(verts, -1, axis=0)
    dist = edge_distance(p, verts, nxt)
    inside = np.all(np.cross(nxt - verts, p[:, None] - verts[None]) >= 0.0, axis=1)
    return np.where(inside, -dist, dist)


def sphere_depth(points: np.ndarray, centre, radius: float, inside: bool, reach: float):
    """Deepest of ``points`` (grown by ``reach``) across the circle or sphere's surface (m)."""
    r = np.linalg.norm(points - np.asarray(centre), axis=1)
    d = r + reach - radius if inside else radius + reach - r
    return max(0.0, float(d.max()))


def reversed_order(spec_: Spec, twin: Spec) -> float:
    """The largest change of the centres over the run when the pair is named the other way
    round (``twin``), over the row's length."""
    a, b = executed(spec_.sim)[1], executed(twin.sim)[1]
    n = min(len(a["t"]), len(b["t"]))
    return float(np.max(np.abs(centres(a)[:n] - centres(b)[:n]))) / spec_.length


# -- 2D -----------------------------------------------------------------------------------------


def free_strip_on_point(x=0.5, v=1.0, vx=0.0, mu=0.0, e=0.0):
    """A free steel strip (1 m, 1 cm thick, 20 elements) thrown down at ``v`` onto a fixed
    ``Point`` under its abscissa ``x`` (m), moving along at ``vx``."""
    beam = pinned_strip(supports="", start=(0.0, TUBE + 0.002))
    point = Point([x, 0.0])
    model = Model([beam], [Contact(beam, point, clearance=TUBE, friction=mu, restitution=e)],
                  gravity=(0.0, 0.0))  # fmt: skip

    def depth(st):
        xb = beam.positions(st.q[model.body_slice(0)])
        return max(0.0, TUBE - float(polyline_distance(point.position[None], xb)[0]))

    v0 = model.translation(beam, (vx, -v))
    label = f"Beam2D/Point: free strip {v:g} m/s onto a point under x = {x:g} m"
    label += f", along {vx:g} m/s, mu {mu:g}, e_N {e:g}"
    return spec(label, model, depth, 5e-5, 0.002 / v + 0.01, v0, TUBE, v, pk=x == 0.5)


def strip_disk(x=0.5, v=3.0, vx=0.0, mu=0.0, e=0.0, strip_first=True):
    """A rigid disk (R, 0.5 kg) thrown down at ``v`` onto a pinned strip at abscissa ``x``;
    the pair named (strip, disk), or (disk, strip) as stress_2d names it."""
    beam = pinned_strip()
    disk = RigidBody2D.uniform(0.5, [x, TUBE + 0.002 + R], Disk(R))
    pair = (beam, disk) if strip_first else (disk, beam)
    pair = Contact(*pair, clearance=TUBE, friction=mu, restitution=e)
    model = Model([beam, disk], [pair], gravity=(0.0, 0.0))

    def depth(st):
        xb = beam.positions(st.q[model.body_slice(0)])
        c = disk.center(st.q[model.body_slice(1)])
        return max(0.0, R + TUBE - float(polyline_distance(c[None], xb)[0]))

    v0 = model.translation(disk, (vx, -v))
    order = "Beam2D/RigidBody2D" if strip_first else "RigidBody2D/Beam2D"
    label = f"{order}: rigid disk {v:g} m/s onto a pinned strip at x = {x:g} m, along {vx:g}"
    label += f" m/s, mu {mu:g}, e_N {e:g}"
    return spec(label, model, depth, 2e-5, 0.002 / v + 0.01, v0, R, v, pk=x == 0.5)


def rigid_circle(shape="disk", inside=True, v=2.0, offset=0.0, spin=0.0, mu=0.0, e=0.0):
    """A rigid disk or pentagon (R, 1 kg) thrown at ``v`` along x inside a circular cavity
    (radius 4 R) from its centre, or at a fixed circle (radius R) from outside, ``offset``
    (m) across; gravity off."""
    body_shape = Disk(R) if shape == "disk" else Polygon.regular(5, R)
    start = [0.0, offset] if inside else [-2.0 * R - 0.002, offset]
    body = RigidBody2D.uniform(1.0, start, body_shape)
    circle = Circle([0.0, 0.0], 4 * R if inside else R, inside=inside)
    model = Model([body], [Contact(body, circle, friction=mu, restitution=e)], (0.0, 0.0))

    def depth(st):
        q = st.q[model.body_slice(0)]
        if shape == "disk":
            return sphere_depth(body.center(q)[None], circle.center, circle.radius, inside, R)
        return sphere_depth(body.positions(q), circle.center, circle.radius, inside, 0.0)

    v0 = body.velocity(v, 0.0, spin)
    where = "in a cavity of radius 4 R" if inside else "at a circle of radius R"
    label = f"RigidBody2D/Circle: rigid {shape} {v:g} m/s {where}, offset {offset:g} m, "
    label += f"spin {spin:g}, mu {mu:g}, e_N {e:g}"
    t_end = (5 * R if inside else 0.004) / v + 0.02
    return spec(label, model, depth, 1e-4, t_end, v0, R, v, pk=True)


def disk_polygon(v=2.0, offset=0.03, spin=20.0, mu=0.3, e=1.0, disk_first=True):
    """A rigid disk (R, 1 kg) thrown at ``v`` with ``spin`` at a free rigid square (half
    diagonal 1.4 R, 1.5 kg) ``offset`` (m) across: a free pair."""
    disk = RigidBody2D.uniform(1.0, [-2.0 * R - 0.002, offset], Disk(R))
    square = RigidBody2D.uniform(1.5, [0.0, 0.0], Polygon.regular(4, 1.4 * R), angle=np.pi / 4)
    pair = (disk, square) if disk_first else (square, disk)
    model = Model([disk, square], [Contact(*pair, friction=mu, restitution=e)], (0.0, 0.0))

    def depth(st):
        c = disk.center(st.q[model.body_slice(0)])
        verts = square.positions(st.q[model.body_slice(1)])
        return max(0.0, R - float(convex_distance(c[None], verts)[0]))

    v0 = np.concatenate([disk.velocity(v, 0.0, spin), np.zeros(3)])
    order = "RigidBody2D disk/polygon" if disk_first else "RigidBody2D polygon/disk"
    label = f"{order}: disk {v:g} m/s, spin {spin:g}, at a free square, offset {offset:g} m, "
    label += f"mu {mu:g}, e_N {e:g}"
    return spec(label, model, depth, 1e-4, 0.004 / v + 0.02, v0, R, v, free=True, pk=True)


def block_rigid(shape="disk", v=1.0, spin=40.0, mu=0.3, e=0.0, block_first=True):
    """probe_pairs' spinning rigid disk or pentagon (1 kg) thrown into a free elastic block
    6 × 10 cm, the pair named (block, body) or (body, block)."""
    body = RigidBody2D.uniform(1.0, [-R - 0.001, 0.01], Disk(R) if shape == "disk"
                               else Polygon.regular(5, R))  # fmt: skip
    block = Solid.rectangle([0.0, -0.05], [0.06, 0.05], (6, 10), SOFT)
    pair = (block, body) if block_first else (body, block)
    model = Model([body, block], [Contact(*pair, friction=mu, restitution=e)], (0.0, 0.0))
    facets = block.boundary_facets()

    def depth(st):
        qb, xs = st.q[model.body_slice(0)], block.positions(st.q[model.body_slice(1)])
        nodes = boundary_points(block, st.q[model.body_slice(1)])
        if shape == "disk":
            inside = R - np.linalg.norm(nodes - body.center(qb), axis=1)
            return max(0.0, float(inside.max()))
        verts = body.positions(qb)
        into = -convex_distance(nodes, verts)  # block nodes inside the pentagon
        vin = polygon_depths(verts, xs[facets[:, 0]], xs[facets[:, 1]])[0]  # vertices in block
        return max(0.0, float(into.max()), float(vin.max()))

    v0 = np.zeros(model.n)
    v0[model.body_slice(0)] = [v, 0.0, spin]
    order = "Solid/RigidBody2D" if block_first else "RigidBody2D/Solid"
    label = f"{order}: spinning rigid {shape} {v:g} m/s, {spin:g} rad/s, into a free block, "
    label += f"mu {mu:g}, e_N {e:g}"
    edge = block.min_edge_length
    return spec(label, model, depth, wave_step(block, 1.0, edge), 0.001 / v + 0.012, v0, R, v,
                edge=edge, free=True, pk=True)  # fmt: skip


def solid_circle(inside=True, v=1.0, mu=0.0, e=0.0, under=False):
    """An elastic disk (R) thrown at ``v`` along x in a circular cavity (radius 2.4 R) from
    its centre (its nodes against the circle), or at a fixed peg (radius R/5, half a
    boundary edge off the line of the disk's pole node, or on it: ``under``) from outside
    (its boundary segments); the depth also counts the peg entering between two nodes."""
    disk = Solid.disk([0.0 if inside else -1.2 * R - 0.001, 0.0], R, 2, SOFT)
    peg = [0.0, 0.0 if inside or under else 0.5 * disk.min_edge_length]
    circle = Circle(peg, 2.4 * R if inside else 0.2 * R, inside=inside)
    model = Model([disk], [Contact(disk, circle, friction=mu, restitution=e)], (0.0, 0.0))
    facets = disk.boundary_facets()

    def depth(st):
        x = disk.positions(st.q)
        d = sphere_depth(x[disk.boundary_nodes()], circle.center, circle.radius, inside, 0.0)
        if inside:
            return d
        c = np.asarray(circle.center, dtype=float)[None]
        a, b = x[facets[:, 0]], x[facets[:, 1]]
        sign = -1.0 if polygon_depths(c, a, b)[0][0] > 0.0 else 1.0  # the peg's centre inside
        gap = sign * float(edge_distance(c, a, b)[0])
        return max(d, circle.radius - float(gap))

    v0 = model.translation(disk, (v, 0.0))
    where = "in a cavity of radius 2.4 R" if inside else "at a peg of radius R/5"
    where += " under a node" if under else ""
    label = f"Solid/Circle: elastic disk {v:g} m/s {where}, mu {mu:g}, e_N {e:g}"
    edge = disk.min_edge_length
    t_end = (1.4 * R if inside else 0.001) / v + 0.012
    return spec(label, model, depth, wave_step(disk, 1.0), t_end, v0, R, v, edge=edge, pk=True)


def p2_disks(method="mortar", mixed=False, offset=0.3, mu=0.3, e=0.0, v=1.0):
    """Two elastic disks (R, 2 refinements) at ``v`` each, 2 mm apart, the right one
    ``offset`` R up: P2 cells on the left, P1 (``mixed``) or P2 on the right; the depth of
    either's boundary nodes inside the other's boundary, a P2 boundary's curved segments cut
    into chords (stress_2d's measure)."""
    gap = 0.002
    left = Solid.disk([-R - 0.5 * gap, 0.0], R, 2, SOFT, element="P2")
    right = Solid.disk([R + 0.5 * gap, offset * R], R, 2, SOFT, element="P1" if mixed else "P2")
    opts = dict(method=method, friction=mu, restitution=e)
    pairs = [Contact(left, right, **opts)]
    if method == "node-to-surface":
        pairs.append(Contact(right, left, **opts))
    model = Model([left, right], pairs, (0.0, 0.0))
    watch = depth_probe(model, [("solid", left, right, None), ("solid", right, left, None)])
    v0 = model.translation(left, (v, 0.0)) + model.translation(right, (-v, 0.0))
    dt = min(wave_step(d, 1.0) for d in (left, right)) / 2.0  # (P2: half the P1 step)
    label = f"Solid P2/{'P1' if mixed else 'P2'} 2D, {method}: disks {v:g} m/s each, "
    label += f"offset {offset:g} R, mu {mu:g}, e_N {e:g}"
    edge = min(left.min_edge_length, right.min_edge_length)
    out = spec(label, model, lambda st: 0.0, dt, gap / (2 * v) + 0.1 * R, v0, R, v, edge=edge,
               free=True, pk=True)  # fmt: skip
    probes = dict(out.sim.probes) | {"depth": watch["depth"]}
    out.sim = out.sim.replace(probes=probes)
    return out


def p2_balls(method="mortar", b=0.3, mu=0.3):
    """explore_3d's two elastic balls on P2 cells (uniform meshes, base 1), ``b`` R off
    centre: the 3D P2 pairs (mortar on the faces' flat triangles, or node-to-surface)."""
    from explore_3d import balls

    out = balls(b=b, mu=mu, spacing=(None, None), base=1, element="P2", method=method)
    out.group, out.label = "3D", f"Solid P2/P2 3D, {method}: " + out.label
    return out


# -- 3D -----------------------------------------------------------------------------------------


def rod(centre, n=10, length=0.5) -> Beam3D:
    """The steel rod of cases/rod_drop.py (0.5 m, r = 5 mm, 10 elements) lying along x,
    centred on ``centre``."""
    c = np.asarray(centre, dtype=float)
    half = np.array([0.5 * length, 0.0, 0.0])
    return Beam3D.straight(c - half, c + half, n, STEEL, Section.circle(TUBE))


def rod_points(model, beam):
    """The rod's centreline, 9 points a segment, at a state (P, 3)."""
    s = model.body_slice(model.bodies.index(beam))
    return lambda st: along(beam.positions(st.q[s]))


def rod_sphere(inside=False, x=0.0, v=1.0, vx=0.0, mu=0.0, e=0.0):
    """The rod thrown down at ``v`` (along at ``vx``) onto a fixed sphere (radius R) under its
    abscissa ``x`` (m from the middle), or across at ``v`` inside a spherical cavity (radius
    0.27 m, the rod 1 cm off its centre: its ends meet the wall)."""
    beam = rod([-x, 0.0, R + TUBE + 0.002] if not inside else [0.0, 0.0, 0.01])
    sphere = Sphere([0.0, 0.0, 0.0], 0.27 if inside else R, inside=inside)
    pair = Contact(beam, sphere, clearance=TUBE, friction=mu, restitution=e)
    model = Model([beam], [pair], gravity=(0.0, 0.0, 0.0))
    pts = rod_points(model, beam)

    def depth(st):
        return sphere_depth(pts(st), sphere.center, sphere.radius, inside, TUBE)

    v0 = model.translation(beam, (vx, 0.0, -v) if not inside else (0.0, v, 0.0))
    where = "inside a spherical cavity" if inside else f"onto a sphere under x = {x:g} m"
    label = f"Beam3D/Sphere: rod {v:g} m/s {where}, along {vx:g} m/s, mu {mu:g}, e_N {e:g}"
    t_end = (0.09 if inside else 0.002) / v + 0.01
    return spec(label, model, depth, 1e-4, t_end, v0, TUBE, v, pk=True, group="3D")


def rigid_rod(shape="ball", v=1.0, vx=0.0, mu=0.0, e=0.0, rigid_first=True):
    """The rod thrown down at ``v`` (along at ``vx``) onto a fixed rigid ball (radius R), a
    free capsule of 1e4 kg (R, 0.2 m, across the rod) or a fixed box (0.2 × 0.2 × 0.1 m), 5 cm
    off the rod's middle; the pair named (rigid, rod) or (rod, rigid)."""
    kind = {"ball": Ball(R), "capsule": Capsule(R, 0.2), "box": Box(0.2, 0.2, 0.1)}[shape]
    top = 0.05 if shape == "box" else R
    rigid = RigidBody3D.uniform(10.0, [0.0, 0.0, 0.0], kind)
    if shape != "capsule":  # (a fixed body starts unturned: the capsule 1e4 kg, free)
        rigid = rigid.fix()
    else:
        rigid = RigidBody3D.uniform(1e4, [0.0, 0.0, 0.0], kind)
    beam = rod([0.05, 0.0, top + TUBE + 0.002])
    pair = (rigid, beam) if rigid_first else (beam, rigid)
    model = Model([rigid, beam], [Contact(*pair, clearance=TUBE, friction=mu, restitution=e)],
                  gravity=(0.0, 0.0, 0.0))  # fmt: skip
    q0 = np.zeros(model.n)
    if shape == "capsule":  # its axis turned from z to y, across the rod
        q0[model.body_slice(0).start + 3] = 0.5 * np.pi
    sr, pts = model.body_slice(0), rod_points(model, beam)
    if shape == "capsule":  # its axis' segment, less its radius and the tube's
        centres_, radius = kind.balls

        def depth(st):
            axis = centres_ @ rigid.rotation(st.q[sr]).T + rigid.center(st.q[sr])
            return max(0.0, radius + TUBE - float(polyline_distance(pts(st), axis).min()))
    else:
        depth = rigid_points_depth(rigid, sr, pts, pad=TUBE)
    v0 = model.translation(beam, (vx, 0.0, -v))
    order = "RigidBody3D/Beam3D" if rigid_first else "Beam3D/RigidBody3D"
    held = "free" if shape == "capsule" else "fixed"
    label = f"{order}: rod {v:g} m/s onto a {held} rigid {shape}, along {vx:g} m/s, mu {mu:g}"
    label += f", e_N {e:g}"
    out = spec(label, model, depth, 1e-4, 0.002 / v + 0.01, v0, TUBE, v, pk=True, group="3D")
    out.sim = out.sim.replace(q0=q0)
    return out


def block(width=0.2, thick=0.04, divisions=4):
    """An elastic block (stress_3d's rubber) clamped at its base, top face z = 0."""
    from explore_3d import _slab

    return _slab(width, thick, divisions, 2)


def rod_block(v=1.0, across_edge=False, method=None, rod_first=True, mu=0.0, length=0.3,
              edges=True):  # fmt: skip
    """A rod (``length`` m, 6 elements) thrown down at ``v`` onto an elastic block (0.2 m,
    4 cells a side), level over its middle (0.3 m: 5 cm beyond both edges), or across its
    edge x = 0.1 m, going down 10° beyond it (the nodes against the faces and the segments
    against the convex edges, ``SolidEdges``, unless not ``edges``)."""
    slab, a = block(), np.radians(10.0)
    if across_edge:  # down 10° beyond the edge x = 0.1 m, which meets it between two nodes
        start = [-0.025, 0.0, (TUBE + 0.002) / np.cos(a) + 0.125 * np.tan(a)]
        end = np.asarray(start) + 0.3 * np.array([np.cos(a), 0.0, -np.sin(a)])
    else:
        start, end = [-0.5 * length, 0.0, TUBE + 0.002], [0.5 * length, 0.0, TUBE + 0.002]
    beam = Beam3D.straight(start, end, 6, STEEL, Section.circle(TUBE))
    pair = (beam, slab) if rod_first else (slab, beam)
    pairs = [Contact(*pair, clearance=TUBE, method=method, friction=mu)]
    if across_edge and edges:
        pairs.append(Contact(beam, SolidEdges(slab), clearance=TUBE))
    model = Model([slab, beam], pairs, gravity=(0.0, 0.0, 0.0))
    ss = model.body_slice(0)
    surface, nodes = Surface(slab.contact_facets()), np.unique(slab.contact_facets())
    sb = model.body_slice(1)

    def depth(st):  # block nodes inside the tube, the tube's centreline inside the block
        xs, xb = slab.positions(st.q[ss]), beam.positions(st.q[sb])
        near = float(polyline_distance(xs[nodes], xb).min())
        s = float(surface.signed_distance(xs, along(xb))[0].min())
        return max(0.0, TUBE - near, TUBE - s)

    v0 = model.translation(beam, (0.0, 0.0, -v))
    order = "Beam3D/Solid" if rod_first else "Solid/Beam3D"
    where = "down 10 deg across its edge" if across_edge else f"level, {length:g} m"
    label = f"{order}: rod {v:g} m/s onto an elastic block, {where}, {method or 'default'}"
    label += f", mu {mu:g}" + (", SolidEdges" if across_edge and edges else "")
    return spec(label, model, depth, 1e-4, 0.002 / v + 0.01, v0, TUBE, v,
                edge=slab.min_edge_length, group="3D", pk=not across_edge)  # fmt: skip


def rigid_on_plane(shape="ball", v=2.0, vx=1.0, spin=(0.0, -30.0, 0.0), mu=0.3, e=0.5):
    """A rigid ball (R, 1 kg) or capsule (R, 0.1 m, tilted 0.4 rad) thrown at (vx, 0, −v)
    with ``spin`` (rad/s) onto a plane z = 0, gravity."""
    body = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.12], Ball(R) if shape == "ball"
                               else Capsule(R, 0.1))  # fmt: skip
    plane = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    model = Model([body], [Contact(body, plane, friction=mu, restitution=e)], (0.0, 0.0, -9.81))
    q0 = np.zeros(6)
    q0[3] = 0.0 if shape == "ball" else 0.4
    centres_, radius = body.shape.balls

    def depth(st):
        q = st.q[model.body_slice(0)]
        z = (centres_ @ body.rotation(q).T + body.center(q))[:, 2]
        return max(0.0, radius - float(z.min()))

    v0 = np.concatenate([[vx, 0.0, -v], spin])
    label = f"RigidBody3D/Plane: rigid {shape} ({vx:g}, 0, {-v:g}) m/s, spin {spin[1]:g} rad/s,"
    label += f" mu {mu:g}, e_N {e:g}"
    out = spec(label, model, depth, 1e-3, 0.4, v0, R, v, pk=True, group="3D")
    out.sim = out.sim.replace(q0=q0)
    return out


def ball_box(v=2.0, b=0.3, mu=0.3, e=0.5, ball_first=True):
    """A rigid ball (R, 1 kg) thrown at ``v`` at a free box 0.2 × 0.15 × 0.1 m (1.5 kg)
    spinning at 10 rad/s about z, ``b`` of the sum of the sizes across: a free pair named
    (ball, box) (``BallBoxContact``) or (box, ball) (``ConvexContact``)."""
    box = RigidBody3D.uniform(1.5, [0.0, 0.0, 0.0], Box(0.2, 0.15, 0.1))
    ball = RigidBody3D.uniform(1.0, [-0.3, b * (R + 0.075), 0.01], Ball(R))
    pair = (ball, box) if ball_first else (box, ball)
    model = Model([box, ball], [Contact(*pair, friction=mu, restitution=e)], (0.0, 0.0, 0.0))
    v0 = np.zeros(12)
    v0[3:6], v0[6:9] = [0.0, 0.0, 10.0], [v, 0.0, 0.0]
    centre = lambda st: ball.center(st.q[model.body_slice(1)])[None]  # noqa: E731
    depth = rigid_points_depth(box, model.body_slice(0), centre, pad=R)
    order = "RigidBody3D ball/box" if ball_first else "RigidBody3D box/ball"
    label = f"{order}: ball {v:g} m/s at a spinning free box, b {b:g}, mu {mu:g}, e_N {e:g}"
    return spec(label, model, depth, 2e-4, 0.3 / v, v0, R, v, free=True, pk=True, group="3D")


def rigid_solid(shape="box", v=1.0, b=0.0, method=None, rigid_first=True, mu=0.0):
    """stress_3d's elastic ball (R, 1 refinement) thrown at ``v`` at a free rigid box
    0.1 × 0.15 × 0.2 m as heavy, ``b`` R across (a free pair; mortar), or a rigid ball (R,
    1 kg) thrown down onto the elastic block (node-to-surface: the block's nodes against the
    ball; the depth also counts the ball entering between them)."""
    if shape == "box":
        solid = Solid.ball([-(R + 0.05 + 0.001), b * R, 0.0], R, 1, SOFT)
        rigid = RigidBody3D.uniform(solid.mass, [0.0, 0.0, 0.0], Box(0.1, 0.15, 0.2))
        v0_of = lambda m: m.translation(solid, (v, 0.0, 0.0))  # noqa: E731
    else:
        solid = block()
        rigid = RigidBody3D.uniform(1.0, [b * R, 0.0, R + 0.001], Ball(R))
        v0_of = lambda m: m.translation(rigid, (0.0, 0.0, -v))  # noqa: E731
    pair = (rigid, solid) if rigid_first else (solid, rigid)
    model = Model([solid, rigid], [Contact(*pair, method=method, friction=mu)], (0.0, 0.0, 0.0))
    ss, sr = model.body_slice(0), model.body_slice(1)
    nodes = np.unique(solid.contact_facets())
    nodes_in = rigid_points_depth(rigid, sr, lambda st: solid.positions(st.q[ss])[nodes])
    if shape == "box":
        depth = with_features(nodes_in, model.contacts.pairs[0])
    else:
        surface = Surface(solid.contact_facets())

        def depth(st):  # the ball's centre nearer the block's faces than R
            c = rigid.center(st.q[sr])[None]
            s = float(surface.signed_distance(solid.positions(st.q[ss]), c)[0][0])
            return max(nodes_in(st), R - s)

    order = "RigidBody3D/Solid" if rigid_first else "Solid/RigidBody3D"
    what = "elastic ball at a free rigid box" if shape == "box" else "rigid ball onto a block"
    label = f"{order}: {what}, {v:g} m/s, b {b:g}, {method or 'default'}, mu {mu:g}"
    dt = wave_step(solid, 1.0)
    return spec(label, model, depth, dt, 0.001 / v + 1.5 * hertz_time(v, R), v0_of(model), R, v,
                edge=solid.min_edge_length, free=shape == "box", pk=True, group="3D")  # fmt: skip


# -- the rows -----------------------------------------------------------------------------------

# (builder, its arguments, the builder's switch that names the pair the other way round)
ROWS = [
    (free_strip_on_point, {}, None),
    (free_strip_on_point, dict(x=0.225, vx=0.5, mu=0.3, e=1.0), None),
    (free_strip_on_point, dict(x=0.225, v=10.0), None),
    (strip_disk, {}, "strip_first"),
    (strip_disk, dict(x=0.1, vx=1.0, mu=0.3, e=1.0), "strip_first"),
    (strip_disk, dict(v=30.0), "strip_first"),
    (rigid_circle, dict(e=1.0), None),
    (rigid_circle, dict(v=20.0), None),
    (rigid_circle, dict(inside=False, offset=0.03, spin=20.0, mu=0.3, e=0.5), None),
    (rigid_circle, dict(shape="pentagon", offset=0.02, spin=20.0, mu=0.3), None),
    (disk_polygon, {}, "disk_first"),
    (disk_polygon, dict(offset=0.0, spin=0.0, mu=0.0, e=0.0), "disk_first"),
    (disk_polygon, dict(v=20.0), "disk_first"),
    (block_rigid, {}, "block_first"),
    (block_rigid, dict(shape="pentagon", v=10.0, mu=0.0, e=1.0), "block_first"),
    (solid_circle, dict(mu=0.3), None),
    (solid_circle, dict(v=10.0, e=1.0), None),
    (solid_circle, dict(inside=False), None),
    (solid_circle, dict(inside=False, under=True), None),
    (solid_circle, dict(inside=False, mu=0.3), None),
    (solid_circle, dict(inside=False, under=True, mu=0.3), None),
    (solid_circle, dict(inside=False, under=True, mu=0.3, e=1.0, v=10.0), None),
    (p2_disks, {}, None),
    (p2_disks, dict(mixed=True), None),
    (p2_disks, dict(method="node-to-surface", offset=0.0, mu=0.0, e=1.0), None),
    (rod_sphere, {}, None),
    (rod_sphere, dict(x=0.125, vx=0.5, mu=0.3, e=1.0), None),
    (rod_sphere, dict(x=0.125, v=10.0), None),
    (rod_sphere, dict(inside=True, mu=0.3), None),
    (rigid_rod, {}, "rigid_first"),
    (rigid_rod, dict(shape="capsule", vx=0.5, mu=0.3, e=1.0), "rigid_first"),
    (rigid_rod, dict(shape="box", v=10.0), "rigid_first"),
    (rod_block, {}, "rod_first"),
    (rod_block, dict(length=0.15), None),
    (rod_block, dict(method="node-to-surface", mu=0.3), "rod_first"),
    (rod_block, dict(across_edge=True, method="node-to-surface"), None),
    (rod_block, dict(across_edge=True, method="node-to-surface", edges=False), None),
    (rigid_on_plane, {}, None),
    (rigid_on_plane, dict(v=20.0, e=1.0), None),
    (rigid_on_plane, dict(shape="capsule", e=0.0), None),
    (ball_box, {}, "ball_first"),
    (ball_box, dict(b=0.0, mu=0.0, e=1.0), "ball_first"),
    (ball_box, dict(v=20.0), "ball_first"),
    (rigid_solid, dict(b=0.5), "rigid_first"),
    (rigid_solid, dict(shape="ball", b=0.3, method="node-to-surface", mu=0.3), "rigid_first"),
    (rigid_solid, dict(shape="ball", v=10.0, method="node-to-surface"), None),
    (p2_balls, {}, None),
    (p2_balls, dict(method="node-to-surface"), None),
]
QUICK = [ROWS[0], ROWS[6], ROWS[28]]

COLUMNS = ("group", "run", "step", "status", "max_penetration (m)", "depth (m)", "depth / edge",
           "created / scale", "dP / (m v)", "dL / (m v R)", "fallbacks",
           "p x1000: d centre / R", "k /100: d centre / R", "order: d centre / L")  # fmt: skip


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--row", default="", help="run only the rows whose label contains this text")
    args = p.parse_args()
    rows = []
    for builder, kwargs, switch in QUICK if args.quick else ROWS:
        build = lambda b=builder, k=kwargs: b(**k)  # noqa: E731
        (row,) = measured_rows([build], args.row) or [None]
        if row is not None and switch is not None and row["status"] == "completed":
            twin = builder(**kwargs, **{switch: False})
            row["order: d centre / L"] = reversed_order(builder(**kwargs), twin)
        rows += [row] if row is not None else []
    table, summary, failed = report_tables(rows, COLUMNS)
    sections = [("Every run: status, depth, energy, momentum, fallbacks, p/k, order", summary)]
    if failed:
        sections.append(("Runs that stopped, and why", failed))
    publish_report(args.out, "explore_pairs", args.quick, "Contact pair kinds no sweep runs",
                   table, *sections)  # fmt: skip


if __name__ == "__main__":
    main()
