"""Impacts located inside their step (fecontact/time/localize.py): exact answers at isolated
impacts, today's treatment under accumulation, zero penetration, p and k independence."""

import dataclasses
import math

import numpy as np
import pytest

from fecontact import InputError, run
from fecontact.cli.commands import main
from fecontact.io.output import read_json
from fecontact.testing import G, ball_exact_gap, ball_impact_times, case, pendulum_exact, trace
from fecontact.time import IntegratorOptions, StepStats, simulate
from fecontact.time.hermite import hermite_root
from fecontact.time.localize import localizes

E_BALL = 0.8


def ball_run(t_end, localize=True, h=1e-3, **options):
    sim = case("bouncing_ball").build(height=1.0, restitution=E_BALL)
    stats = StepStats()
    opts = IntegratorOptions(localize=localize, **options)
    states = list(simulate(sim.model, h, t_end, opts, q0=sim.q0, v0=sim.v0, stats=stats))
    t = np.array([st.t for st in states])
    gap = np.array([st.q[1] for st in states]) + 1.0  # the lowest point starts 1 m up
    v = np.array([st.v[1] for st in states])
    min_gap = min(float(st.gaps.min()) for st in states)
    return t, gap, v, min_gap, stats


@pytest.fixture(scope="module")
def ball():
    return ball_run(3.0)


def test_ball_follows_the_exact_parabolas(ball):
    # between impacts the generalized-α step is exact for a constant force, and each impact
    # is applied at its instant to the gap tolerance (1e-12 m): only round-off remains
    t, gap, _, min_gap, stats = ball
    assert np.max(np.abs(gap - ball_exact_gap(t, e=E_BALL))) <= 1e-9
    assert min_gap >= -1e-12  # zero penetration
    assert stats.localization.impacts == 6  # t_1 ... t_6 < 3 s
    assert stats.localization.fallbacks == dict.fromkeys(stats.localization.fallbacks, 0)


def test_ball_impact_times_and_apex_heights(ball):
    # after impact k the flight is v_k - g s from t_k: each row after the impact gives back
    # t_k = t + (v - v_k)/g with v_k = e^k g t_1, and the apex g + v²/2g = e^{2k} h_0
    t, gap, v, _, _ = ball
    t_k = ball_impact_times(7, e=E_BALL)
    v1 = G * t_k[0]
    for k in range(1, 6):
        rows = (t > t_k[k - 1] + 1e-3) & (t < t_k[k] - 1e-3)
        v_k = E_BALL**k * v1
        np.testing.assert_allclose(t[rows] + (v[rows] - v_k) / G, t_k[k - 1], atol=1e-10)
        apex = gap[rows] + v[rows] ** 2 / (2 * G)
        np.testing.assert_allclose(apex, E_BALL ** (2 * k), atol=1e-10)


def test_pendulum_within_its_smooth_step_error():
    # the uniform bar of 1.5 m swings as a point mass on a 1 m rod; the generalized-α step
    # itself is second order: 8.4e-6 rad before the first impact at h = 1e-3, the bound
    sim = case("rigid_pendulum").build(length=1.5, mass=1.0, restitution=0.5)
    r = trace(sim, dt=1e-3, t_end=3.0)
    exact, t_imp = pendulum_exact(r["t"], e=0.5, length=1.5)
    assert np.sum(t_imp < 3.0) == 3
    assert np.max(np.abs(r["theta"] - exact)) <= 1e-5
    assert r["min_gap"].min() >= -1e-12


def test_the_error_is_second_order_through_impacts():
    # halving h divides the max angle error by 4 (2.0 measured), where the end-of-step
    # impact divides it by 2
    sim = case("rigid_pendulum").build(length=1.5, restitution=0.5)
    err = []
    for h in (2e-3, 1e-3):
        r = trace(sim, dt=h, t_end=1.5)
        err.append(np.max(np.abs(r["theta"] - pendulum_exact(r["t"], 0.5, 1.5)[0])))
    assert math.log2(err[0] / err[1]) > 1.8


