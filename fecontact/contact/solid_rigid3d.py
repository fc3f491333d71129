r"""A 3D :class:`~fecontact.Solid`'s nodes against the exact surface of a
:class:`~fecontact.bodies.rigid3d.RigidBody3D` (node-to-surface on a rigid master).

``Contact(solid, body, method="node-to-surface")`` builds these pairs; the default for the two
is dual mortar over the solid's boundary (:mod:`fecontact.contact.mortar_rigid3d`).

One contact per slave node x (its boundary nodes by default), against the rigid body's shape:

==========  ======================================================================================
``Ball``    g = |x − c| − ρ, c the body's centre; the normal e = (x − c)/|x − c|
``Box``     g = |ρ − p| with ρ = Rᵀ(x − c) the node in the box frame and p = clamp(ρ, ±h) its
            closest point of the box (h the half sides); inside the box g = −(depth below the
            nearest face). The normal n = R (ρ − p)/|ρ − p| (the nearest face's inside).
==========  ======================================================================================

Gradients act on the node's translations and on the body's (u, Θ), Θ body-frame: with δρ =
ρ × δΘ under R ⊕ δΘ = R exp(δΘ̃), ∂g/∂Θ = n_b × ρ (n_b = Rᵀn). The ball's curvature is exact,
K = (I − e eᵀ)/|x − c| on the two translations; the box's is left out (Newton's rate, not its
answer), as for the rigid ball against a box. Both shapes are exact: a rigid ball is no
faceted surface, and the box's faces are flat. A box's corners and edges, which can enter
between the nodes, carry rows of their own (:mod:`fecontact.contact.box_corners`,
:mod:`fecontact.contact.box_edges`), and the pair's watch measures its corners and edges
inside the solid. Coulomb friction: the nodes slip against the body's material points under
them (:mod:`fecontact.contact.node_rigid`), the corners and edges as theirs, with the pair's μ.
"""

from __future__ import annotations

import numpy as np

from ..bodies.rigid3d import RigidBody3D
from ..bodies.shapes3d import Ball, Box
from ..bodies.solid import Solid
from ..rotations import cross, exp, hat
from .box_corners import BoxCorners
from .box_edges import BoxEdges
from .node_rigid import NodeRigidRows, NodeRoundRows, node_rows
from .registry import register_pair
from .rigid_distance import FeatureDepths

__all__ = ["NodeBallContact", "NodeBoxContact"]


class NodeRigidContact(NodeRigidRows):
    """Nodes of a 3D solid against a rigid body in space; the subclasses give the shape."""

    dim, rigid_dofs = 3, 6

    def __init__(self, body: Solid, rigid: RigidBody3D, nodes, restitution, clearance):
        super().__init__(body, rigid, nodes, restitution, clearance)
        # a box's corners and edges, which the nodes' rows let in between them
        if isinstance(rigid.shape, Box):
            self.companions = (
                BoxCorners(self, body, rigid, clearance),
                BoxEdges(self, body, rigid, clearance),
            )

    def bind(self, model) -> None:
        self.offsets = (model.offset_of(self.body), model.offset_of(self.rigid))
        for pair in self.companions:
            pair.bind(model)

    def _rotation(self, qr: np.ndarray) -> np.ndarray:
        return exp(qr[3:])

    def _turn_rows(self, arm: np.ndarray, qr: np.ndarray) -> np.ndarray:
        return hat(arm) @ exp(qr[3:])  # R ρ̃ = (R ρ)~ R: ẏ = u̇ − R ρ̃ Ω

    def watch(self) -> FeatureDepths | None:
        """A box's corners and edges against the solid's boundary (the rows hold nodes only:
        a corner between them is measured, :class:`FeatureDepths`); None for a ball."""
        return FeatureDepths(self) if isinstance(self.rigid.shape, Box) else None


class NodeBallContact(NodeRoundRows, NodeRigidContact):
    """Nodes of a 3D solid against a rigid ``Ball`` (outside it; :class:`.NodeRoundRows`)."""


class NodeBoxContact(NodeRigidContact):
    """Nodes of a 3D solid against a rigid ``Box``."""

    def _geometry(self, q):
        """R, ρ (m, 3), the normal in the box frame n_b (m, 3) and the signed distance (m,)."""
        x, qr = self._state(q)
        R = exp(qr[3:])
        half = 0.5 * self.rigid.shape.sides
        rho = (x - self.rigid.center(qr)) @ R
        d = rho - np.clip(rho, -half, half)
        dist = np.linalg.norm(d, axis=1)
        inside = dist == 0.0
        nb = np.zeros_like(rho)
        nb[~inside] = d[~inside] / dist[~inside, None]
        if inside.any():  # leave by the nearest face
            depth = half - np.abs(rho[inside])
            k = np.argmin(depth, axis=1)
            rows = np.flatnonzero(inside)
            nb[rows, k] = np.where(rho[rows, k] >= 0.0, 1.0, -1.0)
            dist[inside] = -depth[np.arange(len(rows)), k]
        return R, rho, nb, dist

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._geometry(q)[3] - self.clearance

    def _normals(self, q: np.ndarray) -> np.ndarray:
        R, _, nb, _ = self._geometry(q)
        return nb @ R.T

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, 9), gradients (m, 9), no curvature."""
        R, rho, nb, dist = self._geometry(q)
        n = nb @ R.T
        G = np.concatenate([n, -n, cross(nb, rho)], axis=1)
        return dist - self.clearance, self._dofs(), G, None


# the shapes a solid's nodes meet, each its pair's class
SHAPES = {Ball: NodeBallContact, Box: NodeBoxContact}


@register_pair(Solid, RigidBody3D)
def _solid_rigid3d(solid, rigid, nodes, restitution, clearance):
    """The solid's nodes (default its boundary nodes) against a rigid Ball or Box."""
    return node_rows(SHAPES, solid, rigid, nodes, restitution, clearance)


@register_pair(RigidBody3D, Solid)
def _rigid3d_solid(rigid, solid, nodes, restitution, clearance):
    """The same pair named the other way round (``nodes`` of the solid)."""
    return _solid_rigid3d(solid, rigid, nodes, restitution, clearance)
