"""Redundant frictional contacts: more closed rows than the degrees of freedom they move (a
box face's four corners on a plane: four normal rows on the three dofs that lift it). The
law's multipliers are then not unique, and Coulomb friction can make the motion depend on
which are taken; the choices here depend on neither p nor k (see
:func:`fecontact.contact.friction.solve_coulomb` with ``minimum_norm``)."""

from __future__ import annotations

import numpy as np

from ..linalg.svd import lstsq, svd
from .coulomb_newton import (
    NotConverged,
    coulomb_projection,
    newton,
    newton_jacobian,
    newton_residual,
    penalty_factor,
    stopping_error,
)
from .lemke import lemke

__all__ = [
    "closed_member",
    "closed_solution",
    "grazing_closed",
    "least_norm",
    "one_open",
    "pivoted",
    "proximal",
    "reachable_slips",
    "without_round_off",
]


def proximal(c, D, p, k, mu, nt, x0, tol, max_iter, stats, steps=40, stall=5):
    """Where Newton stalls on redundant rows (D singular: a face's nodes, corners and edges
    on one plane), the law solved by the proximal point method, as the frictionless rows
    are (:mod:`.redundant_jump`): each step solves it by Newton with D + εI and c − kεx^i,
    whose Jacobian is regular, and the fixed point is the law's with D. Along D's null
    space (forces that move nothing) a step moves x by the rows' inconsistency over ε, so
    that a row that has to open does so at once; in D's range a step leaves the error
    ε(x^{i+1} − x^i). ε starts at 1e-8 of D's largest diagonal; a step whose Newton fails
    is taken again from the same x with ε × 100 (up to 1e-2: near-parallel rows make
    D + εI with a small ε as hard as D), and after each step that converges ε falls by
    ten again. Stops on the law's own error with D (:func:`stopping_error`, in the units
    of w, whatever p), so that ε only steers the path; a start whose error has not halved
    over ``stall`` steps is left (the law is not monotone: on the box sliding flat, steps
    settled with 20 contacts slipping and their normal rows inside by 4 times the tolerance,
    where the law's solution opens 9 of the 25) for :func:`pivoted` from where it settled.
    From ``x0``, then from zero where that start does not solve it. Returns (x, Newton
    iterations) or None; counted in ``stats.proximal_solves`` and ``stats.proximal_steps``."""
    scale = float(np.max(np.diag(D), initial=0.0))
    if not scale > 0.0:
        return None
    N, nc = len(c), len(mu) * (1 + nt)
    weight = penalty_factor(D, p, nc, 1 + nt)
    for start in (x0, None) if x0 is not None else (None,):
        x = np.zeros(N) if start is None else np.asarray(start, dtype=float)
        its, rel, errors = 0, 1e-8, []
        for step in range(1, steps + 1):
            if len(errors) > stall and errors[-1] > 0.5 * errors[-1 - stall]:
                break  # (settled at a fixed point that is not the law's)
            eps = rel * scale
            regular = D + eps * np.eye(N)
            try:
                x_new, _, n = newton(c - k * eps * x, regular, p, k, mu, nt, x, 0.1 * tol,
                                     max_iter, stats)  # fmt: skip
            except NotConverged:
                if rel >= 1e-2:
                    break
                rel = min(1e-2, 100.0 * rel)
                continue
            x, its, rel = x_new, its + n, max(1e-8, 0.1 * rel)
            R, (_, ident), _ = newton_residual(x, c, k * D, p, k, mu, nc)
            errors.append(stopping_error(R, ident, weight))
            if errors[-1] <= tol:
                stats.proximal_solves += 1
                stats.proximal_steps += step
                return x, its
        found = pivoted(c, D, p, k, mu, nt, x, tol, max_iter, stats) if errors else None
        if found is not None:
            return found[0], its + found[1]
    return None


