"""Contact between deformable bodies: gap derivatives, facet choice, spatial search, pairs."""

import numpy as np
import pytest
import skfem

from fecontact import Beam2D, Contact, InputError, Material, Model, Section
from fecontact.bodies.materials import LinearElastic, NeoHookean
from fecontact.bodies.solid import Solid
from fecontact.contact.beam_sides import PointBeamContact
from fecontact.contact.body_pairs import (
    NodeNodeContact,
    NodeSurfaceContact,
    closest_facet_distance,
    facet_plane_gap,
    triangle_plane_distance,
)
from fecontact.contact.mortar import MortarContact

MAT = LinearElastic(E=1e6, nu=0.3, rho=1000.0)
RNG = np.random.default_rng(20240611)


def central_differences(fun, y, eps):
    """Gradient (m, n) and Hessian (m, n, n) of fun: (m, n) -> (g, G) by central differences
    (the Hessian from the differences of the analytic gradient)."""
    m, n = y.shape
    G = np.zeros((m, n))
    H = np.zeros((m, n, n))
    for k in range(n):
        e = np.zeros(n)
        e[k] = eps
        gp, Gp = fun(y + e)[:2]
        gm, Gm = fun(y - e)[:2]
        G[:, k] = (gp - gm) / (2 * eps)
        H[:, :, k] = (Gp - Gm) / (2 * eps)
    return G, H


def relative_error(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


# -- gap functions ---------------------------------------------------------------------------


def test_triangle_plane_gap_derivatives_match_central_differences():
    # g is smooth (a ratio of polynomials) away from degenerate triangles; eps = 1e-6 on O(1)
    # coordinates leaves truncation ~1e-12 and round-off ~1e-10: 1e-6 is a safe bound
    y = RNG.normal(size=(20, 12))

    def fun(y):
        return triangle_plane_distance(y[:, :3], y[:, 3:6], y[:, 6:9], y[:, 9:])

    g, G, H = fun(y)
    G_fd, H_fd = central_differences(fun, y, 1e-6)
    assert relative_error(G, G_fd) < 1e-6
    assert relative_error(H, H_fd) < 1e-6
    np.testing.assert_allclose(H, H.transpose(0, 2, 1), atol=1e-12)


def test_segment_plane_gap_derivatives_match_central_differences():
    y = RNG.normal(size=(20, 6))

    def fun(y):
        return facet_plane_gap(y[:, :2], y[:, 2:].reshape(-1, 2, 2))

    g, G, H = fun(y)
    G_fd, H_fd = central_differences(fun, y, 1e-6)
    assert relative_error(G, G_fd) < 1e-6
    assert relative_error(H, H_fd) < 1e-6


def test_gap_signs_follow_the_outward_normal():
    # 2D: segment from (0, 0) to (1, 0), body on its left (y > 0), outward normal −y
    seg = np.array([[[0.0, 0.0], [1.0, 0.0]]] * 2)
    g = facet_plane_gap(np.array([[0.3, -0.2], [0.3, 0.1]]), seg)[0]
    np.testing.assert_allclose(g, [0.2, -0.1])
    # 3D: triangle in z = 0 numbered counter-clockwise seen from +z: outward normal +z
    tri = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]] * 2)
    g = facet_plane_gap(np.array([[0.2, 0.2, 0.3], [0.2, 0.2, -0.1]]), tri)[0]
    np.testing.assert_allclose(g, [0.3, -0.1])


def test_closest_facet_distance_clips_to_the_facet():
    tri = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]] * 3)
    x = np.array([[0.2, 0.2, 0.5], [2.0, 0.0, 0.0], [-1.0, -1.0, 1.0]])
    dist, g = closest_facet_distance(x, tri)
    np.testing.assert_allclose(dist, [0.5, 1.0, np.sqrt(3.0)])
    np.testing.assert_allclose(g, [0.5, 0.0, 1.0])
    seg = np.array([[[0.0, 0.0], [1.0, 0.0]]] * 2)
    dist, g = closest_facet_distance(np.array([[0.5, -0.5], [2.0, -1.0]]), seg)
    np.testing.assert_allclose(dist, [0.5, np.sqrt(2.0)])
    np.testing.assert_allclose(g, [0.5, 1.0])


# -- node-to-surface pairs -------------------------------------------------------------------


def square(lower, size, n, **options):
    return Solid.rectangle(lower, np.add(lower, size), n, MAT, **options)


