r"""The angular momentum of free planar rigid bodies, held through a position correction.

The correction q̃ → q moves the centres c_a at fixed velocities (a projection of the
positions, not a force), so the total angular momentum about a fixed point O,

    L_O = Σ_a (c_a − O) × m_a u̇_a + I_a ω_a        (scalar: the plane's normal component),

changes by Σ_a (c_a − c̃_a) × m_a u̇_a. For a free pair closing off-centre the centres are
pushed apart along the normal n while the momenta have a tangential part: ΔL is about
depth × reduced mass × the tangential relative speed, first order in h. The velocity jump
itself keeps L (its impulses are equal, opposite and at one point), so the whole change of
a free pair's L over a closing step is the correction's.

A *group* of free bodies whose contacts in the correction join only bodies of the group is
acted on by internal forces alone: its total L and P are conserved. The test is
objectivity: no row's gap changes under a rigid motion of the whole group (the rates G f of
its three rigid fields zero to round-off); a row on an obstacle or on another kind of body
fails it. The lost ℓ = L_O(q̃, ṽ) − L_O(q, ṽ) is put back by the velocity change of least
kinetic energy that keeps P: a rigid rotation of the group about its centre of mass c_G at
q, δω = ℓ / I_G, δu̇_a = δω e_z × (c_a − c_G), δω_a = δω, with I_G = Σ m_a |c_a − c_G|² + I_a
the group's locked inertia (the planar case of :mod:`.momentum_rigid`).

Decided once per model: the free ``RigidBody2D`` bodies (no support) that no joint holds (a
joint's force on one body of a pair is external to it); a jointed body is left alone like
another kind of body, so that a group it touches is left alone too.
"""

from __future__ import annotations

import numpy as np

from .momentum_rigid import body_groups, jointed

__all__ = ["PlanarMomentum", "planar_momentum"]

OBJECTIVE = 1e-10
"""Rates G f of the group's rigid fields below this fraction of max|G| · max|f| are zero: a
row on an obstacle moves at O(1) of that under a rigid motion of the group, a row between
two of its bodies by round-off of its normal (1e-16 of the coordinates over the size)."""


class PlanarMomentum:
    """The free planar rigid bodies of a model, and the velocity change that puts back the
    angular momentum a position correction moved without a force (module docstring)."""

    def __init__(self, model):
        # (body, global slice) of each free RigidBody2D, its free dofs (3 a column)
        self.bodies = []
        columns = []
        held = jointed(model)
        for i, b in enumerate(model.bodies):
            if b.rigid_frame and b.dim == 2 and not b.fixed and id(b) not in held:
                s = model.body_slice(i)
                self.bodies.append((b, s))
                columns.append(model.free_index[s])
        self.columns = np.concatenate(columns) if columns else None

    def __call__(self, q_tilde, q, v, G) -> np.ndarray:
        """The increment (all dofs) of the velocity ``v`` (ṽ) that holds each free group's
        total angular momentum (kg·m²/s) at its value at (q̃, ṽ) after the correction to
        ``q``; ``G``: the correction's contacts' gradients (dense, free dofs)."""
        dv = np.zeros_like(v)
        Gr = G[:, self.columns]
        touch = np.abs(Gr).reshape(len(G), len(self.bodies), 3).max(axis=2) > 0.0
        rows = touch.any(axis=1)
        # a row that also acts on dofs outside these bodies (a solid, a beam) taints its group
        outside = np.count_nonzero(G, axis=1) > np.count_nonzero(Gr, axis=1)
        # (a lone free body is pushed by an obstacle: its L is not its own)
        for group in body_groups(touch[rows], outside[rows]):
            if group.size < 2:
                continue
            members = [self.bodies[a] for a in group]
            cols = (3 * group[:, None] + np.arange(3)).ravel()
            G_group = Gr[rows][touch[rows][:, group].any(axis=1)][:, cols]
            if _objective(G_group, _rigid_fields(members, q)):
                _put_back(members, q_tilde, q, v, dv)
        return dv


def _rigid_fields(members, q) -> np.ndarray:
    """(3, 3 k) velocities of the group's rigid motions: translations along e_x, e_y, then
    the rotation about c_G at ``q``: u̇_a = e_z × (c_a − c_G), ω_a = 1."""
    c = np.array([b.center(q[s]) for b, s in members])
    m = np.array([b.mass for b, _ in members])
    r = c - m @ c / m.sum()
    fields = np.zeros((3, len(members), 3))
    fields[0, :, 0] = fields[1, :, 1] = 1.0
    fields[2, :, 0], fields[2, :, 1], fields[2, :, 2] = -r[:, 1], r[:, 0], 1.0
    return fields.reshape(3, -1)


def _objective(G: np.ndarray, fields: np.ndarray) -> bool:
    """Whether no row of ``G`` moves under the rigid ``fields`` (to round-off)."""
    rates = G @ fields.T
    return bool(np.abs(rates).max() <= OBJECTIVE * np.abs(G).max() * np.abs(fields).max())


def _momentum(members, q, v) -> float:
    """L about the origin (kg·m²/s) of the group at (q, v)."""
    L = 0.0
    for b, s in members:
        c, w = b.center(q[s]), v[s]
        L += b.mass * (c[0] * w[1] - c[1] * w[0]) + b.inertia * w[2]
    return L


def _put_back(members, q_tilde, q, v, dv) -> None:
    """Add to ``dv`` the rigid rotation of the group about c_G that returns its L to its
    value at (q̃, ṽ) (module docstring)."""
    lost = _momentum(members, q_tilde, v) - _momentum(members, q, v)
    f = _rigid_fields(members, q)[2].reshape(len(members), 3)
    m = np.array([b.mass for b, _ in members])
    inertia = m @ (f[:, :2] ** 2).sum(axis=1) + sum(b.inertia for b, _ in members)
    for a, (_, s) in enumerate(members):
        dv[s] += lost / inertia * f[a]


def planar_momentum(model) -> PlanarMomentum | None:
    """The model's :class:`PlanarMomentum`, decided once per run; None without two free
    planar rigid bodies."""
    kept = PlanarMomentum(model)
    return kept if len(kept.bodies) > 1 else None
