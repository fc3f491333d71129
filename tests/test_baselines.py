"""Baseline schemes: Moreau–Jean (velocity-level impact law) and penalty contact in the smooth
generalized-α step, checked against exact answers of impacts and contact mechanics."""

import math

import numpy as np
import pytest
from conftest import load_case

from fecontact import (
    Beam2D,
    Circle,
    Contact,
    IntegratorOptions,
    Material,
    Model,
    Pin,
    Plane,
    Section,
)
from fecontact.bodies.rigid import PointMass
from fecontact.time import STEPPERS, PhaseTimer, initial_state
from fecontact.time.constraints import StepFailure
from fecontact.time.moreau import moreau_step
from fecontact.time.nsga import nsga_step
from fecontact.time.penalty import (
    automatic_penalty_stiffness,
    damping_ratio,
    effective_masses,
    penalty_step,
)

MATERIAL = Material(E=70e9, nu=0.33, rho=2700.0)
SECTION = Section.rectangle(0.02, 0.002)


def options(**values):
    """IntegratorOptions with the baseline options set (attributes the baselines read)."""
    opts = IntegratorOptions()
    for name, value in values.items():
        setattr(opts, name, value)
    return opts


def run(stepper, model, h, n, opts=None, v0=None):
    """States after each of n steps of size h from rest (or v0) in the reference state."""
    opts = opts or IntegratorOptions()
    st, timer = initial_state(model, v0=v0), PhaseTimer()
    states = []
    for _ in range(n):
        st = stepper(model, st, h, opts, timer)
        states.append(st)
    return states


def point_on_plane(gap0, restitution, gravity=0.0, mass=1.0):
    """A point mass ``gap0`` above the plane y = 0 (the plane below it)."""
    point = PointMass(mass, [0.0, gap0], size=0.1)
    plane = Plane([0.0, 0.0], [0.0, 1.0])
    return Model([point], [Contact(point, plane, restitution=restitution)], (0.0, -gravity))


def series(states, name):
    return np.array([getattr(s, name) for s in states])


def test_registry():
    assert STEPPERS == {"nsga": nsga_step, "moreau": moreau_step, "penalty": penalty_step}


# -- Moreau–Jean ---------------------------------------------------------------------------------


@pytest.mark.parametrize("h", [1e-3, 5e-4, 2.5e-4])
def test_moreau_plastic_impact_penetrates_order_h(h):
    """No gravity, speed v₀ toward the plane, reaching it a quarter step after t = N h. The
    contact closes at step N (predicted gap v₀h/4 − v₀h/2 ≤ 0), e = 0 stops the point within
    the step, q moves by h/2 v_N: the penetration is exactly (½ − ¼) v₀ h, linear in h, and
    stays (no position correction). The impulse is the momentum m v₀."""
    v0, N = 1.0, 20
    model = point_on_plane(v0 * (N + 0.25) * h, restitution=0.0)
    states = run(moreau_step, model, h, 2 * N, v0=np.array([0.0, -v0]))
    gaps, vy = series(states, "gaps")[:, 0], series(states, "v")[:, 1]
    assert gaps.min() == pytest.approx(-0.25 * v0 * h, rel=1e-9)
    assert np.all(gaps[N:] == pytest.approx(-0.25 * v0 * h, rel=1e-9))
    assert np.all(np.abs(vy[N:]) < 1e-14)
    assert series(states, "impulse").sum() == pytest.approx(1.0 * v0, rel=1e-12)


@pytest.mark.parametrize("e", [1.0, 0.5])
def test_moreau_impact_law_gives_rebound_minus_e_times_approach(e):
    """Newton's law on a point: v⁺ = −e v⁻ in one step (energy kept for e = 1)."""
    v0 = 2.0
    model = point_on_plane(0.01, restitution=e)
    states = run(moreau_step, model, 1e-3, 20, v0=np.array([0.0, -v0]))
    assert states[-1].v[1] == pytest.approx(e * v0, rel=1e-12)
    assert series(states, "impulse").sum() == pytest.approx((1 + e) * v0, rel=1e-12)
    assert np.count_nonzero(series(states, "impulse")) == 1


