"""Solves with A − C from the factors of A when C touches few unknowns (Woodbury)."""

import numpy as np
import pytest
import scipy.sparse as sp

from fecontact.linalg import UnitColumns, factorize, low_rank_solver
from fecontact.linalg.low_rank import FACTORIZATION_COLUMNS
from fecontact.time.held_curvature import NEAR


def spd(n, seed):
    A = sp.random(n, n, 0.02, random_state=seed)
    return (A + A.T + 10.0 * sp.identity(n)).tocsc()


@pytest.mark.parametrize("t", [1, 6, 30])
def test_low_rank_update_solves_like_a_new_factorization(t):
    n, rng = 400, np.random.default_rng(t)
    A = spd(n, t)
    T = rng.choice(n, t, replace=False)
    B = rng.normal(size=(t, t))
    C = sp.coo_matrix(((B + B.T).ravel(), (np.repeat(T, t), np.tile(T, t))), shape=(n, n))
    solve_A = factorize(A, symmetric=True)
    units = UnitColumns(solve_A, n)
    b = rng.normal(size=(n, 4))
    x = low_rank_solver(solve_A, C, units)(b)
    expected = factorize((A - C).tocsc())(b)
    # both are backward stable solves of a system with condition number below 1e3 here
    np.testing.assert_allclose(x, expected, rtol=1e-10, atol=1e-12)
    assert units.solves == t
    low_rank_solver(solve_A, C, units)  # the columns of A⁻¹ are kept: no new solve
    assert units.solves == t


def test_singular_update_is_reported():
    n = 50
    A = sp.identity(n, format="csc")
    C = sp.coo_matrix(([1.0], ([7], [7])), shape=(n, n))  # A − C is singular at dof 7
    solve_A = factorize(A.toarray())
    with pytest.raises(np.linalg.LinAlgError):
        low_rank_solver(solve_A, C, UnitColumns(solve_A, n))


def test_a_size_met_once_factorizes_while_cheaper_than_its_columns():
    n, t = 400, 3 * FACTORIZATION_COLUMNS + 10
    T = np.arange(0, 2 * t, 2)
    solve_A = factorize(spd(n, 1), symmetric=True)
    units = UnitColumns(solve_A, n, once=True)
    # three factorizations cost less than the t columns, a fourth would not: columns then
    decisions = [units.factorize_instead(T) for _ in range(4)]
    assert decisions == [True, True, True, False] and units.factorized == 3
    units(T)  # (the columns, made at the fourth update)
    assert not units.factorize_instead(T) and units.solves == t
    # a run's own size keeps its columns for every step: never a factorization
    own = UnitColumns(solve_A, n)
    assert not any(own.factorize_instead(T) for _ in range(4))
    # a few touched dofs: their columns cost less than one factorization
    few = UnitColumns(solve_A, n, once=True)
    assert not few.factorize_instead(T[: FACTORIZATION_COLUMNS - 1])


def fast_balls(monkeypatch, columns: int, held: bool = False):
    """The coarse two balls (1,122 dofs) at 10 m/s into their first located impacts, with
    ``columns`` the cost of a factorization in column solves (0: never one), ``held``: the
    factors of S(a₀) + C₀ serve the updates at nearby sizes (modified Newton), else every
    update is Newton's own. Returns (the last state, the ladder's counts, the model)."""
    from fecontact.linalg import low_rank
    from fecontact.testing import case
    from fecontact.time import StepStats, held_curvature, simulate

    monkeypatch.setattr(low_rank, "FACTORIZATION_COLUMNS", columns or 10**9)
    monkeypatch.setattr(held_curvature, "NEAR", NEAR if held else 0.0)
    sim = case("two_balls").build(velocity=10.0, spacing=0.2, base=1, t_end=1.2e-4)
    stats = StepStats()
    run = simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats)
    states = list(run)
    return states[-1], stats.localization.ladder, sim


@pytest.mark.slow
def test_factorizations_at_sizes_met_once_move_no_state_beyond_the_solves(monkeypatch):
    columns_always = fast_balls(monkeypatch, 0)
    st, ladder, _ = fast_balls(monkeypatch, FACTORIZATION_COLUMNS)
    assert columns_always[1]["curvature_factorizations"] == 0
    assert ladder["curvature_factorizations"] > 0  # (the rule took the factorizations)
    # the same Newton updates but for their solves' round-off (measured 1.2e-14 in q and
    # 2.9e-14 in v); the bounds are those of the steps' own tolerance (1e-8 of the
    # residual), which an update more or less would still meet
    q, v = columns_always[0].q, columns_always[0].v
    assert np.max(np.abs(st.q - q)) <= 1e-9 * np.max(np.abs(q))
    assert np.max(np.abs(st.v - v)) <= 1e-7 * np.max(np.abs(v))


@pytest.mark.slow
def test_held_factors_of_a_nearby_size_reach_the_same_steps_within_the_newton_tolerance(
    monkeypatch,
):
    newton, newton_ladder, _ = fast_balls(monkeypatch, FACTORIZATION_COLUMNS)
    st, ladder, sim = fast_balls(monkeypatch, FACTORIZATION_COLUMNS, held=True)
    assert newton_ladder["curvature_reuses"] == 0 and ladder["curvature_reuses"] > 0
    # fewer factorizations of S(a) + C (28 → 8 measured) and of S(a) for its columns (23 → 3)
    assert ladder["curvature_factorizations"] < newton_ladder["curvature_factorizations"]
    assert ladder["pcg_refactorized"] < newton_ladder["pcg_refactorized"]
    # a modified Newton iterate stops within the increment tolerance of the root, where
    # Newton's own stops far inside it: the states agree to that tolerance (of the model's
    # size in q, over the step in v), not to round-off (measured 2.8e-11 m in q and 6.7e-7
    # m/s in v against bounds of 1.7e-9 m and 3.8e-5 m/s)
    size, h = sim.options.tol_increment * sim.model.length, sim.dt
    assert np.max(np.abs(st.q - newton.q)) <= size
    assert np.max(np.abs(st.v - newton.v)) <= size / h
