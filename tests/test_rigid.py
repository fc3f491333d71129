"""Rigid bodies, point masses and the contact pairs of rigid disks.

Gradients and Hessians of every gap are checked against central differences of the gap and of
the gradient at random configurations. With a step ε = 1e-6 on quantities of order 0.1–1 the
truncation error is O(ε²) ~ 1e-12 and the round-off O(1e-16/ε) ~ 1e-10, so a relative error
below 1e-6 leaves four orders of margin and still catches any wrong term.
"""

import numpy as np
import pytest

from fecontact import (
    Beam2D,
    Circle,
    Contact,
    InputError,
    Material,
    Model,
    Plane,
    Point,
    Section,
    simulate,
)
from fecontact.bodies.rigid import Disk, PointMass, Polygon, RigidBody2D, rotation
from fecontact.contact import NodeContact
from fecontact.contact.geometry import polygon_distance
from fecontact.contact.rigid_pairs import (
    DiskBeamContact,
    DiskDiskContact,
    DiskObstacleContact,
    DiskPolygonContact,
)

RNG_SEED = 20240611
FD_STEP = 1e-6
FD_TOLERANCE = 1e-6


def steel_beam(n=5, length=1.0):
    section = Section.rectangle(0.05, 0.01)
    return Beam2D.straight([0.0, 0.0], [length, 0.0], n, Material(210e9, rho=7850.0), section)


def disk(position, radius=0.1, angle=0.0, mass=2.0):
    return RigidBody2D.uniform(mass, position, Disk(radius), angle=angle)


def box(position, angle=0.0, width=0.4, height=0.3):
    return RigidBody2D.uniform(3.0, position, Polygon.box(width, height), angle=angle)


def bind(pair, bodies):
    """Bind ``pair`` to a model of ``bodies`` (no gravity); return the model."""
    model = Model(bodies, [pair], gravity=(0.0, 0.0))
    return model


def dense(pair, q):
    """Gaps (m,), gradients (m, n) and Hessians (m, n, n) of ``pair`` over all n dofs of q."""
    g, dofs, G, H = pair.evaluate(q)
    m, n = len(g), len(q)
    Gd = np.zeros((m, n))
    Hd = np.zeros((m, n, n))
    rows = np.broadcast_to(np.arange(m)[:, None], dofs.shape)
    np.add.at(Gd, (rows, dofs), G)
    if H is not None:
        r3 = np.broadcast_to(np.arange(m)[:, None, None], H.shape)
        np.add.at(Hd, (r3, dofs[:, :, None], dofs[:, None, :]), H)
    return g, Gd, Hd


def check_derivatives(pair, q, rows=None):
    """Central-difference check of G and H of the contacts ``rows`` (default: finite gaps)."""
    g, G, H = dense(pair, q)
    rows = np.flatnonzero(np.isfinite(g)) if rows is None else np.asarray(rows)
    assert rows.size
    G_fd = np.zeros_like(G)
    H_fd = np.zeros_like(H)
    for k in range(len(q)):
        dq = np.zeros(len(q))
        dq[k] = FD_STEP
        gp, Gp, _ = dense(pair, q + dq)
        gm, Gm, _ = dense(pair, q - dq)
        G_fd[rows, k] = (gp[rows] - gm[rows]) / (2.0 * FD_STEP)
        H_fd[rows, :, k] = (Gp[rows] - Gm[rows]) / (2.0 * FD_STEP)
    for j in rows:
        assert np.linalg.norm(G[j] - G_fd[j]) <= FD_TOLERANCE * np.linalg.norm(G[j])
        scale = max(np.linalg.norm(H[j]), np.linalg.norm(G[j]))
        assert np.linalg.norm(H[j] - H_fd[j]) <= FD_TOLERANCE * scale
        np.testing.assert_allclose(H[j], H[j].T, atol=1e-12 * scale)
    return g, G, H


# -- bodies ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"mass": 0.0}, "mass"),
        ({"mass": -1.0}, "mass"),
        ({"mass": np.nan}, "mass"),
        ({"inertia": 0.0}, "inertia"),
        ({"inertia": np.inf}, "inertia"),
        ({"position": [0.0, np.nan]}, "position"),
        ({"position": [0.0, 1.0, 2.0]}, "position"),
        ({"angle": np.nan}, "angle"),
        ({"shape": None}, "shape"),
        ({"shape": "disk"}, "shape"),
    ],
)
def test_rigid_body_rejects_bad_input(kwargs, message):
    args = {"mass": 1.0, "inertia": 0.1, "position": [0.0, 0.0], "shape": Disk(0.1)} | kwargs
    with pytest.raises(InputError, match=message):
        RigidBody2D(**args)


