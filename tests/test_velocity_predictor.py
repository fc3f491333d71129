"""A step refused for turning a beam node by more than a quarter turn is taken at ρ∞ = 0 in
runs whose steps the energy guard checks, its predictor started at constant velocity where
it still turns a node too far (fecontact.time.turns): the founding pendulum at ρ∞ = 1,
e_N = 0 and h = 1e-2, which failed at 0.39 s, and the same step from either first
iterate."""

import dataclasses

import numpy as np
import pytest

from fecontact.errors import SolverError
from fecontact.testing import case
from fecontact.time import make_stepper, simulate
from fecontact.time.generalized_alpha import coefficients
from fecontact.time.state import PhaseTimer
from fecontact.time.stats import StepStats
from fecontact.time.turns import TURN_BOUND


def ringing(**options):
    """The founding pendulum at ρ∞ = 1 and e_N = 0: its strip rings undamped after the strike
    (0.32 s), its rotation modes (0.46-0.79 MHz) with it."""
    sim = case("flexible_pendulum").build(restitution=0.0)
    return sim.model, dataclasses.replace(sim.options, rho_inf=1.0, **options)


def energies(model, st):
    return model.kinetic_energy(st.v) + model.strain_energy(st.q) + model.potential_energy(st.q)


def test_the_ringing_strip_at_ten_times_the_step_completes():
    """Before: at 0.34-0.39 s every predictor turned a node beyond the bound, ½h²v̇ of an
    acceleration of 1e4-1e8 rad/s² that is consistent with the strain (the rotation modes,
    micro-radians of turn), and six halvings did not bring it under: failed at 0.39 s with
    83 halvings. Now 2 steps (to 0.5 s) are taken at ρ∞ = 0 from 4 predictors at constant
    velocity and the run goes on; the tip stays within 1.7 mm of the run at h = 1e-3
    (measured)."""
    model, options = ringing()
    stats, E, tip = StepStats(), [], []
    for st in simulate(model, 1e-2, 0.5, options, stats=stats):
        E.append(energies(model, st))
        tip.append(st.q[model.n - 3 : model.n - 1].copy())
    assert st.t == pytest.approx(0.5)
    turns = stats.turns
    assert turns.damped_steps >= 1 and turns.velocity_predictors >= 1
    assert turns.refused == turns.damped_steps  # (none of the steps at ρ∞ = 0 refused)
    # e_N = 0: the strike takes 0.44 J out and nothing may put it back; the guard retakes a
    # step that gains 1e-3 of the scale (its level, GAIN), here 1e-3 J: no step reaches it
    assert max(E[1:]) - E[0] <= 1e-3 * max(E[0] - min(E), 1.0)
    fine = [st.q[model.n - 3 : model.n - 1].copy() for st in simulate(model, 1e-3, 0.5, options)]
    # 1.7 mm measured; 3 mm: about that of the default ρ∞ = 0.5 at h = 1e-2 (3.1 mm)
    assert np.abs(np.array(tip) - np.array(fine[::10])).max() <= 3e-3


def test_without_the_guard_the_step_is_halved_as_before():
    """Without the energy guard the halvings bound the ringing (module fecontact.time.turns):
    the same row fails at 0.39 s, no step taken at ρ∞ = 0."""
    model, options = ringing(energy_retakes=0)
    stats, reached = StepStats(), []
    with pytest.raises(SolverError, match="the predictor turns a beam node by"):
        for st in simulate(model, 1e-2, 0.5, options, stats=stats):
            reached.append(st.t)
    assert reached[-1] == pytest.approx(0.39)
    assert stats.turns.velocity_predictors == stats.turns.damped_steps == 0


def test_the_velocity_predictor_leads_newton_to_the_same_step():
    """The constant-velocity start moves (v, v̇, a) with q at the rates of a Newton update,
    so the step's equations are unchanged: from a free-flight state both first iterates end
    on the same step, to the Newton tolerance."""
    model, options = ringing()
    states = list(simulate(model, 1e-2, 0.2, options))
    st, h = states[-1], 1e-2
    opts = make_stepper(model, options).settings
    c = coefficients(opts.rho_inf, h)

    def step(coast: bool) -> np.ndarray:
        newton = opts.plan.loop(model, opts, PhaseTimer()).start(st, st.t + h, c, None)
        start = newton.step.X[0].copy()
        if coast:
            newton.form.coast()
            assert np.allclose(newton.step.X[0], st.q + h * st.v, rtol=0.0, atol=1e-15)
        assert np.abs(newton.step.X[0] - start).max() < TURN_BOUND  # (a free-flight step)
        newton.run()
        return newton.step.X.copy()

    plain, coasted = step(False), step(True)
    assert not np.array_equal(plain, coasted)  # (two Newton paths)
    # measured 6e-16, 2e-14 and 6e-14 of each row's size: both iterations end on the same
    # root to round-off; 1e-10 leaves room for where Newton's residual test stops them
    for row, ref in zip(plain - coasted, plain, strict=True):
        assert np.abs(row).max() <= 1e-10 * np.abs(ref).max()
