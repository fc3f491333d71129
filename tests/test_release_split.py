"""Releases at their own instant: the step of solids in which the sub-steps taken aside read
the release is split there (:mod:`fecontact.time.release_split`), against the finest step's
run of Hertz's ball and the energy of a release at many wave transits
(docs/validation/localization.md, *Releases located inside the step*)."""

import dataclasses

import numpy as np
import pytest

from fecontact.testing import case
from fecontact.time import StepStats, simulate
from fecontact.time import substeps as releases

E, NU, R, RHO = 1e7, 0.3, 0.05, 1000.0


def hertz_rebound(h_over_tc=None, localize="auto", **options):
    """(the ball's rebound speed (m/s), the run's localization counts, its deepest
    penetration (m)) of the P1 ball (refinements 1) of tests/test_localize.py at 1 m/s, no
    gravity, closing 0.37 of a step into its third step, over 1.5 t_c; h = t_c × the fraction,
    or 2^-15 s."""
    build = case("ball_drop").build
    ball = build(refinements=1, E=E, nu=NU, rho=RHO).model.bodies[0]
    t_c = 2.87 * (ball.mass**2 / (R * (E / (1 - NU**2)) ** 2 * 1.0)) ** 0.2
    h = 2.0**-15 if h_over_tc is None else t_c * h_over_tc
    sim = build(
        refinements=1, E=E, nu=NU, rho=RHO, velocity=1.0, gravity=0.0,
        drop_height=2.37 * h, t_end=1.5 * t_c,
    )  # fmt: skip
    opts = dataclasses.replace(sim.options, localize=localize, detection_margin=0.01, **options)
    body = sim.model.bodies[0]
    w = body.mass_matrix() @ body.translation_field(np.array([0.0, 0.0, 1.0])) / body.mass
    stats, deepest = StepStats(), 0.0
    for st in simulate(sim.model, h, 1.5 * t_c, opts, q0=sim.q0, v0=sim.v0, stats=stats):
        deepest = max(deepest, st.penetration)
    return float(w @ st.v[sim.model.body_slice(0)]), stats.localization, deepest


@pytest.fixture(scope="module")
def finest():
    return hertz_rebound()[0]


def test_the_located_release_brings_the_rebound_nearer_the_finest_step(finest, monkeypatch):
    # at t_c/20 the whole steps hold the contact to the end of the step in which the
    # sub-steps read its release (0.875 of it) with 27 N left, and let it go from the next
    # step's start: the ball leaves 1.62e-2 m/s slower than at the finest step; split at
    # the reading 1.01e-2 (measured). The bound sits between them, 2e-3 (a fifth of the
    # split's error) above the split's: what is left is the whole steps' contact phase
    split, counts, deepest = hertz_rebound(1 / 20)
    assert counts.release_splits == 1 and counts.release_split_fallbacks == 0
    assert counts.release_probes == 1  # (the probe's reading is the split's instant)
    assert abs(split - finest) <= 1.2e-2
    assert deepest <= 1e-12  # exact contact: no penetration beyond round-off
    init = releases.Releases.__init__
    monkeypatch.setattr(
        releases.Releases, "__init__", lambda self, model, split=False: init(self, model)
    )
    whole, counts, _ = hertz_rebound(1 / 20)
    assert counts.release_splits == 0
    assert abs(whole - finest) > 1.5e-2  # (1.62e-2 measured: the split is what gains)


def test_the_split_does_not_depend_on_p_and_k():
    # the instant is the probe's converged reading and both parts are converged steps:
    # p × 1000 and k / 100 change only the paths of the semi-smooth Newton (round-off of
    # the solves over a few hundred steps: 1e-12 of the speed)
    base = hertz_rebound(1 / 20)[0]
    for option in ({"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}):
        assert hertz_rebound(1 / 20, **option)[0] == pytest.approx(base, abs=1e-12)
