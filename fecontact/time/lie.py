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
from ..rotations import tangent
from .configuration import plus
from .constraints import bordered

__all__ = ["LieStep", "check_group", "inertial_forces", "on_group", "predict_increment"]


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
    matrices; a body gives its own dense or sparse)."""
    f = np.zeros(model.n)
    n_free = model.n_free
    dense = np.zeros((n_free, n_free)) if tangent and model.dense else None
    rows, cols, vals = [], [], []
    for body, s in model.inertial_bodies:
        fb, Cb = body.inertial(q[s], v[s])
        f[s] += fb
        if not tangent:
            continue
        idx = model.free_index[s]
        i0, n = int(idx[0]), len(idx)
        if dense is not None and not sp.issparse(Cb) and i0 >= 0 and idx[-1] == i0 + n - 1:
            dense[i0 : i0 + n, i0 : i0 + n] += Cb  # a body with every dof free (contiguous)
            continue
        Cb = sp.coo_matrix(Cb)
        r, c = idx[Cb.row], idx[Cb.col]
        keep = (r >= 0) & (c >= 0)
        rows.append(r[keep]), cols.append(c[keep]), vals.append(Cb.data[keep])
    if not tangent:
        return f[model.free_slice], None
    C = None
    if rows:
        C = sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(n_free, n_free),
        )
    if dense is not None:
        return f[model.free_slice], dense if C is None else dense + C.toarray()
    return f[model.free_slice], C if C is not None else sp.csr_matrix((n_free, n_free))


class LieStep:
    """The Lie-group parts of one smooth step from the positions ``q_n``: the configuration
    q_n ⊕ D and the right tangent T(D)."""

    def __init__(self, model, q_n: np.ndarray):
        self.model, self.q_n = model, q_n
        self.T = None  # (k, 3, 3) right tangents at the current D

    def configuration(self, D: np.ndarray) -> np.ndarray:
        """q = q_n ⊕ D (all dofs); also evaluates T(D) for the matrices of the iteration."""
        model = self.model
        R = model.rotations
        if len(R) == 1:  # one body: the single-vector path of ``tangent``
            self.T = tangent(D[model.free[R[0]]])[None]
        elif R.size:
            self.T = tangent(D[model.free[R]])
        return plus(model, self.q_n, D[model.free_slice])

    def right(self, A):
        """A T(D): the columns of the rotation triples of ``A`` (free dofs) times T(D)."""
        R = self.model.rotations
        if A is None or not R.size:
            return A
        if sp.issparse(A):
            return (A @ self._block()).tocsr()
        out = np.array(A, dtype=float, copy=True)
        out[:, R] = np.einsum("nki,kij->nkj", np.asarray(A)[:, R], self.T)
        return out

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
        place of K (the stiffness moves with D through the right tangent)."""
        if self.model.rotations.size and K is not None:
            S = S + (self.right(K) - K)
        return S

    def bordered(self, Kb, G):
        """[[K_b, Gᵀ], [G T(D), 0]]: the forces Gᵀλ act in the body frame, the constraint
        rows move with D through T(D)."""
        return bordered(Kb, G, self.right(G))
