"""Coulomb friction on the tube contacts of a Beam3D against rigid bodies in space
(fecontact.contact.beam3d_pairs: TubeRigidContact, TubeBoxContact) and on its nodes against a
plane (the point under each section, which the section's turn moves: a rod rolls), against the
exact answers of a body sliding under gravity: a stop after v₀²/(2μg), an incline that holds
for μ ≥ tan θ and is slid down at g(sin θ − μ cos θ) otherwise, a ball that ends rolling at
5/7 of its launch speed, a rod pushed across itself on a plane at 2/3; and the slip rows as
the derivatives of the slips."""

import numpy as np
import pytest

from fecontact import Model, simulate
from fecontact.bodies import Beam2D, Beam3D, Material, RigidBody3D, Section
from fecontact.bodies.rigid import Disk, RigidBody2D
from fecontact.bodies.shapes3d import Ball, Box, Capsule
from fecontact.contact import Circle, Contact, Plane, Point, Sphere
from fecontact.contact.beam3d_box import closest_to_box
from fecontact.testing import moved_on_group, slip_derivative_errors
from fecontact.time.settings import IntegratorOptions

STEEL = Material(210e9, nu=0.3, rho=7850.0)
R_TUBE = 0.005
G = 9.81


def rod(a, b, n=1):
    return Beam3D.straight(a, b, n, STEEL, Section.circle(R_TUBE))


def held_rod(a, b):
    return rod(a, b).clamp(0).clamp(1)


# -- the rows --------------------------------------------------------------------------------
def partners():
    """A rod (three elements, bent out of straight by q) against a ball, a capsule and a box
    (turned), each near one of its segments."""
    ball = RigidBody3D.uniform(1.0, [0.1, 0.03, -0.02], Ball(0.02))
    capsule = RigidBody3D.uniform(1.0, [-0.1, 0.0, -0.03], Capsule(0.01, 0.08))
    # (the box turned below the rod: the segments outside it, where the rows are derivatives;
    # inside, two faces can be equally deep, a kink of the gap)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.15], Box(0.3, 0.2, 0.1))
    return {"ball": ball, "capsule": capsule, "box": box}


@pytest.mark.parametrize("name", ["ball", "capsule", "box"])
def test_slip_rows_are_the_derivatives_of_the_slips(name):
    """G_T of every dof (both bodies, rigid rotations in the body frame) against the central
    difference of the pair's exact slip T·(Δx_tube − Δx_rigid) between q ⊕ d and q ⊕ (−d),
    |d| = 1e-7: the material points are those at q ⊕ d, which moves them by O(|d|), so the
    difference agrees to O(|d|) (1e-6 with the arms of 0.1 m here)."""
    bar = rod([-0.2, 0.0, 0.0], [0.2, 0.02, 0.01], 3)
    other = partners()[name]
    pair = Contact(bar, other, clearance=R_TUBE, friction=0.3)
    model = Model([bar, other], [pair], gravity=(0.0, 0.0, 0.0))
    q = 1e-3 * np.random.default_rng(7).normal(size=model.n)
    q[-3:] = [0.1, -0.2, 0.3]
    assert name != "box" or pair.gaps(q).min() > 0.0  # (a core's distance is smooth anyway)
    dofs, GT, T = pair.tangents(q)
    # the tube's section turns under each (its rotations' six columns; under a box its spin
    # about the segment alone, TubeBoxContact)
    assert GT.shape == (pair.size, 2, 18) and np.abs(GT[:, :, 6:12]).max() > 0.1
    assert np.abs(GT[:, :, 12:]).max() > 1e-3
    assert_slip_rows(model, pair, q, dofs, GT, T)


def assert_slip_rows(model, pair, q, dofs, GT, T) -> None:
    """Each column of the slip rows GT against the central difference (ε = 1e-7) of the exact
    slips, on every dof they name: O(ε²) truncation and round-off over ε on slips of order
    1 leave 1e-6 with margin."""
    for j in np.unique(dofs):
        d = np.zeros(model.n)
        d[j] = 1e-7
        slip = pair.slips(moved_on_group(model, q, d), moved_on_group(model, q, -d), T) / 2e-7
        col = (dofs == j).astype(float)
        np.testing.assert_allclose(slip, np.einsum("mtk,mk->mt", GT, col), atol=1e-6)


