"""Dual mortar contact of a 3D solid against the exact surface of a rigid body in space
(fecontact.contact.mortar_rigid3d): rows against central differences, the patch test on a flat
box face, Newton's quadratic rate, and impacts against exact answers."""

import warnings

import numpy as np
import pytest

from fecontact import Model, simulate
from fecontact.bodies import LinearElastic, RigidBody3D, Solid
from fecontact.bodies.shapes3d import Ball, Box, Capsule
from fecontact.contact import Contact, Plane
from fecontact.contact.mortar_rigid3d import MortarRigid3D
from fecontact.contact.rigid_distance import feature_weights, triangle_rule
from fecontact.contact.solid_rigid3d import NodeBoxContact
from fecontact.errors import InputError
from fecontact.rotations import exp
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation, run
from fecontact.testing import block_on_rigid_box, group_derivative_errors
from fecontact.time.settings import IntegratorOptions

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
R = 0.05


def pair_at(shape, below, refinements=1):
    ball = Solid.ball([0.01, 0.02, R + 0.01], R, refinements, RUBBER)
    rigid = RigidBody3D.uniform(1.0, [0.0, 0.0, below], shape)
    pair = Contact(ball, rigid)
    return pair, Model([ball, rigid], [pair], gravity=(0.0, 0.0, 0.0))


@pytest.mark.parametrize(
    "shape, below, step",
    [
        (Ball(0.04), -0.03, 1e-6),  # a curved master
        (Box(0.3, 0.2, 0.05), -0.0245, 1e-6),  # the ball's bottom pressed into a face
        (Box(0.08, 0.06, 0.05), -0.0245, 1e-7),  # the box's edges under the ball
        (Box(0.08, 0.06, 0.05), 0.02, 1e-6),  # the ball cut deep by the box
    ],
)
def test_mortar_rows_are_the_derivatives_of_the_weighted_gaps(shape, below, step):
    """G against central differences of the rows along every dof (the rigid rotation in the
    body frame, composed on the right), the curvature against those of G. The differences'
    own error is O(step²) times the third derivative of the distance, large near a box edge
    (1/distance²): measured 6.4e-7 at 1e-6 and 6.3e-9 at 1e-7 there, so that case takes
    1e-7; the bound 1e-6 relative to the largest curvature holds every case with a margin of
    10 or more."""
    pair, model = pair_at(shape, below)
    assert isinstance(pair, MortarRigid3D)
    rng = np.random.default_rng(2)
    q = 2e-3 * rng.normal(size=model.n)
    q[-3:] = [0.2, -0.3, 0.4]
    g, dofs, _, _ = pair.evaluate(q)
    assert np.isfinite(g).sum() >= 10  # the rows within the margin's bound
    err_g, err_h = group_derivative_errors(pair, model, q, np.unique(dofs), step)
    assert err_g <= 1e-8 and err_h <= 1e-6


def test_triangle_rule_is_of_degree_five_on_every_subdivision():
    """∫ λ₁^a λ₂^b λ₃^c dA / |e| = 2 a! b! c! / (a + b + c + 2)! for a + b + c ≤ 5."""
    from math import factorial

    for s in (1, 2, 4):
        lam, w = triangle_rule(s)
        for a, b, c in [(0, 0, 0), (1, 0, 0), (2, 1, 0), (1, 1, 1), (3, 2, 0), (2, 2, 1)]:
            exact = 2.0 * factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 2)
            got = np.sum(w * lam[:, 0] ** a * lam[:, 1] ** b * lam[:, 2] ** c)
            assert got == pytest.approx(exact, rel=1e-13)


def block_over_box(turn=(0.0, 0.0, 0.0), strain=None):
    """A solid block above a wide rigid box, moved rigidly by ``turn`` (a rotation vector)
    and a lift, or stretched by the affine map I + ``strain``: every point of the block lies
    over the box's top face, where the distance is linear. Returns the pair and the rows,
    nodal distances and the current over reference areas of the nodes at that q."""
    block = Solid.box([-0.05, -0.04, 0.0], [0.05, 0.04, 0.03], (3, 2, 2), RUBBER)
    box = RigidBody3D.uniform(10.0, [0.01, -0.02, -0.05], Box(0.6, 0.5, 0.1))
    pair = Contact(block, box)
    model = Model([block, box], [pair], gravity=(0.0, 0.0, 0.0))
    X = block.X
    F = exp(np.asarray(turn)) if strain is None else np.eye(3) + strain
    x = (X - X.mean(axis=0)) @ F.T + X.mean(axis=0) + [0.003, -0.002, 0.01]
    q = np.zeros(model.n)
    q[: block.ndof] = (x - X).ravel()
    q[block.ndof + 3 :] = [0.01, -0.02, 0.03]  # the box turned a little about its centre
    return pair, q


