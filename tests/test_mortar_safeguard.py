"""The pointwise safeguard of mortar interfaces: a node deeper than half the allowance
inside the other solid is held by its own gap g_N + δ, a row of its own (a slave node's is
the twin of its weighted row: an active set holds one of the two), with exact derivatives,
and the weighted gaps are untouched bit for bit. In 3D the row is the smooth maximum of the
plane gaps around the nearest master vertex."""

import dataclasses

import numpy as np
import pytest

from fecontact import Model
from fecontact.bodies import Solid
from fecontact.bodies.meshes import ball_mesh
from fecontact.contact import Contact
from fecontact.contact.mortar_safeguard import (
    ALLOWANCE,
    SMOOTHING,
    DeepNodeRows3D,
    shortest_edge,
    twins_among,
)
from fecontact.scenes import solid_material
from fecontact.testing import gap_derivatives_error


def overlapping_disks(gap, safeguard=True):
    """Two disks of radius 0.1 m (refinements 2, 12 mm edges) ``gap`` apart (m; < 0 overlap),
    the right one 3 mm up, their mortar pair and model; ``safeguard`` False: the weighted gaps
    alone (for comparison)."""
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    a = Solid.disk([-0.1 - gap / 2, 0.0], 0.1, 2, mat)
    b = Solid.disk([0.1 + gap / 2, 0.003], 0.1, 2, mat)
    pair = Contact(a, b, method="mortar")
    if not safeguard:
        pair.pointwise = pair.master_rows = None
    model = Model([a, b], [pair], gravity=(0.0, 0.0))
    pair.detect_within(0.02)
    return model, pair


def poked(model, body: int, depth: float) -> np.ndarray:
    """q that moves the boundary node of disk ``body`` nearest the other disk ``depth`` (m)
    towards it along x, the rest of both disks at rest."""
    solid, sign = model.bodies[body], (1.0, -1.0)[body]
    tip = solid.contact_nodes(None)[np.argmax(sign * solid.X[solid.contact_nodes(None), 0])]
    q = np.zeros(model.n)
    q[model.offset_of(solid) + solid.node_translation_dofs(np.array([tip]))[0, 0]] = sign * depth
    return q


def test_a_slave_node_deep_inside_has_a_row_of_its_own_twin_of_its_weighted_row():
    # statically overlapping or poked disks have their weighted gaps below the nodes' own
    # (the dual weights extrapolate from the covered part); the nodes that sink deeper than
    # their weighted gaps are those of a surface bulging in flight (tests/test_fast_approach).
    # Here the allowance is made negative (−5 mm) so that every node near the contact has
    # its row: the rows, their derivatives and their numbering are what is tested
    model, pair = overlapping_disks(-0.003)
    _, weighted = overlapping_disks(-0.003, safeguard=False)
    rows = pair.pointwise
    rows.allowance = -0.005
    q = np.random.default_rng(2).normal(0.0, 1e-4, model.n)
    # the weighted rows are the weighted gaps, bit for bit, however deep a node
    for a, b in zip(pair.evaluate(q)[:3], weighted.evaluate(q)[:3], strict=True):
        assert np.array_equal(a, b)
    g, _, G, _ = rows.evaluate(q)
    deep = g < 0.5 * rows.allowance
    assert deep.sum() >= 1  # (the tip of the left disk)
    assert np.all(g[~deep] == 2.0 * rows.base_margin) and not G[~deep].any()
    # central differences, step 1e-7 m: round-off ~1e-9 relative
    err_g, err_h = gap_derivatives_error(rows, q, 1e-7)
    assert err_g < 1e-8 and err_h < 1e-6
    # in the model: the weighted rows first, the master's nodes, then the slave's, each the
    # twin of the weighted row of its node
    contacts, n = model.contacts, pair.size
    assert contacts.pairs == [pair, pair.master_rows, rows]
    start = n + pair.master_rows.size
    twins = contacts.twins
    assert np.array_equal(twins[:n], start + np.arange(n))
    assert np.array_equal(twins[start:], np.arange(n))
    assert np.all(twins[n:start] == -1)
    local = twins_among(twins, np.array([start + 3, 5, 3]), 1)
    assert np.array_equal(local, [2, -1, 0, -1])


