r"""Joints: bilateral constraints g_b(q) = 0 between bodies, or between a body and the ground.

A joint has the interface of a contact pair (``size``, ``bind``, ``evaluate`` giving the
constraint values, their gradient and Hessian) and is enforced at every step: with a Lagrange
multiplier λ in the smooth step (index-3 generalized-α of Arnold & Brüls, so the smooth part
keeps its second order), and as equalities in the position correction and the velocity jump
(G_b v_{n+1} = 0), so that it holds at position and velocity level to solver tolerance.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError, check_finite

__all__ = ["Pin"]


class Pin:
    """Pin joint: the material point at ``point`` (reference coordinates, m) of ``body`` stays
    on the same material point of ``other``, or, when ``other`` is None, fixed in space.

    On a beam the point must be a node; a rigid body can be pinned anywhere. Two constraint
    equations: g_b = x_a(q) − x_b(q) (m).
    """

    restitution = 0.0
    size = 2

    def __init__(self, body, point, other=None):
        self.body = body
        self.other = other
        self.point = check_finite("point", point).reshape(2)
        self.kin_a = _material_point(body, self.point)
        self.kin_b = None if other is None else _material_point(other, self.point)
        if other is body:
            raise InputError("other: a body cannot be pinned to itself")
        self.linear = body.linear_kinematics and (other is None or other.linear_kinematics)
        self.offsets = (0, 0)

    def bind(self, model) -> None:
        ob = 0 if self.other is None else model.offset_of(self.other)
        self.offsets = (model.offset_of(self.body), ob)

    def _side(self, body, kin, offset, q):
        x, dofs, Jx, Hx = kin(q[offset : offset + body.ndof])
        return x[0], dofs[0] + offset, Jx[0], None if Hx is None else Hx[0]

    def evaluate(self, q: np.ndarray):
        """Constraint values (2,), dofs (2, k), gradient rows (2, k), Hessians (2, k, k)."""
        xa, da, Ja, Ha = self._side(self.body, self.kin_a, self.offsets[0], q)
        if self.other is None:
            g, dofs, G = xa - self.point, da, Ja
            H = Ha
        else:
            xb, db, Jb, Hb = self._side(self.other, self.kin_b, self.offsets[1], q)
            g = xa - xb
            dofs = np.concatenate([da, db])
            G = np.concatenate([Ja, -Jb], axis=1)
            H = None
            if Ha is not None or Hb is not None:
                k = len(dofs)
                H = np.zeros((2, k, k))
                if Ha is not None:
                    H[:, : len(da), : len(da)] = Ha
                if Hb is not None:
                    H[:, len(da) :, len(da) :] = -Hb
        return g, np.repeat(dofs[None], 2, axis=0), G, H


def _material_point(body, point):
    """Kinematics q ↦ (x, dofs, ∂x/∂q, ∂²x/∂q²) of the body's material point at ``point``."""
    if hasattr(body, "frame_point_kinematics"):  # rigid body: any point of its frame
        r = body.to_frame(point)[None, :]
        return lambda q: body.frame_point_kinematics(q, r)
    node = np.array([body.locate(point)])
    return lambda q: body.point_kinematics(q, node)
