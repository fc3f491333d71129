"""A 2D solid's nodes against the exact outline of a planar rigid body (a Disk or a Polygon):
rows by central differences, and a rigid disk striking an elastic block
(fecontact.contact.solid_rigid2d)."""

import warnings

import numpy as np
import pytest
import skfem

from fecontact import Contact, IntegratorOptions, Model, Simulation, run
from fecontact.bodies import LinearElastic, NeoHookean, RigidBody2D, Solid
from fecontact.bodies.rigid import Disk, Polygon
from fecontact.contact.solid_rigid2d import NodeDiskContact, NodePolygonContact
from fecontact.errors import InputError
from fecontact.ledger import CREATED
from fecontact.scenes import wave_step
from fecontact.time.simulate import simulate

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
R = 0.03
DISK = Disk(R)


def block():
    """A 0.2 m x 0.05 m block, top face at y = 0 (P1 triangles, 5 mm cells)."""
    return Solid.rectangle([-0.1, -0.05], [0.1, 0.0], (40, 10), RUBBER)


@pytest.mark.parametrize("shape", [Disk(R), Polygon.regular(5, 0.04), Polygon.box(0.06, 0.03)])
def test_node_rows_are_the_derivatives_of_the_gaps(shape):
    """G against central differences (step 1e-6) of the gaps along every dof of the nodes
    and of the body (x, y, θ), and ∇²g against those of G, at a random pose that sinks the
    shape into the block (nodes inside, near the edges and near the vertices). Bounds: the
    differences' truncation h² g''' ~ 1e-12/1e-2 m and their round-off 1e-16 m/1e-6 = 1e-10:
    1e-8 on G, 1e-6 on ∇²g (one more difference of G)."""
    solid = block()
    rigid = RigidBody2D.uniform(1.0, [0.004, 0.02], shape, angle=0.3)
    pair = Contact(solid, rigid)
    assert isinstance(pair, NodeDiskContact if isinstance(shape, Disk) else NodePolygonContact)
    model = Model([solid, rigid], [pair], gravity=(0.0, 0.0))
    rng = np.random.default_rng(7)
    q = 1e-3 * rng.normal(size=model.n)
    q[-3:] = [0.003, -0.012, 0.4]
    g, dofs, G, H = pair.evaluate(q)
    assert (g < 0).any()  # the shape has entered the block
    np.testing.assert_array_equal(g, pair.gaps(q))
    for j in np.unique(dofs):
        d = np.zeros(model.n)
        d[j] = 1e-6
        gp, _, Gp, _ = pair.evaluate(q + d)
        gm, _, Gm, _ = pair.evaluate(q - d)
        col = (dofs == j).astype(float)
        np.testing.assert_allclose((gp - gm) / 2e-6, np.sum(G * col, axis=1), atol=1e-8)
        np.testing.assert_allclose((Gp - Gm) / 2e-6, np.einsum("mkl,ml->mk", H, col), atol=1e-6)


@pytest.mark.parametrize("shape", [Polygon.regular(5, 0.04), Polygon.box(0.06, 0.03)])
@pytest.mark.parametrize("seed", [2, 3])
def test_vertex_rows_are_the_derivatives_of_their_gaps(shape, seed):
    """The polygon's vertex rows (the signed distance to the solid's boundary): G and
    ∇²g against central differences (step 1e-7, no segment switches within it) at random
    poses with vertices inside the block and outside. Bounds: the truncation, h² times the
    third derivative ~ w²/L⁴, is 1e-7 for a vertex 4 cm from a 5 mm segment (measured: the
    error falls as h²), the round-off 1e-16/1e-7 = 1e-9: 1e-8 on G, 1e-6 on ∇²g."""
    rows, q, _ = companion_rows_at_a_random_pose(shape, seed, angle=0.3)
    np.testing.assert_allclose(rows.evaluate(q)[0], rows.gaps(q), rtol=0, atol=1e-17)
    assert_rows_are_the_derivatives(rows, q)


def companion_rows_at_a_random_pose(shape, seed, angle=0.0):
    """The companion rows of ``shape`` (a rigid body 4 mm off the block's middle) against
    the block, and a random pose q with some rows closed and some open: (rows, q, rng)."""
    solid = block()
    rigid = RigidBody2D.uniform(1.0, [0.004, 0.02], shape, angle=angle)
    pair = Contact(solid, rigid)
    (rows,) = pair.companions
    Model([solid, rigid], [pair], gravity=(0.0, 0.0))
    rng = np.random.default_rng(seed)
    q = 1e-4 * rng.normal(size=solid.ndof + 3)
    q[-3:] = [0.003, -0.012, 0.4] + 1e-3 * rng.normal(size=3)
    g = rows.evaluate(q)[0]
    assert (g < 0).any() and (g > 0).any()
    return rows, q, rng


