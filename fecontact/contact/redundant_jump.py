r"""Newton's impact law on redundant frictionless rows: more closed rows than the degrees of
freedom they move (a box face's four corners on a plane: four rows on the three dofs that
lift it), so that the Delassus matrix D = G M⁻¹Gᵀ is singular.

The law is the linear complementarity problem 0 ≤ Λ ⊥ ġ = c + k D Λ ≥ 0 (equalities
ġ = 0 on bilateral rows). Its velocity is unique (the M-projection of ṽ on the cone the rows
allow), its multipliers are not. Two cases defeat the active-set iteration of
:func:`fecontact.contact.solve_velocity_jump` there:

- c outside the range of D (the restitution term e_j ġ⁻_j differs from corner to corner, or
  G(q_n) differs from G(q_{n+1})): the rows cannot all close; least squares then splits the
  error between them, every row keeps a positive multiplier, the set repeats, and the
  iteration stops with ġ ≠ 0 on closed rows. One row has to open instead.
- the least-norm multipliers of the closed rows have a negative member while a nonnegative
  solution exists.

Here the law is solved by the proximal point method on its dual (Rockafellar 1976, SIAM J.
Control Optim.): each iterate Λ^{i+1} solves the law with D + ε I and c − ε Λ^i, a matrix
positive definite, so that the sub-problem has one solution, found exactly by block
principal pivoting (Júdice & Pires 1994, Comput. Oper. Res.). Along the null space of D each
proximal step moves Λ by the inconsistency over ε: it reaches the bound at once and the row
that has to open leaves. In the range of D the sub-problem's answer is the law's up to
ε(Λ^{i+1} − Λ^i). After each step the multipliers of the rows it found closed are replaced by
their least-norm solution where that is nonnegative and satisfies the law. Neither the
augmentation p nor a warm start's path enters the answer's velocity, and the stop is the
law's own error (in m/s, whatever p).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["proximal_jump"]


def proximal_jump(
    kD: np.ndarray,
    c: np.ndarray,
    eq: np.ndarray,
    Lam: np.ndarray,
    settled: Callable[[np.ndarray, np.ndarray], bool],
    tol: float,
    max_steps: int = 20,
    eps_rel: float = 1e-8,
) -> tuple[np.ndarray, int] | None:
    """Multipliers Λ of 0 ≤ Λ ⊥ c + kD Λ ≥ 0 (ġ = 0 on the rows ``eq``) from ``Lam``.

    ``kD`` (m, m): k times the Delassus matrix, symmetric positive semidefinite (m/s per
    unit multiplier); ``c`` (m,) the rows' rates without the jump (m/s); ``settled(Λ, ġ)``
    the law's stopping test at the tolerance ``tol`` (m/s).
    ε = ``eps_rel`` times the largest diagonal of kD. Returns (Λ, proximal steps), or None
    when ``max_steps`` do not settle (the caller then reports its own answer)."""
    eps = eps_rel * float(np.max(np.diag(kD), initial=0.0))
    if not eps > 0.0:
        return None
    Lam = np.where(eq, Lam, np.maximum(Lam, 0.0))
    regular = kD + eps * np.eye(len(c))
    for step in range(1, max_steps + 1):
        Lam = _pivoting(regular, c - eps * Lam, eq, Lam > 0.0, 0.1 * tol)
        if Lam is None:
            return None
        Lam = _least_norm(kD, c, eq, Lam, settled, tol)
        if settled(Lam, c + kD @ Lam):
            return Lam, step
    return None


def _pivoting(S, b, eq, A, tol_rate, max_iter=200):
    """The one solution x of 0 ≤ x ⊥ b + S x ≥ 0 (= 0 on ``eq``) for S positive definite,
    by block principal pivoting from the set ``A`` of positive x: all infeasible rows
    change side while that lowers their number, else the one of largest index (Murty's
    rule: finite for any P-matrix). A rate above −``tol_rate`` (m/s) counts as feasible.
    None if it has not ended within ``max_iter`` pivots."""
    m = len(b)
    A = A | eq
    best, budget = m + 1, 3
    for _ in range(max_iter):
        x = np.zeros(m)
        if A.any():
            x[A] = np.linalg.solve(S[np.ix_(A, A)], -b[A])
        w = b + S @ x
        bad = (A & ~eq & (x < 0.0)) | (~A & (w < -tol_rate))
        n_bad = int(np.count_nonzero(bad))
        if n_bad == 0:
            return x
        if n_bad < best:
            best, budget = n_bad, 3
        elif budget > 0:
            budget -= 1
        else:  # (the full exchange did not lower the count three times: one row only)
            bad = np.arange(m) == np.flatnonzero(bad)[-1]
        A = A ^ bad
    return None


def _least_norm(kD, c, eq, Lam, settled, tol):
    """Λ with the multipliers of its closed rows (Λ > 0, bilateral, or |ġ| ≤ ``tol`` once
    those are solved exactly) replaced by their least-norm solution of kD Λ = −c on those
    rows, where that one is nonnegative on the unilateral rows and satisfies the law; else Λ
    as given. This makes the multipliers independent of the path where the law leaves a
    family of them."""
    x = Lam
    S = eq | (Lam > 0.0)
    for _ in range(2):  # (the loaded rows first: their exact rates tell which others close)
        S = S | (np.abs(c + kD @ x) <= tol)
        x = np.zeros_like(Lam)
        x[S] = np.linalg.lstsq(kD[np.ix_(S, S)], -c[S], rcond=1e-10)[0]
    # (a row the least-norm solution leaves unloaded comes out at ± round-off of the others)
    x = np.where(eq | (x < -1e-12 * np.max(np.abs(x), initial=0.0)), x, np.maximum(x, 0.0))
    if np.any(x[~eq] < 0.0) or not settled(x, c + kD @ x):
        return Lam
    return x
