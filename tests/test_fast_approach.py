"""Two elastic disks thrown at each other faster than the contact search used to look ahead:
every run completes, no node ends a step inside the other disk, and the energy is accounted
for. The penetration is measured here by a ray-crossing test on the disks' boundary polygons,
independent of the solver's gaps and of its inside/outside test."""

import numpy as np
import pytest

from fecontact.scenes import wave_step
from fecontact.testing import case
from fecontact.time import simulate


def crossing_inside(points, a, b):
    """Whether each point lies inside the polygon of segments (a, b): the parity of the
    crossings of a ray from the point along +x."""
    x, y = points[:, None, 0], points[:, None, 1]
    straddle = (a[None, :, 1] > y) != (b[None, :, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (y - a[None, :, 1]) / (b[None, :, 1] - a[None, :, 1])
    x_cross = a[None, :, 0] + t * (b[None, :, 0] - a[None, :, 0])
    return np.sum(straddle & (x_cross > x), axis=1) % 2 == 1


def depth_over_edge(points, a, b):
    """Depth of each point inside the polygon (0 outside) over the length of the boundary
    edge closest to it."""
    d, w = b - a, points[:, None, :] - a[None]
    xi = np.clip(np.einsum("pei,ei->pe", w, d) / np.sum(d * d, axis=1), 0.0, 1.0)
    dist = np.linalg.norm(w - xi[:, :, None] * d[None], axis=2)
    e = np.argmin(dist, axis=1)
    depth = np.where(crossing_inside(points, a, b), dist[np.arange(len(points)), e], 0.0)
    return depth / np.linalg.norm(d[e], axis=1)


def worst_penetration(model, q):
    """The deepest boundary node of either disk inside the other, over the local edge."""
    worst = 0.0
    for i, j in ((0, 1), (1, 0)):
        bi, bj = model.bodies[i], model.bodies[j]
        xi = bi.positions(q[model.body_slice(i)])[bi.boundary_nodes()]
        xj = bj.positions(q[model.body_slice(j)])
        seg = bj.boundary_facets()
        worst = max(worst, float(np.max(depth_over_edge(xi, xj[seg[:, 0]], xj[seg[:, 1]]))))
    return worst


@pytest.mark.parametrize("velocity", [5.0, 10.0, 30.0])
@pytest.mark.parametrize("courant", [1, 2, 4, 8])
def test_disks_thrown_at_each_other_do_not_interpenetrate(velocity, courant):
    sim = case("two_disks").build(
        velocity=velocity, refinements=2, gap=0.0005, t_end=0.006, method="node-to-surface"
    )
    model = sim.model
    dt = wave_step(model.bodies[0], courant)
    states = simulate(model, dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    energy, worst = [], 0.0
    for st in states:  # a SolverError would fail the test: every run must complete
        energy.append(model.kinetic_energy(st.v) + model.strain_energy(st.q))
        worst = max(worst, worst_penetration(model, st.q))
    assert st.t == pytest.approx(sim.t_end, rel=1e-12)
    # the bound of a node-to-surface contact is round-off; 1 % of the edge is the bound a
    # discretization may leave (mortar), far above round-off and far below a lost node
    assert worst <= 0.01
    # no energy is created: the steps that would close by more than 5 % of a facet are
    # halved (measured: at most +0.01 %, at 30 m/s and Dx/c; the loss is the scheme's
    # damping and e_N = 0 at the contact nodes)
    assert max(energy) <= 1.03 * energy[0]


@pytest.mark.parametrize("velocity", [5.0, 10.0, 30.0])
@pytest.mark.parametrize("courant", [1, 2, 4, 8])
def test_mortar_disks_thrown_at_each_other_do_not_pass_through(velocity, courant):
    """The default contact of two solids (mortar), from the case's default gap (a closer start
    is refused where the weighted gap stands off the surface). The predictor's depth check
    halves a step that would close past the search (at 10 m/s and 8 Dx/c the disks passed
    through each other, 4.9 cm deep, before it). At 30 m/s the weighted gaps alone let
    nodes in by 2.2 % of an edge at Dx/c; a node of either disk deeper than half the
    allowance (0.5 % of the shortest edge) is held by its own gap (contact.mortar_safeguard).
    Measured (deepest over the local edge, Dx/c ... 8 Dx/c): 0 at 5 and 10 m/s; at 30 m/s
    0.47, 0.47, 0.47, 0.07 % (the weighted gaps alone: 2.2, 0.97, 0.48, 0.08 %)."""
    sim = case("two_disks").build(velocity=velocity, refinements=2, t_end=0.006)
    model = sim.model
    dt = wave_step(model.bodies[0], courant)
    states = simulate(model, dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    energy, worst, reported = [], 0.0, 0.0
    for st in states:  # a SolverError would fail the test: every run must complete
        energy.append(model.kinetic_energy(st.v) + model.strain_energy(st.q))
        worst = max(worst, worst_penetration(model, st.q))
        reported = max(reported, st.mortar_depth)
    assert st.t == pytest.approx(sim.t_end, rel=1e-12)
    assert worst <= 0.01  # the discretization's own amount (1 % of an edge)
    assert reported >= 0.5 * worst  # nothing silent: the watch sees what this test measures
    # measured: never above the initial energy (the loss is e_N = 0 and the scheme's damping)
    assert max(energy) <= 1.03 * energy[0]


def test_the_search_reaches_as_far_as_the_bodies_can_close_in_a_step():
    # two disks 3.5 cm apart closing at 2 x 100 m/s: within a step of 0.1 ms they close by
    # 2 cm, beyond the search margin of the model (5 % of its size, 1 cm); looking ahead,
    # the nearest nodes see the facets they are heading for
    sim = case("two_disks").build(
        velocity=100.0, refinements=1, gap=0.035, method="node-to-surface"
    )
    model, pair = sim.model, sim.model.contacts.pairs[0]
    q = np.zeros(model.n)
    model.contacts.detect_within(0.01)
    g = pair.gaps(q)
    assert np.all(np.isinf(g)) and pair.margin == 0.01
    model.contacts.look_ahead(q, sim.v0, 1e-4)
    # 2 x the 2 cm of closing x sqrt(2) (speeds bounded by their components), rounded up to a
    # power of two of 1 cm
    assert pair.margin == 0.08
    g = pair.gaps(q)
    # (the plane gap outside the facing vertex: a lower bound of the 3.5 cm distance)
    assert 0.03 < np.min(g) <= 0.035
    model.contacts.look_ahead(q, 0.0 * sim.v0, 1e-4)
    assert pair.margin == 0.01


def test_the_summary_counts_the_retaken_steps_and_reports_the_measured_penetration(tmp_path):
    import json
    from pathlib import Path

    from fecontact.cli.commands import main

    path = Path(__file__).resolve().parents[1] / "cases" / "two_disks.py"
    args = ["run", str(path), "--quiet", "--out", str(tmp_path), "--checkpoint-every", "0"]
    args += ["--set", "velocity=10", "--set", "refinements=2", "--set", "gap=0.0005"]
    # the end-of-step closing's retakes: "auto" localizes a frictionless solid's closings
    args += ["--set", "method=node-to-surface", "--set", "localize=0"]
    sim = case("two_disks").build(refinements=2)
    assert main([*args, "--dt", str(wave_step(sim.model.bodies[0], 8)), "--t-end", "0.004"]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "completed"
    assert summary["penetration_retakes"] > 0
    assert summary["step_halvings"] >= summary["penetration_retakes"]
    # round-off of the position correction: tol_gap (1e-12) x the model size (0.2 m)
    assert 0.0 <= summary["max_penetration"] <= 1e-12


# -- the predictor's depth against the facet entered (graded meshes) ----------------------------


def graded_blocks(overlap: float):
    """Two 2D blocks 0.1 m tall meeting along x = 0, ``overlap`` (m) into each other: their
    cells are 1 cm along the contact face and 1 mm wide at the far ends only (the shortest
    boundary edges, 5–10 cm from the contact), so each face node enters a 1 cm facet."""
    import skfem

    from fecontact import Model
    from fecontact.bodies import LinearElastic, Solid
    from fecontact.contact import Contact

    rubber = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
    far = np.array([-0.1, -0.099, -0.097, -0.093, -0.085, -0.07, -0.05, -0.03, -0.01, 0.0])
    y = np.linspace(-0.05, 0.05, 11)
    left = Solid(skfem.MeshTri.init_tensor(far, y), rubber)
    right = Solid(skfem.MeshTri.init_tensor(-far[::-1] - overlap, y), rubber)
    return Model([left, right], [Contact(left, right)], gravity=(0.0, 0.0))


@pytest.mark.parametrize("overlap, caught", [(3e-4, False), (6e-4, True), (3e-3, True)])
def test_the_predictor_bound_is_the_size_of_the_facet_entered_in_2d(overlap, caught):
    """A face node 0.3 mm inside the other block is 3 % of the 1 cm facet it entered (below
    the 5 % of DEEPEST) but 30 % of the shortest boundary edge (1 mm, far from the contact):
    the step goes on. 0.6 mm (6 % of the facet) and 3 mm are halved."""
    from fecontact.time.penetration import DEEPEST, PenetrationFailure, check_predictor

    model = graded_blocks(overlap)
    q = np.zeros(model.n)
    assert min(b.min_edge_length for b in model.bodies) == pytest.approx(1e-3)
    assert model.contacts.watches  # (a mortar interface: the watch measures its nodes)
    entered = max(w.entry(q) for w in model.contacts.watches)
    # the face nodes enter 1 cm facets by the overlap (the plane of the face)
    assert entered == pytest.approx(overlap / 0.01, rel=1e-9)
    assert (entered > DEEPEST) == caught
    if caught:
        with pytest.raises(PenetrationFailure, match="facet lengths deep"):
            check_predictor(model, q, model.contacts.gaps(q))
    else:
        check_predictor(model, q, model.contacts.gaps(q))
    # the depth reported at the end of a step keeps its measure: over the shortest edge
    depth, relative = model.contacts.watches[0].depth(q)
    assert depth == pytest.approx(overlap, rel=1e-9)
    assert relative == pytest.approx(overlap / 1e-3, rel=1e-9)


def graded_balls(overlap: float):
    """Two 5 cm balls pole to pole, ``overlap`` (m) into each other, their tetrahedra graded
    from 1 cm at the far poles (the shortest boundary edges, 6.9 mm) to 2.6–4 cm at the
    poles that meet."""
    from fecontact import Model
    from fecontact.bodies import LinearElastic, Solid
    from fecontact.bodies.meshes import graded_ball_mesh
    from fecontact.contact import Contact

    rubber, r, c = LinearElastic(E=1e7, nu=0.3, rho=1000.0), 0.05, 0.05 - 0.5 * overlap
    left = Solid(graded_ball_mesh([-c, 0, 0], r, 0.2 * r, [-c - r, 0, 0], 0.5, 1), rubber)
    right = Solid(graded_ball_mesh([c, 0, 0], r, 0.2 * r, [c + r, 0, 0], 0.5, 1), rubber)
    return Model([left, right], [Contact(left, right)], gravity=(0.0, 0.0, 0.0))


@pytest.mark.parametrize("overlap, caught", [(1e-3, False), (2e-3, True)])
def test_the_predictor_bound_is_the_size_of_the_facet_entered_in_3d(overlap, caught):
    """A pole node 1 mm inside the other ball is 13 % of its shortest boundary edge (6.9 mm,
    at the far pole) and 3.6 % of the shortest edge of the triangle it entered (26 mm): the
    step goes on. 2 mm (7 % of that triangle) is halved."""
    from fecontact.time.penetration import DEEPEST, PenetrationFailure, check_predictor

    model = graded_balls(overlap)
    q = np.zeros(model.n)
    watch = model.contacts.watches[0]
    depth, relative = watch.depth(q)
    entered = watch.entry(q)
    # (the pole sits 0.9 overlap deep: the facets around the other pole are flat chords)
    assert 0.8 * overlap < depth <= overlap
    # the entered triangles are far coarser than the shortest edge (a factor 3.7 measured)
    assert relative > 3.0 * entered
    assert (entered > DEEPEST) == caught and relative > DEEPEST
    if caught:
        with pytest.raises(PenetrationFailure, match="facet lengths deep"):
            check_predictor(model, q, model.contacts.gaps(q))
    else:
        check_predictor(model, q, model.contacts.gaps(q))


# -- mortar disks at one boundary edge a step: the weighted gaps stay continuous ----------------


@pytest.mark.parametrize(
    "z",
    [  # (x_p, x_a, x_b, x_c, y_1, y_2) in mm: a slave segment 2 cm above the master segment
        [0.0286, 17.3124, -0.5122, 36.0963, -13.5897, 50.7901, -33.0547, 51.2778]
        + [0.141, 17.3981, 0.0759, 0.0],
        # 1/40 of a Newton update later: y_2's projection has passed through infinity
        [0.024, 17.313, -0.4853, 36.0944, -13.6001, 50.7944, -33.0531, 51.2708]
        + [0.1311, 17.3979, 0.0808, 0.0],
    ],
)
def test_a_master_segment_whose_projection_passes_through_infinity_does_not_overlap(z):
    """A slave segment whose normals turn parallel to a master segment's line (two disks at
    29 m/s pressed flat, the segment 2 cm from the contact): the master segment's image on
    the slave's parameter line is two rays, neither meeting [-1, 1]. Taken as the interval
    between the projections of its ends it covered the whole segment once y_2's projection
    passed from -17.6 to +17.8, and the node's weighted gap jumped by 1.4 mm within one
    Newton update (the position correction then cycled)."""
    from fecontact.contact.mortar_segments import segment_pair_integrals

    z = np.array([z]) * 1e-3
    yes = np.array([True])
    ga, gb, coverage, _, _ = segment_pair_integrals(z, yes, yes, None, 0.01)
    assert coverage[0] == 0.0 and ga.v[0] == 0.0 and gb.v[0] == 0.0


@pytest.mark.parametrize("gap", [6.5e-3, 8e-3])
def test_mortar_disks_one_edge_a_step_complete_from_any_initial_gap(gap):
    """Two rubber disks head-on at 29 m/s each, 4 Dx/c (one boundary edge a step), from the
    initial gaps that stopped with a cycling Newton (6.5, 7 and 8 mm; the whole table 4 to 8 mm
    in docs/validation/stress_2d.md): each run completes, mirror-symmetric, no node deeper
    than 1 % of an edge (measured 0.47 % and 0.14 %)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from stress_2d import cell_speed, two_disks

    sim, _ = two_disks(speed=cell_speed(1, 4), courant=4, gap=gap)
    model = sim.model
    states = simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    worst = 0.0
    for st in states:  # a SolverError would fail the test: the run must complete
        worst = max(worst, worst_penetration(model, st.q))
    assert st.t == pytest.approx(sim.t_end, rel=1e-12)
    assert worst <= 0.01  # the discretization's own amount (1 % of an edge)
    # head-on and mirror-symmetric: no lateral velocity of either disk's nodes on average
    # (measured 8e-11 and 1.8e-10 m/s: the round-off of some 20 steps' solves)
    for i in range(2):
        v = st.v[model.body_slice(i)].reshape(-1, 2)
        assert abs(v[:, 1].mean()) <= 1e-9 * 29.0


@pytest.mark.slow
def test_fast_off_centre_balls_get_past_their_first_contact():
    """The stress sweep's two rubber balls at 5 m/s each, 0.7 R off-centre, a step of 57 Dx/c
    that closes two cells (graded meshes, the finest cells under the contact). With the
    predictor's bound over the shortest boundary edge the run stopped at step 1 ("a node
    enters another body 0.05 facet lengths deep in one step ... after 6 step halvings"); over
    the shortest edge of the triangle each node enters it takes that step (29 halvings over
    the whole run, which completes: docs/validation/stress_3d.md)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from stress_3d import solid_depth, two_balls

    sim = two_balls(5.0, b=0.7, cells=2).sim
    model = sim.model
    depth = solid_depth(*model.bodies, model.body_slice(0), model.body_slice(1))
    worst, t_end = 0.0, sim.dt
    for st in simulate(model, sim.dt, t_end, sim.options, q0=sim.q0, v0=sim.v0):
        worst = max(worst, depth(st)[1])  # (a SolverError fails the test)
    assert st.t == pytest.approx(t_end, rel=1e-12)
    # the deepest node over the longest edge of the triangle it is under: 1.7 % measured
    # over the run, the P1 balls' known excess over the 1 % of the weighted gaps (warned
    # by the run), far below the 5 % a step may bring in
    assert worst <= 0.03


# -- three boundary edges a step (43.5 m/s, 8 Dx/c): the correction's active sets -------------


def three_edges_a_step(offset: float, method: str, steps: int):
    """The stress sweep's disks at 43.5 m/s each and 8 Dx/c (a step moves each disk by three
    of its shortest boundary edges), ``offset`` of the radius off-centre, run ``steps`` steps
    (the first contact is in step 3)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from stress_2d import cell_speed, two_disks

    sim, _ = two_disks(speed=cell_speed(3, 8), courant=8, offset=0.05 * offset, method=method)
    return sim.replace(t_end=steps * sim.dt, probes={})


def test_mortar_disks_three_edges_a_step_off_centre_get_past_the_first_contact(tmp_path):
    """Mortar, 0.3 R off-centre: a deep slave node's weighted row and its own row were one
    row, their minimum, whose kink the smooth step's Newton jumped across (the run stopped
    at step 4); as twin rows, of which the correction's active set holds the deeper, it got
    past. With the smooth step's p-free active set it stopped at step 4 again: a node's own
    row, pressed in the last step, came out of the node's depth at the predictor (a far gap,
    14 mm, and a zero gradient) and stayed in the set with the force it came with, which no
    update could change, and its gap never closed. A row with a zero gradient holds nothing
    and leaves the set: the run completes, no node deeper than 1 % of an edge (0.55 %
    measured)."""
    sim = three_edges_a_step(0.3, "mortar", 6)
    model = sim.model
    states = simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    worst = 0.0
    for st in states:  # a SolverError would fail the test
        worst = max(worst, worst_penetration(model, st.q))
    assert st.t == pytest.approx(sim.t_end, rel=1e-12)
    assert 0.0 < worst <= 0.01  # (the contact has begun; the discretization's own amount)


@pytest.mark.slow
def test_coarser_fast_off_centre_balls_get_past_their_first_contact():
    """The row above on a coarser mesh (spacing 0.3 R, one refinement: 42 Dx/c, two cells a
    step). It stopped at step 1 with every halving failing the predictor: the weighted gaps
    had let nodes 4.6 % of an edge in before the last sub-step started, and a smaller step
    cannot take that out. A node deeper than twice BOUND at a step's start is measured by
    what the step adds (the run completes, nothing created: docs/validation/stress_3d.md)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from stress_3d import two_balls

    sim = two_balls(5.0, b=0.7, cells=2, spacing=0.3, base=1).sim
    model = sim.model
    energy = model.kinetic_energy(sim.v0)
    # (a SolverError fails the test)
    st = list(simulate(model, sim.dt, sim.dt, sim.options, q0=sim.q0, v0=sim.v0))[-1]
    assert st.t == pytest.approx(sim.dt, rel=1e-12)
    # nothing silent: the nodes the weighted gaps let in are reported (0.93 mm measured,
    # 11 % of the shortest edge), the energy not above the start (e_N = 0)
    assert st.penetration > 0.0
    assert model.kinetic_energy(st.v) + model.strain_energy(st.q) <= 1.001 * energy


def test_a_smooth_row_with_no_gradient_leaves_the_active_set():
    """A node's own row (contact.mortar_safeguard) reports a far gap and a zero gradient once
    its node is out of the other body; pressed in the last step, it came into the smooth step
    with a force that a bordered update cannot change (its row of G is zero) and a gap that
    never closes. It leaves the set, as a row whose gap is undefined does; a pressed row with
    a gradient stays, and a penetrating one enters."""
    from types import SimpleNamespace

    from fecontact.time.smooth_contact import SmoothContacts

    g = np.array([0.014, 1e-6, -1e-6, 0.02])
    G = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 1.0]])
    contacts = SimpleNamespace(linearize=lambda q, P, w: (g, G, None), affine=False)
    opts = SimpleNamespace(stats=SimpleNamespace(contact=SimpleNamespace(minimum_norm=False)))
    sc = SmoothContacts(
        SimpleNamespace(contacts=contacts), np.arange(4), np.array([1e5, 2.0, 0, 0]), opts
    )
    sc.update(np.zeros(2), False)
    assert sc.active.tolist() == [False, True, True, False]
    assert sc.lam[0] == 0.0  # (no force is carried on a row that holds nothing)