def test_a_segment_along_a_face_touches_it_at_the_middle_of_its_stretch_over_it():
    """A segment parallel to a box's top face is equally near along its stretch over the face:
    the contact is at the middle of that stretch (the point does not jump with round-off)."""
    half = np.array([0.1, 0.1, 0.05])
    A = np.array([[-0.3, 0.0, 0.06], [-0.05, 0.02, 0.06], [0.0, -0.3, 0.07]])
    B = np.array([[0.0, 0.0, 0.06], [0.05, 0.02, 0.06], [0.0, 0.3, 0.07]])
    xi, s, rho, nb = closest_to_box(A, B, half)
    np.testing.assert_allclose(rho[:, :2], [[-0.05, 0.0], [0.0, 0.02], [0.0, 0.0]], atol=1e-15)
    np.testing.assert_allclose(s, [0.01, 0.01, 0.02], atol=1e-15)
    np.testing.assert_allclose(nb, [[0, 0, 1]] * 3)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_node_rows_of_a_beam_take_the_turn_of_its_sections(dim):
    """A beam's nodes against a tilted plane and a circle (a sphere in space), 5 mm of
    clearance: the slip rows of the point under each section, x − c n, on the translations
    and the rotations, against central differences of the pair's slips (that material point
    turned back with its section) on the group, a beam bent and turned at random. The
    differences agree to O(ε²) (measured ≤ 2.6e-11 against rows of order 1 at ε = 1e-6).
    In space the same for the segments against the sphere (TubeSphereContact), whose point
    at ξ turns with its ends' sections interpolated (measured 1.3e-11)."""
    rng = np.random.default_rng(0)
    if dim == 3:
        bar = Beam3D.straight([0, 0, 0.01], [0.5, 0.1, 0.02], 5, STEEL, Section.circle(R_TUBE))
        obstacles = (Plane([0, 0, 0], [0.1, 0.2, 1.0]), Sphere([0.2, 0.0, -0.5], 0.5))
    else:
        section = Section.rectangle(0.05, 2 * R_TUBE)
        bar = Beam2D.straight([0, 0.01], [0.5, 0.02], 5, STEEL, section)
        obstacles = (Plane([0, 0], [0.1, 1.0]), Circle([0.2, -0.5], 0.5))
    for obstacle in obstacles:
        nodes = list(range(bar.n_nodes))  # (the nodes' pair: a circle takes segments else)
        pair = Contact(bar, obstacle, nodes=nodes, clearance=R_TUBE, friction=0.3)
        model = Model([bar], [pair])
        q = 0.03 * rng.normal(size=model.n)
        _, W, T = pair.tangents(q)
        assert np.abs(W[:, :, dim:]).max() > 1e-3  # the rotations move the point
        errors, largest = slip_derivative_errors(pair, model, q, T)
        assert errors[-1] < 1e-9 * largest
    if dim == 3:
        pair = Contact(bar, obstacles[1], clearance=R_TUBE, friction=0.3)
        model = Model([bar], [pair])
        q = 0.03 * rng.normal(size=model.n)
        _, W, T = pair.tangents(q)
        assert W.shape[2] == 12 and np.abs(W[:, :, 6:]).max() > 1e-3
        errors, largest = slip_derivative_errors(pair, model, q, T)
        assert errors[-1] < 1e-9 * largest


def test_two_tubes_slip_rows_are_the_derivatives_of_their_slips():
    """Two rods crossing 1 mm apart (three elements each, bent out of straight by q): the
    slip rows of every contact (segment pairs, and each rod's nodes against the other's
    segments) carry both sections' turns, each touching point on its own tube (r each) and
    moved by its section, against the central difference of the exact slips as above
    (1e-6 with the arms here)."""
    bar = rod([-0.2, 0.0, 0.0], [0.2, 0.02, 0.01], 3)
    other = rod([0.05, -0.2, -0.011], [-0.03, 0.2, -0.006], 3)
    pair = Contact(bar, other, clearance=2 * R_TUBE, friction=0.3)
    model = Model([bar, other], [pair], gravity=(0.0, 0.0, 0.0))
    q = 1e-3 * np.random.default_rng(7).normal(size=model.n)
    dofs, GT, T = pair.tangents(q)
    assert GT.shape == (pair.size, 2, 24) and np.abs(GT[:, :, 12:]).max() > 1e-3
    assert_slip_rows(model, pair, q, dofs, GT, T)