def test_patch_test_the_rows_of_a_flat_face_are_the_nodes_own_gaps():
    """A gap field linear on every slave triangle (a block above a box face): the weighted
    gap of each node is its own distance (biorthogonality on the reference triangle,
    ∫ Φ_j λ_k dA₀ = δ_jk |e|₀/3) to round-off, the block moved rigidly or stretched by 5 %."""
    for moved_block in (block_over_box(turn=(0.05, -0.08, 0.3)),
                        block_over_box(strain=np.array([[0.02, 0.01, 0.0], [0.0, -0.03, 0.02],
                                                        [0.01, 0.0, 0.05]]))):  # fmt: skip
        pair, q = moved_block
        d = pair.node_distances(q)
        assert d.min() > 0.0  # every node above the box
        np.testing.assert_allclose(pair.gaps(q), d, rtol=1e-12, atol=1e-15)


def test_mortar_is_the_default_and_the_options_are_checked_by_name():
    """Mortar for a 3D solid and a RigidBody3D named either way; ``method="node-to-surface"``
    keeps the node pair; ``nodes`` under mortar, other shapes and bad options are refused
    with the parameter's name before any work."""
    ball = Solid.ball([0.0, 0.0, R], R, 1, RUBBER)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.1], Box(0.2, 0.2, 0.1))
    assert isinstance(Contact(box, ball), MortarRigid3D)
    assert Contact(box, ball).body is ball
    assert isinstance(Contact(ball, box, method="node-to-surface"), NodeBoxContact)
    with pytest.raises(InputError, match="nodes: a mortar contact"):
        Contact(ball, box, nodes=[0, 1])
    with pytest.raises(InputError, match="Ball or a Box"):
        Contact(ball, RigidBody3D.uniform(1.0, [0.0, 0.0, -0.1], Capsule(0.05, 0.2)))
    with pytest.raises(InputError, match="subdivisions"):
        MortarRigid3D(ball, box, subdivisions=0)
    with pytest.raises(InputError, match="restitution"):
        Contact(ball, box, restitution=1.5)
    with pytest.raises(InputError, match="method"):
        Contact(ball, box, method="segments")


def newton_residuals(shape, below):
    """Newton's method on the projection of a ball pressed into a rigid shape onto the
    weighted gaps' surface: min ½|q − q₀|² over the ball's dofs subject to g_j(q) = 0 on the
    rows pressed at q₀, with the rows' exact curvature in the matrix. Returns |r| per
    iteration."""
    pair, model = pair_at(shape, below, refinements=2)
    n = pair.body.ndof
    q0 = np.zeros(model.n)
    q0[n:] = [0.0, 0.0, 0.0, 0.1, -0.2, 0.3]  # the rigid body turned, held there
    g, dofs, _, _ = pair.evaluate(q0)
    rows = np.flatnonzero(g < 0.0)
    assert len(rows) >= 2
    q, lam, out = q0.copy(), np.zeros(len(rows)), []
    for _ in range(8):
        g, dofs, Gv, _ = pair.evaluate(q)
        G = np.zeros((len(rows), model.n))
        np.add.at(G, (np.arange(len(rows))[:, None], dofs[rows]), Gv[rows])
        r = np.concatenate([q[:n] - q0[:n] + G[:, :n].T @ lam, g[rows]])
        out.append(np.linalg.norm(r))
        if out[-1] < 1e-14:
            break
        C = np.zeros((model.n, model.n))
        H = pair.hessians(q, rows)
        np.add.at(C, (dofs[rows][:, :, None], dofs[rows][:, None, :]), lam[:, None, None] * H)
        S = np.block([[np.eye(n) + C[:n, :n], G[:, :n].T], [G[:, :n], np.zeros((len(rows),) * 2)]])
        step = np.linalg.solve(S, -r)
        q[:n] += step[:n]
        lam += step[n:]
    return np.array(out)