def test_moreau_ball_comes_to_rest_after_the_accumulation_time():
    """A point dropped from 0.1 m with e = 0.5 bounces until t₁(1 + e)/(1 − e) = 3 t₁, then
    rests: zero velocity, constant gap and a contact impulse m g h per step (its weight)."""
    g, e, h0, h = 9.81, 0.5, 0.1, 1e-3
    model = point_on_plane(h0, restitution=e, gravity=g)
    t_zeno = math.sqrt(2 * h0 / g) * (1 + e) / (1 - e)
    states = run(moreau_step, model, h, 600)
    t = series(states, "t")
    rest = t > t_zeno + 0.05
    vy, gaps = series(states, "v")[rest, 1], series(states, "gaps")[rest, 0]
    imp = series(states, "impulse")[rest, 0]
    assert np.abs(vy).max() < 1e-12
    assert np.ptp(gaps) < 1e-12 and -h * math.sqrt(2 * g * h0) < gaps[0] <= 0.0
    assert imp == pytest.approx(np.full(imp.size, 1.0 * g * h), rel=1e-9)


def test_moreau_beam_falling_flat_stops_with_order_h_penetration():
    """A free beam falls flat on a plane (every node a contact) with e = 0: all nodes stop at
    the impact (plastic impact of a body moving rigidly) and the penetration, for an impact a
    quarter step after a step start, is ≈ ¼ v⁻ h: halving h halves it."""
    g = 9.81
    pen = []
    for h in (1e-3, 5e-4):
        t_hit = 0.1 + 0.25 * h  # a quarter step after t = 0.1 s
        beam = Beam2D.straight(
            [0.0, 0.5 * g * t_hit**2], [0.2, 0.5 * g * t_hit**2], 4, MATERIAL, SECTION
        )
        floor = Contact(beam, Plane([0.0, 0.0], [0.0, 1.0]), restitution=0.0)
        model = Model([beam], [floor], gravity=(0.0, -g))
        states = run(moreau_step, model, h, round(0.15 / h))
        vy = np.array([s.v[1::3] for s in states])
        after = series(states, "t") > t_hit + h
        assert np.abs(vy[after]).max() < 1e-9
        pen.append(-series(states, "gaps").min())
        assert pen[-1] == pytest.approx(0.25 * g * t_hit * h, rel=0.02)
    assert pen[0] / pen[1] == pytest.approx(2.0, rel=0.02)


def test_moreau_keeps_a_sliding_point_on_a_circle():
    """A point sliding inside a rigid circle (no gravity; gap nonlinear in q, so the
    curvature of the gap enters the Newton matrix): the wall's mean force over a step is the
    centripetal m V²/R, the point stays on the wall to far better than the chord deviation
    (Vh)²/(8R), and the speed is kept to O(h)."""
    R, V, h, m = 0.5, 2.0, 2e-4, 0.3
    point = PointMass(m, [0.0, -R], size=R)
    model = Model([point], [Contact(point, Circle([0.0, 0.0], R, inside=True))], (0.0, 0.0))
    states = run(moreau_step, model, h, round(0.5 * math.pi * R / V / h), v0=np.array([V, 0.0]))
    force = series(states, "impulse")[:, 0] / h
    assert np.median(force) == pytest.approx(m * V**2 / R, rel=1e-3)
    assert np.abs(series(states, "gaps")).max() < 1e-2 * (V * h) ** 2 / (8 * R)
    assert np.linalg.norm(states[-1].v) == pytest.approx(V, rel=V * h / R)


def pendulum(restitution=0.0, with_pin=False):
    """The founding flexible pendulum (pinned by a support or by a Pin joint)."""
    beam = Beam2D.straight([0, 0], [0.3, 0], 4, MATERIAL, SECTION).add_mass(-1, 0.14)
    joints = [Pin(beam, [0, 0])] if with_pin else []
    if not with_pin:
        beam.pin(0)
    stop = Contact(beam, Plane([0, -0.3], [1, 0]), nodes=[-1], restitution=restitution)
    return beam, Model([beam], [stop], joints=joints)


def tip(beam, states):
    return np.array([beam.positions(s.q)[-1] for s in states])


