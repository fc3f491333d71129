r"""Contact forces in the smooth step: persistent contacts as unilateral constraints of Newton.

In the fully decoupled scheme the smooth step carries no contact force, and a contact that
stays closed is held only by the position correction U and the velocity jump W, which never
enter v̇ or a. Elastic bodies in lasting contact then integrate their contact zone with the
wrong accelerations, and the step must stay below about Δx/c. Here the contacts that are
*persistent*, pressed in the step that ended at t_n and still near,

    P = {j : λ_j,n > 0 or ν_j,n > 0 or Λ_j,n > 0, and g_j(q_n) ≤ d (the detection margin)},

carry a smooth contact force λ_j ≥ 0 (N) in the equations of motion at t_{n+1},

    M v̇_{n+1} + C ṽ_{n+1} + f_int(q̃_{n+1}) − f_ext(t_{n+1}) − Σ_{j∈P} G_jᵀ λ_j = 0,
    k λ_j − [k λ_j − p_j g_j(q̃_{n+1})]_+ = 0   (j ∈ P),

the position-level Alart–Curnier law, 0 ≤ g_j ⊥ λ_j ≥ 0, solved together with the dynamics
by a primal–dual active set: on A the linearised gap G_j Δq = −g_j is a row of the
bordered iteration matrix, off A λ_j = 0. A is decided on the force and the gap apart (first
the contacts carried in pressed or penetrating; then a contact leaves when its force turns
negative and enters when it penetrates), so that no augmentation p or scale k steers it.
This is the index-3 treatment of the joints, given to the contacts that stay closed, with a
multiplier warm-started from the previous step (after Chen, Acary, Virlez & Brüls 2013 and
Brüls, Acary & Cardona 2014, who carry λ in the smooth part; here at position level so that
the smooth step itself leaves g ≥ 0 on P).

Contacts that close within the step (impacts) stay out of P: an index-3 force that stops a
body within one step is an impulse divided by h², which would pollute v̇ and a for many
steps. They are left to the position correction and the velocity jump with Newton's impact
law, exactly as in the decoupled scheme, which then also keep the velocities of P
consistent (ġ_j ≥ 0) and fix whatever the smooth step leaves. A contact leaves P when its
force vanishes: the complementarity lets it separate with λ_j = 0. P is not limited to the
gaps closed at t_n: a correction that lifts a pressed node by a little (it spreads over the
body) must not drop it from P, or the node would fall back through the next smooth step and
be stopped by a correction again, every other step (measured on a ball pressed on a plane
at 4.8 Δx/c: a ring of nodes alternating, its contact 7 % too soft).

In the velocity jump a contact held by λ_j > 0 at the end of the smooth step keeps ġ_j = 0
as an equality (an impulse of either sign): it removes the O(h) velocity drift of the index-3
step. After a step that stopped a contact, the acceleration variable restarts from the
post-impact state (:func:`restarted_acceleration`). Not on models with beams: a beam's
rotations and stretching lie far above any step it takes (the founding strip's rotations at
hω ≈ 50, its tip mass on the axial spring at 7.9 for h = 1e-3 s), and their consistent
acceleration after an impact put the strip's energy from 0.0018 J to 518 J in one step. There
v̇ and a take the decoupled scheme's update through S_t instead, consistent in the modes the
step resolves and bounded in the others (:mod:`.position_jump`), the contacts' shares of it
included (:func:`held_shares`).

A force carried in v̇ acts in the next step too: the predictor and the recursion

    (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) v̇_{n+1} + α_f v̇_n

move q_{n+1} by h²β a_{n+1} and h²(½ − β) a_n, both holding M⁻¹G_jᵀλ_j,n. A contact that
opens in step n+1 (λ_j,n > 0, λ_j,n+1 = 0) is then still pushed by its last force while its
gap grows: work on a separating contact, energy put in at every release. An elastic block
suddenly loaded on a plane at 4 Δx/c with ρ∞ = 0.5 hopped off it this way, its energy
0.0024 J above the start after 0.2 s (0.063 J at ρ∞ = 0.9); two disks left each other 1.2 %
too fast at 4 Δx/c. So a step that releases a contact is taken again from v̇_n and a_n
without that contact's share (:func:`without_released`): M⁻¹G_jᵀ of its force λ_j,n in v̇_n,
and of its share λ̄_j,n of a_n, which follows the same recursion as a,

    (1 − α_m) λ̄_{n+1} + α_m λ̄_n = (1 − α_f) λ_{n+1} + α_f λ_n   (:func:`force_shares`),

the tangential forces alike. The contact leaves the step as it would leave a step with its
force switched off at t_n; if it closes again in the new step, it carries the force that
step gives it. After a restart, v̇ = a hold the restart's contact forces instead.

v̇_n loses M⁻¹G_jᵀλ_j,n, the acceleration at t_n without the force; a_n loses the step's
response β′S_t⁻¹G_jᵀλ̄_j,n instead of M⁻¹G_jᵀλ̄_j,n. The two agree on the modes the step
resolves (ωh ≪ 1, and exactly on rigid motions, which K does not strain: the momentum
taken out is the same), but a_n enters the predictor explicitly, q̃ by h²(½ − β)a_n, and
a contact node held on the obstacle at many Δx/c is a mode far above the step: M⁻¹ of its
force moves it by (ωh)²(½ − β) times its static compression under that force, S_t⁻¹ by a
bounded fraction of it. Through M⁻¹, the elastic ball of 20,577 dofs at 20 Δx/c gained
58 % of its kinetic energy in its release step (its pole node, held by 3.1 N, let go);
through S_t⁻¹ the step creates nothing and the ball ends 3.8 % below its start. v̇_n enters
the step only through the implicit recursion of a, where M⁻¹ of the force stays bounded.

The active set reads no augmentation: the semi-smooth test k λ_j − p_j g_j > 0 kept or
dropped a pressed contact whose predictor gap came out slightly open depending on p (λ/p
against g), and each choice took its own Newton path to within the tolerance, its own step
halvings and its own trajectory (a box dropped corner first parted by 1e-4 of its speed
between p and p × 1000, two fast oblique disks by 1 %; now to round-off). Frictional
contacts carry a tangential force too (:class:`fecontact.time.coulomb.SmoothFriction`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..contact.laws import kkt_multipliers, solve_velocity_jump
from ..linalg.ladder import Spectral
from .constraints import Constraints, StepFailure, augmentation, constraint_columns
from .coulomb import frictional_restart, frictional_start
from .lie import inertial_forces
from .records import SmoothForces
from .smooth_redundant import linearised_law, wandering

__all__ = [
    "SmoothContacts",
    "force_shares",
    "held_shares",
    "persistent_contacts",
    "released",
    "restarted_acceleration",
    "resting_start",
    "without_released",
]

_NONE = np.zeros(0, int)
_NONE.flags.writeable = False


def persistent_contacts(model, st, near: float) -> np.ndarray:
    """The contacts P of the step after ``st``: pressed by any of the last step's forces,
    and with a gap g(q_n) ≤ ``near`` (m). A model with friction and joints has none."""
    contacts = model.contacts
    m = contacts.size
    # a contact pressed in the last step was one of its candidates: in flight, nothing to do
    if m == 0 or st.gaps.size != m or st.candidates.size == 0:
        return _NONE
    if contacts.frictional and model.joints.size:  # (friction: the bordered path has none)
        return _NONE
    pressed = st.nu > 0.0 if st.nu.size == m else np.zeros(m, bool)
    if st.impulse.size == m:
        pressed |= st.impulse > 0.0
    if st.smooth is None and not pressed.any():  # (most steps near an obstacle: none)
        return _NONE
    if st.smooth is not None:
        pressed |= st.smooth.normal > 0.0
        if st.smooth.closing is not None:  # (beams: an impact's contact settles a step first)
            pressed &= st.smooth.closing == 0.0
    return np.flatnonzero(pressed & (st.gaps <= near))


class SmoothContacts:
    """The persistent contacts ``P`` of one smooth step, their forces λ (N) and active set.

    ``update(q)`` evaluates the gaps and gradients at q, decides the active set from the
    current forces and drops the forces off it; ``force_term`` is then Σ_{j∈A} G_jᵀ λ_j
    (to subtract from the residual), ``rows`` the active rows to border the iteration
    matrix with, and ``satisfied(tol)`` the complementarity test of convergence."""

    def __init__(self, model, P: np.ndarray, force0: np.ndarray, opts):
        self.contacts, self.P = model.contacts, P
        self.lam = np.maximum(force0, 0.0)
        self.stats = opts.stats.contact
        self.g = self.G = None
        self.active = np.zeros(P.size, bool)
        self.solved = None  # the active set of the last update that enforced its gaps
        # (affine gaps: finite, their gradients constant, so the rows that can hold are
        # known from the first update: :meth:`_next_active_set`)
        self.affine, self.live = model.contacts.affine, None
        self.last = None  # (the rows and the change of λ of the last update)
        # (once per run, :mod:`.smooth_redundant`; beams keep theirs: test_spatial_strike.py)
        self.redundant = self.stats.minimum_norm and not model.slender
        self.complementary, self.seen = False, []

    def update(self, q: np.ndarray, curvature: bool) -> None:
        """Gaps, gradients (and, with ``curvature``, the curvature −Σ_A λ_j ∇²g_j of the
        force term) at q; the active set from the forces carried in."""
        # the forces carried in weigh the curvature; one that leaves A below lags one update
        weights = -self.lam if curvature else None
        self.g, self.G, self.C = self.contacts.linearize(q, self.P, weights)
        self.active = self._next_active_set(self.g, self.G)
        self.lam[~self.active] = 0.0
        if self.redundant and not self.complementary:
            self.complementary = wandering(self.seen, self.active, self.G)

    def _next_active_set(self, g: np.ndarray, G: np.ndarray) -> np.ndarray:
        """The contacts of the next update, decided on the force and the gap apart, so that
        neither p nor k steers it. The first set: the contacts carried in pressed (λ > 0)
        or penetrating at the predictor. After an update a contact leaves the set when its
        force turns negative and enters it when it penetrates. The test k λ − p g > 0 kept
        or dropped a pressed contact whose predictor gap came out slightly open depending on
        p (λ/p against g), and with it the Newton path, the step halvings and the trajectory
        (a box dropped corner first: 1.4e-5 of its size between p and p × 1000)."""
        # (a row whose gap is undefined, g = +inf, or whose gradient is zero holds nothing: a
        # deep node's own row reports a finite far gap once the node is out; kept, its force
        # would stay as it came, untouched by a singular update, and its gap never close)
        live = self.live
        if live is None:
            live = (g < np.inf) & G.any(axis=1)
            if self.affine:
                self.live = live
        holds = (self.lam > 0.0) & live
        if self.complementary and self.solved is not None:
            return self.active  # (the law's own set, :meth:`complementary_update`)
        if self.solved is None:
            return holds | (g < 0.0)
        return np.where(self.active, holds, g < 0.0)

    def complementary_update(self, L, x0, Y, lower, tol: float):
        """Newton's update, the forces of the live rows ``L`` from their linearised law solved
        whole (:func:`~.smooth_redundant.linearised_law`); None where it does not settle."""
        lam = self.lam[L]
        new = linearised_law(self.g[L], lam, x0, Y, lower, tol)
        if new is None:
            return None
        self.stats.complementary_smooth_updates += 1
        change, self.lam = new - lam, np.zeros(self.P.size)
        self.lam[L] = new
        self.active = self.lam > 0.0
        self.solved = self.active.copy()
        self.last = (np.isin(np.arange(self.P.size), L), change)
        return x0 + Y @ change

    def force_term(self) -> np.ndarray:
        return self.G.T @ self.lam

    def rows(self):
        """(g_A, G_A): the active contacts as rows of the bordered system, whose multipliers
        μ = −λ_A enter the residual as + G_Aᵀ μ."""
        A = self.active
        return self.g[A], self.G[A]

    def take(self, dmu: np.ndarray) -> None:
        """Apply the bordered solve's update of the rows' multipliers (μ = −λ)."""
        self.lam[self.active] -= dmu
        self.solved = self.active.copy()
        self.last = (self.solved, -dmu)

    def schur_update(self, model, r, solve, key=None) -> np.ndarray:
        """The Newton update of the bordered system [[S, −G_Aᵀ], [G_A, 0]] (dq, Δλ_A) from
        S's own ``solve`` and the Schur complement G_A S⁻¹G_Aᵀ of the active rows, for gaps
        without curvature: S dq − G_Aᵀ Δλ = −r, G_A dq = −g_A. With a ``key`` (S is
        constant at this step size) the columns S⁻¹G_jᵀ of constant gradients are kept per
        contact, so a linear body in lasting contact factorizes S once per run."""
        A = self.active
        GA, gA, rows = self.G[A], self.g[A], self.P[A]
        constant = key is not None
        if constant and type(solve) is Spectral and model.contacts.linear:
            return self._modal_update(rows, GA, gA, r, solve)
        cons = Constraints(model, rows)  # (no joints here: the bordered path has them)
        at = ("smooth", *(key or ()))
        Y, x = constraint_columns(model, at, rows, GA, solve, cons, constant, rhs=r)
        dlam = kkt_multipliers(GA, Y, GA @ x - gA, 1.0, self.stats)
        self.lam[A] += dlam
        self.solved = A.copy()
        self.last = (self.solved, dlam)
        return -x + Y @ dlam

    def _modal_update(self, rows, GA, gA, r, spectral: Spectral) -> np.ndarray:
        """:meth:`schur_update` at a size solved in the modes Φ of S(a) = a M + K (a linear
        model's size met once, :class:`~fecontact.linalg.ladder.Spectral`), with P = Φᵀ G_Aᵀ
        kept per contact (constant gradients: the same at every size) and D = (a + Ω²)⁻¹:
        S⁻¹r = Φ D Φᵀr, S⁻¹G_Aᵀ = Φ D P and G_A S⁻¹G_Aᵀ = Pᵀ D P, so the update is one
        product by Φᵀ and one by Φ, where S⁻¹[G_Aᵀ r] made two of n × n by two columns
        (callgrind, 387 dofs: 0.24 M against 1.45 M instructions). The same numbers but
        for the products' round-off."""
        A, D = self.active, spectral.scale
        P = spectral.modal(rows, GA.T)
        z = D * (spectral.phi.T @ r)  # S⁻¹r in the modes
        Z = D[:, None] * P  # D Φᵀ G_Aᵀ
        dlam = kkt_multipliers(P.T, Z, P.T @ z - gA, 1.0, self.stats)
        self.lam[A] += dlam
        self.solved = A.copy()
        self.last = (self.solved, dlam)
        return spectral.phi @ (Z @ dlam - z)

    def retreat(self, s: float) -> None:
        """Take back the fraction ``s`` of the last update of the forces."""
        rows, change = self.last
        self.lam[rows] -= s * change

    def satisfied(self, admits) -> bool:
        """Complementarity within the gap tolerance (``admits(x)``: x ≤ tolerance, m): the
        active gaps closed, the inactive ones not penetrating. Active gaps count as closed
        only after an update has enforced them (then to round-off where they are linear, as
        in the position correction), not because the predictor lands within tolerance."""
        A = self.active
        if A.any() and (self.solved is None or not (A == self.solved).all()):
            return False
        worst = max(np.abs(self.g[A]).max(initial=0.0), (-self.g[~A]).max(initial=0.0))
        return admits(worst)

    def holds(self, q: np.ndarray, admits) -> bool:
        """Whether the active set just solved with is the one q gives and complementarity
        holds at q (:meth:`satisfied`), with nothing of the contacts moved: the test of an
        exact update (affine gaps and forces), whose residual is zero to round-off. Where
        it fails the loop evaluates the residual, which updates the set once, as after any
        update."""
        A = self.active
        # ((A == B).all(): np.array_equal's checks cost more, on arrays of P's one size)
        if self.solved is None or not (A == self.solved).all():
            return False
        g, G, _ = self.contacts.linearize(q, self.P)
        if not (self._next_active_set(g, G) == A).all():
            return False
        return admits(max(np.abs(g[A]).max(initial=0.0), (-g[~A]).max(initial=0.0)))

    def settled(self, q: np.ndarray, admits) -> bool:
        """Whether the active set at q is the one just solved with and complementarity holds
        there (the test of an update below the increment tolerance)."""
        before = self.active.copy()
        self.update(q, False)
        return bool(np.array_equal(before, self.active)) and self.satisfied(admits)

    def forces(self, m: int) -> np.ndarray:
        """λ of every contact (N), zero outside P."""
        out = np.zeros(m)
        out[self.P] = self.lam
        return out


def resting_start(
    model, st, tol_gap: float, tol_rate: float, stats=None, v_smooth=None, first=None
):
    """The initial state ``st`` with its resting contacts pressed: those that touch (gap ≤
    ``tol_gap``, m) and neither approach nor leave (|ġ| ≤ ``tol_rate``, m/s) carry the
    contact forces of the consistent acceleration (:func:`restarted_acceleration`), in v̇₀ =
    a₀ and as the smooth forces that make them persistent. A body resting on an obstacle
    then starts supported, instead of falling into it in the first step and being stopped
    by a correction, which put energy in the strain of an unresolved mesh (a block on a
    plane at 8 Δx/c: 6e-5 J, ten times the energy of its ringing). Approaching contacts are
    left to the impact law. ``stats``: the run's :class:`fecontact.contact.stats.ContactStats`;
    ``v_smooth``: the velocity damping is taken at, the given one before an impact at t = 0
    (:func:`fecontact.time.impacts.impact_start`; default ``st.v``). With friction and
    ``first``, the coefficients of the first step, the start is the step's own
    (:func:`fecontact.time.coulomb.frictional_start`)."""
    F = model.free
    touching = np.flatnonzero(st.gaps <= tol_gap)
    if touching.size == 0 or model.contacts.moving:  # (moving obstacles: no restart)
        return st
    _, G = model.contacts.linearize(st.q, touching)[:2]
    solve = None
    if model.contacts.frictional and first is not None:
        tol_rate, solve = frictional_start(model, st.q, st.t, G, tol_rate, first)
    resting = touching[np.abs(G @ st.v[F]) <= tol_rate]
    v_smooth = st.v if v_smooth is None else v_smooth
    start = restarted_acceleration(
        model, st.q, st.v, v_smooth, st.t, resting, tol_rate, stats, solve=solve
    )
    if start is None or start[1][0].size == 0:
        return st
    acc, (rows, forces) = start
    vd = st.vd.copy()
    vd[F] = acc
    in_vd, in_a = force_shares(model, st, None, None, None, (rows, forces))
    tangential = in_vd[:, 1:].copy() if model.contacts.frictional else None
    smooth = SmoothForces(in_vd[:, 0].copy(), tangential, in_vd, in_a)
    return dataclasses.replace(st, vd=vd, a=vd.copy(), candidates=touching, smooth=smooth)


def released(model, st, P: np.ndarray, force, rtol: float, closed=None) -> np.ndarray:
    """The contacts of ``P`` pressed by a smooth force at t_n (``st``) that the smooth step's
    ``force`` (N, every contact) let go: down to ``rtol`` (the smooth Newton's relative
    tolerance) of the force at t_n, zero within the solve (a contact and its mirror image
    in a symmetric model end one at 0 N, the other at 1e-16 of their force). A row whose
    twin (the other row of the same node, ``model.contacts.twins``:
    :func:`fecontact.contact.mortar_safeguard.twin_rows`) the step presses above that bound
    is not let go: the node is still held, its load handed from one of its rows to the
    other, and taking the row's share out of v̇_n and a_n would start the step without a
    force that still acts (the elastic ball on the slab off-pole at 3 m/s: a node's
    weighted row handed 106 N to its own row, the retake without it pressed it again at
    88 N and put in 3.4e-3 J). Where rows can be redundant, ``closed`` = (q̃, gap
    tolerance m): a row unloaded but closed at q̃ handed its force on, and is held."""
    if st.smooth is None or force is None or P.size == 0:
        return _NONE
    before = st.smooth.normal
    rows = P[(before[P] > 0.0) & (force[P] <= rtol * before[P])]
    if closed is not None and rows.size:
        rows = rows[model.contacts.gaps(closed[0])[rows] > closed[1]]
    twins = model.contacts.twins
    if twins is None or rows.size == 0:
        return rows
    twin = twins[rows]
    held = (twin >= 0) & (force[np.maximum(twin, 0)] > rtol * before[rows])
    return rows[~held]


def without_released(model, st, rows: np.ndarray, solve_H):
    """``st`` with the smooth forces of the contacts ``rows`` taken out of v̇_n (through
    M⁻¹) and a_n (through ``solve_H``, H⁻¹ with H = S_t/β′ the step's iteration matrix),
    and out of the forces that warm-start the step (see the module docstring)."""
    F = model.free_slice
    in_vd, in_a = st.smooth.in_vd[rows], st.smooth.in_a[rows]
    _, G = model.contacts.linearize(st.q, rows)[:2]
    f = G.T @ np.column_stack([in_vd[:, 0], in_a[:, 0]])
    if model.contacts.frictional:
        GT, _ = model.contacts.tangent_jacobian(st.q, rows)
        f += np.column_stack([np.einsum("mtn,mt->n", GT, x[:, 1:]) for x in (in_vd, in_a)])
    vd, a = st.vd.copy(), st.a.copy()
    vd[F] -= model.solve_M(f[:, 0])
    a[F] -= solve_H(f[:, 1])
    return dataclasses.replace(st, vd=vd, a=a, smooth=st.smooth.without(rows))


def force_shares(model, st, c, force, force_t, restart=None) -> tuple[np.ndarray, np.ndarray]:
    """The contacts' forces (m, dim) (N) carried in v̇_{n+1} and in a_{n+1}: the smooth
    step's (λ_N, λ_T), and the share of a by the recursion of a; after a ``restart`` =
    (rows, forces (rows, dim)), the restart's forces in both (v̇ = a)."""
    m, dim = model.contacts.size, model.dim
    lam = np.zeros((m, dim))
    if restart is not None:
        rows, forces = restart
        lam[rows] = forces
        return lam, lam.copy()
    if force is not None:
        lam[:, 0] = force
        if force_t is not None:
            lam[:, 1:] = force_t
    if st.smooth is None:
        in_vd = in_a = np.zeros((m, dim))
    else:
        in_vd, in_a = st.smooth.in_vd, st.smooth.in_a
    share = ((1.0 - c.af) * lam + c.af * in_vd - c.am * in_a) / (1.0 - c.am)
    return lam, share


def held_shares(
    forces: SmoothForces, closed: np.ndarray, hold: np.ndarray, c
) -> tuple[np.ndarray, np.ndarray]:
    """The contacts' shares of v̇ and a after the update of v̇ and a through S_t
    (:func:`fecontact.time.position_jump.acceleration_jump`), whose ``closed`` contacts held
    it with the normal forces ``hold`` (N): Δv̇ carries them, Δa (1 − α_f)/(1 − α_m) of them."""
    in_vd, in_a = forces.in_vd.copy(), forces.in_a.copy()
    in_vd[closed, 0] += hold
    in_a[closed, 0] += (1.0 - c.af) / (1.0 - c.am) * hold
    return in_vd, in_a


def restarted_acceleration(
    model,
    q,
    v,
    v_smooth,
    t,
    closed,
    tol_rate: float,
    stats=None,
    fint=None,
    solve=None,
    tol_acc=0.0,
):
    """The acceleration v̇ (free dofs) consistent with the state after an impact step, from
    which the generalized-α acceleration variable restarts (a = v̇, as at t = 0):

        M v̇ = f_ext(t) − f_int(q) − C ṽ − f_gyr(q, v) + Σ G_jᵀ μ_j,
        0 ≤ G_j v̇ + vᵀ∇²g_j v ⊥ μ_j ≥ 0 on the closed contacts that do not separate
        (ġ_j ≤ ``tol_rate``).

    After an impact U and W have moved the state, but v̇ and a still carry the free flight's
    acceleration and the strain that U put in acts on nothing; the index-3 force of the next
    step then makes up for both within one step and puts energy in (two disks at 4 Δx/c:
    +1.4 % of the impact kinetic energy, the disks leaving 2.05 % too fast; with the restart
    +0.54 % and 1.24 %). The damping C is taken at the smooth step's velocity ṽ
    (``v_smooth``): the jump W is an impulse the mesh does not resolve, and the dashpot
    force on its velocity discontinuity, carried through a whole step by the predictor,
    launched a damped block resting on a plane at 8 times its impact speed. The Signorini
    problem at the acceleration level is the velocity jump's, solved by the same primal–dual
    active set (:func:`fecontact.contact.solve_velocity_jump`); with friction, Coulomb's
    law at the acceleration level (:func:`fecontact.time.coulomb.frictional_restart`).
    Moving obstacles (gaps that change with t) and joints keep a as it is: None. Else
    (v̇, (rows, their forces (normal, tangential) (N), (rows, dim))). ``stats``: the run's
    :class:`fecontact.contact.stats.ContactStats`; ``fint``: f_int(q) (N, all dofs) where the
    smooth step evaluated it at q, else evaluated here; ``solve``: the metric's H⁻¹ in
    place of M⁻¹ (:func:`fecontact.time.coulomb.frictional_start`); ``tol_acc`` (m/s²): the law's
    tolerance, at which rows redundant up to round-off whose active set cycles are solved
    again by the proximal point method (:mod:`fecontact.contact.redundant_jump`); 0: the set
    must repeat. Round-off decided whether such a set repeated (an elastic ball pressed on a
    box beside its edge: seven rows of rank five), and a set that cycled failed the step."""
    contacts = model.contacts
    if contacts.moving or model.joints.size:
        return None
    F = model.free
    alpha, beta_k = model.damping
    K = None
    if fint is None or alpha or beta_k:  # (K: the damping's)
        _, fint, K = model.internal(q, tangent=bool(alpha or beta_k))
    f = model.external(t)[F] - fint[F]
    if model.inertial_bodies:  # the gyroscopic forces of rotating bodies, Ω × JΩ
        f -= inertial_forces(model, q, v, tangent=False)[0]
    if alpha or beta_k:
        f -= (alpha * model.M + beta_k * K) @ v_smooth[F]
    solve_H = model.solve_M if solve is None else solve
    x = solve_H(f)
    _, G = contacts.linearize(q, closed)[:2]
    holding = G @ v[F] <= tol_rate
    rows = closed[holding]
    forces = np.zeros((rows.size, model.dim))
    if rows.size == 0:
        return x, (rows, forces)
    cons = Constraints(model, rows)
    G = G[holding]
    Y = constraint_columns(model, ("mass",), rows, G, solve_H, cons, constant=solve is None)
    # the velocity jump's problem, one level up: 0 ≤ G (x + M⁻¹Gᵀμ) + vᵀ∇²g v ⊥ μ ≥ 0
    rates = G @ x + contacts.quadratic(q, v)[rows]
    if contacts.frictional:
        dvd, forces = frictional_restart(model, q, v, x, rows, G, rates, tol_rate, stats, solve)
        return x + dvd, (rows, forces)
    try:
        dvd, forces[:, 0], _ = solve_velocity_jump(
            G, rates, solve_H, augmentation(1.0, G, Y), 1.0, rows.size + 2, Y=Y, stats=stats,
            tol=tol_acc,
        )  # fmt: skip
    except RuntimeError:
        raise StepFailure("restarted acceleration: the active set did not settle", np.nan) from None
    return x + dvd, (rows, forces)
