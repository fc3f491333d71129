"""A 3D solid's nodes against the exact surface of a rigid body in space (a Ball or a Box):
rows by central differences, and an elastic ball bouncing on a rigid box
(fecontact.contact.solid_rigid3d, ``method="node-to-surface"``; the default, mortar, is in
tests/test_mortar_rigid3d.py)."""

import numpy as np
import pytest

from fecontact import Model, simulate
from fecontact.bodies import LinearElastic, RigidBody3D, Solid
from fecontact.bodies.shapes3d import Ball, Box, Capsule
from fecontact.contact import Contact, Plane
from fecontact.contact.solid_rigid3d import NodeBallContact, NodeBoxContact
from fecontact.errors import InputError
from fecontact.rotations import compose
from fecontact.scenes import wave_step
from fecontact.time.settings import IntegratorOptions

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
R = 0.05


def moved(model, q, d):
    out = q + d
    for triple in model.rotations:
        out[triple] = compose(q[triple], d[triple])
    return out


@pytest.mark.parametrize("shape", [Ball(0.04), Box(0.3, 0.2, 0.05)])
def test_node_rows_are_the_derivatives_of_the_gaps(shape):
    """G against central differences (step 1e-6) of the gaps along every dof, the rigid
    rotation in the body frame; the ball's curvature against those of G (the box's is left
    out). Nodes outside and inside the box, on both sides of its corners."""
    ball = Solid.ball([0.01, 0.02, R + 0.01], R, 1, RUBBER)
    below = -0.03 if isinstance(shape, Ball) else 0.02  # the box's top face cuts the ball
    rigid = RigidBody3D.uniform(1.0, [0.0, 0.0, below], shape)
    pair = Contact(ball, rigid, method="node-to-surface")
    assert isinstance(pair, NodeBallContact if isinstance(shape, Ball) else NodeBoxContact)
    model = Model([ball, rigid], [pair], gravity=(0.0, 0.0, 0.0))
    rng = np.random.default_rng(2)
    q = 2e-3 * rng.normal(size=model.n)
    q[-3:] = [0.2, -0.3, 0.4]
    g, dofs, G, H = pair.evaluate(q)
    assert (g < 0).any() == isinstance(shape, Box)
    for j in np.unique(dofs):
        d = np.zeros(model.n)
        d[j] = 1e-6
        gp, _, Gp, _ = pair.evaluate(moved(model, q, d))
        gm, _, Gm, _ = pair.evaluate(moved(model, q, -d))
        col = (dofs == j).astype(float)
        np.testing.assert_allclose((gp - gm) / 2e-6, np.sum(G * col, axis=1), atol=1e-8)
        if H is not None:
            np.testing.assert_allclose((Gp - Gm) / 2e-6, np.einsum("mkl,ml->mk", H, col), atol=1e-6)


def test_other_shapes_are_refused_by_name():
    ball = Solid.ball([0.0, 0.0, R], R, 1, RUBBER)
    capsule = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.1], Capsule(0.05, 0.2))
    for method in ("node-to-surface", None):
        with pytest.raises(InputError, match="Ball or a Box"):
            Contact(ball, capsule, method=method)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.1], Box(0.2, 0.2, 0.1))
    pair = Contact(box, ball, method="node-to-surface")
    assert isinstance(pair, NodeBoxContact)  # named either way round


def ball_drop(floor: str, method="node-to-surface"):
    """The elastic ball of ``ball_drop`` (P1, 2 refinements) at 1 m/s onto a rigid plane, onto
    a rigid box 1000 times its mass standing on that plane, or onto a free box twice its mass
    (no gravity); the step is Δx/c as the case's. Returns the ball's and the box's vertical
    momenta over the run (N·s) and the smallest gap."""
    ball = Solid.ball([0.0, 0.0, R + 0.002], R, 2, RUBBER)
    mb, side = ball.mass, 0.05
    gravity = (0.0, 0.0, 0.0 if floor == "free" else -9.81)
    if floor == "plane":
        model = Model([ball], [Contact(ball, Plane([0, 0, 0], [0, 0, 1]))], gravity)
    else:
        mass = 1000.0 * mb if floor == "heavy" else 2.0 * mb
        box = RigidBody3D.uniform(mass, [0.0, 0.0, -side / 2], Box(0.3, 0.3, side))
        pairs = [Contact(ball, box, method=method)]
        if floor == "heavy":  # on three of its bottom corners: four would be redundant rows
            corners = [i for i, v in enumerate(box.shape.vertices) if v[2] < 0][:3]
            pairs.append(Contact(box, Plane([0, 0, -side], [0, 0, 1]), nodes=corners))
        model = Model([ball, box], pairs, gravity)
    p, gmin = [], np.inf
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    # impacts at the step's end on every floor: "auto" localizes a model of solids alone,
    # not one with a rigid body, and the floors are compared by one step algorithm
    opts = IntegratorOptions(localize=False)
    for st in simulate(model, wave_step(ball, 1.0, None), 0.008, opts, v0=v0):
        gmin = min(gmin, float(np.min(st.gaps, initial=np.inf)))
        mv = model.M_full @ st.v
        p.append((mv[: ball.ndof][2::3].sum(), mv[ball.ndof + 2] if floor != "plane" else 0.0))
    return np.array(p) / mb, gmin


