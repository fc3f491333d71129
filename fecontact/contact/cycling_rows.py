"""Rows that defeat the active-set iteration of the position correction
(:func:`fecontact.contact.laws.solve_position_correction`): pairs of nearly redundant rows,
of which the iteration holds one, active sets that cycle, whose updates are then solved
as complementarity problems on every row at once, and held rows that leave a frozen set no
answer of the law."""

from __future__ import annotations

import numpy as np

from .redundant_jump import proximal_jump
from .stats import ContactStats

__all__ = [
    "COMPLEMENTARY",
    "NEAR",
    "apart",
    "complementary_update",
    "unheld_correction",
    "unsettled",
]


NEAR = 1e-3
"""1 − the correlation above which two active rows are nearly redundant (:func:`apart`)."""


def apart(A, GA, Y, g, eq, twins):
    """The active set A (its rows' gradients ``GA`` and columns Y = H⁻¹G_Aᵀ) without the
    shallower of two rows whose correlation in the metric H⁻¹, S_ij / √(S_ii S_jj) with
    S = G_A H⁻¹G_Aᵀ, is above 1 − ``NEAR``: two constraints that move the same points along
    nearly the same direction, as twins (:func:`fecontact.contact.laws.one_of_twins`) but
    not declared. A slave node's weighted gap and the own row of the master node facing it
    are such a pair (two disks head-on on matching meshes: 0.9998); held together, their
    multipliers split into large forces of opposite signs and the update moved the gaps by
    millimetres. The test reads neither p nor k. Only where rows have twins (``twins`` not
    None, decided once per run: mortar interfaces with their nodes' own rows). Returns
    (A, G_A, Y) of the rows kept."""
    if twins is None:
        return A, GA, Y
    S = GA @ Y
    d = np.sqrt(np.abs(np.diagonal(S)))
    with np.errstate(divide="ignore", invalid="ignore"):  # (a zero row correlates with none)
        i, j = np.nonzero(np.triu(S / np.outer(d, d), 1) > 1.0 - NEAR)
    if i.size == 0:
        return A, GA, Y
    rows = np.flatnonzero(A)
    keep = np.ones(rows.size, bool)
    for a, b in zip(i, j, strict=True):  # (the deeper of each pair, the first on a tie)
        if keep[a] and keep[b]:
            drop = b if g[rows[b]] >= g[rows[a]] else a
            keep[drop] = bool(eq[rows[drop]])  # (joints stay)
    A = A.copy()
    A[rows[~keep]] = False
    return A, GA[keep], Y[:, keep]


COMPLEMENTARY = 10
"""Updates of a cycling position correction solved as complementarity problems before its
best set is frozen: Newton's on the linearised law, which settles in a few where the gaps
are smooth; a gap that jumps defeats it."""


def complementary_update(U, g, G, nu, rows, system, law):
    """The update of a cycling position correction at the iterate U: the linearised law on
    every row that holds (a gap and a gradient),
    0 ≤ ν ⊥ g + G(x₀ − U) + k G Y ν ≥ 0 (= 0 on the equalities) with Y = (H − C)⁻¹Gᵀ and
    x₀ = −(H − C)⁻¹C U, solved whole by :func:`proximal_jump` (principal pivoting): the set
    of the answer is chosen by the law, not row by row, and two nearly redundant rows may be
    held together where the law holds them (a held row and its twin, of which the
    active-set iteration keeps one). ``rows``: (``holding``, the gaps where rows hold, +inf
    elsewhere; ``eq``, the equalities); ``system`` as in
    :func:`fecontact.contact.laws.solve_position_correction`; ``law``: (p per row, k, the
    tolerance in m, ``settled(ν, g, p, eq)`` the law's stopping test at it). Returns
    (A, ν, U, C), or None where the pivoting does not settle."""
    holding, eq = rows
    p, k, tol, judge = law
    rows = holding < np.inf
    w = np.where(eq, k * nu, np.maximum(k * nu, 0.0))
    solve, C = system(U, w, rows & (eq | (nu > 0.0)))
    x0 = np.zeros(U.size) if C is None else solve(-(C @ U))
    Gr = G[rows]
    Y = solve(Gr.T).reshape(U.size, -1)
    e, pr = eq[rows], p[rows]

    def settled(x, gap):
        return judge(x, gap, pr, e)

    start = np.where(e, nu[rows], np.maximum(nu[rows], 0.0))
    found = proximal_jump(k * (Gr @ Y), g[rows] + Gr @ (x0 - U), e, start, settled, tol)
    if found is None:
        return None
    nu = np.zeros(len(g))
    nu[rows] = found[0]
    A = rows & (eq | (nu > 0.0))
    return A, nu, x0 + k * (Y @ found[0]), C


def unheld_correction(held, stats, again):
    """A correction whose ``held`` rows (the smooth step's decision) froze with the law
    unsettled, solved ``again`` from its start with them unilateral (``again(trial)``, its
    counts in ``trial``): the held equalities left no set where every row closes and pushes
    (the fast P2 disks: a held row 20.9 µm open beside its twin, a master node's row pulling
    among 10–13 held ones). The answer where the law then holds to its tolerance, counted in
    ``stats.released_corrections``; else None (the frozen set stands)."""
    if held is None or not np.count_nonzero(held):
        return None
    trial = ContactStats()
    if stats is not None:  # (the run's decisions on its rows hold in the trial)
        trial.minimum_norm, trial.merge_duplicates = stats.minimum_norm, stats.merge_duplicates
    try:
        answer = again(trial)
    except RuntimeError:
        return None
    if trial.final_residuals.position > 1.0:
        return None
    if stats is None:
        return answer
    for name in ("least_squares", "duplicate_rows", "frozen_active_sets",
                 "complementary_corrections"):  # fmt: skip
        setattr(stats, name, getattr(stats, name) + getattr(trial, name))
    stats.released_corrections += 1
    stats.final_residuals.record("position", trial.final_residuals.position)
    return answer


def unsettled(max_iter: int, error: float) -> str:
    """The message of a position correction whose active set kept changing for ``max_iter``
    iterations, with the law's error (m) at its last iterate (a step that fails there has no
    residual of its own to report)."""
    return (
        f"position correction: active set did not settle in {max_iter} iterations (it "
        f"cycled; the law's error at the last iterate {error:.3e} m)"
    )
