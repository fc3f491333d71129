r"""Contact pairs of rigid bodies in space (:class:`fecontact.bodies.rigid3d.RigidBody3D`).

Gradients act on (u, Θ), Θ the body-frame rotation (R ⊕ δΘ = R exp(δΘ̃)); a body-frame point r
then moves by δx = δu − R r̃ δΘ (:mod:`fecontact.bodies.rigid3d`).

==========================  =================================================================
pair                        gap
==========================  =================================================================
``BallsPlaneContact``       n·(c + R r_k − p) − ρ per ball k of the shape (a ``Ball``, the
                            two caps of a ``Capsule``): the ball's centre less its radius
``BallBallContact``         |c_b − c_a| − ρ_a − ρ_b of two ``Ball`` bodies
``BallBoxContact``          |ρ − p| − ρ_a: the ball's centre ρ in the box frame and its
                            closest point p of the box
vertices on a ``Plane``     :class:`fecontact.contact.NodeContact` through the body's
                            ``point_kinematics`` (a ``Box``'s corners, a ``Cylinder``'s rims)
any other two shapes        :class:`fecontact.contact.convex_pairs.ConvexContact`: GJK/EPA,
                            the face-clipping manifold of polyhedra
==========================  =================================================================

Friction acts at the contact points, the balls' points nearest the partner: its slip rows
carry the rotation (a ball rolls), and the slip over a step is those rows applied to the
step's increment (Δu, log(R_nᵀR)), zero when the ball rolls.
"""

from __future__ import annotations

import numpy as np

from ..bodies.rigid3d import RigidBody3D
from ..bodies.shapes3d import Ball, Box
from ..errors import InputError, check_range
from ..rotations import cross, exp, hat, log
from .ball_batches import BallBallBatch, BallPlaneBatch
from .base import PairDefaults
from .convex_pairs import ConvexContact
from .friction import tangent_basis
from .node_pairs import NodeContact
from .obstacles import Circle, Plane
from .registry import register_pair

__all__ = ["BallBallContact", "BallBoxContact", "BallsPlaneContact", "RigidPair"]


def _arm_rows(R: np.ndarray, a: np.ndarray) -> np.ndarray:
    """∂x/∂(u, Θ) (m, 3, 6) of the body-frame points ``a`` (m, 3): [I | −R ã]."""
    J = np.zeros((len(a), 3, 6))
    J[:, :, :3] = np.eye(3)
    J[:, :, 3:] = -R @ hat(a)
    return J


def _increment(q: np.ndarray, q_n: np.ndarray) -> np.ndarray:
    """(Δu, log(R_nᵀR)) of a rigid body from q_n to q: the body-frame increment of a step."""
    return np.concatenate([q[:3] - q_n[:3], log(exp(q_n[3:]).T @ exp(q[3:]))])


class BallsPlaneContact(PairDefaults):
    """The balls of a rigid body's shape against a ``Plane``; one contact per ball."""

    frictional = True

    def __init__(self, body: RigidBody3D, plane: Plane, restitution=0.0, clearance=0.0):
        if not isinstance(plane, Plane) or plane.dim != 3:
            raise InputError("obstacle must be a Plane in space (3 components)")
        self.body, self.obstacle = body, plane
        self.centres, self.radius = body.shape.balls
        if len(self.centres) == 0:
            raise InputError(f"a {type(body.shape).__name__} has no balls: contact its vertices")
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.radius = self.radius + clearance
        self.size = len(self.centres)
        self.linear = False
        self.offset = 0
        self.dofs = np.repeat(np.arange(6)[None], self.size, axis=0)

    def bind(self, model) -> None:
        self.offset = model.offset_of(self.body)

    def batch_key(self):
        """A ``Ball`` on a fixed plane, with friction or without, is evaluated with others."""
        if not isinstance(self.body.shape, Ball) or self.obstacle.moving:
            return None
        return BallPlaneBatch, self.friction > 0.0

    def _local(self, q):
        return q[self.offset : self.offset + 6]

    def gaps(self, q: np.ndarray) -> np.ndarray:
        x = self.body.point_positions_frame(self._local(q), self.centres)
        return self.obstacle.gap_values(x) - self.radius

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, 6), gradients (m, 6), curvature (m, 6, 6)."""
        x, _, J, H = self.body.frame_point_kinematics(self._local(q), self.centres)
        n = self.obstacle.normal
        g = self.obstacle.gap_values(x) - self.radius
        return g, self.dofs + self.offset, J.transpose(0, 2, 1) @ n, np.einsum("i,mikl->mkl", n, H)

    def rate(self, q: np.ndarray) -> np.ndarray:
        if not self.obstacle.moving:
            return np.zeros(self.size)
        return -np.full(self.size, self.obstacle.normal @ self.obstacle.speed())

    def _arms(self, q: np.ndarray):
        """R and the body-frame arms (m, 3) of the contact points c + R r_k − ρ n."""
        R = self.body.rotation(self._local(q))
        return R, self.centres - self.radius * (R.T @ self.obstacle.normal)

    def tangents(self, q: np.ndarray):
        """Slip rows T [I | −R ã] at the contact points (the rotation included: balls roll)."""
        R, a = self._arms(q)
        T = tangent_basis(np.repeat(self.obstacle.normal[None], self.size, axis=0))
        return self.dofs + self.offset, np.einsum("mti,mik->mtk", T, _arm_rows(R, a)), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The slip rows at q applied to the step's increment (Δu, log(R_nᵀR)): zero for a
        ball rolling over the step, as its slip velocity (a material point would trace a
        cycloid, O(Δθ³) off)."""
        _, G, _ = self.tangents(q)
        return G @ _increment(self._local(q), q_n[self.offset : self.offset + 6])