def cube(lower, size, n, **options):
    return Solid.box(lower, np.add(lower, size), n, MAT, **options)


def bodies_2d(element="P1", cell="triangle"):
    """A coarse square (slave) just above a larger, finer one (master)."""
    master = square([0.0, 0.0], [1.0, 0.5], (5, 3), element=element, cell=cell)
    slave = square([0.13, 0.52], [0.5, 0.3], (2, 2), element=element, cell=cell)
    return slave, master


def bodies_3d(element="P1", cell="tetra"):
    master = cube([0.0, 0.0, 0.0], [1.0, 1.0, 0.5], (3, 3, 2), element=element, cell=cell)
    slave = cube([0.21, 0.27, 0.52], [0.4, 0.4, 0.3], (2, 2, 1), element=element, cell=cell)
    return slave, master


CONFIGURATIONS = [
    ("2D P1 triangles", lambda: bodies_2d()),
    ("2D P1 quads", lambda: bodies_2d(cell="quad")),
    ("2D P2 triangles", lambda: bodies_2d("P2")),
    ("3D P1 tetrahedra", lambda: bodies_3d()),
    ("3D P1 hexahedra", lambda: bodies_3d(cell="hexahedron")),
    ("3D P2 tetrahedra", lambda: bodies_3d("P2")),
]


def bound_pair(slave, master, **options):
    pair = Contact(slave, master, method="node-to-surface", **options)
    Model([slave, master], [pair], gravity=np.zeros(slave.dim))
    return pair


@pytest.mark.parametrize("name, make", CONFIGURATIONS, ids=[c[0] for c in CONFIGURATIONS])
def test_pair_gradient_and_hessian_match_central_differences(name, make):
    # random displacements of both bodies (0.3 % of their size) with the slave pressed 1 %
    # into the master (it starts 2 % above it); each row is differentiated
    # through the pair's own evaluate with the selected facet held (checked unchanged)
    slave, master = make()
    pair = bound_pair(slave, master)
    n = slave.ndof + master.ndof
    q = 0.003 * RNG.normal(size=n)
    q[: slave.ndof] -= 0.03 * np.tile(np.eye(slave.dim)[-1], slave.n_nodes)  # press in
    g, dofs, G, _ = pair.evaluate(q)
    rows = np.flatnonzero(np.isfinite(g))
    H = np.zeros(G.shape + G.shape[1:])
    H[rows] = pair.hessians(q, rows)
    assert rows.size >= 3 and np.any(g[rows] < 0)
    selected = pair.selected.copy()
    eps = 1e-7
    k = dofs.shape[1]
    G_fd, H_fd = np.zeros((rows.size, k)), np.zeros((rows.size, k, k))
    for i, r in enumerate(rows):
        for c in range(k):
            for sign in (1.0, -1.0):
                dq = np.zeros(n)
                dq[dofs[r, c]] = sign * eps
                g_, _, G_, _ = pair.evaluate(q + dq)
                assert np.array_equal(pair.selected, selected)
                G_fd[i, c] += sign * g_[r] / (2 * eps)
                H_fd[i, :, c] += sign * G_[r] / (2 * eps)
    assert relative_error(G[rows], G_fd) < 1e-6
    assert relative_error(H[rows], H_fd) < 1e-6


@pytest.mark.parametrize("name, make", CONFIGURATIONS, ids=[c[0] for c in CONFIGURATIONS])
def test_gradients_are_translation_invariant(name, make):
    # g depends on relative positions only: the contact force Σ G_jᵀ λ_j has zero resultant,
    # so the total momentum is untouched by contact (to round-off)
    slave, master = make()
    pair = bound_pair(slave, master)
    q = 0.01 * RNG.normal(size=slave.ndof + master.ndof)
    g, dofs, G, _ = pair.evaluate(q)
    rows = np.isfinite(g)
    d = slave.dim
    np.testing.assert_allclose(G[rows].reshape(rows.sum(), -1, d).sum(axis=1), 0.0, atol=1e-13)
    assert np.all(G[~rows] == 0.0) and np.all(pair.hessians(q, np.flatnonzero(~rows)) == 0.0)