def test_an_active_set_holds_the_deeper_of_two_twins():
    from fecontact.contact.laws import one_of_twins

    A = np.array([True, True, True, True, False, True])
    g = np.array([-2.0, -1.0, -3.0, -3.0, -9.0, 0.5])
    twins = np.array([1, 0, 3, 2, 5, 4])  # (4 inactive: 5 stays)
    assert np.array_equal(one_of_twins(A, g, twins), [True, False, True, False, False, True])
    assert one_of_twins(A, g, None) is A


def test_a_master_node_deep_inside_gets_a_row_and_the_others_are_never_candidates():
    model, pair = overlapping_disks(-0.003)
    rows = pair.master_rows
    a = model.bodies[0]  # the slave disk, whose surface the master's nodes are held out of
    assert rows.allowance == ALLOWANCE * shortest_edge(a, a.contact_facets())
    q = np.zeros(model.n)
    g, _, G, _ = rows.evaluate(q)
    deep = g < 0.5 * rows.allowance
    assert deep.sum() >= 1
    # the shallow nodes: a finite gap beyond the detection distance, no gradient
    assert np.all(g[~deep] == 2.0 * rows.base_margin) and not G[~deep].any()
    assert (
        gap_derivatives_error(rows, np.random.default_rng(3).normal(0.0, 1e-4, model.n))[0] < 1e-8
    )


def test_no_node_that_deep_leaves_the_weighted_gaps_bit_for_bit():
    # 0.5 mm apart: every row is the weighted gap, the master's rows are never candidates
    model, pair = overlapping_disks(0.0005)
    _, weighted = overlapping_disks(0.0005, safeguard=False)
    q = np.zeros(model.n)
    for a, b in zip(pair.evaluate(q)[:3], weighted.evaluate(q)[:3], strict=True):
        assert np.array_equal(a, b)
    assert np.all(pair.master_rows.gaps(q) > 0.02)


def test_the_summary_counts_the_steps_that_end_with_a_node_held(tmp_path):
    import json
    from pathlib import Path

    from fecontact.cli.commands import main
    from fecontact.scenes import wave_step
    from fecontact.testing import case

    path = Path(__file__).resolve().parents[1] / "cases" / "two_disks.py"
    dt = wave_step(case("two_disks").build(refinements=2).model.bodies[0], 1)
    for velocity, held in ((30, True), (1, False)):
        out = tmp_path / str(velocity)
        args = ["run", str(path), "--quiet", "--out", str(out), "--checkpoint-every", "0"]
        args += ["--set", f"velocity={velocity}", "--set", "refinements=2"]
        assert main([*args, "--dt", str(dt), "--t-end", "0.004"]) == 0
        summary = json.loads((out / "summary.json").read_text())
        assert summary["status"] == "completed"
        # 30 m/s at dx/c: nodes of both disks sink and are held (the weighted gaps alone let
        # them 2.2 % of an edge in); 1 m/s: the weighted gaps alone, no node held
        assert (summary["mortar_held_steps"] > 0) == held
        assert summary["mortar_depth"] <= 0.01


def test_a_pole_inside_the_apex_of_a_turned_ball_is_pushed_along_the_axis():
    """The coarsest balls (18 boundary nodes) overlapping pole into pole by d = 1 mm, the
    right one turned 30° about the axis: each pole lies behind the four facets around the
    other's pole, all tilted by θ from the axis (cos θ = 1/√(1 + 2(√2 − 1)²), θ = 30.4°:
    the ring's nodes R/√2 off the axis), by d cos θ each. Its row reads that depth less the
    ε ln 4 of a four-plane tie, and its gradient on the pole is the facets' mean normal,
    along the axis (a single facet's plane gap pushed the poles sideways by half the force)."""
    cos = 1.0 / np.sqrt(1.0 + 2.0 * (np.sqrt(2.0) - 1.0) ** 2)
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    d, angle = 1e-3, np.radians(30.0)
    mesh = ball_mesh([-0.05 + d / 2, 0.0, 0.0], 0.05, 1)
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ np.diag([-1.0, -1.0, 1.0])
    a, b = Solid(mesh, mat), Solid(dataclasses.replace(mesh, doflocs=turn @ mesh.doflocs), mat)
    pair = Contact(a, b, method="mortar")
    Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.005)
    rows = pair.pointwise
    # (both passes: the master's nodes are the same kind of row against the slave's surface)
    assert isinstance(rows, DeepNodeRows3D) and isinstance(pair.master_rows, DeepNodeRows3D)
    j = np.argmax(a.X[rows.nodes, 0])
    g, _, G, _ = rows.evaluate(np.zeros(2 * a.ndof))
    eps = SMOOTHING * rows.allowance
    expected = -d * cos + eps * np.log(4.0) + rows.allowance
    # exact but for round-off (the mesh's nodes on the sphere): 1e-9 of d
    assert abs(g[j] - expected) <= 1e-9 * d
    push = G[j, :3]  # on the pole node (the gradient of a gap: unit length along x)
    assert abs(push[0] + cos) <= 1e-9  # (toward −x: out of the right ball)
    assert np.hypot(push[1], push[2]) <= 1e-9  # round-off of the symmetric planes
    # central differences, step 1e-9 m against ε = 19 µm: the soft maximum's curvature 1/ε
    # makes the differences' truncation ~(h/ε)² relative
    q = np.random.default_rng(3).normal(0.0, 1e-6, 2 * a.ndof)
    err_g, err_h = gap_derivatives_error(rows, q, 1e-9)
    assert err_g < 1e-6 and err_h < 1e-4