def test_moreau_free_flight_converges_to_nsga_at_order_one_or_two():
    """Before the first impact (t < 0.318 s) both schemes solve the same smooth problem:
    against NSGA with a fine step, Moreau–Jean's tip error falls by 2 when h halves with
    θ = 1 (implicit Euler, first order) and by 4 or more with θ = ½ (trapezoidal rule, second
    order; measured 10, and below 1e-7 m the beam's unresolved axial and shear vibration,
    which θ = ½ does not damp, sets the error)."""
    case = load_case("flexible_pendulum")
    model = case.build().model
    beam = model.bodies[0]
    T = 0.2
    ref = tip(beam, run(nsga_step, model, 1.25e-4, round(T / 1.25e-4)))[-1]

    def error(theta, h):
        states = run(moreau_step, model, h, round(T / h), options(theta=theta))
        return np.linalg.norm(tip(beam, states)[-1] - ref)

    e1 = [error(1.0, h) for h in (1e-3, 5e-4, 2.5e-4)]
    assert e1[0] / e1[1] == pytest.approx(2.0, rel=0.1)
    assert e1[1] / e1[2] == pytest.approx(2.0, rel=0.1)
    e2 = [error(0.5, h) for h in (1e-3, 5e-4)]
    assert e2[0] / e2[1] > 3.5
    assert e2[0] < 1e-2 * e1[0]


def test_moreau_pendulum_impact_stops_the_tip_with_order_h_penetration():
    """The founding pendulum, e = 0: the tip arrives at the stop at about the rigid 2.47 m/s,
    its normal velocity is zero after the impact and the penetration is below h|ġ⁻|."""
    beam, model = pendulum()
    h = 1e-3
    states = run(moreau_step, model, h, 340)
    imp = series(states, "impulse")[:, 0]
    n = int(np.flatnonzero(imp > 0)[0])
    vx_before, vx_after = states[n - 1].v[-3], states[n].v[-3]
    assert -2.5 < vx_before < -2.4
    assert abs(vx_after) < 1e-10
    pen = -series(states, "gaps").min()
    assert 0.0 < pen < h * abs(vx_before)


@pytest.mark.parametrize("stepper", [moreau_step, penalty_step])
def test_pin_joint_holds_and_matches_the_pinned_support(stepper):
    """A Pin to the ground gives the motion of the Dirichlet pin through the impact; Moreau–Jean
    keeps G_b v = 0, the penalty step g_b(q) = 0 (multiplier in its Newton)."""
    beam_a, model_a = pendulum()
    beam_b, model_b = pendulum(with_pin=True)
    opts = options(theta=0.55)
    a = run(stepper, model_a, 1e-3, 400, opts)
    b = run(stepper, model_b, 1e-3, 400, opts)
    assert max(np.abs(s.q[:2]).max() for s in b) < 1e-12
    assert max(np.abs(s.v[:2]).max() for s in b) < 1e-12
    assert np.abs(tip(beam_a, a) - tip(beam_b, b)).max() < 1e-7
    assert series(a, "impulse").sum() > 0.1  # the stop was hit


def test_a_failing_newton_raises_step_failure():
    """Newton failures surface as StepFailure, which the step-halving machinery catches."""
    _, model = pendulum()
    st = initial_state(model)
    for stepper in (moreau_step, penalty_step):
        with pytest.raises(StepFailure):
            stepper(model, st, 1e-3, options(max_iterations=0), PhaseTimer())


# -- penalty ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("k", [1e4, 1e6])
def test_penalty_resting_penetration_is_weight_over_stiffness(k):
    """A point set down on the plane sinks to the static penetration m g / k_p: stiffer
    penalty, proportionally less penetration (critical damping for e = 0)."""
    m, g = 2.0, 9.81
    model = point_on_plane(0.0, restitution=0.0, gravity=g, mass=m)
    h = 2e-4
    states = run(penalty_step, model, h, round(0.3 / h), options(penalty_stiffness=k))
    assert states[-1].gaps[0] == pytest.approx(-m * g / k, rel=1e-4)
    assert states[-1].impulse[0] == pytest.approx(m * g * h, rel=1e-4)


