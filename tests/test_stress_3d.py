"""3D body-to-body contact beyond the cases (``benchmarks/stress_3d.py``): what the sweep found,
as small regression tests.

- A rigid box's corner entering a solid between its nodes is held by its own row
  (:mod:`fecontact.contact.box_corners`), and its corners and edges are measured every step,
  instead of the run completing with the corner millimetres inside and ``max_penetration``
  0.
- Every 3D pair's gaps are objective (unchanged by a rigid motion of the whole model), so its
  contact forces have no net force and no net moment: the momentum of a free pair changes by
  the integrator alone.
- An elastic ball thrown at a free rigid box in space keeps the pair's linear momentum to
  round-off.
"""

import numpy as np
import pytest

from fecontact import Model, simulate
from fecontact.bodies import Beam3D, LinearElastic, Material, RigidBody3D, Section, Solid
from fecontact.bodies.shapes3d import Ball, Box
from fecontact.contact import Contact, Plane
from fecontact.contact.box_corners import BoxCorners
from fecontact.contact.rigid_distance import FeatureDepths, box_features
from fecontact.rotations import exp, log
from fecontact.scenes import wave_step
from fecontact.testing import group_gradient_error, slip_step_errors
from fecontact.time.settings import IntegratorOptions

RUBBER = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
TILT = np.array([0.4, 0.3, 0.0])  # rad: a corner of the box lowest


def slab(divisions=4):
    s = Solid.box([-0.05, -0.05, -0.04], [0.05, 0.05, 0.0], (divisions, divisions, 2), RUBBER)
    s.fix(s.nodes_where(lambda x: x[2] <= -0.04 + 1e-9))
    return s


def corner_first(method, lift):
    """A 4 × 3 × 2 cm rigid box over a 4 × 4 slab (2.5 cm cells), its lowest corner ``lift``
    (m) above the top face, between the nodes."""
    base = slab()
    box = RigidBody3D.of_density(1000.0, [0.006, -0.004, 0.0], Box(0.04, 0.03, 0.02))
    model = Model([base, box], [Contact(base, box, method=method)], (0.0, 0.0, -9.81))
    low = np.min(box_features(box.shape) @ exp(TILT).T, axis=0)[2]
    q0 = np.zeros(model.n)
    q0[base.ndof :] = [0.0, 0.0, lift - low, *TILT]
    return model, q0


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_a_box_corner_between_the_nodes_is_measured(method):
    model, q0 = corner_first(method, -0.002)  # the corner 2 mm inside the slab
    pair = model.contacts.pairs[0]
    # the rows hold nodes: every node is outside the box
    assert np.all(pair.gaps(q0)[np.isfinite(pair.gaps(q0))] > 0.0)
    watch = pair.watch()
    depth, ratio = (watch.features if method == "mortar" else watch).depth(q0)
    # the corner's own depth below the flat top face, to round-off
    assert depth == pytest.approx(0.002, abs=1e-12)
    assert ratio == pytest.approx(0.002 / np.hypot(0.025, 0.025), rel=1e-9)
    assert model.contacts.watches  # the run measures it at every step


def test_a_ball_has_no_features():
    base = slab()
    ball = RigidBody3D.of_density(1000.0, [0.0, 0.0, 0.0495], Ball(0.05))
    model = Model([base, ball], [Contact(base, ball)], (0.0, 0.0, -9.81))
    assert FeatureDepths(model.contacts.pairs[0]).depth(np.zeros(model.n)) == (0.0, 0.0)


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_a_box_dropped_corner_first_is_held_at_its_corner(method):
    """Before the corner rows, the corner sank 6.7 mm between the nodes of an 8 × 8 slab and
    the run completed with max_penetration 2e-14 m (benchmarks/stress_3d.py)."""
    model, q0 = corner_first(method, 0.001)
    v0 = np.zeros(model.n)
    v0[-6:-3] = [0.0, 0.0, -1.0]
    corners = _corner_rows(model)
    rows = np.flatnonzero(model.contacts.owner == model.contacts.pairs.index(corners))
    n, deepest, pressed = model.bodies[0].ndof, 0.0, 0
    for st in simulate(model, wave_step(model.bodies[0], 1.0), 0.012, IntegratorOptions(),
                       q0=q0, v0=v0):  # fmt: skip
        deepest = max(deepest, -float(np.min(corners.gaps(st.q))))
        pressed += bool(st.pressed()[rows].any())
        assert st.q[n + 2] > -0.01  # (not through the slab)
    assert pressed > 0
    # the corners' rows are held as any gap: to the correction's round-off (tol_gap)
    assert deepest < 1e-12


def _corner_rows(model) -> BoxCorners:
    """The corner rows of a model's solid–box pair (numbered after every other pair)."""
    return next(pair for pair in model.contacts.pairs if isinstance(pair, BoxCorners))


