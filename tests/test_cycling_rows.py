"""A position correction whose active sets cycle (a held row and its twin, of which the
active-set rule keeps one) ends at the law: its updates past the iteration limit solve the
linearised law on every row at once (:mod:`fecontact.contact.cycling_rows`)."""

import numpy as np
import pytest

from fecontact.contact import solve_position_correction
from fecontact.contact.stats import ContactStats

COS = 0.93  # the correlation of the held row and its twin (the 57 Δx/c balls: 0.934)
G = np.array([[1.0, 0.0, 0.0], [COS, np.sqrt(1.0 - COS**2), 0.0], [0.3, -0.2, 1.0]])
G0 = np.array([0.0, -1e-3, 2e-5])  # m: the held row closed, its twin 1 mm in, a third open
HELD = np.array([True, False, False])
TWINS = np.array([1, 0, -1])
TOL = 1e-12  # m: the gap tolerance of the correction


def _gaps(curvature: float):
    """Rows 0 and 1 linear, row 2 curved: g₂ = G₂U + ½ κ |U|² (κ in 1/m), with the solver
    of H − C, H = I and C = κ s₂ I, as the correction's ``system`` gives it."""

    def gaps(U):
        g = G0 + G @ U
        g[2] += 0.5 * curvature * U @ U
        grad = G.copy()
        grad[2] += curvature * U
        return g, grad

    def system(U, s, A):
        if curvature == 0.0:
            return (lambda B: B), None
        C = np.eye(3) * curvature * (s[2] if A[2] else 0.0)
        return (lambda B: np.linalg.solve(np.eye(3) - C, B)), C

    return gaps, system


def _corrected(curvature: float, p: float, k: float):
    gaps, system = _gaps(curvature)
    stats = ContactStats()
    U, nu, _ = solve_position_correction(
        gaps, system, 3, np.full(3, p), k, TOL, 0.1 * TOL, bilateral=HELD, stats=stats,
        twins=TWINS,
    )  # fmt: skip
    return U, k * nu, gaps(U)[0], stats


@pytest.mark.parametrize("curvature", [0.0, 50.0])
def test_a_held_row_and_its_twin_that_take_turns_end_at_the_law(curvature):
    """The active-set iteration keeps the deeper of the twins: without the held row the
    update lifts it 0.93 mm, with it the twin stays 1 mm in; the set repeats without
    settling. The frozen set of least residual left the held row open by 0.93 mm (9.3e8
    tolerances). Solved as a complementarity problem the correction ends at the law: the
    held row closed, every unilateral row closed with a pushing force or open without one,
    to the correction's tolerance, whatever p (× 1000) or k (÷ 100)."""
    U, force, g, stats = _corrected(curvature, 1.0, 1.0)
    assert stats.complementary_corrections == 1 and stats.frozen_active_sets == 0
    assert stats.final_residuals.position <= 1.0  # (the law's own residual, in tolerances)
    assert abs(g[0]) <= TOL and np.all(g[1:] >= -TOL)  # held closed, nothing inside
    assert np.all(force[1:] >= 0.0)  # unilateral rows push
    # complementarity: a row that pushes is closed (its force moves nothing else)
    assert np.all((force[1:] == 0.0) | (np.abs(g[1:]) <= TOL))
    assert force[1] > 0.0 and force[0] < 0.0  # both twins held: the law needs them both
    for p, k in ((1e3, 1.0), (1.0, 1e-2)):
        other = _corrected(curvature, p, k)
        # (the same law's answer, each to the gap tolerance: U moves the gaps one for one)
        assert np.max(np.abs(other[0] - U)) <= 10.0 * TOL


def test_a_held_row_that_freezes_against_its_twin_is_solved_again_unilateral():
    """A held row and its twin along the same normal (correlation 1), the twin 1 mm deeper:
    no set closes the held row with the twin outside (closed, the held row pushes the twin
    1 mm in; closing the twin lifts the held row 1 mm), and the complementarity updates
    find no answer of the held law. The frozen set kept the deeper twin and left the held
    equality 1 mm open (1e9 tolerances: the fast P2 disks' 1.13e8). Solved again with the
    held row unilateral, the correction ends at the law: the twin closed and pushing, the
    held row open without force, a third row untouched; counted as released, not frozen."""
    G = np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    g0 = np.array([0.0, -1e-3, 2e-5])  # m: the held row closed, its twin 1 mm in, one open

    def gaps(U):
        return g0 + G @ U, G.copy()

    def system(U, s, A):
        return (lambda B: B), None

    stats = ContactStats()
    U, nu, _ = solve_position_correction(
        gaps, system, 3, np.ones(3), 1.0, TOL, 0.1 * TOL, bilateral=HELD, stats=stats,
        twins=TWINS, held_rows=HELD,
    )  # fmt: skip
    g = gaps(U)[0]
    assert stats.released_corrections == 1 and stats.frozen_active_sets == 0
    assert stats.final_residuals.position <= 1.0  # (the law's own residual, in tolerances)
    # (U moves the gaps one for one: the twin closed to the tolerance, the held row lifted
    # by the 1 mm the twin needed, to the same tolerance)
    assert abs(g[1]) <= TOL and abs(g[0] - 1e-3) <= TOL and g[2] == pytest.approx(2e-5)
    assert nu[1] > 0.0 and nu[0] == 0.0 and nu[2] == 0.0