def test_the_balls_at_three_times_the_speed_keep_every_node_within_the_bound():
    """``two_balls`` at 3 m/s each (graded P1, the right ball turned 30°) over its first
    0.9 ms: with the slave's rows alone a node of the master ball sank 3.7 % of the shortest
    boundary edge into the slave ball at step 35 (the weighted gaps let it in, and nothing
    held it). The master's nodes now have rows too, whose planes are read by the facet each
    node's foot lies on: the slave's surface dents around a master node that presses into
    it, and there the largest plane gap around a vertex is a neighbour's plane that the node
    is not behind."""
    from fecontact import simulate
    from fecontact.contact.watch import BOUND, watched_depth
    from fecontact.testing import case

    sim = case("two_balls").build(velocity=3.0, t_end=9e-4)
    model = sim.model
    worst = 0.0
    for st in simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0):
        worst = max(worst, watched_depth(model.contacts.watches, st.q)[1])
    assert st.t == sim.t_end or abs(st.t - sim.t_end) <= 1e-12 * sim.t_end
    # the held nodes end about δ = 0.5 % of the edge deep: the bound is the run's warning's
    assert 0.0 < worst <= BOUND


def test_a_node_behind_a_dented_vertex_reads_the_facet_it_is_under():
    """A block's top face dented at its centre vertex by 6 mm (the facets around it slope
    into the block: a concave vertex, as the slave ball's surface around a master node that
    presses into it) and a node of a small cube 0.16 mm behind one of those facets, 9 mm
    from the vertex. The planes of the facets across the dent pass above the node: their
    largest plane gap read it 1 cm outside (beyond the detection distance: no row), so
    nothing held it. With each plane read deeper by the node's foot beyond its facet, the
    row is the node's plane gap behind the facet it is under, its signed distance to the
    surface, with exact derivatives."""
    from fecontact.contact.inside import Surface

    block, cube, model, rows = cube_over_block()
    q = np.zeros(model.n)
    centre = int(np.argmin(np.linalg.norm(block.X, axis=1)))  # (0, 0, 0): the top's centre
    dofs = model.offset_of(block) + block.node_translation_dofs(np.array([centre]))[0]
    q[dofs] = [0.0, 0.0, -0.006]
    corner = int(np.argmin(cube.X.sum(axis=1)))
    node = np.array([0.009, 0.004, -0.004])
    q[model.offset_of(cube) + cube.node_translation_dofs(np.array([corner]))[0]] = (
        node - cube.X[corner]
    )
    g, _, G, _ = rows.evaluate(q)
    j = int(np.flatnonzero(rows.nodes == corner)[0])
    x = block.positions(q[model.body_slice(1)])
    depth = Surface(block.contact_facets()).signed_distance(x, node[None], outside=False)[0][0]
    assert depth < -1e-4  # (0.156 mm inside)
    # the other planes lie millimetres farther: their weights are e^(−mm/ε), nothing
    assert abs(g[j] - rows.allowance - depth) <= 1e-12 * abs(depth)
    assert np.linalg.norm(G[j, :3]) == pytest.approx(1.0, abs=1e-12)  # (a plane's normal)
    err_g, err_h = gap_derivatives_error(rows, q, 1e-9)
    assert err_g < 1e-6 and err_h < 1e-4  # as for the pole above: truncation (h/ε)²