@pytest.mark.parametrize("shape, below", [(Ball(0.015), 0.009), (Box(0.08, 0.06, 0.05), -0.013)])
def test_newton_converges_quadratically_with_the_rows_curvature(shape, below):
    """|r_{k+1}| ≤ C |r_k|² with C of the order of the curvature (1/m); a first-order
    curvature would give a linear rate. A ball's rows are the nodes' own distances (its
    centre has rows of its own where the triangles outgrow it), which are linear along the
    radial line the projection moves each node on: one step lands (3.9e-3, 2.5e-18); on a
    box face the rows are the nodes' own distances too (7e-3, 0). The weighted rows'
    curvature is checked against differences above (11 rows on a box edge's ramp)."""
    r = newton_residuals(shape, below)
    assert r[-1] < 1e-13 * max(1.0, r[0]) or r[-1] < 1e-14
    rates = r[2:] / r[1:-1] ** 2
    assert len(r) <= 6
    assert np.all(rates[r[2:] > 1e-13] < 1e3)


def drop_on(floor: str, offset=(0.0, 0.0)):
    """The elastic ball of ``ball_drop`` (P1, 2 refinements) at 1 m/s, its lowest point
    2 mm up, onto a rigid plane (node-to-surface) or onto a rigid box 1000 times its mass
    standing on three corners on that plane (mortar, the default), at Δx/c, for 8 ms.
    Returns the centre-of-mass velocity (steps, 3) and the deepest node inside the floor by
    the nodes' own coordinates (the floor's top is flat: −z of the ball's lowest node over
    the box's top, whatever the solver's gaps say), over the ball's shortest edge."""
    ball = Solid.ball([offset[0], offset[1], R + 0.002], R, 2, RUBBER)
    side, g = 0.05, (0.0, 0.0, -9.81)
    if floor == "plane":
        model, top = Model([ball], [Contact(ball, Plane([0, 0, 0], [0, 0, 1]))], g), None
    else:
        box = RigidBody3D.uniform(1000.0 * ball.mass, [0.0, 0.0, -side / 2], Box(0.3, 0.3, side))
        corners = [i for i, v in enumerate(box.shape.vertices) if v[2] < 0][:3]
        pairs = [Contact(ball, box), Contact(box, Plane([0, 0, -side], [0, 0, 1]), nodes=corners)]
        assert isinstance(pairs[0], MortarRigid3D)
        model, top = Model([ball, box], pairs, g), ball.ndof + 2
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    vc, depth = [], 0.0
    # impacts at the step's end on every floor: "auto" localizes a model of solids alone,
    # not one with a rigid body, and the floors are compared by one step algorithm
    opts = IntegratorOptions(localize=False)
    for st in simulate(model, wave_step(ball, 1.0, None), 0.008, opts, v0=v0):
        vc.append((model.M_full @ st.v)[: ball.ndof].reshape(-1, 3).sum(axis=0) / ball.mass)
        z = ball.positions(st.q[: ball.ndof])[:, 2] - (0.0 if top is None else st.q[top])
        depth = max(depth, -z.min())
    return np.array(vc), depth / ball.min_edge_length


def test_an_elastic_ball_rebounds_from_a_heavy_box_with_mortar_as_from_the_plane():
    """Mortar on the box's flat top face against node-to-surface on a plane at the same
    height: the same rebound (the rows are the nodes' own gaps there, the patch test; measured
    equal to 5e-10 m/s), restitution within 2 %, lateral centre-of-mass speed ≤ 1 % of the
    approach speed, no node inside the box beyond 1 % of an edge (measured 3e-15 m)."""
    plane, _ = drop_on("plane")
    box, depth = drop_on("box", offset=(0.013, -0.021))
    assert box[-1, 2] > 0.9  # it has bounced
    assert box[-1, 2] == pytest.approx(plane[-1, 2], rel=0.02)
    assert np.abs(box[:, :2]).max() <= 0.01
    assert depth <= 0.01
    np.testing.assert_allclose(box[:, 2], plane[:, 2], atol=1e-8)


