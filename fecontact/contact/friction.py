r"""Coulomb friction in the Alart–Curnier augmented Lagrangian (Alart & Curnier, CMAME 1991).

A frictional contact j has one normal row and ``nt`` tangential rows (one in 2D, two in 3D):
the gradient of its gap, then the tangents T_j of the contact plane applied to the relative
motion of the two contact points. Over one level of the step these rows measure

=========  ============================================================================
w_N        the normal gap g_j (position level, m) or its rate ġ_j (velocity level, m/s)
w_T        the slip of the contact point over the step (m), or its slip rate (m/s)
x_N, x_T   the multipliers; k x is the contact impulse (N·s) or positional force (kg·m)
=========  ============================================================================

With the augmented variables σ_N = k x_N − p_N w_N and σ_T = k x_T − p_T w_T, Coulomb's law
with Signorini's condition is the projection

    k x_N = [σ_N]_+,     k x_T = Π_B(μ [σ_N]_+)(σ_T),

Π_B(r) the projection on the disk of radius r (an interval in 2D). The contact is open when
σ_N ≤ 0 and carries nothing; closed, it sticks (w_T = 0) while |σ_T| < μ k x_N and slips
otherwise, with k x_T = μ k x_N σ_T/|σ_T| opposing the slip. The residual
R = k x − Π(σ) vanishes exactly there, for any p, k > 0: they steer the semi-smooth Newton
of :func:`solve_coulomb`, not its answer.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg.lapack import dgetrf, dgetrs

from .stats import CoulombStats

__all__ = [
    "coulomb_projection",
    "coulomb_residual",
    "coulomb_violation",
    "point_tangents",
    "solve_coulomb",
    "tangent_basis",
]


def tangent_basis(n: np.ndarray) -> np.ndarray:
    """Unit tangents (m, d−1, d) of the contact planes with unit normals n (m, d).

    2D: t = (n_y, −n_x), so that (t, n) is right-handed; for n = +y, t = +x. 3D: t₁ along
    the axis least aligned with n projected on the plane, t₂ = n × t₁. Coulomb's disk is
    isotropic, so the choice in the plane only names the components of the output."""
    n = np.asarray(n, dtype=float)
    if n.shape[1] == 2:
        return np.stack([n[:, 1], -n[:, 0]], axis=1)[:, None, :]
    axis = np.eye(3)[np.argmin(np.abs(n), axis=1)]
    t1 = axis - np.einsum("mi,mi->m", axis, n)[:, None] * n
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return np.stack([t1, np.cross(n, t1)], axis=1)


def point_tangents(G: np.ndarray, dim: int) -> np.ndarray:
    """Tangential rows (m, nt, k) of gaps whose gradient rows (m, k) act on the translations
    of points only, as n ⊗ (w_1, ..., w_P): the first point's block is the unit normal n
    (weight 1) and the others carry weights w_i (a node against a facet: w_i = −N_i(ξ) at
    the closest point). The slip is then T·Σ w_i ẋ_i, with the same weights. Rows with a
    zero gradient (no facet near) get zero tangents."""
    m, k = G.shape
    Gp = G.reshape(m, k // dim, dim)
    n = Gp[:, 0]
    w = np.einsum("mpd,md->mp", Gp, n)
    T = tangent_basis(n) * (np.linalg.norm(n, axis=1) > 0.0)[:, None, None]
    return np.einsum("mp,mtd->mtpd", w, T).reshape(m, T.shape[1], k)


def coulomb_projection(sigma: np.ndarray, mu: np.ndarray):
    """Π(σ) and its generalized Jacobian for contacts σ (m, 1 + nt), normal first.

    Returns (Π (m, b), ∂Π/∂σ (m, b, b), status (m,)): 0 open, 1 stick, 2 slip. A contact
    with μ = 0 slips with zero tangential force whatever σ_T."""
    m, b = sigma.shape
    sN, sT = sigma[:, 0], sigma[:, 1:]
    closed = sN > 0.0
    r = mu * np.maximum(sN, 0.0)
    norm = np.linalg.norm(sT, axis=1)
    stick = closed & (r > 0.0) & (norm <= r)
    slip = closed & ~stick
    Pi = np.zeros((m, b))
    dPi = np.zeros((m, b, b))
    Pi[closed, 0] = sN[closed]
    dPi[closed, 0, 0] = 1.0
    Pi[stick, 1:] = sT[stick]
    dPi[stick, 1:, 1:] = np.eye(b - 1)
    u = np.divide(sT, norm[:, None], out=np.zeros_like(sT), where=norm[:, None] > 0.0)
    Pi[slip, 1:] = r[slip, None] * u[slip]
    dPi[slip, 1:, 0] = mu[slip, None] * u[slip]
    ratio = np.divide(r, norm, out=np.zeros_like(r), where=norm > 0.0)
    uu = np.eye(b - 1)[None] - u[:, :, None] * u[:, None, :]
    dPi[slip, 1:, 1:] = ratio[slip, None, None] * uu[slip]
    status = np.where(stick, 1, np.where(slip, 2, 0))
    return Pi, dPi, status


def solve_coulomb(c, D, p, k, mu, nt, x0=None, tol=0.0, max_iter=50, stats=None):
    """Multipliers x of m frictional contacts (and any equality rows after them) with
    w = c + k D x and R(x) = k x − Π(k x − p w) = 0 (see :func:`_newton`).

    Semi-smooth Newton first; where it does not converge (the Newton of the disk cone is
    not globally convergent when D couples contacts strongly), a nonsmooth Gauss–Seidel over
    the contacts, each solved exactly on its own, comes near the solution and Newton
    finishes from there. ``stats`` (:class:`fecontact.contact.stats.CoulombStats`, or None)
    receives the counts of the work. Returns (x, status (m,), iterations); raises
    ``RuntimeError`` when neither converges.
    """
    stats = CoulombStats() if stats is None else stats
    stats.solves += 1
    p = _isotropic(np.asarray(p, dtype=float), len(mu), nt)
    if len(mu) == 1 and len(c) == 1 + nt:  # one contact: its law solved exactly
        x = _local(c, D, p, k, float(mu[0]), nt, x0, tol, stats)
        if x is not None:
            R, status = _settled(c, D, k, np.asarray(mu, dtype=float), nt, x)
            if R <= tol:
                return x, status, 1
    try:
        return _newton(c, D, p, k, mu, nt, x0, tol, max_iter, stats)
    except _NotConverged:
        stats.gauss_seidel_solves += 1
    x, sweeps = _gauss_seidel(c, D, p, k, np.asarray(mu, dtype=float), nt, x0, tol, stats)
    try:
        x, status, its = _newton(c, D, p, k, mu, nt, x, tol, max_iter, stats)
    except _NotConverged as err:
        R, status = _settled(c, D, k, np.asarray(mu, dtype=float), nt, x)
        if R <= tol:  # Gauss–Seidel converged where Newton's polish did not
            return x, status, sweeps
        msg = f"frictional contact: {err} (after {sweeps} Gauss-Seidel sweeps)"
        raise RuntimeError(msg) from None
    return x, status, its + sweeps


class _NotConverged(Exception):
    pass


def _settled(c, D, k, mu, nt, x):
    """:func:`coulomb_violation` at w = c + k D x."""
    return coulomb_violation(c + k * (D @ x), x, mu, nt)


def coulomb_residual(w, x, p, k, mu, nt) -> float:
    """max |R_i/p_i| (units of w) of the Alart–Curnier residual R = k x − Π(k x − p w) of m
    frictional contacts (no equality rows): zero exactly where the law holds, for any p.
    Unlike :func:`coulomb_violation` it weighs a force by what it does: a vanishing force
    with a slip counts as open, not as a stick that creeps."""
    mu = np.asarray(mu, dtype=float)
    p = _isotropic(np.asarray(p, dtype=float), len(mu), nt)
    sigma = k * x - p * w
    Pi = coulomb_projection(sigma.reshape(len(mu), 1 + nt), mu)[0].ravel()
    return float(np.max(np.abs((k * x - Pi) / p), initial=0.0))


def coulomb_violation(w, x, mu, nt):
    """The largest violation (in units of w) of the law by the rows w and multipliers x
    (any positive scale of the force), measured without p: normal complementarity, the
    cone, zero slip where it sticks, slip against Λ_T where it slips; and the status of
    each contact (0 open, 1 stick, 2 slip)."""
    mu = np.asarray(mu, dtype=float)
    m, b = len(mu), 1 + nt
    xs, ws = x[: m * b].reshape(m, b), w[: m * b].reshape(m, b)
    xn, xt, wn, wt = xs[:, 0], xs[:, 1:], ws[:, 0], ws[:, 1:]
    closed = xn > 0.0
    cone = np.linalg.norm(xt, axis=1)
    slip = closed & (cone >= mu * xn * (1 - 1e-12)) & (np.linalg.norm(wt, axis=1) > 0)
    stick = closed & ~slip
    viol = [np.maximum(-wn, 0.0), np.where(closed, np.abs(wn), 0.0)]
    viol.append(np.where(stick, np.linalg.norm(wt, axis=1), 0.0))
    # the slip rate must lie along −Λ_T: no component across Λ_T, none along it
    u = np.divide(xt, cone[:, None], out=np.zeros_like(xt), where=cone[:, None] > 0)
    across = wt - np.einsum("md,md->m", wt, u)[:, None] * u
    viol.append(np.where(slip, np.linalg.norm(across, axis=1), 0.0))
    viol.append(np.where(slip, np.maximum(np.einsum("md,md->m", wt, u), 0.0), 0.0))
    if x.size > m * b:
        viol.append(np.abs(w[m * b :]))
    status = np.where(stick, 1, np.where(slip, 2, 0))
    return max(float(np.max(v, initial=0.0)) for v in viol), status


def _isotropic(p: np.ndarray, m: int, nt: int) -> np.ndarray:
    """One p for the tangent rows of each contact, their mean: with different ones the
    fixed point puts Λ_T against P_T w_T instead of against the slip w_T (no longer the
    maximum dissipation of Coulomb's disk)."""
    p = p.copy()
    tangential = p[: m * (1 + nt)].reshape(m, 1 + nt)[:, 1:]
    tangential[:] = tangential.mean(axis=1, keepdims=True)
    return p


def _gauss_seidel(c, D, p, k, mu, nt, x0, tol, stats, max_sweeps=2000):
    """Sweeps over the contacts (then the equality rows as one block), each contact's law
    solved exactly with the others' multipliers fixed, until the largest change of w is
    below ``tol`` or ``max_sweeps``. Returns (x, sweeps)."""
    m, b = len(mu), 1 + nt
    N = len(c)
    x = np.zeros(N) if x0 is None else np.asarray(x0, dtype=float).copy()
    blocks = [np.arange(j * b, (j + 1) * b) for j in range(m)]
    eq = np.arange(m * b, N)
    kD = k * D
    sweep = 0
    while sweep < max_sweeps:
        sweep += 1
        change, stuck = 0.0, False
        for j, rows in enumerate(blocks):
            Djj = D[np.ix_(rows, rows)]
            local = c[rows] + kD[rows] @ x - k * (Djj @ x[rows])
            xj = _local(local, Djj, p[rows], k, mu[j], nt, x[rows], tol, stats)
            if xj is None:
                stuck = True  # kept for this sweep; the others move on
                continue
            change = max(change, float(np.max(np.abs(k * (Djj @ (xj - x[rows]))))))
            x[rows] = xj
        if eq.size:
            rhs = c[eq] + kD[eq] @ x - kD[np.ix_(eq, eq)] @ x[eq]
            xe = np.linalg.lstsq(kD[np.ix_(eq, eq)], -rhs, rcond=None)[0]
            change = max(change, float(np.max(np.abs(kD[np.ix_(eq, eq)] @ (xe - x[eq])))))
            x[eq] = xe
        if change <= tol and not stuck:
            break
    return x, sweep


def _local(c, D, p, k, mu, nt, x0, tol, stats):
    """One contact's law with w = c + k D x, exact: the first of open, stick and slip whose
    conditions hold (none of which involves p); in 3D the slip direction is the root of a
    function of one angle (:func:`_slip_direction`), Newton only where none is found. None
    when no answer is found."""
    if c[0] >= 0.0:
        return np.zeros(1 + nt)
    kD = k * D
    try:
        x = np.linalg.solve(kD, -c)
    except np.linalg.LinAlgError:
        x = None
    if x is not None and x[0] >= 0.0 and np.linalg.norm(x[1:]) <= mu * x[0]:
        return x
    if nt == 1:
        for s in (1.0, -1.0):
            den = kD[0, 0] + s * mu * kD[0, 1]
            if den <= 0.0:
                continue
            xn = -c[0] / den
            x = np.array([xn, s * mu * xn])
            if xn >= 0.0 and s * (c[1] + kD[1] @ x) <= 0.0:
                return x
        return None
    x = _slip_direction(c, kD, mu)
    if x is not None:
        return x
    try:
        return _newton(c, D, p, k, np.array([mu]), nt, x0, 0.1 * tol, 50, stats)[0]
    except _NotConverged:
        return None


def _slip_direction(c, D, mu, samples=72):
    """Slip of one 3D contact with w = c + D x and c_N < 0: x = x_N (1, −μu) with
    u = (cos θ, sin θ) the direction of the slip, w_N = 0, and the slip w_T = s u, s ≥ 0.
    With b(θ) = D_TN − μ D_TT u and d(θ) = D_NN − μ D_NT·u, w_N = 0 gives x_N = −c_N/d, and
    the slip is along u where

        F(θ) = d (u × c_T) − c_N (u × b) = 0   (d w_T × u, free of the poles of x_N),

    bracketed on ``samples`` angles and solved by Brent's method; the first root with
    d > 0 (x_N ≥ 0) and d s ≥ 0 is the answer (None if none)."""
    from scipy.optimize import brentq  # lazily: scipy.optimize takes 0.1 s to import

    def parts(theta):
        u = np.array([np.cos(theta), np.sin(theta)])  # (2, n)
        d = D[0, 0] - mu * (D[0, 1:] @ u)
        b = D[1:, :1] - mu * (D[1:, 1:] @ u)
        cross = d * (u[0] * c[2] - u[1] * c[1]) - c[0] * (u[0] * b[1] - u[1] * b[0])
        along = d * (u.T @ c[1:]) - c[0] * np.sum(u * b, axis=0)
        return cross, along, d, u

    theta = np.linspace(0.0, 2.0 * np.pi, samples + 1)
    f = parts(theta)[0]
    for i in np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:])):
        root = brentq(lambda a: parts(np.array([a]))[0][0], theta[i], theta[i + 1], xtol=1e-15)
        _, along, d, u = parts(np.array([root]))
        if d[0] > 0.0 and along[0] >= 0.0:
            xn = -c[0] / d[0]
            return np.concatenate([[xn], -mu * xn * u[:, 0]])
    return None