# -- sliding under gravity -------------------------------------------------------------------
def rod_on(partner: str, mu: float, theta: float = 0.0, n: int = 4, **options):
    """A free rod of 20 cm (``n`` elements) lying on a plane or on the top of a held box (its
    segments along the face), gravity tilted by ``theta`` (rad) down −x: the floor as an
    incline. Returns (model, rod)."""
    bar = rod([-0.1, 0.0, R_TUBE], [0.1, 0.0, R_TUBE], n)
    gravity = (-G * np.sin(theta), 0.0, -G * np.cos(theta))
    if partner == "plane":
        return Model([bar], [Contact(bar, Plane([0, 0, 0], [0, 0, 1]), clearance=R_TUBE,
                                     friction=mu)], gravity=gravity), bar  # fmt: skip
    box = RigidBody3D.uniform(10.0, [0.0, 0.0, -0.05], Box(0.6, 0.6, 0.1)).fix()
    pair = Contact(bar, box, clearance=R_TUBE, friction=mu)
    return Model([bar, box], [pair], gravity=gravity), bar


def slide(model, bar, v0, t_end=0.25, h=1e-3, options=None):
    """(t, centre-node displacements (k, 3), velocities (k, 3)) of the rod's middle node."""
    v = model.translation(bar, v0)
    mid = 6 * (bar.n_nodes // 2)
    t, x, u = [], [], []
    for st in simulate(model, h, t_end, options or IntegratorOptions(), v0=v):
        assert st.gaps.min() >= -1e-9
        t.append(st.t)
        x.append(st.q[mid : mid + 3].copy())
        u.append(st.v[mid : mid + 3].copy())
    return np.array(t), np.array(x), np.array(u)


def _rolls_across(where: str, mu: float, v0: float, options) -> None:
    """The rod on ``where`` pushed across itself at v₀ slows at μg until t* = v₀/(3μg), then
    rolls at 2v₀/3 (a cylinder, I = mR²/2), to 1e-12 m/s at every step but the one holding
    t* (h = 1 ms: that step rolls from inside it)."""
    t, x, u = slide(*rod_on(where, mu), (0.0, v0, 0.0), t_end=0.1, options=options)
    t_star = v0 / (3 * mu * G)
    exact = np.where(t < t_star, v0 - mu * G * t, 2 * v0 / 3)
    kept = np.abs(t - t_star) > 1e-3
    np.testing.assert_allclose(u[kept, 1], exact[kept], atol=1e-12)
    np.testing.assert_allclose(u[:, [0, 2]], 0.0, atol=1e-12)


def test_a_rod_on_a_box_top_slides_along_itself_as_on_a_plane_and_rolls_across_itself():
    """A rod lying on a held box (its segments, whose slip rows take their sections' turn)
    pushed at 0.5 m/s, μ = 0.3. Along itself each segment's rows lie at its nodes, the
    points under their sections, as a plane's: the friction's moment μN r bends the rod as
    on the plane, and while it slides the run is the plane's to round-off (measured 2.4e-16
    m and 2.3e-12 m/s; bound 1e-11, the friction solves' stopping tolerance carried by the
    bending; with the sections' spin alone, the rows before, the box's rod stayed straight
    and left the plane's by 6.5e-10 m/s; after the stop the two stick to that tolerance,
    8.6e-10 m/s apart). It stops after v₀²/(2μg) = 4.247 cm, the stop inside a step
    (measured 1.6e-8 m short at h = 1 ms). Across itself the friction under the sections
    spins it up and it rolls from t* = v₀/(3μg) at 2v₀/3, exact at every step but the one
    holding t* (measured 3.5e-14 m/s)."""
    mu, v0 = 0.3, 0.5
    # the decoupled contact phase, whose positional friction is exact for a constant force
    # (the smooth friction of the default stops at the smooth Newton's tolerance: 9.9e-11
    # and 7.9e-10 m/s measured, the same stopping distance to 1e-8 m)
    decoupled = IntegratorOptions(smooth_contact="off")
    t, x, u = slide(*rod_on("box", mu), (v0, 0.0, 0.0), options=decoupled)
    _, x_plane, u_plane = slide(*rod_on("plane", mu), (v0, 0.0, 0.0), options=decoupled)
    sliding = t < v0 / (mu * G)
    np.testing.assert_allclose(x[sliding], x_plane[sliding], rtol=0, atol=1e-11)
    np.testing.assert_allclose(u[sliding], u_plane[sliding], rtol=0, atol=1e-11)
    assert x[-1, 0] == pytest.approx(v0**2 / (2 * mu * G), abs=1e-7)
    _rolls_across("box", mu, v0, decoupled)


def test_a_rod_on_a_plane_rolls_across_itself_and_slides_along_itself():
    """The rod lying on a plane, its nodes' rows holding the point under each section,
    x − R n, which the section's turn moves: pushed across itself at v₀ = 0.5 m/s, μ = 0.3,
    the friction there spins it up, and it rolls from t* = v₀/(3μg) at 2v₀/3 (a cylinder,
    I = mR²/2, the sections' polar inertia). The decoupled step is exact for the constant
    force at every step but the one holding t* (measured 2.6e-14 m/s; before, the rows were
    the centreline's and it slid to a stop). Pushed along itself it stops at v₀²/(2μg): the
    friction's moment μN R at each node bends the rod, which moves the middle node off
    v₀ − μgt by 6.5e-10 m/s before the stop and rings at 2.4e-8 m/s after it, and the stop
    by 1.6e-8 m (bound 1e-5 m, 0.02 % of the distance)."""
    mu, v0 = 0.3, 0.5
    decoupled = IntegratorOptions(smooth_contact="off")
    _rolls_across("plane", mu, v0, decoupled)
    t, x, u = slide(*rod_on("plane", mu), (v0, 0.0, 0.0), options=decoupled)
    assert x[-1, 0] == pytest.approx(v0**2 / (2 * mu * G), abs=1e-5)


@pytest.mark.parametrize("partner", ["plane", "box"])
def test_on_an_incline_the_rod_sticks_for_mu_at_least_tan_theta_and_else_slides(partner):
    """An incline of 20° (gravity tilted): for μ = 1.01 tan θ and above the rod stays, and
    for μ = 0.2 < tan θ it slides down at g(sin θ − μ cos θ) from rest. On the plane and on
    the box alike the friction acts under the sections, x − R n: its moment μN R bends the
    rod, which rings at up to 2.9e-8 m/s and settles 1.4e-11 m down the slope (at tan θ
    exactly the nodes that the bending presses less slip, 1e-7 m/s), and the slide down
    keeps g(sin θ − μ cos θ) to 1.1e-10 m/s (bounds 1e-7, 1e-10 and 1e-9: ten times over)."""
    theta = np.radians(20.0)
    speed, shift, slide_error = 1e-7, 1e-10, 1e-9
    for mu in (1.01 * np.tan(theta), 0.5):
        t, x, u = slide(*rod_on(partner, mu, theta), np.zeros(3), t_end=0.1)
        assert np.abs(u).max() < speed and np.abs(x).max() < shift
    mu = 0.2
    t, x, u = slide(*rod_on(partner, mu, theta), np.zeros(3), t_end=0.1)
    a = G * (np.sin(theta) - mu * np.cos(theta))
    np.testing.assert_allclose(u[:, 0], -a * t, atol=slide_error)
    np.testing.assert_allclose(u[:, 1:], 0.0, atol=1e-12)


def test_the_sliding_rod_on_a_box_is_independent_of_p_and_k():
    """The rod on the box top, pushed along and across itself (it slides along and rolls
    across), with the penalty and the multiplier scales ×10 and ×0.1: the same positions to
    1e-12 m (the semi-smooth Newton's solution, not its path). The sections' spin rows make
    the contacts' Delassus matrix ill-conditioned (2.2e5), which carries the friction
    solves' stopping tolerance into the velocities: at the default gap tolerance 1e-12 the
    penalty ×10 moves the positions by 5.4e-11 m, at 1e-14 (here) by 7.1e-14 m (p × 1000
    and k ÷ 100: 9.7e-14 and 1.3e-13 m)."""
    mu, v0 = 0.3, np.array([0.5, 0.3, 0.0])
    base = slide(*rod_on("box", mu), v0, t_end=0.15, options=IntegratorOptions(tol_gap=1e-14))[1]
    for p, k in ((10.0, 1.0), (0.1, 1.0), (1.0, 10.0), (1.0, 0.1)):
        options = IntegratorOptions(penalty_scale=p, multiplier_scale=k, tol_gap=1e-14)
        x = slide(*rod_on("box", mu), v0, t_end=0.15, options=options)[1]
        np.testing.assert_allclose(x, base, rtol=0, atol=1e-12)


def test_a_ball_launched_along_a_held_rod_ends_rolling_at_five_sevenths():
    """A rigid ball (radius 2 cm) on a held rod, launched along it at 0.5 m/s without spin,
    μ = 0.3: friction at the ball's contact point slows it at μg and spins it up at
    5μg/(2ρ) until it rolls, at t = 2v₀/(7μg), at 5v₀/7 with Ω = v/ρ. Exact at every step
    (measured 3.3e-16 m/s): the ball's rotation is in the slip rows."""
    mu, v0, rb = 0.3, 0.5, 0.02
    rail = held_rod([0.0, -0.5, 0.0], [0.0, 0.5, 0.0])
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, R_TUBE + rb], Ball(rb))
    model = Model([rail, ball], [Contact(rail, ball, clearance=R_TUBE, friction=mu)],
                  gravity=(0.0, 0.0, -G))  # fmt: skip
    o = model.offset_of(ball)
    t, v, w = [], [], []
    for st in simulate(
        model, 1e-3, 0.1, IntegratorOptions(), v0=model.translation(ball, (0, v0, 0))
    ):
        t.append(st.t)
        v.append(st.v[o : o + 3].copy())
        w.append(st.v[o + 3 : o + 6].copy())
    t, v, w = np.array(t), np.array(v), np.array(w)
    t_roll = 2 * v0 / (7 * mu * G)
    exact = np.where(t < t_roll, v0 - mu * G * t, 5 * v0 / 7)
    np.testing.assert_allclose(v[:, 1], exact, atol=1e-12)
    np.testing.assert_allclose(v[:, [0, 2]], 0.0, atol=1e-12)
    # the ball's frame turns about x: its body-frame Ω stays along x (−v/ρ: rolling along +y)
    np.testing.assert_allclose(w[-1], [-5 * v0 / 7 / rb, 0.0, 0.0], atol=1e-10)


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_a_box_sliding_across_two_held_rods_stops_at_the_coulomb_distance(mu):
    """A rigid box on two held rods, launched across them at 0.5 m/s: it stops after
    v₀²/(2μg) (to O(μg h²), measured 1.6e-8 m), flat (no rotation above 1e-15 rad); without
    friction it keeps its speed."""
    v0 = 0.5
    rails = [held_rod([-0.5, y, 0.0], [0.5, y, 0.0]) for y in (-0.1, 0.1)]
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, R_TUBE + 0.025], Box(0.1, 0.5, 0.05))
    pairs = [Contact(r, box, clearance=R_TUBE, friction=mu) for r in rails]
    model = Model([*rails, box], pairs, gravity=(0.0, 0.0, -G))
    o = model.offset_of(box)
    t, y, v, turn = [], [], [], []
    decoupled = IntegratorOptions(smooth_contact="off")  # (exact: see the rod above)
    for st in simulate(model, 1e-3, 0.2, decoupled, v0=model.translation(box, (0, v0, 0))):
        assert st.gaps.min() >= -1e-9
        t.append(st.t)
        y.append(st.q[o + 1])
        v.append(st.v[o + 1])
        turn.append(np.abs(st.q[o + 3 : o + 6]).max())
    t = np.array(t)
    np.testing.assert_allclose(v, np.maximum(v0 - mu * G * t, 0.0), atol=1e-12)
    assert max(turn) < 1e-15
    if mu:
        assert y[-1] == pytest.approx(v0**2 / (2 * mu * G), abs=1e-7)


