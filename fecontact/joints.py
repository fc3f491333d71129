r"""Joints: bilateral constraints g_b(q) = 0 between bodies, or between a body and the ground.

A joint has the interface of a contact pair (``size``, ``bind``, ``evaluate`` giving the
constraint values, their gradient and Hessian) and is enforced at every step: with a Lagrange
multiplier λ in the smooth step (index-3 generalized-α of Arnold & Brüls, so the smooth part
keeps its second order), and as equalities in the position correction and the velocity jump
(G_b v_{n+1} = 0), so that it holds at position and velocity level to solver tolerance.
"""

from __future__ import annotations

import math

import numpy as np

from .bodies.base import BODY, BodyDefaults
from .contact.base import PairDefaults
from .errors import InputError, check_kind, check_vector

__all__ = ["Pin", "newton_remainder"]


class Pin(PairDefaults):
    """Pin joint: the material point at ``point`` (reference coordinates, m) of ``body`` stays
    on the same material point of ``other``, or, when ``other`` is None, fixed in space.

    On a beam the point must be a node; a rigid body can be pinned anywhere. Two constraint
    equations: g_b = x_a(q) − x_b(q) (m).
    """

    restitution = 0.0
    size = 2

    def __init__(self, body, point, other=None):
        self.body = check_kind("body", body, BodyDefaults, BODY)
        self.other = other if other is None else check_kind("other", other, BodyDefaults, BODY)
        self.point = check_vector("point", point, 2)
        self.kin_a = _material_point(body, self.point)
        self.kin_b = None if other is None else _material_point(other, self.point)
        if other is body:
            raise InputError("other: a body cannot be pinned to itself")
        self.linear = body.linear_kinematics and (other is None or other.linear_kinematics)
        self.offsets = (0, 0)
        self._dofs = self._global_dofs()
        self.arms = None

    def bind(self, model) -> None:
        ob = 0 if self.other is None else model.offset_of(self.other)
        self.offsets = (model.offset_of(self.body), ob)
        self._dofs = self._global_dofs()
        self.arms = self._arms(model.free_index)

    def _arms(self, free_index: np.ndarray):
        """[(free rotation dof, |r| in m)] of the rigid bodies of the pin, or None when a side
        is neither rigid nor of linear kinematics (its curvature is then unknown here).

        On a rigid body x = c + R(φ) r, so every derivative of order ≥ 2 of x is along the
        rotation alone and has length |r|; on a body of linear kinematics (beam and solid nodes,
        point masses) x is affine in q."""
        arms = []
        for body, offset in zip((self.body, self.other), self.offsets, strict=True):
            if body is None or body.linear_kinematics:
                continue
            if not body.rigid_frame:
                return None
            dof = int(free_index[offset + 2])  # θ, the third dof of a rigid body
            if dof >= 0:
                arms.append((dof, float(np.linalg.norm(body.to_frame(self.point)))))
        return arms

    def _global_dofs(self) -> np.ndarray:
        """The dofs (2, k) of both rows: a material point keeps its dofs, so built once."""
        oa, ob = self.offsets
        dofs = self.kin_a(np.zeros(self.body.ndof))[1][0] + oa
        if self.other is not None:
            dofs = np.concatenate([dofs, self.kin_b(np.zeros(self.other.ndof))[1][0] + ob])
        dofs = np.repeat(dofs[None], 2, axis=0)
        dofs.flags.writeable = False
        return dofs

    def evaluate(self, q: np.ndarray):
        """Constraint values (2,), dofs (2, k), gradient rows (2, k), Hessians (2, k, k)."""
        oa, ob = self.offsets
        xa, _, Ja, Ha = self.kin_a(q[oa : oa + self.body.ndof])
        if self.other is None:
            return xa[0] - self.point, self._dofs, Ja[0], None if Ha is None else Ha[0]
        xb, _, Jb, Hb = self.kin_b(q[ob : ob + self.other.ndof])
        G = np.concatenate([Ja[0], -Jb[0]], axis=1)
        H = None
        if Ha is not None or Hb is not None:
            ka = Ja.shape[2]
            H = np.zeros((2,) + G.shape[1:] * 2)
            if Ha is not None:
                H[:, :ka, :ka] = Ha[0]
            if Hb is not None:
                H[:, ka:, ka:] = -Hb[0]
        return xa[0] - xb[0], self._dofs, G, H


def _material_point(body, point):
    """Kinematics q ↦ (x, dofs, ∂x/∂q, ∂²x/∂q²) of the body's material point at ``point``."""
    if body.rigid_frame:  # rigid body: any point of its frame
        return body.frame_point_function(body.to_frame(point)[None, :])
    node = np.array([body.locate(point)])
    return lambda q: body.point_kinematics(q, node)


def newton_remainder(joints, dq: np.ndarray, lam: np.ndarray, dlam: np.ndarray):
    """Bounds on the joint terms of the smooth-step residual after a Newton update.

    A Newton update (dq, dλ) from (q, λ), solved with the exact tangent β′M + γ′C + K +
    Σ λ_i ∇²g_i and the rows G dq = −g, leaves in a model whose other forces are affine in q
    (``Model.linear``) only the Taylor remainders of the joints:

        g(q + dq)          = ½ dqᵀ∇²g(ξ) dq,
        R(q + dq, λ + dλ)  = [G(q + dq) − G(q) − ∇G dq]ᵀ(λ + dλ) + (Σ dλ_i ∇²g_i) dq.

    With the pins' rigid sides (arm |r|, rotation increment dθ) every derivative of order ≥ 2
    has length |r|, so per pin |g| ≤ ½ Σ|r| dθ² and the force term is at most
    Σ |r| (½ |λ + dλ| dθ² + |dλ| |dθ|): Newton's quadratic convergence made explicit. Returns
    (max over pins of the gap bound in m, the force bound in N), or None when a pin's
    curvature is unknown. ``lam`` is λ + dλ, rows as in ``joints`` (two per pin).

    A ball joint in space (:mod:`fecontact.joints3d`) gives its arms with the three dofs of
    each rotation increment d (dθ = |d|: the second derivative of d ↦ exp((D + d)~) r is at
    most |r| |d|², and the first |r| |d|), its rows three.
    """
    gap = force = 0.0
    row = 0
    for pin in joints.pairs:
        arms = pin.arms
        if arms is None:
            return None
        if arms:
            s1 = s2 = 0.0
            for dof, arm in arms:
                d = abs(float(dq[dof])) if np.ndim(dof) == 0 else math.sqrt(dq[dof] @ dq[dof])
                s1 += arm * d
                s2 += arm * d * d
            rows = slice(row, row + pin.size)
            lam_norm, dlam_norm = _norm(lam[rows]), _norm(dlam[rows])
            gap = max(gap, 0.5 * s2)
            force += 0.5 * lam_norm * s2 + dlam_norm * s1
        row += pin.size
    return gap, force


def _norm(x: np.ndarray) -> float:
    """|x| of a pin's two rows (as math.hypot) or a ball joint's three."""
    if x.size == 2:
        a, b = x.tolist()
        return math.hypot(a, b)
    return math.sqrt(x @ x)
