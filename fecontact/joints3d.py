r"""Joints in space between rigid bodies, beam nodes and the ground.

Each joint is a set of bilateral position constraints g_b(q) = 0 with the interface of a
contact pair, enforced like the planar ``Pin`` (a multiplier in the smooth step, equalities in
the position correction and the velocity jump). Two kinds of rows make them all:

* a point: x_a(r_a) − x_b(r_b) = 0 (3 rows, m): the body-frame point r_a of body a stays on the
  point r_b of body b (or on a point fixed in space);
* a right angle: (R_a d_a)·(R_b d_b) = 0 (1 row): two body-fixed unit directions stay
  perpendicular (the ground's directions are fixed);
* a line: (R_b e)·(x_a(r_a) − x_b(r_b)) = 0 (1 row per direction e ⊥ the axis, m): body a's
  point stays on a line fixed in body b (or in space).

==================  ===========================================  ====  ======================
joint               rows                                         rows  free motion
==================  ===========================================  ====  ======================
``BallJoint``       the point                                    3     3 rotations
``HingeJoint``      the point, the axis ⊥ two directions of b     5     rotation about the axis
``UniversalJoint``  the point, one direction of a ⊥ one of b      4     2 rotations
``PrismaticJoint``  a line (2 rows), three right angles           5     sliding along the axis
``FixedJoint``      the point, three right angles                6     none
==================  ===========================================  ====  ======================

A side of a joint is a ``RigidBody3D`` or a node of a ``Beam3D``. A beam node is a frame too: its
centre is the node, x = X + u, and its rotation the section's, R = exp(ψ̃) with increments
composed on the right as a rigid body's (:mod:`fecontact.bodies.beam3d`); R = I in the
reference, so a direction given in the pose q = 0 is one fixed in the section (the section
frame is R Λ₀). The joint's point must be the node (its arm r is zero: the point rows are
x_node − x_b, linear on that side, and a right angle or a line turns with R alone).

Gradients are taken along body-frame rotations δΘ (R ⊕ δΘ = R exp(δΘ̃)): ∂(R d)/∂Θ = −R d̃.
The curvature given with them is the derivative of the force Gᵀλ along the group, which Newton
needs: for a right angle with w = R_aᵀR_b d_b, the blocks d̃_a w̃ (a, a), −d̃_a R_aᵀR_b d̃_b (a, b)
and their mirror images; for a point, that of :class:`fecontact.bodies.rigid3d.RigidBody3D`.
Its quadratic form vᵀHv is the acceleration term of the constraint, g̈ − Gv̇.
"""

from __future__ import annotations

import numpy as np

from .bodies.beam3d import Beam3D
from .bodies.rigid3d import RigidBody3D
from .contact.base import PairDefaults
from .errors import InputError, check_finite
from .rotations import cross, exp, hat

__all__ = ["BallJoint", "FixedJoint", "HingeJoint", "PrismaticJoint", "UniversalJoint"]


def _vector3(name: str, value) -> np.ndarray:
    x = check_finite(name, value).ravel()
    if x.shape != (3,):
        raise InputError(f"{name} must be a 3-vector, got shape {x.shape}")
    return x


def _unit(name: str, value) -> np.ndarray:
    x = _vector3(name, value)
    n = np.linalg.norm(x)
    if n == 0.0:
        raise InputError(f"{name} must be a non-zero vector")
    return x / n