def winding_number(x, xf):
    """Winding number of the closed surface of facets xf (F, k, d) around the point x, summed
    over every facet: the angles subtended by the segments (2D), the solid angles of the
    triangles by Van Oosterom & Strackee (IEEE Trans. Biomed. Eng., 1983) (3D)."""
    r = xf - x
    if x.size == 2:
        a, b = r[:, 0], r[:, 1]
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        return np.sum(np.arctan2(cross, np.sum(a * b, axis=1))) / (2 * np.pi)
    a, b, c = r[:, 0], r[:, 1], r[:, 2]
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    num = np.einsum("ij,ij->i", a, np.cross(b, c))
    dot = lambda u, v: np.sum(u * v, axis=1)  # noqa: E731
    den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la
    return np.sum(2 * np.arctan2(num, den)) / (4 * np.pi)


def brute_force_gaps(pair, q):
    """Gaps by the facet rule of the module docstring over every facet (no search): nodes
    within the margin of a facet, or inside the master by their winding number."""
    xs, xm = pair.positions(q)
    F = len(pair.facets)
    out = np.full(len(xs), np.inf)
    for i, x in enumerate(xs):
        dist, g = closest_facet_distance(np.repeat(x[None], F, 0), xm[pair.facets])
        if dist.min() > pair.margin and winding_number(x, xm[pair.facets]) < 0.5:
            continue
        ties = dist <= dist.min() + pair.tie_tolerance
        out[i] = g[ties][np.argmax(np.abs(g[ties]))]
    return out


@pytest.mark.parametrize("name, make", CONFIGURATIONS, ids=[c[0] for c in CONFIGURATIONS])
def test_spatial_search_finds_what_a_brute_force_search_finds(name, make):
    slave, master = make()
    pair = bound_pair(slave, master, nodes=None)
    for scale in (0.0, 0.01, 0.05):
        q = scale * RNG.normal(size=slave.ndof + master.ndof)
        np.testing.assert_allclose(closest_gaps(pair, q), brute_force_gaps(pair, q), atol=1e-14)


def closest_gaps(pair, q):
    """Each slave node's gap from its closest facet's plane: the row that holds that facet
    (a node at a concave feature has rows for the feature's other facets too)."""
    g, n = pair.evaluate(q)[0], len(pair.nodes)
    rows = pair.selected.reshape(-1, n) == pair.closest
    out = np.full(n, np.inf)
    node, slot = np.nonzero(rows.T)
    out[node] = g.reshape(-1, n).T[node, slot]
    return out


def test_outside_a_convex_corner_the_gap_is_the_larger_plane_gap():
    # the master square's corner (1, 1); a node in the cone outside it has both adjacent
    # edges equally close (at the vertex): g = max of the two plane gaps, continuous across
    # the diagonal, and below the distance to the corner
    master = square([0.0, 0.0], [1.0, 1.0], 2)
    probe = Solid(
        skfem.MeshTri(np.array([[0.0, 0.01, 0.0], [0.0, 0.0, 0.01]]), [[0], [1], [2]]), MAT
    )
    pair = NodeSurfaceContact(probe, master, nodes=[0], margin=0.2)
    pair.offsets = (0, probe.ndof)
    q = np.zeros(probe.ndof + master.ndof)
    gaps = []
    for angle in (0.2, np.pi / 4 - 1e-9, np.pi / 4 + 1e-9, 1.2):
        q[:2] = np.array([1.0, 1.0]) + 0.05 * np.array([np.cos(angle), np.sin(angle)])
        g = pair.evaluate(q)[0][0]
        assert g == pytest.approx(0.05 * max(np.cos(angle), np.sin(angle)), rel=1e-12)
        gaps.append(g)
    assert gaps[1] == pytest.approx(gaps[2], rel=1e-8)  # continuous across the diagonal
    assert max(gaps) < 0.05


def test_a_node_inside_the_master_gets_minus_its_depth_to_the_nearest_edge():
    master = square([0.0, 0.0], [1.0, 1.0], 4)
    probe = Solid(
        skfem.MeshTri(np.array([[0.0, 0.01, 0.0], [0.0, 0.0, 0.01]]), [[0], [1], [2]]), MAT
    )
    pair = NodeSurfaceContact(probe, master, nodes=[0], margin=0.1)
    pair.offsets = (0, probe.ndof)
    q = np.zeros(probe.ndof + master.ndof)
    for x, depth in (((0.95, 0.5), 0.05), ((0.97, 0.98), 0.02), ((0.5, 0.03), 0.03)):
        q[:2] = x
        assert pair.evaluate(q)[0][0] == pytest.approx(-depth, abs=1e-14)


