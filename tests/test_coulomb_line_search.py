"""The backtracking of the Coulomb Newton (:mod:`fecontact.contact.coulomb_newton`) reads the
merits of its cuts at once and passes over those that fail by more than their round-off:
it takes the cut one point at a time would take."""

import numpy as np
import pytest

from fecontact.contact import coulomb_newton
from fecontact.contact.coulomb_newton import NotConverged, newton, newton_residual, trial_merits
from fecontact.contact.stats import CoulombStats


def problem(seed, m, dofs, nt=2):
    """m frictional contacts on ``dofs`` degrees of freedom (fewer than the rows: redundant
    ones, D singular), a gap vector driving them in, one augmentation per row."""
    rng = np.random.default_rng(seed)
    N = m * (1 + nt)
    G = rng.normal(size=(N, dofs))
    D = G @ G.T
    c = rng.normal(size=N)
    c[:: 1 + nt] -= 1.0  # (most normals pressed)
    p = 1.0 / np.maximum(np.diag(D), 1e-12)
    mu = np.full(m, 0.3)
    return c, D, p, mu, nt


def point_by_point(residual, merits, x, directions, R, stats):
    """The backtracking as the plain Armijo loop: each cut's residual on its own."""
    f0 = R @ R
    directions = [d for d in directions if d is not None]
    for dx in directions:
        s = 1.0
        for _ in range(coulomb_newton.CUTS):
            xs = x + s * dx
            Rs = residual(xs, False)[0]
            if Rs @ Rs <= (1.0 - 1e-4 * s) * f0:
                return (xs, *residual(xs))
            s *= 0.5
            stats.line_search_cuts += 1
    stats.full_steps_forced += 1
    xs = x + directions[-1]
    return (xs, *residual(xs))


@pytest.mark.parametrize("seed", range(6))
def test_the_merits_read_at_once_are_the_points_within_their_margin(seed):
    c, D, p, mu, nt = problem(seed, 5, 9)
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(19, len(c))) * 10.0 ** rng.integers(-3, 3, size=(19, 1))
    closing = rng.random(len(mu)) < 0.5
    merit, margin = trial_merits(X, c, D, p, 1.0, mu, len(c), closing)
    single = [newton_residual(x, c, D, p, 1.0, mu, len(c), closing, False)[0] for x in X]
    alone = np.array([r @ r for r in single])
    assert np.all(np.abs(merit - alone) <= margin)
    # (the margin is round-off's, far below the merits it screens)
    assert np.all(margin <= 1e-9 * alone)


@pytest.mark.parametrize("seed", range(8))
def test_newton_takes_the_cuts_of_the_point_by_point_search(seed, monkeypatch):
    c, D, p, mu, nt = problem(seed, 4 + seed % 3, 8)
    outcomes = []
    for search in (None, point_by_point):
        if search is not None:
            monkeypatch.setattr(coulomb_newton, "_backtrack", search)
        stats = CoulombStats()
        try:
            x, status, its = newton(c, D, p, 1.0, mu, nt, None, 1e-10, 50, stats)
            outcomes.append((x, status, its, stats.line_search_cuts, stats.full_steps_forced))
        except NotConverged as err:
            outcomes.append((str(err), stats.line_search_cuts, stats.full_steps_forced))
    batched, plain = outcomes
    assert len(batched) == len(plain)
    for a, b in zip(batched, plain, strict=True):
        np.testing.assert_array_equal(a, b)  # (bit for bit)