@pytest.mark.parametrize("partner", ["disk", "point"])
def test_a_disk_or_point_on_a_planar_beam_slips_against_its_sections_surface(partner):
    """A rigid disk and a rigid point 1 mm off a straight strip (turned by 0.4 rad, its
    sections turned at random: the centreline stays straight, so ξ and the normal n are
    known), 5 mm of clearance: the slip rows of the beam's columns against central
    differences of the motion of the touching point x(ξ) + R(Δθ(ξ)) c n, each end's section
    turning its arm (rows of order 1 on the translations, c on the turns). The section's
    rows are c(1 − ξ) and cξ: the arc of its surface point. Measured 7.0e-12 (bound 1e-9:
    round-off over ε of rows of order 1)."""
    c, xi, angle = R_TUBE, 0.3, 0.4
    axis = np.array([np.cos(angle), np.sin(angle)])
    n = np.array([-axis[1], axis[0]])
    strip = Beam2D.straight([0, 0], 0.5 * axis, 5, STEEL, Section.rectangle(0.05, 2 * c))
    radius = 0.02 if partner == "disk" else 0.0
    centre = (1 + xi) * 0.1 * axis + (c + radius + 1e-3) * n  # over element 1 at ξ
    other = RigidBody2D.uniform(1.0, centre, Disk(radius)) if partner == "disk" else None
    pair = Contact(strip, other or Point(centre), clearance=c, friction=0.3)
    model = Model([strip] + ([other] if other else []), [pair], (0.0, 0.0))
    q = np.zeros(model.n)
    q[2 : strip.ndof : 3] = 0.05 * np.random.default_rng(3).normal(size=strip.n_nodes)
    dofs, GT, T = pair.tangents(q)
    row = 1 if partner == "disk" else 0  # (the disk's rows are per element; the point's 2)
    np.testing.assert_allclose(T[row, 0], [n[1], -n[0]], atol=1e-15)

    def touching(qq):
        x = strip.positions(qq[: strip.ndof])
        turns = qq[2 : strip.ndof : 3] - q[2 : strip.ndof : 3]
        # (e_z × n = −axis: a section turned by δ holds its arm at cos δ n − sin δ axis)
        ends = [x[i] + c * (np.cos(turns[i]) * n - np.sin(turns[i]) * axis) for i in (1, 2)]
        return (1 - xi) * ends[0] + xi * ends[1]

    for j in range(3, 9):  # (u_x, u_y, θ) of the element's nodes 1 and 2
        d = np.zeros(model.n)
        d[j] = 1e-6
        rate = T[row, 0] @ (touching(q + d) - touching(q - d)) / 2e-6
        np.testing.assert_allclose(GT[row, 0, dofs[row] == j].sum(), -rate, rtol=0, atol=1e-9)
    turns = GT[row, 0, np.isin(dofs[row], [5, 8])]
    np.testing.assert_allclose(turns, [c * (1 - xi), c * xi], rtol=1e-12)


