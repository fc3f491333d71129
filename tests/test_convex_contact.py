"""Convex–convex contact of rigid bodies in space (GJK/EPA by coal, face-clipping manifold):
distances against closed forms, a box resting on a box, a box dropped corner first, two free
boxes colliding."""

import dataclasses
import sys

import numpy as np
import pytest
from conftest import load_case, needs_coal

from fecontact import (
    Ball,
    Box,
    Contact,
    ConvexMesh,
    InputError,
    IntegratorOptions,
    Model,
    RigidBody3D,
)
from fecontact.contact.convex_pairs import ConvexContact
from fecontact.contact.rigid3d_pairs import BallBoxContact
from fecontact.rotations import exp, log
from fecontact.simulation import run
from fecontact.time.simulate import simulate

G = 9.81
# a rotation that turns the corner (−1, −1, −1)/√3 of a cube straight down
_D = np.array([-1.0, -1.0, -1.0]) / np.sqrt(3.0)
_AXIS = np.cross(_D, [0.0, 0.0, -1.0])
CORNER_DOWN = exp(_AXIS / np.linalg.norm(_AXIS) * np.arccos(-_D[2]))


def _pair(a, b, q):
    pair = ConvexContact(a, b)
    pair.offsets = (0, 6)
    return pair, np.asarray(q, dtype=float)


@needs_coal
@pytest.mark.parametrize("gap", [0.3, 1e-6, 0.0, -1e-3, -0.05])
def test_the_gaps_of_a_box_over_a_box_face_and_corner_first_are_the_closed_forms(gap):
    """Face over face, offset sideways: every corner of the small box over the big face has
    the gap; corner first: the lowest corner, gap = z − 1/2 − √3/2 (unit cubes). GJK/EPA to
    1e-10 m, the manifold's projection exact: 1e-12 m."""
    big = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(1.0, 1.0, 1.0))
    small = RigidBody3D.uniform(1.0, [0.2, 0.1, 0.0], Box(0.4, 0.3, 0.2))
    pair, q = _pair(big, small, np.r_[np.zeros(6), 0.0, 0.0, 0.6 + gap, 0.0, 0.0, 0.0])
    g = pair.gaps(q)
    assert np.sort(g)[:4] == pytest.approx(np.full(4, gap), abs=1e-12)
    assert np.sort(g)[4] > 0.2
    cube = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(1.0, 1.0, 1.0))
    z = 0.5 + np.sqrt(3.0) / 2.0 + gap
    pair, q = _pair(big, cube, np.r_[np.zeros(6), 0.0, 0.0, z, log(CORNER_DOWN)])
    assert pair.gaps(q).min() == pytest.approx(gap, abs=1e-10)


@needs_coal
def test_a_ball_against_a_mesh_cube_has_the_analytic_ball_box_gap():
    """A Ball against a ConvexMesh cube by GJK/EPA against the closed-form ball–box pair:
    outside over a face, an edge and a corner, and overlapping (EPA), to 1e-9 m."""
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Ball(0.1))
    cube = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], ConvexMesh(Box(1.0, 1.0, 1.0).vertices))
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(1.0, 1.0, 1.0))
    exact = BallBoxContact(ball, box)
    exact.offsets = (0, 6)
    pair, _ = _pair(ball, cube, np.zeros(12))
    tilt = log(exp(np.array([0.3, -0.2, 0.5])))
    for x in ([0.1, 0.2, 0.7], [0.7, 0.65, 0.1], [0.62, 0.6, 0.58], [0.1, 0.0, 0.55]):
        q = np.r_[x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, tilt]
        g = pair.gaps(q)
        assert g.shape == (1,)
        assert g[0] == pytest.approx(exact.gaps(q)[0], abs=1e-9), x