def slab_drop(fraction=1.0, options=None, t_end=0.0075, out=None):
    """A rigid ball (radius 5 cm, 1000 kg/m³) at 1 m/s, 1 mm above an elastic slab
    (0.1 × 0.1 × 0.04 m, 8 × 8 × 3 cells, clamped at its base), mortar against the ball's
    exact sphere, at ``fraction`` of the slab's Δx/c. Returns the states (or, with ``out``
    a folder, the run's summary and its states)."""
    width, thick, radius = 0.1, 0.04, 0.05
    slab = Solid.box([-width / 2, -width / 2, -thick], [width / 2, width / 2, 0.0], (8, 8, 3),
                     RUBBER)  # fmt: skip
    slab.fix(slab.nodes_where(lambda x: x[2] <= -thick * (1.0 - 1e-9)))
    ball = RigidBody3D.of_density(1000.0, [0.003, -0.002, radius + 0.001], Ball(radius))
    pair = Contact(slab, ball)
    assert isinstance(pair, MortarRigid3D)
    model = Model([slab, ball], [pair], (0.0, 0.0, -9.81))
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    dt = fraction * wave_step(slab, 1.0)
    if out is None:
        return list(simulate(model, dt, t_end, options or IntegratorOptions(), v0=v0))
    sim = Simulation(model, dt=dt, t_end=t_end, name="rigid_ball_on_slab", v0=v0,
                     output_interval=t_end)  # fmt: skip
    return run(sim, out, frames=False, checkpoint_every=0)


def turning_time(states) -> float:
    """The instant (s) the ball's vertical velocity turns from down to up (its deepest
    point), interpolated linearly within the step."""
    t, v = np.array([s.t for s in states]), np.array([s.v[-4] for s in states])
    i = np.flatnonzero((v[:-1] < 0.0) & (v[1:] >= 0.0))[0]
    return t[i] - v[i] * (t[i + 1] - t[i]) / (v[i + 1] - v[i])


def test_a_rigid_ball_on_an_elastic_slab_is_hertz_like_without_halving(tmp_path):
    """At the slab's Δx/c: no step halved, the ball's turning instant within 0.5 % of the run
    at a quarter of the step (measured 3.7386 against 3.7372 ms; with the dual weighted gaps
    the stand-off took it 0.51 ms earlier), the ball rebounds, the energy ledger's
    ``created`` is small (bound 1 %, made in the position correction of the persistent
    contact, which the run's warning names), no slave node lies deeper in the ball than 1 %
    of its shortest edge (the watch's exact distances), and no contact is taken before the
    nearest node reaches the sphere (its gap 1.13 mm at 1 m/s; the dual weighted gaps took it
    at 0.54 ms, the surfaces 0.46 mm apart)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        summary = slab_drop(out=tmp_path)
    assert all("position correction" in str(w.message) for w in caught)
    assert summary["status"] == "completed" and summary["step_halvings"] == 0
    ledger = summary["energy_ledger"]
    assert 0.0 <= ledger["created"] <= 0.01 * ledger["scale"]
    coarse = slab_drop()
    fine = slab_drop(fraction=0.25)
    assert sum(s.halvings for s in coarse) == 0
    assert turning_time(coarse) == pytest.approx(turning_time(fine), rel=0.005)
    assert coarse[-1].v[-4] > 0.9  # the ball's vertical velocity: it has rebounded
    assert max(s.mortar_depth for s in coarse) <= 0.01
    first = next(s.t for s in fine if np.any(s.lam > 0.0) or np.any(s.impulse > 0.0))
    dt = fine[1].t - fine[0].t
    gap = min(fine[0].gaps)  # the nearest node's distance to the sphere at t = 0
    assert first > gap / 1.0 - dt  # 1 m/s: the step that takes the contact ends after it


@pytest.fixture(scope="module")
def slab_base():
    """The slab drop at the default p and k, run once for both changes."""
    return slab_drop(t_end=0.003)


@pytest.mark.parametrize("change", [{"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}])
def test_the_rigid_ball_on_the_slab_is_independent_of_p_and_k(change, slab_base):
    """p × 1000 and k / 100 change the trajectory by round-off (bound 1e-8 of the radius)."""
    base = slab_base
    other = slab_drop(options=IntegratorOptions(**change), t_end=0.003)
    diff = max(np.max(np.abs(a.q - b.q)) for a, b in zip(base, other, strict=True))
    assert diff <= 1e-8 * 0.05


def test_the_slip_rows_read_no_slip_in_a_motion_of_both_bodies_together():
    """A ball sunk over a box edge at a random pose, both bodies moving as one rigid body (a
    random translation and spin, 12 m/s at most): every slip row, the weighted ones too
    (their sums over the rules' points, 8 of 14 rows here), reads no slip, the blocks of the
    solid's nodes, the box's translation and its turn cancelling. Measured 5.6e-16 m/s
    (4.5e-17 of the speed: round-off of sums of some 10² products of its size); a block
    wrong by a sign or an arm's origin reads the speed itself. Bound 1e-14 of the speed."""
    solid = Solid.ball([0.05, 0.0, 0.045], R, 1, RUBBER)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.025], Box(0.1, 0.1, 0.05))
    model = Model([solid, box], [Contact(solid, box, friction=0.3)], gravity=(0.0, 0.0, 0.0))
    pair = model.contacts.pairs[0]
    rng = np.random.default_rng(5)
    q = 1e-3 * rng.normal(size=model.n)
    ss, sb = model.body_slice(0), model.body_slice(1)
    q[sb][3:6] = [0.05, -0.03, 0.1]
    x, R_, c = solid.positions(q[ss]), exp(q[sb][3:6]), box.center(q[sb])
    a, w = rng.normal(size=3), 10.0 * rng.normal(size=3)
    v = np.zeros(model.n)
    v[ss] = (a + np.cross(w, x - c)).ravel()
    v[sb][:3], v[sb][3:6] = a, R_.T @ w  # (the body-frame spin)
    dofs, W, _ = pair.tangents(q)
    weighted = feature_weights(box.shape, (x[pair.nodes] - c) @ R_, pair.reference_reach)[0] > 0
    assert np.sum(weighted & (np.abs(W).sum(axis=(1, 2)) > 0.0)) >= 4
    slip = np.einsum("mtk,mk->mt", W, v[dofs])
    assert np.abs(slip).max() <= 1e-14 * np.abs(v).max()


