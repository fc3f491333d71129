r"""A 2D solid's boundary segments against a moving rigid ``Disk`` (a
:class:`~fecontact.bodies.rigid.RigidBody2D`): the rows that keep the disk's arc out of the
chords between two boundary nodes, companions of the node rows
(:class:`~fecontact.contact.solid_rigid2d.NodeDiskContact`), which hold the nodes alone and
let a disk resting between two nodes sink by the sagitta L²/8r of their edge L.

Each segment (a, b) carries the row of :class:`~fecontact.contact.segment_pairs.
SegmentCircleContact` against the disk's circle, its centre c = c(q) the body's and r its
radius: x* = a + ξ(b − a) the closest point to c, g = |x* − c| − r − clearance. With
e = (x* − c)/|x* − c| the gradient over (a, b, c, θ) is G = [(1 − ξ)e, ξe, −e, 0] (the
disk's rotation moves no point of its outline off it), and the Hessian that of the distance
from c to the segment's line over (c, a, b) (:func:`~fecontact.contact.geometry.
point_line_distance`); at an end node (ξ = 0 or 1) the gap is that node's distance to c,
the node's own row once more (merged with it as a duplicate in the multipliers' solve).

Coulomb friction: the segment's material point at ξ against the disk's material point at
x*, c + r e: slip rows T[(1 − ξ)I, ξI, −I, −r J e], J the rotation by +90°, with the node
pair's μ; the slip over a step is exact for any rotation (:meth:`DiskSegmentRows.slips`).
"""

from __future__ import annotations

import numpy as np

from ..bodies.rigid import rotation
from .friction import tangent_basis
from .geometry import point_line_distance
from .segment_pairs import SegmentCircleContact

__all__ = ["DiskSegmentRows"]

_PERP = np.array([[0.0, -1.0], [1.0, 0.0]])  # J, the rotation by +90°
# (c, a, b) of point_line_distance's 6 entries in the rows' dofs (a, b, c)
_ORDER = np.array([4, 5, 0, 1, 2, 3])


class DiskSegmentRows(SegmentCircleContact):
    """The boundary segments of the 2D solid of the pair ``owner`` against its rigid body's
    ``Disk``: one row per segment (module docstring), the owner's restitution and clearance.
    Gaps in m, dofs (m, 7): the segment's two nodes' (u_x, u_y), then the body's
    (u_x, u_y, θ)."""

    redundant_rows = True  # (a row just inside its segment and the node's row near it)
    duplicate_rows = True  # (a row clipped to a node: the node's own row, once or twice)

    def __init__(self, owner):
        super().__init__(
            owner.body, None, owner.restitution, owner.clearance, owner.body.contact_facets()
        )
        self.owner, self.rigid = owner, owner.rigid
        self.bodies = (owner.body, owner.rigid)
        self.offsets = (0, 0)

    def bind(self, model) -> None:
        self.offsets = (model.offset_of(self.body), model.offset_of(self.rigid))
        self.offset = self.offsets[0]

    @property
    def radius(self) -> float:
        return self.rigid.shape.radius

    @property
    def friction(self) -> float:
        """Coulomb's μ of the pair that brings the rows (``Contact`` sets it there)."""
        return self.owner.friction

    def centre(self, q: np.ndarray) -> np.ndarray:
        ob = self.offsets[1]
        return self.rigid.center(q[ob : ob + 3])

    def _dofs(self) -> np.ndarray:
        ob = self.offsets[1]
        body = np.broadcast_to(ob + np.arange(3), (self.size, 3))
        return np.concatenate([super()._dofs(), body], axis=1)

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dof indices (m, 7), gradients (m, 7), Hessians (m, 7, 7)."""
        a, b, xi, dist, e = self._closest(q)
        G = np.zeros((self.size, 7))
        G[:, :2], G[:, 2:4], G[:, 4:6] = (1.0 - xi)[:, None] * e, xi[:, None] * e, -e
        H = np.zeros((self.size, 7, 7))
        inner = (xi > 0.0) & (xi < 1.0)
        if inner.any():
            centre = np.broadcast_to(self.centre(q), a.shape)
            f, _, Hf = point_line_distance(centre[inner], a[inner], b[inner])
            H[np.ix_(inner.nonzero()[0], _ORDER, _ORDER)] = np.sign(f)[:, None, None] * Hf
        end = ~inner
        if end.any():  # the node's distance |x_e − c|: K = (I − e eᵀ)/|x_e − c| on x_e − c
            B = np.zeros((int(end.sum()), 2, 7))
            B[:, :, :2] = (1.0 - xi[end])[:, None, None] * np.eye(2)
            B[:, :, 2:4] = xi[end][:, None, None] * np.eye(2)
            B[:, :, 4:6] = -np.eye(2)
            ee = e[end]
            K = (np.eye(2) - ee[:, :, None] * ee[:, None, :]) / dist[end, None, None]
            H[end] = np.einsum("mia,mij,mjb->mab", B, K, B)
        return dist - self.radius - self.clearance, self._dofs(), G, H

    def rate(self, q: np.ndarray) -> np.ndarray:
        """Zero: the disk's motion is in its dofs."""
        return np.zeros(self.size)

    def tangents(self, q: np.ndarray):
        """Dofs (m, 7), slip rows (m, 1, 7) and unit tangents T (m, 1, 2): the segment's
        point at ξ against the disk's point c + r e, T[(1 − ξ)I, ξI, −I, −r J e]."""
        _, _, xi, _, e = self._closest(q)
        W = np.zeros((self.size, 2, 7))
        W[:, :, :2] = (1.0 - xi)[:, None, None] * np.eye(2)
        W[:, :, 2:4] = xi[:, None, None] * np.eye(2)
        W[:, :, 4:6] = -np.eye(2)
        W[:, :, 6] = -self.radius * (e @ _PERP.T)
        T = tangent_basis(e)
        return self._dofs(), np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·((1 − ξ)(a − aₙ) + ξ(b − bₙ) − (p − pₙ)) (m, 1), p = c + r e the disk's
        material point at x* at q and pₙ the same point at q_n (exact for any rotation)."""
        a, b, xi, _, e = self._closest(q)
        (oa, ob), body = self.offsets, self.body
        x_n = body.positions(q_n[oa : oa + body.ndof])
        a_n, b_n = x_n[self.segments[:, 0]], x_n[self.segments[:, 1]]
        qr, qr_n = q[ob : ob + 3], q_n[ob : ob + 3]
        turn = rotation(self.rigid.orientation(qr_n) - self.rigid.orientation(qr))
        arm = self.radius * e
        dp = self.centre(q) + arm - self.rigid.center(qr_n) - arm @ turn.T
        dx = (1.0 - xi)[:, None] * (a - a_n) + xi[:, None] * (b - b_n) - dp
        return np.einsum("mtd,md->mt", T, dx)