def test_ball_comes_to_rest_through_the_accumulation():
    # e = 0.8: infinitely many impacts before t_1 (1 + e)/(1 − e) = 4.07 s; each step takes
    # at most MAX_IMPACTS of them, the rest at its end, and the ball ends resting
    t, gap, v, min_gap, stats = ball_run(6.0)
    assert t.size == 6001
    loc = stats.localization
    assert loc.impacts + loc.smooth_steps <= 6000  # the extra steps: within twice the count
    assert loc.impacts > 20 and sum(loc.fallbacks.values()) >= 1
    assert min_gap >= -1e-12 and gap[-1] >= -1e-12 and abs(v[-1]) <= 1e-9


def test_steps_without_an_impact_are_unchanged():
    # before the first impact (t_1 = 0.4515 s) the localizing step is the NSGA step itself
    on, off = ball_run(0.45, True), ball_run(0.45, False)
    np.testing.assert_array_equal(on[1], off[1])
    np.testing.assert_array_equal(on[2], off[2])


@pytest.mark.parametrize("p, k", [(1e-4, 1.0), (1e4, 1.0), (1.0, 1e-4), (1.0, 1e4)])
def test_results_do_not_depend_on_p_and_k(ball, p, k):
    t, gap, v, _, _ = ball_run(3.0, penalty_scale=p, multiplier_scale=k)
    # the gap tolerance (1e-12 m) bounds where each instant lands; its effect on the
    # velocity after five bounces stays below 1e-9 m/s
    np.testing.assert_allclose(gap, ball[1], rtol=0, atol=1e-10)
    np.testing.assert_allclose(v, ball[2], rtol=0, atol=1e-9)


def test_poisson_law_localizes_too():
    # frictionless single contact: Poisson's law gives Newton's rebound, at the same instant
    t, gap, _, min_gap, stats = ball_run(1.5, impact_law="poisson")
    assert stats.localization.impacts == 2
    assert np.max(np.abs(gap - ball_exact_gap(t, e=E_BALL))) <= 1e-9 and min_gap >= -1e-12


def test_solid_impact_step_adds_no_energy():
    # the disk's first contact step, wherever the closing falls in it: the excess over the
    # initial energy in % of the kinetic energy at impact (0.44 % and 1.39 % at the end of
    # the step, measured at fractions 0 and 0.75 of a step)
    for frac in (0.0, 0.75):
        sim = case("disk_drop").build(refinements=2, drop_height=0.002 + frac * 1.0774e-4)
        sim = sim.replace(options=dataclasses.replace(sim.options, localize=True))
        r = trace(sim, t_end=0.004)
        first = np.flatnonzero(r["active"])[0]
        excess = 100 * (r["total"].max() - r["total"][0]) / r["kinetic"][first - 1]
        assert r["status"] == "completed" and excess <= 0.1, frac
        assert r["min_gap"].min() >= -1e-12


def tip_run(h, t_end=0.36):
    # the decoupled contact phase, whose impulses carry all the stop's momentum (with the
    # smooth force, the default of beams, the tip follows the h/8 run to 0.179 mm as well,
    # part of the momentum in the smooth force)
    sim = case("flexible_pendulum").build()
    options = dataclasses.replace(sim.options, localize=True, smooth_contact="off")
    sim = sim.replace(options=options)
    return trace(sim, dt=h, t_end=t_end)