def _moved(model, q, R, t):
    """q after the rigid motion x → R x + t of the whole model."""
    out = q.copy()
    for i, body in enumerate(model.bodies):
        s = model.body_slice(i)
        if isinstance(body, RigidBody3D):
            out[s][:3] = R @ body.center(q[s]) + t - body.position
            out[s][3:6] = log(R @ exp(q[s][3:6]))
        elif isinstance(body, Beam3D):
            nodes = q[s].reshape(-1, 6).copy()
            nodes[:, :3] = body.positions(q[s]) @ R.T + t - body.X
            nodes[:, 3:] = [log(R @ exp(psi)) for psi in nodes[:, 3:]]
            out[s] = nodes.ravel()
        else:
            X = body.positions(np.zeros(body.ndof))
            out[s] = (body.positions(q[s]) @ R.T + t - X).ravel()
    return out


def _pairs():
    rng = np.random.default_rng(3)
    steel = Material(210e9, nu=0.3, rho=7850.0)
    for method in ("mortar", "node-to-surface"):
        for shape, at in ((Box(0.3, 0.3, 0.05), [0.14, 0.0, -0.025]), (Ball(0.04), [0, 0, -0.04])):
            ball = Solid.ball([0.0, 0.0, 0.0505], 0.05, 2, RUBBER)
            body = RigidBody3D.uniform(1.0, at, shape)
            model = Model([ball, body], [Contact(ball, body, method=method)], (0, 0, 0))
            q = np.zeros(model.n)
            q[: ball.ndof] = rng.normal(size=ball.ndof) * 1e-5
            q[ball.ndof :] = [1e-3, -2e-3, 0.0, 0.1, -0.05, 0.2]
            name = f"solid-{type(shape).__name__.lower()}-{method}"
            yield pytest.param(model, q, id=name)
    shapes = ((Ball(0.05), Ball(0.06), [0.11, 0.02, 0.0]), (Box(0.2, 0.15, 0.1),
              Box(0.3, 0.3, 0.1), [0.0, 0.0, -0.1]), (Ball(0.05), Box(0.2, 0.15, 0.1),
              [0.0, 0.0, -0.1]))  # fmt: skip
    for a, b, at in shapes:
        A, B = RigidBody3D.uniform(1.0, [0, 0, 0], a), RigidBody3D.uniform(1.0, at, b)
        model = Model([A, B], [Contact(A, B)], (0, 0, 0))
        q = np.r_[0.0, 0.0, 0.0, 0.02, 0.0, 0.01, 0.0, 0.0, 0.0, 0.01, 0.02, -0.01]
        name = f"rigid-{type(a).__name__.lower()}-{type(b).__name__.lower()}"
        yield pytest.param(model, q, id=name)
    rod = Beam3D.straight([-0.1, 0, 0.006], [0.1, 0.02, 0.008], 4, steel, Section.circle(0.005))
    box = RigidBody3D.uniform(1.0, [0, 0, -0.05], Box(0.3, 0.3, 0.1))
    model = Model([box, rod], [Contact(rod, box, clearance=0.005)], (0, 0, 0))
    q = np.zeros(model.n)
    q[6:] = rng.normal(size=rod.ndof) * 1e-4
    yield pytest.param(model, q, id="beam-box")


@pytest.mark.parametrize("model, q", list(_pairs()))
def test_gaps_are_objective(model, q):
    """g(rigid motion of q) = g(q) to round-off over the rows near contact: G is orthogonal
    to the rigid translations and rotations of the whole model (no net force or moment)."""
    g = model.contacts.gaps(q)
    near = np.isfinite(g) & (np.abs(g) < 0.02)
    assert near.any()
    moved = model.contacts.gaps(
        _moved(model, q, exp(np.array([0.3, -0.5, 0.7])), [0.01, -0.02, 0.03])
    )
    # (coordinates of order 0.1 m moved and turned: a few ulps of them)
    assert np.abs(moved[near] - g[near]).max() < 1e-15