def test_a_correction_row_with_no_gradient_leaves_the_active_set():
    """The same in the position correction: a node's own row pressed in the last step (its
    multiplier warm-starts the correction) whose node is now out (a far gap, 14 mm, and a
    zero gradient) made the Schur complement singular; it held nothing, and at h/128 of the
    fast head-on mortar disks its update stalled at the round-off of the least-squares
    multipliers until the iterations ran out. It leaves the set: no least squares, the other
    row closed to round-off."""
    g0 = np.array([-1e-3, 0.014])
    U, nu, stats = _corrected_with_a_flat_row(g0, nu0=np.array([0.0, 1.0]))
    assert stats.least_squares == 0 and nu[1] == 0.0
    assert abs(g0[0] + U[0]) <= 1e-15  # (one linear row: closed by one solve)


def test_a_held_row_with_no_gradient_is_no_equality_of_the_correction():
    """The same for a row held as an equality (pressed by the smooth step's force): a master
    node's own row whose node the smooth step lifted above half its allowance reads its
    placeholder (a far gap, 17 mm, and a zero gradient). Kept as an equality, its zero row
    made the Schur complement singular (least squares) and its gap the correction's residual
    (1e11 tolerances on the 57 Δx/c off-centre balls of stress_3d.md). It holds nothing:
    no least squares, the other row closed to round-off, the residual within tolerance."""
    g0 = np.array([-1e-3, 0.0173])
    U, nu, stats = _corrected_with_a_flat_row(g0, bilateral=np.array([False, True]))
    assert stats.least_squares == 0 and nu[1] == 0.0
    assert abs(g0[0] + U[0]) <= 1e-15  # (one linear row: closed by one solve)
    assert stats.final_residuals.position <= 1.0  # (in tolerances: the law holds)


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_disks_three_edges_a_step_head_on_complete_at_h_over_128(method):
    """Head-on at 43.5 m/s and 8 Dx/c the rim nodes of the growing contact zone reach the
    other disk at 0.75 c, and the predictor's bound (5 % of a facet a step) needs h/128: one
    halving more than the default six allows (the runs stop at step 3 on the predictor).
    With seven, the mortar row's correction did not settle at h/128: a node's own row out of
    the other disk stayed in the set (a zero gradient, least-squares multipliers), then a
    slave node's weighted row and the own row of the master node facing it (correlation
    0.9998 in the correction's metric) split into large opposite forces. Both runs now
    complete, no node deeper than 1 % of an edge; the mortar disks on their axis."""
    import dataclasses

    sim = three_edges_a_step(0.0, method, 6)
    model = sim.model
    opts = dataclasses.replace(sim.options, max_halvings=7)
    worst = 0.0
    for st in simulate(model, sim.dt, sim.t_end, opts, q0=sim.q0, v0=sim.v0):
        worst = max(worst, worst_penetration(model, st.q))  # (a SolverError fails the test)
    assert st.t == pytest.approx(sim.t_end, rel=1e-12)
    assert 0.0 < worst <= 0.01  # (the contact has begun; the discretization's own amount)
    if method != "mortar":  # (one-pass node-to-surface is not symmetric: 8.6 % measured)
        return
    for i in range(2):  # mirror-symmetric: round-off of the steps' solves (1e-9 of the speed)
        v = st.v[model.body_slice(i)].reshape(-1, 2)
        assert abs(v[:, 1].mean()) <= 1e-9 * 43.5