@needs_coal
def test_the_gradient_rows_are_the_derivatives_of_the_gaps():
    """G = [−n, −r_a × R_aᵀn, n, r_b × R_bᵀn] against central differences of the gaps along
    the group (body-frame increments), two tilted boxes face on face: 1e-7 (h² of the
    differences)."""
    a = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(1.0, 0.8, 0.6))
    b = RigidBody3D.uniform(1.0, [0.1, -0.05, 0.0], Box(0.4, 0.3, 0.2))
    pair, q = _pair(a, b, np.r_[0.0, 0.0, 0.0, 0.02, -0.01, 0.03, 0.0, 0.0, 0.41, 0.01, 0.02, 0.3])
    g, _, Gr, _ = pair.evaluate(q)
    rows = np.flatnonzero(g < pair.far)
    assert len(rows) == 4
    h = 1e-6
    for k in range(12):
        dq = np.zeros(12)
        dq[k] = h

        def moved(s, k=k, dq=dq):
            p = q.copy()
            body = 0 if k < 6 else 6
            if k % 6 < 3:
                return p + s * dq
            p[body + 3 : body + 6] = log(
                exp(q[body + 3 : body + 6]) @ exp(s * dq[body + 3 : body + 6])
            )
            return p

        fd = (pair.gaps(moved(1.0))[rows] - pair.gaps(moved(-1.0))[rows]) / (2 * h)
        assert fd == pytest.approx(Gr[rows, k], abs=1e-7), k


def resting(options=None, t_end=0.2):
    base = RigidBody3D.uniform(5.0, [0.0, 0.0, -0.1], Box(0.6, 0.4, 0.2)).fix()
    top = RigidBody3D.uniform(1.0, [0.05, 0.02, 0.05], Box(0.2, 0.15, 0.1))
    model = Model([top, base], [Contact(top, base)], gravity=(0.0, 0.0, -G))
    return list(simulate(model, 1e-3, t_end, options))


@needs_coal
def test_a_box_resting_on_a_box_stays_at_rest_on_four_corners():
    """Face on face: the manifold's four corners carry the weight (h m g / 4 each), nothing
    moves (1e-12) and no gap opens below −1e-9 m."""
    states = resting()
    assert max(np.abs(s.q).max() for s in states) < 1e-12
    assert max(np.abs(s.v).max() for s in states) < 1e-12
    assert min(s.gaps.min() for s in states[1:]) > -1e-9
    loaded = states[-1].impulse[states[-1].impulse > 0]
    assert loaded == pytest.approx(np.full(4, 1e-3 * G / 4), rel=1e-9)


@needs_coal
def test_the_resting_box_is_independent_of_p_and_k():
    """The multipliers' scalings change the iterations, not the answer: the motion and the
    total impulse (four coplanar corners share it in a statically indeterminate way)."""
    ref = resting(t_end=0.05)
    for p, k in ((10.0, 1.0), (0.1, 1.0), (1.0, 10.0), (1.0, 0.1)):
        opts = IntegratorOptions(penalty_scale=p, multiplier_scale=k)
        other = resting(opts, t_end=0.05)
        assert max(np.abs(a.q - b.q).max() for a, b in zip(ref, other, strict=True)) < 1e-12
        assert (
            max(abs(a.impulse.sum() - b.impulse.sum()) for a, b in zip(ref, other, strict=True))
            < 1e-12
        )


