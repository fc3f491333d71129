"""Node-to-surface rows at a concave feature of the master (``contact.concave_rows``): a
node over a dented vertex of a slab gets one row per facet around the vertex, a flat or
bumped surface none; the rows keep their facets as the node slides across the vertex;
their gradients and Hessians are exact; redundant rows take minimum-norm multipliers; the
rows are held through the iterates of a Newton loop, so that two Neo-Hookean balls meeting
off-centre with friction correct their positions without a step halved."""

import dataclasses

import numpy as np
import pytest
import skfem

from fecontact import Contact, Model, Simulation
from fecontact.bodies.materials import LinearElastic, NeoHookean
from fecontact.bodies.meshes import graded_ball_mesh
from fecontact.bodies.solid import Solid
from fecontact.contact.body_pairs import NodeSurfaceContact
from fecontact.contact.contact_set import rows_held
from fecontact.contact.laws import kkt_multipliers
from fecontact.contact.stats import ContactStats
from fecontact.scenes import wave_step
from fecontact.testing import trace

MAT = LinearElastic(E=1e7, nu=0.3, rho=1e3)


def slab_and_probe():
    """A 1 × 1 × 0.25 slab (4 × 4 × 1 cells, top at z = 0) and a one-tetrahedron probe whose
    node 0 is the slave node, and their model."""
    slab = Solid.box([-0.5, -0.5, -0.25], [0.5, 0.5, 0.0], (4, 4, 1), MAT)
    tet = skfem.MeshTet(
        np.array([[0.0, 0.01, 0.0, 0.0], [0.0, 0.0, 0.01, 0.0], [0.0, 0.0, 0.0, 0.01]]),
        np.array([[0], [1], [2], [3]]),
    )
    probe = Solid(tet, MAT)
    pair = NodeSurfaceContact(probe, slab, nodes=[0], margin=0.1)
    model = Model([probe, slab], [pair], gravity=np.zeros(3))
    centre = int(np.argmin(np.linalg.norm(slab.X - [0.0, 0.0, 0.0], axis=1)))
    return probe, slab, pair, centre, model


def state(probe, slab, node_at, centre, dz):
    """q with the probe's node 0 at ``node_at`` and the slab's centre vertex moved by dz."""
    q = np.zeros(probe.ndof + slab.ndof)
    q[probe.node_translation_dofs([0])[0]] = node_at - probe.X[0]
    q[probe.ndof + slab.node_translation_dofs([centre])[0][2]] = dz
    return q


def rows_of(pair, q):
    g = pair.evaluate(q)[0]
    finite = np.flatnonzero(np.isfinite(g))
    return finite, pair.selected[finite], g[finite]


def around(pair, centre):
    """The slab's boundary facets that have the centre vertex."""
    return set(np.flatnonzero(np.any(pair.facets == centre, axis=1)).tolist())


def test_flat_and_bumped_surfaces_add_no_row():
    probe, slab, pair, centre, _ = slab_and_probe()
    for dz in (0.0, 1e-3):  # flat, and the vertex raised: a convex bump
        rows, _, _ = rows_of(pair, state(probe, slab, [0.01, 0.004, 0.002], centre, dz))
        assert rows.tolist() == [0]


def test_a_dented_vertex_gives_a_row_per_facet_around_it():
    probe, slab, pair, centre, _ = slab_and_probe()
    q = state(probe, slab, [0.002, 0.001, -0.004], centre, -0.005)
    rows, facets, g = rows_of(pair, q)
    assert set(facets.tolist()) == around(pair, centre) and len(rows) == len(facets) > 1
    # the node is above every facet of the dent: each plane gap is positive and, since the
    # planes lie under the surface of the cone, at most the node's distance to its facet
    assert np.all(g > 0.0)


def test_rows_keep_their_facets_as_the_node_slides_across_the_vertex():
    probe, slab, pair, centre, _ = slab_and_probe()
    layouts = set()
    for x in np.linspace(-0.003, 0.003, 13):
        q = state(probe, slab, [x, 0.4 * x + 1e-4, -0.004], centre, -0.005)
        rows, facets, _ = rows_of(pair, q)
        layouts.add(tuple(zip(rows.tolist(), facets.tolist(), strict=True)))
    assert len(layouts) == 1


def test_rows_gradients_and_hessians_match_central_differences():
    probe, slab, pair, centre, _ = slab_and_probe()
    q0 = state(probe, slab, [0.002, 0.001, -0.004], centre, -0.005)
    rows, facets, _ = rows_of(pair, q0)
    _, dofs, G, _ = pair.evaluate(q0)
    H = pair.hessians(q0, rows)
    eps = 1e-7  # central differences: truncation eps² |g'''| against round-off 1e-16/eps
    for r, row in enumerate(rows):
        d = dofs[row]
        num = np.empty(len(d))
        num_G = np.empty((len(d), len(d)))
        for i, dof in enumerate(d):
            qp, qm = q0.copy(), q0.copy()
            qp[dof] += eps
            qm[dof] -= eps
            gp, _, Gp, _ = pair.evaluate(qp)
            gm, _, Gm, _ = pair.evaluate(qm)
            assert pair.selected[row] == facets[r]  # (the same facet in its row)
            num[i] = (gp[row] - gm[row]) / (2 * eps)
            num_G[i] = (Gp[row] - Gm[row]) / (2 * eps)
        assert np.max(np.abs(num - G[row])) <= 1e-7 * np.max(np.abs(G[row]))
        assert np.max(np.abs(num_G - H[r])) <= 1e-5 * np.max(np.abs(H[r]))


