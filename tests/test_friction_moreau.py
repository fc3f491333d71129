"""Coulomb friction in the Moreau–Jean baseline: the same cone on the slip rates at velocity
level, checked against the block on an incline (exact for a constant force: the θ-method
integrates a constant acceleration exactly) and the energy balance."""

import dataclasses
import math

import numpy as np
import pytest

from fecontact.io.output import read_history
from fecontact.simulation import run
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


def _moreau_run(name, tmp_path, **params):
    """The summary and history of case ``name`` under Moreau–Jean (options in ``params``
    with the key ``impact_law``; the rest are the case's parameters)."""
    law = params.pop("impact_law", "newton")
    sim = case(name).build(**params)
    options = dataclasses.replace(sim.options, integrator="moreau", impact_law=law)
    summary = run(sim.replace(options=options), tmp_path, frames=False)
    return summary, read_history(tmp_path / "history.csv")


@pytest.mark.parametrize("spin", [0.0, 30.0])
def test_a_rolling_disk_dissipates_the_closed_form_energy(spin, tmp_path):
    """A disk thrown at v₀ with spin ω₀ on a rough floor slips until it rolls at
    v = (2v₀ − ω₀R)/3 (I = mR²/2): friction takes ½mv₀² + ½Iω₀² − ¾mv², all of it in the
    slip, the step where the slip stops included (one contact whose slip does not couple to
    its normal motion: the reading of that step is Routh's, impulse × mean slip)."""
    m, R, v0 = 1.0, 0.1, 2.0
    summary, history = _moreau_run("rolling_disk", tmp_path, velocity=v0, spin=spin)
    v = (2.0 * v0 - spin * R) / 3.0
    exact = 0.5 * m * v0**2 + 0.25 * m * R**2 * spin**2 - 0.75 * m * v**2
    ledger = summary["energy_ledger"]
    # the θ-method is exact for these constant forces: round-off of ~10³ steps
    assert ledger["friction_dissipation"] == pytest.approx(exact, rel=1e-9)
    assert abs(ledger["impact_dissipation"]) <= 1e-9 * exact
    assert abs(ledger["numerical_dissipation"]) <= 1e-9 * exact
    assert np.all(np.diff(history["friction_dissipation"]) >= 0.0)


@pytest.mark.parametrize("law", ["newton", "poisson"])
def test_kane_chain_friction_takes_energy_at_every_step(law, tmp_path):
    """Kane's chain (e_N = 1, μ = 0.5): the striking end's slip stops on the cone's edge
    early in the impact and the end sticks; friction takes Routh's 0.028 J there (the
    sticking reaction, along the slip before the step, is not positive work). Poisson's
    law creates nothing; Newton's kinematic restitution creates 1.13 J in the impact, where
    the warning names friction's positive work at the step's mean slip (the only energy
    warning: the process reading of friction stays ≥ 0)."""
    summary, history = _moreau_run("kane_chain", tmp_path, impact_law=law)
    friction = history["friction_dissipation"]
    assert np.all(np.diff(friction) >= 0.0)
    assert 0.027 < friction[-1] < 0.029
    energy = [w for w in summary["warnings"] if w.startswith("energy")]
    assert not [w for w in energy if w.startswith("energy: friction")]
    if law == "poisson":
        assert not energy
        # measured 1.0e-6 of the scale, in the smooth steps around the strike
        assert summary["energy_ledger"]["created"] <= 1e-5 * summary["energy_ledger"]["scale"]
    else:
        (created,) = energy
        assert "in the impact" in created and "t = 0.408 s" in created
        assert "friction did positive work" in created


def test_kane_chain_friction_agrees_with_nsga_at_every_strike(tmp_path):
    """Kane's chain with e_N = 0.5 under Poisson's law strikes three times; at the second
    the striking end slips back along the floor, sticks, and the decompression keeps it
    stuck. Moreau–Jean reads its one step's impulse against the slip at the step's ends,
    NSGA each phase of its jump: both read Routh's slip-then-stick, and their friction
    agrees to the difference of the two integrators' strikes (counting the sticking
    reaction as work would take 0.97 J instead of 0.095 J at the second)."""
    out = {}
    for integrator in ("moreau", "nsga"):
        sim = case("kane_chain").build(restitution=0.5)
        options = dataclasses.replace(sim.options, integrator=integrator, impact_law="poisson")
        run(sim.replace(options=options), tmp_path / integrator, frames=False)
        out[integrator] = read_history(tmp_path / integrator / "history.csv")
    strikes = {}
    for integrator, h in out.items():
        d = np.diff(h["friction_dissipation"])
        assert np.all(d >= 0.0)
        strikes[integrator] = np.sort(d)[-3:]
    # Moreau–Jean strikes from its own predicted, slightly penetrated state, a step
    # (h = 2.5e-4 s) from NSGA's: friction ∝ the slip squared differs by 1.0, 0.2 and
    # 0.8 % at the three strikes (measured)
    np.testing.assert_allclose(strikes["moreau"], strikes["nsga"], rtol=0.02)
