"""Coulomb friction on convex pairs (GJK/EPA and the face-clipping manifold) against exact
answers: a box sliding on a box to its stop, a box on an incline below and above tan θ = μ, a
ball rolling out of a slide on a box face, a cylinder rolling on a box face as on a plane."""

import numpy as np
import pytest
from conftest import needs_coal

from fecontact import (
    Ball,
    Box,
    Capsule,
    Contact,
    ConvexMesh,
    Cylinder,
    IntegratorOptions,
    Model,
    Plane,
    RigidBody3D,
)
from fecontact.rotations import exp, log
from fecontact.time.simulate import simulate
from fecontact.time.stats import StepStats

G = 9.81
SLAB = Box(2.0, 1.0, 0.2)  # the fixed body, its top face at z = 0
BRICK = Box(0.2, 0.15, 0.1)


def on_slab(body, mu, v0, t_end, options=None, q0=None, slab=SLAB, stats=None):
    """``body`` (first, 6 dofs) on a fixed ConvexMesh slab whose top face is z = 0."""
    slab = RigidBody3D.uniform(5.0, [0.0, 0.0, -0.1], ConvexMesh(slab.vertices)).fix()
    model = Model([body, slab], [Contact(body, slab, friction=mu)], gravity=(0.0, 0.0, -G))
    q = np.zeros(12) if q0 is None else np.r_[q0, np.zeros(6)]
    return list(simulate(model, 1e-3, t_end, options, q0=q, v0=np.r_[v0, np.zeros(6)], stats=stats))


def on_plane(body, mu, v0, t_end, options=None, q0=None):
    floor = Contact(body, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), friction=mu)
    model = Model([body], [floor], gravity=(0.0, 0.0, -G))
    return list(simulate(model, 1e-3, t_end, options, q0=q0, v0=v0))


def brick(shape=BRICK):
    return RigidBody3D.uniform(1.0, [0.0, 0.0, 0.05], shape)


MU, V0 = 0.4, np.r_[1.0, 0.5, 0.0, 0.0, 0.0, 0.0]


@needs_coal
def test_a_box_sliding_on_a_box_stops_at_the_exact_time_and_distance():
    """A ConvexMesh brick launched at |v₀| = 1.118 m/s on a ConvexMesh slab, its four corners
    in the manifold: the speed falls at μg to t* = |v₀|/(μg) = 0.285 s and it stops after
    |v₀|²/(2μg) = 0.159 m, along its launch direction. The Coulomb solves hold the slip to
    the gap tolerance (1e-12 of the model size) at every step, and that error accumulates:
    measured 9.7e-9 m/s and 1.2e-8 m; bound 1e-7."""
    stats = StepStats()
    states = on_slab(brick(ConvexMesh(BRICK.vertices)), MU, V0, 0.35, stats=stats)
    t = np.array([s.t for s in states])
    v = np.array([s.v[:3] for s in states])
    speed0 = np.linalg.norm(V0[:3])
    assert np.abs(np.linalg.norm(v, axis=1) - np.maximum(speed0 - MU * G * t, 0.0)).max() < 1e-7
    moved = states[-1].q[:3]
    assert np.linalg.norm(moved) == pytest.approx(speed0**2 / (2 * MU * G), abs=1e-7)
    assert np.abs(np.cross(moved, V0[:3])).max() < 1e-7  # along v₀
    assert np.abs(v[t > speed0 / (MU * G) + 1e-3]).max() < 1e-12  # stuck after t*
    assert min(s.gaps.min() for s in states[1:]) > -1e-12
    assert stats.contact.coulomb.gauss_seidel_solves == 0


def test_a_convex_mesh_box_on_a_plane_is_the_box_on_the_plane():
    """On a plane the mesh's vertices are the box's corners (node contact): the same motion
    to round-off (1e-13) through the slide and the stop."""
    mesh = on_plane(brick(ConvexMesh(BRICK.vertices)), MU, V0, 0.35)
    box = on_plane(brick(), MU, V0, 0.35)
    for a, b in zip(mesh, box, strict=True):
        assert np.abs(a.q - b.q).max() < 1e-13 and np.abs(a.v - b.v).max() < 1e-13


