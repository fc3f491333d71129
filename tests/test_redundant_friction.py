"""Frictional contact on more rows than degrees of freedom: a cylinder on the rim points of its
base (8 to 64 coplanar contacts: 24 to 192 rows on 6 dofs).
The Delassus matrix is singular and the semi-smooth Newton's step there the minimum-norm one
(:func:`fecontact.contact.friction.solve_coulomb`); the answers are exact all the same."""

import numpy as np
import pytest

from fecontact import Box, Contact, Cylinder, Model, Plane, RigidBody3D
from fecontact.time.simulate import simulate
from fecontact.time.stats import StepStats

R, H, MU, G = 0.1, 0.2, 0.5, 9.81


def standing(n_rim, height=0.0, v0=None, t_end=0.3):
    cylinder = RigidBody3D.uniform(1.0, [0.0, 0.0, H / 2 + height], Cylinder(R, H, n_rim))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    model = Model([cylinder], [Contact(cylinder, floor, friction=MU)], gravity=(0.0, 0.0, -G))
    stats = StepStats()
    states = list(simulate(model, 1e-3, t_end, v0=v0, stats=stats))
    bottom = [cylinder.point_positions(s.q, np.arange(n_rim))[:, 2] for s in states]
    return states, np.array(bottom), stats.contact.coulomb


@pytest.mark.parametrize("n_rim", [8, 24, 64])
def test_a_cylinder_dropped_on_its_rim_comes_to_rest_standing(n_rim):
    """Dropped 1 cm flat onto its base: the impact stops it (e = 0) and it stands still.
    Its velocities end at the velocity level's tolerance, not zero (measured 1.2e-11 rad/s;
    the jump's tolerance is 1e-12 of the size over the step, 2e-10 m/s); the solver
    neither cut its steps nor fell back to Gauss–Seidel (with the LU step on the singular
    systems, 8 points took 29 fallbacks and 14 692 cuts in 0.1 s, and stopped at 5.9e-11
    m/s after 0.3 s)."""
    states, bottom, coulomb = standing(n_rim, height=0.01)
    assert np.abs(states[-1].v).max() < 1e-9
    assert bottom.min() >= -1e-9
    assert np.abs(states[-1].q[3:]).max() < 1e-9  # still upright, not turned
    assert coulomb.gauss_seidel_solves == 0 and coulomb.line_search_cuts == 0
    assert coulomb.minimum_norm_steps > 0  # the singular systems were there


@pytest.mark.parametrize("n_rim", [8, 24])
def test_a_cylinder_sliding_on_its_base_stops_at_the_exact_time(n_rim):
    """Pushed along x at 1 m/s, it slides on all its base points at once: the friction
    μmg decelerates it by μg exactly (constant force: the scheme is exact) until it
    sticks at t* = v₀/(μg) = 0.204 s and stays. It does not tip (μH/2 < R)."""
    v0 = 1.0
    states, bottom, _ = standing(n_rim, v0=np.r_[v0, 0.0, 0.0, 0.0, 0.0, 0.0])
    t = np.array([s.t for s in states])
    v = np.array([s.v[0] for s in states])
    exact = np.maximum(v0 - MU * G * t, 0.0)
    # 1e-10 m/s: the stick holds the slip to the position tolerance over a step
    assert np.abs(v - exact).max() < 1e-10
    assert np.abs(bottom).max() < 1e-12


@pytest.mark.parametrize("n_rim", [8, 24])
def test_a_cylinder_spinning_on_its_base_stops_at_the_exact_time(n_rim):
    """Spun about its axis at 5 rad/s, every base point slips along the rim: the torque
    μmgR against the inertia mR²/2 stops the spin at 2μg/R, at t* = Ω₀R/(2μg) = 0.051 s, and
    the centre never moves. The rotation goes through the group's update, the slip of each
    point through its positions at both ends of the step: measured 1.2e-9 rad/s off the
    exact line (the slip is the chord of the step's arc, not its tangent), 1e-8 asserted."""
    w0 = 5.0
    states, bottom, _ = standing(n_rim, v0=np.r_[0.0, 0.0, 0.0, 0.0, 0.0, w0], t_end=0.1)
    t = np.array([s.t for s in states])
    w = np.array([s.v[5] for s in states])
    assert np.abs(w - np.maximum(w0 - 2 * MU * G / R * t, 0.0)).max() < 1e-8
    assert max(np.abs(s.v[:5]).max() for s in states) < 1e-12
    assert np.abs(bottom).max() < 1e-12


def test_a_box_held_on_an_incline_near_its_friction_angle_settles_its_least_norm():
    """A box resting on a 20° incline with μ = 1.1 tan 20°: four sticking corners on six
    dofs, and the least-norm member of the family puts the two upper corners (less loaded)
    at the edge of their cones with no slip. Read on their stick branch there, the family's
    directions let their tangential multipliers grow past the cone, and the moves went
    round members of the family until the limit of 8 cycles: 24 of the 60 solves of 20
    steps ended unsettled (833 of 1500 over 0.5 s). Read on their slip branch, the
    least-norm member settles."""
    theta = np.radians(20.0)
    n = np.array([-np.sin(theta), 0.0, np.cos(theta)])
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(0.2, 0.15, 0.1))
    contact = Contact(box, Plane([0.0, 0.0, 0.0], n), friction=1.1 * np.tan(theta))
    model = Model([box], [contact], gravity=(0.0, 0.0, -G))
    q0 = np.r_[0.05 * n, 0.0, -theta, 0.0]  # the face flat on the incline
    stats = StepStats()
    states = list(simulate(model, 1e-3, 0.02, q0=q0, stats=stats))
    coulomb = stats.contact.coulomb
    assert coulomb.least_norm_unsettled == 0
    assert coulomb.least_norm_moves > 0  # (the family is met)
    # held: the velocities stay below the jump's tolerance (1e-12 of the size over the
    # step, 2.7e-10 m/s; measured 2.3e-16), the rotation with them
    assert np.abs(states[-1].v).max() < 1e-9
    assert np.abs(states[-1].q - q0).max() < 1e-12
