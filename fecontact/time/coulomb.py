r"""Coulomb friction at every level of the NSGA step.

In the decoupled step the smooth step carries no contact force, so its predictor moves a
contact point along the contact plane by the O(h²) pull of the tangential load, as it moves
it into the obstacle. Both corrections therefore carry the slip rows of
:mod:`fecontact.contact.friction` beside the normal ones (after Alart & Curnier 1991, in the
decoupled form of Galvez, Cavalieri, Cosimo, Brüls & Cardona 2020):

- position level, q = q̃ + U: the slip over the step,
  w_T = T(x_rel(q) − x_rel(q_n)) − T(d_{n+1} − d_n) ≈ G_T(q)(q − q_n) − T Δd, in the cone
  |ν_T| ≤ μ ν_N of the normal correction: a contact that sticks does not creep, one that
  slips is held back by μ ν_N. Only contacts closed (or pressed) at t_n have it: the
  tangential motion of a contact that lands within the step is no slip (its impact is a
  velocity-level matter);
- velocity level, v = ṽ + W: the slip rate w_T = G_T v − T ḋ in the cone |Λ_T| ≤ μ Λ_N;
  Newton's law stays normal (no tangential restitution).

Where the smooth step carries the normal force of persistent contacts
(:mod:`.smooth_contact`), it carries their tangential force too, under the same law at
position level (:class:`SmoothFriction`); the corrections then hold the step's total in the
cone, the smooth forces' share preloaded, and the acceleration restart after an impact
solves the law at the acceleration level (:func:`frictional_restart`).

Each level solves :func:`fecontact.contact.friction.solve_coulomb` on the Delassus matrix
A H⁻¹ Aᵀ of its rows A (H the correction metric, M for the jump, S_t in the smooth step). The
position level relinearizes the gaps at q̃ + U until U settles: circles and rotating bodies
curve them. Joints stay equalities (rows after the contacts).
"""

from __future__ import annotations

import math

import numpy as np

from ..contact.contact_set import whole_points
from ..contact.friction import coulomb_residual, solve_coulomb
from ..contact.friction_redundant import reachable_slips
from ..contact.restitution import friction_dissipation
from .configuration import plus
from .constraints import Constraints, StepFailure, constraint_columns
from .correction import correction_metric

__all__ = [
    "SmoothFriction",
    "frictional_correction",
    "frictional_jump",
    "frictional_restart",
    "frictional_start",
]


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


def frictional_correction(model, st, q_tilde, work, solve_H, opts, tol_gap, t, preload=None):
    """Position correction q = q̃ + U over the contacts ``work`` and the joints, with slip
    rows. Returns (U, k ν_N (len(work),), k ν_T (len(work), nt), U_T, iterations) with
    U_T = H⁻¹ G_Tᵀ k ν_T the part of U that friction moves (its work against the applied
    and internal forces is the positional share of the friction work).

    ``preload`` (len(work), 1 + nt): positional multipliers the contacts already carry, the
    smooth forces as (λ_N, λ_T)/β′ (in the metric H = S_t/β′, H⁻¹Gᵀλ/β′ = S_t⁻¹Gᵀλ). The
    law then holds for the total kν + preload, as in :func:`frictional_jump`: a contact
    held in the smooth step keeps its grip while the correction of another moves the body.

    Without ``opts.positional_friction`` (the decoupled step of the models that settle) a
    contact keeps its slip rows only where the correction holds it stuck (and it was not
    struck in the last step, whose record marks it): one that the correction slips at the
    cone's edge is solved again without them, its friction the jump's
    (:func:`fecontact.time.settings.positional_friction`)."""
    mu = _slip_coefficients(model.contacts, st, work, tol_gap)
    out = _correct(model, st, q_tilde, work, solve_H, opts, tol_gap, t, preload, mu)
    slipping = (out[-1] == 2) & (mu > 0.0)
    if opts.positional_friction or not slipping.any():
        return out[:-1]
    its = out[-2]
    mu = np.where(slipping, 0.0, mu)
    out = _correct(model, st, q_tilde, work, solve_H, opts, tol_gap, t, preload, mu)
    return (*out[:-2], its + out[-2])


