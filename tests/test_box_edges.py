"""A rigid box's edges against a 3D solid's boundary edges (:mod:`fecontact.contact.box_edges`).

Before these rows a box edge entered a solid between its nodes: an elastic ball landing with
its pole on a box edge stopped at 3.34 ms with "penetration not held" (the edge in the ball's
facets; before the edges were measured it completed with the edge inside the ball)."""

import numpy as np
import pytest
from test_stress_3d import check_box_slip_rows

from fecontact import Model, simulate
from fecontact.bodies import LinearElastic, RigidBody3D, Solid
from fecontact.bodies.shapes3d import Box
from fecontact.contact import Contact
from fecontact.contact.box_edges import BoxEdges
from fecontact.contact.rigid_distance import FeatureDepths, box_features, shape_distance
from fecontact.rotations import exp
from fecontact.scenes import wave_step
from fecontact.testing import group_gradient_error
from fecontact.time.settings import IntegratorOptions

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
EDGE_DOWN = np.array([0.0, np.pi / 4, 0.0])  # the box's edge along y lowest, level


def _edge_rows(model) -> BoxEdges:
    return next(pair for pair in model.contacts.pairs if isinstance(pair, BoxEdges))


def edge_first(method, lift, sides=(0.04, 0.03, 0.02), turn=EDGE_DOWN):
    """A rigid box of ``sides`` (m) over a 4 × 4 slab (0.1 m, 2.5 cm cells), its lowest edge
    ``lift`` (m) above the top face, level and between the nodes (x = 6 mm)."""
    slab = Solid.box([-0.05, -0.05, -0.04], [0.05, 0.05, 0.0], (4, 4, 2), RUBBER)
    slab.fix(slab.nodes_where(lambda x: x[2] <= -0.04 + 1e-9))
    box = RigidBody3D.of_density(1000.0, [0.0, 0.0, 0.0], Box(*sides))
    model = Model([slab, box], [Contact(slab, box, method=method)], (0.0, 0.0, -9.81))
    points = box_features(box.shape) @ exp(turn).T
    q0 = np.zeros(model.n)
    low = points[np.argmin(points[:, 2])]
    q0[slab.ndof :] = [0.006 - low[0], -0.004, lift - low[2], *turn]
    return model, q0


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_a_box_edge_between_the_nodes_is_read_by_its_rows(method):
    """The lowest edge level and 1 mm into the flat slab between two lines of nodes: every
    node is outside the box, the corners are beside the slab's nodes, and the rows of the
    boundary edges the box edge crosses read −1 mm (their common normal is the slab's)."""
    model, q0 = edge_first(method, -0.001)
    pair = model.contacts.pairs[0]
    assert np.all(pair.gaps(q0)[np.isfinite(pair.gaps(q0))] > 0.0)
    g = _edge_rows(model).gaps(q0)
    crossed = np.flatnonzero(np.isfinite(g) & (g < 0.0))
    assert crossed.size >= 2
    # (coordinates of 0.05 m: a few ulps of them)
    assert g[crossed] == pytest.approx(-0.001, abs=1e-15)
    model, q0 = edge_first(method, 0.001)
    g = _edge_rows(model).gaps(q0)
    assert np.min(g) == pytest.approx(0.001, abs=1e-15)


def _ball_and_box(inside=0.0, refinements=1):
    """``ball_drop``'s elastic ball over a fixed rigid box, its pole ``inside`` (m) from the
    box's edge along y, turned so that no boundary edge of the ball lies along the box's."""
    ball = Solid.ball([0.0, 0.0, 0.051], 0.05, refinements, RUBBER)
    box = RigidBody3D.uniform(1000 * ball.mass, [0.15 - inside, 0.0, -0.025], Box(0.3, 0.3, 0.05))
    return ball, box.fix()


