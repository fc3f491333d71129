r"""Unilateral contact: gaps, their derivatives, and the Alart–Curnier augmented Lagrangian.

Notation (after Brüls, Acary & Cardona 2014, eqs. 9–10):

=========  ==============================================================================
g_j(q)     signed gap of contact j in m (> 0 open, 0 closed, < 0 penetrating)
G_j        ∂g_j/∂q, a row over the dofs
ν_j        position-level multiplier (kg·m); the contact force of the correction is k ν_j
Λ_j        velocity-level multiplier; k Λ_j is the contact impulse in N·s
p, k       augmentation (penalty) and multiplier scaling, both > 0
[x]_+      max(x, 0)
=========  ==============================================================================

Position level: with s_j = k ν_j − p g_j the contact force is Σ G_jᵀ [s_j]_+ and the
complementarity residual k ν_j − [s_j]_+ vanishes exactly when 0 ≤ g_j ⊥ ν_j ≥ 0. Velocity
level: the same with ġ_j = G_j(q_{n+1}) v_{n+1} + e_j G_j(q_n) v_n (Newton's impact law with
restitution e_j) in place of g_j and Λ_j in place of ν_j.

Semi-smooth Newton on these residuals is a primal–dual active-set method: the active set
A = {j : s_j > 0} is re-evaluated after every update, and on A the linearised constraint is
enforced exactly, so the converged answer does not depend on p or k; they only steer the path.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from .cycling_rows import COMPLEMENTARY, apart, complementary_update, unheld_correction, unsettled
from .kkt import kkt_multipliers, schur_multipliers
from .redundant_jump import proximal_jump

__all__ = [
    "alart_curnier_residual",
    "contact_force_multiplier",
    "kkt_multipliers",
    "one_of_twins",
    "solve_position_correction",
    "solve_velocity_jump",
]


def contact_force_multiplier(nu, g, p, k):
    """[k ν − p g]_+ : the contact force (or impulse) multiplier of the augmented Lagrangian."""
    return np.maximum(k * np.asarray(nu) - p * np.asarray(g), 0.0)


def alart_curnier_residual(nu, g, p, k):
    """k ν − [k ν − p g]_+, zero exactly when 0 ≤ g ⊥ ν ≥ 0 (any p, k > 0)."""
    return k * np.asarray(nu) - contact_force_multiplier(nu, g, p, k)


# -- contact pairs -----------------------------------------------------------------------------


# -- semi-smooth Newton on the Alart–Curnier residuals -------------------------------------------


def _residual(nu, g, p, k, eq, scale: float = 1.0) -> float:
    """The largest error of the unilateral rows' law in the units of g, whatever p, and |g|
    of the equalities. On a closed row (k ν − p g > 0) the Alart–Curnier residual over p,
    k ν − [k ν − p g]_+ over p, is the gap g itself; on an open row it is the force k ν
    over p, which times p_j D_jj (``scale``: the rows' augmentation over their effective
    mass, p_j = scale / D_jj with D_jj = G_j H⁻¹G_jᵀ) is the gap the force makes at its own
    row, k ν D_jj. Judged by k ν/p alone, p × 1000 accepted forces that moved the gaps by up
    to 1000 tolerances. At the default scale 1 the factor is exactly 1."""
    if not np.count_nonzero(eq):  # (no equalities: the rows as they are, without copies)
        return float(_unilateral(nu, g, p, k, scale))
    u = ~eq
    r = _unilateral(nu[u], g[u], p[u], k, scale)
    return float(max(r, np.maximum.reduce(np.abs(g[eq]), initial=0.0)))


def _unilateral(nu, g, p, k, scale: float):
    """The largest error of the law on unilateral rows (:func:`_residual`); the factor
    ``scale`` on open rows only where it is not 1 (R · 1 is R to the bit)."""
    # k ν − p g once: the Alart–Curnier residual's argument and the closed rows' test (the
    # numbers of alart_curnier_residual; a stop test made at every jump's end)
    trial = k * nu - p * g
    R = (k * nu - np.maximum(trial, 0.0)) / p
    if scale != 1.0:
        R = np.where(trial > 0.0, R, R * scale)
    return np.maximum.reduce(np.abs(R), initial=0.0)


def _record(stats, level: str, nu, g, p, k, eq, tol, scale: float = 1.0) -> None:
    if tol > 0 and stats is not None:
        stats.final_residuals.record(level, _residual(nu, g, p, k, eq, scale) / tol)


def _settled(nu, g, p, k, eq, tol, scale: float = 1.0) -> bool:
    """The law's error (:func:`_residual`, in the units of g) is within ``tol`` for every
    unilateral row, and every equality holds to ``tol``.

    This is the stopping test rather than a repeated active set: a contact whose gap is at
    round-off level (a body resting on another) may enter and leave the set from one
    iteration to the next while the answer has converged."""
    return _residual(nu, g, p, k, eq, scale) <= tol


def solve_position_correction(
    gaps, system, n, p, k, tol_gap, tol_u, max_iter=30, bilateral=None, nu0=None, stats=None,
    twins=None,
    scale=1.0,
    held_rows=None,
):  # fmt: skip
    """Position correction q = q̃ + U: find (U, ν) with H U = Σ G_jᵀ [k ν_j − p g_j(q)]_+ and
    k ν_j − [k ν_j − p g_j(q)]_+ = 0 for every candidate j.

    ``gaps(U) -> (g, G)`` evaluates the candidate gaps (m,) and their gradient (m × n dense) at
    q̃ + U. ``system(U, s, A) -> (solve, C)`` gives the solver of the Newton matrix
    H − C, where C = Σ_A s_j ∇²g_j is the curvature of the gaps (``None`` when they are linear).
    Each Newton step solves the bordered system [H − C, −k G_Aᵀ; G_A, 0] through its Schur
    complement. ``bilateral`` marks equality constraints (joints): always active, with
    multipliers of either sign. ``nu0`` warm-starts the multipliers (those of the previous
    step): only the first active set depends on it, so a chain of contacts that stays closed
    (a stack at rest) is found at once instead of one link per iteration. The iteration stops
    when the law's error is below ``tol_gap`` (in m, whatever p: ``scale`` is p_j times the
    rows' inverse effective mass D_jj, see :func:`_residual`) and the update below ``tol_u``
    or no longer shrinking. ``stats`` (:class:`fecontact.contact.stats.ContactStats`, or
    None) receives the least-squares multipliers and the final residual; ``twins`` (each
    row's twin among the rows, −1 none: :func:`one_of_twins`) or None; ``held_rows`` (a mask,
    or None) the ``bilateral`` rows that are equalities by the smooth step's decision, not
    joints: where their set freezes with the law unsettled,
    :func:`fecontact.contact.cycling_rows.unheld_correction`. Returns
    (U, ν, iterations); raises ``RuntimeError`` when the iteration does not settle.
    """
    U = np.zeros(n)
    g, G = _checked(*gaps(U))
    nu = np.zeros(len(g)) if nu0 is None else np.maximum(np.asarray(nu0, dtype=float), 0.0)
    bilateral = np.zeros(len(g), bool) if bilateral is None else bilateral
    held = np.count_nonzero(bilateral) > 0  # (decided once: without equalities, none appear)
    eq = _holding(bilateral, g, G, held)
    law = (np.broadcast_to(p, g.shape), k, tol_gap, lambda x, gap, pr, e: _settled(
        x, gap, pr, k, e, tol_gap, scale))  # fmt: skip
    dU, dU_prev = np.inf, np.inf
    A = last = None
    cycle = _Cycle()
    # (beyond max_iter only to end a cycle: complementarity updates, then a frozen set)
    for it in range(2 * max_iter + COMPLEMENTARY + 1):
        settled = _update_settled(dU, dU_prev, tol_u, tol_gap)
        if it > 0 and settled and cycle.ends(A, nu, g, p, k, eq, tol_gap, scale):
            return cycle.answer((U, nu, it), (g, p, k, eq, tol_gap, scale), stats, lambda: (
                unheld_correction(held_rows, stats, lambda trial: solve_position_correction(
                    gaps, system, n, p, k, tol_gap, tol_u, max_iter, bilateral & ~held_rows,
                    nu0, trial, twins, scale))))  # fmt: skip
        if it > 0:
            cycle.visit(A, _residual(nu, g, p, k, eq, scale))
        if it > max_iter and not cycle.escalate():
            break
        # (a row with a zero gradient holds nothing, as one whose gap is undefined: a deep
        # node's own row reports a finite far gap once its node is out, and kept in the set
        # it made the Schur complement singular and the update stall at its round-off)
        holding = np.where(G.any(axis=1), g, np.inf)
        update = None
        if cycle.complementary:
            update = complementary_update(U, g, G, nu, (holding, eq), system, law)
            cycle.complementary = update is not None  # (else frozen at once)
        if update is None:
            A = cycle.next(A, nu, holding, p, k, eq, twins, settled and (g < -tol_gap))
            update = _active_set_update(A, U, g, G, nu, eq, k, (system, last, twins), stats)
            last = update[4]
        A, nu, U_new, C = update[:4]
        dU_prev = dU
        dU = 0.0 if C is None else float(np.max(np.abs(U_new - U), initial=0.0))
        U = U_new
        g, G = _defined(gaps, U)
        eq = _holding(bilateral, g, G, held)
    raise RuntimeError(unsettled(max_iter, _residual(nu, g, p, k, eq, scale)))


def _active_set_update(A, U, g, G, nu, eq, k, solver, stats):
    """The semi-smooth Newton update of :func:`solve_position_correction` on the active set
    A at the iterate U (gaps g, gradient G, multipliers ν); ``solver``: (``system``, the last
    system (A, w, solve, C) or None, ``twins``). Returns (A, ν, U, C, last): the set the
    update held (without the rows that :func:`fecontact.contact.cycling_rows.apart` takes
    apart), its multipliers, the new iterate, the curvature and the system used."""
    system, last, twins = solver
    n = U.size
    # the gaps' curvature weighted by the current contact forces k ν (the Hessian of the
    # Lagrangian, as in SQP), not by k ν − p g: on the first update that is −p g, which
    # with a large p dwarfs H and makes H − C indefinite; at convergence both agree
    w = np.where(eq, k * nu, np.maximum(k * nu, 0.0))
    if not _close(last, A, w):
        last = (A.copy(), w, *system(U, w, A))
    # else the matrix of the last update serves again (a chord step): the active set is
    # the same and the forces weighting the curvature moved by under a tenth, so the
    # iteration still contracts fast and converges to the same U (the fixed point does
    # not depend on C); each new curvature costs its evaluation and a factor update
    solve, C = last[2], last[3]
    x0 = np.zeros(n) if C is None else solve(-(C @ U))
    nu = np.zeros(len(g))
    U_new = x0
    if A.any():
        GA = G[A]
        Y = solve(GA.T).reshape(n, -1)
        A, GA, Y = apart(A, GA, Y, g, eq, twins)
        nu[A] = kkt_multipliers(GA, Y, GA @ (U - x0) - g[A], k, stats)
        U_new = x0 + k * (Y @ nu[A])
    return A, nu, U_new, C, last


def _defined(gaps, U: np.ndarray):
    """The gaps and gradient at q̃ + U (:func:`_checked`), or ``RuntimeError`` (the step's
    failure, counted where it is retaken) where the update is not a number: no iterate to
    go on from. A NaN or an infinity anywhere in U makes its sum non-finite: one reduction
    (these checks are a large share of a resting body's step)."""
    if not math.isfinite(np.add.reduce(U)):
        raise RuntimeError("position correction: non-finite update")
    return _checked(*gaps(U))


def _checked(g: np.ndarray, G: np.ndarray):
    """(g, G), or ``RuntimeError`` where a gap or the gradient is not a number: a row without
    a defined gap reads +inf with a zero gradient, and anything else non-finite is no
    iterate to go on from. The least gap is NaN (``np.minimum`` keeps it) or −inf where any
    gap is; a NaN or an infinity anywhere in G makes its sum non-finite."""
    if not (np.minimum.reduce(g, initial=np.inf) > -np.inf):
        raise RuntimeError("position correction: non-finite gap or gradient")
    if not math.isfinite(np.add.reduce(G, axis=None)):
        raise RuntimeError("position correction: non-finite gap or gradient")
    return g, G


def _holding(bilateral: np.ndarray, g: np.ndarray, G: np.ndarray, held: bool) -> np.ndarray:
    """The equalities among the rows: the ``bilateral`` ones whose gap is defined and has a
    gradient ``G`` (``held``: whether any row is bilateral; if none, ``bilateral`` itself).
    A contact held by the smooth step's force is an equality of the correction, but where
    its gap became undefined at an iterate (+inf: a box edge's row whose common normal left
    the ridge's normal cone) it holds nothing, as any row there (:func:`_next_active_set`);
    kept as an equality its +inf gap made the multipliers and the update NaN. So does a
    mortar node's own row whose node is above half its allowance (a placeholder gap, no
    gradient): kept as an equality its zero row made the Schur complement singular (least
    squares) and its placeholder gap (1.7e-2 m) the correction's residual 1e11 tolerances
    (stress_3d.md, the 57 Δx/c off-centre balls)."""
    return bilateral & (g < np.inf) & G.any(axis=1) if held else bilateral


class _Cycle:
    """The active sets of one position correction. Where the primal–dual iteration has not
    settled within its ``max_iter`` iterations and a set came three times or more, it cycles
    (a held row and its twin taking turns, as the active-set rule keeps one of two twins; a
    gap that jumps where a node's closest facet changes, seen on node-to-surface disks at
    three edges a step: {1, 2} holds row 1 with a pulling force, {2} leaves it 0.44 mm
    inside). Its next updates solve the linearised law as a complementarity problem on every
    row at once (:func:`fecontact.contact.cycling_rows.complementary_update`, up to
    ``COMPLEMENTARY`` of them, counted in ``complementary_corrections`` where they
    settle). Where those do not settle, the set whose iterate had the least Alart–Curnier
    residual is *frozen*: iterated as equalities, rows entering it where they penetrate at
    its converged iterate and none leaving (so it ends within as many additions as rows),
    and accepted when its rows' gaps close and no other row penetrates, whatever the sign of
    its multipliers (the step's final residual records the pull; counted in
    ``frozen_active_sets``). Only then: a correction that settles within ``max_iter`` is
    unchanged to the bit (frozen at a set's third coming,
    the shipped node-to-surface disks froze once and moved by round-off)."""

    def __init__(self):
        self.visits: dict = {}
        self.best, self.frozen = (np.inf, None), None
        self.complementary, self.solved = False, 0

    def visit(self, A: np.ndarray, residual: float) -> None:
        """The residual of the iterate that the set A gave."""
        if residual < self.best[0]:
            self.best = (residual, A.copy())

    def next(self, A, nu, g, p, k, eq, twins, inside) -> np.ndarray:
        """The set of the next update after A (``inside``: the rows that enter a frozen set,
        those that penetrate once it has converged)."""
        if self.frozen is None and self.best[1] is not None and self.solved:
            self.frozen = self.best[1]  # (the complementarity updates did not settle)
        if self.frozen is not None:  # (a row whose gap became undefined leaves, as below)
            self.frozen = (self.frozen & (g < np.inf)) | inside
            return self.frozen
        A = one_of_twins(_next_active_set(A, nu, g, p, k, eq), g, twins)
        key = A.tobytes()
        self.visits[key] = self.visits.get(key, 0) + 1
        return A

    def escalate(self) -> bool:
        """Past ``max_iter``: the next complementarity update if the iteration has cycled and
        fewer than ``COMPLEMENTARY`` were made, else the frozen set; whether either goes on."""
        if self.frozen is not None:
            return True
        if self.best[1] is None or max(self.visits.values()) <= 2:
            return False
        self.complementary = self.solved < COMPLEMENTARY
        self.solved += 1
        return True

    def ends(self, A, nu, g, p, k, eq, tol: float, scale: float = 1.0) -> bool:
        """Whether the settled iterate from the set A ends the correction: complementarity
        within ``tol``, or, for a frozen set, its rows closed and no other inside."""
        if self.frozen is None:
            return _settled(nu, g, p, k, eq, tol, scale)
        return bool(np.all(np.abs(g[A]) <= tol) and np.all(g[~A] >= -tol))

    def answer(self, ended, law, stats, unheld):
        """The correction's answer (U, ν, iterations) from its ``ended`` iterate (``law``:
        g, p, k, the equalities, the tolerance, the scale of :func:`_residual`): where a
        frozen set left the law unsettled, ``unheld()`` if it is not None (the held rows
        unilateral); else the iterate, counted in ``stats`` (a frozen set, or
        complementarity updates that settled) with its residual."""
        nu = ended[1]
        if self.frozen is not None and not _settled(nu, *law):
            again = unheld()
            if again is not None:
                return again
        if stats is not None and self.frozen is not None:
            stats.frozen_active_sets += 1
        elif stats is not None and self.solved:
            stats.complementary_corrections += 1
        _record(stats, "position", nu, *law)
        return ended


def _update_settled(dU: float, dU_prev: float, tol_u: float, tol_gap: float) -> bool:
    """Whether the position update has converged: it is below tol_u, or it contracts
    (ρ = dU/dU_prev < ½) so fast that the distance left to the solution, at most
    ρ/(1 − ρ) dU, is (Newton's quadratic phase: the update that would confirm it costs a solve
    and changes U by round-off); or it stalls at the round-off of the solve (H − C of a stiff
    body amplifies it past tol_u) while far below the gap tolerance: an update that stalls or
    cycles above the gap tolerance has not converged."""
    rho = dU / dU_prev if np.isfinite(dU_prev) and dU_prev > 0.0 else 1.0
    return (
        dU <= tol_u
        or (rho < 0.5 and rho / (1.0 - rho) * dU <= tol_u)
        or (dU > 0.5 * dU_prev and dU <= tol_gap)
    )


def _next_active_set(A, nu, g, p, k, eq) -> np.ndarray:
    """The contacts of the next Newton update (joints ``eq`` always among them). The first
    set is where k ν − p g > 0. After that a contact leaves the set when its force turns
    negative, and enters it when it penetrates: k ν − p g > 0 would also drop a pressed
    contact whose linearised gap came out slightly open (the curvature's second-order
    error), and with a large p the set then cycles between pressed and open."""
    if A is None:
        return ((k * nu - p * g) > 0) | eq
    # (a row whose gap became undefined, g = +inf with a zero gradient, leaves: it holds
    # nothing, and kept it put inf in the Schur right-hand side and NaN in U)
    return np.where(A, (nu > 0) & (g < np.inf), g < 0) | eq


def one_of_twins(A: np.ndarray, g: np.ndarray, twins) -> np.ndarray:
    """The active set A with at most one of two twin rows, two constraints on one node along
    nearly the same normal (``twins``: each row's twin, −1 for none; None: no twins): the
    one of smaller gap, the first on a tie. Both in one set are nearly redundant, and the
    Schur complement splits their multipliers into large forces of opposite signs
    (:mod:`fecontact.contact.mortar_safeguard`)."""
    if twins is None:
        return A
    t = np.maximum(twins, 0)
    first = np.arange(len(g)) < t
    other = (twins >= 0) & A & A[t] & ((g > g[t]) | ((g == g[t]) & ~first))
    return A & ~other


def _close(last, A, w) -> bool:
    """Whether the system ``last`` = (A, w, solve, C) serves the active set A with curvature
    weights w."""
    if last is None or last[3] is None or not np.array_equal(A, last[0]):
        return False
    return bool(np.all(np.abs(w - last[1]) <= 0.1 * np.abs(last[1])))


def solve_velocity_jump(
    G, c, solve_M, p, k, max_iter=30, bilateral=None, Y=None, Lam0=None, tol=0.0, stats=None,
    scale=1.0,
):  # fmt: skip
    """Velocity jump v = ṽ + W: M W = Σ G_jᵀ [k Λ_j − p ġ_j]_+ with ġ = c + G W and
    k Λ_j − [k Λ_j − p ġ_j]_+ = 0 (c_j = G_j ṽ + e_j G_j(q_n) v_n). Linear in W for a given
    active set, so the iteration ends when the set repeats, or when the law's error (as a
    velocity, m/s, whatever p: ``scale`` as in :func:`solve_position_correction`) is below
    ``tol``. ``bilateral`` rows (joints) are always
    active: G_b v = 0. ``Y`` may give M⁻¹Gᵀ; ``Lam0`` warm-starts the multipliers (those of
    the previous step: see :func:`solve_position_correction`); ``stats`` as there. Returns
    (W, Λ, iterations)."""
    m = len(c)
    Lam = np.zeros(m) if Lam0 is None else np.maximum(np.asarray(Lam0, dtype=float), 0.0)
    gd = np.asarray(c, dtype=float)
    Gd = G.toarray() if sp.issparse(G) else np.asarray(G)
    Y_all = solve_M(Gd.T).reshape(-1, m) if Y is None else Y
    eq = np.zeros(m, bool) if bilateral is None else bilateral
    law = (p, k, eq, tol, scale)
    if m and eq.all():  # (every row an equality: the set is known, one solve)
        return _held_jump(Gd, c, Y_all, law, stats)
    A_prev = None
    W = np.zeros(Y_all.shape[0])
    redundant = False  # (an active set's rows were redundant: least squares)
    for it in range(1, max_iter + 1):
        A = ((k * Lam - p * gd) > 0) | eq
        if A_prev is not None and (  # ((A == A_prev).all(): np.array_equal's checks cost more)
            (A == A_prev).all() or (tol > 0 and _settled(Lam, gd, p, k, eq, tol, scale))
        ):
            if redundant:
                W, Lam, gd = _redundant_jump(Gd, c, Y_all, (W, Lam, gd), law, stats)
            _record(stats, "velocity", Lam, gd, p, k, eq, tol, scale)
            return W, Lam, it - 1
        Lam = np.zeros(m)
        if A.any():
            GA = Gd[A]
            Lam[A], singular = schur_multipliers(k * (GA @ Y_all[:, A]), -c[A], stats, GA=GA)
            redundant |= singular
        W = k * (Y_all @ Lam)
        gd = c + Gd @ W
        A_prev = A
    if redundant:  # (an active set cycling between redundant rows)
        return _cycling_jump(Gd, c, Y_all, (W, Lam, gd), law, stats, max_iter)
    raise RuntimeError(_unsettled_jump(Lam, gd, law, max_iter))


def _unsettled_jump(Lam, gd, law, max_iter: int) -> str:
    """Why the jump stopped, with the law's residual where it stopped (N·s): the largest
    |k Λ_j − [k Λ_j − p ġ_j]_+| of the contacts, |p ġ_j| of the equalities. (The run's
    failure message takes it: the time and step it names then come with a residual.)"""
    p, k, eq, _, _ = law
    r = np.where(eq, p * gd, k * Lam - np.maximum(k * Lam - p * gd, 0.0))
    worst = float(np.max(np.abs(r), initial=0.0))
    return (
        f"velocity jump: active set did not settle in {max_iter} iterations "
        f"(law residual {worst:.3e} N·s)"
    )


def _held_jump(Gd, c, Y, law, stats):
    """:func:`solve_velocity_jump` where every row is an equality (joints, held contacts):
    the active set is every row, so its first solve is the jump (the loop took a second
    iteration to see the set repeat); least squares on redundant rows as there."""
    p, k, eq, tol, scale = law
    # (the rows taken as the loop takes a set: copies in its layout, the same round-off)
    GA = Gd[eq]
    Lam, singular = schur_multipliers(k * (GA @ Y[:, eq]), -c[eq], stats, GA=GA)
    W = k * (Y @ Lam)
    gd = c + Gd @ W
    if singular:
        W, Lam, gd = _redundant_jump(Gd, c, Y, (W, Lam, gd), law, stats)
    _record(stats, "velocity", Lam, gd, p, k, eq, tol, scale)
    return W, Lam, 1


def _cycling_jump(Gd, c, Y, jump, law, stats, max_iter: int):
    """The jump (W, Λ, ġ) whose active sets cycled between redundant rows for ``max_iter``
    iterations, solved again by :func:`_redundant_jump`: (W, Λ, ``max_iter``) where the law
    then holds to its tolerance; raises RuntimeError otherwise."""
    p, k, eq, tol, scale = law
    W, Lam, gd = _redundant_jump(Gd, c, Y, jump, law, stats)
    if tol > 0 and _settled(Lam, gd, p, k, eq, tol, scale):
        _record(stats, "velocity", Lam, gd, p, k, eq, tol, scale)
        return W, Lam, max_iter
    raise RuntimeError(_unsettled_jump(Lam, gd, law, max_iter))


def _redundant_jump(Gd, c, Y, jump, law, stats):
    """The jump (W, Λ, ġ) as given where the law holds (or has no tolerance), else, its
    active sets having been redundant, solved again by
    :func:`fecontact.contact.redundant_jump.proximal_jump` from Λ (``law``: p, k, the
    bilateral rows, the tolerance in m/s and the scale of :func:`_residual`); as given where
    that does not settle either. Counted in ``stats.redundant_jumps`` (its proximal steps
    in ``stats.redundant_jump_steps``)."""
    p, k, eq, tol, scale = law
    Lam = jump[1]
    if tol <= 0 or _settled(Lam, jump[2], p, k, eq, tol, scale):
        return jump
    kD = k * (Gd @ Y)

    def settled(x, gd):
        return _settled(x, gd, p, k, eq, tol, scale)

    found = proximal_jump(kD, c, eq, Lam, settled, tol)
    if stats is not None:
        stats.redundant_jumps += 1
        stats.redundant_jump_steps += 0 if found is None else found[1]
    if found is None:
        return jump
    Lam = found[0]
    W = k * (Y @ Lam)
    return W, Lam, c + Gd @ W
