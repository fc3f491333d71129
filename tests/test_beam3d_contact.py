"""Beam3D contact through its segments: tubes of the section's radius against spheres, rigid
balls and capsules, and other tubes (fecontact.contact.beam3d_pairs, .segment3d)."""

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from fecontact import Model, Solid, simulate
from fecontact.bodies import Beam3D, Material, RigidBody3D, Section
from fecontact.bodies.materials import LinearElastic
from fecontact.bodies.meshes import box_mesh
from fecontact.bodies.shapes3d import Ball, Box, Capsule, Cylinder
from fecontact.contact import Contact, NodeContact, Sphere
from fecontact.contact.beam3d_box import box_signed_distance, closest_to_box
from fecontact.contact.beam3d_edges import SolidEdges, TubeEdgeContact
from fecontact.contact.beam3d_pairs import TubeBoxContact, TubeRigidContact, TubeSphereContact
from fecontact.contact.beam3d_solid import TubeSolidContact
from fecontact.contact.body_pairs import closest_facet_distance
from fecontact.contact.geometry import segment_distance
from fecontact.contact.segment3d import tube_distance
from fecontact.contact.tube_beam import TubeBeamContact
from fecontact.errors import InputError
from fecontact.testing import moved_on_group
from fecontact.time.settings import IntegratorOptions

STEEL = Material(210e9, nu=0.3, rho=7850.0)
R_TUBE = 0.005


def rod(a, b, n=6):
    return Beam3D.straight(a, b, n, STEEL, Section.circle(R_TUBE))


