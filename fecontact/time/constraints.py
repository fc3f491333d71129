"""Constraint rows shared by the steppers: contacts and joints as one set of rows, the bordered
saddle-point matrix, a factorization that reports a singular matrix as a failed step, and
Newton's impact law on the rows with the run's augmentation."""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ..contact import solve_velocity_jump
from ..linalg import factorize

__all__ = [
    "Constraints",
    "StepFailure",
    "augmentation",
    "bordered",
    "constraint_columns",
    "factorize_or_fail",
    "impact_law",
    "independent_rows",
    "plus_curvature",
    "pulled_held_rows",
]


class StepFailure(Exception):
    """A step that failed, with the residual its solve left (nan: none). A stepper that
    halves it adds what its attempts did before the failure reached the run (``halvings``,
    of them ``retakes`` for a penetration and ``turn_halvings`` for a beam node's turn, and
    the ``shortest`` sub-step tried), so
    that the run counts a failed step's halvings as those of its other steps."""

    def __init__(self, message: str, residual: float):
        super().__init__(message)
        self.residual = residual
        self.halvings = self.retakes = self.turn_halvings = 0
        self.shortest = math.inf  # s: the shortest (sub-)step tried

    def carries(self, halvings: int, retakes: int, turn_halvings: int) -> None:
        """Add the halvings of an attempt of the failed step (those of a half that
        succeeded, or the halving that led to the failure)."""
        self.halvings += halvings
        self.retakes += retakes
        self.turn_halvings += turn_halvings


def augmentation(scale: float, G, Y) -> np.ndarray:
    """p_j = scale / (G H⁻¹ Gᵀ)_jj for the rows G with Y = H⁻¹Gᵀ: the augmentation of each
    row in the units of its effective mass. A row along which H is not positive definite (an
    indefinite tangent, a row of zeros) has no effective mass and would turn the
    Alart–Curnier tests around: the step fails instead, to be halved."""
    inverse_mass = np.einsum("ij,ji->i", G, Y)
    bad = ~(np.isfinite(inverse_mass) & (inverse_mass > 0.0))
    if np.count_nonzero(bad):
        raise StepFailure(
            f"constraint row {int(np.argmax(bad))} has no positive effective mass "
            f"(G H^-1 G^T = {inverse_mass[bad][0]:.3e})",
            np.nan,
        )
    return scale / inverse_mass


def impact_law(G, c, solve, Y, opts, bilateral=None, P0=None, tol: float = 0.0):
    """Newton's impact law on the rows G in the metric H (``solve``: H⁻¹, ``Y`` = H⁻¹Gᵀ):
    H W = Σ G_jᵀ P_j with 0 ≤ c_j + G_j W ⊥ P_j ≥ 0 (equalities on ``bilateral`` rows),
    by the Alart–Curnier semi-smooth Newton of
    :func:`fecontact.contact.solve_velocity_jump` with the run's augmentation and
    multiplier scale k (``opts``), from the impulses ``P0`` (N·s; None: zero) to the
    tolerance ``tol`` (m/s; 0: until the active set repeats). Returns W, P = kΛ (N·s) and
    the iterations; an active set that does not settle fails the step."""
    p = augmentation(opts.penalty_scale, G, Y)
    k = opts.multiplier_scale
    Lam0 = None if P0 is None else P0 / k
    try:
        W, Lam, its = solve_velocity_jump(
            G,
            c,
            solve,
            p,
            k,
            opts.max_iterations,
            bilateral=bilateral,
            Y=Y,
            Lam0=Lam0,
            tol=tol,
            stats=opts.stats.contact,
            scale=opts.penalty_scale,  # (p_j D_jj: the stop in m/s whatever p)
        )
    except RuntimeError as err:
        raise StepFailure(str(err), np.nan) from None
    return W, k * Lam, its


def pulled_held_rows(P: np.ndarray, pressed: np.ndarray, bilateral: np.ndarray):
    """Where a jump's impulses ``P`` pulled a held contact (a contact row of ``bilateral``)
    by more than its smooth force pressed it (``pressed``: h λ_N of the closed contacts,
    P_j + h λ_j < 0 beyond round-off): (pre, own), ``pre`` the held contacts' smooth impulses
    (zero elsewhere) to solve the jump again on the step's total impulses, ``own`` the rows
    that stay equalities (the joints). None where nothing was pulled (most steps)."""
    m = pressed.size
    held = bilateral[:m]
    floor = 1e-12 * max(np.abs(P).max(initial=0.0), pressed.max(initial=0.0))
    if not np.count_nonzero(held & (P[:m] + pressed < -floor)):
        return None
    pre = np.zeros(P.size)
    pre[:m][held] = pressed[held]
    own = bilateral.copy()
    own[:m] = False
    return pre, own