@needs_coal
@pytest.mark.parametrize("tol_gap, bound", [(1e-12, 1e-7), (1e-14, 2e-9)])
def test_a_box_on_a_box_slides_as_the_box_on_a_plane_to_the_solve_tolerance(tol_gap, bound):
    """GJK/EPA and the manifold against the analytic box on the plane z = 0: the same slide
    and stop. The difference is the Coulomb solve's tolerance accumulated over the slide (the
    normal forces of four coplanar corners are statically indeterminate, and an unbalanced
    yaw moment of the tolerance's size turns the mesh brick by nanoradians): measured
    4.8e-7, 2.1e-8 and 3.1e-10 m/s at tol_gap 1e-10, 1e-12 and 1e-14 (q: 2.7e-10 m at 1e-12)."""
    opts = IntegratorOptions(tol_gap=tol_gap)
    mesh = on_slab(brick(ConvexMesh(BRICK.vertices)), MU, V0, 0.35, opts)
    box = on_plane(brick(), MU, V0, 0.35, opts)
    assert len(mesh) == len(box)
    assert max(np.abs(a.v[:6] - b.v).max() for a, b in zip(mesh, box, strict=True)) < bound
    assert max(np.abs(a.q[:6] - b.q).max() for a, b in zip(mesh, box, strict=True)) < bound


THETA = 0.3  # rad: tan θ = 0.309


def incline(mu, t_end=0.3, options=None):
    """A ConvexMesh brick resting on a fixed slab tilted by θ about y (both convex meshes),
    released at rest; returns the states and the unit vector down the slope."""
    R = exp(np.array([0.0, -THETA, 0.0]))
    n = R @ np.array([0.0, 0.0, 1.0])
    slab = RigidBody3D.uniform(5.0, [0.0, 0.0, 0.0], ConvexMesh(SLAB.vertices @ R.T)).fix()
    top = RigidBody3D.uniform(1.0, 0.15 * n, ConvexMesh(BRICK.vertices))
    model = Model([top, slab], [Contact(top, slab, friction=mu)], gravity=(0.0, 0.0, -G))
    q0 = np.r_[0.0, 0.0, 0.0, log(R), np.zeros(6)]
    states = list(simulate(model, 1e-3, t_end, options, q0=q0))
    down = R @ np.array([-1.0, 0.0, 0.0])  # (the slope falls towards −x)
    return states, down


@needs_coal
@pytest.mark.parametrize("mu", [0.4, 0.32, 0.3, 0.2])
def test_a_box_on_an_incline_sticks_below_tan_theta_and_slides_at_the_exact_rate(mu):
    """μ > tan θ: it stays (speeds at round-off); μ < tan θ: it slides straight down the slope
    at g(sin θ − μ cos θ) from rest, without turning (constant forces: the scheme is exact;
    measured 1e-15 m/s)."""
    states, down = incline(mu)
    t = np.array([s.t for s in states])
    v = np.array([s.v[:3] for s in states])
    a = max(0.0, G * (np.sin(THETA) - mu * np.cos(THETA)))
    assert np.abs(v - np.outer(a * t, down)).max() < 1e-13
    assert max(np.abs(s.v[3:6]).max() for s in states) < 1e-12
    assert min(s.gaps.min() for s in states[1:]) > -1e-12


@needs_coal
def test_the_sliding_incline_is_independent_of_p_and_k():
    ref, _ = incline(0.2, t_end=0.1)
    for p, k in ((10.0, 1.0), (0.1, 1.0), (1.0, 10.0), (1.0, 0.1)):
        other, _ = incline(0.2, 0.1, IntegratorOptions(penalty_scale=p, multiplier_scale=k))
        assert max(np.abs(a.v - b.v).max() for a, b in zip(ref, other, strict=True)) < 1e-13


