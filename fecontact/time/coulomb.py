r"""Coulomb friction in both corrections of the decoupled step.

The smooth step carries no contact force, so its predictor moves a contact point along the
contact plane by the O(h²) pull of the tangential load, as it moves it into the obstacle. Both
corrections therefore carry the slip rows of :mod:`fecontact.contact.friction` beside the
normal ones (after Alart & Curnier 1991, in the decoupled form of Galvez, Cavalieri, Cosimo,
Brüls & Cardona 2020):

- position level, q = q̃ + U: the slip over the step,
  w_T = T(x_rel(q) − x_rel(q_n)) − T(d_{n+1} − d_n) ≈ G_T(q)(q − q_n) − T Δd, in the cone
  |ν_T| ≤ μ ν_N of the normal correction: a contact that sticks does not creep, one that
  slips is held back by μ ν_N. Only contacts closed at t_n have it: the tangential motion
  of a contact that lands within the step is no slip (its impact is a velocity-level matter);
- velocity level, v = ṽ + W: the slip rate w_T = G_T v − T ḋ in the cone |Λ_T| ≤ μ Λ_N;
  Newton's law stays normal (no tangential restitution).

Each level solves :func:`fecontact.contact.friction.solve_coulomb` on the Delassus matrix
A H⁻¹ Aᵀ of its rows A (H the correction metric, M for the jump). The position level
relinearizes the gaps at q̃ + U until U settles: circles and rotating bodies curve them.
Joints stay equalities (rows after the contacts).
"""

from __future__ import annotations

import numpy as np

from ..contact.friction import solve_coulomb
from .constraints import Constraints, StepFailure

__all__ = ["friction_memory", "frictional_jump", "frictional_correction"]


def _rows(G: np.ndarray, GT: np.ndarray) -> np.ndarray:
    """Contact rows interleaved as (normal, tangents) per contact, then the joint rows."""
    m, nt, n = GT.shape
    out = np.empty((m * (1 + nt) + G.shape[0] - m, n))
    blocks = out[: m * (1 + nt)].reshape(m, 1 + nt, n)
    blocks[:, 0], blocks[:, 1:] = G[:m], GT
    out[m * (1 + nt) :] = G[m:]
    return out


def _stack(w_n: np.ndarray, w_t: np.ndarray, rest: np.ndarray) -> np.ndarray:
    return np.concatenate([np.column_stack([w_n, w_t]).ravel(), rest])


def _augmentation(D: np.ndarray, scale: float) -> np.ndarray:
    """p_i = scale/D_ii (an effective mass per row); rows without a gradient (the slip of a
    frictionless pair, a node with no facet near) are decoupled: any p > 0 serves."""
    d = np.diag(D).copy()
    positive = d > 0.0
    d[~positive] = d[positive].mean() if positive.any() else 1.0
    return scale / d


def _split(x: np.ndarray, m: int, nt: int):
    blocks = x[: m * (1 + nt)].reshape(m, 1 + nt)
    return blocks[:, 0], blocks[:, 1:], x[m * (1 + nt) :]


def _obstacle_shift(contacts, select, t_n: float, t: float):
    """d(t) − d(t_n) (m) of the moving obstacles of ``select`` (None when none moves)."""
    d1 = contacts.obstacle_motion(select, velocity=False)
    if d1 is None:
        return None
    contacts.set_time(t_n)
    d0 = contacts.obstacle_motion(select, velocity=False)
    contacts.set_time(t)
    return d1 - d0