def test_a_ball_on_a_free_box_keeps_the_linear_momentum():
    ball = Solid.ball([-0.101, 0.02, 0.0], 0.05, 1, RUBBER)
    box = RigidBody3D.uniform(ball.mass, [0.0, 0.0, 0.0], Box(0.1, 0.15, 0.2))
    model = Model([ball, box], [Contact(ball, box)], gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(ball, (1.0, 0.0, 0.0))
    w = ball.mass_matrix() @ ball.translation_field([1.0, 0.0, 0.0])
    n = ball.ndof
    p, pressed = [], 0
    for st in simulate(model, wave_step(ball, 1.0), 0.012, IntegratorOptions(), v0=v0):
        p.append([w @ st.v[:n] + box.mass * st.v[n], st.v[n]])
        pressed += bool(st.pressed().any())
    p = np.array(p)
    assert pressed > 0 and p[-1, 1] > 0.3  # it hit the box and pushed it
    # the momentum is a sum of O(1) terms: round-off
    assert np.abs(p[:, 0] - p[0, 0]).max() < 1e-12 * ball.mass


def test_corner_rows_have_the_exact_gradient():
    """Central differences of the corners' gaps over their 15 dofs (the box's translations and
    body-frame rotation increments, their triangle's nodes) against G."""
    model, q = corner_first("mortar", -0.0005)
    rng = np.random.default_rng(5)
    n = model.bodies[0].ndof
    q[:n] = rng.normal(size=n) * 2e-4  # tilted triangles
    corners = _corner_rows(model)
    g, dofs, G, _ = corners.evaluate(q)
    rows = np.flatnonzero(np.isfinite(g))
    assert rows.size
    # (central differences of O(1) slopes: error h² g''' + round-off 1e-17/h)
    assert group_gradient_error(corners, model, q, np.unique(dofs[rows]), 1e-7) < 1e-7


def test_corner_rows_slip_against_the_triangle():
    """Friction on the corner rows: the slip over a small step (the box's body-frame
    increment, the nodes' displacements) is the slip rows times that step, and a motion of
    the box and the triangle together (the triangle's nodes moved as the corner) slips by
    nothing."""
    model, q = corner_first("mortar", -0.0005)
    corners = _corner_rows(model)
    rows, T = check_box_slip_rows(corners, model, q)
    assert np.allclose(np.einsum("mtd,md->mt", T[rows], corners._geometry(q)[4][rows]), 0.0)


def check_box_slip_rows(feature_rows, model, q):
    """The slip rows of a box's feature rows against a solid (the solid's dofs first, then the
    box's translation and rotation) at q: the slip over a small step (the box's body-frame
    increment, the nodes' displacements) is the slip rows times that step, and a common
    translation of the box and the solid slips by nothing. Returns the rows and tangents."""
    n = model.bodies[0].ndof
    dofs, GT, T = feature_rows.tangents(q)
    rows = np.flatnonzero(np.isfinite(feature_rows.gaps(q)))
    d = np.random.default_rng(7).normal(size=model.n) * 1e-7
    d[n + 3 : n + 6] = 0.0  # (translations: the rows are exact for them)
    # the rows at the step's end against those at its start: second order in the step, so
    # the relative error falls as the step
    errors = slip_step_errors(feature_rows, q, d, rows)
    assert errors[0] < 1e-4
    assert errors[1] < 0.2 * errors[0]
    together = np.zeros(model.n)
    together[:n] = np.tile([2e-6, -1e-6, 0.0], n // 3)
    together[n : n + 3] = [2e-6, -1e-6, 0.0]
    assert np.abs(np.einsum("mtk,mk->mt", GT, together[dofs]))[rows].max() < 1e-18
    return rows, T


def test_a_frictional_model_whose_closing_contacts_are_frictionless():
    """A box landing on a frictionless floor while its only frictional pair (a wall) is far:
    the frictional correction met no slip rows at all and stopped with a ValueError."""
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.051], Box(0.1, 0.1, 0.1))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=1.0)
    wall = Plane([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], extent=1.0)
    pairs = [Contact(box, floor), Contact(box, wall, friction=0.3)]
    model = Model([box], pairs, (0.0, 0.0, -9.81))
    v0 = np.r_[0.0, 0.0, -1.0, 0.0, 0.0, 0.0]
    states = list(simulate(model, 1e-3, 0.05, IntegratorOptions(), v0=v0))
    assert any(st.pressed()[:8].any() for st in states)
    assert states[-1].gaps[:8].min() > -1e-12  # (the floor's corners held to round-off)


@pytest.mark.parametrize("method", ["mortar", "node-to-surface"])
def test_the_predictor_names_what_enters(method):
    """A step whose predictor puts a box's corner 3 mm inside the slab (0.08 of the longest
    edge of its triangle, beyond the 0.05 allowed) fails naming the corner; a ball 3 mm into
    the slab over a node (0.12 of the shortest edge), which the mortar rows hold only
    weighted, names the node."""
    from fecontact.time.penetration import PenetrationFailure, check_predictor

    model, q0 = corner_first(method, -0.003)
    with pytest.raises(PenetrationFailure, match="^a box edge or corner of a rigid body enters"):
        check_predictor(model, q0, model.contacts.gaps(q0))
    model, q0 = corner_first(method, 0.001)
    check_predictor(model, q0, model.contacts.gaps(q0))  # outside: no failure
    if method != "mortar":  # node-to-surface rows are the nodes' own signed distances
        return
    base = slab()
    ball = RigidBody3D.of_density(1000.0, [0.0, 0.0, 0.047], Ball(0.05))
    model = Model([base, ball], [Contact(base, ball, method=method)], (0.0, 0.0, -9.81))
    q0 = np.zeros(model.n)
    with pytest.raises(PenetrationFailure, match="^a node enters"):
        check_predictor(model, q0, model.contacts.gaps(q0))