def _slip_coefficients(contacts, st, work, tol_gap) -> np.ndarray:
    """μ of the slip rows of the contacts ``work`` in the position correction (0: none)."""
    mu = contacts.friction[work]
    if st.gaps.size == contacts.size:  # slip counts from contact on: closed ones at t_n only
        # (or pressed in the step before: after a rebound split inside a step a contact that
        # strikes again may start its sub-step a little open; without its rows its normal
        # correction turns the body against the others' grip)
        # (a node closed by one of its rows slips on the others too: concave_rows)
        closed = (st.gaps <= tol_gap) | st.pressed()
        mu = np.where(whole_points(contacts, closed)[work], mu, 0.0)
        if st.smooth is not None and st.smooth.closing is not None:
            # settling beams (and their decoupled step, which marks its strikes too): a
            # contact struck in the last step takes its lasting force, and
            # friction with it, in the next smooth step; in this one its tangential motion is
            # what the strike's jump left under Coulomb's law. Slip rows here pulled the
            # predictor's slip back along the strip in its own metric S_t/β′, bending the
            # ringing strip: 2.4e-4 J of strain on the founding case at μ = 1
            mu = np.where(st.smooth.closing[work] > 0.0, 0.0, mu)
    return mu


def _correct(model, st, q_tilde, work, solve_H, opts, tol_gap, t, preload, mu):
    """The Newton loop of :func:`frictional_correction` with the slip coefficients ``mu``;
    returns its results, then the contacts' status (0 open, 1 stick, 2 slip)."""
    contacts, F = model.contacts, model.free
    cons = Constraints(model, work)
    m, k = len(work), opts.multiplier_scale
    shift = _obstacle_shift(contacts, work, st.t, t)
    U, x, its, dU = np.zeros(len(F)), None, 0, np.inf
    pre = None
    for _ in range(opts.max_iterations):
        q = plus(model, q_tilde, U)
        g, G = cons.jacobian(q)
        GT, T = contacts.tangent_jacobian(q, work)
        slip = contacts.slips(q, st.q, work, GT, T)
        if shift is not None:
            slip -= np.einsum("mtd,md->mt", T, shift)
        A = _rows(G, GT)
        Y = solve_H(A.T).reshape(len(F), -1)
        D = A @ Y
        c = _stack(g[:m], slip, g[m:]) - A @ U
        if pre is None:
            pre = np.zeros(len(c))
            if preload is not None:
                pre[: preload.size] = preload.ravel()
            x = None if not pre.any() else pre / k
        # (a relinearization starts from the last one's solution, chosen between the warm
        # and cold starts there: solving it from zero again, on redundant rows, doubled
        # the correction's iterations at rest)
        x, status, n = _position_law(
            c - D @ pre, D, mu, GT.shape[1], x, dU == np.inf, opts, tol_gap
        )
        its += n
        own = k * x - pre
        U_new = Y @ own
        dU = float(np.max(np.abs(U_new - U), initial=0.0))
        if not math.isfinite(dU):  # (a NaN or inf in U_new: no iterate to go on from)
            raise StepFailure("position correction: non-finite update", np.nan)
        U = U_new
        if dU <= 0.1 * tol_gap:
            nt = GT.shape[1]
            # a contact left open beyond the gap tolerance carries nothing in total: Newton
            # holds its multipliers to round-off only (k/p on its rows of the Newton
            # matrix), and their sign would decide whether the next step counts it pressed
            x = x.copy()
            x[: m * (1 + nt)].reshape(m, 1 + nt)[(status == 0) & (g[:m] > tol_gap)] = 0.0
            nu_n, nu_t, _ = _split(k * x - pre, m, nt)
            tangential = np.zeros(len(x), bool)
            tangential[: m * (1 + nt)] = np.arange(m * (1 + nt)) % (1 + nt) > 0
            return U, nu_n, nu_t, Y[:, tangential] @ own[tangential], its, status
    raise StepFailure(f"frictional position correction: update {dU:.3e} m did not settle", dU)


