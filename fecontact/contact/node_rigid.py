r"""A :class:`~fecontact.Solid`'s nodes against the exact shape of a rigid body, in the plane
or in space: what the pairs of :mod:`fecontact.contact.solid_rigid2d` and
:mod:`fecontact.contact.solid_rigid3d` share.

One contact per slave node x (the solid's boundary nodes by default, or ``nodes``). A row's
dofs are the node's d translations followed by the rigid body's (its centre's d translations
first, then its rotation: θ in the plane, Θ in space). For a round shape (a ``Disk``, a
``Ball``) of radius r about the centre c, g = |x − c| − r − clearance (m, positive open),
G = [e, −e, 0] with e = (x − c)/|x − c|, and the curvature is exact, K = (I − e eᵀ)/|x − c|
on the two translations (turning the body moves no point of its outline off it).

Coulomb friction acts on the slip of the node against the body's material point under it,
ẋ − ẏ with ẏ = ċ + ω × (x − c) (ω the body's angular velocity): the rows T·[I, −I, B], T the
unit tangents of the row's normal n (:func:`~fecontact.contact.friction.tangent_basis`) and
B = −∂ẏ/∂(rotation rate) (in the plane −J(x − c), J the rotation by +90°; in space R ρ̃ with
ρ = Rᵀ(x − c), Ω in the body frame). Over a step from (q_n) the slip is exact: the material
point now under the node was at c_n + R_n Rᵀ(x − c) at t_n, so T·(c_n + R_n Rᵀ(x − c) − x_n).
Since G = n·[I, −I, B] on every shape, the normal and slip rows hold one relative motion.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, check_range
from .base import PairDefaults
from .friction import tangent_basis

__all__ = ["NodeRigidRows", "NodeRoundRows", "node_rows"]


class NodeRigidRows(PairDefaults):
    """Nodes of a ``dim``-D solid against a rigid body of ``rigid_dofs`` dofs (the subclasses
    give the dimension and the shape)."""

    linear = False
    frictional = True
    dim = 3
    rigid_dofs = 6

    def __init__(self, body, rigid, nodes, restitution, clearance):
        if body.dim != self.dim:
            kind = type(rigid).__name__
            raise InputError(f"a {kind} meets the nodes of a {self.dim}D Solid")
        self.body, self.rigid = body, rigid
        self.bodies = (body, rigid)
        self.nodes = body.contact_nodes(nodes)
        if len(self.nodes) == 0:
            raise InputError("nodes must name at least one node")
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = clearance
        self.size = len(self.nodes)
        self._node_dofs = body.node_translation_dofs(self.nodes)
        self.offsets = (0, 0)

    def _state(self, q: np.ndarray):
        """The nodes' positions (m, d) and the rigid body's dofs."""
        (oa, ob), body = self.offsets, self.body
        x = body.positions(q[oa : oa + body.ndof])[self.nodes]
        return x, q[ob : ob + self.rigid_dofs]

    def _dofs(self) -> np.ndarray:
        oa, ob = self.offsets
        rigid = np.broadcast_to(ob + np.arange(self.rigid_dofs), (self.size, self.rigid_dofs))
        return np.concatenate([oa + self._node_dofs, rigid], axis=1)

    # what the shape and the dimension give
    def _normals(self, q: np.ndarray) -> np.ndarray:
        """Unit normals n (m, d) of the rows, along the node's gradient block of G."""
        raise NotImplementedError

    def _rotation(self, qr: np.ndarray) -> np.ndarray:
        """The body's rotation R (d, d) at its dofs ``qr``."""
        raise NotImplementedError

    def _turn_rows(self, arm: np.ndarray, qr: np.ndarray) -> np.ndarray:
        """B (m, d, rotation dofs) = −∂ẏ/∂(rotation rate) of the body's points at ``arm`` =
        y − c (m, d) from its centre."""
        raise NotImplementedError

    def tangents(self, q: np.ndarray):
        """Dofs (m, n), slip rows T·[I, −I, B] (m, d − 1, n) and unit tangents T (m, d − 1, d)
        of the rows' normals (module docstring)."""
        x, qr = self._state(q)
        d = self.dim
        T = tangent_basis(self._normals(q))
        W = np.zeros((self.size, d, d + self.rigid_dofs))
        W[:, :, :d], W[:, :, d : 2 * d] = np.eye(d), -np.eye(d)
        W[:, :, 2 * d :] = self._turn_rows(x - self.rigid.center(qr), qr)
        return self._dofs(), np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·(c_n + R_n Rᵀ(x − c) − x_n) (m, d − 1): the node's motion over the step relative
        to the body's material point under it at q (exact for any rotation)."""
        (x, qr), (x_n, qr_n) = self._state(q), self._state(q_n)
        arm = (x - self.rigid.center(qr)) @ self._rotation(qr) @ self._rotation(qr_n).T
        return np.einsum("mtd,md->mt", T, self.rigid.center(qr_n) + arm - x_n)


class NodeRoundRows(NodeRigidRows):
    """Nodes outside a rigid ``Disk`` or ``Ball`` (module docstring)."""

    def _geometry(self, q):
        x, qr = self._state(q)
        d = x - self.rigid.center(qr)
        dist = np.linalg.norm(d, axis=1)
        if np.any(dist == 0.0):
            shape = type(self.rigid.shape).__name__.lower()
            raise InputError(f"a node lies at the rigid {shape}'s centre: no contact normal")
        return d / dist[:, None], dist

    def _normals(self, q: np.ndarray) -> np.ndarray:
        return self._geometry(q)[0]

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._geometry(q)[1] - self.rigid.shape.radius - self.clearance

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, n), gradients (m, n) and curvatures (m, n, n), n the node's d
        translations and the body's dofs."""
        e, dist = self._geometry(q)
        (m, d), n = e.shape, self.dim + self.rigid_dofs
        G = np.zeros((m, n))
        G[:, :d], G[:, d : 2 * d] = e, -e
        K = (np.eye(d) - e[:, :, None] * e[:, None, :]) / dist[:, None, None]
        H = np.zeros((m, n, n))
        H[:, :d, :d] = H[:, d : 2 * d, d : 2 * d] = K
        H[:, :d, d : 2 * d] = H[:, d : 2 * d, :d] = -K
        g = dist - self.rigid.shape.radius - self.clearance
        return g, self._dofs(), G, H


def node_rows(kinds: dict, solid, rigid, nodes, restitution, clearance) -> NodeRigidRows:
    """The pair of ``solid``'s nodes against ``rigid``: the class ``kinds[type]`` of the first
    shape type ``rigid.shape`` is an instance of; an unknown shape is refused by name."""
    for shape, kind in kinds.items():
        if isinstance(rigid.shape, shape):
            return kind(solid, rigid, nodes, restitution, clearance)
    allowed = " or a ".join(shape.__name__ for shape in kinds)
    raise InputError(
        f"a Solid's nodes meet a {type(rigid).__name__} with a {allowed} shape, "
        f"got a {type(rigid.shape).__name__}"
    )
