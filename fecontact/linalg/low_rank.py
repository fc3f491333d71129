r"""Solves with A − C for a C that touches few unknowns, from the factors of A.

When C is nonzero only on the rows and columns T (|T| = t ≪ n), C = E C_TT Eᵀ with E the
columns of the identity at T, and the push-through (Woodbury) identity gives

    (A − E C_TT Eᵀ)⁻¹ = A⁻¹ + Z (I − C_TT Z_T)⁻¹ C_TT Eᵀ A⁻¹,    Z = A⁻¹ E,  Z_T = Eᵀ Z,

which needs no inverse of C_TT (a curvature may be singular): one solve with A, a dense t × t
factorization, and the t columns Z, which stay valid for as long as A does. The contact
corrections use it for the gap curvature Σ s_j ∇²g_j of the active contacts, which touches
the dofs of the contact zone only.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .direct import factorize

__all__ = ["UnitColumns", "low_rank_solver"]


class UnitColumns:
    """A⁻¹ e_i for the unknowns i asked for, each solved once with ``solve`` (A⁻¹)."""

    def __init__(self, solve, n: int):
        self.solve, self.n = solve, n
        self.columns: dict[int, np.ndarray] = {}
        self.solves = 0
        self.last = None  # (T, its columns stacked) of the latest call

    def __call__(self, T: np.ndarray) -> np.ndarray:
        missing = [int(i) for i in T if int(i) not in self.columns]
        if missing:
            E = np.zeros((self.n, len(missing)))
            E[missing, np.arange(len(missing))] = 1.0
            Z = np.asarray(self.solve(E)).reshape(self.n, -1)
            self.solves += len(missing)
            for col, i in enumerate(missing):
                self.columns[i] = Z[:, col]
        if self.last is None or not np.array_equal(self.last[0], T):  # (most: the same T)
            self.last = (T.copy(), np.column_stack([self.columns[int(i)] for i in T]))
        return self.last[1]


def low_rank_solver(solve_A, C, unit_columns: UnitColumns):
    """``solve(b)`` with (A − C)⁻¹ by the identity above; C (n × n) sparse or dense. Raises
    ``np.linalg.LinAlgError`` when A − C is singular (I − C_TT Z_T is)."""
    C = sp.coo_matrix(C)
    # (T sorted and C_TT summed in C's order, as np.unique and np.add.at made them, in linear
    # time: the sort was 15 % of this function on two_balls at 10 m/s)
    touched = np.zeros(C.shape[0], dtype=bool)
    touched[C.row] = touched[C.col] = True
    T = np.flatnonzero(touched)
    if T.size == 0:
        return solve_A
    t = len(T)
    at = np.zeros(C.shape[0], dtype=np.intp)
    at[T] = np.arange(t)
    C_TT = np.bincount(at[C.row] * t + at[C.col], C.data, minlength=t * t).reshape(t, t)
    Z = unit_columns(T)
    solve_M = factorize(np.eye(len(T)) - C_TT @ Z[T])

    def solve(b):
        y = np.asarray(solve_A(b))
        return y + Z @ solve_M(C_TT @ y[T])

    return solve
