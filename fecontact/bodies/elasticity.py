r"""Kernels of the total Lagrangian elasticity of :class:`~fecontact.bodies.solid.Solid`,
vectorised over all elements and quadrature points.

With the shape functions N_a and their reference gradients ∇N_a, H = Σ_a u_a ⊗ ∇N_a,
F = I + H, E = ½(FᵀF − I) (the linear material: ε = sym H), P = F S, and

    f_ai = ∫ P_iJ ∂_J N_a dV,    K_aibk = ∫ ∂_J N_a A_iJkL ∂_L N_b dV,
    A_iJkL = F_iI ℂ_IJKL F_kK + δ_ik S_JL.

Arrays keep scikit-fem's layout, points last and elements innermost: ∇N_a as (n_loc, d, Q, E),
dV as (Q, E), tensors as (d, d, Q, E).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from skfem.helpers import det

__all__ = [
    "Quadrature",
    "cauchy_stress",
    "cell_invariants",
    "deformation",
    "displacement_gradient",
    "element_tangent",
    "internal_force",
]


@dataclass(frozen=True)
class Quadrature:
    """Basis data of a mesh, computed once: ``grad`` ∇N_a (n_loc, d, Q, E), ``dV`` weights
    times |det ∂x/∂ξ| (times the thickness in 2D) (Q, E), ``nodes`` of each element
    (E, n_loc) and their ``dofs`` (E, n_loc·d), dof = d·node + component."""

    grad: np.ndarray
    dV: np.ndarray
    nodes: np.ndarray
    dofs: np.ndarray

    @classmethod
    def of(cls, basis, thickness: float) -> Quadrature:
        grads = np.stack([phi[0].grad for phi in basis.basis])
        nodes = np.ascontiguousarray(basis.element_dofs.T)
        d = basis.mesh.dim()
        return cls(
            grad=np.ascontiguousarray(grads.swapaxes(-1, -2)),
            dV=np.ascontiguousarray(basis.dx.T) * thickness,
            nodes=nodes,
            dofs=(d * nodes[:, :, None] + np.arange(d)).reshape(len(nodes), -1),
        )

    @cached_property
    def weighted_grad(self) -> np.ndarray:
        """∇N_a dV element-major, (E, n_loc, Q·d), as :func:`element_tangent`'s batched
        product reads it: fixed with the reference mesh, so made on first use."""
        G = self.grad * self.dV
        return np.ascontiguousarray(G.transpose(3, 0, 2, 1)).reshape(G.shape[-1], len(G), -1)

    @property
    def dim(self) -> int:
        return self.grad.shape[1]


def displacement_gradient(quad: Quadrature, q: np.ndarray) -> np.ndarray:
    """H = ∇u (d, d, Q, E) of the dof vector q."""
    Ue = np.asarray(q, dtype=float).reshape(-1, quad.dim).T[:, quad.nodes.T]
    return np.einsum("iae,ajqe->ijqe", Ue, quad.grad)


def deformation(H: np.ndarray, linear: bool):
    """F = I + H (None for the linear material) and the strain: E = ½(H + Hᵀ + HᵀH), or
    ε = ½(H + Hᵀ) when ``linear``."""
    Ht = H.swapaxes(0, 1)
    if linear:
        return None, 0.5 * (H + Ht)
    F = H.copy()
    for i in range(len(H)):
        F[i, i] += 1.0
    return F, 0.5 * (H + Ht + np.einsum("kiqe,kjqe->ijqe", H, H))


def internal_force(quad: Quadrature, F: np.ndarray, S: np.ndarray, ndof: int) -> np.ndarray:
    """f_ai = ∫ (F S)_iJ ∂_J N_a dV, assembled (N, (ndof,))."""
    P = np.einsum("iIqe,IJqe->iJqe", F, S)
    fe = np.einsum("qe,iJqe,aJqe->eai", quad.dV, P, quad.grad)
    return np.bincount(quad.dofs.ravel(), fe.ravel(), minlength=ndof)


def element_tangent(quad: Quadrature, F, CC: np.ndarray, S) -> np.ndarray:
    """K_e (E, n_loc·d, n_loc·d) from A_iJkL = F_iI ℂ_IJKL F_kK + δ_ik S_JL (F = I when None,
    no S term when None)."""
    G, dV = quad.grad, quad.dV
    if F is None:
        A = np.broadcast_to(CC, CC.shape[:4] + dV.shape)
    else:
        FC = np.einsum("iI...,IJKL...->iJKL...", F, CC)
        A = np.einsum("iJKL...,kK...->iJkL...", FC, F)
    if S is not None:
        for i in range(quad.dim):
            A[i, :, i] += S
    AG = np.einsum("iJkL...,bL...->Jibk...", A, G)  # (J, i, b, k, Q, E)
    # element-major from here: one batched matmul per element, contracting over the
    # quadrature points and J together, writes K_e contiguous as Pattern reads it
    n_el, n = G.shape[-1], quad.dofs.shape[1]
    AG = np.ascontiguousarray(AG.transpose(5, 4, 0, 1, 2, 3)).reshape(n_el, -1, n * quad.dim)
    return np.matmul(quad.weighted_grad, AG).reshape(n_el, n, n)


def cauchy_stress(material, plane, F, E: np.ndarray) -> np.ndarray:
    """Cauchy stress σ = F S Fᵀ / det F (Pa, (3, 3, Q, E)); the linear material (F None)
    gives σ = S. In 2D the out-of-plane strain comes from the material's ``plane``."""
    d = len(E)
    E3 = np.zeros((3, 3) + E.shape[2:])
    E3[:d, :d] = E
    F3 = np.zeros_like(E3)
    for i in range(3):
        F3[i, i] = 1.0
    if d == 2:
        E3[2, 2] = material.out_of_plane(E, plane)[0]
        F3[2, 2] = np.sqrt(1.0 + 2.0 * E3[2, 2])
    S = material.response3(E3, tangent=False)[1]
    if F is None:
        return S
    F3[:d, :d] = F
    return np.einsum("iIqe,IJqe,jJqe->ijqe", F3, S, F3) / det(F3)


def cell_invariants(sigma: np.ndarray, dV: np.ndarray) -> dict[str, np.ndarray]:
    """Cell averages of the von Mises stress √(3/2 s:s), s the deviator of σ, and of the
    pressure −tr σ/3 (both Pa), from σ (3, 3, Q, E) and the volume weights dV (Q, E)."""
    p = -(sigma[0, 0] + sigma[1, 1] + sigma[2, 2]) / 3.0
    s = sigma.copy()
    for i in range(3):
        s[i, i] += p
    vm = np.sqrt(1.5 * np.sum(s * s, axis=(0, 1)))
    w = dV / dV.sum(axis=0)
    return {"stress_von_mises": np.sum(w * vm, axis=0), "pressure": np.sum(w * p, axis=0)}