def test_edge_rows_have_the_exact_gradient():
    """Central differences of the rows over their 12 dofs (the box's translations and
    body-frame rotation increments, the boundary edge's two nodes) against G, over a ball
    pressed on a box edge at random poses, the release ramps included (rows whose closest
    points lie beyond a segment's end or whose normal lies outside the box edge's cone), the
    wedge's test lifted (every pair admitted, as while held: the test chooses rows, not their
    gradient, and most rows beyond a ridge's end here clear the wedge)."""
    ball = Solid.ball([0.0, 0.0, 0.0], 0.05, 1, RUBBER)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(0.1, 0.08, 0.06))
    model = Model([ball, box], [Contact(ball, box, method="node-to-surface")], (0, 0, 0))
    edges, n = _edge_rows(model), ball.ndof
    rng = np.random.default_rng(1)
    h, checked, ramped = 1e-7, 0, 0
    for _ in range(40):
        psi = rng.normal(size=3)
        q = np.zeros(model.n)
        q[:n] = rng.normal(size=n) * 3e-4
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        points = box_features(box.shape) @ exp(psi).T  # a box edge at the sphere along d
        q[n:] = [*(d * 0.05 - points[np.argmin(points @ d)] + d * rng.uniform(-3e-3, 3e-3)), *psi]
        edges._held = np.ones((len(edges.ridges), len(edges.a)), dtype=bool)
        g, dofs, G, _ = edges.evaluate(q)
        ramped += int(np.count_nonzero(edges._geometry(q)[-1][np.isfinite(g)] > 0.0))

        rows = np.flatnonzero(np.isfinite(g))
        # (central differences of O(1) slopes: h² g''' + round-off 1e-17/h)
        assert group_gradient_error(edges, model, q, np.unique(dofs[rows]), h) < 1e-7
        checked += rows.size
        edges.release_rows()
    assert checked > 25 and ramped > 10, (checked, ramped)


def test_rows_past_the_cone_border_have_the_exact_gradient():
    """A ball flattened on a box face across its edge (its low nodes pressed to the face,
    2e-5 m of noise): boundary edges lying on the face cross the box edge with their common
    normal at the border of the box edge's cone, some past it, where the release ramp in ψ
    acts (the random poses above meet only the ramp past a ridge's end). Central
    differences against G there."""
    ball, box = _ball_and_box(inside=0.005, refinements=2)
    model = Model([ball, box], [Contact(ball, box)], (0.0, 0.0, 0.0))
    edges, n = _edge_rows(model), ball.ndof
    X = ball.positions(np.zeros(n))
    low = X[:, 2] < 0.012
    rng = np.random.default_rng(2)
    past = 0
    for _ in range(3):
        u = np.zeros_like(X)
        u[low, 2] = -X[low, 2] + rng.normal(size=low.sum()) * 2e-5
        q = np.zeros(model.n)
        q[:n] = u.ravel()
        g, dofs, _, _ = edges.evaluate(q)
        _, _, _, _, _, t, _, ramp = edges._geometry(q)
        rows = np.flatnonzero(np.isfinite(g))
        past += int(np.count_nonzero((ramp[rows] > 0.0) & (t[rows] > 0.0) & (t[rows] < 1.0)))
        # (central differences of O(1) slopes at h = 1e-8: h² g''' + round-off 1e-17/h; the
        # ramp's kink at the border lies farther than h from every row here)
        assert group_gradient_error(edges, model, q, np.unique(dofs[rows]), 1e-8) < 1e-7
    assert past >= 2, past


def test_edge_rows_slip_between_the_edge_and_the_boundary_edge():
    """Friction on the edge rows: the slip over a small step is the slip rows times that
    step, to second order, and a motion of the box and the solid together slips by
    nothing."""
    model, q = edge_first("mortar", -0.001)
    check_box_slip_rows(_edge_rows(model), model, q)


