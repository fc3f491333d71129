r"""The angular momentum of free rigid bodies in space, held through a position correction.

The correction q̃ → q moves the bodies (q = q̃ ⊕ U) at fixed velocities: it is a projection,
not a force, yet it changes the angular momentum about a fixed point O,

    L_O = Σ_a (c_a − O) × m_a u̇_a + R_a J_a Ω_a,

by Σ_a (c_a − c̃_a) × m_a u̇_a + (R_a − R̃_a) J_a Ω_a: two balls in an off-centre impact are
pushed apart along their normal at fixed momenta, and the pair's total L changes at first
order in h. Which components the contact forces conserve decides what is
put back:

- a *group* of free bodies whose contacts in the correction join only bodies of the group
  (a free pair): every contact force acts on two bodies of the group, equal, opposite and
  on one line through the contact point (or, with friction, at one point), so the group's
  total L (and P) is conserved. The test is objectivity: no row's gap changes under any
  rigid motion of the whole group (rates G f of its six rigid fields zero to round-off);
- a *single* free body pushed only by fixed obstacles along one normal n with no moment
  about n (a plane, or one contact), frictionless: L·n is conserved, the rule of
  :class:`fecontact.time.correction.MomentumKept` for beams.

The lost components, ℓ = Wᵀ(L_O(q̃, ṽ) − L_O(q, ṽ)) with W the held axes (3 × k), are put
back by the velocity change of least kinetic energy that keeps P: a rigid rotation δω = W a
of the group about its centre of mass c_G at q (O = c_G), δu̇_a = δω × (c_a − c_G),
δΩ_a = R_aᵀδω, with (Wᵀ I_G W) a = ℓ and I_G the group's locked inertia about c_G. (Of all
velocity changes with WᵀΔL = ℓ and ΔP = 0 that one minimises ½ δvᵀ M δv: its Lagrange
conditions M δv = Σ (∂L·w/∂v)ᵀ a_w + (∂P/∂v)ᵀ b give exactly a rigid twist, and ΔP = 0 puts
its axis through c_G.)

With friction the correction also turns each body it moves tangentially: R = R̃ exp(Ũ) at
fixed body-frame Ω turns the spatial ω = RΩ by U × ω, U ≈ h²/2 J⁻¹Rᵀτ a step of a friction
torque τ, which sums to (h t/2) α × ω over a slide (first order: a ball spinning about the
vertical). In a frictional model the spin R J Ω of each free body that only fixed
obstacles touch is held in space through the correction, Ω ← J⁻¹RᵀR̃JΩ̃ (bodies it does
not turn are left as they are); its change of ½ΩᵀJΩ (J not isotropic) is the ledger's
``momentum hold`` (:mod:`fecontact.ledger`). Bodies in contact with each other take, of
the velocity changes that leave every row's normal and slip rate as it is, the one nearest
in kinetic energy to that hold (:func:`hold_pressed_spins`): the contact law at the points
sees no change, and what the rows act on is left to them (a ball sliding on a free box
keeps its spin about the normal; a box resting flat on another keeps almost nothing). The
group rule above then puts back a free group's total L.

Decided once per model: the free ``RigidBody3D`` bodies (no support) that no joint holds
(a joint's force on one body of a pair is external to it; the joints' velocity projection
of the jump follows the correction). A jointed body is left alone like another kind of
body (a solid, a beam): a group that a row joins to one is left alone, and a body it
touches is not lone; the others are held whatever joints the rest of the model has (a ball
rolling beside a pendulum on a ball joint kept its v_end 7.2e-3 off at h = 1 ms when any
joint turned the hold off for the whole model). A fixed body is an obstacle.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RigidMomentum", "body_groups", "common_normal", "jointed", "rigid_momentum"]

OBJECTIVE = 1e-10
"""Rates G f of the group's rigid fields below this fraction of max|G| · max|f| are zero: a
row against a fixed obstacle moves at O(1) of that under a rigid motion of the group, a row
between two of its bodies by round-off of its normal (1e-16 of the coordinates over the
size); six orders in between."""


class RigidMomentum:
    """The free rigid bodies in space of a model, and the velocity change that puts back
    the angular momentum a position correction moved without a force (module docstring)."""

    def __init__(self, model):
        # (body, global slice, its free dofs (6,)) of each free RigidBody3D
        self.bodies = []
        self.frictional = model.contacts.frictional  # (then each body's spin is held)
        held = jointed(model)
        for i, b in enumerate(model.bodies):
            if b.rigid_frame and b.dim == 3 and not b.fixed and id(b) not in held:
                s = model.body_slice(i)
                self.bodies.append((b, s, model.free_index[s]))
        self.columns = np.concatenate([f for _, _, f in self.bodies]) if self.bodies else None

    def __call__(self, q_tilde, q, v, G, GT) -> np.ndarray:
        """The increment (all dofs) of the velocity ``v`` (ṽ) that holds the components of
        the angular momentum (kg·m²/s) the contact forces conserve at their value at
        (q̃, ṽ) after the correction to ``q``; ``G``: the correction's contacts' gradients
        (dense, free dofs), ``GT`` their slip rows (rows, nt, free dofs; None without
        friction)."""
        dv = np.zeros_like(v)
        Gr = G[:, self.columns]
        rows = np.abs(Gr).max(axis=1) > 0.0
        outside = np.count_nonzero(G, axis=1) > np.count_nonzero(Gr, axis=1)  # other bodies
        touch = np.abs(Gr).reshape(len(G), len(self.bodies), 6).max(axis=2) > 0.0
        if self.frictional:
            _hold_spins(self.bodies, _lone(touch, outside), q_tilde, q, v, dv)
        for group in body_groups(touch[rows], outside[rows]):
            members = [self.bodies[a] for a in group]
            g_rows = Gr[rows][touch[rows][:, group].any(axis=1)]
            cols = np.concatenate([np.arange(6 * a, 6 * a + 6) for a in group])
            if self.frictional and len(group) > 1:
                slips = GT[rows & touch[:, group].any(axis=1)][:, :, self.columns]
                fixed = np.vstack([g_rows, slips.reshape(-1, len(self.columns))])
                hold_pressed_spins(members, fixed[:, cols], (q_tilde, q, v), dv)
            held = v + dv
            axes = self._held_axes(members, q, g_rows[:, cols])
            if axes is not None:
                _put_back(members, (q_tilde, v), (q, held), dv, axes)
        return dv

    def _held_axes(self, members, q, G) -> np.ndarray | None:
        """The axes W (3, k) of the group's conserved angular momentum components, or None:
        all three where its rows are objective, n where a lone frictionless body is pushed
        along n with no moment about n."""
        fields = _rigid_fields(members, q)  # 3 translations, 3 rotations about c_G
        rates = G @ fields.T
        if np.abs(rates).max() <= OBJECTIVE * np.abs(G).max() * np.abs(fields).max():
            return np.eye(3)
        if len(members) > 1 or self.frictional:
            return None
        n = common_normal(G, fields[3:])
        return None if n is None else n[:, None]


def jointed(model) -> set[int]:
    """The ids of the bodies a joint of ``model`` holds: their momentum is not their own."""
    return {id(b) for j in model.joints.pairs for b in (j.body, j.other) if b is not None}


def body_groups(touch: np.ndarray, outside: np.ndarray) -> list[np.ndarray]:
    """The bodies joined by rows (``touch``: rows × bodies), one list per connected group,
    leaving out every group one of whose rows also acts on other bodies (``outside``)."""
    label = np.arange(touch.shape[1])
    for r in touch:  # (a few rows: union by relabelling)
        on = np.flatnonzero(r)
        if on.size > 1:
            label[np.isin(label, label[on])] = label[on[0]]
    tainted = set(label[np.flatnonzero(touch[outside].any(axis=0))].tolist())
    used = set(label[touch.any(axis=0)].tolist())
    return [np.flatnonzero(label == g) for g in sorted(used - tainted)]


def _rigid_fields(members, q) -> np.ndarray:
    """(6, 6 k) velocities of the group's rigid motions: translations along e_x, e_y, e_z,
    then rotations about them through the group's centre of mass c_G at ``q``:
    u̇_a = e × (c_a − c_G), Ω_a = R_aᵀ e."""
    c = np.array([b.center(q[s]) for b, s, _ in members])
    m = np.array([b.mass for b, _, _ in members])
    r = c - m @ c / m.sum()
    fields = np.zeros((6, len(members), 6))
    fields[:3, :, :3] = np.eye(3)[:, None, :]
    fields[3:, :, :3] = np.cross(np.eye(3)[:, None, :], r)
    for a, (b, s, _) in enumerate(members):
        fields[3:, a, 3:] = b.rotation(q[s])  # row k: R_aᵀ e_k, the k-th row of R_a
    return fields.reshape(6, -1)


def _momentum(members, q, v, origin) -> np.ndarray:
    """L about ``origin`` (kg·m²/s) of the group at (q, v) (module docstring)."""
    L = np.zeros(3)
    for b, s, _ in members:
        qa, va = q[s], v[s]
        L += np.cross(b.center(qa) - origin, b.mass * va[:3]) + b.rotation(qa) @ (b.J @ va[3:])
    return L


def _lone(touch: np.ndarray, outside: np.ndarray) -> np.ndarray:
    """Which bodies (mask) only fixed obstacles touch in the correction (``touch``: rows ×
    bodies): no row of theirs joins another body."""
    joined = (touch.sum(axis=1) > 1) | outside
    return touch.any(axis=0) & ~touch[joined].any(axis=0)


def _hold_spins(bodies, lone, q_tilde, q, v, dv) -> None:
    """Add to ``dv`` the change of each ``lone`` body's Ω that holds its spin R J Ω in space
    through the correction q̃ → q (Ω ← J⁻¹RᵀR̃JΩ̃), where it moved its rotation."""
    for (b, s, _), alone in zip(bodies, lone, strict=True):
        psi_tilde, psi = q_tilde[s][3:6], q[s][3:6]
        if not alone or np.array_equal(psi_tilde, psi):
            continue
        W = v[s][3:6]
        spin = b.rotation(q_tilde[s]) @ (b.J @ W)
        dv[s][3:6] = np.linalg.solve(b.J, b.rotation(q[s]).T @ spin) - W


def hold_pressed_spins(members, G, states, dv) -> None:
    """Add to ``dv`` the spin hold of a group of bodies pressed against each other (rows
    ``G`` on the group's 6 k dofs): of the velocity changes that leave every row's rate G v
    as it is, the one nearest in kinetic energy to holding each body's R J Ω in space
    (Ω ← J⁻¹RᵀR̃JΩ̃); ``states``: (q̃, q, ṽ)."""
    q_tilde, q, v = states
    target = np.zeros((len(members), 6))
    for a, (b, s, _) in enumerate(members):
        if not np.array_equal(q_tilde[s][3:6], q[s][3:6]):
            W = v[s][3:6]
            spin = b.rotation(q_tilde[s]) @ (b.J @ W)
            target[a, 3:] = np.linalg.solve(b.J, b.rotation(q[s]).T @ spin) - W
    if not target.any():
        return
    # S Sᵀ = M⁻¹ per body (J = C Cᵀ): with y = S⁻¹ δv the kinetic metric is Euclidean, and
    # y's part in the null space of G S keeps the rates (a least-squares projection: the
    # rows of a box resting flat on another are dependent)
    S = np.zeros((len(members), 6, 6))
    for a, (b, _, _) in enumerate(members):
        S[a, :3, :3] = np.eye(3) / np.sqrt(b.mass)
        S[a, 3:, 3:] = np.linalg.inv(np.linalg.cholesky(b.J)).T
    y = np.einsum("aij,aj->ai", np.linalg.inv(S), target).ravel()
    A = G.reshape(len(G), len(members), 6)
    A = np.einsum("rai,aij->raj", A, S).reshape(len(G), -1)
    y = (y - np.linalg.lstsq(A, A @ y, rcond=None)[0]).reshape(len(members), 6)
    for a, (_, s, _) in enumerate(members):
        dv[s] += S[a] @ y[a]


def _put_back(members, before, after, dv, axes) -> None:
    """Add to ``dv`` the rigid rotation of the group about c_G, along ``axes`` (3, k), that
    returns those components of L at ``after`` (q, v) to their value at ``before`` (q̃, ṽ)
    (module docstring)."""
    q = after[0]
    c = np.array([b.center(q[s]) for b, s, _ in members])
    m = np.array([b.mass for b, _, _ in members])
    origin = m @ c / m.sum()
    lost = _momentum(members, *before, origin) - _momentum(members, *after, origin)
    k = axes.shape[1]
    f = (axes.T @ _rigid_fields(members, q)[3:]).reshape(k, len(members), 6)
    # the locked inertia along the axes, fᵀ M f with M = diag(m_a I, J_a) per body
    gram = np.zeros((k, k))
    for a, (b, _, _) in enumerate(members):
        u, w = f[:, a, :3], f[:, a, 3:]
        gram += m[a] * u @ u.T + w @ b.J @ w.T
    rate = np.linalg.solve(gram, axes.T @ lost)
    for a, (_, s, _) in enumerate(members):
        dv[s] += rate @ f[:, a]


def common_normal(G, fields) -> np.ndarray | None:
    """The unit normal n shared by the contacts of gradient rows ``G`` (on one body's dofs,
    6 per node, translations first): the force direction Σ_i G_c(x_i) of each, all parallel,
    with no moment about n (the rate G_c f_n of the rigid rotation f_n = n·``fields``, the
    three rotations about e_k through the centre of mass, is zero to round-off); else None."""
    if len(G) == 0:
        return None
    forces = G.reshape(len(G), -1, 6)[:, :, :3].sum(axis=1)
    size = np.linalg.norm(forces, axis=1)
    if np.any(size == 0.0):
        return None
    n = forces[0] / size[0]
    # (round-off of unit normals made from coordinates of order the body's size)
    if np.abs(np.cross(forces / size[:, None], n)).max() > 1e-12:
        return None
    rate = G @ (n @ fields)
    if np.abs(rate).max() > 1e-12 * np.abs(G).max() * np.abs(fields).max():
        return None
    return n


def rigid_momentum(model) -> RigidMomentum | None:
    """The model's :class:`RigidMomentum`, decided once per run; None without free rigid
    bodies in space."""
    kept = RigidMomentum(model)
    return kept if kept.bodies else None
