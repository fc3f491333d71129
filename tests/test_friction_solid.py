"""Coulomb friction on an elastic solid: a 2D Neo-Hookean disk thrown at an angle onto a
plane (``disk_drop`` with ``slide_velocity`` and ``friction``), checked against the integral
form of Coulomb's law: over the impact the tangential momentum changes by at most μ times the
normal one, and by exactly that while every contact node slips one way."""

import numpy as np
import pytest

from fecontact.testing import G, case, trace


@pytest.fixture(scope="module")
def throws():
    def throw(friction, slide):
        sim = case("disk_drop").build(
            refinements=2, slide_velocity=slide, friction=friction, t_end=0.006
        )
        run = trace(sim)
        assert run["status"] == "completed" and run["halvings"].sum() == 0
        assert run["min_gap"].min() >= -1e-12  # the gap tolerance
        m = sim.model.bodies[0].mass
        # momentum the plane gave: along it, and normal to it (gravity's impulse removed)
        tangential = m * (run["vx_center"][-1] - run["vx_center"][0])
        normal = m * (run["vy_center"][-1] - run["vy_center"][0]) + m * G * run["t"][-1]
        return run, tangential, normal

    return throw


def test_without_friction_the_momentum_along_the_plane_is_kept(throws):
    run, tangential, normal = throws(0.0, 2.0)
    assert normal > 10.0  # kg·m/s per m: the disk hit the plane
    assert abs(tangential) <= 1e-12 * normal  # round-off of the momentum sums
    assert np.max(np.abs(run["omega"])) <= 1e-10


def test_a_disk_slipping_throughout_loses_mu_times_the_normal_momentum(throws):
    # at 2 m/s along the plane and μ = 0.1 no contact node stops slipping during the impact:
    # every tangential impulse is −μ times its normal impulse, so their sums are too
    run, tangential, normal = throws(0.1, 2.0)
    assert tangential == pytest.approx(-0.1 * normal, rel=1e-9)
    assert run["omega"][-1] < 0.0  # friction at the bottom spins the disk clockwise


def test_a_disk_that_grips_transfers_less_than_the_cone_allows(throws):
    run, tangential, normal = throws(1.0, 2.0)
    assert -normal < tangential < -0.1 * normal  # inside the cone: nodes stuck for a while
    # the tangential impulse R|ΔP_t| about the centre spins the disk: ω ~ R|ΔP_t|/(½mR²)
    radius, mass = 0.05, 1000.0 * np.pi * 0.05**2
    rigid = radius * abs(tangential) / (0.5 * mass * radius**2)
    assert -1.5 * rigid < run["omega"][-1] < -0.5 * rigid  # the disk still rings elastically
    assert run["total"][-1] < throws(0.0, 2.0)[0]["total"][-1]  # friction dissipates
