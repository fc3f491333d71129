r"""Solves with A − C for a C that touches few unknowns, from the factors of A.

When C is nonzero only on the rows and columns T (|T| = t ≪ n), C = E C_TT Eᵀ with E the
columns of the identity at T, and the push-through (Woodbury) identity gives

    (A − E C_TT Eᵀ)⁻¹ = A⁻¹ + Z (I − C_TT Z_T)⁻¹ C_TT Eᵀ A⁻¹,    Z = A⁻¹ E,  Z_T = Eᵀ Z,

which needs no inverse of C_TT (a curvature may be singular): one solve with A, a dense t × t
factorization, and the t columns Z, which stay valid for as long as A does. The contact
corrections use it for the gap curvature Σ s_j ∇²g_j of the active contacts, which touches
the dofs of the contact zone only.

The columns pay where A serves many updates (a run's own step size). At a size met once
they serve the few Newton updates of one smooth step, and t of them cost more than
factorizing A − C at each update (:data:`FACTORIZATION_COLUMNS`):
:meth:`UnitColumns.factorize_instead` decides, size by size, which of the two to take.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .direct import factorize

__all__ = ["FACTORIZATION_COLUMNS", "UnitColumns", "low_rank_solver", "touched"]

FACTORIZATION_COLUMNS = 50
"""Columns A⁻¹e_i whose solves cost as much as one factorization of A (SuperLU's symmetric
mode, one thread, S(a) = aM + K of the 3D balls: 2,706 dofs 19 ms against 0.28 to 0.39 ms a
column, 49 to 68 columns for 8 to 280 at once; 1,113 dofs 3.8 against 0.052 to 0.064 ms, 59
to 72): the smaller of the measured ratios."""


class UnitColumns:
    """A⁻¹ e_i for the unknowns i asked for, each solved once with ``solve`` (A⁻¹)."""

    def __init__(self, solve, n: int, once: bool = False):
        self.solve, self.n = solve, n
        self.columns: dict[int, np.ndarray] = {}
        self.solves = 0
        self.last = None  # (T, its columns stacked) of the latest call
        self.once = once  # (A serves one size met once: factorizations may stand in)
        self.factorized = 0  # (factorizations of A − C made in the columns' place)

    def factorize_instead(self, T: np.ndarray) -> bool:
        """Whether an update whose curvature touches ``T`` factorizes A − C instead of making
        the columns of T, counted in ``factorized``: at a size met once, while those
        factorizations, this one included, cost no more than the columns still missing
        (in :data:`FACTORIZATION_COLUMNS` each). Renting until the rent would have bought:
        at most twice the cheaper of the two, whatever the number of updates, which no size
        knows ahead; in two_balls at 10 m/s a size met once takes about 2 curved updates
        against the 280 columns' 5.6 factorizations."""
        if not self.once:
            return False
        missing = sum(int(i) not in self.columns for i in T)
        if (self.factorized + 1) * FACTORIZATION_COLUMNS > missing:
            return False
        self.factorized += 1
        return True

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


def touched(C) -> np.ndarray:
    """The rows and columns T on which the (n × n) ``C`` is nonzero, sorted."""
    C = sp.coo_matrix(C)
    # (T sorted as np.unique made it, in linear time: the sort was 15 % of low_rank_solver
    # on two_balls at 10 m/s)
    mask = np.zeros(C.shape[0], dtype=bool)
    mask[C.row] = mask[C.col] = True
    return np.flatnonzero(mask)


def low_rank_solver(solve_A, C, unit_columns: UnitColumns):
    """``solve(b)`` with (A − C)⁻¹ by the identity above; C (n × n) sparse or dense. Raises
    ``np.linalg.LinAlgError`` when A − C is singular (I − C_TT Z_T is)."""
    C = sp.coo_matrix(C)
    T = touched(C)
    if T.size == 0:
        return solve_A
    t = len(T)  # (C_TT summed in C's order, as np.add.at did, in linear time)
    at = np.zeros(C.shape[0], dtype=np.intp)
    at[T] = np.arange(t)
    C_TT = np.bincount(at[C.row] * t + at[C.col], C.data, minlength=t * t).reshape(t, t)
    Z = unit_columns(T)
    solve_M = factorize(np.eye(len(T)) - C_TT @ Z[T])

    def solve(b):
        y = np.asarray(solve_A(b))
        return y + Z @ solve_M(C_TT @ y[T])

    return solve