@pytest.mark.parametrize("radius", [0.0, -0.1, np.nan, np.inf])
def test_disk_rejects_bad_radius(radius):
    with pytest.raises(InputError, match="radius"):
        Disk(radius)


@pytest.mark.parametrize(
    "vertices, message",
    [
        ([[0, 0], [1, 0]], "n >= 3"),
        ([[0, 0], [1, 0], [1, 0], [0, 1]], "distinct"),
        ([[0, 0], [0, 0], [0, 0]], "distinct"),
        ([[0, 0], [0, 1], [1, 1], [1, 0]], "counter-clockwise"),
        ([[0, 0], [2, 0], [1, 0.2], [2, 1], [0, 1]], "convex"),
        ([[0, 0], [1, 0], [2, 0], [1, 1]], "convex"),  # collinear vertex
        ([[0, 0], [1, np.nan], [0, 1]], "finite"),
        # a pentagram turns left at every vertex but winds twice
        (
            [[np.cos(a), np.sin(a)] for a in 2.0 * np.pi * np.array([0, 2, 4, 1, 3]) / 5],
            "convex",
        ),
    ],
)
def test_polygon_rejects_bad_vertices(vertices, message):
    with pytest.raises(InputError, match=message):
        Polygon(vertices)


def test_point_mass_rejects_bad_input():
    with pytest.raises(InputError, match="mass"):
        PointMass(0.0, [0.0, 0.0])
    with pytest.raises(InputError, match="position"):
        PointMass(1.0, [np.nan, 0.0])
    with pytest.raises(InputError, match="size"):
        PointMass(1.0, [0.0, 0.0], size=0.0)
    with pytest.raises(InputError, match="point"):
        PointMass(1.0, [0.0, 0.0]).node_index(1)


def test_shape_properties():
    b = Polygon.box(0.4, 0.3)
    assert b.area == pytest.approx(0.12)
    np.testing.assert_allclose(b.centroid, 0.0, atol=1e-15)
    assert b.moment(2.0) == pytest.approx(2.0 * (0.4**2 + 0.3**2) / 12.0)
    assert b.size == pytest.approx(0.5)
    np.testing.assert_allclose(b.normals, [[0, -1], [1, 0], [0, 1], [-1, 0]], atol=1e-15)
    assert Disk(0.2).moment(3.0) == pytest.approx(0.5 * 3.0 * 0.04)
    # a many-sided regular polygon tends to the disk (error ~ (2π/n)²)
    assert Polygon.regular(400, 0.2).moment(3.0) == pytest.approx(0.06, rel=1e-3)
    with pytest.raises(InputError, match="centroid"):
        RigidBody2D.uniform(1.0, [0, 0], Polygon([[0, 0], [1, 0], [0, 1]]))


def test_rigid_body_mass_gravity_and_fixed_dofs():
    body = RigidBody2D(2.0, 0.3, [1.0, 2.0], 0.4, Polygon.box(1.0, 0.5))
    M = body.mass_matrix().toarray()
    np.testing.assert_array_equal(M, np.diag([2.0, 2.0, 0.3]))
    np.testing.assert_array_equal(M @ body.translation_field((0.0, -9.81)), [0.0, -19.62, 0.0])
    W, f, Ke = body.internal(np.ones(3))
    assert W == 0.0 and not f.any() and Ke.shape == (0, 3, 3)
    assert body.fix("theta").fixed == {2}
    with pytest.raises(InputError, match="components must be among x, y, theta"):
        body.fix("z")
    assert PointMass(1.5, [0, 0]).mass_matrix().toarray().tolist() == [[1.5, 0], [0, 1.5]]


def test_positions_follow_the_pose_and_cells_close_the_outline():
    body = RigidBody2D(1.0, 0.1, [1.0, 2.0], np.pi / 2, Polygon.box(2.0, 1.0))
    q = np.array([0.5, -0.5, np.pi / 2])  # now turned by π: the box is upside down
    x = body.positions(q)
    np.testing.assert_allclose(x[:4], [[2.5, 2.0], [0.5, 2.0], [0.5, 1.0], [2.5, 1.0]], atol=1e-14)
    np.testing.assert_allclose(x[body.center_index], [1.5, 1.5])
    assert body.cells()[0][1].tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]
    d = disk([0.0, 0.0], radius=0.5)
    assert d.n_nodes == 49 and d.center_index == 0
    conn = d.cells()[0][1]
    assert conn.min() == 0 and conn.max() == d.n_nodes - 1
    np.testing.assert_allclose(np.linalg.norm(d.positions(np.zeros(3))[1:], axis=1), 0.5)


