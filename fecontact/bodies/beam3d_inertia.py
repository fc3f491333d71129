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

from .beam3d_kernels import Beam3DElements

__all__ = ["Gyroscopic", "consistent_mass", "lumped_inertias"]

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


def _levi_civita() -> np.ndarray:
    """ε_ijk (3, 3, 3): (a × b)_i = ε_ijk a_j b_k, so that ã_ik = ε_ijk a_j."""
    E = np.zeros((3, 3, 3))
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        E[i, j, k], E[i, k, j] = 1.0, -1.0
    return E


_EPS = _levi_civita()


def _skew6() -> np.ndarray:
    """(6, 36): a node's 6 dof values @ it is the (6, 6) matrix with the skew matrix w̃ of
    its rotation part w (the last three) on the rotation block, zero elsewhere, flattened."""
    S = np.zeros((6, 6, 6))
    S[3:, 3:, 3:] = -_EPS  # w̃_ij = −ε_ijk w_k: entry (k, i, j)
    return S.reshape(6, 36)


_SKEW6 = _skew6()


def _skew12() -> np.ndarray:
    """(12, 72): a node's 6 dof values w then its 6 values π @ it is the (6, 12) matrix
    [w̃ | π̃] (:func:`_skew6` of each, side by side), flattened."""
    S = np.zeros((2, 6, 6, 2, 6))
    S[0, :, :, 0], S[1, :, :, 1] = _SKEW6.reshape(6, 6, 6), _SKEW6.reshape(6, 6, 6)
    return S.reshape(12, 72)


_SKEW12 = _skew12()
_ONE_PRODUCT = 8  # the most nodes whose gyroscopic term is made by _few_forces