def test_a_rod_across_two_rails_rolls_at_two_thirds():
    """The free rod of 20 cm (four elements) lying across two held capsules (rails of radius
    1 cm under the middles of its end elements, gravity across both), pushed along the rails
    at v₀ = 0.5 m/s, μ = 0.3: the friction under the tube's sections, between their nodes,
    spins it up and it rolls from t* = v₀/(3μg) at 2v₀/3 (centreline rows slid it on at
    v₀ − μgt, 0.206 m/s at 0.1 s). Supported at two points the rod sags and rings; over the
    last 20 ms its middle moves at 2v₀/3 − 1.06e-4 m/s, O(h²) (4.3e-4 at h = 2 ms; bound
    1e-3 m/s: ten times over).
    The penalty × 1000 and the multipliers ÷ 100 move its positions by 4.6e-12 m and 9e-15 m
    (measured, docs/explanation/friction.md)."""
    mu, v0, rail = 0.3, 0.5, 0.01
    bar = rod([-0.1, rail + R_TUBE, 0.0], [0.1, rail + R_TUBE, 0.0], 4)
    rails = [RigidBody3D.uniform(1.0, [x, 0, 0], Capsule(rail, 0.4)).fix() for x in (-0.075, 0.075)]
    pairs = [Contact(bar, r, clearance=R_TUBE, friction=mu) for r in rails]
    model = Model([bar, *rails], pairs, gravity=(0.0, -G, 0.0))  # (capsules lie along z)
    speeds = [
        st.v[14]  # the middle node's u_z
        for st in simulate(
            model, 1e-3, 0.1, IntegratorOptions(), v0=model.translation(bar, (0, 0, v0))
        )
    ]
    assert np.mean(speeds[-20:]) == pytest.approx(2 * v0 / 3, abs=1e-3)


