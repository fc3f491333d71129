r"""Contact of a :class:`~fecontact.bodies.beam3d.Beam3D` through its segments: a tube of radius
r (the ``clearance``) about the centreline against a sphere, a rigid body's core or a second
tube.

Every segment (a, b) of the beam carries one contact at its point closest to the partner's
core, a point c or a segment (c, d) (:mod:`.segment3d`):

==========================  ====================================================================
partner                     core, gap
==========================  ====================================================================
``Sphere`` (outside)        its centre c: g = |x₁ − c| − R − r
``RigidBody3D`` ``Ball``    its centre: g = |x₁ − c| − ρ − r
``RigidBody3D`` ``Capsule`` the segment between its caps' centres: g = |x₁ − x₂| − ρ − r
``RigidBody3D`` ``Box``     the box itself: g = s(x₁) − r, s the signed distance from the box
                            (:mod:`.beam3d_box`; gradient only)
``Beam3D``                  the other beam's segment closest to this one: g = |x₁ − x₂| − r,
                            r the sum of the two tubes' radii
==========================  ====================================================================

A segment lying across a sphere touches it between its nodes, where node contact would let the
chord pass through. Against a ``Plane`` a segment's distance is linear along it, so its nodes
(:class:`~fecontact.contact.NodeContact`) are exact.

Two-sided: the normal is the direction of the closest points, whichever side the partner is on.
Two centrelines that pass through each other within a step reverse that direction; the gap of a
contact whose normal has turned by more than 90° from the start of the step against the same
partner segment is −|x₁ − x₂| − r (the side taken from the motion over the step, as for the
planar beams of :mod:`.beam_sides`), so the correction pushes the tubes back the way they came.
The gradients act on the translations of the segments' nodes (and on the (u, Θ) of a rigid
partner, Θ body-frame, by the chain rule through its points' kinematics); the curvature is exact
(:func:`.segment3d.tube_distance`).
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam3d import Beam3D
from ..bodies.rigid3d import RigidBody3D
from ..bodies.shapes3d import Ball, Box, Capsule
from ..errors import InputError, check_range
from ..rotations import exp
from .base import PairDefaults
from .beam3d_box import closest_to_box
from .friction import tangent_basis
from .node_pairs import NodeContact
from .obstacles import Circle
from .registry import register_pair
from .segment3d import closest_segments, tube_distance

__all__ = ["TubeBeamContact", "TubeBoxContact", "TubeRigidContact", "TubeSphereContact"]


class TubeContact(PairDefaults):
    """The segments of a ``Beam3D`` (one contact each) against a core of a partner; subclasses
    give the core's points (``_core``) and place the partner's rows (``_partner_rows``)."""

    linear = False
    looks_ahead = True

    def __init__(self, body: Beam3D, restitution: float, radius: float):
        self.body = body
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.radius = radius  # m: the sum of the tube radii and any partner's radius
        self.segments = body.segments()
        self.size = len(self.segments)
        self.offset = 0
        self._start = None  # (normal e₀, partner segment) at the start of the step

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)
        self._start = None

    def _ends(self, q: np.ndarray) -> np.ndarray:
        """The segments' end points (m, 2, 3)."""
        x = self.body.positions(q[self.offset : self.offset + self.body.ndof])
        return x[self.segments]

    def _beam_dofs(self) -> np.ndarray:
        nodes = self.segments.ravel()
        return self.offset + self.body.node_translation_dofs(nodes).reshape(self.size, 6)

    def _sides(self, e: np.ndarray, which: np.ndarray) -> np.ndarray:
        """σ = −1 where the normal has reversed since the step's start against the same
        partner segment (the centrelines went through each other), else +1."""
        if self._start is None:
            return np.ones(len(e))
        e0, which0 = self._start
        crossed = (np.einsum("mi,mi->m", e, e0) < 0.0) & (which == which0)
        return np.where(crossed, -1.0, 1.0)

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Keep the normals at the start of the coming step (the sides follow the motion)."""
        P = self._ends(q)
        Q, which = self._core(q, P)[:2]
        e = tube_distance(P, Q, hessian=False)[1]
        self._start = (e * self._sides(e, which)[:, None], which)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        P = self._ends(q)
        Q, which = self._core(q, P)[:2]
        f, e = tube_distance(P, Q, hessian=False)[:2]
        return self._sides(e, which) * f - self.radius

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, k), gradients (m, k) and curvatures (m, k, k)."""
        P = self._ends(q)
        Q, which, core = self._core(q, P)
        f, e, _, G, H = tube_distance(P, Q)
        sigma = self._sides(e, which)
        G, H = sigma[:, None] * G, sigma[:, None, None] * H
        dofs, G, H = self._partner_rows(self._beam_dofs(), G, H, core)
        return sigma * f - self.radius, dofs, G, H