def test_a_block_sliding_on_a_rigid_box_stops_where_coulomb_says():
    """Mortar slip rows with μ = 0.3: a block (2 × 2 × 1 cells) launched at 0.5 m/s on a fixed
    box stops after v₀²/(2μg) = 42.474 mm at t = v₀/(μg) = 0.170 s (measured 42.474 mm, the
    residual speed 4e-11 m/s); the bound 1e-5 m is the step's reach of the stopping instant
    (v h² μ g)."""
    block = Solid.box([-0.02, -0.02, 0.0], [0.02, 0.02, 0.02], (2, 2, 1), RUBBER)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.05], Box(1.0, 1.0, 0.1)).fix()
    model = Model([block, box], [Contact(block, box, friction=0.3)], (0.0, 0.0, -9.81))
    v0 = model.translation(block, (0.5, 0.0, 0.0))
    w = block.mass_matrix() @ block.translation_field((1.0, 0.0, 0.0)) / block.mass
    states = list(simulate(model, 1e-3, 0.25, IntegratorOptions(), v0=v0))
    x = np.array([w @ s.q[: block.ndof] for s in states])
    assert x[-1] == pytest.approx(0.25 / (2 * 0.3 * 9.81), abs=1e-5)
    assert abs(w @ states[-1].v[: block.ndof]) <= 1e-8
    assert max(s.penetration for s in states) <= 1e-9


def test_a_block_pressed_on_a_box_carries_a_uniform_pressure():
    """Mortar (the default) and node-to-surface beside it: the bottom pressure is the load,
    1 kPa, at every bottom node to 1e-8 relative (measured 6e-13 and 4e-13): on a flat face
    the weighted gaps are the nodal gaps and the multipliers the nominal pressure times the
    nodes' areas."""
    for method in (None, "node-to-surface"):
        pressure, speed = block_on_rigid_box(method)
        assert speed < 1e-12  # at rest
        np.testing.assert_allclose(pressure, 1e3, rtol=1e-8)


