"""Coulomb friction in the Moreau–Jean baseline: the same cone on the slip rates at velocity
level, checked against the block on an incline (exact for a constant force: the θ-method
integrates a constant acceleration exactly) and the energy balance."""

import dataclasses
import math

import numpy as np
import pytest

from fecontact.testing import G, case
from fecontact.time import simulate


def slide(incline, friction, velocity=0.0, t_end=1.0):
    sim = case("sliding_block").build(incline=incline, friction=friction, velocity=velocity)
    options = dataclasses.replace(sim.options, integrator="moreau")
    model, rows = sim.model, []
    for st in simulate(model, sim.dt, t_end, options, q0=sim.q0, v0=sim.v0):
        energy = model.kinetic_energy(st.v) + model.potential_energy(st.q)
        work = float(st.friction.work) if st.step else 0.0
        rows.append(
            (st.t, sim.probes["s"].fn(model, st), sim.probes["v"].fn(model, st), energy, work)
        )
    return np.array(rows).T, sim.dt


def test_a_sliding_block_has_the_coulomb_acceleration():
    (t, s, v, _, _), _ = slide(30.0, 0.3)
    a = G * (math.sin(math.radians(30.0)) - 0.3 * math.cos(math.radians(30.0)))
    # to round-off of the sums over 1000 steps
    np.testing.assert_allclose(v, a * t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(s, 0.5 * a * t**2, rtol=0, atol=1e-9)


def test_a_block_below_the_friction_angle_does_not_creep():
    (_, s, v, _, _), _ = slide(20.0, 0.5)
    assert np.max(np.abs(s)) <= 1e-10 and np.max(np.abs(v)) <= 1e-10


def test_a_thrown_block_stops_where_coulomb_says_and_stays():
    (t, s, v, _, _), h = slide(20.0, 0.5, velocity=1.0)
    d = G * (0.5 * math.cos(math.radians(20.0)) - math.sin(math.radians(20.0)))
    assert s[-1] == pytest.approx(1.0 / (2.0 * d), abs=1.0 * h)  # within v₀h
    stopped = t > 1.0 / d + 2 * h
    assert np.ptp(s[stopped]) <= 1e-12 and np.max(np.abs(v[stopped])) <= 1e-12


@pytest.mark.parametrize("incline, friction, velocity", [(30.0, 0.3, 0.0), (20.0, 0.5, 1.0)])
def test_the_energy_balance_closes_with_the_work_of_friction(incline, friction, velocity):
    (_, _, _, energy, work), _ = slide(incline, friction, velocity)
    # E(t) − E(0) = −W_friction: the work is P_T·G_T v_θ, the slip the update q_n + h v_θ makes
    assert np.max(np.abs(energy - energy[0] + work)) <= 1e-10 * max(work[-1], 1.0)