class TubeSphereContact(TubeContact):
    """The segments of a ``Beam3D`` of tube radius ``clearance`` against a rigid ``Sphere``
    (a 3D ``Circle`` seen from outside)."""

    frictional = True

    def __init__(self, body: Beam3D, sphere: Circle, restitution=0.0, clearance=0.0):
        if sphere.dim != 3 or sphere.inside:
            raise InputError("obstacle: a Beam3D's segments meet a Sphere seen from outside")
        super().__init__(body, restitution, sphere.radius + clearance)
        self.obstacle = sphere

    def _core(self, q, P):
        c = self.obstacle.center + self.obstacle.shift()
        return np.broadcast_to(c, (self.size, 1, 3)), np.zeros(self.size, int), None

    def _partner_rows(self, dofs, G, H, core):
        return dofs, G[:, :6], H[:, :6, :6]

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g/∂t = −σ e·ċ (m/s) of a moving sphere, per segment."""
        if not self.obstacle.moving:
            return np.zeros(self.size)
        P = self._ends(q)
        Q, which, _ = self._core(q, P)
        e = tube_distance(P, Q, hessian=False)[1]
        return -self._sides(e, which) * (e @ self.obstacle.speed())

    def tangents(self, q: np.ndarray):
        """Slip rows of the segments' material points at ξ against the fixed sphere."""
        P = self._ends(q)
        Q, which, _ = self._core(q, P)
        _, e, (xi, _), _, _ = tube_distance(P, Q, hessian=False)
        T = tangent_basis(e)
        GT = np.concatenate([(1.0 - xi)[:, None, None] * T, xi[:, None, None] * T], axis=2)
        return self._beam_dofs(), GT, T


class TubeBeamContact(TubeContact):
    """The segments of a ``Beam3D`` against the closest segment of a second ``Beam3D``; the
    ``clearance`` is the sum of the two tubes' radii (m, > 0)."""

    frictional = True

    def __init__(self, body: Beam3D, other: Beam3D, restitution=0.0, clearance=0.0):
        if other is body:
            raise InputError("a beam cannot contact itself (self-contact is not supported)")
        if not clearance > 0.0:
            raise InputError("clearance: two Beam3D touch through their tubes; give r1 + r2 > 0")
        super().__init__(body, restitution, clearance)
        self.other = other
        self.bodies = (body, other)
        self.other_segments = other.segments()
        self.other_offset = 0
        # closest distances this near (m) are ties: round-off of the two beams' sizes
        self.tie = 1e-12 * max(body.characteristic_length, other.characteristic_length)

    def bind(self, model) -> None:
        super().bind(model)
        self.other_offset = model.offset_of(self.other)

    def _core(self, q, P):
        """Per segment of the beam, the other beam's closest segment (m, 2, 3) and its index."""
        o = self.other_offset
        x = self.other.positions(q[o : o + self.other.ndof])[self.other_segments]
        which = closest_segments(P, x, self.tie)
        return x[which], which, which

    def _partner_rows(self, dofs, G, H, which):
        nodes = self.other_segments[which].ravel()
        other = self.other_offset + self.other.node_translation_dofs(nodes).reshape(-1, 6)
        return np.concatenate([dofs, other], axis=1), G, H

    def tangents(self, q: np.ndarray):
        """Slip rows of the two material points at ξ and η: T(x₁ − x₂) rates."""
        P = self._ends(q)
        Q, which, _ = self._core(q, P)
        _, e, (xi, eta), _, _ = tube_distance(P, Q, hessian=False)
        T = tangent_basis(e)
        w = np.stack([1.0 - xi, xi, eta - 1.0, -eta], axis=1)
        GT = np.concatenate([w[:, j, None, None] * T for j in range(4)], axis=2)
        dofs = self._partner_rows(self._beam_dofs(), None, None, which)[0]
        return dofs, GT, T


