r"""Unilateral contact: gaps, their derivatives, and the Alart–Curnier augmented Lagrangian.

Notation (after Brüls, Acary & Cardona 2014, eqs. 9–10):

=========  ==============================================================================
g_j(q)     signed gap of contact j in m (> 0 open, 0 closed, < 0 penetrating)
G_j        ∂g_j/∂q, a row over the dofs
ν_j        position-level multiplier (kg·m); the contact force of the correction is k ν_j
Λ_j        velocity-level multiplier; k Λ_j is the contact impulse in N·s
p, k       augmentation (penalty) and multiplier scaling, both > 0
[x]_+      max(x, 0)
=========  ==============================================================================

Position level: with s_j = k ν_j − p g_j the contact force is Σ G_jᵀ [s_j]_+ and the
complementarity residual k ν_j − [s_j]_+ vanishes exactly when 0 ≤ g_j ⊥ ν_j ≥ 0. Velocity
level: the same with ġ_j = G_j(q_{n+1}) v_{n+1} + e_j G_j(q_n) v_n (Newton's impact law with
restitution e_j) in place of g_j and Λ_j in place of ν_j.

Semi-smooth Newton on these residuals is a primal–dual active-set method: the active set
A = {j : s_j > 0} is re-evaluated after every update, and on A the linearised constraint is
enforced exactly, so the converged answer does not depend on p or k; they only steer the path.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import InputError, check_positive, check_range
from .linalg import DENSE_LIMIT
from .obstacles import Circle, Plane, Point

__all__ = [
    "Contact",
    "NodeContact",
    "PointSegmentContact",
    "alart_curnier_residual",
    "contact_force_multiplier",
    "solve_position_correction",
    "solve_velocity_jump",
]


def contact_force_multiplier(nu, g, p, k):
    """[k ν − p g]_+ : the contact force (or impulse) multiplier of the augmented Lagrangian."""
    return np.maximum(k * np.asarray(nu) - p * np.asarray(g), 0.0)


def alart_curnier_residual(nu, g, p, k):
    """k ν − [k ν − p g]_+, zero exactly when 0 ≤ g ⊥ ν ≥ 0 (any p, k > 0)."""
    return k * np.asarray(nu) - contact_force_multiplier(nu, g, p, k)


# -- contact pairs -----------------------------------------------------------------------------


class NodeContact:
    """Points of a body (its nodes, or a rigid body's vertices) against a rigid ``Plane`` or
    ``Circle``; one contact per point.

    ``restitution`` (Newton's coefficient e_N in [0, 1]) applies to every point of the pair.
    The body maps its dofs to the point positions x(q) (``point_kinematics``); the gap of the
    obstacle φ(x) then gives G = ∇φ ∂x/∂q and ∇²g = (∂x/∂q)ᵀ ∇²φ (∂x/∂q) + ∇φ·∂²x/∂q².
    """

    def __init__(self, body, obstacle, nodes=None, restitution: float = 0.0):
        if not isinstance(obstacle, (Plane, Circle)):
            raise InputError(f"obstacle must be a Plane or Circle, got {type(obstacle).__name__}")
        self.body = body
        self.obstacle = obstacle
        self.nodes = body.contact_nodes(nodes)
        if len(self.nodes) == 0:
            raise InputError("nodes must name at least one node")
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.linear = obstacle.linear and body.linear_kinematics
        self.offset = 0
        # positions alone where the body has a cheaper path to them (rigid bodies)
        self._positions = getattr(
            body, "point_positions", lambda q, nodes: body.point_kinematics(q, nodes)[0]
        )

    @property
    def size(self) -> int:
        return len(self.nodes)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offset = model.offset_of(self.body)

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g/∂t = −∇φ·ḋ (m/s) of a moving obstacle at its current time, per contact."""
        if not getattr(self.obstacle, "moving", False):
            return np.zeros(self.size)
        qb = q[self.offset : self.offset + self.body.ndof]
        x = self.body.point_kinematics(qb, self.nodes)[0]
        return -(self.obstacle.gap(x)[1] @ self.obstacle.speed())

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """Gaps (m,) alone, without their derivatives."""
        qb = q[self.offset : self.offset + self.body.ndof]
        return self.obstacle.gap_values(self._positions(qb, self.nodes))

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dof indices (m, d), gradient values (m, d), Hessians (m, d, d) or None."""
        qb = q[self.offset : self.offset + self.body.ndof]
        x, dofs, Jx, Hx = self.body.point_kinematics(qb, self.nodes)
        g, Gx, Hphi = self.obstacle.gap(x)
        G = np.einsum("mi,mik->mk", Gx, Jx)
        H = None
        if Hphi is not None:
            H = np.einsum("mik,mij,mjl->mkl", Jx, Hphi, Jx)
        if Hx is not None:
            H = np.einsum("mi,mikl->mkl", Gx, Hx) + (0.0 if H is None else H)
        return g, dofs + self.offset, G, H


class PointSegmentContact:
    """A rigid ``Point`` (or small disk) against the centreline segments of a beam.

    The contact point slides along the beam: the gap is the distance from the point to the
    closest segment minus the radius, signed by the side of the beam the point started on.
    When the closest point is a vertex the gap is the distance to that node.
    """

    linear = False

    def __init__(self, body, obstacle: Point, restitution: float = 0.0):
        self.body = body
        self.obstacle = obstacle
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.segments = body.segments()
        self.offset = 0
        self.side = 1.0
        f0 = self._signed_distance(np.zeros(body.ndof))
        if f0 == 0.0:
            raise InputError("the Point lies exactly on the beam centreline at t = 0")
        self.side = np.sign(f0)

    size = 1

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)

    def _closest(self, x):
        x1, x2 = x[self.segments[:, 0]], x[self.segments[:, 1]]
        d = x2 - x1
        xi = np.clip(np.einsum("ei,ei->e", self.obstacle.position - x1, d) / np.sum(d * d, 1), 0, 1)
        dist = np.linalg.norm(self.obstacle.position - (x1 + xi[:, None] * d), axis=1)
        e = int(np.argmin(dist))
        return e, xi[e], x1[e], d[e]

    def _signed_distance(self, q_local):
        e, xi, x1, d = self._closest(self.body.positions(q_local))
        w = self.obstacle.position - x1
        return (d[0] * w[1] - d[1] * w[0]) / np.linalg.norm(d)

    def evaluate(self, q: np.ndarray):
        body = self.body
        q_local = q[self.offset : self.offset + body.ndof]
        e, xi, x1, d = self._closest(body.positions(q_local))
        a, b = self.segments[e]
        tdofs = self.offset + body.node_translation_dofs([a, b]).ravel()
        P, r = self.obstacle.position, self.obstacle.radius
        if 0.0 < xi < 1.0:
            g, G, H = _point_line_gap(P, x1, d, self.side)
            g -= r
        else:
            xv = x1 + xi * d
            ev = xv - P
            dist = np.linalg.norm(ev)
            ev = ev / dist
            g = dist - r
            G = np.zeros(4)
            H = np.zeros((4, 4))
            k = 0 if xi == 0.0 else 2
            G[k : k + 2] = ev
            H[k : k + 2, k : k + 2] = (np.eye(2) - np.outer(ev, ev)) / dist
        return np.array([g]), tdofs[None, :], G[None, :], H[None, :, :]


def _point_line_gap(P, x1, d, side):
    """Signed distance f = (d × w)/|d| of P from the line x1 + ξ d (w = P − x1), with its
    gradient and Hessian with respect to the segment end points (x1, x2)."""
    w = P - x1
    L = np.linalg.norm(d)
    c = d[0] * w[1] - d[1] * w[0]
    rho = np.array([w[1], -w[0]])
    dperp = np.array([-d[1], d[0]])
    f_d = rho / L - c * d / L**3
    f_w = dperp / L
    R = np.array([[0.0, 1.0], [-1.0, 0.0]])
    H_dd = -(np.outer(rho, d) + np.outer(d, rho)) / L**3 - c * np.eye(2) / L**3
    H_dd += 3.0 * c * np.outer(d, d) / L**5
    H_dw = R / L - np.outer(d, dperp) / L**3
    Hz = np.block([[H_dd, H_dw], [H_dw.T, np.zeros((2, 2))]])
    eye = np.eye(2)
    T = np.block([[-eye, eye], [-eye, np.zeros((2, 2))]])  # (d, w) = T (x1, x2) + (0, P)
    G = T.T @ np.concatenate([f_d, f_w])
    return side * c / L, side * G, side * (T.T @ Hz @ T)


def Contact(body, obstacle, nodes=None, restitution: float = 0.0, clearance: float = 0.0):
    """Contact pair between ``body`` and a rigid ``obstacle`` or a second body.

    ``Plane`` and ``Circle`` act on ``nodes`` of the body (all nodes, or all polygon vertices
    of a rigid body, by default); a ``Point`` acts on the beam's centreline segments. A rigid
    disk (``RigidBody2D`` with a ``Disk``) contacts a ``Plane``, a ``Circle``, another disk, a
    rigid polygon or a ``Beam2D`` (``clearance``: extra distance in m, e.g. half the beam
    thickness) through its centre and radius; see :mod:`fecontact.rigid_contact`.
    Two deformable bodies: a ``Solid`` against a ``Solid`` is a node-to-surface pair (``nodes``
    of ``body``, default its boundary nodes, against the boundary of the second; add the
    reversed pair for the other direction), a ``Beam2D`` against a ``Beam2D`` an end-to-end
    pair along the bar axis (``nodes`` = (end of body, end of the other), default the closest
    ends); see :mod:`fecontact.body_contact`. ``restitution`` is Newton's e_N in [0, 1].
    """
    from .rigid_contact import rigid_pair

    clearance = check_positive("clearance", clearance, allow_zero=True)
    pair = rigid_pair(body, obstacle, nodes, restitution, clearance)
    if pair is not None:
        return pair
    if clearance:
        raise InputError("clearance applies to a rigid disk against a beam only")
    if hasattr(obstacle, "ndof"):
        from .body_contact import body_pair

        return body_pair(body, obstacle, nodes, restitution)
    if isinstance(obstacle, Point):
        if nodes is not None:
            raise InputError("nodes: a Point obstacle acts on beam segments, not on nodes")
        return PointSegmentContact(body, obstacle, restitution)
    return NodeContact(body, obstacle, nodes, restitution)


# -- semi-smooth Newton on the Alart–Curnier residuals -------------------------------------------


def _kkt_multipliers(GA, Y, rhs, k):
    """Solve k (G_A Y) μ = rhs for the active multipliers (least squares if redundant)."""
    S = k * (GA @ Y)
    try:
        return np.linalg.solve(S, rhs)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(S, rhs, rcond=None)[0]


def _settled(nu, g, p, k, eq, tol) -> bool:
    """The Alart–Curnier residual k ν_j − [k ν_j − p_j g_j]_+, measured as a gap (divided by
    p_j), is within ``tol`` for every unilateral row, and every equality holds to ``tol``.

    This is the stopping test rather than a repeated active set: a contact whose gap is at
    round-off level (a body resting on another) may enter and leave the set from one
    iteration to the next while the answer has converged."""
    u = ~eq
    r = alart_curnier_residual(nu[u], g[u], p[u], k) / p[u]
    return bool(np.all(np.abs(r) <= tol) and np.all(np.abs(g[eq]) <= tol))


def solve_position_correction(
    gaps, system, n, p, k, tol_gap, tol_u, max_iter=30, bilateral=None, nu0=None
):
    """Position correction q = q̃ + U: find (U, ν) with H U = Σ G_jᵀ [k ν_j − p g_j(q)]_+ and
    k ν_j − [k ν_j − p g_j(q)]_+ = 0 for every candidate j.

    ``gaps(U) -> (g, G)`` evaluates the candidate gaps (m,) and their gradient (m × n dense) at
    q̃ + U. ``system(U, s, A) -> (solve, C)`` gives the solver of the Newton matrix
    H − C, where C = Σ_A s_j ∇²g_j is the curvature of the gaps (``None`` when they are linear).
    Each Newton step solves the bordered system [H − C, −k G_Aᵀ; G_A, 0] through its Schur
    complement. ``bilateral`` marks equality constraints (joints): always active, with
    multipliers of either sign. ``nu0`` warm-starts the multipliers (those of the previous
    step): only the first active set depends on it, so a chain of contacts that stays closed
    (a stack at rest) is found at once instead of one link per iteration. The iteration stops
    when the Alart–Curnier residual is below ``tol_gap`` (in m) and the update below ``tol_u``
    or no longer shrinking. Returns (U, ν, iterations); raises ``RuntimeError`` when the
    iteration does not settle.
    """
    U = np.zeros(n)
    g, G = gaps(U)
    nu = np.zeros(len(g)) if nu0 is None else np.maximum(np.asarray(nu0, dtype=float), 0.0)
    eq = np.zeros(len(g), bool) if bilateral is None else bilateral
    dU, dU_prev = np.inf, np.inf
    for it in range(max_iter + 1):
        # the update has converged, or stopped shrinking: round-off of nearly parallel
        # constraints (a disk in the kink of a beam) once the gaps hold
        settled = dU <= tol_u or dU > 0.5 * dU_prev
        if it > 0 and settled and _settled(nu, g, p, k, eq, tol_gap):
            return U, nu, it
        A = ((k * nu - p * g) > 0) | eq
        solve, C = system(U, k * nu - p * g, A)
        x0 = np.zeros(n) if C is None else solve(-(C @ U))
        nu = np.zeros(len(g))
        U_new = x0
        if A.any():
            GA = G[A]
            Y = solve(GA.T).reshape(n, -1)
            nu[A] = _kkt_multipliers(GA, Y, GA @ (U - x0) - g[A], k)
            U_new = x0 + k * (Y @ nu[A])
        dU_prev = dU
        dU = 0.0 if C is None else float(np.max(np.abs(U_new - U), initial=0.0))
        U = U_new
        g, G = gaps(U)
    raise RuntimeError(f"position correction: active set did not settle in {max_iter} iterations")


def solve_velocity_jump(
    G, c, solve_M, p, k, max_iter=30, bilateral=None, Y=None, Lam0=None, tol=0.0
):
    """Velocity jump v = ṽ + W: M W = Σ G_jᵀ [k Λ_j − p ġ_j]_+ with ġ = c + G W and
    k Λ_j − [k Λ_j − p ġ_j]_+ = 0 (c_j = G_j ṽ + e_j G_j(q_n) v_n). Linear in W for a given
    active set, so the iteration ends when the set repeats, or when the Alart–Curnier
    residual (as a velocity, m/s) is below ``tol``. ``bilateral`` rows (joints) are always
    active: G_b v = 0. ``Y`` may give M⁻¹Gᵀ; ``Lam0`` warm-starts the multipliers (those of
    the previous step: see :func:`solve_position_correction`). Returns (W, Λ, iterations)."""
    m = len(c)
    Lam = np.zeros(m) if Lam0 is None else np.maximum(np.asarray(Lam0, dtype=float), 0.0)
    gd = np.asarray(c, dtype=float)
    Gd = np.asarray(G.todense()) if hasattr(G, "todense") else np.asarray(G)
    Y_all = solve_M(Gd.T).reshape(-1, m) if Y is None else Y
    eq = np.zeros(m, bool) if bilateral is None else bilateral
    A_prev = None
    W = np.zeros(Y_all.shape[0])
    for it in range(1, max_iter + 1):
        A = ((k * Lam - p * gd) > 0) | eq
        if A_prev is not None and (
            np.array_equal(A, A_prev) or (tol > 0 and _settled(Lam, gd, p, k, eq, tol))
        ):
            return W, Lam, it - 1
        Lam = np.zeros(m)
        if A.any():
            Lam[A] = _kkt_multipliers(Gd[A], Y_all[:, A], -c[A], k)
        W = k * (Y_all @ Lam)
        gd = c + Gd @ W
        A_prev = A
    raise RuntimeError(f"velocity jump: active set did not settle in {max_iter} iterations")


class ContactSet:
    """All contact pairs of a model, numbered globally and restricted to the free dofs."""

    def __init__(self, pairs, free_index: np.ndarray, n_free: int):
        self.pairs = list(pairs)
        self.free_index = free_index
        self.n_free = n_free
        self.size = sum(pair.size for pair in self.pairs)
        self.restitution = np.concatenate(
            [np.full(pair.size, pair.restitution) for pair in self.pairs] or [np.zeros(0)]
        )
        self.linear = all(pair.linear for pair in self.pairs)
        self.owner = np.concatenate(
            [np.full(pair.size, i) for i, pair in enumerate(self.pairs)] or [np.zeros(0, int)]
        )
        self.local = np.concatenate([np.arange(pair.size) for pair in self.pairs] or [self.owner])
        self._scatters: dict = {}
        self._last_scatter: dict = {}  # per pair: read-only (rows, dofs) and their _Scatter
        self._all = np.arange(self.size)
        self._all.flags.writeable = False
        obstacles = [getattr(pair, "obstacle", None) for pair in self.pairs]
        self._moving = [o for o in obstacles if getattr(o, "moving", False)]
        # the gaps alone are cheaper where a pair can skip its derivatives
        self._gap_functions = [
            getattr(pair, "gaps", None) or (lambda q, pair=pair: pair.evaluate(q)[0])
            for pair in self.pairs
        ]
        # affine gaps (constant gradients, fixed obstacles) of a small model: g(q) = g₀ + G q
        # with G stored dense, so that a step without candidates costs one product
        self._affine = None
        if self.pairs and self.linear and not self.moving and self.size * len(free_index) <= 2**16:
            self._affine = self._affine_form()

    @property
    def all(self) -> np.ndarray:
        return self._all

    @property
    def moving(self) -> bool:
        return bool(self._moving)

    def set_time(self, t: float) -> None:
        """Place the moving obstacles where they are at time t (s)."""
        for obstacle in self._moving:
            obstacle.time = t

    def rates(self, q: np.ndarray, select: np.ndarray) -> np.ndarray:
        """∂g_j/∂t of the contacts ``select`` (m/s): nonzero for moving obstacles only."""
        if not self.moving:
            return np.zeros(len(select))
        parts = [p.rate(q) if hasattr(p, "rate") else np.zeros(p.size) for p in self.pairs]
        return np.concatenate(parts)[select]

    def quadratic(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """vᵀ ∇²g_j v for every constraint j (the acceleration term of a holonomic one)."""
        out = []
        for g, dofs, _, H in self.evaluate(q):
            if H is None:
                out.append(np.zeros(len(g)))
            else:
                vd = v[np.broadcast_to(dofs, H.shape[:2])]
                out.append(np.einsum("mi,mij,mj->m", vd, H, vd))
        return np.concatenate(out) if out else np.zeros(0)

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (list per pair), gradient values and Hessians of every contact."""
        return [pair.evaluate(q) for pair in self.pairs]

    def _affine_form(self):
        """(g₀, G on all dofs, G on the free dofs) of affine gaps g = g₀ + G q."""
        n = len(self.free_index)
        parts = self.evaluate(np.zeros(n))
        G = np.zeros((self.size, n))
        rows = np.split(self._all, np.cumsum([len(g) for g, _, _, _ in parts])[:-1])
        for r, (_, dofs, Gv, _) in zip(rows, parts, strict=True):
            dofs = np.broadcast_to(dofs, Gv.shape) if dofs.shape != Gv.shape else dofs
            np.add.at(G, (np.repeat(r, Gv.shape[1]), dofs.ravel()), Gv.ravel())
        g0 = np.concatenate([g for g, _, _, _ in parts])
        return g0, G, np.ascontiguousarray(G[:, self.free_index >= 0])

    def gaps(self, q: np.ndarray) -> np.ndarray:
        if not self.pairs:
            return np.zeros(0)
        if self._affine is not None:
            return self._affine[0] + self._affine[1] @ q
        if len(self.pairs) == 1:
            return self._gap_functions[0](q)
        return np.concatenate([gaps(q) for gaps in self._gap_functions])

    def jacobian(self, q: np.ndarray, select: np.ndarray):
        """Gaps and dense gradient (len(select) × n_free) of the contacts ``select``."""
        return self.linearize(q, select)[:2]

    def curvature(self, q: np.ndarray, select: np.ndarray, weights: np.ndarray):
        """Σ_j weights_j ∇²g_j over ``select`` (n_free × n_free; see :meth:`linearize`)."""
        return self.linearize(q, select, weights)[2]

    def linearize(self, q: np.ndarray, select: np.ndarray, weights=None):
        """Gaps g (len(select),), their dense gradient G (len(select) × n_free) and, when
        ``weights`` are given, the curvature C = Σ_j weights_j ∇²g_j (n_free × n_free), from
        one evaluation of the pairs at q. C is dense like the model's matrices up to
        ``DENSE_LIMIT`` free dofs, else sparse (CSR) over the dofs of the contacts with a
        nonzero weight."""
        n = self.n_free
        G = np.zeros((len(select), n))
        dense = n <= DENSE_LIMIT
        C = None if weights is None else (np.zeros((n, n)) if dense else [])
        if not self.pairs or len(select) == 0:
            return np.zeros(0), G, _curvature_matrix(C, n)
        if self._affine is not None:  # affine gaps: no curvature
            g0, Gq, Gf = self._affine
            return g0[select] + Gq[select] @ q, Gf[select], _curvature_matrix(C, n)
        parts = [pair.evaluate(q) for pair in self.pairs]
        single = len(parts) == 1
        g_all = parts[0][0] if single else np.concatenate([p[0] for p in parts])
        owner = None if single else self.owner[select]
        every = single and select is self._all  # no selection to copy
        for i, (_, dofs, Gv, H) in enumerate(parts):
            if every:
                rows = loc = self._all
            elif single:
                rows, loc = np.arange(len(select)), select
            else:
                rows = np.flatnonzero(owner == i)
                if rows.size == 0:
                    continue
                loc = self.local[select[rows]]
            if dofs.shape != Gv.shape:
                dofs = np.repeat(dofs.reshape(1, -1), len(Gv), axis=0)
            sc = self._scatter(i, rows, dofs if every else dofs[loc])
            if not every:  # the selected rows (linear kinematics carry no Hessian)
                Gv, H = Gv[loc], (None if H is None else H[loc])
            # each pair fills rows of its own: an assignment unless a row repeats a dof
            _add(G, sc.g_index, Gv.ravel()[sc.g_keep], sc.g_unique, assign=True)
            if C is not None and H is not None:
                w = weights[rows]
                # rows on the same dofs (a joint's two equations): summed before the scatter
                Hw = w @ H.reshape(len(w), -1) if sc.shared else w[:, None, None] * H
                values = Hw.ravel()[sc.c_keep]
                if dense:  # (a single pair writes into a C still zero)
                    _add(C, sc.c_index, values, sc.c_unique, assign=single)
                else:
                    C.append((values, sc.c_index))
        return g_all[select], G, _curvature_matrix(C, n)

    def _scatter(self, i: int, rows: np.ndarray, dofs: np.ndarray):
        """Where the gradient rows and Hessians of pair i land in G and C (cached: the dofs
        of most pairs never change)."""
        last = self._last_scatter.get(i)
        if last is not None and last[0] is rows and last[1] is dofs:
            return last[2]  # the same unchangeable arrays as last time
        key = (i, rows.tobytes(), dofs.tobytes())
        sc = self._scatters.get(key)
        if sc is None:
            sc = _Scatter(rows, self.free_index[dofs], self.n_free)
            if len(self._scatters) > 256:
                self._scatters.clear()
            self._scatters[key] = sc
        if not (rows.flags.writeable or dofs.flags.writeable):
            self._last_scatter[i] = (rows, dofs, sc)
        return sc

    def generalized_force(self, q: np.ndarray, select: np.ndarray, mult: np.ndarray, n: int):
        """Σ_j G_jᵀ mult_j over ``select`` on all n dofs (for output of nodal forces)."""
        parts = self.evaluate(q)
        f = np.zeros(n)
        wfull = np.zeros(self.size)
        wfull[select] = mult
        offset = 0
        for g, dofs, G, _ in parts:
            m = len(g)
            f += np.bincount(
                dofs.ravel(), (wfull[offset : offset + m, None] * G).ravel(), minlength=n
            )
            offset += m
        return f


def _curvature_matrix(C, n: int):
    """The curvature as it was gathered: dense, or CSR from (values, (rows, cols)) parts
    (duplicates summed; zero weights dropped, so only the active contacts' dofs appear)."""
    if not isinstance(C, list):
        return C
    values = np.concatenate([v for v, _ in C] or [np.zeros(0)])
    flat = np.concatenate([i for _, i in C] or [np.zeros(0, int)])
    keep = values != 0.0
    rows, cols = np.divmod(flat[keep], n)
    return sp.csr_matrix((values[keep], (rows, cols)), shape=(n, n))


class _Scatter:
    """Index arrays that place gradient rows (r, k) and Hessians (r, k, k) of contacts into the
    dense G (rows × free dofs) and C (free × free), n free dofs; fixed dofs (index −1) are
    dropped. The indices are flat (row × n + column): a one-dimensional fancy assignment
    costs half of a two-dimensional one on these small arrays."""

    def __init__(self, rows: np.ndarray, fi: np.ndarray, n: int):
        k = fi.shape[1]
        r = np.repeat(rows, k)
        f = fi.ravel()
        self.g_keep = f >= 0
        self.g_index = r[self.g_keep] * n + f[self.g_keep]
        self.g_unique = _unique(self.g_index)
        a = np.repeat(fi, k, axis=1).ravel()
        b = np.tile(fi, (1, k)).ravel()
        # Hessians of rows on the same dofs are summed first: scattered as one row
        self.shared = len(fi) > 1 and bool(np.all(fi == fi[0]))
        if self.shared:
            a, b = np.repeat(fi[0], k), np.tile(fi[0], k)
        self.c_keep = (a >= 0) & (b >= 0)
        self.c_index = a[self.c_keep] * n + b[self.c_keep]
        self.c_unique = _unique(self.c_index)
        # no fixed dof: a view instead of a boolean selection
        self.g_keep = slice(None) if self.g_keep.all() else self.g_keep
        self.c_keep = slice(None) if self.c_keep.all() else self.c_keep


def _unique(index: np.ndarray) -> bool:
    return len(np.unique(index)) == len(index)


def _add(A: np.ndarray, index, values: np.ndarray, unique: bool, assign=False) -> None:
    """A.flat[index] += values (A C-contiguous); a plain fancy assignment when no index repeats
    (much cheaper), and ``assign`` when those entries of A are known to be zero."""
    flat = A.reshape(-1)  # a view
    if unique and assign:
        flat[index] = values
    elif unique:
        flat[index] += values
    else:
        np.add.at(flat, index, values)