def _position_law(c, D, mu, nt, x0, cold_start, opts, tol_gap):
    """:func:`solve_coulomb` of the position correction. Where it fails on redundant rows
    the slips are solved again without the part no multiplier reaches
    (:func:`fecontact.contact.friction_redundant.reachable_slips`: the stretch of a face
    landing flat, second order in the step), counted in ``unreachable_slip_solves``;
    where they have none, or that fails too, the step fails."""
    stats = opts.stats.contact.coulomb

    def solve(c):
        p = _augmentation(D, opts.penalty_scale)
        redundant = opts.stats.contact.minimum_norm
        return solve_coulomb(c, D, p, opts.multiplier_scale, mu, nt, x0, tol_gap, stats=stats,
                             minimum_norm=redundant, cold_start=cold_start)  # fmt: skip

    try:
        return solve(c)
    except RuntimeError as err:
        failure = err
    reachable = reachable_slips(c, D, mu, nt, stats) if opts.stats.contact.minimum_norm else None
    if reachable is not None:
        try:
            found = solve(reachable)
        except RuntimeError:
            pass
        else:
            stats.unreachable_slip_solves += 1
            return found
    raise StepFailure(f"position correction: {failure}", np.nan) from None


def frictional_jump(model, st, q, v, closed, G1, gdot, opts, tol, solve=None, preload=None):
    """Velocity jump v = ṽ + W over the contacts ``closed`` (normal rates ``gdot`` with the
    impact law, then the joints' rows) with slip rows, in the metric ``solve`` = H⁻¹
    (default M⁻¹). Returns (W, k Λ_N, k Λ_T (len(closed), nt), status, iterations, work,
    k Λ_b of the joints): work (J) is the kinetic energy the tangential impulses take, read
    as acting after the normal ones (:func:`fecontact.contact.restitution.friction_dissipation`,
    ≥ 0 where Coulomb's law holds for the jump's own impulse).

    ``preload`` (len(closed), 1 + nt): impulses (N·s) the contacts already carry over the
    step, h(λ_N, λ_T) of the smooth forces. The law then holds for the step's total impulse
    kΛ + preload: Λ_N may be negative where it only lowers the smooth force's impulse, and
    the cone bounds the total tangential impulse by μ times the total normal one."""
    contacts, F = model.contacts, model.free
    m, k = len(closed), opts.multiplier_scale
    GT, T = contacts.tangent_jacobian(q, closed)
    nt = GT.shape[1]
    rate = GT @ v[F]
    speed = contacts.obstacle_motion(closed, velocity=True)
    if speed is not None:
        rate -= np.einsum("mtd,md->mt", T, speed)
    A = _rows(G1, GT)
    Y = (model.solve_M if solve is None else solve)(A.T).reshape(len(F), -1)
    D = A @ Y
    w = _stack(gdot[:m], rate, gdot[m:])
    pre = np.zeros(len(w))
    if preload is not None:
        pre[: m * (1 + nt)] = preload.ravel()
    x0 = None
    if st.impulse.size == contacts.size and st.friction is not None:
        x0 = _stack(st.impulse[closed], st.friction.impulse[closed], gdot[m:] * 0)
        x0 = (x0 + pre) / k
    try:
        x, status, its = solve_coulomb(
            w - D @ pre,
            D,
            _augmentation(D, opts.penalty_scale),
            k,
            contacts.friction[closed],
            nt,
            x0,
            tol,
            stats=opts.stats.contact.coulomb,
            minimum_norm=opts.stats.contact.minimum_norm,
        )
    except RuntimeError as err:
        raise StepFailure(f"velocity jump: {err}", np.nan) from None
    own = k * x - pre
    lam_n, lam_t, lam_b = _split(own, m, nt)
    W = Y @ own
    work = friction_dissipation(own, w, w + D @ own, D, contacts.friction[closed], nt, tol)
    return W, lam_n, lam_t, status, its, work, lam_b


