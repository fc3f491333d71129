"""The frictionless laws' and the smooth friction's stopping tests do not grow with p.

Their tests read the Alart–Curnier residual over p. On a closed row that is the gap (or the
normal rate) itself, but on an open row it is the row's force over p: p × 1000 accepted
forces whose gaps were off by up to 1000 tolerances. The tests now weigh an open row's
force error by p_j D_jj (``scale``: p_j = scale / D_jj, D_jj = G_j H⁻¹G_jᵀ), the change it
makes at its own row, exactly 1 at the default scale.

Two rows on two dofs (H = M = I) with D = [[1, c], [c, 1]], c = cos 30°, both approaching:
the first set holds both, and the second row comes out with a small negative force
−ε/(1 − c²). The exact answer holds the first row alone and leaves the second open at ε.
"""

import numpy as np
import pytest

from fecontact.contact.friction import coulomb_residual
from fecontact.contact.laws import solve_position_correction, solve_velocity_jump

TOL = 1e-9  # the solver's tolerance (m, or m/s)
COS = np.cos(np.pi / 6)
G = np.array([[1.0, 0.0], [COS, np.sin(np.pi / 6)]])
D = G @ G.T  # (M = I)


def rates(eps):
    """The rows' rates (or gaps) before the update: the first closes at −1, the second at
    −c + ε, so that holding the first leaves the second at ε."""
    return np.array([-1.0, -COS + eps])


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_the_velocity_jump_leaves_no_pulling_impulse_whatever_p(scale):
    """With ε = 100 tolerances the both-rows iterate pulls the second row with an impulse
    that moves its rate by 100 tolerances. Judged as impulse over p, p × 1000 accepted it
    (its rate then 100 tolerances off); now every p goes on to the exact answer."""
    eps = 100 * TOL
    c = rates(eps)
    p = scale / np.diag(D)
    W, Lam, _ = solve_velocity_jump(G, c, lambda b: b, p, 1.0, tol=TOL, scale=scale)
    assert np.all(Lam >= 0.0)
    # the exact rates (0, ε): a direct solve to round-off, far below the tolerance
    assert np.max(np.abs(c + G @ W - [0.0, eps])) <= 1e-3 * TOL


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_the_position_correction_leaves_no_pulling_force_whatever_p(scale):
    """The same rows as linear gaps g(U) = g̃ + G U in the metric H = I."""
    eps = 100 * TOL
    g0 = rates(eps)
    p = scale / np.diag(D)

    def system(U, s, A):
        return (lambda B: B), None  # (linear gaps: H⁻¹ = I, no curvature)

    U, nu, _ = solve_position_correction(
        lambda U: (g0 + G @ U, G), system, 2, p, 1.0, TOL, 0.1 * TOL, scale=scale
    )
    assert np.all(nu >= 0.0)
    assert np.max(np.abs(g0 + G @ U - [0.0, eps])) <= 1e-3 * TOL


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_the_smooth_frictions_law_error_is_what_the_error_does(scale):
    """A contact (normal, two tangents) open by 1 mm that still carries a normal force δ
    and a sticking one: the open row's error is the gap δ D_NN its force makes, whatever p
    (before, δ/p_N: δ D_NN / 1000 at p × 1000); the sticking contact's is its slip."""
    Dc = np.diag([2.0, 3.0, 3.0, 0.5, 0.8, 0.8])  # (rows' inverse effective masses)
    p = scale / np.diag(Dc)
    delta = 4e-8  # N: below p w_N at p × 1e-3 (5e-7), so the row reads open at every p
    x = np.array([delta, 0.0, 0.0, 10.0, 1.0, 0.0])  # the second contact sticks, |x_T| < μ x_N
    w = np.array([1e-3, 0.0, 0.0, 0.0, 2e-12, 0.0])
    err = coulomb_residual(w, x, p, 1.0, np.array([0.5, 0.5]), 2, scale)
    assert err == pytest.approx(delta * Dc[0, 0], rel=1e-12)
