r"""Discrete gradient of the planar beam's strain energy, for the energy-decaying smooth step
(:mod:`fecontact.time.energy_step`); the element vectors e1…e4 of :mod:`.beam_kernels`.

From q₀ to q₁ the strains ε = (Γ, γ, κ) of an element change by exactly ε₁ − ε₀ = B̄ (q₁ − q₀)
(Gonzalez's discrete gradient, made explicit for these strains), with

    B̄_Γ = t̄ₓ e1 + t̄_y e2 + σ ā·n(φ̄) e3,
    B̄_γ = n̄ₓ e1 + n̄_y e2 − σ ā·t(φ̄) e3,     σ = sin(Δφ/2)/(Δφ/2),
    B̄_κ = e4,

where a is the axis' stretch vector (Γ = a·t − 1, γ = a·n), t = (cos φ, sin φ) and
n = (−sin φ, cos φ), ā, t̄, n̄ the means of the end values and φ̄ the mean angle: the exact
identity t(φ₁) − t(φ₀) = σ Δφ n(φ̄) makes B̄ exact at any rotation. The algorithmic force is

    f = Σ_e ℓ B̄ᵀ S,   S = C[(ε₀ + ε₁)/2 + χ(ε₁ − ε₀ − d)],

so that f·(q₁ − q₀) = W(q₁) − W(q₀) + χ Σ_e ℓ Δε·C(Δε − d), Δε = ε₁ − ε₀: the strain energy's
change plus the work of the dissipative stress χC(Δε − d) (d: the previous step's Δε, scaled
to this step). Its tangent ∂f/∂q₁ is taken by complex step, exact to round-off.
"""

from __future__ import annotations

import numpy as np

from .beam_kernels import BeamElements

__all__ = ["beam_energy_force", "element_strains"]

STEP = 1e-30  # the complex step: far below round-off, no cancellation in Im f


def _local(el: BeamElements, q: np.ndarray) -> np.ndarray:
    """The elements' dofs (E, 6): (u_x, u_y, θ) of the first node, then of the second."""
    U = q.reshape(-1, 3)
    return np.concatenate([U[el.n0], U[el.n1]], axis=1)


def _axis(el: BeamElements, U: np.ndarray):
    """Stretch vector a (..., E, 2), angle φ (rad) and curvature κ (1/m) of each element of
    the element dofs U (..., E, 6)."""
    inv = 1.0 / el.ell
    a = (el.chord + U[..., 3:5] - U[..., 0:2]) * inv[:, None]
    return a, el.phi0 + 0.5 * (U[..., 2] + U[..., 5]), (U[..., 5] - U[..., 2]) * inv


def _strains(a, phi, kappa) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    gam = a[..., 0] * c + a[..., 1] * s - 1.0
    return np.stack([gam, a[..., 1] * c - a[..., 0] * s, kappa], axis=-1)


def element_strains(el: BeamElements, q: np.ndarray) -> np.ndarray:
    """(Γ, γ, κ) of every element (E, 3)."""
    return _strains(*_axis(el, _local(el, q)))


def _force(el: BeamElements, U0, U1, chi: float, d) -> np.ndarray:
    """Element forces (..., E, 6) of the element dofs U1 (..., E, 6) from U0 (E, 6)."""
    a0, p0, k0 = _axis(el, U0)
    a1, p1, k1 = _axis(el, U1)
    e0, e1 = _strains(a0, p0, k0), _strains(a1, p1, k1)
    S = el.C * (0.5 * (e0 + e1) + chi * (e1 - e0 - d))
    N, V, M = S[..., 0], S[..., 1], S[..., 2]
    am, pm = 0.5 * (a0 + a1), 0.5 * (p0 + p1)
    sigma = np.sinc((p1 - p0) / (2.0 * np.pi))  # numpy's sinc is sin(πx)/(πx)
    cb, sb = 0.5 * (np.cos(p0) + np.cos(p1)), 0.5 * (np.sin(p0) + np.sin(p1))
    an = am[..., 1] * np.cos(pm) - am[..., 0] * np.sin(pm)  # ā·n(φ̄)
    at = am[..., 0] * np.cos(pm) + am[..., 1] * np.sin(pm)  # ā·t(φ̄)
    coef = np.stack([N * cb - V * sb, N * sb + V * cb, sigma * (N * an - V * at), M], axis=-1)
    return np.einsum("...ek,eki->...ei", el.ell[:, None] * coef, el.e)


def beam_energy_force(el: BeamElements, q0, q1, chi: float, d, ndof: int, tangent=True):
    """The algorithmic force f(q₀, q₁) (N, N·m; module docstring) on the beam's ``ndof`` dofs
    and its element tangents ∂f_e/∂q₁ (E, 6, 6), not symmetric; ``d`` (E, 3) or 0."""
    U0, U1 = _local(el, q0), _local(el, q1)
    if not tangent:
        f_e = _force(el, U0, U1, chi, d)
        return np.bincount(el.dofs.ravel(), f_e.ravel(), minlength=ndof), None
    # one evaluation for the force (real part of slot 0) and the six complex steps
    Uc = np.repeat(U1[None].astype(complex), 7, axis=0)
    Uc[1:] += 1j * STEP * np.eye(6)[:, None, :]
    f_c = _force(el, U0, Uc, chi, d)
    f = np.bincount(el.dofs.ravel(), f_c[0].real.ravel(), minlength=ndof)
    return f, np.moveaxis(f_c[1:].imag / STEP, 0, -1)
