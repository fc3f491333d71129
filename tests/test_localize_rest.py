"""The rest of a localized impact step of a nonlinear solid, solved by modified Newton
(:func:`fecontact.time.acceleration_form.held_factors`): fewer factorizations of S_t than
full Newton, to the same answer (docs/validation/localization.md, Cost)."""

import numpy as np

from fecontact.testing import case, trace
from fecontact.time import acceleration_form, newton


def counted(monkeypatch, contraction: float):
    """The Neo-Hookean disk's first impact, localized (refinements 2, 4 ms: one impact
    located in the step from 1.94 ms, then the contact phase), with ``CONTRACTION`` set:
    (its trace, the smooth steps' factorizations of S_t: 38 held, 40 full measured)."""
    made = []
    factorize = acceleration_form.factorize_or_fail

    def counting(*args, **kwargs):
        made.append(1)
        return factorize(*args, **kwargs)

    monkeypatch.setattr(acceleration_form, "factorize_or_fail", counting)
    monkeypatch.setattr(acceleration_form, "CONTRACTION", contraction)
    r = trace(case("disk_drop").build(refinements=2), t_end=0.004)
    assert r["status"] == "completed"
    return r, len(made)


def test_rest_of_the_step_by_modified_newton_matches_full_newton(monkeypatch):
    held, n_held = counted(monkeypatch, acceleration_form.CONTRACTION)
    full, n_full = counted(monkeypatch, 0.0)  # (a factor 0 never holds: full Newton)
    assert n_held < n_full
    # both converged to the Newton tolerances (residual 1e-8 of the forces' scale): the
    # energies agree to far below the step's own error (3e-2 J against h/8 on this run)
    scale = float(np.max(np.abs(full["total"])))
    assert np.max(np.abs(held["total"] - full["total"])) <= 1e-8 * scale
    assert np.max(np.abs(held["kinetic"] - full["kinetic"])) <= 1e-8 * scale
    assert held["min_gap"].min() >= -1e-12 and full["min_gap"].min() >= -1e-12


def test_step_terms_sorted_once_per_types_as_sorted_each_step(monkeypatch):
    # the roles a step's terms are put in from their types' places (NewtonPlan.sorted) are
    # those sorting them gives (newton.roles), term for term, in every step with a pressed
    # contact of the ball's landing and rebound (identity: no tolerance)
    checked = []
    sorted_ = newton.NewtonPlan.sorted

    def compared(plan, terms):
        terms = list(terms)
        placed, sorted_each = sorted_(plan, terms), newton.roles(terms)
        for a, b in zip(placed, sorted_each, strict=True):
            assert a == b if isinstance(a, list) else a is b
        checked.append(1)
        return placed

    monkeypatch.setattr(newton.NewtonPlan, "sorted", compared)
    r = trace(case("ball_drop").build(refinements=1), t_end=0.004)
    assert r["status"] == "completed" and checked
