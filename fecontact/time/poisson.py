r"""Poisson's impact law at the velocity level: a compression impulse, then a decompression
impulse at least e_N times the compression's, each under Coulomb's law.

Glocker (Multibody Syst. Dyn., 2013, Part II) writes Poisson's law as two inequality
problems. On the closed contacts of a step, with the free velocity ṽ (the smooth step's, or
Moreau–Jean's free velocity) and the metric H (M, or Moreau–Jean's iteration matrix):

1. compression, v_c = ṽ + H⁻¹(Gᵀ Λ_c + G_Tᵀ Λ_T,c): Newton's law with e = 0,
   0 ≤ G v_c ⊥ Λ_c ≥ 0, with Coulomb's law on the slip rate G_T v_c;
2. decompression, v⁺ = v_c + H⁻¹(Gᵀ Λ_d + G_Tᵀ Λ_T,d): Λ_d ≥ e_N Λ_i ⊥ G v⁺ ≥ 0 with
   Coulomb's law on G_T v⁺ and the cone |Λ_T,d| ≤ μ Λ_d
   (:func:`fecontact.contact.restitution.solve_decompression`).

Joints are equalities in both phases. Λ_i is the percussion of the impact: the compression
impulse that stops the approach ġ⁻ (the same pre-impact rate as Newton's law), found by the
compression problem with ġ⁻ in place of the normal rates G ṽ (the joints and the contacts
held by smooth forces at rest, and without the smooth forces' impulses), and at most Λ_c.
The rest of Λ_c is the impulse of the finite forces over the step (gravity pressing a body
that rests; the smooth force a held contact gives up, which the rows coupled to it take):
it is not restituted, or a resting body would be thrown up by e_N g h every step. Without
forces over the step Λ_i = Λ_c. For one frictionless contact the two phases give
ġ⁺ = −e_N ġ⁻, Newton's answer, and at e_N = 0 they are Newton's law.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..contact.restitution import friction_dissipation, impulse_work, solve_decompression
from .constraints import StepFailure, impact_law, pulled_held_rows
from .coulomb import frictional_jump

__all__ = ["poisson_jump"]

NULL = 1e-12  # of the largest eigenvalue of D: the rows' null space (:func:`_split_as`)


def poisson_jump(model, st, q, v, closed, G1, rates, e, approach, opts, tol, **kw):
    """The velocity jump W under Poisson's law on the contacts ``closed`` and the joints.

    G1: rows (contacts, then joints) at q; ``rates`` their rates at ṽ = ``v`` (m/s) with no
    restitution term; ``e`` the coefficients per row (0 on joints and held contacts);
    ``approach`` ġ⁻ of the contacts. Keywords: ``solve`` the metric's H⁻¹ (default M⁻¹),
    ``bilateral`` the equality rows (held contacts and joints; with friction the contacts
    keep their law and the smooth forces' ``preload`` holds them),
    ``preload`` as in :func:`fecontact.time.coulomb.frictional_jump`. Returns (W, k Λ of
    every row (N·s), iterations, friction, works) with friction = (Λ_T (len(closed), nt),
    status, work of Λ_T (J)) or None without friction, as
    :func:`fecontact.time.impacts.velocity_jump`; works sums each phase's impulses times
    the mean of its rates (:func:`fecontact.contact.restitution.impulse_work`).
    """
    solve = kw.get("solve") or model.solve_M
    nc = closed.size
    struck = e[:nc] > 0.0
    held = np.zeros(nc, bool) if kw.get("bilateral") is None else kw["bilateral"][:nc]
    pre = rates.copy()
    pre[:nc] = np.where(struck, approach, np.where(held, 0.0, rates[:nc]))  # ġ⁻ for G ṽ
    pre[nc:] = 0.0  # (the drift G ṽ of the index-3 smooth step on joints and held rows is
    # no approach)
    if model.contacts.frictional:
        out = _frictional(model, st, q, v, closed, G1, rates, pre, e, opts, tol, solve, kw)
    else:
        rows = (G1, rates, pre, e, nc)
        out = _frictionless(rows, opts, tol, solve, kw.get("bilateral"), kw.get("pressed"))
    return out


def _frictionless(rows, opts, tol, solve, bilateral, pressed):
    """The two phases on normal rows; ``pressed`` (len(closed),): the smooth forces'
    impulses h λ_N (N s) of the closed contacts, with which the held rows (equalities, as
    in Newton's law) are unilateral on the step's total impulse: the compression lets one
    go where its equality pulled it by more than its force pressed it (:func:`_let_go`),
    and the decompression's impulse may lower a held row's total to zero, not below, where
    the struck rows' restitution lifts it off (without them, None, the held rows stay
    equalities). The percussion's held rows are unilateral, at rest."""
    G1, rates, pre, e, nc = rows
    G = _dense(G1)
    Y = solve(G.T).reshape(G.shape[1], -1)
    D = G @ Y
    eq = np.zeros(len(rates), bool) if bilateral is None else bilateral
    lam_c, its_c = _compression(G, rates, solve, Y, eq, opts, tol)
    joints = np.arange(len(rates)) >= nc
    if pressed is not None:
        lam_c, its_c = _let_go(G, rates, solve, Y, eq, opts, tol, (lam_c, its_c), pressed)
    lam_i, its_i = _compression(G, pre, solve, Y, eq & joints, opts, tol)
    if opts.stats.contact.minimum_norm:
        lam_i = _split_as(lam_i, lam_c, D)
    floor = e * np.clip(lam_i, 0.0, lam_c)
    if pressed is not None:
        floor[:nc] = np.where(eq[:nc], -np.maximum(pressed + lam_c[:nc], 0.0), floor[:nc])
        eq = eq & joints
    unilateral = np.flatnonzero(~eq)
    order = np.concatenate([unilateral, np.flatnonzero(eq)])
    c = (rates + D @ lam_c)[order]
    floor = floor[unilateral]
    x, its_d = _decompression(c, D[np.ix_(order, order)], np.zeros(unilateral.size), 0, floor, tol)
    lam_d = np.zeros_like(lam_c)
    lam_d[order] = x
    w_c = rates + D @ lam_c  # the rates after the compression
    works = impulse_work(lam_c, rates, w_c, nc, 0)
    works += impulse_work(lam_d, w_c, w_c + D @ lam_d, nc, 0)
    return Y @ (lam_c + lam_d), lam_c + lam_d, its_c + its_i + its_d, None, works


def _let_go(G, rates, solve, Y, eq, opts, tol, compression, pressed):
    """The compression again with the held rows unilateral on the step's total impulse
    (its own plus ``pressed``), where their equalities pulled one by more than its smooth
    force pressed it (as :func:`fecontact.time.impacts.velocity_jump` lets rigid bodies'
    contacts go): the struck rows' compression then lifts the held row off."""
    lam_c, its = compression
    if (pulled := pulled_held_rows(lam_c, pressed, eq)) is None:  # (most: none pulled)
        return lam_c, its
    pre, own = pulled
    total, its2 = _compression(G, rates - G @ (Y @ pre), solve, Y, own, opts, tol)
    return total - pre, its + its2


def _compression(G, rates, solve, Y, eq, opts, tol):
    _, P, its = impact_law(G, rates, solve, Y, opts, eq, tol=tol)
    return P, its


def _frictional(model, st, q, v, closed, G1, rates, pre, e, opts, tol, solve, kw):
    nc = closed.size
    preload = kw.get("preload")
    W_c, n_c, t_c, status, its, work, b_c = frictional_jump(
        model, st, q, v, closed, G1, rates, opts, tol, solve, preload
    )
    # the percussion without the smooth forces' preload: with it the held rows could give
    # their force's impulse up (a negative own impulse) to a struck row, which then
    # restituted it as if the approach had brought it
    percussion = frictional_jump(model, st, q, v, closed, G1, pre, opts, tol, solve)
    F = model.free
    GT, T = model.contacts.tangent_jacobian(q, closed)
    nt = GT.shape[1]
    slip = GT @ v[F]
    speed = model.contacts.obstacle_motion(closed, velocity=True)
    if speed is not None:
        slip -= np.einsum("mtd,md->mt", T, speed)
    G = _dense(G1)
    blocks = np.concatenate([G[:nc, None], GT], axis=1)  # (normal, tangents) per contact
    A = np.concatenate([blocks.reshape(-1, G.shape[1]), G[nc:]])
    Y = solve(A.T).reshape(len(F), -1)
    D = A @ Y
    x_c = np.concatenate([np.column_stack([n_c, t_c]).ravel(), b_c])
    n_i = percussion[1]
    if opts.stats.contact.minimum_norm:
        _, n, t, _, _, _, b = percussion
        x_i = _split_as(np.concatenate([np.column_stack([n, t]).ravel(), b]), x_c, D)
        n_i = x_i[: nc * (1 + nt)].reshape(nc, 1 + nt)[:, 0]
    w0 = np.concatenate([np.column_stack([rates[:nc], slip]).ravel(), rates[nc:]])
    c = w0 + D @ x_c
    floor = e[:nc] * np.clip(n_i, 0.0, n_c)
    mu = model.contacts.friction[closed]
    x_d, its_d = _decompression(c, D, mu, nt, floor, tol)
    blocks = x_d[: nc * (1 + nt)].reshape(nc, 1 + nt)
    work_d = friction_dissipation(x_d, c, c + D @ x_d, D, mu, nt, tol)  # the decompression's
    lam = np.concatenate([n_c + blocks[:, 0], b_c + x_d[nc * (1 + nt) :]])
    restituted = np.any(x_d[: nc * (1 + nt)].reshape(nc, -1) != 0.0, axis=1)
    status = np.where(restituted, _slip_status(c + D @ x_d, nc, nt, tol), status)
    W = W_c + Y @ x_d
    works = impulse_work(x_c, w0, c, nc, nt) + impulse_work(x_d, c, c + D @ x_d, nc, nt)
    return W, lam, its + its_d, (t_c + blocks[:, 1:], status, work + work_d), works


def _split_as(x, like, D) -> np.ndarray:
    """The impulses ``x`` (N s) of rows with the Delassus matrix ``D`` = A H⁻¹Aᵀ moved along
    the null space of D (that of Aᵀ: impulses that move no velocity) to lie nearest to
    ``like``: the percussion in the compression's split. Where rows are dependent (two bars'
    vertices at the pin that joins them, both on the floor) the solver shares an impulse
    among them as its pivots fall, and two solves of nearly the same rates may share it
    otherwise: the compression (1.18, 1.21) N s, the percussion (0, 2.40) N s. Compared row
    by row, the floor e Λ_i ≤ e Λ_c then kept 1.21 N s of the 2.40 N s to restitute, and a
    chain struck at e_N = 1 lost half its normal rate. Null: eigenvalues below 1e-12 of the
    largest, far above D's round-off (1e-16) and far below an independent row's."""
    w, V = np.linalg.eigh(D)
    N = V[:, w <= NULL * w.max(initial=0.0)]
    if N.shape[1] == 0:
        return x
    return x + N @ (N.T @ (like - x))


def _slip_status(w, nc, nt, tol) -> np.ndarray:
    slip = np.linalg.norm(w[: nc * (1 + nt)].reshape(nc, 1 + nt)[:, 1:], axis=1)
    return np.where(slip > tol, 2, 1)


def _decompression(c, D, mu, nt, floor, tol):
    try:
        x, _, sweeps = solve_decompression(c, D, mu, nt, floor, tol)
    except RuntimeError as err:
        raise StepFailure(f"velocity jump: {err}", np.nan) from None
    return x, sweeps


def _dense(G):
    return G.toarray() if sp.issparse(G) else np.asarray(G)