def frictional_restart(model, q, v, x, rows, G, rates, tol_rate: float, stats=None, solve=None):
    r"""The contacts' share M⁻¹(Σ G_jᵀμ_N,j + G_T,jᵀμ_T,j) of the acceleration that restarts
    the generalized-α variable after an impact (:func:`.smooth_contact.restarted_acceleration`,
    whose free acceleration is ``x`` and whose normal acceleration rates are ``rates`` on
    the closed, non-separating ``rows`` with gradients ``G``), under Coulomb's law at the
    acceleration level: a contact that slips (|w_T| = |G_T v| above ``tol_rate``, m/s) is
    pulled back along its slip direction u, μ_T = −μ μ_N u (its normal column G − μ u·G_T);
    one that sticks keeps a zero tangential acceleration inside the cone, |μ_T| ≤ μ μ_N, or
    slides off against it. The law is met to 1e-12 of the largest free rate: a restart
    needs no more than the step's own accuracy. Returns (that share, the forces (μ_N, μ_T)
    (N) of the rows, (rows, 1 + nt)); ``stats``: the run's
    :class:`fecontact.contact.stats.ContactStats`; ``solve``: H⁻¹ in place of M⁻¹
    (:func:`frictional_start`)."""
    contacts, nt = model.contacts, model.dim - 1
    GT, _ = contacts.tangent_jacobian(q, rows)
    slip = GT @ v[model.free]
    speed = np.linalg.norm(slip, axis=1)
    sliding = speed > tol_rate
    u = np.divide(slip, speed[:, None], out=np.zeros_like(slip), where=sliding[:, None])
    mu = contacts.friction[rows]
    pulled = G - mu[:, None] * np.einsum("mt,mtn->mn", u, GT)
    GT_stuck = GT * ~sliding[:, None, None]
    A, B = _rows(G, GT_stuck), _rows(pulled, GT_stuck)
    Y = (model.solve_M if solve is None else solve)(B.T).reshape(len(model.free), -1)
    D = A @ Y
    c = _stack(rates, GT_stuck @ x, np.zeros(0))
    tol = 1e-12 * np.max(np.abs(c), initial=0.0)
    try:
        z, _, _ = solve_coulomb(
            c,
            D,
            _augmentation(D, 1.0),
            1.0,
            np.where(sliding, 0.0, mu),
            nt,
            None,
            tol,
            stats=None if stats is None else stats.coulomb,
            # (in the step's metric a stiff solid couples its rows: on the block on two rods
            # the Delassus matrix's condition is 1.3e5, and Newton after Gauss–Seidel took 55)
            max_iter=200,
        )
    except RuntimeError as err:
        raise StepFailure(f"restarted acceleration: {err}", np.nan) from None
    forces = z.reshape(-1, 1 + nt).copy()
    forces[sliding, 1:] = -(mu * forces[:, 0])[sliding, None] * u[sliding]
    return Y @ z, forces


def frictional_start(model, q, t: float, G, tol_rate: float, first):
    r"""The rate tolerance (m/s) and the metric H⁻¹ of a frictional run's start
    (:func:`.smooth_contact.resting_start`; ``G``: the gradients of the contacts touching at
    q, ``first``: the coefficients of the first step).

    H = S_t/β′ of the first step: the start's acceleration restarts a, and a contact the
    step holds turns what a carries into velocity, ṽ = h(1 − γ − γ(½ − β)/β) a₀ (h a₀/4 at
    ρ∞ = 0), which the velocity jump removes along the normal but across it only inside
    the cone the smooth force has filled. Through M⁻¹ a solid loaded along the face it
    rests on starts with its interior accelerating over that face, a mode the step does not
    resolve, and slides at that drift; through S_t⁻¹ it moves as the step moves it.

    A rate counts as zero, for the normal rates (resting) and the slip rates (sticking)
    alike, where it moves a contact over the step by less than 1e-6 of what the applied and
    internal forces f at (q, t) move the contacts by in it: max(``tol_rate``,
    ½·1e-6 max|G H⁻¹f| h). The rates of a state settled at a finer step are zero to that
    step's tolerance only. Measured in ``docs/explanation/friction.md``."""
    solve = correction_metric(model, q, None, first, "stiffness")[1]
    F = model.free
    f = model.external(t)[F] - model.internal(q, tangent=False)[1][F]
    load = float(np.max(np.abs(G @ solve(f)), initial=0.0))
    return max(tol_rate, 0.5e-6 * load * first.h), solve