def assert_rows_are_the_derivatives(rows, q):
    """G and ∇²g of ``rows`` against central differences of step 1e-7 (bounds in the
    callers' docstrings: 1e-8 on G, 1e-6 on ∇²g), the rows' dofs unchanged by the step."""
    g, dofs, G, H = rows.evaluate(q)
    for j in np.unique(dofs):
        d = np.zeros(q.size)
        d[j] = 1e-7
        gp, dp, Gp, _ = rows.evaluate(q + d)
        gm, dm, Gm, _ = rows.evaluate(q - d)
        assert (dp == dofs).all() and (dm == dofs).all()
        col = (dofs == j).astype(float)
        np.testing.assert_allclose((gp - gm) / 2e-7, np.sum(G * col, axis=1), atol=1e-8)
        np.testing.assert_allclose((Gp - Gm) / 2e-7, np.einsum("mkl,ml->mk", H, col), atol=1e-6)


def vertex_rows(solid, points):
    """The vertex rows of a rigid triangle with its vertices at ``points`` (3, 2) (m, the body
    unturned at their centroid) against ``solid``: (rows, n)."""
    points = np.asarray(points, float)
    centre = points.mean(axis=0)  # a triangle's centroid
    rigid = RigidBody2D.uniform(1.0, centre, Polygon(points - centre))
    pair = Contact(solid, rigid)
    Model([solid, rigid], [pair], gravity=(0.0, 0.0))
    return pair.companions[0], solid.ndof + 3


def l_shape():
    """The 2 cm L (the square [−1, 1]² cm without its quarter x, y > 0), refined to 2.5 mm
    cells: a concave corner of the boundary at the origin."""
    mesh = skfem.MeshTri.init_lshaped().scaled(0.01).refined(2)
    return Solid(mesh, RUBBER)


def test_vertex_rows_read_the_distance_to_the_boundary():
    """A vertex row's gap is the vertex's signed distance to the solid's boundary: to the
    block's corner node where its projection falls beyond the top face (the far corners of a
    1 m lid resting on the 0.2 m block, 0.4 m off, and a vertex 0.1 m above and 0.3 m
    beside the block), to the face under a vertex 2 cm deep, four segments' length; and in
    the L, to its concave corner node from inside (5 mm: closer than the sides' lines, 3
    and 4 mm), to the faces at the notch from outside and from inside. Exact up to the
    round-off of the coordinates (1e-16 m)."""
    solid = block()
    lid, n = vertex_rows(solid, [[-0.5, 0.0], [0.5, 0.0], [0.0, 0.1]])
    g = lid.gaps(np.zeros(n))
    np.testing.assert_allclose(g, [0.4, 0.4, 0.1], rtol=0, atol=1e-16)
    rows, n = vertex_rows(solid, [[0.0012, -0.02], [0.4, 0.1], [0.5, 0.2]])
    expected = [-0.02, np.hypot(0.3, 0.1), np.hypot(0.4, 0.2)]
    np.testing.assert_allclose(rows.gaps(np.zeros(n)), expected, rtol=0, atol=1e-16)
    rows, n = vertex_rows(l_shape(), [[-0.003, -0.004], [0.004, 0.003], [-0.002, 0.004]])
    np.testing.assert_allclose(rows.gaps(np.zeros(n)), [-0.005, 0.003, -0.002], atol=1e-16)


def assert_vertex_derivatives(rows, q, n, h, bounds):
    """G and ∇²g of ``rows`` at q against central differences (step h) along every dof of
    the rows, within ``bounds`` (on G, on ∇²g); no row changes its segment within ± h."""
    g, dofs, G, H = rows.evaluate(q)
    np.testing.assert_allclose(g, rows.gaps(q), rtol=0, atol=1e-17)
    for j in np.unique(dofs):
        d = np.zeros(n)
        d[j] = h
        gp, dp, Gp, _ = rows.evaluate(q + d)
        gm, dm, Gm, _ = rows.evaluate(q - d)
        assert (dp == dofs).all() and (dm == dofs).all()
        col = (dofs == j).astype(float)
        np.testing.assert_allclose((gp - gm) / (2 * h), np.sum(G * col, axis=1), atol=bounds[0])
        hd = np.einsum("mkl,ml->mk", H, col)
        np.testing.assert_allclose((Gp - Gm) / (2 * h), hd, atol=bounds[1])
    return g