def test_a_ridge_on_the_face_beside_the_edge_has_no_row_below_zero():
    """A ball resting on a box face 5 mm inside an edge: a boundary edge from the pole runs
    along the box edge 5 mm from it, and the two lines' common normal lies along the face.
    Their distance (−5 mm) is no penetration: the normal lies outside the cone of the
    boundary edge's two triangles, and no row reads it."""
    ball, box = _ball_and_box(inside=0.005, refinements=2)
    model = Model([ball, box], [Contact(ball, box)], (0.0, 0.0, -9.81))
    q = np.zeros(model.n)
    q[2 : ball.ndof : 3] = -0.001  # the pole on the face
    g = _edge_rows(model).gaps(q)
    assert np.min(g) > 0.0


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_a_box_dropped_edge_first_is_held_at_its_edge(method):
    """A bar (2 × 20 × 2 cm) dropped at 1 m/s with its lowest edge level across the slab,
    between two lines of nodes, its corners beyond the slab: the edge rows take the load and
    hold, and no point of the box's edges enters the slab's facets (the watch's 7 points an
    edge)."""
    model, q0 = edge_first(method, 0.001, sides=(0.02, 0.2, 0.02))
    v0 = np.zeros(model.n)
    v0[-4] = -1.0
    edges, watch = _edge_rows(model), FeatureDepths(model.contacts.pairs[0])
    rows = np.flatnonzero(model.contacts.owner == model.contacts.pairs.index(edges))
    deepest, inside, pressed = 0.0, 0.0, 0
    for st in simulate(model, wave_step(model.bodies[0], 1.0), 0.01, IntegratorOptions(),
                       q0=q0, v0=v0):  # fmt: skip
        deepest = max(deepest, -float(np.min(edges.gaps(st.q))))
        inside = max(inside, watch.depth(st.q)[0])
        pressed += bool(st.pressed()[rows].any())
    assert pressed > 0
    # held as any gap, to the correction's tolerance on the gaps (tol_gap)
    assert deepest < 1e-12 and inside < 1e-12


def test_a_ball_landing_with_its_pole_on_a_box_edge_completes():
    """``ball_drop``'s ball (refinements 2) at 1 m/s with its pole over a box edge, through
    the impact: the edge rows hold the edge out of the ball's facets at every step."""
    ball, box = _ball_and_box(inside=0.0, refinements=2)
    model = Model([ball, box], [Contact(ball, box)], (0.0, 0.0, -9.81))
    watch = FeatureDepths(model.contacts.pairs[0])
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    inside, steps = 0.0, 0
    for st in simulate(model, wave_step(ball, 1.0), 0.004, IntegratorOptions(), v0=v0):
        inside = max(inside, watch.depth(st.q)[0])
        steps += 1
    assert steps > 30 and inside < 1e-12


@pytest.mark.parametrize("inside, steps", [(0.0, 31), (0.005, 23)])
def test_a_ball_pressed_by_a_box_edge_reads_neither_p_nor_k(inside, steps):
    """``ball_drop``'s ball (refinements 2) at 3 m/s with its pole on a box edge (through 31
    steps of Δx/c) and 5 mm inside it (23 steps): its ridges pressed flat on the box's top face
    beside the edge have their common normal on the face's normal, where the cone ramp
    starts, and their rows are redundant with the face nodes' rows. Round-off chose the row's
    gradient at the ramp's kink, the split of the correction's force (LU), whether the
    restarted acceleration's active set repeated, and whether a 1e-17 N s impulse restarted
    it: k ÷ 100 moved a node by 5.5e-6 m (1.1e-4 R) at the 31st step on the edge, by 3.6e-4 R
    at the 22nd 5 mm inside. Now p × 1000 and k ÷ 100 take the same path."""
    import dataclasses
    import warnings

    ball, box = _ball_and_box(inside=inside, refinements=2)
    model = Model([ball, box], [Contact(ball, box, method="mortar")], (0.0, 0.0, -9.81))
    v0 = model.translation(ball, (0.0, 0.0, -3.0))
    dt = wave_step(ball, 1.0)
    base = IntegratorOptions()
    # no NaN on the way: a box edge's row held by the smooth step's force loses its gap
    # (+inf) at an iterate of a correction on the edge (its common normal leaves the
    # ridge's cone), and as an equality it made the update NaN
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        runs = [
            [st.q.copy() for st in simulate(model, dt, steps * dt, options, v0=v0)]
            for options in (
                base,
                dataclasses.replace(base, penalty_scale=1e3),
                dataclasses.replace(base, multiplier_scale=1e-2),
            )
        ]
    for other in runs[1:]:
        drift = max(np.max(np.abs(a - b)) for a, b in zip(runs[0], other, strict=True))
        # (the solves' round-off, ≤ 6.5e-16 R measured; a different path is 1e-5 R or more)
        assert drift <= 1e-12 * 0.05


