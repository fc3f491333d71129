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
from ..rotations import RightIncrements, compose, tangent
from .constraints import bordered

__all__ = [
    "InertialForces",
    "LieGroup",
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


def predict_increment(st, c, extrapolate: bool = False) -> np.ndarray:
    """The generalized-α predictor of (D, v, v̇, a) (rows of one (4, n) array), D = q_{n+1} ⊖
    q_n the increment of the positions: v̇_{n+1} = v̇_n, or with ``extrapolate`` v̇_{n+1} =
    v̇_n + h v̈_n.

    The variable a lags v̇ by (α_f − α_m) h: a_n = v̇(t_n + (α_m − α_f) h_{n−1}) + O(h²)
    (Arnold & Brüls, Multibody Syst. Dyn. 2007), so v̈_n ≈ (v̇_n − a_n)/((α_f − α_m) h_{n−1})
    without storing v̇_{n−1}. Where Newton ends on the joints' remainder bound after one
    update, that bound is quadratic in the update, d ≈ h³ × the jerk with v̇_{n+1} = v̇_n: a
    top spinning at 100 rad/s feels its gravity torque turn at 100 rad/s in its body frame,
    d ≈ 4e-6 rad at h = 1 ms and the gap's remainder ½|r|d² ≈ 3e-13 m, above the tolerance
    (1e-13 m for a 0.1 m top), so a second update follows; extrapolated, d ≈ 1e-6 rad
    … 1e-7 rad and one update ends the step. The change of v̇ moves (D, v, a) at the rates of
    a Newton update (c.w / β′), which keeps the generalized-α relations between them. Over a
    step longer than the last one the slope is taken over the last one's length only (the
    estimate of v̈ is not amplified beyond 1/(α_f − α_m)); at the first step (h_{n−1} = 0) and
    at ρ∞ = 1 (α_f = α_m: a = v̇ carries nothing of v̈) v̇_{n+1} = v̇_n."""
    X = c.P @ np.array([np.zeros_like(st.q), st.v, st.vd, st.a])
    lag = (c.af - c.am) * st.h
    if extrapolate and lag > 0.0:
        X += np.multiply.outer(c.w / c.bp, (min(c.h, st.h) / lag) * (st.vd - st.a))
    return X


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

        # one body whose dofs are all the model's, with a dense tangent: its own force and
        # tangent are the model's (a top: all dofs free), or their rows and columns of the
        # free dofs where those are one range (a beam pinned at its first node)
        self.alone = self.window = None
        if len(self.parts) == 1 and model.dense:
            body, s, local, place = self.parts[0]
            zero = np.zeros(body.ndof)
            if body.ndof == model.n and isinstance(body.inertial(zero, zero)[1], np.ndarray):
                if model.n_free == model.n and local is None:
                    self.alone = body
                elif isinstance(model.free_slice, slice):
                    self.alone, self.window = body, model.free_slice

    def __call__(self, q: np.ndarray, v: np.ndarray, tangent: bool = True):
        """(f on the free dofs, ∂f/∂v on the free dofs or None without ``tangent``)."""
        if self.alone is not None:
            return self._own(q, v, tangent)
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

    def _own(self, q: np.ndarray, v: np.ndarray, tangent: bool):
        """The one body's own force and tangent, cut to the free dofs' range if need be."""
        f, C = self.alone.inertial(q, v)
        w = self.window
        if w is None:
            return f, (C if tangent else None)
        return f[w], (C[w, w] if tangent else None)

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


class LieGroup:
    """What a run of ``model`` on the Lie group decides once: its rotation triples (free dofs
    ``R`` (k, 3), all dofs ``F``, the columns ``cols``), ``single``: there is one (the
    single-vector paths of ``rotations``), and ``stiff``: a stiffness can act on the triples'
    columns (a body with rotation vectors that is not a rigid frame: a ``Beam3D``); a rigid
    body has no internal force, so K T(D) − K is zero on its columns and is not formed."""

    def __init__(self, model):
        self.model = model
        R = model.rotations
        self.R, self.F, self.cols = R, model.free[R], R.ravel()
        self.single = len(R) == 1
        # one triple of consecutive free dofs (a rigid body): a slice of columns
        first = int(R[0, 0]) if self.single else 0
        consecutive = self.single and np.array_equal(R[0], first + np.arange(3))
        self.block = slice(first, first + 3) if consecutive else None
        self.stiff = any(len(b.rotation_triples) and not b.rigid_frame for b in model.bodies)
        # a small dense model: K (T(D) − I) as one product with the block-diagonal T(D) − I,
        # its triples' entries at these flat places of an n × n array (beyond some 40 free
        # dofs the n³ product costs more than the triples' columns gathered)
        n = model.n_free
        self.places = self.Z = None
        if model.dense and n <= _WHOLE_PRODUCT and len(R):
            self.places = (R[:, :, None] * n + R[:, None, :]).ravel()
            self.Z = np.zeros(n * n)  # (T(D) − I placed, zero elsewhere: made once)


# the largest dense model whose K (T(D) − I) is one n × n product
_WHOLE_PRODUCT = 40
_EYE3 = np.eye(3)


class LieStep:
    """The Lie-group parts of one smooth step of a run on ``group`` (:class:`LieGroup`) from
    the positions ``q_n``: the configuration q_n ⊕ D and the right tangent T(D). The
    quaternions of q_n's rotations are made once per step; T(D) when a matrix asks for it."""

    def __init__(self, group: LieGroup, q_n: np.ndarray):
        self.group, self.model = group, group.model
        self.single, self.F, self.cols = group.single, group.F, group.cols
        self.p = None
        self.start(q_n)

    def start(self, q_n: np.ndarray) -> None:
        """Begin the step from the positions ``q_n`` (a run's steps reuse one LieStep)."""
        self.q_n = q_n
        if not self.single and self.cols.size:
            if self.p is None:
                self.p = RightIncrements(q_n[self.F])
            else:
                self.p.start(q_n[self.F])
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
            self.D = D[F[0]]
            out[F[0]] = compose(self.q_n[F[0]], self.D)
        else:
            self.D = D[F]
            out[F] = self.p.compose(self.D)
        return out

    @property
    def T(self) -> np.ndarray:
        """(k, 3, 3) right tangents T(D) of the rotation triples at the current D."""
        if self._T is None:
            self._T = tangent(self.D)[None] if self.single else self.p.tangent()
        return self._T

    def _T_minus_identity(self) -> np.ndarray:
        """T(D) − I (k, 3, 3): made as such for several triples (no broadcast of I)."""
        if self._T is not None or self.single:
            return self.T - _EYE3
        return self.p.tangent(identity=0.0)

    def right(self, A):
        """A T(D): the columns of the rotation triples of ``A`` (free dofs) times T(D)."""
        R = self.model.rotations
        if A is None or not R.size:
            return A
        if sp.issparse(A):
            return (A @ self._block()).tocsr()
        out = np.array(A, dtype=float, copy=True)
        block = self.group.block
        if block is not None:  # one triple: its three columns, one product
            out[:, block] = A[:, block] @ self.T[0]
        else:
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
        if not R.size or K is None or not self.group.stiff:
            return S
        if sp.issparse(S):
            return S + (self.right(K) - K)
        places = self.group.places
        if places is not None:
            n, Z = S.shape[0], self.group.Z
            Z[places] = self._T_minus_identity().ravel()
            S += K @ Z.reshape(n, n)
            return S
        Kc = np.asarray(K)[:, self.cols]
        S[:, self.cols] += self._times(Kc, self.T) - Kc  # K (T − I), no broadcast of I
        return S

    def bordered(self, Kb, G):
        """[[K_b, Gᵀ], [G T(D), 0]]: the forces Gᵀλ act in the body frame, the constraint
        rows move with D through T(D)."""
        return bordered(Kb, G, self.right(G))