def pivoted(c, D, p, k, mu, nt, x, tol, max_iter, stats, rounds=3):
    """The law solved from x where the proximal iterations settled without solving it: with
    each contact's tangential status held as x reads it (slipping along σ_T at μ times its
    normal multiplier, open contacts too where σ_T ≠ 0; sticking, w_T = 0, otherwise), the
    law is a linear complementarity problem in the normal multipliers, the sticking
    tangents and the equality rows as free unknowns (eliminated by their minimum-norm
    least squares: redundant rows), solved by Lemke's pivoting (:func:`.lemke.lemke`): it
    opens and closes every contact at once, where leaving one out at a time
    (:func:`one_open`) took a Newton per contact. Newton on the full law finishes from there
    (the slip directions move with the answer). Where it does not, the statuses are read
    again at the pivoted answer and pivoted again, up to ``rounds`` times (thrown at 0.1 m/s,
    at 26 ms: the second round's Newton converged in 14 iterations where the first stalled).
    Returns (x, iterations) or None; counted in ``stats.pivoted_solves``, ``stats.pivots``
    and ``stats.pivoted_failures``."""
    for _ in range(rounds):
        x = _pivoted_start(c, D, p, k, mu, nt, x, stats)
        if x is None or not np.isfinite(x).all():
            break
        try:
            x, _, its = newton(c, D, p, k, mu, nt, x, tol, max_iter, stats)
        except NotConverged:
            continue
        stats.pivoted_solves += 1
        return x, its
    stats.pivoted_failures += 1
    return None


def _pivoted_start(c, D, p, k, mu, nt, x, stats):
    """The multipliers of the complementarity problem of :func:`pivoted` with the statuses
    x reads, or None where Lemke's path ends on a ray."""
    E, rows = _held_statuses(c, D, p, k, mu, nt, x)
    M, q, m = k * (D[rows] @ E), c[rows], len(mu)
    X, fell_back = lstsq(M[m:, m:], np.column_stack([M[m:, :m], q[m:]]), rcond=1e-10)
    stats.svd_fallbacks += fell_back
    z, pivots = lemke(M[:m, :m] - M[:m, m:] @ X[:, :m], q[:m] - M[:m, m:] @ X[:, m])
    stats.pivots += pivots
    return None if z is None else E @ np.concatenate([z, -(X[:, m] + X[:, :m] @ z)])


def _held_statuses(c, D, p, k, mu, nt, x):
    """(E, rows) of :func:`pivoted`: x = E z for the unknowns z (the normal multipliers,
    the tangential ones of the contacts that stick, the equality rows), a slipping
    contact's tangential multiplier μ x_N s along the unit s of its σ_T at x; ``rows``: the
    rows of w that z answers (the normal rows, the sticking tangents, the equality rows)."""
    m, b, N = len(mu), 1 + nt, len(c)
    nc = m * b
    sigma = (k * x - p * (c + k * (D @ x)))[:nc].reshape(m, b)
    status = coulomb_projection(sigma, mu, jacobian=False)[2]
    norm = np.linalg.norm(sigma[:, 1:], axis=1)
    stick = (mu > 0.0) & ((status == 1) | (norm == 0.0))
    s = np.divide(sigma[:, 1:], norm[:, None], out=np.zeros((m, nt)), where=norm[:, None] > 0)
    held = np.flatnonzero(stick)
    tangents = (held[:, None] * b + 1 + np.arange(nt)).ravel()
    E = np.zeros((N, m + tangents.size + N - nc))
    j = np.arange(m)
    E[j * b, j] = 1.0
    E[(j * b)[:, None] + 1 + np.arange(nt), j[:, None]] = np.where(
        stick[:, None], 0.0, mu[:, None] * s
    )
    E[tangents, m + np.arange(tangents.size)] = 1.0
    E[nc:, m + tangents.size :] = np.eye(N - nc)
    return E, np.concatenate([j * b, tangents, np.arange(nc, N)])