def test_redundant_rows_take_minimum_norm_multipliers():
    # three copies of one row (planes meeting along one line): the multipliers share the
    # force equally, and the least-squares solution is counted
    rng = np.random.default_rng(3)
    row = rng.normal(size=6)
    GA = np.vstack([row, row, row + 1e-13 * rng.normal(size=6)])
    Y = GA.T.copy()  # H = I
    stats = ContactStats(minimum_norm=True)  # (a run with concave rows)
    mu = kkt_multipliers(GA, Y, np.full(3, 2.0), 1.0, stats)
    assert mu == pytest.approx(np.full(3, 2.0 / (3.0 * row @ row)), rel=1e-9)
    assert stats.least_squares == 1
    # independent rows: the LU's answer, not counted
    GB = rng.normal(size=(3, 6))
    mu = kkt_multipliers(GB, GB.T.copy(), np.ones(3), 1.0, stats)
    np.testing.assert_allclose(GB @ GB.T @ mu, np.ones(3), rtol=1e-12)
    assert stats.least_squares == 1


def test_rows_are_held_from_one_configuration_through_the_iterates():
    # a Newton loop's iterate that flattens the dent keeps the rows of the configuration
    # the loop started from, each with its facet (the plane gaps are the iterate's); rows a
    # node gains at an iterate (the loop dents the flat surface) stay to the loop's end,
    # its closest facet on its first row
    probe, slab, pair, centre, model = slab_and_probe()
    node = [0.002, 0.001, -0.004]
    dented, flat = (state(probe, slab, node, centre, dz) for dz in (-0.005, 0.0))
    start = rows_of(pair, dented)
    assert len(start[0]) > 1 and rows_of(pair, flat)[0].tolist() == [0]
    with rows_held(model.contacts, dented):
        rows, facets, g = rows_of(pair, flat)
        assert rows.tolist() == start[0].tolist() and facets.tolist() == start[1].tolist()
        assert np.all(g < start[2])  # the vertex moved up by 5 mm under the node
    assert rows_of(pair, flat)[0].tolist() == [0]  # released: decided at each evaluation
    with rows_held(model.contacts, flat):
        rows, facets, _ = rows_of(pair, dented)
        assert set(facets.tolist()) == set(start[1].tolist())
        assert facets[rows == 0][0] == pair.closest[0]
        kept = rows_of(pair, flat)
        assert kept[0].tolist() == rows.tolist() and kept[1].tolist() == facets.tolist()
    assert rows_of(pair, dented)[0].tolist() == start[0].tolist()


def test_a_node_shares_its_rows_point():
    # the rows i + j n of node i hold one point: a node closed at t_n slips on each
    pair = slab_and_probe()[2]
    assert pair.shared_points and np.all(pair.points() == 0)


def off_centre_balls(t_end: float) -> Simulation:
    """Two Neo-Hookean balls (R = 5 cm, E = 10 MPa, graded P1 meshes, 0.16 R at the contact,
    the right one turned 30° about the line of centres and moved sideways by 0.3 R) meeting
    at 1 m/s each, node-to-surface both ways with μ = 0.3, at the step Δx/c."""
    R, b, gap = 0.05, 0.3, 0.001
    dx = np.sqrt((2 * R + gap) ** 2 - (b * R) ** 2)
    cl, cr = np.array([-0.5 * dx, 0.0, 0.0]), np.array([0.5 * dx, b * R, 0.0])
    n = np.array([np.sqrt(4 * R**2 - (b * R) ** 2), b * R, 0.0]) / (2 * R)
    ml = graded_ball_mesh(cl, R, 0.16 * R, cl + R * n, 0.5, 2)
    mr = graded_ball_mesh(cr, R, 0.16 * R, cr - R * n, 0.5, 2)
    K = np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])
    turn = np.eye(3) + np.sin(np.pi / 6) * K + (1.0 - np.cos(np.pi / 6)) * K @ K
    mr = dataclasses.replace(mr, doflocs=cr[:, None] + turn @ (mr.doflocs - cr[:, None]))
    rubber = NeoHookean(1e7, 0.3, 1000.0)
    left, right = Solid(ml, rubber), Solid(mr, rubber)
    pairs = [
        Contact(a, c, friction=0.3, method="node-to-surface")
        for a, c in ((left, right), (right, left))
    ]
    model = Model([left, right], pairs, gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(left, (1.0, 0.0, 0.0)) + model.translation(right, (-1.0, 0.0, 0.0))
    dt = min(wave_step(left, 1.0), wave_step(right, 1.0))
    return Simulation(model, dt=dt, t_end=t_end, v0=v0, output_interval=t_end)


def test_off_centre_frictional_balls_correct_without_halving():
    # at 1.23 and 1.26 ms a node of each ball faces the other's vertex, whose dent reads
    # concave at one iterate of the frictional position correction and convex at the next:
    # with the rows decided at each iterate the correction cycled between two updates
    # (5.5e-5 m, 1.5e-6 m) and both steps were halved
    run = trace(off_centre_balls(1.3e-3))
    assert run["status"] == "completed"
    assert run["halvings"].sum() == 0
    assert np.min(run["min_gap"]) >= -1e-12  # (the gap tolerance, 1e-12 of the size)
