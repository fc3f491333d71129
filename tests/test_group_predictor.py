"""The Lie-group step's predictor (fecontact.time.lie.predict_increment) with v̇ extrapolated:
exact for an acceleration linear in time, and consistent with the generalized-α relations
between D, v, v̇ and a."""

import numpy as np
import pytest

from fecontact.time.generalized_alpha import coefficients
from fecontact.time.lie import predict_increment
from fecontact.time.state import State


def linear_acceleration_state(c, h_last: float, A: np.ndarray, B: np.ndarray) -> State:
    """A state at t = 0 of a motion with v̇(t) = A + B t, reached by a step of h_last: a lags
    v̇ by (α_f − α_m) h_last, which solves the recursion of a exactly for a linear v̇."""
    v = np.array([0.3, -1.2, 2.0, 0.7])
    vd = A
    a = A + B * (c.am - c.af) * h_last
    return State(0.0, np.zeros(4), v, vd, a, h=h_last)


@pytest.mark.parametrize("rho_inf", [0.0, 0.5, 0.9])
def test_the_extrapolated_predictor_is_exact_for_a_linear_acceleration(rho_inf):
    h = 1e-3
    c = coefficients(rho_inf, h)
    A, B = np.array([1.0, -2.0, 0.5, 3.0]), np.array([40.0, 7.0, -300.0, 0.0])
    st = linear_acceleration_state(c, h, A, B)
    D, v, vd, a = predict_increment(st, c, extrapolate=True)
    # v̇_{n+1} = v̇(h), to the round-off of v̇ − a (ε|a| ≈ 7e-14) over α_f − α_m (≥ 0.05): 1e-12
    assert np.allclose(vd, A + B * h, rtol=0.0, atol=1e-9)
    # the generalized-α relations between the four rows hold as for any iterate
    am, af, gm, be = c.am, c.af, c.gamma, c.beta
    assert np.allclose((1 - am) * a + am * st.a, (1 - af) * vd + af * st.vd, rtol=1e-15)
    assert np.allclose(v, st.v + h * ((1 - gm) * st.a + gm * a), rtol=1e-15)
    assert np.allclose(D, h * st.v + h * h * ((0.5 - be) * st.a + be * a), rtol=1e-15)


def test_without_a_slope_the_predictor_keeps_the_acceleration():
    """At the first step (h_{n−1} = 0), at ρ∞ = 1 (a carries nothing of v̈) and unless asked,
    v̇_{n+1} = v̇_n: the constant-acceleration predictor of the planar step."""
    A, B = np.array([1.0, -2.0, 0.5, 3.0]), np.array([40.0, 7.0, -300.0, 0.0])
    for rho_inf, h_last, extrapolate in ((0.5, 0.0, True), (1.0, 1e-3, True), (0.5, 1e-3, False)):
        c = coefficients(rho_inf, 1e-3)
        st = linear_acceleration_state(c, h_last, A, B)
        plain = c.P @ np.array([np.zeros(4), st.v, st.vd, st.a])
        assert np.array_equal(predict_increment(st, c, extrapolate), plain)


def test_after_a_shorter_step_the_slope_is_taken_over_its_length():
    """A step of h after one of h/4 extrapolates v̇ over h/4 only: the estimate of v̈ from the
    short lag is not amplified by the ratio of the steps."""
    h = 1e-3
    c = coefficients(0.5, h)
    A, B = np.array([1.0, -2.0, 0.5, 3.0]), np.array([40.0, 7.0, -300.0, 0.0])
    st = linear_acceleration_state(c, h / 4, A, B)
    vd = predict_increment(st, c, extrapolate=True)[2]
    assert np.allclose(vd, A + B * h / 4, rtol=0.0, atol=1e-9)