@needs_coal
def test_a_cube_dropped_corner_first_on_a_box_topples_onto_a_face_without_penetrating():
    """A cube tilted 0.15 rad off corner-down falls 2 cm on a fixed box, pivots on its corner,
    then an edge, and lands on a face: the gaps stay above −1e-9 m, and it ends with its
    centre at half its side over the face, a face down, and no vertical motion (1e-9)."""
    base = RigidBody3D.uniform(5.0, [0.0, 0.0, -0.1], Box(0.6, 0.4, 0.2)).fix()
    cube = RigidBody3D.uniform(1.0, [0.01, 0.0, 0.05 * np.sqrt(3) + 0.02], Box(0.1, 0.1, 0.1))
    model = Model([cube, base], [Contact(cube, base)], gravity=(0.0, 0.0, -G))
    q0 = np.zeros(12)
    q0[3:6] = log(exp(np.array([0.15, 0.0, 0.0])) @ CORNER_DOWN)
    states = list(simulate(model, 2e-3, 0.4, q0=q0))
    assert min(s.gaps.min() for s in states[1:]) > -1e-9
    last = states[-1]
    assert cube.center(last.q)[2] == pytest.approx(0.05, abs=1e-9)
    assert np.abs(cube.rotation(last.q)[2]).max() == pytest.approx(1.0, abs=1e-9)
    assert abs(last.v[2]) < 1e-9
    # the face carries the weight (its corners share it in an indeterminate way)
    assert last.impulse.sum() == pytest.approx(2e-3 * G, rel=1e-9)


def _momenta(bodies, s):
    P, L = np.zeros(3), np.zeros(3)
    for i, b in enumerate(bodies):
        q, v = s.q[6 * i : 6 * i + 6], s.v[6 * i : 6 * i + 6]
        R, c = b.rotation(q), b.center(q)
        P += b.mass * v[:3]
        L += b.mass * np.cross(c, v[:3]) + R @ (b.J @ v[3:])
    return P, L


@needs_coal
def test_two_free_boxes_collide_conserving_momentum():
    """Frictionless, no gravity, an off-centre oblique hit of a tilted box on another (twice,
    restitution 0.5): the impulses act at two points one gap apart along n, so the linear
    momentum holds to round-off. The angular momentum holds to round-off in free flight and
    changes around the contact steps (their position corrections), by 1.9e-5 kg·m²/s at
    h = 1e-3 s (1.3e-5 at h = 5e-4 s, of |L| = 0.15)."""
    a = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Box(0.3, 0.2, 0.2))
    b = RigidBody3D.uniform(1.0, [0.05, 0.08, 0.3], Box(0.15, 0.15, 0.15))
    model = Model([a, b], [Contact(a, b, restitution=0.5)], gravity=(0.0, 0.0, 0.0))
    q0 = np.zeros(12)
    q0[9:12] = [0.3, 0.2, 0.1]
    v0 = np.r_[0.0, 0.0, 0.5, 0.0, 0.0, 1.0, 0.1, 0.0, -1.5, 2.0, 0.0, 0.0]
    states = list(simulate(model, 1e-3, 0.2, q0=q0, v0=v0))
    P0, L0 = _momenta([a, b], states[0])
    assert np.linalg.norm(L0) == pytest.approx(0.15, abs=0.01)
    hits = [i for i, s in enumerate(states) if s.impulse.max() > 0.0]
    assert len(hits) >= 2, "the boxes must collide"
    L = np.array([_momenta([a, b], s)[1] for s in states])
    for s in states:
        assert np.abs(_momenta([a, b], s)[0] - P0).max() < 1e-12
    assert np.abs(L - L0).max() < 3e-5
    assert np.abs(L[: hits[0] - 1] - L0).max() < 1e-12  # free flight before the hit
    assert min(s.gaps.min() for s in states[1:]) > -1e-9


def test_a_missing_collision_extra_is_named(monkeypatch):
    a = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(1.0, 1.0, 1.0))
    b = RigidBody3D.uniform(1.0, [0.0, 0.0, 2.0], Box(1.0, 1.0, 1.0))
    monkeypatch.setitem(sys.modules, "coal", None)
    with pytest.raises(InputError, match="collision"):
        Contact(a, b)


@needs_coal
def test_nodes_of_two_rigid_bodies_are_refused():
    a = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(1.0, 1.0, 1.0))
    b = RigidBody3D.uniform(1.0, [0.0, 0.0, 2.0], Box(1.0, 1.0, 1.0))
    with pytest.raises(InputError, match="nodes"):
        Contact(a, b, nodes=[0])