def test_point_kinematics_derivatives_are_exact():
    rng = np.random.default_rng(RNG_SEED)
    body = RigidBody2D(1.0, 0.1, [0.3, -0.2], 0.7, Polygon.regular(5, 0.4))
    nodes = body.contact_nodes()
    for _ in range(5):
        q = rng.normal(size=3)
        x, dofs, Jx, Hx = body.point_kinematics(q, nodes)
        np.testing.assert_allclose(x, body.positions(q)[nodes], atol=1e-15)
        assert dofs.tolist() == [[0, 1, 2]] * 5
        for k in range(3):
            dq = np.zeros(3)
            dq[k] = FD_STEP
            xp, _, Jp, _ = body.point_kinematics(q + dq, nodes)
            xm, _, Jm, _ = body.point_kinematics(q - dq, nodes)
            np.testing.assert_allclose(Jx[:, :, k], (xp - xm) / (2 * FD_STEP), atol=1e-9)
            np.testing.assert_allclose(Hx[:, :, :, k], (Jp - Jm) / (2 * FD_STEP), atol=1e-9)


def test_frame_points_follow_the_body():
    body = RigidBody2D(1.0, 0.1, [0.3, -0.2], 0.7, Polygon.box(0.6, 0.2))
    q = np.array([0.1, 0.2, 0.3])
    x, _, Jx, Hx = body.frame_point_kinematics(q, body.shape.vertices[2])
    ref = body.point_kinematics(q, np.array([2]))
    np.testing.assert_array_equal(x, ref[0])
    np.testing.assert_array_equal(Jx, ref[2])
    np.testing.assert_array_equal(Hx, ref[3])


def test_nodal_velocity_is_the_rate_of_the_output_points():
    body = RigidBody2D(1.0, 0.1, [0.3, -0.2], 0.7, Polygon.box(0.6, 0.2))
    q, v, dt = np.array([0.1, 0.2, 0.3]), np.array([1.0, -2.0, 3.0]), 1e-6
    rate = (body.positions(q + dt * v) - body.positions(q - dt * v)) / (2 * dt)
    np.testing.assert_allclose(body.nodal(v, q), rate, atol=1e-8)
    data = body.point_data(q, v)
    np.testing.assert_allclose(data["velocity"], rate, atol=1e-8)
    np.testing.assert_allclose(data["displacement"], body.positions(q) - body.positions(0 * q))
    # the centre of mass moves with the translation whatever the orientation argument
    np.testing.assert_array_equal(body.nodal(v)[body.center_index], v[:2])


def test_contact_nodes():
    poly = box([0, 0])
    assert poly.contact_nodes().tolist() == [0, 1, 2, 3]
    assert poly.contact_nodes([-1, 1]).tolist() == [3, 1]
    with pytest.raises(InputError, match="vertices"):
        poly.contact_nodes([4])  # the centre of mass is an output point, not a vertex
    with pytest.raises(InputError, match="no vertices"):
        disk([0, 0]).contact_nodes()


# -- contact pairs --------------------------------------------------------------------------


def test_factory_dispatches_to_the_rigid_pairs():
    a, b, p, beam = disk([0, 1]), disk([1, 1]), box([3, 3]), steel_beam()
    assert isinstance(Contact(a, Plane([0, 0], [0, 1])), DiskObstacleContact)
    assert isinstance(Contact(a, Circle([5, 5], 1.0)), DiskObstacleContact)
    assert isinstance(Contact(a, b), DiskDiskContact)
    assert isinstance(Contact(a, p), DiskPolygonContact)
    pair = Contact(p, a, restitution=0.3)
    assert isinstance(pair, DiskPolygonContact) and pair.body is p and pair.restitution == 0.3
    assert isinstance(Contact(a, beam, clearance=0.005), DiskBeamContact)
    assert Contact(beam, a).body is beam
    assert isinstance(Contact(p, Plane([0, 0], [0, 1])), NodeContact)
    assert isinstance(Contact(PointMass(1, [0, 1]), Plane([0, 0], [0, 1])), NodeContact)
    assert Contact(a, b).obstacle is None and Contact(a, b).bodies == (a, b)
    with pytest.raises(InputError, match="nodes"):
        Contact(a, Plane([0, 0], [0, 1]), nodes=[0])
    with pytest.raises(InputError, match="polygon against polygon"):
        Contact(p, box([5, 5]))
    with pytest.raises(InputError, match="clearance"):
        Contact(a, b, clearance=0.1)
    # half the thickness of a beam against any rigid obstacle (its gaps measure the centreline)
    assert Contact(beam, Plane([0, -1], [0, 1]), clearance=0.1).clearance == 0.1
    with pytest.raises(InputError, match="itself"):
        Contact(a, a)
    with pytest.raises(InputError, match="restitution"):
        Contact(a, b, restitution=1.5)
    with pytest.raises(InputError, match="no contact"):
        Contact(a, Point([0, 0]))