class Gyroscopic:
    """The gyroscopic force of the consistent rotary mass of a beam's elements ``el`` over
    ``n`` nodes (module docstring), with its sparsity decided once: the 3 × 3 blocks of the
    rotational mass M (node blocks and the elements' blocks) as entries of the rotation dofs
    (3n × 3n, sorted by row then column). ``dense``: the tangent is returned as a dense
    (6n, 6n) array (a small beam, whose model is dense), else as CSR."""

    def __init__(self, el: Beam3DElements, n: int, dense: bool):
        ends = np.stack([el.n0, el.n1], axis=1)  # (E, 2)
        pairs = np.concatenate([ends, ends[:, ::-1], np.stack([np.arange(n)] * 2, axis=1)])
        self.m, self.n, self.dense = 3 * n, n, dense
        self.half = np.full(6 * n, 0.5)  # (½ as an array: with a Python float numpy costs more)
        self.keys = np.unique(self._keys(pairs[:, 0], pairs[:, 1]))
        rows, self.cols = np.divmod(self.keys, self.m)
        self.rows = rows
        a, i = np.divmod(rows, 3)
        b, j = np.divmod(self.cols, 3)
        # the entries (3a + k, col), k = 0, 1, 2, of each entry's node: Ω̃_a M mixes them,
        # (Ω̃_a)_ik = ε_ilk Ω_l
        self.mix = np.searchsorted(self.keys, (3 * a)[:, None] * self.m + self.cols[:, None]
                                   + self.m * np.arange(3))  # fmt: skip
        # (Ω̃_a M)_e = (Ω_a × M_mix)_i = Ω_j M_k − Ω_k M_j, (i, j, k) cyclic: the flat
        # indices of its two products, so that two gathers of each replace a sum over ε
        j_, k_ = (i + 1) % 3, (i + 2) % 3
        self.omega_j, self.omega_k = 3 * a + j_, 3 * a + k_
        self.mass_k = np.take_along_axis(self.mix, k_[:, None], axis=1)[:, 0]
        self.mass_j = np.take_along_axis(self.mix, j_[:, None], axis=1)[:, 0]
        # − π̃_a on the node blocks: −(π̃_a)_ij = −ε_ilj π_l, one l per entry off the diagonal
        diagonal = np.flatnonzero((a == b) & (i != j))
        l_ = 3 - i[diagonal] - j[diagonal]
        self.diagonal, self.pi_at = diagonal, 3 * a[diagonal] + l_
        self.pi_sign = -_EPS[i[diagonal], l_, j[diagonal]]
        row, col = 6 * a + 3 + i, 6 * b + 3 + j  # in the beam's dofs (6n)
        self.flat = row * (6 * n) + col
        self.indices, self.indptr = col, np.searchsorted(row, np.arange(6 * n + 1))

    def _keys(self, na, nb) -> np.ndarray:
        """The keys row·3n + column of the 3 × 3 blocks (k, 3, 3) of the node pairs."""
        r = 3 * np.asarray(na)[:, None, None] + np.arange(3)[:, None]
        c = 3 * np.asarray(nb)[:, None, None] + np.arange(3)[None, :]
        return (r * self.m + c).ravel()

    def mass(self, el: Beam3DElements, J, point_inertias):
        """M (kg·m²): ℓ P1_ab J_e of the elements, plus the point inertias (n, 3, 3) on the
        node blocks; its values on the entries, or with ``dense`` the operands of the dense path
        (:meth:`_dense_mass`)."""
        lJ = el.ell[:, None, None] * J
        nodes, values = (el.n0, el.n1), np.zeros(self.keys.size)
        for (a, b), w in np.ndenumerate(_P1_MASS):
            slots = np.searchsorted(self.keys, self._keys(nodes[a], nodes[b]))
            np.add.at(values, slots, (w * lJ).ravel())
        every = np.arange(self.n)
        slots = np.searchsorted(self.keys, self._keys(every, every))
        np.add.at(values, slots, point_inertias.ravel())
        return self._dense_mass(values) if self.dense else values

    def _dense_mass(self, M: np.ndarray):
        """The rotary mass as a dense (6n, 6n) array (zero on the translations) from its
        values ``M`` on the entries, and per node a its rows M_a stacked over −E_a (n, 12, 6n),
        E_a the identity on the node's own block: the operands of :meth:`_dense_forces`. On a
        beam of at most ``_ONE_PRODUCT`` nodes the mass is replaced by the map W (6n, 72n) of
        v to every node's [Ω̃_a | π̃_a], π = M v (``_few_forces``)."""
        n, ndof = self.n, 6 * self.n
        out = np.zeros(ndof * ndof)
        out[self.flat] = M
        Md = out.reshape(ndof, ndof)
        M6 = Md.reshape(n, 6, ndof)
        E = -np.eye(ndof).reshape(n, 6, ndof)
        ME = np.concatenate([M6, E], axis=1)
        if n > _ONE_PRODUCT:
            return Md, ME
        # (v_a, π_a) = S_a v with S_a = [E_a; M_a] (12, 6n), then times the skew table
        S = np.concatenate([-E, M6], axis=1).transpose(0, 2, 1)  # (n, 6n, 12): S_aᵀ
        return (S @ _SKEW12).transpose(1, 0, 2).reshape(ndof, 72 * n), ME

    def _dense_forces(self, mass, v: np.ndarray):
        """(f (6n,), ∂f/∂v dense (6n, 6n)) at the velocity ``v`` (6n,) with the dense rotary
        mass (:meth:`_dense_mass`): π = M v, then per node [Ω̃_a | π̃_a] from one product,
        and Ω̃_a π_a and Ω̃_a M_a − π̃_a E_a each one batched product over the nodes (a beam
        small enough for a dense model: a few numpy calls in all)."""
        if self.n <= _ONE_PRODUCT:
            return self._few_forces(mass, v)
        M, ME = mass
        n, ndof = self.n, 6 * self.n
        pi = M @ v
        Vp = np.concatenate([v.reshape(n, 6), pi.reshape(n, 6)], axis=1)
        WP = (Vp @ _SKEW12).reshape(n, 6, 12)  # [Ω̃_a | π̃_a] on the rotation block
        f = WP[:, :, :6] @ pi.reshape(n, 6, 1)
        return f.reshape(ndof), (WP @ ME).reshape(ndof, ndof)

    def _few_forces(self, mass, v: np.ndarray):
        """:meth:`_dense_forces` on a beam of a few nodes: [Ω̃_a | π̃_a] of every node from
        one product of v with the map W, C = ∂f/∂v from one batched product, and f = ½ C v,
        as C v = Ω × π − π × Ω = 2 Ω × π node by node (the products of W cost 432 n² flops:
        beyond some eight nodes more than the calls they save)."""
        W, ME = mass
        n, ndof = self.n, 6 * self.n
        C = ((v @ W).reshape(n, 6, 12) @ ME).reshape(ndof, ndof)
        return (C @ v) * self.half, C

    def __call__(self, M: np.ndarray, v: np.ndarray):
        """(f (6n,), ∂f/∂v) at the velocity ``v`` (6n,) with the rotary mass ``M`` made by
        :meth:`mass`."""
        if self.dense:
            return self._dense_forces(M, v)
        Om = v.reshape(-1, 6)[:, 3:]
        w = Om.ravel()
        pi = np.bincount(self.rows, weights=M * w[self.cols], minlength=self.m)
        f = np.zeros((self.n, 6))
        P = pi.reshape(-1, 3)
        for i, j, k in ((3, 1, 2), (4, 2, 0), (5, 0, 1)):  # Ω × π by its components
            f[:, i] = Om[:, j] * P[:, k] - Om[:, k] * P[:, j]
        # Ω̃_a M on every entry, − π̃_a on the node blocks
        values = w[self.omega_j] * M[self.mass_k] - w[self.omega_k] * M[self.mass_j]
        values[self.diagonal] += self.pi_sign * pi[self.pi_at]
        ndof = 6 * self.n
        return f.ravel(), sp.csr_matrix((values, self.indices, self.indptr), shape=(ndof, ndof))
