"""Redundant frictionless rows: a rigid box lying on a face has four corner rows for the three
motions they hold (one translation, two rotations), so that W = G M⁻¹Gᵀ is singular. Newton's
impact law there is a linear complementarity problem whose velocity is unique; its rates c
need not lie in the range of W (the impact law's e_j ġ⁻_j differs from corner to corner),
and then one corner has to open. These tests hold the velocity jump to the law's tolerance
on such rows, against an exact enumeration of the problem's solutions."""

import itertools

import numpy as np
import pytest

from fecontact.contact import ContactStats
from fecontact.contact.laws import solve_velocity_jump
from fecontact.contact.redundant_jump import proximal_jump
from fecontact.simulation import run
from fecontact.testing import case

A, B, C, MASS = 0.2, 0.15, 0.1, 1.0  # the tumbling box's sides (m) and mass (kg)


def _box_on_face():
    """(G, M⁻¹) of a box lying on its −z face on the plane z = 0 (rotation identity): rows
    [n, r_j × n] of its four bottom corners r_j, dofs (x, Ω) with Ω in the body frame."""
    corners = np.array([[sx * A / 2, sy * B / 2, -C / 2] for sx in (-1, 1) for sy in (-1, 1)])
    n = np.array([0.0, 0.0, 1.0])
    G = np.hstack([np.tile(n, (4, 1)), np.cross(corners, n)])
    J = MASS / 12.0 * np.array([B**2 + C**2, A**2 + C**2, A**2 + B**2])
    return G, np.diag(1.0 / np.r_[MASS, MASS, MASS, J])


def _exact_jump(G, Minv, c):
    """The velocity jump of 0 ≤ P ⊥ c + G M⁻¹Gᵀ P ≥ 0 by enumeration of the rows that close
    (the velocity is unique; the multipliers of redundant rows are taken of least norm)."""
    D = G @ Minv @ G.T
    for size in range(len(c) + 1):
        for S in map(list, itertools.combinations(range(len(c)), size)):
            P = np.zeros(len(c))
            P[S] = np.linalg.lstsq(D[np.ix_(S, S)], -c[S], rcond=1e-12)[0] if S else []
            gd = c + D @ P
            if np.all(P >= -1e-14) and np.all(gd >= -1e-14) and np.all(np.abs(gd[S]) <= 1e-14):
                return Minv @ G.T @ P
    raise AssertionError("no solution")


def _jump(G, Minv, c, p_factor=1.0, tol=1e-9, Lam0=None):
    Y = Minv @ G.T
    p = p_factor / np.einsum("ij,ji->i", G, Y)  # the effective-mass augmentation × p_factor
    stats = ContactStats(minimum_norm=True)
    W, Lam, _ = solve_velocity_jump(
        G, c, None, p, 1.0, 30, Y=Y, Lam0=Lam0, tol=tol, stats=stats, scale=p_factor
    )
    return W, Lam, stats


# rates from a tumbling_box run at 0.273 s (friction 0, e_N = 0.2): c1 − c2 − c3 + c4 = 3.3e-4
# m/s, outside the range of W (a rigid motion gives 0), so the four corners cannot all close
INCONSISTENT = np.array([-0.0388, -0.0138, -0.0355, -0.0102])


@pytest.mark.parametrize("p_factor", [1e-3, 1.0, 1e3])
def test_rows_that_cannot_all_close_open_one_and_hold_the_law(p_factor):
    G, Minv = _box_on_face()
    W, Lam, stats = _jump(G, Minv, INCONSISTENT, p_factor)
    gd = INCONSISTENT + G @ W
    # before: least squares spread the inconsistency over the four closed corners,
    # ġ = ±8e-5 m/s, 1e5 times the tolerance, and the active set repeated
    assert np.all(gd >= -1e-9) and np.all(Lam >= 0.0)
    assert np.max(np.abs(gd * Lam)) <= 1e-9 * np.max(Lam)  # complementarity
    assert stats.final_residuals.velocity <= 1.0
    # the velocity is unique: exact to round-off of the rates (1e-2 m/s × 1e-14)
    np.testing.assert_allclose(W, _exact_jump(G, Minv, INCONSISTENT), rtol=0, atol=1e-13)


def test_consistent_rates_on_redundant_rows_keep_the_least_squares_answer():
    """Rates of a rigid motion (in the range of W): the four corners all close, the least-norm
    multipliers are positive, and no proximal step is taken: the same answer as before."""
    G, Minv = _box_on_face()
    c = G @ np.array([0.0, 0.0, -0.5, 0.3, -0.2, 0.0])  # landing flat while rocking
    W, Lam, stats = _jump(G, Minv, c)
    assert stats.redundant_jumps == 0 and stats.least_squares > 0
    np.testing.assert_allclose(G @ W + c, 0.0, atol=1e-15)
    np.testing.assert_allclose(W, _exact_jump(G, Minv, c), rtol=0, atol=1e-14)