def test_disk_obstacle_gaps():
    d = disk([1.0, 0.5], radius=0.1)
    plane = Contact(d, Plane([0.0, 0.0], [0.0, 1.0]))
    bind(plane, [d])
    g, dofs, G, H = plane.evaluate(np.array([0.3, -0.1, 2.0]))
    assert g == pytest.approx([0.3]) and dofs.tolist() == [[0, 1]] and H is None
    assert plane.linear
    cavity = Contact(d, Circle([1.0, 0.0], 1.0, inside=True))
    bind(cavity, [d])
    assert cavity.evaluate(np.zeros(3))[0] == pytest.approx([0.4])
    assert not cavity.linear


def test_disk_from_a_cavitys_centre_bounces_back():
    """A disk starting at the centre of a circular cavity (R from the wall there, its normal
    any direction) is thrown at the wall, e_N = 1: it comes back at its speed, never
    deeper than round-off (a single rigid impact: exact)."""
    d = disk([1.0, 0.0], radius=0.1, mass=1.0)
    model = Model([d], [Contact(d, Circle([1.0, 0.0], 0.5, inside=True), restitution=1.0)],
                  gravity=(0.0, 0.0))  # fmt: skip
    states = list(simulate(model, 1e-3, 0.5, v0=np.array([2.0, 0.0, 0.0])))
    assert states[-1].v[:2] == pytest.approx([-2.0, 0.0], abs=1e-12)
    assert min(st.gaps.min() for st in states) >= -1e-12


@pytest.mark.parametrize("trial", range(4))
def test_disk_obstacle_derivatives(trial):
    rng = np.random.default_rng(RNG_SEED + trial)
    d = disk([0.3, 0.5], angle=0.2)
    for obstacle in (Plane([0, 0], [0.3, 1.0]), Circle([0, 0], 0.2), Circle([0, 0], 2, True)):
        pair = Contact(d, obstacle)
        bind(pair, [d])
        check_derivatives(pair, 0.1 * rng.normal(size=3))


@pytest.mark.parametrize("trial", range(4))
def test_disk_disk_gap_and_derivatives(trial):
    rng = np.random.default_rng(RNG_SEED + trial)
    a, b = disk([0.3, 0.5], radius=0.1), disk([0.1, 0.9], radius=0.2)
    pair = Contact(a, b)
    bind(pair, [a, b])
    q = 0.1 * rng.normal(size=6)
    g, *_ = check_derivatives(pair, q)
    ca, cb = a.center(q[:3]), b.center(q[3:])
    assert g[0] == pytest.approx(np.linalg.norm(cb - ca) - 0.3, abs=1e-15)


def test_polygon_distance_pieces():
    shape = Polygon.box(2.0, 1.0)
    V, N = shape.vertices, shape.normals
    s, ds, dds = polygon_distance(V, N, np.array([0.3, 1.5]))  # above the top edge
    assert s == pytest.approx(1.0) and ds.tolist() == [0.0, 1.0] and not dds.any()
    s, ds, _ = polygon_distance(V, N, np.array([4.0, 4.5]))  # beyond the top-right corner
    assert s == pytest.approx(5.0)
    np.testing.assert_allclose(ds, [0.6, 0.8])
    s, ds, _ = polygon_distance(V, N, np.array([0.9, 0.1]))  # inside, nearest the right edge
    assert s == pytest.approx(-0.1) and ds.tolist() == [1.0, 0.0]
    # continuous with a continuous gradient across the edge/vertex boundary x = 1
    for eps in (1e-9, -1e-9):
        s, ds, _ = polygon_distance(V, N, np.array([1.0 + eps, 0.9]))
        assert s == pytest.approx(0.4, abs=1e-8)
        np.testing.assert_allclose(ds, [0.0, 1.0], atol=1e-8)


