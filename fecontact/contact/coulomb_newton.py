"""The semi-smooth Newton of Coulomb's law in the Alart–Curnier form (see
:mod:`fecontact.contact.friction`): the projection Π on the cone and its generalized
Jacobian, the residual R/p and its Jacobian, the Newton update (minimum-norm on a singular
matrix) and its backtracking."""

from __future__ import annotations

import numpy as np
from scipy.linalg.lapack import dgetrf, dgetrs

from ..linalg.svd import lstsq

__all__ = [
    "NotConverged",
    "coulomb_projection",
    "edge_on_slip",
    "newton",
    "newton_jacobian",
    "newton_residual",
    "penalty_factor",
    "stopping_error",
]


class NotConverged(Exception):
    """Newton did not bring the residual below its tolerance."""


def coulomb_projection(sigma: np.ndarray, mu: np.ndarray, jacobian: bool = True):
    """Π(σ) and its generalized Jacobian for contacts σ (m, 1 + nt), normal first.

    Returns (Π (m, b), ∂Π/∂σ (m, b, b), status (m,)): 0 open, 1 stick, 2 slip. A contact
    with μ = 0 slips with zero tangential force whatever σ_T. ``jacobian`` False leaves
    ∂Π/∂σ out (None): a line search's trial points need Π alone."""
    m, b = sigma.shape
    sN, sT = sigma[:, 0], sigma[:, 1:]
    closed = sN > 0.0
    r = mu * np.maximum(sN, 0.0)
    norm = np.linalg.norm(sT, axis=1)
    stick = closed & (r > 0.0) & (norm <= r)
    slip = closed & ~stick
    u = np.divide(sT, norm[:, None], out=np.zeros_like(sT), where=norm[:, None] > 0.0)
    Pi = np.empty((m, b))
    Pi[:, 0] = np.where(closed, sN, 0.0)
    Pi[:, 1:] = np.where(stick[:, None], sT, np.where(slip[:, None], r[:, None] * u, 0.0))
    status = np.where(stick, 1, np.where(slip, 2, 0))
    if not jacobian:
        return Pi, None, status
    dPi = np.zeros((m, b, b))
    dPi[closed, 0, 0] = 1.0
    dPi[stick, 1:, 1:] = np.eye(b - 1)
    dPi[slip, 1:, 0] = mu[slip, None] * u[slip]
    ratio = np.divide(r, norm, out=np.zeros_like(r), where=norm > 0.0)
    uu = np.eye(b - 1)[None] - u[:, :, None] * u[:, None, :]
    dPi[slip, 1:, 1:] = ratio[slip, None, None] * uu[slip]
    return Pi, dPi, status


def newton(c, D, p, k, mu, nt, x0, tol, max_iter, stats, closing=None):
    """Multipliers x of m frictional contacts (and any equality rows after them) with
    w = c + k D x and R(x) = k x − Π(k x − p w) = 0.

    Rows are ordered contact by contact (normal, then its ``nt`` tangents), then any
    bilateral rows (joints: Π = identity, so w = 0 there). ``D`` is the Delassus matrix
    G H⁻¹ Gᵀ of the rows, ``p`` one augmentation per row (> 0; the same on the tangent rows
    of a contact, see :func:`fecontact.contact.friction.solve_coulomb`), ``mu`` (m,) the friction
    coefficients. Semi-smooth Newton on R/p, a residual in the units of w: on the rows where
    Π is the identity (closed normal, stick, bilateral) R/p = w, evaluated as such, so that
    the equations w = 0 keep their accuracy for any p (k x − σ would cancel to round-off of
    k x). Backtracking on |R/p|²; it stops when the law's error, in the units of w and
    whatever p, is below ``tol`` on every row (:func:`stopping_error`). ``closing`` (m,)
    bool: contacts held on their closed branch (:func:`newton_residual`). Returns (x,
    status (m,), iterations); raises ``RuntimeError`` when it does not converge.
    """
    mu = np.asarray(mu, dtype=float)
    nc, N = len(mu) * (1 + nt), len(c)
    x = np.zeros(N) if x0 is None else np.asarray(x0, dtype=float).copy()
    kD = k * D
    dsigma = k * np.eye(N) - p[:, None] * kD

    def residual(x, jacobian=True):
        return newton_residual(x, c, kD, p, k, mu, nc, closing, jacobian=jacobian)

    def merits(X):
        return trial_merits(X, c, kD, p, k, mu, nc, closing)

    R, lin, status = residual(x)
    weight = penalty_factor(D, p, nc, 1 + nt)
    for it in range(max_iter + 1):
        err = stopping_error(R, lin[1], weight)
        if not np.isfinite(err):
            raise RuntimeError("frictional contact: non-finite residual")
        if err <= tol:
            stats.iterations += it
            return x, status, it
        if it == max_iter:
            break
        directions = _newton_direction(kD, dsigma, *lin, p, k, R, stats)
        forced, start = stats.full_steps_forced, x
        x, R, lin, status = _backtrack(residual, merits, x, directions, R, stats)
        if stats.full_steps_forced > forced and _round_off_move(x, start):
            stats.stalled_newtons += 1
            raise NotConverged(f"residual {err:.3e} above {tol:.3e}: stalled at iteration {it}")
    raise NotConverged(f"residual {err:.3e} above {tol:.3e} after {max_iter} iterations")