@pytest.mark.parametrize("shape, below", [(Ball(0.04), -0.02), (Box(0.08, 0.06, 0.05), -0.013)])
def test_rows_left_out_are_beyond_the_margin(shape, below):
    """A row reported +inf (its node farther than margin + LIPSCHITZ × its longest edge) has a
    weighted gap above the margin, and the rows kept are those of the whole integral: on
    deformed balls (refinements 2) against a rigid ball and a box, margins 1-8 mm."""
    ball = Solid.ball([0.01, 0.02, R + 0.01], R, 2, RUBBER)
    rigid = RigidBody3D.uniform(1.0, [0.0, 0.0, below], shape)
    everything = MortarRigid3D(ball, rigid, margin=1.0)
    Model([ball, rigid], [everything], gravity=(0.0, 0.0, 0.0))
    rng = np.random.default_rng(5)
    for margin in (1e-3, 3e-3, 8e-3):
        pair = MortarRigid3D(ball, rigid, margin=margin)
        model = Model([ball, rigid], [pair], gravity=(0.0, 0.0, 0.0))
        q = 3e-3 * rng.normal(size=model.n)
        g, full = pair.gaps(q), everything.gaps(q)
        kept = np.isfinite(g)
        assert np.all(np.isfinite(full))
        assert 0 < kept.sum() < pair.size
        np.testing.assert_allclose(g[kept], full[kept], rtol=0, atol=1e-15)
        assert np.all(full[~kept] > margin)


@pytest.mark.parametrize("mu, v0", [(0.0, (0.0, 0.0, -1.0)), (0.3, (0.5, 0.2, -1.0))])
def test_a_free_box_takes_the_momentum_the_ball_loses_through_mortar_rows(mu, v0):
    """No gravity, the ball (refinements 2) thrown off-centre onto a free box twice its mass,
    head-on frictionless or obliquely with μ = 0.3: the normal and slip rows act on the box's
    (u, Θ) as on the ball's nodes, equal and opposite; the total momentum is kept to round-off
    at every step (1.6e-13 and 1.3e-13 of m × 1 m/s measured), the box leaves downwards and
    turns (dragged sideways with friction)."""
    ball = Solid.ball([0.03, -0.02, R + 0.002], R, 2, RUBBER)
    box = RigidBody3D.uniform(2.0 * ball.mass, [0.0, 0.0, -0.025], Box(0.3, 0.3, 0.05))
    model = Model([ball, box], [Contact(ball, box, friction=mu)], (0.0, 0.0, 0.0))
    n = ball.ndof
    p = []
    start = model.translation(ball, v0)
    for st in simulate(model, wave_step(ball, 1.0, None), 0.008, IntegratorOptions(), v0=start):
        mv = model.M_full @ st.v
        p.append(mv[:n].reshape(-1, 3).sum(axis=0) + mv[n : n + 3])
    np.testing.assert_allclose(np.array(p) / ball.mass, [v0] * len(p), atol=1e-10)
    assert st.v[n + 2] < -0.3 and np.linalg.norm(st.v[n + 3 :]) > 0.1
    assert (st.v[n] > 0.05) == (mu > 0.0)  # dragged along the ball's slip


def test_the_watch_reports_the_deepest_node_by_its_exact_distance():
    """The pair's watch joins the model's watches (the run's ``max_penetration`` and the
    mortar-depth warning): a ball sunk 2 mm into a box face reports 2 mm, over the shortest
    edge at its lowest node; lifted clear, 0."""
    ball = Solid.ball([0.0, 0.0, R - 0.002], R, 1, RUBBER)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.05], Box(0.3, 0.3, 0.1))
    model = Model([ball, box], [Contact(ball, box)], gravity=(0.0, 0.0, 0.0))
    (watch,) = model.contacts.watches
    depth, relative = watch.depth(np.zeros(model.n))
    assert depth == pytest.approx(0.002, rel=1e-12)
    assert relative == pytest.approx(0.002 / watch.edge[np.argmin(ball.X[watch.pair.nodes, 2])])
    q = np.zeros(model.n)
    q[: ball.ndof] = model.translation(ball, (0.0, 0.0, 0.003))[: ball.ndof]
    assert watch.depth(q) == (0.0, 0.0)


