"""Inertia of the spatial beam :class:`~fecontact.bodies.beam3d.Beam3D`: its constant
consistent mass matrix and the gyroscopic force of its nodes' rotations."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..rotations import hat
from .beam3d_kernels import Beam3DElements

__all__ = ["consistent_mass", "gyroscopic", "lumped_inertias"]

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


def gyroscopic(J: np.ndarray, v: np.ndarray, triples: np.ndarray):
    """Force Ω × JΩ (N·m) on the rotation dofs ``triples`` (n, 3) of the velocity ``v``, zero
    elsewhere, and its tangent ∂f/∂v = Ω̃J − (JΩ)~ (sparse)."""
    Om = v[triples]
    JOm = np.einsum("nij,nj->ni", J, Om)
    f = np.zeros(v.size)
    f[triples] = np.cross(Om, JOm)
    blocks = hat(Om) @ J - hat(JOm)
    rows = np.broadcast_to(triples[:, :, None], blocks.shape).ravel()
    cols = np.broadcast_to(triples[:, None, :], blocks.shape).ravel()
    return f, sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(v.size, v.size))
