r"""The energy-decaying smooth step (``scheme="energy-decaying"``): step 1 of the NSGA for
geometrically exact beams, where generalized-α can pump energy into the stiff modes an impact
leaves ringing (docs/explanation/stability.md).

A midpoint step with the discrete gradient of the strain energy, made dissipative by second
differences of the strains and of the velocities (in the spirit of Armero & Romero's
energy-dissipative schemes, CMAME 2001):

    q_{n+1} − q_n = h (v_n + v_{n+1})/2 + η h (Δv_{n+1} − r Δv_n),
    M Δv_{n+1} = h [f_ext(t_n + h/2) − f̄],
    f̄ = Σ_e ℓ B̄ᵀ C [(ε_n + ε_{n+1})/2 + χ (Δε_{n+1} − r Δε_n)],

Δv_{n+1} = v_{n+1} − v_n, Δε_{n+1} = ε_{n+1} − ε_n, r = h/h_n, and B̄ Δq = Δε exactly
(:mod:`fecontact.bodies.beam_energy`). Over a step, with a constant step and load, the total
energy E = T + W + V (V: the loads' potential, gravity's included) obeys

    E_{n+1} − E_n = −(η/2)(|Δv_{n+1}|²_M − |Δv_n|²_M + |Δv_{n+1} − Δv_n|²_M)
                    − (χ/2) Σ ℓ (|Δε_{n+1}|²_C − |Δε_n|²_C + |Δε_{n+1} − Δε_n|²_C),

so H = E + (η/2)|Δv_n|²_M + (χ/2) Σ ℓ |Δε_n|²_C never grows over a smooth step, whatever the
beam's rotations and the step: the nonlinear coupling of its axial and bending modes cannot
pump energy as it does in generalized-α. For resolved motion both corrections are second
differences, O(h²): the step stays second order. On a linear oscillator the spectral radius
at infinite frequency is ρ∞ when χ = η = ρ∞(1 − ρ∞)/(2(1 + ρ∞)²) (ρ∞ ∈ [1/3, 1]; ρ∞ = 1 is
the energy-conserving midpoint step), the choice made here from ``rho_inf``.

Impacts are steps 2 and 3 of :mod:`.nsga`, with the metric of the trapezoidal rule
(ρ∞ = 1: S_t/β′ = M + h²K_t/4), and the velocity follows the strain of the correction over
half a step as in the decoupled scheme (:mod:`.position_jump`, γ = ½): without it the first
impact of the founding pendulum put 1.7 % of its kinetic energy into the strip at
h = 8e-4 s. The step keeps no acceleration variable: v̇ = Δṽ/h of the
smooth step (not the impact's jump) is reported and carries Δv_n to the next step; Δε_n of
the smooth step (not the correction's strain) travels in the state (``strain_increment``).
Newton uses the exact tangent of f̄ (complex step per element), not symmetric.
"""

from __future__ import annotations

import math
import time

from ..errors import InputError
from .constraints import StepFailure, factorize_or_fail
from .nsga import SmoothStep, decoupled_step
from .settings import run_settings, uses_smooth_contact

__all__ = ["check_energy_scheme", "energy_nsga_step"]


def check_energy_scheme(model, opts) -> None:
    """InputError, before any work, where the energy-decaying step does not apply."""
    why = None
    if opts.integrator != "nsga":
        why = f"it is a step of the nsga integrator, not of {opts.integrator!r}"
    elif not 1.0 / 3.0 <= opts.rho_inf <= 1.0:
        why = f"rho_inf must be in [1/3, 1] (its dissipation's range), got {opts.rho_inf:g}"
    elif model.dim != 2:
        why = "it is built for planar models (no gyroscopic terms in the midpoint rule)"
    elif not all(b.energy_consistent for b in model.bodies if b.element_dofs.size):
        why = (
            "every body with elements must be a geometrically exact Beam2D (the "
            "generalized-alpha step of linear bodies is unconditionally stable)"
        )
    elif model.joints.size:
        why = "joints are not supported (their multipliers live in the generalized-alpha step)"
    elif any(model.damping):
        why = "Rayleigh damping is not supported"
    elif uses_smooth_contact(model, opts):
        why = "smooth_contact must be off (the decoupled contact phase is used)"
    if why:
        raise InputError(f"scheme = 'energy-decaying': {why}")


def energy_nsga_step(model, st, h: float, opts, timer):
    """The NSGA step with the energy-decaying step 1; the state remembers its Δε."""
    opts = run_settings(model, opts)
    state, q_tilde = decoupled_step(model, st, h, opts, timer, energy_smooth_step)
    # the smooth step's own Δε: a correction's strain is no part of the stored energy
    state.strain_increment = model.element_strains(q_tilde) - model.element_strains(st.q)
    return state


def dissipation(rho_inf: float) -> float:
    """χ = η of the spectral radius ρ∞ ∈ [1/3, 1] at infinite frequency (module docstring)."""
    return rho_inf * (1.0 - rho_inf) / (2.0 * (1.0 + rho_inf) ** 2)


def _previous_increments(model, st, h: float):
    """r Δε_n (the smooth step's, without the correction) and r Δv_n = h v̇_n; at the start,
    from the strain rate of (q_0, v_0) and the initial acceleration."""
    de = st.strain_increment
    if de is None or not st.h:
        return model.element_strains(st.q) - model.element_strains(st.q - h * st.v), h * st.vd
    return (h / st.h) * de, h * st.vd


def energy_smooth_step(model, st, t, c, opts, timer, P=None) -> SmoothStep:
    """Step 1 by the energy-decaying midpoint rule (module docstring): Newton on
    R(q) = M Δv/h + f̄(q_n, q) − f_ext(t_n + h/2) = 0, Δv affine in q, with the exact tangent
    M/(h²(½ + η)) + ∂f̄/∂q."""
    F, h = model.free_slice, c.h
    chi = eta = dissipation(opts.rho_inf)
    d, dv = _previous_increments(model, st, h) if chi else (None, 0.0 * st.v)
    fe = 0.5 * (model.external(st.t) + model.external(t))[F]
    ff = fe @ fe
    w = 1.0 / (h * (0.5 + eta))

    def velocity_change(q):  # from q − q_n = h v_n + h(½ + η)Δv − η h rΔv_n
        return w * (q - st.q - h * st.v + eta * h * dv)

    q = st.q.copy()
    q[F] += h * st.v[F]
    clock = time.perf_counter()
    for it in range(opts.max_iterations + 1):  # noqa: B007 (the count is returned)
        f, K = model.algorithmic_force(st.q, q, chi, d)
        Mvd = model.M @ velocity_change(q)[F] / h
        r = Mvd + f[F] - fe
        clock = timer.add("assembly", clock)
        ref = math.sqrt(max(ff, f[F] @ f[F], Mvd @ Mvd, 1e-300))
        rnorm = math.sqrt(r @ r)
        if not math.isfinite(rnorm):
            raise StepFailure("energy-decaying smooth step diverged", rnorm)
        if rnorm <= opts.tol_residual * ref:
            break
        if it == opts.max_iterations:
            raise StepFailure("energy-decaying smooth step", rnorm / ref)
        opts.stats.newton.iterations += 1
        dq = -factorize_or_fail(model.iteration_sum(w / h, K), rnorm / ref, False, model.solver)(r)
        q[F] += dq
        clock = timer.add("solve", clock)
        if model.update_size(dq) <= opts.tol_increment:  # round-off bounds the residual
            it += 1
            break
    vd = velocity_change(q) / h
    return SmoothStep(q, st.v + h * vd, vd, vd.copy(), st.lam, None, it, None, None, None, 0.0)
