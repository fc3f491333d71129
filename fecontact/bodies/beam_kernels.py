r"""Kernels of the planar Simo–Reissner beam of :class:`~fecontact.bodies.beam.Beam2D`:
linear elements with the one-point rule, vectorised over the elements.

P1 with the one-point rule: N_a = ½ and N_a' = ±1/ℓ_e at the midpoint. The strain gradients
are then combinations of four constant element vectors

    e1 = (−1, 0, 0, 1, 0, 0)/ℓ,  e2 = (0, −1, 0, 0, 1, 0)/ℓ,
    e3 = (0, 0, ½, 0, 0, ½),      e4 = (0, 0, −1, 0, 0, 1)/ℓ:

    ∂Γ = c e1 + s e2 + γ e3,  ∂γ = −s e1 + c e2 − (1 + Γ) e3,  ∂κ = e4,

and so are the internal force f_e = ℓ (N ∂Γ + V ∂γ + M ∂κ) and the tangent (with the
products e_i ⊗ e_j), N = EA Γ, V = GA_s γ, M = EI κ.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BeamElements", "beam_internal", "beam_strains"]


@dataclass(frozen=True)
class BeamElements:
    """Per-element data of a beam, computed once: end nodes ``n0``, ``n1``, ``dofs`` (E, 6),
    ``chord`` (E, 2) and length ``ell`` (m), reference angle ``phi0`` (rad), the rigidities
    ``C`` = (EA, GA_s, EI), the vectors ``e`` (E, 4, 6) and their products ``P`` (E, 7, 6, 6):
    e1e1, e2e2, e3e3, sym(e1e2), sym(e1e3), sym(e2e3), e4e4."""

    n0: np.ndarray
    n1: np.ndarray
    dofs: np.ndarray
    chord: np.ndarray
    ell: np.ndarray
    phi0: np.ndarray
    C: np.ndarray
    e: np.ndarray
    P: np.ndarray

    @classmethod
    def of(cls, X: np.ndarray, connectivity: np.ndarray, rigidities) -> BeamElements:
        """From the node coordinates X (n, 2), the elements' nodes (2, E) and (EA, GA_s, EI)."""
        n0, n1 = connectivity
        chord = X[n1] - X[n0]
        ell = np.linalg.norm(chord, axis=1)  # ∫ J dξ over the element: its length
        inv = 1.0 / ell[:, None]
        e = np.zeros((len(chord), 4, 6))
        e[:, 0, [0, 3]] = [-1.0, 1.0] * inv
        e[:, 1, [1, 4]] = [-1.0, 1.0] * inv
        e[:, 2, [2, 5]] = 0.5
        e[:, 3, [2, 5]] = [-1.0, 1.0] * inv
        pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2), (3, 3)]
        P = np.stack([np.einsum("ei,ej->eij", e[:, i], e[:, j]) for i, j in pairs], axis=1)
        P[:, 3:6] += P[:, 3:6].transpose(0, 1, 3, 2)
        return cls(
            n0=n0,
            n1=n1,
            dofs=(3 * connectivity.T[:, :, None] + np.arange(3)).reshape(len(chord), -1),
            chord=chord,
            ell=ell,
            phi0=np.arctan2(chord[:, 1], chord[:, 0]),
            C=np.asarray(rigidities, dtype=float),
            e=e,
            P=P,
        )


def beam_strains(el: BeamElements, q: np.ndarray):
    """Axial Γ, shear γ and curvature κ (1/m) at the midpoints, with cos φ and sin φ."""
    U = q.reshape(-1, 3)
    Ua, Ub = U[el.n0], U[el.n1]
    inv = 1.0 / el.ell
    ax = (el.chord[:, 0] + Ub[:, 0] - Ua[:, 0]) * inv
    ay = (el.chord[:, 1] + Ub[:, 1] - Ua[:, 1]) * inv
    phi = el.phi0 + 0.5 * (Ua[:, 2] + Ub[:, 2])
    c, s = np.cos(phi), np.sin(phi)
    Gam = ax * c + ay * s - 1.0
    gam = ay * c - ax * s
    kap = (Ub[:, 2] - Ua[:, 2]) * inv
    return Gam, gam, kap, c, s


def beam_internal(el: BeamElements, q: np.ndarray, ndof: int, tangent: bool):
    """Strain energy W (J), internal force ∂W/∂q (N, N·m) and element tangents (E, 6, 6)."""
    Gam, gam, kap, c, s = beam_strains(el, q)
    (EA, GA, EI), w = el.C, el.ell
    N, V, Mb = EA * Gam, GA * gam, EI * kap  # axial force, shear force, bending moment
    g1 = 1.0 + Gam
    W = 0.5 * float(w @ (N * Gam + V * gam + Mb * kap))
    # f_e = w (N ∂Γ + V ∂γ + M ∂κ)
    # (columns written into one array: np.stack costs more than the products on a beam of
    # tens of elements, and the layout, hence every sum below, is the same)
    coef = np.empty((w.size, 4))
    coef[:, 0] = N * c - V * s
    coef[:, 1] = N * s + V * c
    coef[:, 2] = N * gam - V * g1
    coef[:, 3] = Mb
    f_e = np.einsum("ek,eki->ei", w[:, None] * coef, el.e)
    f = np.bincount(el.dofs.ravel(), f_e.ravel(), minlength=ndof)
    if not tangent:
        return W, f, None
    # K_e = w (EA ∂Γ⊗∂Γ + GA ∂γ⊗∂γ + EI ∂κ⊗∂κ + N ∂²Γ + V ∂²γ); the second derivatives
    # couple translations and rotations (sym(e1e3), sym(e2e3)) and the rotations (e3e3)
    cs = c * s
    K = np.empty((w.size, 7))
    K[:, 0] = EA * c * c + GA * s * s
    K[:, 1] = EA * s * s + GA * c * c
    K[:, 2] = EA * gam * gam + GA * g1 * g1 - N * g1 - V * gam
    K[:, 3] = (EA - GA) * cs
    K[:, 4] = EA * c * gam + GA * s * g1 - N * s - V * c
    K[:, 5] = EA * s * gam - GA * c * g1 + N * c - V * s
    K[:, 6] = EI
    K_e = np.einsum("ek,ekij->eij", w[:, None] * K, el.P)
    return W, f, K_e
