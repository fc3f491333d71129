"""Solves with A − C from the factors of A when C touches few unknowns (Woodbury)."""

import numpy as np
import pytest
import scipy.sparse as sp

from fecontact.linalg import UnitColumns, factorize, low_rank_solver


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