def test_a_node_held_under_an_edge_of_a_shallow_dent_is_not_pushed_sideways():
    """The pole of a coarse ball pressed at 10 m/s into a fine rubber slab sits δ deep under
    the shared edge of two facets of the dent it makes (nearly coplanar, concave). There the
    row weighs both planes, each less its foot's excess beyond its facet; with the excess's
    ramp as narrow as the soft maximum's ε the row pushed the node sideways by up to 0.39 of
    its force within ε of the edge, that push swinging sign across it, and the smooth step's
    Newton iterates crossed the edge back and forth without converging (17 halvings of the
    ball on the slab, docs/validation/solid_sweep.md). The ramp is δ wide, as the excess of
    a node's distance from its facet over that from its plane is at a depth of δ."""
    block, cube, model, rows = cube_over_block()
    delta, eps = rows.allowance, SMOOTHING * rows.allowance
    q = np.zeros(model.n)
    centre = int(np.argmin(np.linalg.norm(block.X, axis=1)))  # dented 0.5 mm: 2 % slopes
    q[model.offset_of(block) + block.node_translation_dofs(np.array([centre]))[0]] = [0, 0, -5e-4]
    corner = int(np.argmin(cube.X.sum(axis=1)))
    j = int(np.flatnonzero(rows.nodes == corner)[0])
    dofs = model.offset_of(cube) + cube.node_translation_dofs(np.array([corner]))[0]
    sideways = []
    for y in np.linspace(-eps, eps, 9):  # across the facets' shared edge along x (y = 0)
        at = q.copy()  # (9 mm from the dented vertex, δ below the edge)
        at[dofs] = np.array([0.009, y, -5e-4 * (1.0 - 0.009 / 0.025) - delta]) - cube.X[corner]
        g, _, G, _ = rows.evaluate(at)
        assert -0.1 * delta < g[j] < 0.1 * delta  # (held: g_N ≈ −δ)
        sideways.append(G[j, 1])
    # at most the planes' tilt 0.02 plus the ramp's slope e/δ ≤ (ε + 2 µm)/δ = 0.12 (the
    # node's foot on the tilted neighbour plane lies |g| × 0.02 = 2 µm farther out): 0.14, a
    # bound of the geometry, not of round-off; measured 0.059 (a ramp of width ε: 0.39)
    assert max(abs(s) for s in sideways) < 0.14
    err_g, err_h = gap_derivatives_error(rows, at, 1e-9)
    assert err_g < 1e-6 and err_h < 1e-4  # as for the pole above: truncation (h/ε)²


def test_a_node_beside_a_corner_in_front_of_every_plane_has_no_row():
    """A node of a cube beside a corner of a box (2 × 2 × 2 cells, the four facets around
    that corner), 2 cm below its bottom and 0.7 and 1.6 cm beyond its sides: in front of
    every plane around the corner, outside. Each plane gap, less its foot's excess beyond its
    facet (2.0-2.7 cm), read it inside, and their smooth maximum 3.0 mm deep: a row that
    pushed the box from a node nowhere near it (an elastic box sliding over a slab whose mesh
    is turned 17°: a node of the clamped base beside the box's corner, whose row came and
    went at each relinearization of the position correction until the run stopped). The row
    is never deeper than the deepest plane gap itself: here 7 mm out, no row."""
    from fecontact.contact.inside import Surface

    mat = solid_material("linear", 1e7, 0.3, 1e3)
    box = Solid.box([-0.04, -0.02, 0.0], [0.0, 0.02, 0.02], 2, mat)
    node = np.array([0.007, -0.036, -0.02])  # (the corner (0, −0.02, 0) + (7, −16, −20) mm)
    cube = Solid.box(node + [0.0, -0.01, -0.01], node + [0.01, 0.0, 0.0], 1, mat)
    pair = Contact(cube, box, method="mortar")
    model = Model([cube, box], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.03)  # (the node's closest facet within reach)
    rows = pair.pointwise
    j = int(np.flatnonzero(np.all(np.isclose(cube.X[rows.nodes], node), axis=1))[0])
    g, _, G, _ = rows.evaluate(np.zeros(model.n))
    assert Surface(box.contact_facets()).signed_distance(box.X, node[None])[0][0] > 0.02
    assert np.array_equal(box.X[rows.vertex[j]], [0.0, -0.02, 0.0])
    assert g[j] == 2.0 * rows.base_margin and not G[j].any()  # (g_s = −2.9 mm before)


