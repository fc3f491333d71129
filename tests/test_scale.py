"""Gap tolerances follow the magnitude of the coordinates, and impacts too violent for the
mesh stop with a message that says so."""

import math

import numpy as np
import pytest
from conftest import load_case

from fecontact import Contact, Model, Plane, SolverError, simulate
from fecontact.bodies.rigid import Disk, RigidBody2D
from fecontact.time import length_scale

G = 9.81


def test_ball_dropped_from_five_kilometres_bounces():
    """The ball reaches the ground with q ≈ −5000 m, so its gap y₀ + q − r carries a round-off
    of ε·5000 m ≈ 1e-12 m: a tolerance of 1e-12 of the ball's size (2e-13 m) could not be met
    and the correction never settled. Relative to the coordinates' magnitude it is met, and
    the rebound is e times the impact speed √(2 g h₀) = 313 m/s."""
    h0, e, dt = 5000.0, 0.8, 1e-2
    sim = load_case("bouncing_ball").build(height=h0, restitution=e)
    t1 = math.sqrt(2 * h0 / G)
    states = list(simulate(sim.model, dt, t1 + 0.5))
    assert length_scale(sim.model, states[-1].q) > 5000.0
    assert min(st.gaps.min() for st in states) >= -1e-12 * 5000.0
    up = max(st.v[1] for st in states)
    # the rebound leaves from the start of its step: first order in dt
    assert up == pytest.approx(e * math.sqrt(2 * G * h0), abs=(1 + e) * G * dt)


def test_ball_resting_on_a_plane_five_kilometres_up():
    """Large reference coordinates (a plane at y = 5000 m) rather than large displacements."""
    y = 5000.0
    ball = RigidBody2D.uniform(1.0, [0.0, y + 0.1], Disk(0.1))
    model = Model([ball], [Contact(ball, Plane([0.0, y], [0.0, 1.0]))])
    states = list(simulate(model, 1e-3, 1.0))[1:]
    assert min(st.gaps.min() for st in states) >= -1e-12 * y
    assert max(abs(st.v).max() for st in states) < 1e-10
    assert max(st.newton_iterations for st in states) <= 3


def test_impact_that_inverts_elements_stops_with_a_clear_message():
    """A Neo-Hookean disk hitting the plane at 443 m/s, four times its dilatational wave
    speed: the position correction would fold elements over (det F ≤ 0, infinite energy).
    That state is never accepted; the run stops and says why."""
    sim = load_case("disk_drop").build(velocity=443.0)
    disk = sim.model.bodies[0]
    with pytest.raises(SolverError, match="(inverts an element|an element inverts)"):
        for st in simulate(sim.model, sim.dt, sim.t_end, sim.options, v0=sim.v0):
            assert np.isfinite(disk.energy(st.q))
