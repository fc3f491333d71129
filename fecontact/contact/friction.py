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

__all__ = [
    "COULOMB",
    "coulomb_projection",
    "point_tangents",
    "solve_coulomb",
    "tangent_basis",
]

COULOMB = {"solves": 0, "iterations": 0, "line_search_cuts": 0, "full_steps_forced": 0}
"""Frictional contact solves of this process: Newton iterations, backtracking cuts of the
merit |R|², and updates taken in full after the backtracking found no decrease (a kink of the
nonsmooth residual). Runs report their share in ``summary.json``."""


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


def solve_coulomb(c, D, p, k, mu, nt, x0=None, tol=0.0, max_iter=50):
    """Multipliers x of m frictional contacts (and any equality rows after them) with
    w = c + k D x and R(x) = k x − Π(k x − p w) = 0.

    Rows are ordered contact by contact (normal, then its ``nt`` tangents), then any
    bilateral rows (joints: Π = identity, so w = 0 there). ``D`` is the Delassus matrix
    G H⁻¹ Gᵀ of the rows, ``p`` one augmentation per row (> 0), ``mu`` (m,) the friction
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
    COULOMB["solves"] += 1
    for it in range(max_iter + 1):
        err = np.max(np.abs(R), initial=0.0)
        if not np.isfinite(err):
            raise RuntimeError("frictional contact: non-finite residual")
        if err <= tol:
            COULOMB["iterations"] += it
            return x, status, it
        if it == max_iter:
            break
        dPi, ident = lin
        J = -(dPi @ dsigma)
        J[np.diag_indices(N)] += k
        J = np.where(ident[:, None], kD, J / p[:, None])
        try:
            dx = np.linalg.solve(J, -R)
        except np.linalg.LinAlgError:
            dx = np.linalg.lstsq(J, -R, rcond=None)[0]
        x, R, lin, status = _backtrack(residual, x, dx, R)
    raise RuntimeError(
        f"frictional contact: residual {err:.3e} above {tol:.3e} after {max_iter} iterations"
    )


def _backtrack(residual, x, dx, R):
    """x + s dx with the largest s = 2⁻ⁱ that decreases |R|² (Armijo); the full step when
    none of 20 does (the merit of a nonsmooth residual can rise across a kink), counted."""
    f0 = R @ R
    s = 1.0
    for _ in range(20):
        xs = x + s * dx
        Rs, lin, status = residual(xs)
        if Rs @ Rs <= (1.0 - 1e-4 * s) * f0:
            return xs, Rs, lin, status
        s *= 0.5
        COULOMB["line_search_cuts"] += 1
    COULOMB["full_steps_forced"] += 1
    xs = x + dx
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