def factorize_or_fail(A, residual, symmetric=False, solver=None):
    """``factorize(A, symmetric, solver)`` with a singular A reported as a failed step, also
    when the sparse solver is iterative and finds it out in ``solve`` (its fallback
    factorization)."""
    try:
        solve = factorize(A, symmetric, solver)
    except np.linalg.LinAlgError:
        raise StepFailure("singular iteration matrix", residual) from None
    if not (symmetric and sp.issparse(A)):
        return solve

    def checked(b):
        try:
            return solve(b)
        except np.linalg.LinAlgError:
            raise StepFailure("singular iteration matrix", residual) from None

    return checked


def independent_rows(G, rtol: float = 1e-10) -> np.ndarray:
    """The indices of a maximal set of linearly independent rows of G (dense or sparse), by
    a QR factorization of Gᵀ with column pivoting: the pivots whose |R_ii| exceed ``rtol``
    of the largest (far above round-off, far below any independent row's size)."""
    Gd = G.toarray() if sp.issparse(G) else np.asarray(G)
    if Gd.shape[0] == 0:
        return np.zeros(0, int)
    R, piv = scipy.linalg.qr(Gd.T, mode="r", pivoting=True)
    d = np.abs(np.diag(R))
    return np.sort(piv[: int(np.count_nonzero(d > rtol * d[0]))])


def bordered(K, G, lower=None):
    """The saddle-point matrix [[K, Gᵀ], [G, 0]] (dense or sparse like K); ``lower``: the
    rows' linearization where it is not G (on a Lie group, G T(D))."""
    lower = G if lower is None else lower
    if sp.issparse(K):
        return sp.bmat([[K, sp.csr_matrix(G.T)], [sp.csr_matrix(lower), None]], format="csc")
    n = K.shape[0]
    A = np.zeros((n + G.shape[0],) * 2)
    A[:n, :n], A[:n, n:], A[n:, :n] = K, G.T, lower
    return A


class Constraints:
    """The contacts ``select`` followed by every joint, as one set of constraint rows."""

    def __init__(self, model, select):
        self.contacts, self.joints, self.select = model.contacts, model.joints, select
        self.bilateral = np.zeros(len(select) + model.joints.size, bool)
        self.bilateral[len(select) :] = True
        self.linear = self.contacts.linear and self.joints.linear
        self.n = model.n_free

    def jacobian(self, q):
        return self.linearize(q)[:2]

    def curvature(self, q, weights):
        return self.linearize(q, weights)[2]

    def linearize(self, q, weights=None):
        """(g, G, C) of the contacts then the joints; C = Σ weights_j ∇²g_j if weights."""
        m = len(self.select)
        wc = None if weights is None else weights[:m]
        g, G, C = self.contacts.linearize(q, self.select, wc)
        if self.joints.size:
            wb = None if weights is None else weights[m:]
            gb, Gb, Cb = self.joints.linearize(q, self.joints.all, wb)
            g, G = np.concatenate([g, gb]), np.vstack([G, Gb])
            C = Cb if C is None else (C if Cb is None else C + Cb)
        return g, G, C


def plus_curvature(A, scale, C):
    """A + scale C for a curvature C (dense or sparse; None: zero), in the format of A."""
    if C is None:
        return A
    return A + scale * (sp.csr_matrix(C) if sp.issparse(A) else C)


def constraint_columns(model, key, select, G, solve, cons, constant: bool, rhs=None):
    """H⁻¹ G_jᵀ for the constraints ``select`` (n × m). When H is ``constant`` (the mass, or
    S_t/β′ of a linear model at a given step) and the gap gradients are too (nodes against
    planes), the columns are kept per contact: a large model in contact over a small zone
    then solves only for contacts that are new. With ``rhs`` (n,), (the columns, H⁻¹ rhs),
    solved together where kept columns are solved (one solve of a few columns costs little
    more than one of a single column)."""
    n = G.shape[1]
    if not (constant and cons.linear and model.joints.size == 0 and model.contacts.linear):
        Y = solve(G.T).reshape(n, -1)
        # (rhs apart: a dense factor's solve of several columns rounds otherwise than of one,
        # and these models' histories stay those of the solves one by one)
        return Y if rhs is None else (Y, solve(rhs))
    cache = model.column_cache.setdefault(key, {})
    x = _missing_columns(cache, select, G, solve, rhs)
    Y = np.column_stack([cache[j] for j in select]) if len(select) else G.T.copy()
    if rhs is None:
        return Y
    return Y, (solve(rhs) if x is None else x)


def _missing_columns(cache: dict, select, G, solve, rhs):
    """Solve into ``cache`` the columns H⁻¹G_jᵀ of the contacts of ``select`` it lacks, with
    ``rhs`` where given: H⁻¹ rhs, or None where no column was missing (or no ``rhs``)."""
    missing = [i for i, j in enumerate(select) if j not in cache]
    if not missing:
        return None
    B = G[missing].T if rhs is None else np.column_stack([G[missing].T, rhs])
    Y = solve(B).reshape(G.shape[1], -1)
    for col, i in enumerate(missing):
        cache[select[i]] = Y[:, col]
    return None if rhs is None else Y[:, -1].copy()
