r"""The smooth step on a Lie group: models with rotation vectors or gyroscopic forces.

The generalized-α step of Brüls & Cardona (J. Comput. Nonlinear Dyn. 2010) and Arnold, Brüls &
Cardona (Multibody Syst. Dyn. 2015). The velocities v, v̇ and a of a rotation are body-frame
vectors (Ω and its rates) and add; the positions do not: with the increment

    D = h Δq_n = h v_n + h²(½ − β) a_n + h²β a_{n+1},     q_{n+1} = q_n ⊕ D,

(⊕ the right composition exp(ψ̃) exp(D̃) on each rotation triple, addition elsewhere). The
Newton iteration keeps D additive, like q in the planar step, and evaluates q = q_n ⊕ D. A
position-dependent term f(q) moves with D through the right tangent, ∂f/∂D = (∂f/∂Θ) T(D) with
∂/∂Θ the body-frame derivative, so its stiffness and the constraint rows are multiplied on the
right by the block-diagonal T(D) (identity off the triples). The gyroscopic force Ω × JΩ joins
the residual, its tangent ∂/∂Ω with the rate γ′ at which v moves with D:

    S_t = β′M + γ′(C + C_Ω) + K_t T(D).

Contact rows of persistent smooth contacts keep T = I in the matrix (their residual is exact;
T(D) = I + O(|D|) only slows Newton by a factor O(|D|) where they act). With friction they
are not bordered rows but a Coulomb law solved on their Delassus matrix A S_t⁻¹Aᵀ
(:class:`fecontact.time.coulomb.SmoothFriction`), through S_t's own (unsymmetric) factors,
the rows A unchanged: a ball's slip over the step is its slip rows applied to D itself.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ..rotations import compose, compose_quaternions, quaternions, tangent
from .constraints import bordered

__all__ = [
    "InertialForces",
    "LieStep",
    "check_group",
    "inertial_forces",
    "on_group",
    "predict_increment",
]


def on_group(model) -> bool:
    """Whether the model's smooth step runs on the Lie group (decided once per model)."""
    return bool(model.rotations.size or model.inertial_bodies)


def check_group(model, settings) -> None:
    """Rotations in space run on the NSGA integrator with the generalized-α smooth step: an
    ``InputError`` naming the option otherwise (before any step)."""
    if not on_group(model):
        return
    if settings.integrator != "nsga":
        raise InputError(
            f"integrator = {settings.integrator!r}: rotations in space (RigidBody3D, gyroscopic "
            "forces) run on integrator 'nsga' only"
        )
    if settings.scheme != "generalized-alpha":
        raise InputError(
            f"scheme = {settings.scheme!r}: rotations in space (RigidBody3D, gyroscopic forces) "
            "run on scheme 'generalized-alpha' only"
        )


def predict_increment(st, c) -> np.ndarray:
    """The generalized-α predictor of (D, v, v̇, a) (rows of one (4, n) array), D = q_{n+1} ⊖
    q_n the increment of the positions."""
    return c.P @ np.array([np.zeros_like(st.q), st.v, st.vd, st.a])


def inertial_forces(model, q: np.ndarray, v: np.ndarray, tangent: bool = True):
    """The bodies' velocity-dependent inertial forces (gyroscopic Ω × JΩ, N·m) on the free
    dofs and, with ``tangent``, their tangent ∂f/∂v (free dofs; dense or CSR like the model's
    matrices). For the Newton iterations of a run, :class:`InertialForces` keeps the scatter."""
    return InertialForces(model)(q, v, tangent)


class InertialForces:
    """The bodies' inertial forces and tangents on the free dofs of ``model``, with each
    body's scatter onto them decided once: the body's free local dofs and their free numbers
    (a slice where they are every dof of the body, in order)."""

    def __init__(self, model):
        self.model = model
        self.parts = []
        for body, s in model.inertial_bodies:
            idx = model.free_index[s]
            local = np.flatnonzero(idx >= 0)
            glob = idx[local]
            whole = local.size == idx.size and np.array_equal(glob, glob[0] + local)
            if whole:
                place = slice(int(glob[0]), int(glob[0]) + local.size)
                self.parts.append((body, s, None, place))
            else:  # (the flat indices of the dense scatter, made once)
                n_b, n_f = idx.size, model.n_free
                flat = ((local * n_b)[:, None] + local).ravel()
                self.parts.append(
                    (body, s, (local, flat), (glob, ((glob * n_f)[:, None] + glob).ravel()))
                )

    def __call__(self, q: np.ndarray, v: np.ndarray, tangent: bool = True):
        """(f on the free dofs, ∂f/∂v on the free dofs or None without ``tangent``)."""
        model = self.model
        f = np.zeros(model.n)
        dense = model.dense and tangent
        C = np.zeros((model.n_free,) * 2) if dense else None
        sparse_parts = []
        for body, s, local, place in self.parts:
            fb, Cb = body.inertial(q[s], v[s])
            f[s] += fb
            if not tangent:
                continue
            if not dense:
                sparse_parts.append(self._coo(Cb, local, place))
                continue
            Cb = Cb.toarray() if sp.issparse(Cb) else np.asarray(Cb)
            if local is None:
                C[place, place] += Cb
            else:  # (bodies share no dof: each entry of C is set by one body)
                C.put(place[1], Cb.take(local[1]))
        f = f[model.free_slice]
        if not tangent or dense:
            return f, C
        n = model.n_free
        if not sparse_parts:
            return f, sp.csr_matrix((n, n))
        rows, cols, vals = (np.concatenate(x) for x in zip(*sparse_parts, strict=True))
        return f, sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    def _coo(self, Cb, local, place):
        """(rows, columns, values) of a body's tangent on the free dofs."""
        Cb = sp.coo_matrix(Cb)
        if local is None:
            return Cb.row + place.start, Cb.col + place.start, Cb.data
        idx = np.full(Cb.shape[0], -1)
        idx[local[0]] = place[0]
        r, c = idx[Cb.row], idx[Cb.col]
        keep = (r >= 0) & (c >= 0)
        return r[keep], c[keep], Cb.data[keep]