def test_founding_chattering_contact_follows_the_fine_step():
    # the tip strikes the stop at 0.3186 s, lifts off and strikes again three times within
    # 8 ms; steps of 1 ms held it pressed through 0.327 s (0.89 mm from the h/8 run by
    # 0.36 s, impulse 0.3882 N s against 0.3923); in sub-steps while it chatters the h run
    # follows the h/8 run: 0.18 mm, 0.3923 N s against 0.3929 measured (the rest is the
    # sub-steps' own first-order error)
    r, f = tip_run(1e-3), tip_run(1e-3 / 8)
    rows = slice(0, None, 8)  # the h/8 rows at the h rows' times
    d = np.hypot(r["tip_x"] - f["tip_x"][rows], r["tip_y"] - f["tip_y"][rows])
    np.testing.assert_allclose(r["t"], f["t"][rows], atol=1e-12)
    assert d.max() <= 0.3e-3  # m
    assert r["min_gap"].min() >= -1e-12 and f["min_gap"].min() >= -1e-12
    assert abs(r["impulse"].sum() - f["impulse"].sum()) <= 2e-3 * f["impulse"].sum()


def test_sticking_corners_do_not_slide_after_a_located_rebound():
    # μ = 1: the rocking block pivots on its corners. A corner that rebounds (e = 0.5) and
    # strikes again within a step opened 1.5e-9 m at the split; its correction then lacked
    # its slip rows and turned the box, and the other corner, held at its cone's edge, slid
    # 4.0e-8 m in a step where both were reported sticking. Both keep their rows: 4e-13 m,
    # 3e-13 m without localization (round-off of the 0.1 m corner positions)
    sim = case("rocking_block").build(friction=1.0)
    sim = sim.replace(options=dataclasses.replace(sim.options, localize=True))
    stats = StepStats()
    q, status = [], []
    for st in simulate(sim.model, sim.dt, sim.t_end, sim.options, sim.q0, sim.v0, stats=stats):
        if st.friction is not None:
            q.append(st.q.copy())
            status.append(st.friction.status[:2].copy())
    q, status = np.array(q), np.array(status)
    x, th = q[:, 0], q[:, 2]
    corners = np.column_stack([x + s * np.cos(th) + 0.2 * np.sin(th) for s in (-0.1, 0.1)])
    both = np.all(status[1:] == 1, axis=1) & np.all(status[:-1] == 1, axis=1)
    assert stats.localization.impacts > 10 and both.sum() > 300
    assert np.abs(np.diff(corners, axis=0))[both].max() <= 1e-11


def hertz_span(h_over_tc=None, localize=True):
    """(t_c of Hertz's formula, the located contact span, the run's localization counts) of a
    P1 ball (refinements 1) at
    1 m/s without gravity, closing 0.37 of a step into its third step; h = t_c × the
    fraction, or 2^-15 s (0.15 of the dilatational transit time of its shortest edge)."""
    E, nu, R = 1e7, 0.3, 0.05
    build = case("ball_drop").build
    mass = build(refinements=1, E=E, nu=nu, rho=1000.0).model.bodies[0].mass
    t_c = 2.87 * (mass**2 / (R * (E / (1 - nu**2)) ** 2 * 1.0)) ** 0.2
    h = 2.0**-15 if h_over_tc is None else t_c * h_over_tc
    sim = build(
        refinements=1, E=E, nu=nu, rho=1000.0, velocity=1.0, gravity=0.0,
        drop_height=2.37 * h, t_end=1.5 * t_c,
    )  # fmt: skip
    opts = dataclasses.replace(sim.options, localize=localize, detection_margin=0.01)
    stats = StepStats()
    for _ in simulate(sim.model, h, 1.5 * t_c, opts, q0=sim.q0, v0=sim.v0, stats=stats):
        pass
    span = stats.localization
    return t_c, span.last_release - span.first_closing, span


def test_hertz_contact_duration_from_the_located_closing_and_release():
    # at t_c/20 a release read at the step's end is a step (5 %) off; read at the sub-steps'
    # (t_c/160) it is within 0.5 % of the finest step's (-0.47 % measured; +2.35 % from
    # whole steps)
    _, fine, _ = hertz_span()
    _, coarse, _ = hertz_span(1 / 20)
    assert abs(coarse / fine - 1) <= 0.02