@pytest.mark.parametrize(
    "center, piece",
    [([0.75, 1.0], "edge"), ([1.2, 0.9], "vertex"), ([0.7, 0.62], "inside"), ([0.1, 0.6], "edge")],
)
def test_disk_polygon_derivatives(center, piece):
    """The disk centre starts over an edge, beyond a vertex or inside the tilted box; small
    random motions of both bodies keep it on the same piece of the distance."""
    rng = np.random.default_rng(RNG_SEED)
    d, p = disk(center, radius=0.1), box([0.6, 0.5], angle=0.3)
    for order in ((d, p), (p, d)):
        pair = Contact(*order)
        bind(pair, [d, p])
        for _ in range(3):
            q = 0.005 * rng.normal(size=6)
            g, G, _ = check_derivatives(pair, q)
            rho = rotation(p.orientation(q[3:])).T @ (d.center(q[:3]) - p.center(q[3:]))
            s = polygon_distance(p.shape.vertices, p.shape.normals, rho)[0]
            assert g[0] == pytest.approx(s - 0.1, abs=1e-14)
            assert (s < 0) == (piece == "inside")
            assert not G[0, 2]  # the disk's own rotation does not enter (frictionless)


def test_disk_beam_gaps_are_every_elements_distance_continuous_over_a_node():
    beam = steel_beam(n=4)  # nodes at x = 0, 0.25, 0.5, 0.75, 1
    over_node = disk([0.5, 0.3], radius=0.1)
    pair = Contact(over_node, beam, clearance=0.005)
    bind(pair, [beam, over_node])
    g, dofs, G, _ = pair.evaluate(np.zeros(3 + beam.ndof))
    # both elements at the node x = 0.5 hold it by its distance: one row twice (redundant_rows)
    assert g[1] == pytest.approx(0.195) and g[2] == pytest.approx(0.195)
    assert np.all(g[[0, 3]] > 0.195)
    dense = np.zeros((4, 3 + beam.ndof))
    for e in range(4):
        dense[e, dofs[e]] = G[e]
    np.testing.assert_allclose(dense[1], dense[2], rtol=0.0, atol=1e-15)  # (exact, round-off)
    # across the node the gaps follow the distance: no element's gap jumps (once +inf left of
    # the node for element 2, which a kink under the disk then made negative at once)
    for dx in (-1e-7, 0.0, 1e-7):
        moved = disk([0.5 + dx, 0.3], radius=0.1)
        pair = Contact(moved, beam, clearance=0.005)
        bind(pair, [beam, moved])
        g = pair.evaluate(np.zeros(3 + beam.ndof))[0]
        # the distance is 0.3 m within dx²/0.6 ≈ 2e-14 m; the line distance's round-off is
        # 1.7e-14 m, measured: 1e-12 m leaves a factor 30 (the old rule's jump was infinite)
        np.testing.assert_allclose(g[1:3], 0.195, rtol=0.0, atol=1e-12)
    pair = Contact(over_node, beam, clearance=0.005)
    bind(pair, [beam, over_node])
    # bend the beam into a V under the disk: both elements touch it, each by its own line
    q = np.zeros(3 + beam.ndof)
    q[3 * 2 + 1] = -0.02
    g = pair.evaluate(q)[0]
    assert np.all(np.isfinite(g[1:3])) and g[1] == pytest.approx(g[2])
    below = disk([0.6, -0.3], radius=0.1)
    pair = Contact(below, beam)
    bind(pair, [beam, below])
    # (the disk is below the beam: the gap is its distance, not minus it)
    assert np.min(pair.evaluate(np.zeros(3 + beam.ndof))[0]) == pytest.approx(0.2)
    with pytest.raises(InputError, match="centreline"):
        Contact(disk([0.6, 0.0]), beam)


@pytest.mark.parametrize(
    "center, bend",
    [([0.4, 0.2], 0.0), ([0.5, 0.2], -0.02), ([1.2, 0.1], 0.0), ([-0.1, -0.2], 0.0)],
    ids=["inside-element", "kink", "beyond-end", "before-start"],
)
def test_disk_beam_derivatives(center, bend):
    rng = np.random.default_rng(RNG_SEED)
    beam = steel_beam(n=4)
    d = disk(center, radius=0.05)
    pair = Contact(d, beam, clearance=0.003)
    bind(pair, [beam, d])
    for _ in range(3):
        q = np.concatenate([1e-3 * rng.normal(size=beam.ndof), 1e-3 * rng.normal(size=3)])
        q[3 * 2 + 1] += bend
        check_derivatives(pair, q)