def test_far_nodes_report_an_infinite_gap_and_no_derivatives():
    slave, master = bodies_2d()
    pair = bound_pair(slave, master)
    q = np.zeros(slave.ndof + master.ndof)
    q[: slave.ndof] = np.tile([0.0, 10.0], slave.n_nodes)
    g, dofs, G, _ = pair.evaluate(q)
    # one row per node and its rows at concave features (1 + extra)
    rows = (1 + pair.extra) * len(slave.boundary_nodes())
    assert np.all(np.isinf(g)) and g.shape == (pair.size,) and pair.size == rows
    assert not G.any() and not pair.hessians(q, np.arange(pair.size)).any()
    assert dofs.min() >= 0 and dofs.max() < slave.ndof + master.ndof


def test_only_nodes_within_the_margin_get_a_finite_gap():
    # a fine master, a slave touching it at one corner: the gaps that come back finite are
    # exactly those of the nodes within the margin of the master's boundary
    master = Solid.disk([0.0, 0.0], 1.0, 4, MAT)
    slave = Solid.disk([2.05, 0.0], 1.0, 2, MAT)
    pair = bound_pair(slave, master)
    x = slave.positions(np.zeros(slave.ndof))[pair.nodes]
    finite = np.isfinite(closest_gaps(pair, np.zeros(slave.ndof + master.ndof)))
    distance = np.linalg.norm(x, axis=1) - 1.0  # to the polygon: within its sagitta 2e-3
    assert finite.sum() >= 1
    assert np.all(distance[finite] <= pair.margin + 2e-3)
    assert np.all(distance[~finite] >= pair.margin - 2e-3)


def test_global_dofs_follow_the_model_layout():
    slave, master = bodies_2d()
    beam = Beam2D.straight([0.0, -1.0], [1.0, -1.0], 3, Material(1e9, rho=1e3), Section(1e-4, 1e-9))
    pair = Contact(slave, master, method="node-to-surface")
    model = Model([beam, master, slave], [pair])
    g, dofs, G, H = pair.evaluate(np.zeros(model.n))
    rows = np.isfinite(g)
    o_s, o_m = model.offset_of(slave), model.offset_of(master)
    assert np.all((dofs[:, :2] >= o_s) & (dofs[:, :2] < o_s + slave.ndof))
    assert np.all((dofs[rows, 2:] >= o_m) & (dofs[rows, 2:] < o_m + master.ndof))
    gg, Gd = model.contacts.jacobian(np.zeros(model.n), np.flatnonzero(rows))
    assert Gd.shape == (rows.sum(), model.n_free)
    np.testing.assert_allclose(gg, g[rows])


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("cell", ["tetra", "hexahedron", "triangle", "quad"])
def test_contact_facets_cover_the_boundary_with_outward_normals(cell, element):
    if cell in ("tetra", "hexahedron"):
        body = cube([0.0, 0.0, 0.0], [1.0, 2.0, 0.5], (2, 2, 1), cell=cell, element=element)
        area = 2 * (1.0 * 2.0 + 1.0 * 0.5 + 2.0 * 0.5)
    else:
        body = square([0.0, 0.0], [1.0, 2.0], (2, 3), cell=cell, element=element)
        area = 2 * (1.0 + 2.0)
    facets = body.contact_facets()
    x = body.X[facets]
    dist, g = closest_facet_distance(np.repeat(body.X.mean(0)[None], len(x), 0), x)
    assert np.all(g < 0)  # the centre lies inside every facet's half space
    if body.dim == 2:
        measure = np.linalg.norm(x[:, 1] - x[:, 0], axis=1)
    else:
        measure = 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
    assert measure.sum() == pytest.approx(area, rel=1e-12)
    assert np.all(measure > 0)
    used = np.unique(facets)
    np.testing.assert_array_equal(used, body.boundary_nodes())


def test_pair_rejects_bad_input():
    slave, master = bodies_2d()
    ball = cube([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 1)
    with pytest.raises(InputError, match="itself"):
        NodeSurfaceContact(slave, slave)
    with pytest.raises(InputError, match="2D or both 3D"):
        NodeSurfaceContact(slave, ball)
    with pytest.raises(InputError, match="margin"):
        NodeSurfaceContact(slave, master, margin=0.0)
    with pytest.raises(InputError, match="restitution"):
        Contact(slave, master, restitution=1.5)
    with pytest.raises(InputError):
        Contact(slave, master, nodes=[10**6], method="node-to-surface")
    # the default between two solids is a mortar interface of the whole boundaries
    with pytest.raises(InputError, match="method='node-to-surface'"):
        Contact(slave, master, nodes=[0])
    bar = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 2, Material(1e9, rho=1e3), Section(1e-4, 1e-9))
    # a solid against a beam is the beam's two-sided surface; given the other way round, or
    # in 3D, it is refused
    assert isinstance(Contact(slave, bar, clearance=0.01), PointBeamContact)
    with pytest.raises(InputError, match="Contact\\(solid, beam"):
        Contact(bar, slave)
    with pytest.raises(InputError, match="2D bodies only"):
        Contact(ball, bar)