@pytest.mark.parametrize("seed", [2, 3, 4])
def test_vertex_rows_near_an_end_node_are_the_derivatives_of_their_gaps(seed):
    """Vertices whose closest boundary point is an end node, 1 to 2 mm from it: outside the
    block's corner, inside the L's concave corner (the node branch, g = ±|p − x_e|), with
    the others on faces, at random poses of the nodes and the body (1e-4 m, rad). Bounds:
    the truncation h² g''' ~ h²/r² = 1e-8 on G and h² G''' ~ h²/r³ = 1e-5 m⁻¹ on ∇²g
    (measured 8e-10 and 1.3e-6, a hundred times those at h = 1e-6: the truncation), the
    round-off 1e-16/1e-7: 1e-8 on G, 1e-5 on ∇²g (whose entries are 1/r ~ 1e3 m⁻¹)."""
    rng = np.random.default_rng(seed)
    cases = [
        (block(), [[-0.1012, 0.0009], [-0.095, -0.004], [-0.09, 0.002]], 1.0),
        (l_shape(), [[-0.0011, -0.0013], [0.002, 0.005], [-0.003, 0.004]], -1.0),
    ]
    for solid, points, side in cases:
        rows, n = vertex_rows(solid, points)
        q = 1e-4 * rng.normal(size=n)
        g = assert_vertex_derivatives(rows, q, n, 1e-7, (1e-8, 1e-5))
        assert np.sign(g[0]) == side


def test_the_pair_is_named_either_way_and_checks_its_solid():
    solid = block()
    disk = RigidBody2D.uniform(1.0, [0.0, 0.05], Disk(R))
    pair = Contact(disk, solid, nodes=[0, 1])
    assert isinstance(pair, NodeDiskContact) and pair.size == 2
    assert Contact(solid, disk).size == len(solid.boundary_nodes())
    with pytest.raises(InputError, match="2D Solid"):
        Contact(Solid.box([0, 0, 0], [1, 1, 1], 1, RUBBER), disk)


def disk_on_block(tmp_path, free: bool, p=1.0, k=1.0, shape=DISK, angle=0.0):
    """A rigid disk (or ``shape``, mass 0.5 kg) 1 mm over the block's top at 1 m/s down, over
    8 ms at the step Δx/c (the impact, its rebound and the flight after it); the block's
    bottom held (``free`` False, gravity) or both bodies free in no gravity. Returns the
    summary, the model and the simulation (run into ``tmp_path``)."""
    solid = block()
    if not free:
        solid.fix(np.flatnonzero(np.isclose(solid.positions(np.zeros(solid.ndof))[:, 1], -0.05)))
    c, s = np.cos(angle), np.sin(angle)
    lift = R if isinstance(shape, Disk) else -(shape.vertices @ [s, c]).min()
    disk = RigidBody2D.uniform(0.5, [0.0127, lift + 0.001], shape, angle)
    gravity = (0.0, 0.0) if free else (0.0, -9.81)
    model = Model([solid, disk], [Contact(solid, disk)], gravity)
    v0 = np.zeros(model.n)
    v0[-3:] = [0.0, -1.0, 0.0]
    sim = Simulation(
        model,
        dt=wave_step(solid, 1.0, None),
        t_end=0.008,
        v0=v0,
        options=IntegratorOptions(penalty_scale=p, multiplier_scale=k),
        name="disk",
    )
    with warnings.catch_warnings():  # (energy warnings are also in the summary, tested)
        warnings.simplefilter("ignore", UserWarning)
        summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    return summary, model, sim


def test_a_free_disk_and_block_keep_their_momentum_through_the_impact(tmp_path):
    """No gravity, both bodies free: the total momentum (0, −0.5) N·s is kept at every step
    to the solvers' round-off (6.4e-13 N·s measured; bound 1e-10 of m v, the 3D pair's);
    the disk rebounds, no node enters it beyond the gap tolerance (1e-9 m), and the ledger
    creates nothing (measured 0 J; bound its warning level, 1e-3 of the scale)."""
    summary, model, sim = disk_on_block(tmp_path, free=True)
    assert summary["status"] == "completed" and not summary["warnings"]
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= CREATED * ledger["scale"]
    gmin = np.inf
    for st in simulate(model, sim.dt, sim.t_end, sim.options, v0=sim.v0):
        gmin = min(gmin, float(np.min(st.gaps)))
        mv = model.M_full @ st.v
        momentum = mv[:-3].reshape(-1, 2).sum(axis=0) + mv[-3:-1]
        np.testing.assert_allclose(momentum, [0.0, -0.5], atol=1e-10 * 0.5)
    assert gmin >= -1e-9
    assert st.v[-2] > 0.3  # rebounded (0.399 m/s measured)