def one_open(c, D, p, k, mu, nt, x0, tol, max_iter, stats):
    """Where Newton stalls at a nonzero minimum of |R|² on redundant rows (a box's four
    corners all held closed while the law needs one to lift: the rows are inconsistent for
    those statuses), the law on every contact but one, kept where the one left out
    separates (w_N ≥ −tol): (x, iterations) of the least-norm of those, or None. Counted in
    ``stats.opened_contact_solves``."""
    m, b = len(mu), 1 + nt
    best = None
    for j in range(m):
        keep = np.flatnonzero((np.arange(len(c)) // b != j) | (np.arange(len(c)) >= m * b))
        sub = np.ix_(keep, keep)
        start = None if x0 is None else x0[keep]
        try:
            xr, _, its = newton(
                c[keep], D[sub], p[keep], k, np.delete(mu, j), nt, start, tol, max_iter, stats
            )
        except NotConverged:
            continue
        x = np.zeros(len(c))
        x[keep] = xr
        lifts = c[j * b] + k * (D[j * b] @ x) >= -tol
        if lifts and (best is None or np.linalg.norm(x) < np.linalg.norm(best[0])):
            best = x, its
    if best is None:
        return None
    stats.opened_contact_solves += 1
    return best


EDGE = 1e-9
"""How near the edge of its cone a sticking contact's multipliers lie, |x_T| ≥ (1 − EDGE)
μ x_N, for :func:`least_norm` to read the family's directions on its slip branch: a contact
that Newton brought to the edge sits there to round-off (within 4.3e-16 of μ x_N on a box
held on an incline), one that sticks inside it lies further in (0.15 on that box), and the
margin between them is a multiplier's, whatever p."""


def least_norm(c, D, p, k, mu, nt, x, tol, stats, rcond=1e-10, cycles=8, closing=None):
    """Of the solutions of the law around the solution x, the one of least norm |x|.

    Redundant rows (a box face's four corners on a plane: four normal rows on the three
    dofs that lift it) leave a family of solutions: impulses that move no body (internal
    forces between sticking corners), and, where a corner slips, normal impulses traded
    between the corners whose friction then moves the body differently. Which member the
    semi-smooth Newton reaches depends on its path, and with it on p, k and the warm start.
    The family's directions at x are the null space Z of the Jacobian of R/p (singular
    values below ``rcond`` of the largest); x is moved to x − ZZᵀx (the least-norm point of
    the family's tangent plane) and Newton brings it back onto the law with minimum-norm
    steps, which stay orthogonal to Z. On a straight family (frictionless, sticking) one
    cycle reaches the least-norm solution; friction curves it, and the cycles repeat until
    the move is below 1e-12 of |x|. A contact that sticks at the edge of its cone (``EDGE``)
    is read on its slip branch for these directions: the least-norm member puts the less
    loaded corners of a box held on an incline near its friction angle there, where their
    status is round-off's, and the stick branch's directions, which let x_T grow past the
    cone, sent the moves round other members until the cycles' limit
    (docs/explanation/friction.md). The rule involves neither p nor k: with a frictionless
    law it is the limit of a uniform contact compliance going to zero. Where the cycles end
    unsettled (their limit reached, or a cycle's Newton failed) the least-norm of the
    solutions visited, x among them, is kept: the cycles can go round a loop of members
    (the 2 × 2 pile at k ÷ 100: three, sticking and slipping in turn, |x| equal to 8e-9
    of it and rates 1.1e-13 m apart), and the one they stop on would read where the loop
    was entered, which a relinearization's warm start moves (docs/validation/pile.md).
    Counted in ``stats.least_norm_unsettled``, the moves in ``stats.least_norm_moves``.

    A family can end at a contact that opens: its normal multiplier reaches zero with its
    normal row at zero (a grazing contact, |w_N| ≤ ``tol``). There the open branch's
    Jacobian pins the multiplier and hides the family, and a Newton that ends at that end
    keeps it whatever the member of least norm: on a box sliding on a box (nine contacts,
    27 rows on 12 dofs) the default p reached the end, p × 1e3 and k ÷ 100 the least-norm
    member, 8e-4 m/s apart. The family's directions are therefore read with the grazing
    contacts on their closed branch, and such a move is kept only where it lowers |x|.
    ``closing`` (m,) bool: contacts held on their closed branch throughout
    (:func:`grazing_closed`)."""
    kD = k * D
    nc, N = len(mu) * (1 + nt), len(c)
    dsigma = k * np.eye(N) - p[:, None] * kD
    status, visited = None, []
    for _ in range(cycles):
        R, (dPi, ident), status = newton_residual(x, c, kD, p, k, mu, nc, closing)
        visited.append((x, status))
        grazing = (status == 0) & (np.abs(c[: nc : 1 + nt] + kD[: nc : 1 + nt] @ x) <= tol)
        held = closing
        if grazing.any():
            held = grazing if closing is None else grazing | closing
        if grazing.any() or np.any(status == 1):
            dPi, ident = newton_residual(x, c, kD, p, k, mu, nc, held, edge=EDGE)[1]
        _, s, Vt, fell_back = svd(newton_jacobian(kD, dsigma, dPi, ident, p, k))
        stats.svd_fallbacks += fell_back
        Z = Vt[s <= rcond * s[0]]
        shift = Z.T @ (Z @ x)
        if np.linalg.norm(shift) <= 1e-12 * np.linalg.norm(x):
            return x, status
        stats.least_norm_moves += 1
        try:
            y, found, _ = newton(c, D, p, k, mu, nt, x - shift, tol, 50, stats, closing)
        except NotConverged:
            break
        if grazing.any() and np.linalg.norm(y) >= np.linalg.norm(x):
            return x, status  # (the family through the grazing contacts is no lower)
        x, status = y, found
    stats.least_norm_unsettled += 1
    visited.append((x, status))
    return min(visited, key=lambda member: np.linalg.norm(member[0]))


def grazing_closed(c, D, p, k, mu, nt, x, status, tol, stats, band=1e-6, most=3):
    """Of the solution x and those that differ from it by closing a nearly grazing contact,
    the one of least norm, where the closed one is found whatever the search's start.

    Near a grazing corner the law can have two solutions: one closes the corner with a
    normal impulse, the other leaves it open at a normal rate barely above zero; which one
    Newton reaches depends on p, k and the warm start. A contact is nearly grazing when it
    is open at x with 0 < w_N ≤ ``band`` k D_jj |x|: the rate that an impulse of ``band``
    times the whole jump's makes at that contact alone (the rows' scale, whatever p). Up
    to ``most`` of them, the lowest first, are tried (:func:`closed_solution`); the one of
    least norm below |x| is checked on the law at the run's p (:func:`on_the_law`). Counted
    in ``stats.grazing_tries``, ``stats.grazing_unsettled`` (tries dropped: a search that
    failed, or a start that reached another solution) and ``stats.grazing_closed``; where
    no contact is nearly grazing x is returned as it is, at the cost of one product D x."""
    m, b = len(mu), 1 + nt
    nc, size = m * b, float(np.linalg.norm(x))
    w_n, d_n = (c + k * (D @ x))[:nc:b], np.diag(D)[:nc:b]
    near = np.flatnonzero((status == 0) & (w_n > 0.0) & (w_n <= band * k * d_n * size))
    if not near.size:
        return x, status
    near = near[np.argsort(w_n[near] / d_n[near])][:most]
    stats.grazing_tries += near.size
    rows = p / penalty_factor(D, p, nc, b)  # the rows' own scale 1/D_ii: reads no p
    best = x, status
    for j in near:
        found = closed_solution(c, D, rows, k, mu, nt, x, status, j, tol, stats)
        if found is not None and np.linalg.norm(found[0]) < np.linalg.norm(best[0]):
            best = found
    kept = None if best[0] is x else on_the_law(c, D, p, k, mu, nt, *best, tol, stats)
    if kept is None:
        return x, status
    stats.grazing_closed += 1
    return kept


def closed_solution(c, D, rows, k, mu, nt, x, status, j, tol, stats):
    """The solution of the law that closes contact j, open at x: (x, status) or None.

    Searched from x with j held closed (:func:`closed_member`). It is None where the search
    fails, where no contact open at x carries more than round-off in it (it is then x's own
    solution, moved within its family: on the box thrown flat on an elastic cube such moves,
    2.3e-14 against |x| 1.0e-7, were taken at p × 100 and not at the default and parted the
    runs by 1.4e-6 m in 3 steps), and
    where the search from zero reaches another closed solution, whose rates differ by more
    than ``tol``: on a singular Delassus matrix the closed member found can depend on the
    start (on the box on a box, from zero a contact stuck that slips from x, 2.1e-7 m/s
    apart), and the start depends on p. A search from zero that fails, or that ends on a
    solution closing no contact open at x (x's own), says nothing about the closed member
    (whether Newton converges from zero is its path's, which reads p and k)."""
    m = len(mu)
    held = np.arange(m) == j
    found = closed_member(c, D, rows, k, mu, nt, x, held, tol, stats)
    if found is None:
        stats.grazing_unsettled += 1
        return None
    y, closed = without_round_off(*found, m, nt)
    if not np.any((status == 0) & (closed != 0)):
        return None
    other = closed_member(c, D, rows, k, mu, nt, None, held, tol, stats)
    if other is None:
        return y, closed
    z, also = without_round_off(*other, m, nt)
    if np.any((status == 0) & (also != 0)) and np.max(np.abs(k * (D @ (z - y)))) > tol:
        stats.grazing_unsettled += 1
        return None
    return y, closed


def closed_member(c, D, rows, k, mu, nt, x0, held, tol, stats):
    """The law's least-norm solution reached from ``x0`` (None: zero) with the contacts
    ``held`` on their closed branch, at the rows' own scale p = ``rows`` = 1/D_ii, so that
    the search reads no p: Newton and :func:`least_norm` with them held, then Newton and
    :func:`least_norm` on the law itself. Returns (x, status), or None where a Newton does
    not converge."""
    try:
        y = newton(c, D, rows, k, mu, nt, x0, tol, 50, stats, closing=held)[0]
        y = least_norm(c, D, rows, k, mu, nt, y, tol, stats, closing=held)[0]
        y = newton(c, D, rows, k, mu, nt, y, tol, 50, stats)[0]
    except NotConverged:
        return None
    return least_norm(c, D, rows, k, mu, nt, y, tol, stats)


def on_the_law(c, D, p, k, mu, nt, x, status, tol, stats):
    """x, a solution of the law within ``tol`` found at another p, checked at the run's p
    (the error is in the units of w, so it holds at every p up to round-off) and finished
    by Newton at the run's p where it is not (counted in ``stats.grazing_finished``);
    None where that Newton does not converge (counted in ``stats.grazing_unsettled``)."""
    nc = len(mu) * (1 + nt)
    R, (_, ident), _ = newton_residual(x, c, k * D, p, k, mu, nc)
    if stopping_error(R, ident, penalty_factor(D, p, nc, 1 + nt)) <= tol:
        return x, status
    stats.grazing_finished += 1
    try:
        return newton(c, D, p, k, mu, nt, x, tol, 50, stats)[:2]
    except NotConverged:
        stats.grazing_unsettled += 1
        return None


def without_round_off(x, status, m: int, nt: int):
    """x with the contacts whose normal multiplier is round-off of the largest (1e-14 of
    it) carrying nothing: such a contact is grazing (zero gap, zero force), and the sign of
    its round-off would decide whether the next step counts it as pressed (and gives it
    slip rows)."""
    blocks = x[: m * (1 + nt)].reshape(m, 1 + nt)
    idle = blocks[:, 0] <= 1e-14 * np.max(np.abs(x), initial=0.0)
    idle &= np.any(blocks != 0.0, axis=1)
    if not idle.any():
        return x, status
    x = x.copy()
    x[: m * (1 + nt)].reshape(m, 1 + nt)[idle] = 0.0
    return x, np.where(idle, 0, status)


def reachable_slips(c, D, mu, nt: int, stats, rcond=1e-10):
    """The rows c of a position correction (w = c + k D x; contacts of 1 + nt rows with
    friction coefficients ``mu``, then equality rows) with the part of their slips that no
    multiplier reaches removed: the projection of c on the left null space of D over the
    rows that can carry a force (singular values below ``rcond`` of the largest), taken
    off the tangent rows of the contacts with friction. None where there is none.

    The slip over the step, T(x_rel(q) − x_rel(q_n)), is the finite motion of each point
    projected on the contact plane. Where a rigid face lands flat, tilted at t_n by θ, its
    corners' projections draw in by (1 − cos θ) times their distance from the centre: a
    stretch of the face, second order in the step, that no rigid motion (no combination of
    the rows) makes or undoes. Sticking asks w_T = 0 on all four corners and cannot be met
    where that stretch exceeds the tolerance, at any p. What the rows can tell is the rest,
    the slip of the face as a rigid body. The normal rows keep their gaps: a gap no
    multiplier closes is met by the law opening the contact. A frictionless contact's
    slip is free and stays out: a corner landing without friction beside a pivot that
    sticks does not share the pivot's slip. ``stats``: the
    :class:`fecontact.contact.stats.CoulombStats` that counts a decomposition taken again
    (:func:`fecontact.linalg.svd.svd`)."""
    m, b = len(mu), 1 + nt
    i = np.arange(len(c))
    frictionless = np.zeros(len(c), bool)
    frictionless[: m * b] = np.repeat(np.asarray(mu) == 0.0, b)
    keep = np.flatnonzero(~((i < m * b) & (i % b > 0) & frictionless))
    if not keep.size:
        return None
    U, s, _, fell_back = svd(D[np.ix_(keep, keep)])
    stats.svd_fallbacks += fell_back
    Z = U[:, s <= rcond * s[0]]
    tangential = (keep < m * b) & (keep % b > 0)
    r = np.where(tangential, Z @ (Z.T @ c[keep]), 0.0)
    if not Z.shape[1] or not r.any():
        return None
    out = c.copy()
    out[keep] -= r
    return out
