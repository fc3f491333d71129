r"""Inertia of the spatial beam :class:`~fecontact.bodies.beam3d.Beam3D`: its constant
consistent mass matrix and the gyroscopic force of its nodes' rotations.

The kinetic energy of the rotations is T = ½ Σ_ab Ω_a · M_ab Ω_b, the angular velocities Ω_a
of the nodes (frame R) and M_ab the blocks of the constant rotational mass (the P1 mass of the
elements' ρJ plus the point inertias). With T independent of the rotations, the
Euler–Poincaré equations of the nodes (Simo & Vu-Quoc, Comput. Methods Appl. Mech. Eng. 1988,
for the rotational inertia in the material frame) are

    (M Ω̇)_a + Ω_a × π_a = moments on node a,      π = M Ω,

so the gyroscopic force consistent with that mass is f_a = Ω_a × π_a, with the tangent
∂f_a/∂Ω_b = Ω̃_a M_ab − δ_ab π̃_a. It conserves T (Ω_a · f_a = 0) and, with moments free of a
net torque, the angular momentum Σ_a R_a π_a + Σ x × p of the mass matrix.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..rotations import hat
from .beam3d_kernels import Beam3DElements

__all__ = ["GyroscopicPattern", "consistent_mass", "gyroscopic", "lumped_inertias"]

_P1_MASS = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6.0  # ∫ N_a N_b ds / ℓ of linear elements


def consistent_mass(el: Beam3DElements, rhoA, J, point_masses, point_inertias) -> sp.csr_matrix:
    """Mass matrix (kg, kg·m²): ρA I₃ (kg/m) and the rotary inertias J (E, 3, 3; kg·m) of the
    elements times the P1 mass, plus point masses (n,) and inertias (n, 3, 3)."""
    n = len(point_masses)
    blocks = np.zeros((len(el.ell), 2, 2, 6, 6))
    blocks[..., :3, :3] = rhoA * np.eye(3)
    blocks[..., 3:, 3:] = J[:, None, None]
    Me = (el.ell[:, None, None, None, None] * _P1_MASS[None, :, :, None, None]) * blocks
    Me = Me.transpose(0, 1, 3, 2, 4).reshape(-1, 12, 12)
    rows = np.broadcast_to(el.dofs[:, :, None], Me.shape).ravel()
    cols = np.broadcast_to(el.dofs[:, None, :], Me.shape).ravel()
    M = sp.coo_matrix((Me.ravel(), (rows, cols)), shape=(6 * n, 6 * n))
    points = np.zeros((n, 6, 6))
    points[:, :3, :3] = point_masses[:, None, None] * np.eye(3)
    points[:, 3:, 3:] = point_inertias
    return (M + sp.block_diag(list(points))).tocsr()


def lumped_inertias(el: Beam3DElements, J, point_inertias) -> np.ndarray:
    """(n, 3, 3) rotary inertias of the nodes (kg·m²): half of each element's ℓ J to each of
    its nodes (the rows of the consistent mass summed), plus the point inertias."""
    out = np.array(point_inertias)
    half = 0.5 * el.ell[:, None, None] * J
    np.add.at(out, el.n0, half)
    np.add.at(out, el.n1, half)
    return out


class GyroscopicPattern:
    """The sparsity of the gyroscopic tangent of a beam of ``n`` nodes (the 3 × 3 blocks of
    its rotational mass: node blocks and the elements' ``n0``–``n1`` blocks), fixed once: the
    CSR structure and, for each computed entry, its slot in the CSR data (entries on the same
    slot add)."""

    def __init__(self, el: Beam3DElements, n: int):
        triples = 6 * np.arange(n)[:, None] + np.arange(3, 6)
        ends = np.stack([el.n0, el.n1], axis=1)  # (E, 2)
        # element blocks (E, 2, 2, 3, 3): rows of node ends[:, a], columns of node ends[:, b]
        er = triples[ends][:, :, None, :, None]
        ec = triples[ends][:, None, :, None, :]
        shape = (len(el.ell), 2, 2, 3, 3)
        # node blocks (n, 3, 3)
        nr = np.broadcast_to(triples[:, :, None], (n, 3, 3))
        nc = np.broadcast_to(triples[:, None, :], (n, 3, 3))
        rows = np.concatenate([np.broadcast_to(er, shape).ravel(), nr.ravel()])
        cols = np.concatenate([np.broadcast_to(ec, shape).ravel(), nc.ravel()])
        self.size = 6 * n
        keys, self.slot = np.unique(rows * self.size + cols, return_inverse=True)
        self.indices = (keys % self.size).astype(np.int32)
        counts = np.bincount(keys // self.size, minlength=self.size)
        self.indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)
        self.nnz = keys.size

    def matrix(self, element_blocks: np.ndarray, node_blocks: np.ndarray) -> sp.csr_matrix:
        """The CSR matrix of the blocks (E, 2, 2, 3, 3) and (n, 3, 3), summed where they meet."""
        vals = np.concatenate([element_blocks.ravel(), node_blocks.ravel()])
        data = np.bincount(self.slot, weights=vals, minlength=self.nnz)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.size, self.size))


def gyroscopic(el: Beam3DElements, J, point_inertias, v: np.ndarray, pattern: GyroscopicPattern):
    """Force f_a = Ω_a × (M Ω)_a (N·m) on the nodes' rotation dofs of the velocity ``v``, zero
    elsewhere, M the consistent rotational mass of the elements' rotary inertias J (E, 3, 3;
    kg·m) and the point inertias (n, 3, 3), and its tangent ∂f/∂v (sparse; module
    docstring)."""
    Om = v.reshape(-1, 6)[:, 3:]
    ends = (el.n0, el.n1)
    # element blocks of M: ℓ P1_ab J_e; their action (E, 2, 3): ℓ Σ_b P1_ab J_e Ω_b
    JO = np.stack([np.einsum("eij,ej->ei", J, Om[k]) for k in ends], axis=1)
    MO = el.ell[:, None, None] * np.einsum("ab,ebi->eai", _P1_MASS, JO)
    pi = np.einsum("nij,nj->ni", point_inertias, Om)
    for a, k in enumerate(ends):
        np.add.at(pi, k, MO[:, a])
    f = np.zeros((len(Om), 6))
    f[:, 3:] = np.cross(Om, pi)
    # tangent: Ω̃_a M_ab on every block, − π̃_a on the node blocks
    W = hat(Om)
    lJ = el.ell[:, None, None] * J
    Wa = np.stack([W[k] for k in ends], axis=1)  # (E, 2, 3, 3): Ω̃ of the row's node
    element = _P1_MASS[None, :, :, None, None] * (Wa @ lJ[:, None])[:, :, None]
    node = W @ point_inertias - hat(pi)
    return f.ravel(), pattern.matrix(element, node)