def test_a_coarse_ball_pressed_into_a_fine_slab_takes_no_halving(tmp_path):
    """A rubber ball of refinements 1 thrown at 10 m/s onto a clamped slab of 1 cm cells
    (6 × 6 × 1, 6 cm square): its pole sinks into the dent it makes and is held by its own
    row under a shared edge of the dent's facets. With the excess ramp ε wide the smooth
    step's Newton loop did not converge there: step 22 halved and the located impact of step
    23 was taken whole (``failed``); the 12 × 12 × 2 slab of docs/validation/solid_sweep.md
    took 17 halvings."""
    from fecontact import run
    from fecontact.bodies.materials import NeoHookean
    from fecontact.scenes import wave_step
    from fecontact.simulation import Simulation

    rubber = NeoHookean(1e7, 0.3, 1000.0)
    slab = Solid.box([-0.03, -0.03, -0.02], [0.03, 0.03, 0.0], (6, 6, 1), rubber)
    slab.fix(slab.nodes_where(lambda x: x[2] <= -0.02 + 1e-9))
    ball = Solid.ball([0.0, 0.0, 0.051], 0.05, 1, rubber)
    model = Model([ball, slab], [Contact(ball, slab)], gravity=(0.0, 0.0, 0.0))
    dt = min(wave_step(b, 1.0) for b in (ball, slab))
    v0 = model.translation(ball, (0.0, 0.0, -10.0))
    sim = Simulation(model, dt, 24 * dt, output_interval=24 * dt, v0=v0, name="ball")
    summary = run(sim, tmp_path / "ball", progress=False, frames=False)
    assert summary["status"] == "completed" and summary["steps"] == 24
    assert summary["step_halvings"] == 0
    assert summary["localization_fallbacks"]["failed"] == 0
    assert summary["mortar_held_steps"] > 0  # (the pole held by its own row: the case above)


def test_k_does_not_move_the_balls_whose_rows_close_picoseconds_apart():
    """``two_balls`` through its first 0.45 ms at k and k ÷ 100. At 0.404 ms two master nodes'
    rows cross half their allowance 2e-11 s apart and are taken together at the later
    instant; the correction that puts back the earlier lifts the later 3.5 gap tolerances
    out, and left open by the jump it closed again 1.8e-12 s later, in a smooth step too
    short to determine its contact forces: their sign (a row pressed or not) followed k,
    and k ÷ 100 moved the run by 6.5e-3 of its speed by 0.45 ms. The jump closes every row
    taken together."""
    from fecontact import simulate
    from fecontact.testing import case

    ends = []
    for k in (1.0, 1e-2):
        sim = case("two_balls").build(t_end=4.5e-4)
        opts = dataclasses.replace(sim.options, multiplier_scale=sim.options.multiplier_scale * k)
        *_, end = simulate(sim.model, sim.dt, sim.t_end, opts, q0=sim.q0, v0=sim.v0)
        ends.append(end)
    a, b = ends
    # round-off of the run (measured 2.5e-18 in q over the length, 2.4e-14 in v over the
    # speed), far below the 1e-6 by which p and k may move a case at most; 6.5e-3 in v before
    assert np.abs(a.q - b.q).max() <= 1e-9 * sim.model.length
    assert np.abs(a.v - b.v).max() <= 1e-9 * np.abs(a.v).max()


def cube_over_block():
    """A small cube 1 mm over a block of 4 × 4 × 1 cells (mortar, detection 5 mm): the block,
    the cube, the model and the pair's pointwise safeguard rows."""
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    block = Solid.box([-0.05, -0.05, -0.02], [0.05, 0.05, 0.0], (4, 4, 1), mat)
    cube = Solid.box([-0.005, -0.005, 0.001], [0.005, 0.005, 0.011], 1, mat)
    pair = Contact(cube, block, method="mortar")
    model = Model([cube, block], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.005)
    return block, cube, model, pair.pointwise