def _round_off_move(x, start) -> bool:
    """Whether the update from ``start`` to ``x`` moved it by its last bits alone (4 ulps of
    its largest entry). Where no cut of a Newton step decreased |R|² and the step taken in
    full is that small, Newton sits on a stationary point of |R|² that is not a solution (R
    outside the Jacobian's range on these statuses): its further steps are round-off too,
    and every one of them costs the 20 cuts of the backtracking. A chain of three pinned
    bars on a rough floor: |R/p| stayed at 9.95e-7 (tolerance 2.5e-9) for the 46
    iterations left, steps of 1e-16 |x|, then failed as it does now at once."""
    scale = np.max(np.abs(start), initial=0.0)
    return bool(np.max(np.abs(x - start), initial=0.0) <= 4.0 * np.finfo(float).eps * scale)


def newton_residual(x, c, kD, p, k, mu, nc, closing=None, jacobian=True, edge=0.0):
    """R/p of :func:`newton` at x (w where Π is the identity), the parts of its Jacobian
    (∂Π, the rows evaluated as w) and the contacts' status. ``closing`` (m,) bool: contacts
    whose Jacobian and status are taken on their closed branch, σ_N at 0⁺ where it is ≤ 0
    (:func:`fecontact.contact.friction_redundant.least_norm`). ``edge`` > 0: sticking
    contacts whose multipliers lie at the edge of their cone, |x_T| ≥ (1 − ``edge``) μ x_N,
    are taken on their slip branch (:func:`edge_on_slip`). ``jacobian`` False: ∂Π is
    None (the rows evaluated as w are read from the status alone: closed normals, sticking
    tangents and the equality rows, where ∂Π has its unit diagonal)."""
    m, N = len(mu), len(c)
    b = nc // m if m else 1
    w = c + kD @ x
    sigma = k * x - p * w
    if closing is not None:
        sigma_n = sigma[:nc:b]
        sigma_n[closing & (sigma_n <= 0.0)] = np.finfo(float).tiny
    if edge > 0.0 and m:
        edge_on_slip(sigma[:nc].reshape(m, b), x[:nc].reshape(m, b), mu, edge)
    Pi, dPi, status = coulomb_projection(sigma[:nc].reshape(m, b), mu, jacobian)
    ident = np.ones(N, bool)
    normal = np.arange(nc) % b == 0
    ident[:nc] = np.where(normal, np.repeat(status > 0, b), np.repeat(status == 1, b))
    R = np.where(ident, w, (k * x - np.concatenate([Pi.ravel(), sigma[nc:]])) / p)
    return R, (None if dPi is None else _block_diagonal(dPi, N), ident), status


def edge_on_slip(sigma, x, mu, band):
    """Move σ_T (m, b, in place) of the contacts that stick with their multipliers x at the
    edge of the cone, |x_T| ≥ (1 − ``band``) μ x_N, just outside it: their slip branch.
    There stick and slip are both the law's answer and round-off picks the status; the
    stick branch's Jacobian lets x_T grow past the cone, the slip branch's holds it on the
    edge (:func:`fecontact.contact.friction_redundant.least_norm`)."""
    r = mu * sigma[:, 0]
    norm = np.linalg.norm(sigma[:, 1:], axis=1)
    cone = mu * x[:, 0]
    held = (r > 0.0) & (norm > 0.0) & (norm <= r) & (cone > 0.0)
    held &= np.linalg.norm(x[:, 1:], axis=1) >= (1.0 - band) * cone
    ratio = np.divide(r, norm, out=np.zeros_like(r), where=held)
    sigma[held, 1:] *= (ratio[held] * (1.0 + 4.0 * np.finfo(float).eps))[:, None]


def stopping_error(R, ident, weight) -> float:
    """The largest error of the law in the units of w, whatever p: on the rows evaluated as
    w (``ident``), |w|; on the others (open normals, slipping or open tangents) the impulse
    error k x − Π(σ) times the inverse effective mass D_ii of its row, the change of w it
    makes there: |R_i/p_i| times ``weight`` = p_i D_ii (:func:`penalty_factor`). Judged
    by |R_i/p_i| alone, p × 1000 accepted impulse errors that moved the velocities by up
    to 1000 times the tolerance."""
    return float(np.max(np.abs(np.where(ident, R, R * weight)), initial=0.0))


def penalty_factor(D, p, nc, b):
    """p_i over the effective-mass augmentation 1/D_ii of each row (on the tangent rows of
    a contact, which share one p, over the mean of theirs): the run's penalty scale, and
    exactly 1.0 for p = 1/D_ii, so that the default scale keeps its stopping test bit for
    bit. Rows that move nothing (D_ii ≤ 0) keep the factor 1."""
    d = np.diag(D)
    moves = d > 0.0
    ref = np.divide(1.0, d, out=np.ones_like(d), where=moves)
    if nc:
        tangential = ref[:nc].reshape(-1, b)[:, 1:]
        tangential[:] = tangential.mean(axis=1, keepdims=True)
    return np.where(moves, p / ref, 1.0)