def _overhang(lift):
    """The 2 × 2 × 1 cm rubber box (2 × 2 × 1 cells) ``lift`` (m) over a fixed rigid box
    12 × 8 × 1 cm whose top edge runs under it at x = −2.5 mm, between two lines of its
    bottom nodes (the box overhanging it by 7.5 mm)."""
    box = Solid.box([-0.01, -0.01, lift], [0.01, 0.01, lift + 0.01], (2, 2, 1), RUBBER)
    base = RigidBody3D.uniform(1.0, [0.0575, 0.0, -0.005], Box(0.12, 0.08, 0.01)).fix()
    model = Model([box, base], [Contact(box, base, method="mortar")], (0.0, 0.0, -9.81))
    return box, base, model


def test_a_far_ridge_reads_no_penetration_over_a_box_edge():
    """The boundary edges of the box's face over the rigid box (x = +1 cm) have lines whose
    common normal with the rigid edge's is x, 1.25 cm behind the face: their rows read that
    distance, −1.18e-2 m with the release ramp 0.5 mm above (the closest point 5 % beyond
    the ridge's lower end), −1.25e-2 m laid on it. The ridge lies wholly in front of the
    rigid box's top face (it clears the edge's wedge along its normal with less motion than
    along the lines' normal) and has no row: the least gap is its lower node's."""
    for lift in (5e-4, 0.0):
        box, _, model = _overhang(lift)
        q = np.zeros(model.n)
        g = _edge_rows(model).gaps(q)
        # (the gaps of nodes at z = lift: a few ulps of the coordinates, 0.06 m)
        assert np.min(g) == pytest.approx(lift, abs=1e-16)
        assert np.min(model.contacts.gaps(q)) == pytest.approx(lift, abs=1e-16)


def test_a_box_laid_over_a_box_edge_rests_on_it():
    """The box laid on the rigid box at rest under gravity (refused at t = 0 before: a far
    ridge's row read −1.25e-2 m), 10 steps of 0.5 ms: the rows of its bottom ridges that
    cross the rigid edge hold it, and the depth the run reports at each step is the one read
    from the states, the box's nodes in the rigid box and the rigid edge's points in the
    box's facets."""
    box, base, model = _overhang(0.0)
    edges = _edge_rows(model)
    watch = FeatureDepths(model.contacts.pairs[0])
    rows = np.flatnonzero(model.contacts.owner == model.contacts.pairs.index(edges))
    R, c = exp(np.zeros(3)), base.center(np.zeros(6))
    pressed, steps = 0, 0
    for st in simulate(model, 5e-4, 5e-3, IntegratorOptions()):
        x = box.positions(st.q[: box.ndof])
        nodes = -np.min(shape_distance(base.shape, (x - c) @ R, False)[0])
        depth = max(nodes, watch.depth(st.q)[0], 0.0)
        # (both read the same coordinates: a few ulps of them, 0.06 m)
        assert st.penetration == pytest.approx(depth, abs=1e-16)
        # held as any gap, to the correction's tolerance on the gaps (tol_gap)
        assert depth < 1e-12
        pressed += bool(st.pressed()[rows].any())
        steps += 1
    assert steps == 11 and pressed == steps


def test_a_pair_the_wedge_admits_is_held_through_a_loop():
    """The rubber box moved 1 cm toward the rigid box's edge and sunk 3.5 mm: its face
    x = +1 cm lies 2.5 mm beyond the edge and 2.5 mm below the top face, and the ridges of
    that face cross the edge, reading −2.5 mm. Held from there (a Newton loop's start), the
    rows stay with the box back over the edge, where the wedge's test alone leaves the
    face's diagonals out (their lines read −1.18e-2 m there)."""
    box, _, model = _overhang(5e-4)
    edges = _edge_rows(model)
    crossing, over = np.zeros(model.n), np.zeros(model.n)
    crossing[0 : box.ndof : 3], crossing[2 : box.ndof : 3] = -0.01, -0.003
    g = edges.gaps(crossing)
    far = np.isfinite(g) & ~np.isfinite(edges.gaps(over))
    # (coordinates of 0.06 m: a few ulps of them)
    assert far.sum() == 5 and g[far] == pytest.approx(-0.0025, abs=1e-15)
    edges.hold_rows(crossing)
    held = edges.gaps(over)
    edges.release_rows()
    # the face's two diagonals (the other three ridges have no row there by the other tests)
    kept = np.isfinite(held) & ~np.isfinite(edges.gaps(over))
    assert kept.sum() == 2 and np.all(far[kept])
    assert held[kept] == pytest.approx(-0.01179289, abs=1e-8)  # (printed to 7 digits)
