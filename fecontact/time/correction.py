"""The position correction of the NSGA step (step 2): q = q̃ + U in the metric H = S_t/β′
or M, with the contacts' Alart–Curnier multipliers and the joints kept as equalities."""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..contact import solve_position_correction
from ..linalg import UnitColumns, low_rank_solver
from .configuration import plus
from .constraints import (
    Constraints,
    StepFailure,
    augmentation,
    constraint_columns,
    factorize_or_fail,
)

__all__ = ["correction_metric", "position_correction", "unit_columns"]


def correction_metric(model, q, S, c, kind):
    """(H, solve_H) of the position correction, H = S_t/β′ (``kind`` "stiffness") or H = M
    ("mass"); H itself is returned as a function, needed only when the gaps are curved."""
    if kind == "mass":
        return lambda: model.M, model.solve_M
    if S is None and model.linear:
        S = model.iteration_matrix(c.bp, c.gp)[:2]
    if S is None:
        _, _, K = model.internal(q)
        S = model.iteration_sum(c.bp, K)
        alpha, beta_k = model.damping
        if alpha or beta_k:
            S = S + c.gp * (alpha * model.M + beta_k * K)
        S = (S, factorize_or_fail(S, math.nan, True, model.solver))
    matrix, solve_S = S
    return lambda: matrix / c.bp, lambda b: c.bp * solve_S(b)


def position_correction(model, q_tilde, cand, metric, c, opts, tol_gap, nu0=None):
    """Step 2: q = q̃ + U, H U = Σ G_jᵀ [k ν_j − p g_j]_+ over the contacts ``cand``, with
    the joints kept as equalities (always active, multipliers of any sign); ``metric`` is
    (H, solve_H) from :func:`correction_metric`, ``nu0`` the contacts' multipliers of the previous
    step."""
    F = model.free
    H, solve_H = metric
    cons = Constraints(model, cand)
    _, G0 = cons.jacobian(q_tilde)
    constant = model.linear or opts.metric == "mass"
    Y0 = constraint_columns(model, (opts.metric, c.bp, c.gp), cand, G0, solve_H, cons, constant)
    p = augmentation(opts.penalty_scale, G0, Y0)
    k = opts.multiplier_scale

    def shifted(U):
        return plus(model, q_tilde, U)

    units = []  # H⁻¹e_i, made on the first curved system

    def system(U, s, A):
        if cons.linear:  # constant gradients: H⁻¹G_Aᵀ are columns of Y0
            return (lambda B: Y0[:, A]), None
        C = cons.curvature(shifted(U), np.where(A, s, 0.0))
        if sp.issparse(C) and C.nnz and np.unique(C.row).size <= len(F) // 4:
            # the curvature touches the contact zone only: update H's factors on its dofs
            if not units:
                units.append(unit_columns(model, (opts.metric, c.bp, c.gp), solve_H, constant))
            try:
                return low_rank_solver(solve_H, C, units[0]), C
            except np.linalg.LinAlgError:
                raise StepFailure("singular position-correction matrix", math.nan) from None
        return factorize_or_fail(H() - C, math.nan, True, model.solver), C

    try:
        U, nu, its = solve_position_correction(
            lambda U: cons.jacobian(shifted(U)),
            system,
            len(F),
            p,
            k,
            tol_gap,
            0.1 * tol_gap,
            opts.max_iterations,
            bilateral=cons.bilateral,
            nu0=None if nu0 is None else np.concatenate([nu0, np.zeros(model.joints.size)]),
            stats=opts.stats.contact,
        )
    except RuntimeError as err:
        raise StepFailure(str(err), np.nan) from None
    return U, k * nu, its


def unit_columns(model, key, solve_H, constant: bool) -> UnitColumns:
    """H⁻¹e_i of the dofs that gap curvatures touch, kept over the run when H is constant
    (else over one correction)."""
    if not constant:
        return UnitColumns(solve_H, model.n_free)
    return model.column_cache.setdefault(("unit", *key), UnitColumns(solve_H, model.n_free))
