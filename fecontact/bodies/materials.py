r"""Isotropic hyperelastic materials for :class:`fecontact.Solid`.

Notation (total Lagrangian, e.g. Bonet & Wood, *Nonlinear Continuum Mechanics for FEA*):

=====  =========================================================================================
F      deformation gradient I + ∇u (∇ with respect to the reference coordinates X)
C      right Cauchy–Green tensor FᵀF;  J = det F;  I₁ = tr C
E      Green–Lagrange strain ½(C − I); for the linear material the small strain ε = sym ∇u
W      strain energy per unit reference volume, J/m³
S      second Piola–Kirchhoff stress ∂W/∂E, Pa (tension positive)
P      first Piola–Kirchhoff stress F S, Pa
ℂ      material tangent ∂S/∂E, Pa, with the major and both minor symmetries
λ, μ   Lamé constants: λ = Y ν/((1 + ν)(1 − 2ν)), μ = Y/(2(1 + ν)) from Young's modulus Y
       (the attribute ``E`` of the material) and Poisson's ratio ν
=====  =========================================================================================

Energies (d = 3; the plane cases below reduce them):

* :class:`LinearElastic`: W = λ/2 (tr ε)² + μ ε:ε, S = σ = λ tr ε I + 2μ ε. The body uses the
  small strain ε, so its stiffness is constant.
* :class:`StVenantKirchhoff`: the same function of the Green–Lagrange strain,
  W = λ/2 (tr E)² + μ E:E, S = λ tr E I + 2μ E, ℂ = λ I⊗I + 2μ 𝕀. Frame invariant, but it
  softens and fails in strong compression.
* :class:`NeoHookean` (compressible, the Ciarlet–Simo form):
  W = μ/2 (I₁ − 3 − 2 ln J) + λ/2 (ln J)²,  S = μ(I − C⁻¹) + λ ln J C⁻¹,
  ℂ = λ C⁻¹⊗C⁻¹ + 2(μ − λ ln J) 𝕀_{C⁻¹} with (𝕀_{C⁻¹})_IJKL = ½(C⁻¹_IK C⁻¹_JL + C⁻¹_IL C⁻¹_JK).
  Matches the linear material for small strains; W → ∞ as J → 0⁺.

Arrays follow scikit-fem's layout: tensor indices first, points last, E of shape
(3, 3, *points), S (3, 3, *points), ℂ (3, 3, 3, 3, *points) — with the points innermost,
every operation runs over long contiguous vectors.

Plane problems work on the in-plane block of E. Plane strain: E₃₃ = E₁₃ = E₂₃ = 0.
Plane stress: E₃₃ solves S₃₃(E) = 0 (one Newton step for the linear material and St Venant–
Kirchhoff, where it is linear in E₃₃ and gives λ* = 2λμ/(λ + 2μ); a few for Neo-Hookean), and
the tangent is condensed, ℂ_abcd − ℂ_ab33 ℂ_33cd / ℂ_3333, which is exact since ∂W/∂E₃₃ = 0
there. W is then the energy per unit reference volume of the plate, thickness carried by the
body.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
from skfem.helpers import det, inv

from ..errors import check_positive, check_range

__all__ = ["LinearElastic", "StVenantKirchhoff", "NeoHookean", "PLANES", "SolidMaterial"]

PLANES = ("strain", "stress")

_I3 = np.eye(3)
# symmetric fourth-order identity 𝕀_IJKL = ½(δ_IK δ_JL + δ_IL δ_JK) and I⊗I
_SYM4 = 0.5 * (np.einsum("ik,jl->ijkl", _I3, _I3) + np.einsum("il,jk->ijkl", _I3, _I3))
_OUTER = np.einsum("ij,kl->ijkl", _I3, _I3)


@runtime_checkable
class SolidMaterial(Protocol):
    """What a ``Solid`` asks of its material: density, whether the stiffness is constant, and
    the stress response S(E) (with its tangent) in the total Lagrangian form."""

    E: float  # Young's modulus (Pa): the scale of the stresses a strain makes
    rho: float
    linear: bool

    def response(self, E: np.ndarray, plane: str | None = None, tangent: bool = True): ...


@dataclass(frozen=True)
class _Isotropic:
    """Young's modulus ``E`` (Pa, > 0), Poisson's ratio ``nu`` in (−1, 0.5) and density ``rho``
    (kg/m³, > 0)."""

    E: float
    nu: float
    rho: float

    linear = False
    """True when the body uses small strains (constant stiffness)."""
    barrier = False
    """True when W is infinite for det F <= 0 (the body then reports an infinite energy)."""

    def __post_init__(self):
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_range("nu", self.nu, -1.0, 0.5, (False, False)))
        object.__setattr__(self, "rho", check_positive("rho", self.rho))

    @property
    def lame(self) -> tuple[float, float]:
        """Lamé constants (λ, μ) in Pa (three-dimensional)."""
        lam = self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))
        return lam, self.E / (2.0 * (1.0 + self.nu))

    @property
    def wave_speed(self) -> float:
        """Dilatational (P-wave) speed √((λ + 2μ)/ρ) in m/s, the fastest wave of the material."""
        lam, mu = self.lame
        return float(np.sqrt((lam + 2.0 * mu) / self.rho))

    def response3(self, E: np.ndarray, tangent: bool = True, dims: int = 3):
        """W (*points) in J/m³, S (3, 3, *points) in Pa and ℂ (dims, dims, dims, dims,
        *points) in Pa at Green–Lagrange strains E (3, 3, *points): ℂ's block of the first
        ``dims`` axes (2: the in-plane block plane strain reads). ℂ is None unless
        ``tangent``; a constant ℂ comes with singleton point axes."""
        raise NotImplementedError

    def response(self, E: np.ndarray, plane: str | None = None, tangent: bool = True):
        """W, S, ℂ at strains E (d, d, *points): ``plane`` is None in 3D, "strain" or "stress"
        in 2D. S and ℂ have the dimension d of E."""
        if plane is None:
            return self.response3(E, tangent)
        E3 = self._embed(E, plane)
        # (plane strain reads ℂ's in-plane block alone; plane stress also its E₃₃ entries)
        W, S, CC = self.response3(E3, tangent, 2 if plane == "strain" else 3)
        if not tangent:
            return W, S[:2, :2], None
        CC2 = CC[:2, :2, :2, :2]
        if plane == "stress":
            CC2 = CC2 - CC[:2, :2, 2, 2][:, :, None, None] * CC[2, 2, :2, :2] / CC[2, 2, 2, 2]
        return W, S[:2, :2], CC2

    def out_of_plane(self, E: np.ndarray, plane: str):
        """E₃₃ and S₃₃ (Pa) for in-plane strains E (2, 2, *points): S₃₃ = 0 in plane stress,
        E₃₃ = 0 in plane strain."""
        E3 = self._embed(E, plane)
        return E3[2, 2], self.response3(E3, tangent=False)[1][2, 2]

    def normal33(self, E3: np.ndarray):
        """S₃₃ (Pa) and ℂ₃₃₃₃ (Pa) at strains E3 (3, 3, *points): the residual and slope of
        the plane-stress condition S₃₃ = 0. A material may give them without its whole ℂ."""
        _, S, CC = self.response3(E3, tangent=True)
        return S[2, 2], CC[2, 2, 2, 2]

    def _embed(self, E, plane):
        E3 = np.zeros((3, 3) + E.shape[2:])
        E3[:2, :2] = E
        if plane == "strain":
            return E3
        # Newton on S₃₃(E₃₃) = 0; S₃₃ increases with E₃₃ (ℂ₃₃₃₃ > 0), so it converges from 0
        tol = self.E * 1e-13
        for _ in range(50):
            r, slope = self.normal33(E3)
            if np.all(np.abs(r) <= tol):
                return E3
            step = -r / slope
            # keep C₃₃ = 1 + 2E₃₃ positive (the Neo-Hookean energy is infinite at C₃₃ = 0)
            E3[2, 2] += np.maximum(step, -0.45 * (1.0 + 2.0 * E3[2, 2]))
        return E3


class LinearElastic(_Isotropic):
    """Linear elastic (Hooke) material for small strains: S = σ = λ tr ε I + 2μ ε.

    A :class:`~fecontact.Solid` of this material uses ε = sym ∇u and has a constant stiffness
    (``Solid.linear`` is True). Not frame invariant: large rotations create spurious stress.
    """

    linear = True

    def response3(self, E, tangent=True, dims=3):
        return _quadratic(self.lame, E, tangent, dims)


class StVenantKirchhoff(_Isotropic):
    """St Venant–Kirchhoff: W = λ/2 (tr E)² + μ E:E in the Green–Lagrange strain E.

    Exact under large rotations; use for moderate strains (it softens in strong compression).
    """

    def response3(self, E, tangent=True, dims=3):
        return _quadratic(self.lame, E, tangent, dims)


class NeoHookean(_Isotropic):
    """Compressible Neo-Hookean: W = μ/2 (I₁ − 3 − 2 ln J) + λ/2 (ln J)² (J/m³).

    S = μ(I − C⁻¹) + λ ln J C⁻¹. Reduces to the linear material for small strains. J is taken
    as √(det C) here; a body with an inverted element (det F ≤ 0) has infinite energy.
    """

    barrier = True

    def _inverse(self, E):
        """C⁻¹ and ln J at E (C = 2E + I, J = √det C)."""
        C = 2.0 * E
        for i in range(3):
            C[i, i] += 1.0
        with np.errstate(invalid="ignore", divide="ignore"):
            detC, Ci = det(C), inv(C)
            lnJ = 0.5 * np.log(detC)
        return C, Ci, lnJ

    def normal33(self, E3):
        # the entries of response3's S and ℂ, in its order of operations (the same numbers)
        lam, mu = self.lame
        _, Ci, lnJ = self._inverse(E3)
        c = Ci[2, 2]
        p = c * c
        return (lam * lnJ - mu) * c + mu, (p + p) * (mu - lam * lnJ) + lam * c * c

    def response3(self, E, tangent=True, dims=3):
        lam, mu = self.lame
        C, Ci, lnJ = self._inverse(E)
        W = 0.5 * mu * (C[0, 0] + C[1, 1] + C[2, 2] - 3.0 - 2.0 * lnJ) + 0.5 * lam * lnJ**2
        S = (lam * lnJ - mu) * Ci
        for i in range(3):
            S[i, i] += mu
        if not tangent:
            return W, S, None
        Ci = Ci[:dims, :dims]
        P = Ci[:, None, :, None] * Ci[None, :, None, :]  # C⁻¹_IK C⁻¹_JL
        CC = P + P.swapaxes(2, 3)
        CC *= mu - lam * lnJ
        CC += lam * Ci[:, :, None, None] * Ci[None, None]
        return W, S, CC


def _quadratic(lame, E, tangent, dims=3):
    """W = λ/2 (tr E)² + μ E:E, its stress and (constant) tangent."""
    lam, mu = lame
    trE = E[0, 0] + E[1, 1] + E[2, 2]
    S = 2.0 * mu * E
    for i in range(3):
        S[i, i] += lam * trE
    W = 0.5 * lam * trE**2 + mu * np.sum(E * E, axis=(0, 1))
    if not tangent:
        return W, S, None
    CC = (lam * _OUTER + 2.0 * mu * _SYM4).reshape((3, 3, 3, 3) + (1,) * (E.ndim - 2))
    return W, S, CC[:dims, :dims, :dims, :dims]