def test_nearly_parallel_rows_hold_the_deeper():
    """Two rows whose gradients correlate to 1 − 5e-5 in the correction's metric (a slave
    node's weighted row and the own row of the master node facing it, 0.9998 on the head-on
    disks) held together: their multipliers are ±1e5 times the answer's and the first update
    moves the point by 1 cm for a 1 mm overlap. In a model with twin rows the set holds the
    deeper of the two; the shallower comes out open. The answer is the same (it is unique),
    reached in one update instead of two."""
    from fecontact.contact.laws import solve_position_correction

    G = np.array([[1.0, 0.0], [1.0, 1e-2]])
    g0 = np.array([-1e-3, -0.9e-3])

    def system(U, s, A):
        return (lambda B: B), None  # (linear gaps: H⁻¹ = I, no curvature)

    answers = []
    for twins, updates in ((None, 2), (np.full(2, -1), 1)):
        U, nu, its = solve_position_correction(
            lambda U: (g0 + G @ U, G), system, 2, np.ones(2), 1.0, 1e-12, 1e-13, twins=twins
        )
        assert its == updates
        answers.append(np.concatenate([U, nu]))
    # (one linear row closed: the direct solve's round-off)
    assert np.allclose(answers[0], answers[1], rtol=0.0, atol=1e-18)
    assert answers[1][3] == 0.0 and g0[1] + G[1] @ answers[1][:2] == pytest.approx(1e-4)


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_disks_three_edges_a_step_head_on_complete_with_localized_impacts(method):
    """The same head-on rows at the default budget of six halvings with the impacts
    localized (``localize=1``): a step in which the disks close is cut at the instant they
    touch, so the rim nodes no longer arrive within one step from far off. Both complete
    (measured over the sweep's 19 steps: 21 and 12 halvings, mortar nothing created,
    node-to-surface 1.1e-3 of the scale)."""
    import dataclasses

    sim = three_edges_a_step(0.0, method, 6)
    model = sim.model
    opts = dataclasses.replace(sim.options, localize=True)
    worst = 0.0
    for st in simulate(model, sim.dt, sim.t_end, opts, q0=sim.q0, v0=sim.v0):
        worst = max(worst, worst_penetration(model, st.q))  # (a SolverError fails the test)
    assert st.t == pytest.approx(sim.t_end, rel=1e-12)
    assert worst <= 0.01  # the discretization's own amount (1 % of an edge)


def _corrected_with_a_flat_row(g0: np.ndarray, **kw):
    """(U, ν, the contact statistics) of the position correction of two linear rows, the
    second with no gradient (a placeholder's), from gaps ``g0``; ``kw`` to the solve."""
    from fecontact.contact.laws import solve_position_correction
    from fecontact.contact.stats import ContactStats

    G = np.array([[1.0, 0.0], [0.0, 0.0]])
    stats = ContactStats()

    def system(U, s, A):
        return (lambda B: B), None  # (linear gaps: H⁻¹ = I, no curvature)

    U, nu, _ = solve_position_correction(
        lambda U: (g0 + G @ U, G), system, 2, np.ones(2), 1.0, 1e-12, 1e-13, stats=stats, **kw
    )
    return U, nu, stats