def test_nonlinear_solids_use_the_same_pairs():
    a = Solid.disk([0.0, 0.0], 1.0, 1, NeoHookean(E=1e6, nu=0.3, rho=1e3))
    b = Solid.disk([2.01, 0.0], 1.0, 1, NeoHookean(E=1e6, nu=0.3, rho=1e3))
    pair = Contact(a, b, method="node-to-surface")
    assert isinstance(pair, NodeSurfaceContact) and pair.obstacle is None and pair.body is a
    assert not pair.linear and pair.restitution == 0.0
    mortar = Contact(a, b)  # the default between two solids
    assert isinstance(mortar, MortarContact) and mortar.body is a and not mortar.linear


# -- bar ends --------------------------------------------------------------------------------


def bars(gap=0.0):
    mat, sec = Material(1.0, rho=1.0), Section(1.0, 1.0 / 12.0)
    a = Beam2D.straight([-1.0 - gap, 0.0], [-gap, 0.0], 4, mat, sec)
    b = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 4, mat, sec)
    return a, b


def test_bar_end_pair_is_linear_along_the_axis():
    a, b = bars(gap=0.1)
    pair = Contact(a, b, restitution=0.5)
    assert isinstance(pair, NodeNodeContact) and pair.linear and pair.size == 1
    assert pair.nodes == (4, 0)
    np.testing.assert_allclose(pair.axis, [1.0, 0.0])
    model = Model([a, b], [pair], gravity=(0.0, 0.0))
    q = RNG.normal(size=model.n)
    g, dofs, G, H = pair.evaluate(q)
    xa = a.X[4] + q[12:14]
    xb = b.X[0] + q[a.ndof : a.ndof + 2]
    assert g[0] == pytest.approx(xb[0] - xa[0])
    np.testing.assert_array_equal(dofs[0], [12, 13, a.ndof, a.ndof + 1])
    np.testing.assert_allclose(G[0], [-1.0, 0.0, 1.0, 0.0])
    assert H is None and pair.restitution == 0.5
    # the reversed pair: b's first node against a's last, axis −x
    back = Contact(b, a)
    assert back.nodes == (0, 4)
    np.testing.assert_allclose(back.axis, [-1.0, 0.0])


def test_bar_end_pair_input_rules():
    a, b = bars()
    with pytest.raises(InputError, match="end nodes"):
        Contact(a, b, nodes=(2, 0))
    with pytest.raises(InputError, match="pair"):
        Contact(a, b, nodes=(4, 0, 1))
    with pytest.raises(InputError, match="itself"):
        NodeNodeContact(a, a)
    with pytest.raises(InputError, match="axis"):
        NodeNodeContact(a, b, nodes=(4, 0), axis=(0.0, 0.0))
    pair = NodeNodeContact(a, b, nodes=(4, 0), axis=(2.0, 0.0))
    np.testing.assert_allclose(pair.axis, [1.0, 0.0])


@pytest.mark.parametrize("name, make", CONFIGURATIONS, ids=[c[0] for c in CONFIGURATIONS])
def test_kept_search_misses_no_facet_as_the_bodies_move(name, make):
    """The candidate pairs of a search are reused while the nodes move less than their
    slack: a walk of small steps (each reusing or renewing the search) and the gaps-only
    path must both agree with a search over every facet at every step."""
    slave, master = make()
    pair = bound_pair(slave, master, nodes=None)
    n = slave.ndof + master.ndof
    q = np.zeros(n)
    rng = np.random.default_rng(11)
    for _ in range(30):
        q = q + 0.004 * rng.normal(size=n)
        exact = brute_force_gaps(pair, q)
        # the plane gap of the two paths differs by round-off of the facet's coordinates
        np.testing.assert_allclose(closest_gaps(pair, q), exact, atol=1e-14)
        np.testing.assert_allclose(pair.gaps(q), pair.evaluate(q)[0], atol=1e-14)