class SmoothFriction:
    r"""The persistent frictional contacts ``P`` of one smooth step (:mod:`.smooth_contact`):
    normal forces λ_N ≥ 0 and tangential forces λ_T (N) at t_{n+1}, in the equations of
    motion as − Σ_{j∈P} (G_jᵀ λ_N,j + G_T,jᵀ λ_T,j), under Coulomb's law at position level
    over the step,

        0 ≤ g_j(q̃_{n+1}) ⊥ λ_N,j ≥ 0,   |λ_T,j| ≤ μ_j λ_N,j,
        w_T,j = T_j(x_rel(q̃_{n+1}) − x_rel(q_n)) − T_j Δd = 0 where |λ_T,j| < μ_j λ_N,j,
        λ_T,j = −μ_j λ_N,j w_T,j/|w_T,j| where it slips:

    a contact that sticks does not creep over the step, one that slips is held back by
    μ λ_N. Each Newton update solves this law on the rows linearised at the iterate, with
    the Delassus matrix D = A S_t⁻¹Aᵀ of the rows A = (G_j, G_T,j) and the dynamics'
    own update dq = S_t⁻¹(−r + Aᵀ Δλ): the semi-smooth Newton of
    :func:`fecontact.contact.friction.solve_coulomb` on that small problem, warm-started
    from the current forces. The converged step satisfies the law and the equations of
    motion at q̃_{n+1}; p and k only steer the inner solve. The curvature of the gaps is
    left out of the iteration matrix: curved obstacles converge linearly, to the same
    answer."""

    def __init__(self, model, st, P: np.ndarray, t: float, opts):
        self.contacts, self.P, self.q_n = model.contacts, P, st.q
        # the inner solve's tolerance (m) and the gap of a contact with no facet in reach
        self.tolerance = opts.tol_gap * model.length
        far = opts.detection_margin * model.length
        self.mu, self.nt = self.contacts.friction[P], model.dim - 1
        self.k, self.scale, self.far = opts.multiplier_scale, opts.penalty_scale, far
        self.stats = opts.stats.contact.coulomb
        self.minimum_norm = opts.stats.contact.minimum_norm  # (rows that can be redundant)
        force = None if st.smooth is None else st.smooth.normal
        force_t = None if st.smooth is None else st.smooth.tangential
        self.lam = np.zeros((P.size, 1 + self.nt))
        if force is not None:
            self.lam[:, 0] = np.maximum(force[P], 0.0)
        if force_t is not None:  # (a tangential force only where a normal one presses)
            self.lam[:, 1:] = np.where(self.lam[:, :1] > 0.0, force_t[P], 0.0)
        # (λ_T,n as v̇_n carries it: the step moves v by h(v̇_n + v̇_{n+1})/2 at ρ∞ = 1)
        self.lam_n = 0.0 if st.smooth is None else st.smooth.in_vd[P, 1:]
        self.shift = _obstacle_shift(self.contacts, P, st.t, t)
        self.C = None  # (the curvature of the gaps is not in the iteration matrix)
        self.solved, self.change = False, None  # (and the last update's change of λ)

    def update(self, q: np.ndarray, curvature: bool = False) -> None:
        """Gaps, slips over the step and their rows at q. A contact with no facet within
        reach (g = +∞, no gradient) counts as open at the detection margin ``far``."""
        g, G = self.contacts.linearize(q, self.P)[:2]
        g = np.where(np.isfinite(g), g, self.far)
        GT, T = self.contacts.tangent_jacobian(q, self.P)
        slip = self.contacts.slips(q, self.q_n, self.P, GT, T)
        if self.shift is not None:
            slip -= np.einsum("mtd,md->mt", T, self.shift)
        self.A, self.w, self.slip = _rows(G, GT), _stack(g, slip, np.zeros(0)), slip

    @property
    def active(self) -> np.ndarray:
        """The contacts pressed or penetrating: while one is, the update solves the law."""
        return (self.lam[:, 0] > 0.0) | (self.w[:: 1 + self.nt] < 0.0)

    def force_term(self) -> np.ndarray:
        return self.A.T @ self.lam.ravel()

    def schur_update(self, model, r, solve, key=None) -> np.ndarray:
        """The update dq = S⁻¹(−r + AᵀΔλ) with λ + Δλ the solution of the law on the rows
        linearised at q (``key``: S is constant at this step size, and so are the rows of
        straight gaps: S⁻¹Aᵀ columns are kept per contact and row)."""
        x = solve(r)
        Y = self._columns(model, solve, key)
        D = self.A @ Y
        lam = self.lam.ravel()
        c = self.w - self.A @ x - D @ lam
        tol = 0.1 * self.tolerance
        self.p = _augmentation(D, self.scale)
        z = self._solve(c, D, lam / self.k, tol)
        new = self.k * z
        self.lam = new.reshape(self.lam.shape)
        self.solved, self.change = True, (new - lam).reshape(self.lam.shape)
        return -x + Y @ (new - lam)

    def _solve(self, c, D, x0, tol):
        """:func:`solve_coulomb` of the update; where it fails on redundant rows, solved
        again without the slips no multiplier reaches, as the position correction does
        (:func:`_position_law`; on ``box_stack`` at h = 5e-4 s the corners of the boxes' faces
        on the plane had slips no multiplier reaches of up to 2.7e-13 m, above the solve's
        tolerance of 3e-14 m), counted in ``unreachable_slip_solves``."""

        def solve(c):
            return solve_coulomb(c, D, self.p, self.k, self.mu, self.nt, x0, tol,
                                 stats=self.stats, minimum_norm=self.minimum_norm)[0]  # fmt: skip

        try:
            return solve(c)
        except RuntimeError as err:
            failure = err
        reachable = None
        if self.minimum_norm:
            reachable = reachable_slips(c, D, self.mu, self.nt, self.stats)
        if reachable is not None:
            try:
                z = solve(reachable)
            except RuntimeError:
                pass
            else:
                self.stats.unreachable_slip_solves += 1
                return z
        raise StepFailure(f"smooth step, friction: {failure}", np.nan) from None

    def retreat(self, s: float) -> None:
        """Take back the fraction ``s`` of the last update of the forces (between two
        points of the cone: in it)."""
        self.lam = self.lam - s * self.change

    def _columns(self, model, solve, key):
        if key is None:
            return solve(self.A.T).reshape(self.A.shape[1], -1)
        b, cons = 1 + self.nt, Constraints(model, self.P)
        Y = np.empty((self.A.shape[1], self.A.shape[0]))
        for i in range(b):  # the normal rows, then each tangent's
            Y[:, i::b] = constraint_columns(
                model, ("smooth", i, *key), self.P, self.A[i::b], solve, cons, True
            )
        return Y

    def satisfied(self, admits) -> bool:
        """Coulomb's law at q within the gap tolerance (``admits(x)``: x ≤ tolerance, m):
        its Alart–Curnier residual, in metres, once an update has solved it (before any,
        the forces are zero and no contact may penetrate)."""
        if not self.solved:
            return not self.active.any()
        # (measured at the default augmentation 1/D_ii and k = 1: the same at every p and k.
        # With the run's p, a slipping contact's iterate read 1.84e-13 m at p × 1e3 where the
        # default's read 1.36e-13 m, across the 1.45e-13 m tolerance: the runs took different
        # iterates and parted by 4.8e-11 m (the spinning ball dropped on a block, localized);
        # bit-identical at the defaults)
        p = self.p / self.scale
        law = coulomb_residual(self.w, self.lam.ravel(), p, 1.0, self.mu, self.nt)
        return admits(law)

    def settled(self, q: np.ndarray, admits) -> bool:
        self.update(q)
        return self.satisfied(admits)

    def forces(self, m: int):
        """(λ_N (m,), λ_T (m, nt)) of every contact (N), zero outside P."""
        out = np.zeros((m, 1 + self.nt))
        out[self.P] = self.lam
        return out[:, 0], out[:, 1:]

    def work(self) -> float:
        """The energy the tangential forces dissipated over the step's slip (J): the slip
        times the mean of λ_T at t_n and t_{n+1}, the force the update of v applies at ρ∞ = 1.
        λ_T,n+1 alone overbooks it by h/2 Σ λ̇_T·w_T where λ_N rises and falls on a slide
        (``docs/explanation/energy_ledger.md``, *Friction of the smooth step*)."""
        return -0.5 * float(np.sum((self.lam_n + self.lam[:, 1:]) * self.slip))