def test_a_box_struck_on_a_held_rod_is_independent_of_p():
    """A box (0.5 kg) thrown spinning onto a held rod (10 elements, μ = 0.3, e_N = 0.5): it
    strikes two segments at their shared node, whose slip rows must be one row twice (the
    spin about the sections' normal at the node, not each segment's chord). With the
    chords' directions the rows were near duplicates and the penalty × 1000 chose another
    split of the impulses: the runs parted by 1.9e-4 m at the strike (7.2 ms); now by
    ≤ 1e-10 m over 0.1 s (measured 2.0e-10 m at 0.1 s; 1e-8 m: the friction solves'
    tolerance carried over the few steps here, well under the split's 1e-4)."""
    ends = []
    for p in (1.0, 1000.0):
        bar = Beam3D.straight([-0.3, 0, 0], [0.3, 0, 0], 10, STEEL, Section.circle(R_TUBE))
        bar.clamp(0).clamp(10)
        box = RigidBody3D.uniform(0.5, [0.05, 0.0, R_TUBE + 0.032], Box(0.1, 0.08, 0.06))
        pair = Contact(bar, box, clearance=R_TUBE, restitution=0.5, friction=0.3)
        model = Model([bar, box], [pair], gravity=(0.0, 0.0, -G))
        v0 = np.zeros(model.n)
        o = model.offset_of(box)
        v0[o : o + 6] = (0.3, 0.2, -1.0, 4.0, 6.0, 2.0)
        states = simulate(model, 2e-4, 8e-3, IntegratorOptions(penalty_scale=p), v0=v0)
        ends.append([st.q.copy() for st in states][-1])
    np.testing.assert_allclose(ends[1], ends[0], rtol=0, atol=1e-8)