def test_an_elastic_ball_bounces_on_a_heavy_box_as_on_the_plane_under_it():
    """The box on the plane holds still (its corners' contacts), the ball's node gaps to its
    top face are those to the plane shifted: the rebound is the plane's to round-off (1e-12
    measured; the bound 1e-9 m/s is the solvers' tolerance)."""
    on_plane, _ = ball_drop("plane")
    on_box, gmin = ball_drop("heavy")
    assert gmin >= -1e-9
    assert on_box[-1, 0] > 0.9  # it has bounced
    np.testing.assert_allclose(on_box[:, 0], on_plane[:, 0], atol=1e-9)


def test_a_free_box_recoils_with_the_momentum_the_ball_loses():
    """No gravity, a free box of twice the ball's mass: the vertical momentum of the two is
    kept to round-off at every step (1.7e-13 of m v measured) while the ball bounces."""
    p, gmin = ball_drop("free")
    assert gmin >= -1e-9
    np.testing.assert_allclose(p.sum(axis=1), -1.0, atol=1e-10)
    assert p[-1, 0] > 0.2 and p[-1, 1] < -0.5


def test_a_box_on_its_four_corners_holds_the_ball_s_impact():
    """Four bottom corners on the plane are four rows on the three dofs that move the box off
    it: the bordered matrix of the smooth step is singular (the run stopped at its first step,
    "singular iteration matrix"). The update is taken on an independent subset of the rows
    (counted as ``redundant_row_updates``): the run completes, the box stays on the plane and
    the ball bounces. The ball's momentum against a fixed box:
    test_the_ball_on_a_box_on_four_corners_moves_as_on_a_fixed_box."""
    ball = Solid.ball([0.0, 0.0, R + 0.002], R, 2, RUBBER)
    side = 0.05
    box = RigidBody3D.uniform(1000.0 * ball.mass, [0.0, 0.0, -side / 2], Box(0.3, 0.3, side))
    plane = Plane([0, 0, -side], [0, 0, 1])
    pairs = [Contact(ball, box, method="node-to-surface"), Contact(box, plane)]
    model = Model([ball, box], pairs, (0.0, 0.0, -9.81))
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    gmin, vz = np.inf, []
    for st in simulate(model, wave_step(ball, 1.0, None), 0.008, IntegratorOptions(), v0=v0):
        gmin = min(gmin, float(np.min(st.gaps, initial=np.inf)))
        vz.append((model.M_full @ st.v)[: ball.ndof][2::3].sum() / ball.mass)
    assert gmin >= -1e-9  # the solvers' gap tolerance
    # the box has not moved: its six dofs at round-off of its size (0.3 m)
    assert np.max(np.abs(st.q[ball.ndof :])) <= 1e-12
    assert vz[-1] > 0.9  # the ball has bounced (0.95 m/s on the plane)


def ball_on_box(on_plane: bool, t_end: float = 0.008):
    """The ball (momentum per unit mass, m/s, each step) dropped at 1 m/s on the box of
    test_a_box_on_its_four_corners_holds_the_ball_s_impact, resting on its four bottom
    corners on a plane, or fixed."""
    ball = Solid.ball([0.0, 0.0, R + 0.002], R, 2, RUBBER)
    side = 0.05
    box = RigidBody3D.uniform(1000.0 * ball.mass, [0.0, 0.0, -side / 2], Box(0.3, 0.3, side))
    if on_plane:
        floor = Contact(box, Plane([0, 0, -side], [0, 0, 1]))
        model = Model([ball, box], [Contact(ball, box), floor], (0.0, 0.0, -9.81))
    else:
        model = Model([ball, box.fix()], [Contact(ball, box)], (0.0, 0.0, -9.81))
    v0 = model.translation(ball, (0.0, 0.0, -1.0))
    p = []
    for st in simulate(model, wave_step(ball, 1.0, None), t_end, IntegratorOptions(), v0=v0):
        p.append((model.M_full @ st.v)[: ball.ndof].reshape(-1, 3).sum(axis=0) / ball.mass)
    return np.array(p)


def test_the_ball_on_a_box_on_four_corners_moves_as_on_a_fixed_box():
    """A box 1000x the ball's mass on its four bottom corners does not move, so the ball
    bounces as on a fixed box. It did not: from the step where the ball's rows joined the
    smooth step's bordered matrix, that matrix's LU, singular by the redundant corner rows,
    no longer failed, and its near-zero pivot sent round-off into the update (the corners'
    forces went from 4 x 1170 N to 987, 2158, 2158, 987 N before any touch); the ball's
    momentum then differed by 1.5e-3 of m v. The rows are now tested for independence first
    where they can be redundant. Bound: the velocity jump's tolerance tol_gap L/h =
    1e-12 x 0.427 m / 1.08e-4 s = 4e-9 m/s (measured 1.9e-14 m/s)."""
    on_plane, fixed = ball_on_box(True), ball_on_box(False)
    assert on_plane.shape == fixed.shape
    assert np.abs(on_plane - fixed).max() < 4e-9
    assert on_plane[-1, 2] > 0.9  # bounced
