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
                            r the sum of the two tubes' radii; and every node of either beam
                            against the other's closest segment, two rows in a valley of
                            its centreline (:mod:`.tube_beam`)
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

Coulomb friction acts on the slip of the tube's touching point against the partner's material
point at the contact, a rigid partner's rotation included. Against a sphere or a rigid body the
tube's point is its section's, −r n from the centreline point at ξ, which the section's turn
moves (:mod:`.section_segments`); so do two tubes' (:mod:`.tube_beam`).
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam3d import Beam3D
from ..bodies.rigid3d import RigidBody3D
from ..bodies.shapes3d import Ball, Box, Capsule
from ..errors import InputError, check_range
from ..rotations import cross, exp, hat
from .base import PairDefaults
from .beam3d_box import box_rows
from .friction import tangent_basis
from .node_pairs import NodeContact
from .obstacles import Circle
from .registry import register_pair
from .section_segments import segment_point_moves, segment_turns
from .segment3d import tube_distance

__all__ = ["TubeBoxContact", "TubeContact", "TubeRigidContact", "TubeSphereContact"]


class TubeContact(PairDefaults):
    """The segments of a ``Beam3D`` (one contact each) against a core of a partner; subclasses
    give the core's points (``_core``) and place the partner's rows (``_partner_rows``)."""

    linear = False
    looks_ahead = True
    duplicate_rows = True  # (two segments clipped to their shared node: one row twice)

    def __init__(self, body: Beam3D, restitution: float, radius: float):
        self.body = body
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.radius = radius  # m: the sum of the tube radii and any partner's radius
        self.segments = body.segments()
        self.size = len(self.segments)
        self.offset = 0
        self._start = None  # (normal e₀, partner segment) at the start of the step
        # the tube's radius where its section touches (its turn moves the touching point);
        # 0: the pair knows only the sum of two radii (two tubes) or there is no tube
        self.section_radius = 0.0

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)
        self._start = None

    def _ends(self, q: np.ndarray) -> np.ndarray:
        """The segments' end points (m, 2, 3)."""
        x = self.body.positions(q[self.offset : self.offset + self.body.ndof])
        return x[self.segments]

    def _beam_dofs(self) -> np.ndarray:
        nodes = self.segments.ravel()
        return self.offset + self.body.node_translation_dofs(nodes).reshape(-1, 6)

    def _section_rows(self, q, dofs, GT, T, xi, n):
        """The slip rows with the turn of the tube's section at ξ appended: its touching
        point lies at arm = −r n from the centreline (:mod:`.section_segments`)."""
        if not self.section_radius:
            return dofs, GT
        qb = q[self.offset : self.offset + self.body.ndof]
        turns, B = segment_turns(self.body, qb, self.segments, xi, -self.section_radius * n)
        GT = np.concatenate([GT, np.einsum("mti,mik->mtk", T, B)], axis=2)
        return np.concatenate([dofs, self.offset + turns], axis=1), GT

    def _tube_moves(self, q, q_n, xi, n):
        """The motion (m, 3) over the step of the tube's touching points at ξ: its section's
        point at −r n turned back with the section (the centreline's point where r = 0)."""
        s = slice(self.offset, self.offset + self.body.ndof)
        if self.section_radius:
            arms = -self.section_radius * n
            return segment_point_moves(self.body, q[s], q_n[s], self.segments, xi, arms)
        ends = self._ends(q) - self._ends(q_n)
        return (1.0 - xi)[:, None] * ends[:, 0] + xi[:, None] * ends[:, 1]

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
        self.section_radius = clearance

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

    def _contact_frame(self, q: np.ndarray):
        P = self._ends(q)
        Q = self._core(q, P)[0]
        _, e, (xi, _), _, _ = tube_distance(P, Q, hessian=False)
        return xi, e

    def tangents(self, q: np.ndarray):
        """Slip rows of the tube's touching points at ξ (its section's turn included)
        against the fixed sphere."""
        xi, e = self._contact_frame(q)
        T = tangent_basis(e)
        GT = np.concatenate([(1.0 - xi)[:, None, None] * T, xi[:, None, None] * T], axis=2)
        dofs, GT = self._section_rows(q, self._beam_dofs(), GT, T, xi, e)
        return dofs, GT, T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·Δx of the tube's touching points over the step, turned with their sections
        (the linear form is not exact for a turn)."""
        if not self.section_radius:
            return None
        xi, e = self._contact_frame(q)
        return np.einsum("mtd,md->mt", T, self._tube_moves(q, q_n, xi, e))


class TubeRigidContact(TubeContact):
    """The segments of a ``Beam3D`` of tube radius ``clearance`` against a ``RigidBody3D``
    whose shape is a ``Ball`` (core: its centre) or a ``Capsule`` (core: the segment between
    its caps' centres).

    Coulomb friction acts on the slip of the segment's centreline point at ξ against the rigid
    body's material point at the contact, a = p + ρ Rᵀe in the body frame (p the core point,
    ρ its ball's radius): T((1 − ξ)ẋ_a + ξẋ_b − u̇ + R ã Ω), the rigid body's rotation
    included (a ball rolls on the tube), plus the turn of the tube's section at ξ, which
    moves its touching point −r n from the centreline (r the ``clearance``)."""

    frictional = True

    def __init__(self, body: Beam3D, rigid: RigidBody3D, restitution=0.0, clearance=0.0):
        if not isinstance(rigid.shape, (Ball, Capsule, Box)):
            raise InputError(
                f"a Beam3D's segments meet a RigidBody3D with a Ball, a Capsule or a Box "
                f"shape, got a {type(rigid.shape).__name__}"
            )
        centres, rho = rigid.shape.balls
        super().__init__(body, restitution, rho + clearance)
        self.rho = rho  # m: the radius of the partner's core's balls (0 for a box)
        self.section_radius = clearance
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

    def _contact_frame(self, q: np.ndarray):
        """(ξ, unit normals n (m, 3) from the rigid body to the tube, the rigid body's arms a
        (m, 3) to its contact points in its frame, R)."""
        P = self._ends(q)
        Q = self._core(q, P)[0]
        _, e, (xi, eta), _, _ = tube_distance(P, Q, hessian=False)
        R = exp(q[self.rigid_offset + 3 : self.rigid_offset + 6])
        core = self.points[0] + eta[:, None] * (self.points[-1] - self.points[0])
        return xi, e, core + self.rho * e @ R, R

    def tangents(self, q: np.ndarray):
        """Slip rows: the tube's point at ξ relative to the rigid body's contact point (class
        docstring), on the segment's translations and the rigid body's (u, Θ)."""
        xi, n, arm, R = self._contact_frame(q)
        dofs, GT, T = self._slip_rows(xi, n, arm, R)
        dofs, GT = self._section_rows(q, dofs, GT, T, xi, n)
        return dofs, GT, T

    def _slip_rows(self, xi, n, arm, R):
        T = tangent_basis(n)
        rigid = np.zeros((len(n), 3, 6))
        rigid[:, :, :3] = np.eye(3)
        rigid[:, :, 3:] = -R @ hat(arm)  # ∂(u + R a)/∂(u, Θ), Θ in the body frame
        tube = np.concatenate([(1.0 - xi)[:, None, None] * T, xi[:, None, None] * T], axis=2)
        GT = np.concatenate([tube, -np.einsum("mti,mik->mtk", T, rigid)], axis=2)
        dofs = np.concatenate(
            [self._beam_dofs(), self.rigid_offset + np.arange(6)[None].repeat(len(n), axis=0)],
            axis=1,
        )
        return dofs, GT, T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·(Δx_tube − Δx_rigid) over the step: the rigid contact point's chord
        u + R a − (u_n + R_n a), exact for a rotating body (the linear form is not)."""
        xi, n, arm, R = self._contact_frame(q)
        o = self.rigid_offset
        R_n = exp(q_n[o + 3 : o + 6])
        tube = self._tube_moves(q, q_n, xi, n)
        rigid = (q[o : o + 3] - q_n[o : o + 3]) + arm @ (R - R_n).T
        return np.einsum("mtd,md->mt", T, tube - rigid)


class TubeBoxContact(TubeRigidContact):
    """The segments of a ``Beam3D`` of tube radius ``clearance`` against a ``RigidBody3D``
    ``Box``: three rows per segment, its least signed distance from the box below, above and
    inside its stretch over a face or along an edge (:func:`.beam3d_box.box_rows`; one row,
    the least over the segment, where it has none). The gradient is that of the row's point
    x(ξ) held on the segment with the normal ν (n_b, or n_b less its slide along the plane
    that ends the stretch): ((1 − ξ) n, ξ n) on the ends, n = R ν, and −n, ν × ρ on the box's
    (u, Θ) (ρ = x(ξ) in the box frame, δρ = ρ × δΘ). The curvature is left out (Newton's
    rate, not its answer), as for the rigid ball against a box. Friction as for
    :class:`TubeRigidContact`, the box's material point being its surface point p = ρ − s n_b
    nearest the row's point, the tube's its section's point −r n moved by the sections' turn
    ω(ξ) × arm (:mod:`.section_segments`), as against a ball or a capsule: a rod rolls across
    a face, and the friction's moment μN r about t × n bends it as on a plane. A segment
    lying along a face has its rows at both ends of its stretch, its nodes' sections' points,
    where two segments sharing a node give it one row twice: a rod on a box's top is the rod
    on a plane (the nodes' rows of :class:`.NodeContact`)."""

    redundant_rows = True  # (a segment's two rows at one point where its stretch is one)

    def __init__(self, body: Beam3D, rigid: RigidBody3D, restitution=0.0, clearance=0.0):
        super().__init__(body, rigid, restitution, clearance)
        # three rows per segment: rows [0, m) below its stretch over a face or along an
        # edge, [m, 2m) above, [2m, 3m) inside (:func:`.beam3d_box.box_rows`)
        self.segments = np.concatenate([self.segments] * 3)
        self.size = len(self.segments)

    def _box_geometry(self, q: np.ndarray):
        """(R, ξ, s, ρ, n_b, ν) of the rows (:func:`.beam3d_box.box_rows`), the segments'
        first, second and third rows in turn."""
        o = self.rigid_offset
        qr = q[o : o + 6]
        R = exp(qr[3:])
        m = self.size // 3
        P = self._ends(q)[:m] - self.rigid.center(qr)
        rows = box_rows(P[:, 0] @ R, P[:, 1] @ R, 0.5 * self.rigid.shape.sides)
        xi, s = (a.T.ravel() for a in rows[:2])
        rho, nb, nu = (a.transpose(1, 0, 2).reshape(-1, 3) for a in rows[2:])
        return R, xi, s, rho, nb, nu

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._box_geometry(q)[2] - self.radius

    def evaluate(self, q: np.ndarray):
        """Gaps (3m,), dofs (3m, 12), gradients (3m, 12) (zero on rows left out), no
        curvature."""
        R, xi, s, rho, _, nu = self._box_geometry(q)
        n = nu @ R.T
        G = np.concatenate([(1.0 - xi)[:, None] * n, xi[:, None] * n, -n, cross(nu, rho)], axis=1)
        G[np.isinf(s)] = 0.0
        rigid = np.broadcast_to(self.rigid_offset + np.arange(6), (self.size, 6))
        return s - self.radius, np.concatenate([self._beam_dofs(), rigid], axis=1), G, None

    def tangents(self, q: np.ndarray):
        dofs, GT, T = super().tangents(q)
        GT[np.isinf(self._box_geometry(q)[2])] = 0.0
        return dofs, GT, T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        out = super().slips(q, q_n, T)
        out[np.isinf(self._box_geometry(q)[2])] = 0.0
        return out

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Nothing to keep: a box has an inside, so the side is never in doubt."""

    def _contact_frame(self, q: np.ndarray):
        """(ξ*, the box's outward normals n = R n_b (m, 3), the box's contact points
        p = ρ − s n_b in its frame (on its surface), R)."""
        R, xi, s, rho, nb, _ = self._box_geometry(q)
        return xi, nb @ R.T, rho - np.where(np.isinf(s), 0.0, s)[:, None] * nb, R


@register_pair(Beam3D, Circle)
def _beam3d_sphere(beam, sphere, nodes, restitution, clearance):
    """The segments against a Sphere seen from outside; named ``nodes`` or a cavity: nodes."""
    if sphere.inside or nodes is not None:
        return NodeContact(beam, sphere, nodes, restitution, clearance)
    return TubeSphereContact(beam, sphere, restitution, clearance)


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