class LieStep:
    """The Lie-group parts of one smooth step from the positions ``q_n``: the configuration
    q_n ⊕ D and the right tangent T(D). The quaternions of q_n's rotations are made once per
    step; T(D) when a matrix asks for it."""

    def __init__(self, model, q_n: np.ndarray):
        self.model, self.q_n = model, q_n
        R = model.rotations
        self.single = len(R) == 1  # one body: the single-vector paths of ``rotations``
        self.F = model.free[R]
        self.cols = R.ravel()  # the triples' columns (free dofs), in order
        self.p = None if self.single or not R.size else quaternions(q_n[self.F])
        self.D = None  # the rotation part of the current increment D
        self._T = None  # (k, 3, 3) right tangents at D, once asked for

    def configuration(self, D: np.ndarray) -> np.ndarray:
        """q = q_n ⊕ D (all dofs; D on the free dofs, as the iterate's first row)."""
        model = self.model
        R, F = model.rotations, self.F
        out = self.q_n.copy()
        out[model.free_slice] += D[model.free_slice]
        self._T = None
        if not R.size:
            return out
        if self.single:
            self.D = D[model.free[R[0]]]
            out[F[0]] = compose(self.q_n[F[0]], self.D)
        else:
            self.D = D[model.free[R]]
            out[F] = compose_quaternions(self.p, self.D)
        return out

    @property
    def T(self) -> np.ndarray:
        """(k, 3, 3) right tangents T(D) of the rotation triples at the current D."""
        if self._T is None:
            self._T = tangent(self.D)[None] if self.single else tangent(self.D)
        return self._T

    def right(self, A):
        """A T(D): the columns of the rotation triples of ``A`` (free dofs) times T(D)."""
        R = self.model.rotations
        if A is None or not R.size:
            return A
        if sp.issparse(A):
            return (A @ self._block()).tocsr()
        out = np.array(A, dtype=float, copy=True)
        out[:, self.cols] = self._times(out[:, self.cols], self.T)
        return out

    def _times(self, A: np.ndarray, T: np.ndarray) -> np.ndarray:
        """The columns ``A`` (n, 3k) of the triples, each triple's three times its T (k, 3, 3)."""
        n, k = A.shape[0], T.shape[0]
        AT = A.reshape(n, k, 3).transpose(1, 0, 2) @ T  # (k, n, 3): one batched product
        return AT.transpose(1, 0, 2).reshape(n, 3 * k)

    def _block(self) -> sp.csr_matrix:
        """The block-diagonal T(D) on the free dofs (identity off the triples)."""
        n, R = self.model.n_free, self.model.rotations
        off = np.setdiff1d(np.arange(n), R.ravel())
        rows = np.concatenate([off, np.repeat(R, 3, axis=1).ravel()])
        cols = np.concatenate([off, np.tile(R, (1, 3)).ravel()])
        vals = np.concatenate([np.ones(off.size), self.T.ravel()])
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    def iteration_matrix(self, S, K):
        """S_t of the group: ``S`` = β′M + γ′(C + C_Ω) + K of the terms, with K T(D) in
        place of K (the stiffness moves with D through the right tangent); a dense ``S`` (a
        sum made for this iteration) is changed in place, on the triples' columns only."""
        R = self.model.rotations
        if not R.size or K is None:
            return S
        if sp.issparse(S):
            return S + (self.right(K) - K)
        Kc = np.asarray(K)[:, self.cols]
        S[:, self.cols] += self._times(Kc, self.T) - Kc  # K (T − I), no broadcast of I
        return S

    def bordered(self, Kb, G):
        """[[K_b, Gᵀ], [G T(D), 0]]: the forces Gᵀλ act in the body frame, the constraint
        rows move with D through T(D)."""
        return bordered(Kb, G, self.right(G))