def test_hertz_contact_duration_at_the_defaults():
    # "auto" takes the contact in whole steps and reads its release from eighths of the
    # releasing steps taken aside: +1.41 % from the finest step's at t_c/20 measured
    # (+2.35 % read at the end of the last step with a force, which is up to a step, 5 %,
    # off). The rest is the whole steps' contact phase (the same with 16 sub-steps); the
    # margin, 0.59 points, is about one sub-step of the reading (t_c/160 = 0.63 %)
    _, fine, _ = hertz_span()
    _, coarse, counts = hertz_span(1 / 20, localize="auto")
    assert abs(coarse / fine - 1) <= 0.02
    # the sub-steps read the release; the run takes whole steps, the one in which they read
    # it split there (tests/test_release_split.py)
    assert counts.release_probes == 1 and counts.subdivided == 0
    assert counts.release_splits == 1


def test_hermite_root_of_a_parabola():
    # g(s) = 1 − 2s²: the Hermite cubic of a quadratic is the quadratic, root 1/√2
    s, slope = hermite_root(np.array([1.0]), np.array([0.0]), np.array([-1.0]), np.array([-4.0]))
    assert s[0] == pytest.approx(1 / math.sqrt(2), abs=1e-15)
    assert slope[0] == pytest.approx(-4 / math.sqrt(2), abs=1e-12)


def test_hermite_root_of_one_contact_is_that_of_the_arrays():
    # one contact takes a path of floats, several the arrays': the same operations in the
    # same order, so the same root and slope to the bit (equality, no tolerance)
    rng = np.random.default_rng(7)
    for _ in range(2000):
        g0, g1 = rng.uniform(1e-9, 1e-3, 2) * 10.0 ** rng.uniform(-3, 3, 2) * [1, -1]
        s0, s1 = rng.normal(size=2) * 10.0 ** rng.uniform(-6, 0, 2)
        one = hermite_root(*(np.array([x]) for x in (g0, s0, g1, s1)))
        twice = hermite_root(*(np.array([x, x]) for x in (g0, s0, g1, s1)))
        assert one[0][0] == twice[0][0] and one[1][0] == twice[1][0]


def test_option_values_and_errors():
    assert IntegratorOptions(localize=0).localize is False
    assert IntegratorOptions(localize="on").localize is True
    with pytest.raises(InputError, match="localize must be"):
        IntegratorOptions(localize="sometimes")
    with pytest.raises(InputError, match="localize = true needs integrator 'nsga'"):
        IntegratorOptions(localize=True, integrator="moreau")
    from fecontact.time import run_settings

    def resolved(name, **options):
        model = case(name).build().model
        return localizes(model, run_settings(model, IntegratorOptions(**options)))

    # "auto": rigid bodies, frictional or not, or solids on fixed obstacles
    # (tests/test_localize_solids.py); not beams or the baselines
    assert resolved("bouncing_ball") and resolved("rigid_pendulum")
    assert not resolved("flexible_pendulum") and resolved("disk_drop")
    assert resolved("sliding_block") and not resolved("bouncing_ball", integrator="moreau")
    assert resolved("flexible_pendulum", localize=True)


def test_counts_in_the_summary_and_the_command_line_switch(tmp_path):
    sim = case("bouncing_ball").build(restitution=0.5)
    summary = run(sim.replace(t_end=1.0), tmp_path / "on", frames=False)
    assert summary["localized_impacts"] == 2
    assert set(summary["localization_fallbacks"]) == {
        "accumulation",
        "persistent",
        "grazing",
        "unrefined",
        "failed",
    }
    args = ["run", "--quiet", "--out", str(tmp_path / "off"), "--t-end", "1", "--checkpoint-every"]
    path = str(case("bouncing_ball").__file__)
    assert main([*args, "0", path, "--set", "localize=0"]) == 0
    assert read_json(tmp_path / "off" / "summary.json")["localized_impacts"] == 0