def test_a_rod_dropped_on_a_box_top_lands_as_on_a_plane():
    """A rod (20 cm, four elements) tilted by 5° dropped on a held box's top at (1, 0.3, −1)
    m/s, μ = 0.3: its low end strikes, it slaps down and slides. Over the face its segments'
    rows lie at their nodes, the points under the sections, which the sections' turn moves as
    a plane's nodes' rows do: the box's run is the plane's to the solves' tolerance (measured
    1.1e-11 m/s on the nodes' velocities, 2.1e-10 rad/s on their sections' of up to 160
    rad/s; bounds 1e-9 and 1e-8, the friction solves' stopping tolerance carried through the
    strikes). With the sections' spin about the axis alone (the rows before) the bending's
    turn did not move the touching points: the rod left the plane's run by 0.58 m/s and 160
    rad/s, its middle ending at 0.552 m/s along x against the plane's 0.596."""
    tilt = np.radians(5.0)
    low = R_TUBE + 1e-3
    a, b = [-0.1 * np.cos(tilt), 0.0, low], [0.1 * np.cos(tilt), 0.0, low + 0.2 * np.sin(tilt)]
    runs = []
    for partner in ("plane", "box"):
        bar = rod(a, b, 4)
        if partner == "plane":
            model = Model([bar], [Contact(bar, Plane([0, 0, 0], [0, 0, 1]), clearance=R_TUBE,
                                          friction=0.3)], gravity=(0.0, 0.0, -G))  # fmt: skip
        else:
            box = RigidBody3D.uniform(10.0, [0.0, 0.0, -0.05], Box(0.6, 0.6, 0.1)).fix()
            pair = Contact(bar, box, clearance=R_TUBE, friction=0.3)
            model = Model([bar, box], [pair], gravity=(0.0, 0.0, -G))
        v0 = model.translation(bar, (1.0, 0.3, -1.0))
        runs.append(
            np.array([st.v[: 6 * bar.n_nodes] for st in simulate(model, 1e-3, 0.03, v0=v0)])
        )
    apart = np.abs(runs[1] - runs[0]).reshape(len(runs[0]), -1, 6)
    assert apart[..., :3].max() < 1e-9 and apart[..., 3:].max() < 1e-8