# -- the distance of two segments and its derivatives ----------------------------------------
@pytest.mark.parametrize("k", [1, 2])
def test_segment_distance_derivatives_by_central_differences(k):
    """Gradient and Hessian against central differences of step 1e-6 of random segments and
    points (some parameters inside, some at their bounds): truncation 1e-12 relative, round-off
    of f/1e-6 ≈ 1e-10 on the Hessian."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        ends = rng.normal(size=(2 + k, 3))

        def f(y):
            Y = y.reshape(-1, 3)
            out = tube_distance(Y[None, :2], Y[None, 2:])
            return out[0][0], out[3][0], out[4][0]

        y = ends.ravel()
        _, G, H = f(y)
        for i in range(len(y)):
            d = np.zeros(len(y))
            d[i] = 1e-6
            (fp, Gp, _), (fm, Gm, _) = f(y + d), f(y - d)
            assert (fp - fm) / 2e-6 == pytest.approx(G[i], abs=1e-8)
            np.testing.assert_allclose((Gp - Gm) / 2e-6, H[:, i], atol=2e-7)


def test_crossing_and_parallel_segments_have_their_exact_closest_points():
    P = np.array([[[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]])
    crossing = np.array([[[0.0, -1.0, 0.3], [0.5, 1.0, 0.3]]])
    f, e, (xi, eta), _, _ = tube_distance(P, crossing)
    assert f[0] == pytest.approx(0.3, abs=1e-15)
    np.testing.assert_allclose(e[0], [0.0, 0.0, -1.0], atol=1e-15)
    assert (xi[0], eta[0]) == pytest.approx((0.625, 0.5), abs=1e-15)
    # parallel: the middle of the overlap [−0.5, 1] of the two, not an end
    parallel = np.array([[[-0.5, 0.0, 0.3], [2.0, 0.0, 0.3]]])
    f, e, (xi, eta), G, H = tube_distance(P, parallel)
    assert f[0] == pytest.approx(0.3, abs=1e-15)
    assert xi[0] == pytest.approx(0.625, abs=1e-15) and eta[0] == pytest.approx(0.3, abs=1e-15)
    assert np.all(np.isfinite(H)) and np.allclose(H, H.transpose(0, 2, 1), atol=1e-12)


# -- the pairs: their rows are the derivatives of their gaps ---------------------------------
ROOF = np.array([[0.05, -0.3, 0.125], [0.015, 0.0, 0.16], [-0.02, 0.3, 0.12]])
"""A rod's nodes kinked 14° up over ``scenes``' bar: from below, a valley at its middle."""


def scenes():
    bar = rod([-0.3, 0.02, 0.11], [0.3, -0.03, 0.1])
    sphere = Sphere([0.01, 0.0, -0.2], 0.3)
    other = rod([0.05, -0.3, 0.125], [-0.02, 0.3, 0.12], n=5)
    ball = RigidBody3D.uniform(1.0, [0.02, 0.01, 0.05], Ball(0.05))
    capsule = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.04], Capsule(0.03, 0.4))
    roof = Beam3D(ROOF, STEEL, Section.circle(R_TUBE))  # a valley seen from the bar below
    return [
        ("sphere", [bar], lambda: Contact(bar, sphere, clearance=R_TUBE)),
        ("beam", [bar, other], lambda: Contact(bar, other, clearance=2 * R_TUBE)),
        ("valley", [bar, roof], lambda: Contact(bar, roof, clearance=2 * R_TUBE)),
        ("ball", [bar, ball], lambda: Contact(bar, ball, clearance=R_TUBE)),
        ("capsule", [capsule, bar], lambda: Contact(capsule, bar, clearance=R_TUBE)),
    ]


@pytest.mark.parametrize("name", ["sphere", "beam", "valley", "ball", "capsule"])
def test_tube_rows_are_the_derivatives_of_the_gaps(name):
    """G against central differences of the gaps and H of G along every dof (rigid rotations
    in the body frame), step 1e-6: agreement to 1e-7 relative (truncation and round-off)."""
    bodies, make = next((b, m) for n, b, m in scenes() if n == name)
    pair = make()
    model = Model(bodies, [pair], gravity=(0.0, 0.0, 0.0))
    rng = np.random.default_rng(5)
    q = 1e-3 * rng.normal(size=model.n)
    for triple in model.rotations:
        q[triple] = [0.3, -0.5, 0.8]
    g, dofs, G, H = pair.evaluate(q)
    # (two tubes: the second rows outside a valley are left out, +inf, with the gradient of
    # the valley's row, which a correction that bends the valley takes)
    held = np.isfinite(g)
    assert held.any() and np.all(np.any(G[~held] != 0.0, axis=1))
    lam = rng.uniform(0.5, 1.0, size=pair.size)
    for j in np.unique(dofs):
        d = np.zeros(model.n)
        d[j] = 1e-6
        gp, dp, Gp, _ = pair.evaluate(moved_on_group(model, q, d))
        gm, dm, Gm, _ = pair.evaluate(moved_on_group(model, q, -d))
        assert np.array_equal(dp, dofs) and np.array_equal(dm, dofs)
        col = np.where(dofs == j, 1.0, 0.0)
        np.testing.assert_allclose(
            (gp[held] - gm[held]) / 2e-6, np.sum(G * col, axis=1)[held], atol=1e-8
        )
        dF = np.einsum("m,mk->mk", lam, Gp - Gm) / 2e-6
        assert np.allclose(dF, np.einsum("m,mkl,ml->mk", lam, H, col), atol=1e-5)


def test_the_registry_chooses_the_tube_pairs():
    bar = rod([0, 0, 0.1], [1, 0, 0.1])
    other = rod([0.5, -0.5, 0.2], [0.5, 0.5, 0.2])
    assert isinstance(Contact(bar, Sphere([0.5, 0, -1], 1.0)), TubeSphereContact)
    assert isinstance(Contact(bar, Sphere([0.5, 0, -1], 1.0), nodes=[1]), NodeContact)
    assert isinstance(Contact(bar, Sphere([0.5, 0, 0], 2.0, inside=True)), NodeContact)
    assert isinstance(Contact(bar, other, clearance=0.01), TubeBeamContact)
    ball = RigidBody3D.uniform(1.0, [0.5, 0, -1], Ball(0.5))
    assert isinstance(Contact(ball, bar), TubeRigidContact)
    with pytest.raises(InputError, match="clearance"):
        Contact(bar, other)
    with pytest.raises(InputError, match="a Ball, a Capsule or a Box"):
        Contact(bar, RigidBody3D.uniform(1.0, [0.5, 0, -1], Cylinder(0.1, 1.0)))


# -- impacts with exact answers --------------------------------------------------------------
def run(model, h, t_end, v0, options=None, watch=None):
    """Step the model; the smallest gap the solver saw over the run, the last state and the
    largest value of ``watch(state)``."""
    gmin, worst, st = np.inf, -np.inf, None
    for st in simulate(model, h, t_end, options or IntegratorOptions(), v0=v0):
        gmin = min(gmin, float(np.min(st.gaps, initial=np.inf)))
        if watch is not None:
            worst = max(worst, watch(st))
    return gmin, st, worst


def rod_across_a_sphere(nodes_only: bool):
    """A rod of 4 elements dropped flat at 1 m/s across a sphere whose top lies under the
    middle of an element; the depth of the centreline's tube in the sphere, measured from the
    segments themselves (not the solver's gaps)."""
    R, L, n = 0.1, 0.5, 4
    sphere = Sphere([L / n / 2, 0.0, 0.0], R)
    z0 = R + R_TUBE + 0.002
    bar = rod([-L / 2, 0.0, z0], [L / 2, 0.0, z0], n)
    nodes = list(range(n + 1)) if nodes_only else None
    model = Model([bar], [Contact(bar, sphere, nodes, clearance=R_TUBE)], gravity=(0, 0, -9.81))
    s = bar.segments()
    centre = np.broadcast_to(sphere.center, (len(s), 3))

    def depth(st):
        x = bar.positions(st.q)
        return R + R_TUBE - segment_distance(centre, x[s[:, 0]], x[s[:, 1]]).min()

    return run(model, 1e-4, 0.02, model.translation(bar, (0.0, 0.0, -1.0)), watch=depth)


def test_a_rod_dropped_across_a_sphere_touches_it_between_its_nodes():
    """Node contact lets the chord over the sphere's top sink 2 cm into it (the nodes, 6.25 cm
    to either side, reach the sphere only when the chord's middle is (R + r) − √((R + r)² −
    0.0625²) = 2.06 cm deep); segment contact keeps it out to the solver's tolerance."""
    gmin, _, depth = rod_across_a_sphere(nodes_only=False)
    assert gmin >= -1e-9 and depth <= 1e-9
    _, _, depth_nodes = rod_across_a_sphere(nodes_only=True)
    assert depth_nodes > 0.019


def crossing_rods(restitution: float, n: int, options=None):
    """Rod a (along x) falls at 1 m/s onto rod b (at 60° to it in the horizontal plane), both
    free, no gravity; they cross at their middles."""
    d = np.array([np.cos(np.pi / 3), np.sin(np.pi / 3), 0.0])
    L, z = 0.3, 2 * R_TUBE + 0.001
    a = rod([-L / 2, 0.0, z], [L / 2, 0.0, z], n)
    b = rod(-L / 2 * d, L / 2 * d, n)
    pair = Contact(a, b, clearance=2 * R_TUBE, restitution=restitution)
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    m = STEEL.rho * np.pi * R_TUBE**2 * L

    def momenta(st):
        p = (model.M_full @ st.v).reshape(-1, 6)[:, 2]
        return p[: a.n_nodes].sum() / m, p[a.n_nodes :].sum() / m

    gmin, st, _ = run(model, 1e-5, 0.004, model.translation(a, (0.0, 0.0, -1.0)), options)
    return gmin, momenta(st), pair, st


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_two_crossing_rods_exchange_the_momentum_of_a_rigid_impact(e):
    """One element each, hit at their middles: the nodes' translations move together (no
    strain), so each rod is a rigid mass and Newton's law gives v_a = −(1 − e)/2,
    v_b = −(1 + e)/2 (m/s) exactly; round-off 1e-14."""
    gmin, (va, vb), _, _ = crossing_rods(e, 1)
    assert gmin >= -1e-9
    assert va == pytest.approx(-(1 - e) / 2, abs=1e-12)
    assert vb == pytest.approx(-(1 + e) / 2, abs=1e-12)


def test_flexible_crossing_rods_touch_at_the_crossing_and_keep_their_momentum():
    """Five elements each: the crossing is the middle of both middle elements (ξ = η = ½);
    the flexible rods ring, but the momentum is kept to round-off and p and k change
    nothing beyond the solver's tolerances."""
    gmin, (va, vb), pair, st = crossing_rods(0.5, 5)
    assert gmin >= -1e-9
    assert va + vb == pytest.approx(-1.0, abs=1e-12)
    assert 0.0 > va > vb  # rod a slowed, rod b pushed down
    a, b = pair.bodies  # the middle elements at the start, and the pair's row there
    P, Q = a.X[a.segments()[2]][None], b.X[b.segments()[2]][None]
    xi, eta = tube_distance(P, Q)[2]
    assert (xi[0], eta[0]) == pytest.approx((0.5, 0.5), abs=1e-12)
    g, dofs, G, _ = pair.evaluate(np.zeros_like(st.q))
    assert np.argmin(g) == 2 and np.allclose(G[2], tube_distance(P, Q)[3][0], atol=1e-15)
    scaled = IntegratorOptions(penalty_scale=10.0, multiplier_scale=0.1)
    _, (va2, vb2), _, st2 = crossing_rods(0.5, 5, scaled)
    assert (va2, vb2) == pytest.approx((va, vb), abs=1e-7)
    np.testing.assert_allclose(st2.q, st.q, atol=1e-9)


def test_rods_crossing_over_their_middle_nodes_hold_the_valley_with_both_segments():
    """Two free rods of 6 elements crossing at right angles over their middle nodes, thrown
    at each other at 0.5 m/s each, decoupled contact (``smooth_contact="off"``): the impact
    bends each into a valley under the other's node, whose two segments both press. With one
    row per node or segment against the closer segment, the partner changed between the
    correction's iterates and the step halved 58 times in 1.3 ms (and broke the symmetry by
    1.2e-9 m); with a row on each segment of the valley no step halves and the two rods stay
    images of each other under (x, y, z) → (y, x, −z) within the correction's gap tolerance
    (1e-12 of the length, 3e-13 m; measured 3.6e-15 m)."""
    z = R_TUBE + 0.0005
    a = rod([-0.15, 0.0, z], [0.15, 0.0, z], 6)
    b = rod([0.0, -0.15, -z], [0.0, 0.15, -z], 6)
    model = Model([a, b], [Contact(a, b, clearance=2 * R_TUBE)], gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(a, (0.0, 0.0, -0.5)) + model.translation(b, (0.0, 0.0, 0.5))
    sa, sb = model.body_slice(0), model.body_slice(1)
    halvings, asymmetry = 0, 0.0
    for st in simulate(model, 1e-5, 1.3e-3, IntegratorOptions(smooth_contact="off"), v0=v0):
        halvings += st.halvings
        xa, xb = a.positions(st.q[sa]), b.positions(st.q[sb])
        asymmetry = max(asymmetry, float(np.abs(xa[:, [1, 0, 2]] * [1, 1, -1] - xb).max()))
    assert np.min(st.gaps) >= -1e-12 and st.v[sa][2::6].max() > 0.0  # (in contact, pushed)
    assert halvings == 0
    assert asymmetry <= 3e-13
    # the valley's rows hold nearly one motion (redundant_rows: least-norm multipliers), so
    # the scale k does not choose their split: the same nodes to the correction's gap
    # tolerance, 3e-13 m, and their turns to that over the tube's radius, 6e-11 rad
    # (measured 7.8e-15 m and 6.3e-13 rad; without the least-norm path k ÷ 100 turned the
    # sections by 4.8e-5 rad more in the first step of contact)
    scaled = IntegratorOptions(smooth_contact="off", multiplier_scale=1e-2)
    *_, end = simulate(model, 1e-5, 1.3e-3, scaled, v0=v0)
    moved = np.abs(end.q - st.q).reshape(-1, 6)
    assert moved[:, :3].max() <= 3e-13 and moved[:, 3:].max() <= 3e-13 / R_TUBE


@pytest.mark.parametrize("fixed", [True, False])
def test_a_rod_thrown_onto_a_capsule_rebounds_with_the_rigid_momentum_exchange(fixed):
    """A one-element rod (mass m) thrown at 1 m/s across the middle of a capsule of mass 2m,
    held or free, e = ½: rigid impact, v_rod = +½ (held) or 0 and v_capsule = −½ m/s (free)."""
    m = STEEL.rho * np.pi * R_TUBE**2 * 0.3
    rc, tilt = 0.02, np.radians(50.0)
    d = np.array([0.0, np.cos(tilt), np.sin(tilt)])
    x0 = np.array([rc + R_TUBE + 0.001, 0.0, 0.0])
    bar = rod(x0 - 0.15 * d, x0 + 0.15 * d, 1)
    capsule = RigidBody3D.uniform(2 * m, [0.0, 0.0, 0.0], Capsule(rc, 0.3))
    if fixed:
        capsule.fix()
    pair = Contact(bar, capsule, clearance=R_TUBE, restitution=0.5)
    model = Model([bar, capsule], [pair], gravity=(0.0, 0.0, 0.0))
    gmin, st, _ = run(model, 1e-5, 0.004, model.translation(bar, (-1.0, 0.0, 0.0)))
    assert gmin >= -1e-9
    p = model.M_full @ st.v
    assert p[: bar.ndof].reshape(-1, 6)[:, 0].sum() / m == pytest.approx(
        0.5 if fixed else 0.0, abs=1e-12
    )
    np.testing.assert_allclose(
        st.v[-6:], [0, 0, 0, 0, 0, 0] if fixed else [-0.5, 0, 0, 0, 0, 0], atol=1e-12
    )


def test_a_rod_dropped_on_an_elastic_block_stays_out_and_keeps_the_momentum():
    """A four-element rod falls flat at 1 m/s, obliquely across the top face of a free
    elastic block (no gravity): its nodes stay out of the block's boundary by the tube's
    radius (the solver's gaps and the inside/outside test), the block takes the momentum the
    rod loses (to the solver's tolerances, 1e-9 of m·v), and the rod's last nodes are on the
    face or above it."""
    mesh = box_mesh([-0.1, -0.1, -0.05], [0.1, 0.1, 0.0], (4, 4, 2))
    block = Solid(mesh, LinearElastic(1e9, 0.3, rho=1000.0))
    z0 = R_TUBE + 0.001
    bar = rod([-0.08, -0.05, z0], [0.08, 0.07, z0], 4)
    pair = Contact(bar, block, clearance=R_TUBE, method="node-to-surface")
    assert isinstance(pair, TubeSolidContact)
    model = Model([bar, block], [pair], gravity=(0.0, 0.0, 0.0))
    gmin, st, deepest = run(
        model,
        1e-5,
        0.003,
        model.translation(bar, (0.0, 0.0, -1.0)),
        watch=lambda st: pair.penetration(st.q),
    )
    assert gmin >= -1e-9 and deepest == 0.0
    p = model.M_full @ st.v
    rod_p, block_p = p[: bar.ndof].reshape(-1, 6)[:, 2].sum(), p[bar.ndof :][2::3].sum()
    m = bar.mass
    assert (rod_p + block_p) / m == pytest.approx(-1.0, abs=1e-9)
    assert block_p / m < -0.5 and rod_p > 0.0  # the rod has struck and left


# -- against a box --------------------------------------------------------------------------
def test_the_closest_point_of_a_segment_to_a_box_is_the_least_signed_distance():
    """Against a bounded scalar minimization of the (convex) signed distance along 300
    random segments, some through the box, some parallel to an axis: never above it by more
    than round-off (5.6e-17 measured)."""
    rng = np.random.default_rng(0)
    half = np.array([0.3, 0.2, 0.1])
    A, B = rng.normal(scale=0.4, size=(2, 300, 3))
    B[:40, 1:] = A[:40, 1:]  # along x
    B[40:60] = A[40:60] + [0.0, 0.0, 0.5]  # along z
    xi, s, rho, nb = closest_to_box(A, B, half)
    assert (s < 0).sum() > 50  # some cross the box
    through = closest_to_box(np.array([[-1.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]), half)
    assert through[1][0] == pytest.approx(-0.1)  # through the centre: the thinnest half side
    np.testing.assert_allclose(box_signed_distance(rho, half)[0], s, atol=1e-15)
    for i in range(len(A)):

        def along(t, i=i):
            return box_signed_distance((A[i] + t * (B[i] - A[i]))[None], half)[0][0]

        best = minimize_scalar(along, bounds=(0, 1), method="bounded", options={"xatol": 1e-13})
        assert s[i] <= min(best.fun, along(0.0), along(1.0)) + 1e-15


@pytest.mark.parametrize("case", ["turned", "along the top", "along an edge"])
def test_box_rows_are_the_derivatives_of_the_gaps(case):
    """G against central differences (step 1e-6) along every dof of a rod over a box turned
    by 0.3 rad, its segments closest to a face, an edge or a corner; lying 5 mm over its top
    tilted by ~0.01 rad (rows at both ends of a segment's stretch over the top, the ends
    sliding along the face's edges); and 5 mm off its top edge along it. Rows left out
    (+inf) have no gradient. (Through the box the deepest point of a segment lies where two
    faces are equally deep, a kink of the gap: the row there is one of its subgradients;
    converged states, g ≥ 0, never sit there.)"""
    bar = rod([-0.3, 0.05, 0.12], [0.3, -0.1, 0.05], 6)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.02], Box(0.3, 0.2, 0.1))
    pair = Contact(bar, box, clearance=R_TUBE)
    assert isinstance(pair, TubeBoxContact)
    model = Model([bar, box], [pair], gravity=(0.0, 0.0, 0.0))
    q = 1e-3 * np.random.default_rng(4).normal(size=model.n)
    x = bar.X
    tilt = 0.3 if case == "turned" else 0.003
    if case != "turned":  # the top at z = 0.03, its edge at y = 0.1
        edge = 0.1 + 0.0035 if case == "along an edge" else 0.0
        q[2 : bar.ndof : 6] = 0.03 + 0.005 - x[:, 2] + 1e-3 * x[:, 0] + 1e-3 * x[:, 1]
        q[1 : bar.ndof : 6] = edge - x[:, 1] + 2e-3 * x[:, 0] if edge else q[1 : bar.ndof : 6]
    q[-3:] = [tilt / 3, -2 * tilt / 3, tilt]
    g, dofs, G, _ = pair.evaluate(q)
    live = np.isfinite(g)
    assert (g[live] > 0).all() and g.min() < 0.01 and (G[~live] == 0.0).all()
    assert live.sum() > len(g) // 3  # segments over a face: two rows
    for j in np.unique(dofs):
        d = np.zeros(model.n)
        d[j] = 1e-6
        gp, gm = pair.gaps(moved_on_group(model, q, d)), pair.gaps(moved_on_group(model, q, -d))
        col = (dofs == j).astype(float)
        np.testing.assert_allclose(
            (gp[live] - gm[live]) / 2e-6, np.sum(G * col, axis=1)[live], atol=1e-8
        )


@pytest.mark.parametrize("edge_along", [False, True])
def test_a_cube_struck_onto_a_rod_between_its_nodes_takes_no_halving(edge_along):
    """A 1 cm cube of 0.1 kg, a face parallel to a pinned rod (4 elements of 7.5 cm) or
    turned 45° about the rod's axis (an edge along it), over the middle of an element,
    struck at 1 m/s from 20 µm: the segment's least distance is level along its stretch under
    the face or the edge and moved between its ends as the rod bent (the smooth step failed
    at step 8 after 6 halvings). With rows at both ends, 40 steps of 1e-5 s (the strike and
    3.8e-4 m of the cube's travel) take no halving and no row goes below -1e-9 m (the gap
    tolerance's 1e-12 m, with round-off's margin)."""
    bar = Beam3D.straight([0.0, 0.0, 0.0], [0.3, 0.0, 0.0], 4, STEEL, Section.circle(R_TUBE))
    bar.pin(0).pin(-1)
    half = 0.005 * (np.sqrt(2.0) if edge_along else 1.0)  # the cube's reach below its centre
    cube = RigidBody3D.uniform(0.1, [0.0375, 0.0, R_TUBE + half + 2e-5], Box(0.01, 0.01, 0.01))
    model = Model([bar, cube], [Contact(bar, cube, clearance=R_TUBE)], gravity=(0, 0, 0))
    q0, v0 = np.zeros(model.n), np.zeros(model.n)
    q0[bar.ndof + 3] = np.pi / 4 if edge_along else 0.0
    v0[bar.ndof + 2] = -1.0
    halvings, gmin = 0, np.inf
    for st in simulate(model, 1e-5, 4e-4, IntegratorOptions(), q0=q0, v0=v0):
        halvings += st.halvings
        gmin = min(gmin, st.gaps.min())
    assert halvings == 0 and st.step == 40
    assert -1e-9 <= gmin < 1e-6  # struck: the rows touched
    assert st.v[bar.ndof + 2] > -1.0  # the rod pushes the cube back


@pytest.mark.parametrize("fixed", [True, False])
def test_a_rod_thrown_across_a_box_edge_rebounds_with_the_rigid_momentum_exchange(fixed):
    """A one-element rod thrown horizontally at 1 m/s onto a vertical edge of a box (mass 2m,
    held or free), across it at its middle, e = ½: the edge cuts the segment between its
    nodes, the impulse points from the edge through the box's centre (no torque): v_rod = +½
    (held) or 0 and v_box = −½ m/s along the throw (free), to round-off."""
    m = STEEL.rho * np.pi * R_TUBE**2 * 0.3
    bisector = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
    across = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    centre = (0.1 * np.sqrt(2.0) + R_TUBE + 0.001) * bisector
    bar = rod(centre - 0.15 * across, centre + 0.15 * across, 1)
    box = RigidBody3D.uniform(2 * m, [0.0, 0.0, 0.0], Box(0.2, 0.2, 0.2))
    if fixed:
        box.fix()
    pair = Contact(bar, box, clearance=R_TUBE, restitution=0.5)
    model = Model([bar, box], [pair], gravity=(0.0, 0.0, 0.0))
    gmin, st, _ = run(model, 1e-5, 0.004, model.translation(bar, -bisector))
    assert gmin >= -1e-9
    p = (model.M_full @ st.v)[: bar.ndof].reshape(-1, 6)[:, :3].sum(axis=0) / m
    np.testing.assert_allclose(p, 0.5 * bisector if fixed else 0.0, atol=1e-12)
    box_v = np.zeros(6) if fixed else np.r_[-0.5 * bisector, 0.0, 0.0, 0.0]
    np.testing.assert_allclose(st.v[-6:], box_v, atol=1e-12)


def test_centrelines_that_pass_through_each_other_in_a_step_keep_their_side():
    """Rod a 2 cm above rod b (crossing at right angles, tubes of 5 mm) moved 3 cm down within
    one step: its centreline is 1 cm below b's. From the normal at the step's start the gap of
    the crossing (the first group of rows: the segments of a) is −1 cm − 2r, and its row
    pushes a back up; a pair that has not seen the step's start (no side yet) reads the
    distance, +1 cm − 2r. (b's node under a's tube has gone through it too: −√2 cm − 2r.)"""
    a = rod([-0.2, 0.01, 0.02], [0.2, 0.01, 0.02], 4)
    b = rod([0.05, -0.2, 0.0], [0.05, 0.2, 0.0], 4)
    pair = Contact(a, b, clearance=2 * R_TUBE)
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    q0, q1 = np.zeros(model.n), np.zeros(model.n)
    q1[2 : a.ndof : 6] = -0.03
    crossing = len(a.segments())  # rows of a's segments
    fresh = pair.gaps(q1)[:crossing].min()
    assert fresh == pytest.approx(0.01 - 2 * R_TUBE, abs=1e-15)
    pair.look_ahead(q0, np.zeros(model.n), 1e-4)
    g, dofs, G, _ = pair.evaluate(q1)
    j = int(np.argmin(g[:crossing]))
    assert g[j] == pytest.approx(-0.01 - 2 * R_TUBE, abs=1e-15)
    assert g.min() == pytest.approx(-np.sqrt(2) * 0.01 - 2 * R_TUBE, abs=1e-15)
    up = np.zeros(model.n)
    up[2 : a.ndof : 6] = 1.0
    assert G[j] @ up[dofs[j]] == pytest.approx(1.0, abs=1e-15)


def test_the_rod_across_the_sphere_is_independent_of_p_and_k():
    """The drop across the sphere with p ×10 and k ×0.1: the same motion to the solvers'
    tolerances (1e-9 m)."""
    R, L, n = 0.1, 0.5, 4
    sphere = Sphere([L / n / 2, 0.0, 0.0], R)
    ends = []
    for options in (IntegratorOptions(), IntegratorOptions(penalty_scale=10, multiplier_scale=0.1)):
        bar = rod([-L / 2, 0.0, R + R_TUBE + 0.002], [L / 2, 0.0, R + R_TUBE + 0.002], n)
        model = Model([bar], [Contact(bar, sphere, clearance=R_TUBE)], gravity=(0, 0, -9.81))
        gmin, st, _ = run(model, 1e-4, 0.02, model.translation(bar, (0, 0, -1.0)), options)
        assert gmin >= -1e-9
        ends.append(st.q)
    np.testing.assert_allclose(ends[0], ends[1], atol=1e-9)


def test_a_rod_pushed_across_a_held_rod_rolls_at_two_thirds():
    """A one-element rod lying across a held one (tubes touching) pushed along the held rod's
    axis at v₀ = 0.5 m/s, μ = 0.3: the friction at its tube's touching point, −r e from the
    centreline, spins its sections up, and it rolls from t* = v₀/(3μg) at 2v₀/3 (a cylinder,
    I = mr²/2). Exact at every step but the one holding t* (measured 9.4e-16 m/s; the
    generalized-α step is exact for a constant force). Before the two tubes' slip rows took
    the sections' turn, it slid to a stop at v₀²/(2μg)."""
    mu, v0, h, g = 0.3, 0.5, 1e-3, 9.81
    a = rod([-0.15, 0.0, 2 * R_TUBE], [0.15, 0.0, 2 * R_TUBE], 1)
    b = rod([0.0, -0.5, 0.0], [0.0, 0.5, 0.0], 1).clamp(0).clamp(-1)
    model = Model([a, b], [Contact(a, b, clearance=2 * R_TUBE, friction=mu)])
    t, v = [], []
    for st in simulate(model, h, 0.1, IntegratorOptions(), v0=model.translation(a, (0, v0, 0))):
        assert float(np.min(st.gaps, initial=np.inf)) >= -1e-9
        t.append(st.t)
        v.append(st.v[1])
    t, t_star = np.array(t), v0 / (3 * mu * g)
    exact = np.where(t < t_star, v0 - mu * g * t, 2 * v0 / 3)
    kept = np.abs(t - t_star) > h  # (the step holding t* rolls from inside it)
    np.testing.assert_allclose(np.array(v)[kept], exact[kept], atol=1e-12)


# -- against a solid's convex edges ---------------------------------------------------------
def rod_over_a_block_edge(edges: bool, n=1):
    """A rod of 16 cm tilted 30° down across the top edge x = 0.1 m of an elastic block (its
    middle 1 mm above the edge), falling at 1 m/s; no gravity. Its upper node is over the top
    face, its lower one beyond the side face: only the edge can touch it."""
    block = Solid(
        box_mesh([-0.1, -0.1, -0.05], [0.1, 0.1, 0.0], (4, 4, 2)),
        LinearElastic(1e9, 0.3, rho=1000.0),
    )
    a = np.radians(30.0)
    d, up = np.array([np.cos(a), 0.0, -np.sin(a)]), np.array([np.sin(a), 0.0, np.cos(a)])
    c = np.array([0.1, 0.0, 0.0]) + (R_TUBE + 0.001) * up
    bar = rod(c - 0.08 * d, c + 0.08 * d, n)
    pairs = [Contact(bar, block, clearance=R_TUBE, method="node-to-surface")]
    if edges:
        pairs.append(Contact(bar, SolidEdges(block), clearance=R_TUBE))
    return bar, block, Model([bar, block], pairs, gravity=(0.0, 0.0, 0.0))


def test_edge_rows_are_the_derivatives_of_the_gaps():
    """G against central differences of the gaps (step 1e-6), H of G, on every segment:
    each reads its closest convex edge's distance, inside the edge's normal cone or not
    (the edge is part of the solid either way)."""
    bar, block, model = rod_over_a_block_edge(True, n=4)
    pair = model.contacts.pairs[1]
    assert isinstance(pair, TubeEdgeContact) and len(pair.partner.edges) == 40
    q = 1e-4 * np.random.default_rng(8).normal(size=model.n)
    g, dofs, G, H = pair.evaluate(q)
    near = np.isfinite(g)
    assert near.all()
    for j in np.unique(dofs[near]):
        dq = np.zeros(model.n)
        dq[j] = 1e-6
        gp, _, Gp, _ = pair.evaluate(q + dq)
        gm, _, Gm, _ = pair.evaluate(q - dq)
        col = (dofs == j).astype(float)
        dg = (gp[near] - gm[near]) / 2e-6
        np.testing.assert_allclose(dg, np.sum(G * col, axis=1)[near], atol=1e-8)
        dG = ((Gp - Gm) / 2e-6)[near]
        np.testing.assert_allclose(dG, np.einsum("mkl,ml->mk", H, col)[near], atol=1e-5)


def test_a_rod_falling_across_a_block_edge_is_held_by_the_edge():
    """Over 3 ms: with the edge pair the tube stays out of the block (solver gaps ≥ −1e-9 m;
    the rod's middle fifth sampled every 0.16 mm against the boundary triangles near the
    edge: none nearer than r to within the sampling's 1e-6 m, none inside) and the momentum
    is kept (1e-12 of m v); with the nodes alone the edge cuts into the tube (1.6 mm
    measured)."""

    def run_over(edges):
        bar, block, model = rod_over_a_block_edge(edges)
        tri, s = block.contact_facets(), np.linspace(0.4, 0.6, 201)[:, None]
        X = block.positions(np.zeros(block.ndof))
        tri = tri[np.linalg.norm(X[tri].mean(axis=1) - [0.1, 0.0, 0.0], axis=1) < 0.06]
        k = len(s)

        def depth(st):
            x, xb = bar.positions(st.q[: bar.ndof]), block.positions(st.q[bar.ndof :])
            pts = x[0] * (1 - s) + x[1] * s
            dist, g = closest_facet_distance(
                np.repeat(pts, len(tri), 0), np.tile(xb[tri], (k, 1, 1))
            )
            dist, g = dist.reshape(k, -1), g.reshape(k, -1)
            face = np.argmin(dist, axis=1)
            signed = np.where(g[np.arange(k), face] < 0.0, -dist.min(axis=1), dist.min(axis=1))
            return R_TUBE - signed.min()

        gmin, st, worst = run(model, 1e-5, 0.003, model.translation(bar, (0, 0, -1.0)), watch=depth)
        p = model.M_full @ st.v
        pz = p[: bar.ndof].reshape(-1, 6)[:, 2].sum() + p[bar.ndof :][2::3].sum()
        return gmin, worst, pz / bar.mass, st.v[:3]

    gmin, worst, pz, v = run_over(True)
    assert gmin >= -1e-9 and worst <= 1e-6
    assert pz == pytest.approx(-1.0, abs=1e-12)
    assert v[0] > 0.3  # pushed off along the edge's normal, out and up
    assert run_over(False)[1] > 1e-3


def test_a_rod_dropped_along_a_held_rod_stays_on_it():
    """A rod of 4 elements dropped at 0.5 m/s along a held rod of 4 (parallel, offset by 3 cm
    along the axis, so that no node meets a node), 0.05 s: the segments touch along a line,
    where the nodes of either rod against the other's segments hold them (the segment pairs
    near parallel are left out). The solver's gaps stay ≥ −1e-9 m, and the tubes, sampled every
    1.5 mm along rod a against rod b's segments, stay apart to 1e-9 m. (With one contact per
    segment and none at the nodes the position correction cycled at 2 ms.)"""
    a = rod([-0.12, 0.0, 2 * R_TUBE + 0.001], [0.18, 0.0, 2 * R_TUBE + 0.001], 4)
    b = rod([-0.2, 0.0, 0.0], [0.2, 0.0, 0.0], 4).clamp(0).clamp(-1)
    model = Model([a, b], [Contact(a, b, clearance=2 * R_TUBE)])
    s = np.linspace(0.0, 1.0, 51)[:, None]

    def overlap(st):
        xa, xb = a.positions(st.q[: a.ndof]), b.positions(st.q[a.ndof :])
        pts = np.concatenate([xa[i] * (1 - s) + xa[j] * s for i, j in a.segments()])
        far = min(
            segment_distance(
                pts, np.broadcast_to(xb[i], pts.shape), np.broadcast_to(xb[j], pts.shape)
            ).min()
            for i, j in b.segments()
        )
        return 2 * R_TUBE - far

    gmin, st, deepest = run(
        model, 1e-4, 0.05, model.translation(a, (0.0, 0.0, -0.5)), watch=overlap
    )
    assert gmin >= -1e-9 and deepest <= 1e-9