def hertz_contact_radius(ball: Solid, v: float) -> float:
    """Hertz's contact radius (m) at the peak of an elastic ball's impact at ``v`` (m/s) on a
    rigid flat: δ = (15 m v² / (16 E* √R))^{2/5}, a = √(R δ), E* = E / (1 − ν²)."""
    E_star = RUBBER.E / (1.0 - RUBBER.nu**2)
    delta = (15.0 * ball.mass * v**2 / (16.0 * E_star * np.sqrt(R))) ** 0.4
    return float(np.sqrt(R * delta))


def edge_drop(inside: float, refinements: int = 2) -> np.ndarray:
    """``ball_drop``'s ball (P1) at 1 m/s onto a fixed box whose edge (along y) lies
    ``inside`` (m) from the pole: the ball's centre-of-mass velocity (steps, 3)."""
    ball = Solid.ball([0.0, 0.0, R + 0.002], R, refinements, RUBBER)
    box = RigidBody3D.uniform(1.0, [0.15 - inside, 0.0, -0.025], Box(0.3, 0.3, 0.05)).fix()
    model = Model([ball, box], [Contact(ball, box)], (0.0, 0.0, -9.81))
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    n = ball.ndof
    states = simulate(model, wave_step(ball, 1.0, None), 0.008, IntegratorOptions(), v0=v0)
    return np.array([(model.M_full @ s.v)[:n].reshape(-1, 3).sum(axis=0) / ball.mass
                     for s in states])  # fmt: skip


@pytest.mark.parametrize("inside", [0.01, 0.015, 0.02])
def test_a_ball_landing_inside_a_box_edge_leaves_straight_up_where_its_patch_ends_short(inside):
    """Hertz's contact radius at the peak is 1.00 cm (the 1 cm case only grazes the edge,
    where Hertz's pressure vanishes), so the edge takes no load and the ball leaves straight
    up, as from the face. The nodes' own distances on the face (the rows turn to the weighted
    gap only inside an edge's region) give no lateral force from triangles reaching across the
    edge: measured ≤ 1e-14 of the approach speed at 1, 1.5 and 2 cm (with the dual weighted
    gap of every row: +17.5 %, +4.6 %, 0 at these meshes, and −9.1 %, +1.5 %, 0 one
    refinement finer). Bounds: 1e-9 m/s, Newton's tolerance on the rows; the rebound
    0.95–1.05, the vertical restitution of the same ball on the face."""
    ball = Solid.ball([0.0, 0.0, R + 0.002], R, 2, RUBBER)
    assert hertz_contact_radius(ball, 1.0) == pytest.approx(0.0100, abs=1e-4)
    v = edge_drop(inside)
    assert np.abs(v[:, :2]).max() <= 1e-9
    assert 0.95 <= v[-1, 2] <= 1.05


def small_ball_over_a_node(height: float):
    """A rigid ball (1 cm) ``height`` (m) above a node of a coarse slab (4 × 4 × 1 cells,
    10 cm wide): its triangles (2.5 cm legs) are larger than the ball, so its centre has rows
    of its own against them and the nodes' rows are their distances."""
    slab = Solid.box([-0.05, -0.05, -0.02], [0.05, 0.05, 0.0], (4, 4, 1), RUBBER)
    ball = RigidBody3D.of_density(1000.0, [0.0, 0.0, 0.01 + height], Ball(0.01))
    return Model([slab, ball], [Contact(slab, ball)], (0.0, 0.0, 0.0))


def test_the_initial_state_is_judged_by_the_nodes_and_the_centre_rows():
    """1 mm above a node the dual weighted gap of that node read −0.166 h²/r + 1 mm < 0 (the
    dual functions' negative lobes on the sphere's curvature): a stand-off, admitted with a
    warning. The rows are now the nodes' distances and the centre's distances to the
    triangles, all 1 mm there: admitted without a warning; a node 1 mm inside the ball is
    refused."""
    from fecontact.time.state import initial_state

    model = small_ball_over_a_node(0.001)
    pair, centre = model.contacts.pairs[:2]
    q = np.zeros(model.n)
    assert np.min(pair.gaps(q)) == pytest.approx(1e-3, abs=1e-12)
    assert np.min(centre.gaps(q)) == pytest.approx(1e-3, abs=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        initial_state(model)
    with pytest.raises(InputError, match="penetrates by 1.000e-03 m"):
        initial_state(small_ball_over_a_node(-0.001))