def _perpendiculars(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing ``axis`` to a right-handed orthonormal frame."""
    e = np.eye(3)[int(np.argmin(np.abs(axis)))]
    p1 = cross(axis, e)
    p1 /= np.linalg.norm(p1)
    return p1, cross(axis, p1)


class _NodeFrame:
    """A ``Beam3D`` node as the frame of a joint's side: centre X + u, rotation exp(ψ̃),
    the joint's point on the node (the interface of ``RigidBody3D`` that a joint uses)."""

    def __init__(self, beam: Beam3D, node: int):
        self.position = beam.X[node]
        self.dofs = np.arange(6)[None]
        self.dofs.flags.writeable = False
        self.J = np.zeros((1, 3, 6))
        self.J[0, :, :3] = np.eye(3)

    def center(self, q: np.ndarray) -> np.ndarray:
        return self.position + q[:3]

    def to_frame(self, point) -> np.ndarray:
        """The node's arm to ``point``: zero, the point being the node."""
        return np.zeros(3)

    def point_positions_frame(self, q: np.ndarray, r: np.ndarray) -> np.ndarray:
        return self.center(q)[None]

    def frame_point_function(self, r):
        """q ↦ (x, dofs, ∂x/∂(u, Θ), curvature) of the node: [I | 0], no curvature."""

        def kinematics(q: np.ndarray):
            return self.center(q)[None], self.dofs, self.J.copy(), np.zeros((1, 3, 6, 6))

        return kinematics


def _side(name: str, body, point: np.ndarray):
    """(the frame, the node or 0) of ``body`` (None: the ground) at ``point`` (m)."""
    if body is None or isinstance(body, RigidBody3D):
        return body, 0
    if not isinstance(body, Beam3D):
        kind = type(body).__name__
        raise InputError(f"{name} must be a RigidBody3D or a Beam3D, got {kind}")
    d = np.linalg.norm(body.X - point, axis=1)
    node = int(np.argmin(d))
    if d[node] > 1e-9 * body.length:  # (the tolerance of Beam2D.locate, a Pin's on a beam)
        raise InputError(
            f"point {point.tolist()} is not a node of the Beam3D {name}: a joint holds a "
            f"beam at a node (the nearest, {node}, is {d[node]:.3g} m away)"
        )
    return _NodeFrame(body, node), node


def _joint_point(body, other, point) -> np.ndarray:
    """The joint's point (m, pose q = 0): ``point``, or where it is a node index (an integer,
    negative from the end), that node of the joint's one Beam3D."""
    if isinstance(point, (int, np.integer)) and not isinstance(point, bool):
        beams = [b for b in (body, other) if isinstance(b, Beam3D)]
        if len(beams) != 1:
            raise InputError(
                "point: a node index names a node of the joint's one Beam3D; give the "
                "point's coordinates (m)"
            )
        return beams[0].X[beams[0].node_index(point)].copy()
    return _vector3("point", point)


class _Joint(PairDefaults):
    """The rows of a joint between ``body`` and ``other`` (None: the ground) at ``point``
    (m, in the pose q = 0 of both bodies; on a Beam3D a node, or its index), with the right
    angles ``pairs`` of (direction of a, direction of b) given in the pose q = 0 (both body
    frames are then the world frame)."""

    restitution = 0.0
    linear = False
    arms = None  # the remainder bound's arms (:func:`fecontact.joints.newton_remainder`)

    def __init__(self, body, point, other=None, pairs=(), lines=None):
        if body is None:
            raise InputError("body must be a RigidBody3D or a Beam3D, got None")
        if other is body:
            raise InputError("other: a body cannot be joined to itself")
        self.body, self.other = body, other
        self.point = _joint_point(body, other, point)
        (fa, na), (fb, nb) = _side("body", body, self.point), _side("other", other, self.point)
        self.frames, self.nodes = (fa, fb), (na, nb)
        for frame in self.frames:  # on a beam's node exactly (located within 1e-9 of it)
            if isinstance(frame, _NodeFrame):
                self.point = frame.position.copy()
                break
        self.r_a = fa.to_frame(self.point)[None]
        self.r_b = None if other is None else fb.to_frame(self.point)[None]
        # the pivot's kinematics on each side, with what does not change made once
        self.kin_a = fa.frame_point_function(self.r_a)
        self.kin_b = None if other is None else fb.frame_point_function(self.r_b)
        # the pivots' skew matrices, kept: every Newton iteration evaluates the joint
        self.hats = (hat(self.r_a), None if other is None else hat(self.r_b))
        self.pairs = [(np.asarray(a, float), np.asarray(b, float)) for a, b in pairs]
        # the point rows, or the two rows of a line along which the point slides
        self.lines = lines
        self.size = (3 if lines is None else len(lines)) + len(self.pairs)
        self.offsets = (0, 0)
        self._rows_dofs = None  # (offsets, the rows' dofs) of the last binding
        self.k = 6 if other is None else 12

    def bind(self, model) -> None:
        # a side's six dofs: a rigid body's, or (u, ψ) of the beam node
        oa = model.offset_of(self.body) + 6 * self.nodes[0]
        ob = 0 if self.other is None else model.offset_of(self.other) + 6 * self.nodes[1]
        self.offsets = (oa, ob)
        if self.lines is None and not self.pairs:  # point rows alone: a ball joint
            self.arms = self._arms(model.free_index)

    def _arms(self, free_index: np.ndarray) -> list:
        """[(free rotation dofs (3,), |r| in m)] of the bodies of a ball joint (a held
        rotation has none). Its rows x = c + R exp(D̃) r along an increment d of D have
        second derivatives of length at most |r| |d|², as exp's of skew matrices (the
        bound of :func:`fecontact.joints.newton_remainder`)."""
        arms = []
        sides = ((self.body, self.r_a), (self.other, self.r_b))  # (a node's arm is zero)
        for (body, r), offset in zip(sides, self.offsets, strict=True):
            if body is not None:
                dofs = free_index[offset + np.arange(3, 6)]
                if np.all(dofs >= 0):
                    arms.append((dofs, float(np.linalg.norm(r))))
        return arms

    def _frames(self, q: np.ndarray):
        oa, ob = self.offsets
        qa = q[oa : oa + 6]
        qb = None if self.other is None else q[ob : ob + 6]
        return qa, qb

    def evaluate(self, q: np.ndarray):
        """Constraint values (size,), dofs (size, k), gradient rows (size, k), curvature
        (size, k, k) (module docstring)."""
        qa, qb = self._frames(q)
        ball = self.lines is None and not self.pairs  # a ball joint: its point rows alone
        if ball and qb is None:  # (to the ground: the pivot's own arrays)
            x, _, J, Hx = self.kin_a(qa)
            return x[0] - self.point, self._dofs(qb), J[0], Hx[0]
        g = np.zeros(self.size)
        G = np.zeros((self.size, self.k))
        H = np.zeros((self.size, self.k, self.k))
        if ball:
            self._point_rows(qa, qb, g, G, H)
            return g, self._dofs(qb), G, H
        Ra, Rb = exp(qa[3:]), (np.eye(3) if qb is None else exp(qb[3:]))
        if self.lines is None:
            self._point_rows(qa, qb, g, G, H)
        else:
            for i, e in enumerate(self.lines):
                g[i], G[i], H[i] = self._line_row(qa, qb, Ra, Rb, e)
        first = 3 if self.lines is None else len(self.lines)
        for i, (da, db) in enumerate(self.pairs, start=first):
            g[i], G[i], H[i] = self._right_angle(Ra, Rb, da, db, qb is not None)
        return g, self._dofs(qb), G, H

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The constraint values alone (m for the point rows and lines)."""
        if self.lines is not None or self.pairs:
            return self.evaluate(q)[0]
        qa, qb = self._frames(q)
        fa, fb = self.frames
        x = fa.point_positions_frame(qa, self.r_a)[0]
        if qb is None:
            return x - self.point
        return x - fb.point_positions_frame(qb, self.r_b)[0]

    def _dofs(self, qb) -> np.ndarray:
        """The rows' dofs (size, k): the bodies' twelve (or six), fixed once bound."""
        oa, ob = self.offsets
        if self._rows_dofs is None or self._rows_dofs[0] != self.offsets:
            dofs = oa + np.arange(6)
            if qb is not None:
                dofs = np.concatenate([dofs, ob + np.arange(6)])
            dofs = np.repeat(dofs[None], self.size, axis=0)
            dofs.flags.writeable = False
            self._rows_dofs = (self.offsets, dofs)
        return self._rows_dofs[1]

    def _point_rows(self, qa, qb, g, G, H) -> None:
        """x_a(r_a) − x_b(r_b) (or − the point), into the first three rows."""
        xa, _, Ja, Ha = self.kin_a(qa)
        g[:3], G[:3, :6], H[:3, :6, :6] = xa[0], Ja[0], Ha[0]
        if qb is None:
            g[:3] -= self.point
            return
        xb, _, Jb, Hb = self.kin_b(qb)
        g[:3] -= xb[0]
        G[:3, 6:], H[:3, 6:, 6:] = -Jb[0], -Hb[0]

    def _line_row(self, qa, qb, Ra, Rb, e):
        """(R_b e)·(x_a(r_a) − x_b(r_b)): body a's point off the line of b (or of the ground)
        along e, its gradient and curvature (the frame F = b, the point P = a)."""
        k, ra, Ea = self.k, self.r_a[0], self.hats[0][0]
        xa = self.frames[0].center(qa) + Ra @ ra
        w = Rb @ e
        G, H = np.zeros(k), np.zeros((k, k))
        G[:3], G[3:6] = w, cross(ra, Ra.T @ w)
        H[3:6, 3:6] = Ea @ hat(Ra.T @ w)
        if qb is None:
            return float(w @ (xa - self.point)), G, H
        cb = self.frames[1].center(qb)
        E, rel = hat(e), Rb.T @ (xa - cb)
        G[6:9], G[9:12] = -w, cross(e, rel)
        H[6:9, 9:12], H[:3, 9:12] = Rb @ E, -Rb @ E
        H[9:12, 6:9], H[9:12, :3], H[9:12, 9:12] = -E @ Rb.T, E @ Rb.T, E @ hat(rel)
        H[9:12, 3:6] = -E @ Rb.T @ Ra @ Ea
        H[3:6, 9:12] = -Ea @ Ra.T @ Rb @ E
        xb = cb + Rb @ self.r_b[0]
        return float(w @ (xa - xb)), G, H

    def _right_angle(self, Ra, Rb, da, db, two: bool):
        """(R_a d_a)·(R_b d_b), its gradient and curvature over the joint's dofs."""
        k = self.k
        ea, eb = Ra @ da, Rb @ db
        G, H = np.zeros(k), np.zeros((k, k))
        G[3:6] = -eb @ Ra @ hat(da)
        Da = hat(da)
        H[3:6, 3:6] = Da @ hat(Ra.T @ eb)
        if two:
            Db = hat(db)
            G[9:12] = -ea @ Rb @ Db
            H[9:12, 9:12] = Db @ hat(Rb.T @ ea)
            H[3:6, 9:12] = -Da @ Ra.T @ Rb @ Db
            H[9:12, 3:6] = -Db @ Rb.T @ Ra @ Da
        return float(ea @ eb), G, H


class BallJoint(_Joint):
    """Spherical joint: the material point at ``point`` (m, pose q = 0) of ``body`` stays on
    the same material point of ``other``, or fixed in space when ``other`` is None. 3 rows.

    Either side may be a ``Beam3D``: ``point`` is then one of its nodes (its coordinates, or
    its index), whose section turns freely (a beam hung at a node, a payload on a flexible
    arm's tip)."""

    def __init__(self, body, point, other=None):
        super().__init__(body, point, other)


class HingeJoint(_Joint):
    """Revolute joint: a ball joint at ``point`` whose bodies turn relative to each other only
    about ``axis`` (a direction fixed in both, given in the pose q = 0). 5 rows.

    On a ``Beam3D`` side the axis is fixed in the node's section: it turns with the section's
    rotation R = exp(ψ̃) (its frame R Λ₀)."""

    def __init__(self, body, point, axis, other=None):
        n = _unit("axis", axis)
        p1, p2 = _perpendiculars(n)
        super().__init__(body, point, other, [(n, p1), (n, p2)])


class UniversalJoint(_Joint):
    """Universal (Cardan) joint: a ball joint at ``point`` keeping the direction ``axis_a``
    of ``body`` perpendicular to the direction ``axis_b`` of ``other`` (both in the pose
    q = 0, where they must be perpendicular). 4 rows."""

    def __init__(self, body, point, axis_a, axis_b, other=None):
        a, b = _unit("axis_a", axis_a), _unit("axis_b", axis_b)
        if abs(a @ b) > 1e-12:
            raise InputError("axis_a and axis_b must be perpendicular")
        super().__init__(body, point, other, [(a, b)])


class PrismaticJoint(_Joint):
    """Prismatic (slider) joint: ``body`` keeps its orientation relative to ``other`` (or to
    the ground) and its material point at ``point`` slides along the line through it along
    ``axis`` fixed in ``other`` (both given in the pose q = 0). 5 rows."""

    def __init__(self, body, point, axis, other=None):
        p1, p2 = _perpendiculars(_unit("axis", axis))
        e = np.eye(3)
        super().__init__(body, point, other, [(e[0], e[1]), (e[0], e[2]), (e[1], e[2])], [p1, p2])


class FixedJoint(_Joint):
    """Fixed joint: ``body`` moves with ``other`` (or is held in space) as one rigid body,
    the point ``point`` (m, pose q = 0) and the relative orientation held. 6 rows.

    On a ``Beam3D`` side the weld holds the node and its section: a rigid body welded at a
    beam's node moves as its mass and rotary inertia added there (``Beam3D.add_mass``)."""

    def __init__(self, body, point, other=None):
        e = np.eye(3)
        super().__init__(body, point, other, [(e[0], e[1]), (e[0], e[2]), (e[1], e[2])])