def _newton(c, D, p, k, mu, nt, x0, tol, max_iter, stats):
    """Multipliers x of m frictional contacts (and any equality rows after them) with
    w = c + k D x and R(x) = k x − Π(k x − p w) = 0.

    Rows are ordered contact by contact (normal, then its ``nt`` tangents), then any
    bilateral rows (joints: Π = identity, so w = 0 there). ``D`` is the Delassus matrix
    G H⁻¹ Gᵀ of the rows, ``p`` one augmentation per row (> 0; the same on the tangent rows
    of a contact, see :func:`_isotropic`), ``mu`` (m,) the friction
    coefficients. Semi-smooth Newton on R/p, a residual in the units of w: on the rows where
    Π is the identity (closed normal, stick, bilateral) R/p = w, evaluated as such, so that
    the equations w = 0 keep their accuracy for any p (k x − σ would cancel to round-off of
    k x). Backtracking on |R/p|²; it stops when every |R_i/p_i| is below ``tol``. Returns
    (x, status (m,), iterations); raises ``RuntimeError`` when it does not converge.
    """
    mu = np.asarray(mu, dtype=float)
    m, b = len(mu), 1 + nt
    nc, N = len(mu) * b, len(c)
    x = np.zeros(N) if x0 is None else np.asarray(x0, dtype=float).copy()
    kD = k * D
    dsigma = k * np.eye(N) - p[:, None] * kD

    def residual(x):
        w = c + kD @ x
        sigma = k * x - p * w
        Pi, dPi, status = coulomb_projection(sigma[:nc].reshape(m, b), mu)
        dPi = _block_diagonal(dPi, N)
        ident = np.diagonal(dPi) == 1.0
        ident[nc:] = True
        ident[:nc] &= np.repeat(status == 1, b) | (np.arange(nc) % b == 0)
        R = np.where(ident, w, (k * x - np.concatenate([Pi.ravel(), sigma[nc:]])) / p)
        return R, (dPi, ident), status

    R, lin, status = residual(x)
    for it in range(max_iter + 1):
        err = np.max(np.abs(R), initial=0.0)
        if not np.isfinite(err):
            raise RuntimeError("frictional contact: non-finite residual")
        if err <= tol:
            stats.iterations += it
            return x, status, it
        if it == max_iter:
            break
        directions = _newton_direction(kD, dsigma, *lin, p, k, R, stats)
        x, R, lin, status = _backtrack(residual, x, directions, R, stats)
    raise _NotConverged(f"residual {err:.3e} above {tol:.3e} after {max_iter} iterations")


