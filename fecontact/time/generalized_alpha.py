"""Generalized-α coefficients and predictor (Chung & Hulbert 1993, in the form of Arnold & Brüls
2007), shared by every stepper built on the generalized-α step.

    α_m = (2ρ∞ − 1)/(ρ∞ + 1),  α_f = ρ∞/(ρ∞ + 1),  γ = ½ + α_f − α_m,  β = ¼(γ + ½)².
"""

from __future__ import annotations

import copy
import dataclasses
import functools

import numpy as np

from ..errors import check_range

__all__ = ["Coefficients", "alpha_coefficients", "coefficients", "predict", "resized"]


def alpha_coefficients(rho_inf: float) -> tuple[float, float, float, float]:
    """(α_m, α_f, γ, β) of the generalized-α method for spectral radius ρ∞ ∈ [0, 1]."""
    r = check_range("rho_inf", rho_inf, 0.0, 1.0)
    am = (2.0 * r - 1.0) / (r + 1.0)
    af = r / (r + 1.0)
    gamma = 0.5 + af - am
    return am, af, gamma, 0.25 * (gamma + 0.5) ** 2


class Coefficients:
    """Generalized-α coefficients for one step of size h (shared: see ``coefficients``).

    ``P`` is the predictor as a map of (q, v, v̇, a)_n to (q, v, v̇, a)_{n+1} with
    v̇_{n+1} = v̇_n, and ``w`` = (1, γ′, β′, ∂a/∂q) the rates at which a Newton update of q
    moves the four."""

    def __init__(self, rho_inf: float, h: float):
        am, af, gm, be = alpha_coefficients(rho_inf)
        self.am, self.af, self.gamma, self.beta, self.h = am, af, gm, be, h
        self.bp = (1.0 - am) / (be * h * h * (1.0 - af))  # β′ = ∂v̇/∂q
        self.gp = gm / (be * h)  # γ′ = ∂v/∂q
        self.da = (1.0 - af) / (1.0 - am) * self.bp  # ∂a/∂q
        # a_{n+1} = k1 v̇_n + k2 a_n, from (1 − α_m) a_{n+1} + α_m a_n = v̇_n
        k1, k2 = 1.0 / (1.0 - am), -am / (1.0 - am)
        hh = h * h
        self.P = np.array(
            [
                [1.0, h, hh * be * k1, hh * (0.5 - be) + hh * be * k2],
                [0.0, 1.0, h * gm * k1, h * (1.0 - gm) + h * gm * k2],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, k1, k2],
            ]
        )
        self.w = np.array([1.0, self.gp, self.bp, self.da])
        # of a v̇ rising linearly (a lags it by (α_m − α_f)h) the step makes the drift
        # q − q_n − h v_n = ½h² v̇(t_n + θh) and the rate v − v_n = h v̇(t_n + h/2): the force
        # M v̇(t_n + (1 − θ)h) through that drift does the work ½h² v̇ᵀM v̇ at t_n + h/2 that
        # the rate carries, to O(h⁴) per step, so the correction reads the loads there
        # (θ = ½ for ρ∞ = 1, 5/9 for ρ∞ = ½; docs/explanation/energy_ledger.md)
        theta = 2.0 * ((0.5 - be / (1.0 - am)) * (am - af) + be * (1.0 - af) / (1.0 - am))
        self.drift_load = 1.0 - theta  # (a fraction of the step)


@functools.lru_cache(maxsize=64)
def coefficients(rho_inf: float, h: float) -> Coefficients:
    return Coefficients(rho_inf, h)


def predict(st, c):
    """Generalized-α predictor with a constant acceleration v̇_{n+1} = v̇_n: (q, v, v̇, a),
    rows (views) of one (4, n) array."""
    return c.P @ np.array([st.q, st.v, st.vd, st.a])


def resized(st, h: float):
    """``st`` as the start of a step of ``h`` (s) after the step of ``st.h`` that made its a.

    The variable a lags v̇: a_n = v̇(t_n + (α_m − α_f) h_{n−1}) + O(h²) (Arnold & Brüls,
    Multibody Syst. Dyn. 2007), so a_n − v̇_n ≈ (α_m − α_f) h_{n−1} v̈ belongs to the last
    step's size. A step of another size h takes a_n = v̇_n + (h/h_{n−1})(a_n − v̇_n), the a of
    a step of h, and the contacts' shares of a (``SmoothForces.in_a``) likewise; carried
    unscaled, the last step of the off-pole ball on the slab, cut to 0.56 h to land on
    t_end, made 1.0e-4 J (of 2.2 J), and 0 J so (docs/explanation/energy_ledger.md). A state
    whose a was not made by a step (``st.h`` = 0) or was made by one of ``h`` is returned
    as it is: runs whose steps are all of one size are unchanged to the bit."""
    if st.h <= 0.0 or h == st.h:
        return st
    r = h / st.h
    out = copy.copy(st)  # (shallow: the ledger's deferred record of st is not made)
    out.a = st.vd + r * (st.a - st.vd)
    if st.smooth is not None:
        s = st.smooth
        out.smooth = dataclasses.replace(s, in_a=s.in_vd + r * (s.in_a - s.in_vd))
    return out