class RigidPair(PairDefaults):
    """One frictional contact between two rigid bodies in space ``a`` and ``b`` (the first
    carries the contact's output), with Newton's ``restitution``; its rows touch the twelve
    dofs of the two bodies."""

    frictional = True
    size = 1
    linear = False

    def __init__(self, a: RigidBody3D, b: RigidBody3D, restitution=0.0):
        self.bodies, self.body = (a, b), a
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.offsets = (0, 0)

    def bind(self, model) -> None:
        self.offsets = tuple(model.offset_of(b) for b in self.bodies)

    def _dofs(self):
        oa, ob = self.offsets
        return np.concatenate([oa + np.arange(6), ob + np.arange(6)])[None]


class BallBallContact(RigidPair):
    """Two rigid bodies with ``Ball`` shapes: g = |c_b − c_a| − ρ_a − ρ_b (one contact)."""

    def __init__(self, a: RigidBody3D, b: RigidBody3D, restitution=0.0, clearance=0.0):
        super().__init__(a, b, restitution)
        self.radii = a.shape.radius + b.shape.radius + clearance

    def batch_key(self):
        return BallBallBatch, self.friction > 0.0

    def _geometry(self, q):
        (a, b), (oa, ob) = self.bodies, self.offsets
        qa, qb = q[oa : oa + 6], q[ob : ob + 6]
        d = b.center(qb) - a.center(qa)
        dist = float(np.linalg.norm(d))
        if dist == 0.0:
            raise InputError("two balls share their centre: no contact normal")
        return qa, qb, d / dist, dist

    def evaluate(self, q: np.ndarray):
        """Gap (1,), dofs (1, 12), gradient (1, 12), curvature (1, 12, 12) of the centres."""
        _, _, n, dist = self._geometry(q)
        G = np.zeros((1, 12))
        G[0, :3], G[0, 6:9] = -n, n
        K = (np.eye(3) - np.outer(n, n)) / dist
        H = np.zeros((1, 12, 12))
        H[0, :3, :3] = H[0, 6:9, 6:9] = K
        H[0, :3, 6:9] = H[0, 6:9, :3] = -K
        return np.array([dist - self.radii]), self._dofs(), G, H

    def _arms(self, q):
        qa, qb, n, _ = self._geometry(q)
        (a, b) = self.bodies
        Ra, Rb = exp(qa[3:]), exp(qb[3:])
        return (Ra, Ra.T @ (a.shape.radius * n)), (Rb, Rb.T @ (-b.shape.radius * n)), n

    def tangents(self, q: np.ndarray):
        """Slip rows of the relative motion of b's contact point against a's."""
        (Ra, aa), (Rb, ab), n = self._arms(q)
        T = tangent_basis(n[None])
        rows = np.concatenate([-_arm_rows(Ra, aa[None])[0], _arm_rows(Rb, ab[None])[0]], axis=1)
        return self._dofs(), np.einsum("mti,ik->mtk", T, rows), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The slip rows at q applied to both bodies' increments (as ``BallsPlaneContact``)."""
        _, G, _ = self.tangents(q)
        (oa, ob) = self.offsets
        d = np.concatenate(
            [
                _increment(q[oa : oa + 6], q_n[oa : oa + 6]),
                _increment(q[ob : ob + 6], q_n[ob : ob + 6]),
            ]
        )
        return G @ d