def test_penalty_stiff_undamped_contact_is_elastic():
    """e = 1 (no dashpot), k_p = 10⁶ N/m on 1 kg: a half oscillation of ω = 10³ rad/s
    resolved by 300 steps: rebound −v⁻, maximum penetration v⁻/ω, contact time π/ω."""
    v0, k, h = 1.0, 1e6, 1e-5
    omega = math.sqrt(k / 1.0)
    model = point_on_plane(1e-4, restitution=1.0)
    states = run(penalty_step, model, h, 500, options(penalty_stiffness=k), np.array([0, -v0]))
    assert states[-1].v[1] == pytest.approx(v0, rel=2e-3)
    assert -series(states, "gaps").min() == pytest.approx(v0 / omega, rel=2e-3)
    in_contact = np.count_nonzero(series(states, "impulse")) * h
    assert in_contact == pytest.approx(math.pi / omega, abs=2 * h)
    assert series(states, "impulse").sum() == pytest.approx(2 * v0, rel=2e-3)


@pytest.mark.parametrize("e", [0.8, 0.5])
def test_penalty_dashpot_reproduces_the_restitution(e):
    """The dashpot ratio ζ(e) of the clipped spring–dashpot gives rebound e v⁻ once the
    contact is resolved in time."""
    v0, k, h = 1.0, 1e6, 1e-5
    model = point_on_plane(1e-4, restitution=e)
    states = run(penalty_step, model, h, 500, options(penalty_stiffness=k), np.array([0, -v0]))
    assert states[-1].v[1] == pytest.approx(e * v0, rel=5e-3)
    assert 0.0 < damping_ratio(e) < 1.0


def test_penalty_automatic_stiffness_spans_five_steps():
    """The automatic k_p = m (2π/(10 h))²: an elastic impact lasts half a period, five steps,
    with penetration v⁻/ω = 10 h v⁻/(2π) — both shrink with h."""
    v0, m = 1.0, 1.0
    for h in (1e-3, 5e-4):
        model = point_on_plane(0.25 * v0 * h, restitution=1.0, mass=m)
        assert automatic_penalty_stiffness(model, h) == pytest.approx(
            m * (2 * math.pi / (10 * h)) ** 2
        )
        states = run(penalty_step, model, h, 30, v0=np.array([0, -v0]))
        assert np.count_nonzero(series(states, "impulse")) in (5, 6)
        pen = -series(states, "gaps").min()
        assert pen == pytest.approx(10 * h * v0 / (2 * math.pi), rel=0.1)


def test_penalty_automatic_stiffness_bounces_a_ball_with_about_the_restitution():
    """A point dropped from 0.2 m, e = 0.8, automatic k_p and dashpot: every impact is
    resolved in a few steps, so the rebound ratio is e within a few per cent, and the
    dashpot keeps the penetration below the undamped v⁻/ω = 10 h v⁻/(2π)."""
    g, h0, e, h = 9.81, 0.2, 0.8, 1e-3
    model = point_on_plane(h0, restitution=e, gravity=g)
    states = run(penalty_step, model, h, 700)
    vy, imp = series(states, "v")[:, 1], series(states, "impulse")[:, 0]
    on = imp > 0
    starts = np.flatnonzero(on[1:] & ~on[:-1]) + 1
    ends = np.flatnonzero(on[:-1] & ~on[1:]) + 1
    ratios = [-vy[b] / vy[a - 1] for a, b in zip(starts, ends, strict=False)]
    assert len(ratios) >= 2
    assert np.allclose(ratios, e, rtol=0.05)
    assert -series(states, "gaps").min() < 10 * h * math.sqrt(2 * g * h0) / (2 * math.pi)


def test_effective_mass_sees_joints_like_supports():
    """The contact's effective mass 1/(G M⁻¹ Gᵀ) with M⁻¹ restricted by a Pin joint equals the
    one with the pin as a support; a point mass carries its own mass."""
    _, supported = pendulum()
    _, jointed = pendulum(with_pin=True)
    m_support = effective_masses(supported, np.zeros(supported.n))
    m_joint = effective_masses(jointed, np.zeros(jointed.n))
    assert m_joint == pytest.approx(m_support, rel=1e-10)
    assert 0.14 < m_support[0] < 0.14 + 2700 * 4e-5 * 0.3
    assert effective_masses(point_on_plane(0.1, 0.0, mass=3.0), np.zeros(2)) == pytest.approx(3.0)