def newton_jacobian(kD, dsigma, dPi, ident, p, k):
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
    one, so the answer is exact. Counted in ``stats.minimum_norm_steps`` (and in
    ``stats.svd_fallbacks`` where the decomposition is taken again,
    :func:`fecontact.linalg.svd.lstsq`).

    Returns the directions to try in turn: on a singular matrix the minimum-norm one, then
    the LU's where its pivots are nonzero. Where the rows are inconsistent for the current
    statuses (R outside the range of J) the minimum-norm step stops at a nonzero minimum of
    |R|²; the LU's long step crosses into other statuses (a tumbling box's velocity jumps
    needed it)."""
    J = newton_jacobian(kD, dsigma, dPi, ident, p, k)
    lu, piv, _ = dgetrf(J)  # (LAPACK's getrf and getrs: np.linalg.solve's own path)
    pivots = np.abs(np.diagonal(lu))
    if pivots.min(initial=np.inf) > rcond * pivots.max(initial=0.0):
        return (dgetrs(lu, piv, -R)[0],)
    stats.minimum_norm_steps += 1
    lu_step = dgetrs(lu, piv, -R)[0] if np.all(pivots > 0.0) else None
    step, fell_back = lstsq(J, -R, rcond=rcond)
    stats.svd_fallbacks += fell_back
    return step, lu_step


def trial_merits(X, c, kD, p, k, mu, nc, closing=None):
    """|R/p|² of :func:`newton_residual` at the points X (S, N) at once (its ``edge`` 0),
    and a bound on their round-off: one product and one projection for all of the line
    search's trial points. The products' sums are in another order than one point's, and
    the law's residual is continuous across its branches, so each merit differs from the
    one point's by less than ``margin``: 2|R|δ + δ² with δ = 16 (N + 4) ε (1 + μ) times
    the sizes of the terms each row sums (|c| + |kD| |x| + k|x|/p), far above round-off."""
    S, N = X.shape
    m = len(mu)
    b = nc // m if m else 1
    W = c + X @ kD.T
    sigma = k * X - p * W
    if closing is not None:
        sigma_n = sigma[:, :nc:b]
        sigma_n[closing[None] & (sigma_n <= 0.0)] = np.finfo(float).tiny
    Pi, _, status = coulomb_projection(sigma[:, :nc].reshape(S * m, b), np.tile(mu, S), False)
    status = status.reshape(S, m)
    ident = np.ones((S, N), bool)
    normal = np.arange(nc) % b == 0
    ident[:, :nc] = np.where(normal, np.repeat(status > 0, b, 1), np.repeat(status == 1, b, 1))
    tail = np.concatenate([Pi.reshape(S, nc), sigma[:, nc:]], axis=1)
    R = np.where(ident, W, (k * X - tail) / p)
    merit = np.einsum("si,si->s", R, R)
    size = np.abs(c) + np.abs(X) @ np.abs(kD).T + k * np.abs(X) / p
    scale = 16.0 * (N + 4) * np.finfo(float).eps * (1.0 + np.max(mu, initial=0.0))
    delta = scale * np.linalg.norm(size, axis=1)
    return merit, delta * (2.0 * np.sqrt(merit) + delta)


CUTS = 20
"""Halvings of a Newton step the backtracking tries before it takes the step in full."""


def _backtrack(residual, merits, x, directions, R, stats):
    """x + s dx with the largest s = 2⁻ⁱ that decreases |R|² (Armijo), over the
    ``directions`` in turn (None: none); the full step of the last when none of ``CUTS``
    does along any (the merit of a nonsmooth residual can rise across a kink), counted.
    The trial points' residuals leave the Jacobian out (``residual(x, False)``); the point
    taken has it evaluated. The cuts' merits are first read at once (``merits``,
    :func:`trial_merits`): a cut that fails by more than their round-off is passed over,
    the others are tried in turn as one point, so that the same cut is taken (where the
    full step fails, 5 cuts on average, all of them where the step is forced: point by
    point, 2/3 of the line search of the box thrown on the slab, docs/validation/solid_sweep.md)."""
    f0 = R @ R
    directions = [d for d in directions if d is not None]
    s = 0.5 ** np.arange(CUTS)
    for dx in directions:
        close = np.ones(CUTS, bool)  # (the full step: tried as one point, most often taken)
        for i in range(CUTS):
            if i == 1:
                merit, margin = merits(x + s[1:, None] * dx)
                close[1:] = merit - margin <= (1.0 - 1e-4 * s[1:]) * f0
            if close[i]:
                xs = x + s[i] * dx
                Rs = residual(xs, False)[0]
                if Rs @ Rs <= (1.0 - 1e-4 * s[i]) * f0:
                    return (xs, *residual(xs))
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