@needs_coal
def test_the_box_stack_rests_and_its_knocked_top_box_falls_off():
    """cases/box_stack.py: unknocked, the three boxes rest (speeds below 1e-9 m/s over 0.1 s,
    gaps above −1e-9 m); knocked at 1 m/s, the top box slides off the middle one and falls
    past its top face (z below 0.1 m by 0.3 s) while no gap closes below −1e-9 m."""
    sim = load_case("box_stack").build(knock=0.0, t_end=0.1)
    states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0))
    assert max(np.abs(s.v).max() for s in states) < 1e-9
    assert min(s.gaps.min() for s in states[1:]) > -1e-9
    sim = load_case("box_stack").build(knock=1.0, t_end=0.3)
    states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0))
    top = sim.model.bodies[2]
    assert top.center(states[-1].q[12:18])[2] < 0.1
    assert min(s.gaps.min() for s in states[1:]) > -1e-9


@needs_coal
@pytest.mark.parametrize("dt", [5e-4, 2.5e-4])
def test_the_knocked_box_stack_runs_at_finer_steps(dt, tmp_path):
    """At h = 5e-4 and 2.5e-4 s the position correction closed the middle box onto the
    bottom one to d = −1.4e-17 m, where EPA's normal is arbitrary (it gave (0.71, 0.71,
    1e-5)): the face manifold fell to one witness, the next iterate lost the four corners and
    the correction flip-flopped until the step failed at t = 0.084 s. The pair now takes the
    face normal whose separating axis holds the distance: the run passes 0.1 s with no gap
    below the constraints' round-off bound and no energy created beyond the ledger's warning."""
    sim = load_case("box_stack").build(t_end=0.11)
    sim = sim.replace(dt=dt)
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    # the constraints' own round-off bound, 4 tol_gap × the model size (1.2e-12 m): the
    # correction stops at tol_gap × the coordinates' scale (3.8e-13 m here) and the jump's
    # positions add their round-off (measured 1.7e-13 m at 5e-4, 3.7e-13 at 2.5e-4, and
    # 4.2e-13 at the case's own 2e-3)
    assert summary["max_penetration"] <= 4.0 * sim.options.tol_gap * sim.model.length
    ledger = summary["energy_ledger"]
    # no step creates energy beyond the ledger's warning (1e-3 of the scale)
    assert ledger["created"] <= 1e-3 * ledger["scale"]
    assert not summary["warnings"]


@needs_coal
@pytest.mark.slow
def test_the_knocked_box_stack_runs_with_smooth_contact_at_a_finer_step(tmp_path):
    """With ``smooth_contact`` on at h = 5e-4 s, the smooth step's friction update failed
    three times between 0.5 and 0.6 s (residual up to 9.9e-13 m above its 3e-14 m) on
    the corners of faces resting on the plane, whose slips over the step carry a part no
    multiplier reaches (up to 2.7e-13 m). Where Newton stalls on these redundant rows the law
    is now solved by the proximal point method (6 solves here), before the update would drop
    the unreachable part (counted too; not needed on this run any more). The run completes
    0.6 s without halving a step, no gap below the constraints' round-off bound, no energy
    created beyond the ledger's warning."""
    sim = load_case("box_stack").build()
    sim = sim.replace(dt=5e-4, options=dataclasses.replace(sim.options, smooth_contact="on"))
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    assert summary["step_halvings"] == 0
    solver = summary["friction_solver"]
    # (a redundant-row path is taken: Newton alone stalls on these steps)
    assert solver["proximal_solves"] + solver["unreachable_slip_solves"] > 0
    # 4 tol_gap × the model size (1.2e-12 m), as above (measured 2.9e-13 m)
    assert summary["max_penetration"] <= 4.0 * sim.options.tol_gap * sim.model.length
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 1e-3 * ledger["scale"]  # (the ledger's warning; 3.7e-7 J)
    assert not summary["warnings"]