class BallBoxContact(RigidPair):
    """A ``Ball`` body against a ``Box`` body: g = |ρ − p| − ρ_a with ρ = R_bᵀ(c_a − c_b) the
    ball's centre in the box frame and p its closest point of the box (ρ clamped to the half
    sides); inside the box, g = −(depth below the nearest face) − ρ_a. The normal n = R_b
    (ρ − p)/|ρ − p| (the nearest face's, inside) points from the box to the ball; the gradient
    is exact, the curvature left out (Newton's rate, not its answer)."""

    def __init__(self, ball: RigidBody3D, box: RigidBody3D, restitution=0.0, clearance=0.0):
        super().__init__(ball, box, restitution)
        self.radius = ball.shape.radius + clearance
        self.half = 0.5 * box.shape.sides

    def _geometry(self, q):
        """(q_a, q_b, R_b, ρ, p, n_b in the box frame, signed distance of the centre)."""
        (a, b), (oa, ob) = self.bodies, self.offsets
        qa, qb = q[oa : oa + 6], q[ob : ob + 6]
        Rb = exp(qb[3:])
        rho = Rb.T @ (a.center(qa) - b.center(qb))
        p = np.clip(rho, -self.half, self.half)
        d = rho - p
        dist = float(np.linalg.norm(d))
        if dist > 0.0:
            return qa, qb, Rb, rho, p, d / dist, dist
        depth = self.half - np.abs(rho)  # inside: leave by the nearest face
        k = int(np.argmin(depth))
        n = np.zeros(3)
        n[k] = 1.0 if rho[k] >= 0.0 else -1.0
        p = rho.copy()
        p[k] = n[k] * self.half[k]
        return qa, qb, Rb, rho, p, n, -float(depth[k])

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return np.array([self._geometry(q)[-1] - self.radius])

    def evaluate(self, q: np.ndarray):
        """Gap (1,), dofs (1, 12), gradient (1, 12), no curvature."""
        _, _, Rb, rho, _, nb, dist = self._geometry(q)
        n = Rb @ nb
        G = np.zeros((1, 12))
        G[0, :3], G[0, 6:9], G[0, 9:12] = n, -n, cross(nb, rho)
        return np.array([dist - self.radius]), self._dofs(), G, None

    def tangents(self, q: np.ndarray):
        """Slip rows of the ball's contact point against the box's."""
        qa, _, Rb, _, p, nb, _ = self._geometry(q)
        n = Rb @ nb
        Ra = exp(qa[3:])
        T = tangent_basis(n[None])
        arm_a = Ra.T @ (-self.bodies[0].shape.radius * n)
        rows = np.concatenate([_arm_rows(Ra, arm_a[None])[0], -_arm_rows(Rb, p[None])[0]], axis=1)
        return self._dofs(), np.einsum("mti,ik->mtk", T, rows), T

    slips = BallBallContact.slips


@register_pair(RigidBody3D, Plane)
def _rigid3d_plane(body, plane, nodes, restitution, clearance):
    """Balls (``Ball``, ``Capsule``) by their centres and radius, vertices as points."""
    if len(body.shape.balls[0]):
        if nodes is not None:
            raise InputError("nodes: a ball's contact is its whole surface; give no nodes")
        return BallsPlaneContact(body, plane, restitution, clearance)
    return NodeContact(body, plane, nodes, restitution, clearance)


@register_pair(RigidBody3D, Circle)
def _rigid3d_sphere(body, sphere, nodes, restitution, clearance):
    """Vertices (default: all) against a ``Sphere``; a shape of balls has none."""
    if len(body.shape.balls[0]):
        raise InputError(
            f"no contact between a RigidBody3D's {type(body.shape).__name__} and a Sphere: "
            "a fixed RigidBody3D with a Ball stands for a sphere seen from outside"
        )
    return NodeContact(body, sphere, nodes, restitution, clearance)


@register_pair(RigidBody3D, RigidBody3D)
def _rigid3d_rigid3d(body, other, nodes, restitution, clearance):
    """Ball–ball and ball–box (the ball first) pairs in closed form, any other two shapes by
    GJK/EPA (:class:`fecontact.contact.convex_pairs.ConvexContact`, the ``collision`` extra)."""
    if nodes is not None:
        raise InputError("nodes: two RigidBody3D contact over their whole shapes; give no nodes")
    if isinstance(body.shape, Ball) and isinstance(other.shape, Ball):
        return BallBallContact(body, other, restitution, clearance)
    if isinstance(body.shape, Ball) and isinstance(other.shape, Box):
        return BallBoxContact(body, other, restitution, clearance)
    return ConvexContact(body, other, restitution, clearance)