def test_a_vertex_between_two_nodes_is_measured_by_the_watch():
    """A square turned 45° with its lowest vertex 0.1 mm below the block's top, midway
    between two nodes 5 mm apart: no node row is closed (the nearest nodes are 1.7 mm from
    its faces), and the pair's watch reads the vertex 0.1 mm deep, 0.02 of the segment, to
    round-off of the coordinates (1e-15 m)."""
    solid = block()
    a = 0.02 / np.sqrt(2.0)  # the half diagonal of a 2 cm square
    rigid = RigidBody2D.uniform(1.0, [0.0025, a - 1e-4], Polygon.box(0.02, 0.02), np.pi / 4)
    pair = Contact(solid, rigid)
    model = Model([solid, rigid], [pair], gravity=(0.0, 0.0))
    q = np.zeros(model.n)
    assert pair.gaps(q).min() > 1.5e-3
    depth, ratio = pair.watch().depth(q)
    assert depth == pytest.approx(1e-4, abs=1e-15)
    assert ratio == pytest.approx(1e-4 / 0.005, abs=1e-12)


def coarse_block():
    """A 0.2 m x 0.05 m Neo-Hookean block of 16 x 4 cells (12.5 mm boundary edges), top face
    at y = 0, held at its bottom."""
    solid = Solid.rectangle([-0.1, -0.05], [0.1, 0.0], (16, 4), NeoHookean(1e7, 0.3, 1000.0))
    solid.fix(np.flatnonzero(np.isclose(solid.X[:, 1], -0.05)))
    return solid


@pytest.mark.parametrize("seed", [2, 3])
def test_disk_segment_rows_are_the_derivatives_of_their_gaps(seed):
    """The disk's segment rows (fecontact.contact.disk_segments): G and ∇²g against central
    differences (step 1e-7) of the gaps at random poses sinking the disk into the block,
    and the slip rows as the first-order part of the exact slip over a small step (its error
    falls with the step's square). Bounds as for the vertex rows: the truncation h² times
    the third derivative ~ 1e-14/1e-3 and the round-off 1e-16/1e-7 = 1e-9: 1e-8 on G, 1e-6
    on ∇²g."""
    rows, q, rng = companion_rows_at_a_random_pose(DISK, seed)
    np.testing.assert_array_equal(rows.evaluate(q)[0], rows.gaps(q))
    assert_rows_are_the_derivatives(rows, q)
    tdofs, GT, T = rows.tangents(q)
    dq = rng.normal(size=q.size)
    errors = [
        np.abs(rows.slips(q + h * dq, q, T) - np.einsum("mtk,mk->mt", GT, h * dq[tdofs])).max()
        for h in (1e-6, 1e-7)
    ]
    assert errors[1] <= 0.02 * errors[0]  # second order (0.01, measured); first order: 0.1


def test_the_watch_reads_a_disk_between_two_nodes():
    """A 3 cm disk through the top nodes at x = 0 and 12.5 mm (the node rows closed, g = 0):
    its arc lies through the chord between them by the sagitta r − √(r² − L²/4) = 0.655 mm,
    L²/8r to 1 %, which the pair's watch reads (to the coordinates' round-off, 1e-15 m), and
    which the segment's row reads as its gap (P1 cells; on P2 cells the watch alone)."""
    solid, edge = coarse_block(), 0.0125
    rigid = RigidBody2D.uniform(0.5, [edge / 2, np.sqrt(R**2 - (edge / 2) ** 2)], DISK)
    pair = Contact(solid, rigid)
    Model([solid, rigid], [pair], gravity=(0.0, 0.0))
    q = np.zeros(solid.ndof + 3)
    sagitta = R - np.sqrt(R**2 - edge**2 / 4)
    assert abs(pair.gaps(q)).min() < 1e-15
    depth, ratio = pair.watch().depth(q)
    assert depth == pytest.approx(sagitta, abs=1e-15)
    assert ratio == pytest.approx(sagitta / edge, abs=1e-13)
    (rows,) = pair.companions
    assert rows.gaps(q).min() == pytest.approx(-sagitta, abs=1e-15)
    # a P2 boundary is curved, its chords not its surface: no segment rows, the watch alone
    curved = Solid.rectangle([-0.1, -0.05], [0.1, 0.0], (16, 4), RUBBER, element="P2")
    assert Contact(curved, rigid).companions == () and Contact(curved, rigid).watch()


