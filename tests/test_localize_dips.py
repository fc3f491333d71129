"""Contacts that close and open again inside one step (fecontact/time/dips.py): located at
their instant although both ends of the step are open."""

import numpy as np

from fecontact import Model
from fecontact.bodies import Disk, Polygon, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.testing import G
from fecontact.time import IntegratorOptions, StepStats, simulate
from fecontact.time.dips import dip_closings, hermite_minimum

CEILING, BEYOND, E = 1.0, 1e-6, 0.5


def test_an_apex_grazing_a_ceiling_inside_a_step_rebounds():
    # a ball thrown up under a ceiling 1 m above it, its apex 1e-6 m beyond: inside the
    # ceiling for 0.9 ms, between two step ends (h = 1 ms) where it is open; unseen, it
    # passed through it and lost its rebound, 3.6e-3 m of height by 1 s
    ball = RigidBody2D.uniform(1.0, [0.0, 0.0], Disk(0.1))
    ceiling = Plane([0.0, CEILING + 0.1], [0.0, -1.0])
    model = Model([ball], [Contact(ball, ceiling, restitution=E)], (0.0, -G))
    v0 = np.sqrt(2.0 * G * (CEILING + BEYOND))
    stats = StepStats()
    steps = simulate(
        model, 1e-3, 1.0, IntegratorOptions(), v0=np.array([0.0, v0, 0.0]), stats=stats
    )
    states = list(steps)
    t, y = np.array([s.t for s in states]), np.array([s.q[1] for s in states])
    t_hit = (v0 - np.sqrt(v0**2 - 2.0 * G * CEILING)) / G
    v_hit = v0 - G * t_hit
    s = t - t_hit
    exact = np.where(s < 0.0, v0 * t - 0.5 * G * t**2, CEILING - E * v_hit * s - 0.5 * G * s**2)
    assert stats.localization.impacts == 1
    # 9.9e-10 m measured: the closing aims at half the gap tolerance (5.5e-13 m), where the
    # speed is √(2 g (1e-6 − 5.5e-13)), 2.7e-7 of it less: ~1e-9 m of height by 1 s
    assert np.max(np.abs(y - exact)) <= 1e-8
    assert min(float(st.gaps.min()) for st in states) >= -1e-12


def test_a_spinning_corner_that_sweeps_below_a_floor_inside_a_step_strikes_it():
    # a 0.2 × 0.1 m box spinning at 10 rad/s without gravity, its centre R − 1e-6 m above
    # the floor (R its half-diagonal): the corner (0.1, −0.05) points down 50.5 ms in, and
    # sweeps below the floor for 0.27 ms inside the step from 50 to 51 ms; unseen, the box
    # turned through the floor, 1.06e-3 from the run at h/16 (which locates the closing)
    radius = np.hypot(0.1, 0.05)
    box = RigidBody2D.uniform(1.0, [0.0, radius - 1e-6], Polygon.box(0.2, 0.1))
    model = Model([box], [Contact(box, Plane([0.0, 0.0], [0.0, 1.0]), restitution=E)], (0, 0))
    down = -np.pi / 2 - np.arctan2(-0.05, 0.1)
    q0, v0 = np.array([0.0, 0.0, down - 10.0 * 0.0505]), np.array([0.0, 0.0, 10.0])
    runs = []
    for h in (1e-3, 1e-3 / 16):
        stats = StepStats()
        states = simulate(model, h, 0.2, IntegratorOptions(), q0=q0, v0=v0, stats=stats)
        runs.append((np.array([st.q for st in states]), stats.localization.impacts))
    (q, located), (fine, _) = runs
    assert located == 1
    # 1.1e-11 measured: both runs locate the closing to the gap tolerance (1e-12 m), and
    # the flight between is exact (no force): the bound is 1e-3 of the miss
    assert np.max(np.abs(q - fine[::16])) <= 1e-6


def test_hermite_minimum_and_the_dip_closing_of_a_parabola():
    # g(s) = (s − 0.3)² − 0.01: minimum −0.01 at s = 0.3, first root at s = 0.2 (slope −0.2);
    # a parabola's cubic coefficient is zero, the stable root form's case
    g0, s0, g1, s1 = np.array([0.08]), np.array([-0.6]), np.array([0.48]), np.array([1.4])
    s_m, p_m = hermite_minimum(g0, s0, g1, s1)
    np.testing.assert_allclose([s_m[0], p_m[0]], [0.3, -0.01], rtol=0, atol=1e-15)
    which, tau, slope, end, p_end = dip_closings(g0, s0, g1, s1, depth=1e-3)
    assert which.tolist() == [True] and end[0] == s_m[0]
    np.testing.assert_allclose([tau[0], slope[0]], [0.2, -0.2], rtol=0, atol=1e-14)
    # no interior minimum (monotone), or one above −depth: no dip
    assert not hermite_minimum(g0, -s0, g1 + 1.0, s1)[0][0] < 1.0
    assert not dip_closings(g0, s0, g1, s1, depth=0.02)[0].any()
