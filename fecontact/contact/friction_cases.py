"""Coulomb's law of a few planar contacts solved exactly by its cases.

In the plane each contact's law has four branches: open (x = 0, w_N ≥ 0), stick (w = 0,
|x_T| ≤ μ x_N), and slip either way (w_N = 0, x_T = ±μ x_N, ±w_T ≤ 0). On each combination
of branches the law is a linear system in x; its solutions whose inequalities hold are the
law's solutions, all of them. Semi-smooth Newton can stop short of them where two contacts
hold nearly one motion under different laws: a strip node's row and a disk node's row a
fraction of a cell apart, normals 11° apart, one with slip rows and one without, left the
law's error at a local minimum of |R/p|², 6.6e-6, the multiplier of the row that had to
carry the load negative and the other contact slipping on (docs/explanation/friction.md). With
m ≤ ``MOST`` contacts the 4^m systems are solved at once, and of the solutions the one of
least norm is kept: the choice that neither p nor k enters, as ``least_norm`` makes it
within a family of solutions (a singular system: the member of least norm in the
multipliers it leaves free, a slipping contact's x_N standing for its x_T too; in runs
with redundant rows ``least_norm`` then moves it to the least |x|)."""

from __future__ import annotations

import itertools

import numpy as np

from .coulomb_newton import newton_residual, penalty_factor, stopping_error

__all__ = ["MOST", "planar_cases"]

MOST = 4
"""Contacts solved by their cases: 4⁴ = 256 systems of at most 8 rows beside the joints'."""


def _cases(mu: np.ndarray) -> np.ndarray:
    """The branches (C, m) to try: 0 open, 1 stick, 2 slip with x_T = +μ x_N, 3 with
    x_T = −μ x_N; a frictionless contact has open and slip (x_T = 0) alone."""
    codes = np.array(list(itertools.product(range(4), repeat=len(mu))), dtype=int)
    frictionless = (mu == 0.0)[None] & ((codes == 1) | (codes == 3))
    return codes[~frictionless.any(axis=1)]


def _systems(c, kD, mu, codes):
    """The branches' linear systems in the multipliers they leave free, x = E y: M y = r
    (C, N, N), (C, N), and E (C, N, N). A closed contact's normal row and a sticking one's
    tangent row ask w = 0, as the joints' rows; a slipping contact's x_T is ±μ x_N through
    E, an open one's x is zero (E's columns zero, so that x holds these exactly). The rows
    and columns of the multipliers not free carry the row's own scale D_ii alone on the
    diagonal, which keeps M's singular values on one scale."""
    C, m = codes.shape
    N = len(c)
    n = 2 * np.arange(m)
    E = np.repeat(np.eye(N)[None], C, axis=0)
    held = np.ones((C, N), bool)  # (the rows w = 0, and the free multipliers)
    for j in range(m):
        opened, slips = codes[:, j] == 0, codes[:, j] >= 2
        E[opened, n[j], n[j]] = 0.0
        E[opened | slips, n[j] + 1, n[j] + 1] = 0.0
        E[slips, n[j] + 1, n[j]] = np.where(codes[slips, j] == 2, 1.0, -1.0) * mu[j]
        held[opened, n[j]] = held[opened | slips, n[j] + 1] = False
    M = np.where(held[:, :, None], np.einsum("ij,cjk->cik", kD, E), 0.0)
    idle = np.flatnonzero(~held.ravel())
    scale = np.abs(np.diag(kD))
    scale = np.where(scale > 0.0, scale, np.max(scale, initial=1.0))
    M.reshape(C, -1)[idle // N, (idle % N) * (N + 1)] = scale[idle % N]
    return M, np.where(held, -c[None], 0.0), E


def _admissible(c, kD, mu, codes, X, tol):
    """Which solutions X (C, N) keep the inequalities of their branches (to ``tol`` on
    the rates, to round-off on the multipliers); the law itself is checked after."""
    W = c + X @ kD.T
    m = codes.shape[1]
    xn, xt, wn, wt = (
        X[:, 0 : 2 * m : 2],
        X[:, 1 : 2 * m : 2],
        W[:, 0 : 2 * m : 2],
        W[:, 1 : 2 * m : 2],
    )
    slack = 1e-12 * np.max(np.abs(X), axis=1, keepdims=True)
    sign = np.where(codes == 2, 1.0, -1.0)
    ok = np.where(codes == 0, wn >= -tol, xn >= -slack)
    ok &= (codes != 1) | (np.abs(xt) <= mu * xn + slack)
    ok &= (codes < 2) | (sign * wt <= tol) | (mu == 0.0)  # (μ = 0: x_T = 0, any slip)
    return ok.all(axis=1)


def planar_cases(c, D, p, k, mu, tol):
    """Multipliers x of m ≤ ``MOST`` planar contacts (normal, tangent) and any joints' rows
    after them with w = c + k D x on Coulomb's law: of the solutions of its branches, the
    one of least norm whose error (:func:`fecontact.contact.coulomb_newton.stopping_error`,
    Newton's own test) is below ``tol``. None where there are more contacts or no branch
    holds a solution."""
    m = len(mu)
    if m > MOST:
        return None
    mu = np.asarray(mu, dtype=float)
    kD = k * D
    codes = _cases(mu)
    M, r, E = _systems(c, kD, mu, codes)
    # (a family of solutions: its least-norm member; pinv's cutoff that of the minimum-norm
    # Newton step, 1e-10 of the largest singular value)
    Y = np.einsum("cij,cj->ci", np.linalg.pinv(M, rcond=1e-10), r)
    consistent = np.abs(np.einsum("cij,cj->ci", M, Y) - r).max(axis=1) <= tol
    X = np.einsum("cij,cj->ci", E, Y)
    chosen = consistent & _admissible(c, kD, mu, codes, X, tol)
    nc, weight = 2 * m, penalty_factor(D, p, 2 * m, 2)
    for i in np.flatnonzero(chosen)[np.argsort(np.linalg.norm(X[chosen], axis=1))]:
        R, (_, ident), _ = newton_residual(X[i], c, kD, p, k, mu, nc, jacobian=False)
        if stopping_error(R, ident, weight) <= tol:
            return X[i]
    return None