class TubeRigidContact(TubeContact):
    """The segments of a ``Beam3D`` of tube radius ``clearance`` against a ``RigidBody3D``
    whose shape is a ``Ball`` (core: its centre) or a ``Capsule`` (core: the segment between
    its caps' centres)."""

    def __init__(self, body: Beam3D, rigid: RigidBody3D, restitution=0.0, clearance=0.0):
        if not isinstance(rigid.shape, (Ball, Capsule, Box)):
            raise InputError(
                f"a Beam3D's segments meet a RigidBody3D with a Ball, a Capsule or a Box "
                f"shape, got a {type(rigid.shape).__name__}"
            )
        centres, rho = rigid.shape.balls
        super().__init__(body, restitution, rho + clearance)
        self.rigid = rigid
        self.bodies = (body, rigid)
        self.points = centres if isinstance(rigid.shape, Capsule) else np.zeros((1, 3))
        self.rigid_offset = 0

    def bind(self, model) -> None:
        super().bind(model)
        self.rigid_offset = model.offset_of(self.rigid)

    def _core(self, q, P):
        o = self.rigid_offset
        x, _, J, Hx = self.rigid.frame_point_kinematics(q[o : o + 6], self.points)
        Q = np.broadcast_to(x, (self.size, *x.shape))
        return Q, np.zeros(self.size, int), (J, Hx)

    def _partner_rows(self, dofs, G, H, core):
        """Chain rule through the core points x_i(u, Θ): ∂x_i = J_i, ∂²x_i = H_i."""
        J, Hx = core
        m, k = self.size, len(J)
        Js = J.reshape(3 * k, 6)
        gQ = G[:, 6:].reshape(m, k, 3)
        G_rigid = G[:, 6:] @ Js
        Hout = np.zeros((m, 12, 12))
        Hout[:, :6, :6] = H[:, :6, :6]
        Hout[:, :6, 6:] = H[:, :6, 6:] @ Js
        Hout[:, 6:, :6] = Hout[:, :6, 6:].transpose(0, 2, 1)
        Hout[:, 6:, 6:] = Js.T @ H[:, 6:, 6:] @ Js + np.einsum("mki,kiab->mab", gQ, Hx)
        rigid = np.broadcast_to(self.rigid_offset + np.arange(6), (m, 6))
        return np.concatenate([dofs, rigid], axis=1), np.concatenate([G[:, :6], G_rigid], 1), Hout


class TubeBoxContact(TubeRigidContact):
    """The segments of a ``Beam3D`` of tube radius ``clearance`` against a ``RigidBody3D``
    ``Box``: the segment's point of least signed distance from the box
    (:func:`.beam3d_box.closest_to_box`). The distance is stationary in ξ there (or ξ sits at
    an end), so the gradient is that of the point x(ξ*) held on the segment: ((1 − ξ*) n,
    ξ* n) on the ends, n = R n_b the box's outward normal at its closest point (the nearest
    face's inside), and −n, n_b × ρ on the box's (u, Θ) (ρ = x(ξ*) in the box frame,
    δρ = ρ × δΘ). The curvature is left out (Newton's rate, not its answer), as for the rigid
    ball against a box."""

    def _box_geometry(self, q: np.ndarray):
        o = self.rigid_offset
        qr = q[o : o + 6]
        R = exp(qr[3:])
        P = self._ends(q) - self.rigid.center(qr)
        return (R, *closest_to_box(P[:, 0] @ R, P[:, 1] @ R, 0.5 * self.rigid.shape.sides))

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._box_geometry(q)[2] - self.radius

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, 12), gradients (m, 12), no curvature."""
        R, xi, s, rho, nb = self._box_geometry(q)
        n = nb @ R.T
        G = np.concatenate(
            [(1.0 - xi)[:, None] * n, xi[:, None] * n, -n, np.cross(nb, rho)], axis=1
        )
        rigid = np.broadcast_to(self.rigid_offset + np.arange(6), (self.size, 6))
        return s - self.radius, np.concatenate([self._beam_dofs(), rigid], axis=1), G, None

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Nothing to keep: a box has an inside, so the side is never in doubt."""


@register_pair(Beam3D, Circle)
def _beam3d_sphere(beam, sphere, nodes, restitution, clearance):
    """The segments against a Sphere seen from outside; named ``nodes`` or a cavity: nodes."""
    if sphere.inside or nodes is not None:
        return NodeContact(beam, sphere, nodes, restitution, clearance)
    return TubeSphereContact(beam, sphere, restitution, clearance)


@register_pair(Beam3D, Beam3D)
def _beam3d_beam3d(beam, other, nodes, restitution, clearance):
    """Two tubes, segment against segment; ``clearance`` the sum of their radii."""
    if nodes is not None:
        raise InputError("nodes: two Beam3D meet through their segments; give no nodes")
    return TubeBeamContact(beam, other, restitution, clearance)


@register_pair(Beam3D, RigidBody3D)
def _beam3d_rigid(beam, rigid, nodes, restitution, clearance):
    """The segments against a rigid Ball, Capsule or Box."""
    if nodes is not None:
        raise InputError("nodes: a Beam3D meets a RigidBody3D through its segments")
    if isinstance(rigid.shape, Box):
        return TubeBoxContact(beam, rigid, restitution, clearance)
    return TubeRigidContact(beam, rigid, restitution, clearance)


@register_pair(RigidBody3D, Beam3D)
def _rigid_beam3d(rigid, beam, nodes, restitution, clearance):
    """The same pair named the other way round."""
    return _beam3d_rigid(beam, rigid, nodes, restitution, clearance)