def test_independent_rows_never_take_the_proximal_path():
    G, Minv = _box_on_face()
    W, Lam, stats = _jump(G[:3], Minv, INCONSISTENT[:3])
    assert stats.redundant_jumps == 0 and stats.least_squares == 0
    np.testing.assert_allclose(W, _exact_jump(G[:3], Minv, INCONSISTENT[:3]), atol=1e-15)


def test_proximal_jump_gives_least_norm_multipliers_whatever_the_start():
    """Consistent rates whose least-norm multipliers are all positive: any start ends on them
    (the proximal iterate is replaced by the least-norm solution of its closed rows)."""
    G, Minv = _box_on_face()
    kD = G @ Minv @ G.T
    c = G @ np.array([0.0, 0.0, -0.5, 0.01, -0.02, 0.0])
    least = np.linalg.lstsq(kD, -c, rcond=1e-12)[0]
    assert np.all(least > 0)
    eq = np.zeros(4, bool)

    def settled(x, gd):
        return np.all(gd >= -1e-10) and np.all(np.abs(gd[x > 0]) <= 1e-10)

    for start in (np.zeros(4), np.array([1.0, 0.0, 0.0, 1.0]), least + [1, -1, -1, 1]):
        Lam, steps = proximal_jump(kD, c, eq, start, settled, 1e-10)
        np.testing.assert_allclose(Lam, least, rtol=1e-12)
        assert steps == 1


def test_a_frictionless_box_settling_on_a_face_holds_its_velocity_law(tmp_path):
    """The frictionless tumbling box lands on a face at 0.27 s: before, its velocity jump
    ended with a residual 7.7e4 times its tolerance and a warning; now every correction ends
    within tolerance, the proximal solves are counted, and the box rests on a face."""
    sim = case("tumbling_box").build(friction=0.0).replace(t_end=0.3)
    summary = run(sim, tmp_path / "free", frames=False)
    assert summary["status"] == "completed"
    assert max(summary["final_residuals"].values()) <= 1.0
    assert not [w for w in summary["warnings"] if w.startswith("contact:")]
    assert summary["redundant_jumps"]["solves"] > 0
    assert summary["min_gap"] >= -1e-9
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 1e-3 * ledger["scale"]


def _rough_box_on_face():
    """(A, M⁻¹) of the box on its face with a normal and two tangent rows per corner."""
    G, Minv = _box_on_face()
    corners = np.array([[sx * A / 2, sy * B / 2, -C / 2] for sx in (-1, 1) for sy in (-1, 1)])
    rows = []
    for r, g in zip(corners, G, strict=True):
        rows.append(g)
        rows += [np.r_[t, np.cross(r, t)] for t in np.eye(3)[:2]]
    return np.array(rows), Minv


def test_a_relinearized_frictional_correction_is_not_solved_from_zero_again():
    """Redundant rough rows (four sticking corners, 12 rows on 6 dofs): solved once from
    the warm start and from zero, the relinearization that starts from that solution keeps
    it without a second cold solve, to the same motion."""
    from fecontact.contact import CoulombStats
    from fecontact.contact.friction import solve_coulomb

    A_, Minv = _rough_box_on_face()
    D = A_ @ Minv @ A_.T
    p = 1.0 / np.diag(D)
    c = A_ @ np.array([0.002, 0.0, -0.01, 0.01, -0.02, 0.0])  # pressed, slipping, rocking
    mu, tol = np.full(4, 0.5), 1e-12
    first = CoulombStats()
    x, _, _ = solve_coulomb(c, D, p, 1.0, mu, 2, 0.5 * np.ones(12), tol, stats=first,
                            minimum_norm=True)  # fmt: skip
    again, warm = CoulombStats(), CoulombStats()
    x_cold, _, _ = solve_coulomb(c, D, p, 1.0, mu, 2, x, tol, stats=again, minimum_norm=True)
    x_warm, _, _ = solve_coulomb(
        c, D, p, 1.0, mu, 2, x, tol, stats=warm, minimum_norm=True, cold_start=False
    )
    assert warm.iterations < again.iterations  # the cold start's Newton iterations saved
    # the same motion to the solver's tolerance (m/s of the rows)
    assert np.max(np.abs(D @ (x_warm - x_cold))) <= tol
