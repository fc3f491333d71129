"""Closed-form answers of rigid multibody motion that ``explore_multibody.py`` compares with.

Torque-free bodies (Landau & Lifshitz, Mechanics §§33, 37), the heavy symmetric top
(Goldstein, Classical Mechanics §5.7), a ball sliding then rolling on a plane, and the
frictionless impact of a free rigid bar on a fixed point.
"""

from __future__ import annotations

import numpy as np
from scipy.special import ellipk


def flip_half_period(J, W0) -> float:
    """Half period 2K(k)/λ of Ω₂ (an sn) of the torque-free body of principal moments
    J₁ < J₂ < J₃ started at body angular velocity ``W0``: the time between two flips about
    the intermediate axis, on either side of the separatrix L² = 2E J₂."""
    J, W0 = np.asarray(J, dtype=float), np.asarray(W0, dtype=float)
    J1, J2, J3 = J
    E2, L2 = float(W0 @ (J * W0)), float(np.sum((J * W0) ** 2))
    if L2 > E2 * J2:  # about the major axis
        lam = np.sqrt((J3 - J2) * (L2 - E2 * J1) / (J1 * J2 * J3))
        k2 = (J2 - J1) * (E2 * J3 - L2) / ((J3 - J2) * (L2 - E2 * J1))
    else:  # about the minor axis: the roles of J₁ and J₃ swapped
        lam = np.sqrt((J2 - J1) * (E2 * J3 - L2) / (J1 * J2 * J3))
        k2 = (J3 - J2) * (L2 - E2 * J1) / ((J2 - J1) * (E2 * J3 - L2))
    return 2.0 * float(ellipk(k2)) / lam


def symmetric_omega(A: float, C: float, W0, t: float) -> np.ndarray:
    """Body angular velocity at ``t`` of a torque-free symmetric body (J = (A, A, C)): the
    transverse part turns about the axis at ν = (C − A)Ω₃/A (Euler's precession)."""
    w1, w2, w3 = W0
    nu = (C - A) * w3 / A
    c, s = np.cos(nu * t), np.sin(nu * t)
    return np.array([c * w1 - s * w2, s * w1 + c * w2, w3])


def steady_precession(A_O: float, C: float, mgl: float, theta: float, w3: float) -> float:
    """The slow steady precession rate φ̇ of a top tilted by ``theta`` with axial angular
    velocity ``w3``: the root of A_O cos θ φ̇² − C ω₃ φ̇ + m g ℓ = 0 nearer zero."""
    a, b = A_O * np.cos(theta), C * w3
    if abs(a) < 1e-14 * b:
        return mgl / b
    return float((b - np.sqrt(b * b - 4.0 * a * mgl)) / (2.0 * a))


def top_nutation_bound(A_O: float, C: float, mgl: float, tilt: float, spin: float) -> float:
    """The largest tilt θ of a top released at ``tilt`` (θ̇ = φ̇ = 0) spinning at ``spin``.

    The cubic f(u) = (1 − u²)b(u₀ − u) − β²(u₀ − u)² (b = 2mgℓ/A_O, β = Cω₃/A_O) has the root
    u₀; the bottom of the nutation is the lower root u₁ of b(1 − u²) − β²(u₀ − u), taken as
    1 − u₁ without cancellation for a top released near upright: above the sleeping threshold
    (s = β² − 2b > 0) the nutation stays within a multiple of the release tilt."""
    b, beta2 = 2.0 * mgl / A_O, (C * spin / A_O) ** 2
    s, w0 = beta2 - 2.0 * b, 2.0 * np.sin(0.5 * tilt) ** 2  # w0 = 1 − u₀
    D = np.sqrt(s * s + 4.0 * b * beta2 * w0)
    w1 = 2.0 * beta2 * w0 / (s + D) if s > 0.0 else (D - s) / (2.0 * b)  # 1 − u₁
    return float(np.pi if w1 >= 2.0 else 2.0 * np.arcsin(np.sqrt(0.5 * w1)))


def rolling_ball(v0, w0, radius: float, mu: float, g: float):
    """A solid ball launched on the plane z = 0 with centre velocity ``v0`` and angular
    velocity ``w0`` (both in space): slip s₀ = v₀ + ω₀ × (−R e_z) falls along its own
    direction at 7μg/2, so it rolls from t* = 2|s₀|/(7μg) at v = v₀ − (2/7)s₀."""
    v0, w0 = np.asarray(v0, dtype=float), np.asarray(w0, dtype=float)
    s0 = v0 + np.cross(w0, [0.0, 0.0, -radius])
    return 2.0 * np.linalg.norm(s0) / (7.0 * mu * g), v0 - 2.0 / 7.0 * s0


def bar_impact(mass: float, inertia: float, d: float, v: float, e: float):
    """A free rigid bar falling flat at ``v`` struck frictionlessly at ``d`` from its centre
    (Newton's law, e_N = ``e``): the impulse P = (1 + e)v/(1/m + d²/I), the centre's
    velocity −v + P/m and the rate of turn P d/I after it."""
    P = (1.0 + e) * v / (1.0 / mass + d * d / inertia)
    return P, -v + P / mass, P * d / inertia


def stuck_impact(mass: float, J, r, u, e: float):
    """A free rigid body (``mass``, spatial inertia ``J`` about its centre) struck at ``r``
    from its centre, the point moving at ``u``, on a plane of normal e_z: the impulse P that
    gives Newton's law, u_N+ = −e u_N, with the point stuck along the plane, u_T+ = 0,
    P = D⁻¹(u+ − u) with D = I/m − [r]× J⁻¹ [r]×. Coulomb's law holds it where
    |P_T| ≤ μ P_N."""
    r, u = np.asarray(r, float), np.asarray(u, float)
    cross = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
    D = np.eye(3) / mass - cross @ np.linalg.solve(J, cross)
    return np.linalg.solve(D, np.array([0.0, 0.0, -e * u[2]]) - u)
