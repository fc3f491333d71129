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

from ..rotations import cross
from .coulomb_newton import NotConverged, coulomb_projection, newton
from .friction_cases import planar_cases
from .friction_redundant import grazing_closed, least_norm, one_open, proximal, without_round_off
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
    the first of the axes x, y, z with |n_i| < 0.6 projected on the plane (at least 0.8 of
    it remains), t₂ = n × t₁. Coulomb's disk is isotropic, so the choice in the plane only
    names the components of the output, but multipliers carried from one evaluation to the
    next (a relinearization, a warm start) need it not to jump where normals usually lie:
    this one jumps only far from the coordinate axes (the axis least aligned with n jumps
    where two components of n tie in magnitude, along the axes themselves)."""
    n = np.asarray(n, dtype=float)
    if n.shape[1] == 2:
        return np.stack([n[:, 1], -n[:, 0]], axis=1)[:, None, :]
    # (a unit vector has a component below 1/√3: with |n_x|, |n_y| ≥ 0.6, |n_z| ≤ 0.53)
    axis = np.eye(3)[np.argmax(np.abs(n) < 0.6, axis=1)]
    t1 = axis - np.einsum("mi,mi->m", axis, n)[:, None] * n
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return np.stack([t1, cross(n, t1)], axis=1)


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


def solve_coulomb(
    c, D, p, k, mu, nt, x0=None, tol=0.0, max_iter=50, stats=None, minimum_norm=False,
    cold_start=True,
):  # fmt: skip
    """Multipliers x of m frictional contacts (and any equality rows after them) with
    w = c + k D x and R(x) = k x − Π(k x − p w) = 0 (see :func:`newton`).

    Semi-smooth Newton first; where it does not converge (the Newton of the disk cone is
    not globally convergent when D couples contacts strongly), a nonsmooth Gauss–Seidel over
    the contacts, each solved exactly on its own, comes near the solution and Newton
    finishes from there. ``minimum_norm`` (decided once per run, for models whose rows can
    be redundant): of a family of solutions, the one of least norm (:func:`_least_norm`),
    and of the solutions reached from ``x0`` and from zero the least-norm; ``cold_start``
    False keeps the one from ``x0`` alone (a relinearization of a problem just solved from
    both, whose solution ``x0`` is), the cold start only where the warm one fails.
    ``stats`` (:class:`fecontact.contact.stats.CoulombStats`, or None) receives the counts
    of the work. Returns (x, status (m,), iterations); raises ``RuntimeError`` when neither
    converges.
    """
    stats = CoulombStats() if stats is None else stats
    stats.solves += 1
    p = _isotropic(np.asarray(p, dtype=float), len(mu), nt)
    if not minimum_norm:
        return _solve(c, D, p, k, mu, nt, x0, tol, max_iter, stats)[:3]
    mu = np.asarray(mu, dtype=float)
    found, failure = [], None
    # several closed contacts with friction can have distinct solutions (three corners
    # slipping and the fourth lifting, or all four slipping): the warm start and the cold
    # one may reach different ones, and the least-norm of them is kept. Where the warm
    # start fails the cold one is tried all the same: on redundant rows whether Newton
    # converges from a warm start is its path's (a box on a box, 27 rows on 12 dofs:
    # from the last step's impulses it failed at the default p and converged at p × 1e3,
    # and from zero at every p, to the same rates)
    cases = stats.case_solves
    for start in (x0,) if x0 is None or len(mu) == 1 else (x0, None):
        if start is None and found and not cold_start:
            break
        try:
            x, status, its = _solve(c, D, p, k, mu, nt, start, tol, max_iter, stats, True)
        except RuntimeError as err:
            failure = err
            continue
        if start is None and failure is not None:
            stats.cold_restarts += 1
        # (a solve by the law's cases has them all: a cold start finds none of lower norm)
        cold_start &= stats.case_solves == cases
        x, status = least_norm(c, D, p, k, mu, nt, x, tol, stats)
        found.append(without_round_off(x, status, len(mu), nt) + (its,))
    if not found:
        raise failure
    x, status, its = min(found, key=lambda f: np.linalg.norm(f[0]))
    if len(found) == 2 and np.max(np.abs(k * D @ (found[0][0] - found[1][0]))) > tol:
        stats.distinct_solutions += 1
    x, status = grazing_closed(c, D, p, k, mu, nt, x, status, tol, stats)
    return x, status, its


def _solve(c, D, p, k, mu, nt, x0, tol, max_iter, stats, redundant=False):
    """:func:`solve_coulomb` without the choice among a family of solutions."""
    if len(mu) == 1 and len(c) == 1 + nt:  # one contact: its law solved exactly
        x = _local(c, D, p, k, float(mu[0]), nt, x0, tol, stats)
        if x is not None:
            R, status = _settled(c, D, k, np.asarray(mu, dtype=float), nt, x)
            if R <= tol:
                return x, status, 1
    try:
        return newton(c, D, p, k, mu, nt, x0, tol, max_iter, stats)
    except NotConverged:
        pass
    found = _exact_fallbacks(c, D, p, k, mu, nt, x0, tol, max_iter, stats, redundant)
    if found is not None:
        return found
    stats.gauss_seidel_solves += 1
    x, sweeps = _gauss_seidel(c, D, p, k, np.asarray(mu, dtype=float), nt, x0, tol, stats)
    try:
        x, status, its = newton(c, D, p, k, mu, nt, x, tol, max_iter, stats)
    except NotConverged as err:
        R, status = _settled(c, D, k, np.asarray(mu, dtype=float), nt, x)
        if R <= tol:  # Gauss–Seidel converged where Newton's polish did not
            return x, status, sweeps
        msg = f"frictional contact: {err} (after {sweeps} Gauss-Seidel sweeps)"
        raise RuntimeError(msg) from None
    return x, status, its + sweeps


def _exact_fallbacks(c, D, p, k, mu, nt, x0, tol, max_iter, stats, redundant):
    """Where Newton did not converge, the solves that end on the law without Gauss–Seidel:
    a few planar contacts by the law's cases (:func:`.friction_cases.planar_cases`), and
    on redundant rows the proximal point method, then one contact left out. Returns
    (x, status, iterations) or None."""
    mu = np.asarray(mu, dtype=float)
    if nt == 1:
        x = planar_cases(c, D, p, k, mu, tol)
        if x is not None:
            stats.case_solves += 1
            return x, _settled(c, D, k, mu, nt, x)[1], 1
    if not redundant or len(mu) == 1:
        return None
    for fallback in (proximal, one_open):
        found = fallback(c, D, p, k, mu, nt, x0, tol, max_iter, stats)
        if found is not None:
            return found[0], _settled(c, D, k, mu, nt, found[0])[1], found[1]
    return None


def _settled(c, D, k, mu, nt, x):
    """:func:`coulomb_violation` at w = c + k D x."""
    return coulomb_violation(c + k * (D @ x), x, mu, nt)


def coulomb_residual(w, x, p, k, mu, nt, scale: float = 1.0) -> float:
    """The largest error (units of w) of the Alart–Curnier residual R = k x − Π(k x − p w)
    of m frictional contacts (no equality rows): zero exactly where the law holds, for any
    p. Where Π is the identity (a closed normal, a sticking tangent) R/p is w; on the other
    rows R/p is a force error over p, weighed by ``scale`` = p_i D_ii (the augmentation over
    the rows' effective mass) into the change of w it makes at its own row, so that the
    measure does not grow with p (exactly |R/p| at the default scale 1). Unlike
    :func:`coulomb_violation` it weighs a force by what it does: a vanishing force with a
    slip counts as open, not as a stick that creeps."""
    mu = np.asarray(mu, dtype=float)
    p = _isotropic(np.asarray(p, dtype=float), len(mu), nt)
    sigma = k * x - p * w
    Pi, _, status = coulomb_projection(sigma.reshape(len(mu), 1 + nt), mu)
    b = 1 + nt
    normal = np.arange(len(w)) % b == 0
    ident = np.where(normal, sigma > 0.0, np.repeat(status == 1, b))
    R = (k * x - Pi.ravel()) / p
    return float(np.max(np.abs(np.where(ident, R, R * scale)), initial=0.0))


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
    eq = np.arange(m * b, N)
    kD = k * D
    # each contact's rows and diagonal block, and the joints' block, taken once: views of
    # the values the sweeps read (the same products, bit for bit)
    rows = [slice(j * b, (j + 1) * b) for j in range(m)]
    idx = np.arange(m * b).reshape(m, b)
    blocks = D[idx[:, :, None], idx[:, None, :]]
    kD_eq = kD[np.ix_(eq, eq)]
    sweep = 0
    while sweep < max_sweeps:
        sweep += 1
        change, stuck = 0.0, 0
        for j, r in enumerate(rows):
            Djj = blocks[j]
            local = c[r] + kD[r] @ x - k * (Djj @ x[r])
            xj = _local(local, Djj, p[r], k, mu[j], nt, x[r], tol, stats)
            if xj is None:
                stuck += 1  # kept for this sweep; the others move on
                continue
            change = max(change, float(np.max(np.abs(k * (Djj @ (xj - x[r]))))))
            x[r] = xj
        if eq.size:
            rhs = c[eq] + kD[eq] @ x - kD_eq @ x[eq]
            xe = np.linalg.lstsq(kD_eq, -rhs, rcond=None)[0]
            change = max(change, float(np.max(np.abs(kD_eq @ (xe - x[eq])))))
            x[eq] = xe
        if change <= tol and not stuck:
            break
        if stuck == m and not eq.size:
            # no contact's law has an answer with the others held (a Delassus block that
            # is not positive, as at a diverging iterate): further sweeps repeat this one
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
        return newton(c, D, p, k, np.array([mu]), nt, x0, 0.1 * tol, 50, stats)[0]
    except NotConverged:
        return None


_ANGLES = np.linspace(0.0, 2.0 * np.pi, 73)
"""The angles on which :func:`_slip_direction` brackets its roots by default."""


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

    # F at one angle in floats, the products in the order of ``parts``: Brent's method
    # calls it some 10 times per root, where numpy's calls on 2-vectors cost more than the
    # arithmetic (a Gauss–Seidel solve of eight 3D contacts spent 60 % of its time there)
    (c_n, c_1, c_2), d00 = c.tolist(), float(D[0, 0])
    (d01, d02), (d10, d20) = D[0, 1:].tolist(), D[1:, 0].tolist()
    (d11, d12), (d21, d22) = D[1:, 1:].tolist()

    def cross_at(a):
        u0, u1 = np.cos(a), np.sin(a)
        d = d00 - mu * (d01 * u0 + d02 * u1)
        b0, b1 = d10 - mu * (d11 * u0 + d12 * u1), d20 - mu * (d21 * u0 + d22 * u1)
        return d * (u0 * c_2 - u1 * c_1) - c_n * (u0 * b1 - u1 * b0)

    theta = _ANGLES if samples == 72 else np.linspace(0.0, 2.0 * np.pi, samples + 1)
    f = parts(theta)[0]
    for i in np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:])):
        root = brentq(cross_at, theta[i], theta[i + 1], xtol=1e-15)
        _, along, d, u = parts(np.array([root]))
        if d[0] > 0.0 and along[0] >= 0.0:
            xn = -c[0] / d[0]
            return np.concatenate([[xn], -mu * xn * u[:, 0]])
    return None