def _jacobian(kD, dsigma, dPi, ident, p, k):
    """∂(R/p)/∂x: kD on the rows evaluated as w, (k I − ∂Π ∂σ/∂x)/p on the others."""
    J = -(dPi @ dsigma)
    J[np.diag_indices(len(J))] += k
    return np.where(ident[:, None], kD, J / p[:, None])


def _newton_direction(kD, dsigma, dPi, ident, p, k, R, stats, rcond=1e-10):
    """The semi-smooth Newton update dx of R/p.

    More closed rows than the bodies' degrees of freedom (a cylinder on the rim points of
    its base, a box face with many points) make D = A H⁻¹ Aᵀ singular, and with it the
    Newton matrix on sticking contacts. An LU then returns a step whose components in the
    null space of D are round-off amplified by the inverse of a pivot near zero: they do not
    move the bodies (H⁻¹Aᵀ x ignores them), but they move σ = k x − p w and with it each
    contact's status, and the backtracking stalls. Where the LU's pivots show the matrix
    singular (the smallest below ``rcond`` of the largest), the step is the minimum-norm
    solution of the truncated singular value decomposition: Newton's step on the range,
    none along the multipliers the contacts cannot tell apart. The residual stays the exact
    one, so the answer is exact. Counted in ``stats.minimum_norm_steps``.

    Returns the directions to try in turn: on a singular matrix the minimum-norm one, then
    the LU's where its pivots are nonzero. Where the rows are inconsistent for the current
    statuses (R outside the range of J) the minimum-norm step stops at a nonzero minimum of
    |R|²; the LU's long step crosses into other statuses (a tumbling box's velocity jumps
    needed it)."""
    J = _jacobian(kD, dsigma, dPi, ident, p, k)
    lu, piv, _ = dgetrf(J)  # (LAPACK's getrf and getrs: np.linalg.solve's own path)
    pivots = np.abs(np.diagonal(lu))
    if pivots.min(initial=np.inf) > rcond * pivots.max(initial=0.0):
        return (dgetrs(lu, piv, -R)[0],)
    stats.minimum_norm_steps += 1
    lu_step = dgetrs(lu, piv, -R)[0] if np.all(pivots > 0.0) else None
    return np.linalg.lstsq(J, -R, rcond=rcond)[0], lu_step


def _backtrack(residual, x, directions, R, stats):
    """x + s dx with the largest s = 2⁻ⁱ that decreases |R|² (Armijo), over the
    ``directions`` in turn (None: none); the full step of the last when none of 20 does
    along any (the merit of a nonsmooth residual can rise across a kink), counted."""
    f0 = R @ R
    directions = [d for d in directions if d is not None]
    for dx in directions:
        s = 1.0
        for _ in range(20):
            xs = x + s * dx
            Rs, lin, status = residual(xs)
            if Rs @ Rs <= (1.0 - 1e-4 * s) * f0:
                return xs, Rs, lin, status
            s *= 0.5
            stats.line_search_cuts += 1
    stats.full_steps_forced += 1
    xs = x + directions[-1]
    return (xs, *residual(xs))


def _block_diagonal(blocks: np.ndarray, N: int) -> np.ndarray:
    """The (N, N) matrix of the contacts' (m, b, b) blocks followed by an identity."""
    m, b, _ = blocks.shape
    out = np.zeros((N, N))
    idx = np.arange(m)[:, None] * b + np.arange(b)
    out[idx[:, :, None], idx[:, None, :]] = blocks
    tail = np.arange(m * b, N)
    out[tail, tail] = 1.0
    return out