@needs_coal
def test_a_ball_launched_sliding_on_a_box_face_ends_rolling_at_five_sevenths():
    """A ball touches a face at one point, which is the single GJK witness: exact as on a
    plane, v = v₀ − μgt until t* = 2v₀/(7μg), then 5v₀/7 (measured 3e-15 m/s)."""
    r, v0, mu = 0.1, 2.0, 0.3
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, r], Ball(r))
    states = on_slab(ball, mu, np.r_[v0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.3)
    t = np.array([s.t for s in states])
    v = np.array([s.v[0] for s in states])
    exact = np.where(t < 2 * v0 / (7 * mu * G), v0 - mu * G * t, 5 * v0 / 7)
    assert np.abs(v - exact).max() < 1e-12
    assert max(abs(ball.center(s.q[:6])[2] - r) for s in states) < 1e-12


@needs_coal
def test_a_cylinder_rolling_on_a_box_face_rolls_as_on_a_plane():
    """A Cylinder is the prism of its rim points: lying on a side face and rolling at 1 m/s,
    it rocks from side face to side face (each edge strikes, e = 0: 1.0 → 0.705 m/s in
    0.5 s with 24 rim points). Its side faces in the manifold give the motion of its rim
    points on a plane (node contact) to the solve tolerance (measured 9.9e-10 m); it never
    drifts sideways."""
    n_rim, r = 24, 0.1
    R = exp(np.array([np.pi / 2, 0.0, 0.0])) @ exp(np.array([0.0, 0.0, np.pi / 2 + np.pi / n_rim]))
    shape = Cylinder(r, 0.2, n_rim)
    low = (shape.vertices @ R.T)[:, 2].min()  # a side face down
    q0 = np.r_[0.0, 0.0, 0.0, log(R)]
    v0 = np.r_[1.0, 0.0, 0.0, R.T @ np.array([0.0, 1.0 / r, 0.0])]
    slab = on_slab(RigidBody3D.uniform(1.0, [0.0, 0.0, -low], shape), 0.5, v0, 0.5, q0=q0)
    plane = on_plane(RigidBody3D.uniform(1.0, [0.0, 0.0, -low], shape), 0.5, v0, 0.5, q0=q0)
    assert max(np.abs(a.q[:6] - b.q).max() for a, b in zip(slab, plane, strict=True)) < 1e-8
    assert max(abs(s.v[1]) for s in slab) < 1e-12
    assert 0.6 < slab[-1].v[0] < 0.8  # slowed by its edges' strikes, still rolling


def capsule(x0=0.0, z0=0.05):
    """A capsule (r = 0.05 m, 0.3 m between its caps' centres) lying along x: q0 turns its
    body z axis onto x."""
    return RigidBody3D.uniform(1.0, [x0, 0.0, z0], Capsule(0.05, 0.3)), np.r_[
        0, 0, 0, 0, np.pi / 2, 0
    ]


@needs_coal
@pytest.mark.parametrize("mu", [0.0, 0.4])
def test_a_capsule_rolling_on_a_box_face_rolls_as_on_a_plane(mu):
    """Lying on a face it touches along a segment: its axis clipped by the face gives two
    points (its caps), as its two cap balls on a plane. Rolling along y at 1 m/s (ω = v/r):
    the same motion as on the plane to round-off (measured 9e-15 m frictionless, 3e-16 m with
    μ = 0.4; the slip over a step is the rows applied to the increments, zero when rolling).
    With one GJK witness along the segment its first step failed."""
    body, q0 = capsule()
    omega = exp(q0[3:]).T @ np.array([-1.0 / 0.05, 0.0, 0.0])
    v0 = np.r_[0.0, 1.0, 0.0, omega]
    slab = on_slab(body, mu, v0, 0.3, q0=q0)
    plane = on_plane(capsule()[0], mu, v0, 0.3, q0=q0)
    assert max(np.abs(a.q[:3] - b.q[:3]).max() for a, b in zip(slab, plane, strict=True)) < 1e-12
    assert max(np.abs(a.v[:6] - b.v).max() for a, b in zip(slab, plane, strict=True)) < 1e-11
    assert min(s.gaps.min() for s in slab[1:]) > -1e-12


@needs_coal
def test_a_capsule_sliding_along_its_axis_stops_at_the_exact_distance():
    """Pushed along its axis at 1 m/s on a face with μ = 0.4 it slides on both caps and
    stops after v₀²/(2μg) = 0.1274 m: measured 4.9e-8 m short, as its caps on a plane (the
    step holding t* sticks within it), and the two runs' stops agree to 1.8e-10 m; speeds
    8.9e-9 m/s off v₀ − μgt (the Coulomb solve's tolerance accumulated as for the brick)."""
    body, q0 = capsule()
    states = on_slab(body, 0.4, np.r_[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.3, q0=q0)
    t = np.array([s.t for s in states])
    v = np.array([s.v[0] for s in states])
    assert np.abs(v - np.maximum(1.0 - 0.4 * G * t, 0.0)).max() < 1e-7
    assert states[-1].q[0] == pytest.approx(1.0 / (2 * 0.4 * G), abs=1e-7)
    plane = on_plane(capsule()[0], 0.4, np.r_[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.3, q0=q0)
    assert states[-1].q[0] == pytest.approx(plane[-1].q[0], abs=1e-9)


@needs_coal
@pytest.mark.parametrize("x0, rests", [(0.95, True), (1.05, False)])
def test_a_capsule_set_over_an_edge_rests_or_tips_off_it(x0, rests):
    """Set down 1 cm above the slab across its edge x = 1 m (its caps at x0 ± 0.15): with its
    centre over the face it rests on its inner cap and the edge (the clipped axis ends there),
    with the centre beyond it tips over the edge and falls; no gap below −1e-9 m."""
    body, q0 = capsule(x0, 0.06)
    states = on_slab(body, 0.0, np.zeros(6), 0.4, q0=q0)
    assert min(s.gaps.min() for s in states[1:]) > -1e-9
    centre = body.center(states[-1].q[:6])
    if rests:
        assert centre == pytest.approx([x0, 0.0, 0.05], abs=1e-9)
        assert np.abs(states[-1].v[:6]).max() < 1e-9
    else:
        assert centre[2] < -0.1 and centre[0] > 1.0