def frictional_correction(model, st, q_tilde, work, solve_H, opts, tol_gap, t):
    """Position correction q = q̃ + U over the contacts ``work`` and the joints, with slip
    rows. Returns (U, k ν_N (len(work),), k ν_T (len(work), nt), U_T, iterations) with
    U_T = H⁻¹ G_Tᵀ k ν_T the part of U that friction moves (its work against the applied
    and internal forces is the positional share of the friction work)."""
    contacts, F = model.contacts, model.free
    cons = Constraints(model, work)
    m, mu, k = len(work), contacts.friction[work], opts.multiplier_scale
    if st.gaps.size == contacts.size:  # slip counts from contact on: closed ones at t_n only
        mu = np.where(st.gaps[work] <= tol_gap, mu, 0.0)
    shift = _obstacle_shift(contacts, work, st.t, t)
    U, x, its, dU = np.zeros(len(F)), None, 0, np.inf
    for _ in range(opts.max_iterations):
        q = q_tilde.copy()
        q[model.free_slice] += U
        g, G = cons.jacobian(q)
        GT, T = contacts.tangent_jacobian(q, work)
        slip = contacts.slips(q, st.q, work, GT, T)
        if shift is not None:
            slip -= np.einsum("mtd,md->mt", T, shift)
        A = _rows(G, GT)
        Y = solve_H(A.T).reshape(len(F), -1)
        D = A @ Y
        c = _stack(g[:m], slip, g[m:]) - A @ U
        try:
            x, status, n = solve_coulomb(
                c, D, _augmentation(D, opts.penalty_scale), k, mu, GT.shape[1], x, tol_gap
            )
        except RuntimeError as err:
            raise StepFailure(f"position correction: {err}", np.nan) from None
        its += n
        U_new = k * (Y @ x)
        dU = float(np.max(np.abs(U_new - U), initial=0.0))
        U = U_new
        if dU <= 0.1 * tol_gap:
            nt = GT.shape[1]
            nu_n, nu_t, _ = _split(k * x, m, nt)
            tangential = np.zeros(len(x), bool)
            tangential[: m * (1 + nt)] = np.arange(m * (1 + nt)) % (1 + nt) > 0
            return U, nu_n, nu_t, k * (Y[:, tangential] @ x[tangential]), its
    raise StepFailure(f"frictional position correction: update {dU:.3e} m did not settle", dU)


def friction_memory(st, m: int, dim: int) -> dict:
    """A step's frictional record, zero but for the work done so far: positional and
    impulsive tangential multipliers (m, nt), status (0 open, 1 stick, 2 slip) and the
    accumulated work of friction (J)."""
    work = st.memory.get("friction_work", np.zeros(1))
    return {
        "friction_nu": np.zeros((m, dim - 1)),
        "friction_impulse": np.zeros((m, dim - 1)),
        "friction_status": np.zeros(m),
        "friction_work": work.copy(),
    }


def frictional_jump(model, st, q, v, closed, G1, gdot, opts, tol, solve=None):
    """Velocity jump v = ṽ + W over the contacts ``closed`` (normal rates ``gdot`` with the
    impact law, then the joints' rows) with slip rows, in the metric ``solve`` = H⁻¹
    (default M⁻¹). Returns (W, k Λ_N, k Λ_T (len(closed), nt), status, iterations, work,
    k Λ_b of the joints): work = −Σ_j k Λ_T,j·(w_T,j(ṽ) + G_T,j W/2) (J) is the kinetic
    energy the tangential impulses take, exactly: the mean slip rate over the jump times the
    impulse."""
    contacts, F = model.contacts, model.free
    m, k = len(closed), opts.multiplier_scale
    GT, T = contacts.tangent_jacobian(q, closed)
    rate = GT @ v[F]
    speed = contacts.obstacle_motion(closed, velocity=True)
    if speed is not None:
        rate -= np.einsum("mtd,md->mt", T, speed)
    A = _rows(G1, GT)
    Y = (model.solve_M if solve is None else solve)(A.T).reshape(len(F), -1)
    D = A @ Y
    w = _stack(gdot[:m], rate, gdot[m:])
    x0 = None
    if st.impulse.size == contacts.size and "friction_impulse" in st.memory:
        x0 = _stack(st.impulse[closed], st.memory["friction_impulse"][closed], gdot[m:] * 0) / k
    try:
        x, status, its = solve_coulomb(
            w,
            D,
            _augmentation(D, opts.penalty_scale),
            k,
            contacts.friction[closed],
            GT.shape[1],
            x0,
            tol,
        )
    except RuntimeError as err:
        raise StepFailure(f"velocity jump: {err}", np.nan) from None
    lam_n, lam_t, lam_b = _split(k * x, m, GT.shape[1])
    W = k * (Y @ x)
    work = -float(np.sum(lam_t * (rate + 0.5 * (GT @ W))))
    return W, lam_n, lam_t, status, its, work, lam_b