@pytest.mark.parametrize("x0, v, mu", [(0.00625, 0.0, 0.0), (0.00625, 10.0, 0.0), (0.0, 1.0, 0.0),
                                       (0.00625 + 0.4 * R, 3.0, 0.3)])  # fmt: skip
def test_a_disk_stays_out_of_the_chords(tmp_path, x0, v, mu):
    """A 3 cm disk (0.5 kg) on the coarse block under gravity for 5 ms: set down on the chord
    between two top nodes, dropped at 10 m/s there (1 mm over it), at 1 m/s over a node, and
    at 3 m/s with μ = 0.3 0.4 r beside the chord's middle. Without the segments' rows the
    arc went through the chords by 0.12 mm (falling through it, g t²/2), 0.69 mm, 2.5 µm and
    0.66 mm, unreported. The run's measure (the watch: the disk's depth into the boundary
    polygon) stays within the gap tolerance (1e-9 m; measured ≤ 7.2e-14 m), nothing is
    warned, and the ledger creates nothing beyond its warning level (1e-3 of the scale;
    measured ≤ 2e-8 of it)."""
    solid = coarse_block()
    rigid = RigidBody2D.uniform(0.5, [x0, R + (0.001 if v else 0.0)], DISK)
    model = Model([solid, rigid], [Contact(solid, rigid, friction=mu)], (0.0, -9.81))
    v0 = np.zeros(model.n)
    v0[-2] = -v
    sim = Simulation(model, dt=wave_step(solid, 1.0, None), t_end=0.005, v0=v0, name="chord")
    with warnings.catch_warnings():  # (warnings are also in the summary, tested)
        warnings.simplefilter("ignore", UserWarning)
        summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed" and not summary["warnings"]
    assert summary["max_penetration"] <= 1e-9
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= CREATED * ledger["scale"]


@pytest.mark.parametrize(
    "shape, angle",
    [(DISK, 0.0), (Polygon.box(0.06, 0.02), 0.0), (Polygon.box(0.04, 0.04), np.pi / 4),
     (Polygon.regular(3, 0.03), 0.3)],
)  # fmt: skip
def test_a_body_dropped_on_a_held_block_neither_penetrates_nor_gains(tmp_path, shape, angle):
    """Under gravity on the block held at its bottom (a disk, a box flat, a square corner
    first, a tilted triangle): the run completes, the deepest node and the deepest vertex
    (the watch, over its segment) stay within the gap tolerance (1e-9 m; measured ≤ 1e-13 m
    and ≤ 2e-11 of a segment; before the vertex rows the flat box's corners ended 57 µm, 1.1 %
    of a segment, inside), the ledger's created energy stays below its warning level (1e-3
    of the scale; measured ≤ 1e-8 of it, the block's round-off) and the run ends below its
    initial energy."""
    summary, model, _ = disk_on_block(tmp_path, free=False, shape=shape, angle=angle)
    assert summary["status"] == "completed" and not summary["warnings"]
    assert summary["max_penetration"] <= 1e-9
    assert summary["mortar_depth"] <= 1e-9 / 0.005
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= CREATED * ledger["scale"]
    assert summary["energy_final"] < summary["energy_initial"]


def test_the_impact_is_independent_of_p_and_k(tmp_path):
    """The multipliers' scalings (p x1000, k /100) change the iterations, not the answer: the
    final configuration agrees to the solvers' tolerance on positions, 1e-12 of the disk's
    1.1 mm travel after the impact (measured: 0 and 2e-19 m)."""
    finals = []
    for p, k in ((1.0, 1.0), (1000.0, 1.0), (1.0, 0.01)):
        _, model, sim = disk_on_block(tmp_path / f"{p}-{k}", free=False, p=p, k=k)
        *_, st = simulate(model, sim.dt, sim.t_end, sim.options, v0=sim.v0)
        finals.append(st.q)
    scale = np.abs(finals[0]).max()
    for q in finals[1:]:
        assert np.abs(q - finals[0]).max() <= 1e-12 * scale