@pytest.mark.parametrize("obstacle", [Plane([0, 0], [0.2, 1.0]), Circle([0.5, -1.0], 1.0)])
def test_polygon_vertex_node_contact_derivatives(obstacle):
    """Polygon vertices against obstacles go through NodeContact and the body's exact
    second derivatives of x(θ)."""
    rng = np.random.default_rng(RNG_SEED)
    p = box([0.5, 0.6], angle=0.4)
    pair = Contact(p, obstacle)
    bind(pair, [p])
    assert not pair.linear
    for _ in range(3):
        check_derivatives(pair, 0.1 * rng.normal(size=3))


# -- dynamics -------------------------------------------------------------------------------


def test_free_flight_is_exact():
    """Under constant gravity the generalized-α solution of a free rigid body is exact: the
    acceleration is constant, and the scheme integrates polynomials of degree 2 exactly."""
    body = RigidBody2D.uniform(2.0, [0.0, 1.0], Polygon.box(0.3, 0.2), angle=0.1)
    model = Model([body], gravity=(0.0, -9.81))
    v0 = np.array([1.0, 3.0, 5.0])
    st = list(simulate(model, 1e-2, 0.5, v0=v0))[-1]
    t = st.t
    np.testing.assert_allclose(st.q, [t, 3 * t - 0.5 * 9.81 * t**2, 5 * t], rtol=1e-12)
    np.testing.assert_allclose(st.v, [1.0, 3.0 - 9.81 * t, 5.0], rtol=1e-12)
    e0 = model.kinetic_energy(v0)
    assert model.kinetic_energy(st.v) + model.potential_energy(st.q) == pytest.approx(e0)


@pytest.mark.parametrize("restitution", [0.0, 0.5, 1.0])
def test_head_on_disk_collision_obeys_newton_and_momentum(restitution):
    """Two disks on a line, no gravity: momentum is conserved and the relative velocity
    reverses with factor e (exact for a single impact between rigid bodies)."""
    a, b = disk([0.0, 0.0], radius=0.1, mass=1.0), disk([0.5, 0.0], radius=0.2, mass=3.0)
    model = Model([a, b], [Contact(a, b, restitution=restitution)], gravity=(0.0, 0.0))
    v0 = np.array([2.0, 0.0, 0.0, -1.0, 0.0, 0.0])
    gaps = []
    for st in simulate(model, 1e-3, 0.2, v0=v0):
        gaps.append(st.gaps[0])
    p0 = 1.0 * 2.0 + 3.0 * -1.0
    assert 1.0 * st.v[0] + 3.0 * st.v[3] == pytest.approx(p0, abs=1e-12)
    assert st.v[3] - st.v[0] == pytest.approx(restitution * 3.0, abs=1e-12)
    assert min(gaps) >= -1e-12
    np.testing.assert_allclose(st.v[[1, 2, 4, 5]], 0.0, atol=1e-14)


def test_disk_striking_a_box_conserves_momenta():
    """A disk hits a free box off-centre: linear momentum and the angular momentum about the
    origin are conserved through the impact, and the box starts spinning."""
    d = disk([-1.0, 0.1], radius=0.1, mass=1.0)
    p = box([0.0, 0.0])
    model = Model([d, p], [Contact(d, p, restitution=0.5)], gravity=(0.0, 0.0))
    v0 = np.zeros(6)
    v0[0] = 4.0

    def momenta(st):
        out = np.zeros(3)
        for i, body in enumerate((d, p)):
            s = model.body_slice(i)
            c, v = body.center(st.q[s]), st.v[s]
            out[:2] += body.mass * v[:2]
            out[2] += body.mass * (c[0] * v[1] - c[1] * v[0]) + body.inertia * v[2]
        return out

    states = list(simulate(model, 1e-3, 0.4, v0=v0))
    assert max(st.impulse.max() for st in states) > 0.0
    np.testing.assert_allclose(momenta(states[-1]), momenta(states[0]), atol=1e-12)
    assert states[-1].v[5] < 0.0  # hit above the centre: clockwise spin
    assert min(st.gaps.min() for st in states) >= -1e-12
