r"""Mortar contact between two 3D P2 solids on their curved 6-node boundary triangles.

The form of :mod:`fecontact.contact.mortar3d` (dual multipliers, one per slave boundary node,
weighted gaps g̃_j = ∫ Φ_j g_N dA as the constraints, rows g_j = g̃_j / L_j) on the quadratic
faces themselves, corner and edge nodes alike, with the transformed basis of Popp, Wohlmuth,
Gee & Wall (2012): L_j = Σ_e ∫_e Ñ_j dA. The integrals, projections and their exact
derivatives are in :mod:`fecontact.contact.mortar_p2_triangles`. A slave face the master
covers in part takes the dual functions biorthogonal on its covered part (as linear
triangles do, :func:`~fecontact.contact.mortar_p2_triangles.weighted_gaps`); a node takes
part from a quarter of its covered weight.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .mortar3d import MortarContact3D
from .mortar_p2 import (
    QuadraticFacePairs,
    counted_weights,
    covered_part_gaps,
    reference_rule,
    shape_functions,
)
from .mortar_p2_triangles import DUALS, TRANSFORM, p2_triangle_integrals

__all__ = ["MortarContact3DP2", "quadratic_triangles", "triangle_shares"]


def quadratic_triangles(body) -> np.ndarray:
    """The 6-node boundary triangles (corners 1, 2, 3 with the outward normal by the
    right-hand rule, then the edge nodes m12, m23, m31) of a 3D P2 tetrahedral ``body``,
    from its boundary split through the edge nodes."""
    split = body.contact_facets()
    n = len(split) // 4
    parts = split.reshape(4, n, 3) if len(split) == 4 * n else None
    faces = None
    if body.element == "P2" and parts is not None:
        faces = np.stack([parts[0, :, 0], parts[1, :, 1], parts[2, :, 2], *parts[3].T], axis=1)
        same = [(0, 1, 3), (0, 2, 5), (1, 0, 3), (1, 2, 4), (2, 0, 5), (2, 1, 4)]
        if not all(np.array_equal(parts[p, :, i], faces[:, k]) for p, i, k in same):
            faces = None
    if faces is None:
        raise InputError("body: quadratic mortar faces need a 3D P2 solid of tetrahedra")
    return np.ascontiguousarray(faces)


_POINTS, _WEIGHTS = reference_rule("triangle")
_NT = shape_functions("triangle", _POINTS) @ TRANSFORM.T  # Ñ at the rule's points


def triangle_shares(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """∫_e Ñ_k dA (faces, 6) of the curved faces at positions x (m)."""
    s, t = _POINTS[:, 0], _POINTS[:, 1]
    l1 = 1.0 - s - t
    # ∂N/∂s and ∂N/∂t of (1, 2, 3, m12, m23, m31) at the points
    ds = np.stack([1 - 4 * l1, 4 * s - 1, 0 * s, 4 * (l1 - s), 4 * t, -4 * t], axis=1)
    dt = np.stack([1 - 4 * l1, 0 * s, 4 * t - 1, -4 * s, 4 * s, 4 * (l1 - t)], axis=1)
    X = x[faces]
    n = np.cross(np.einsum("gk,fkd->fgd", ds, X), np.einsum("gk,fkd->fgd", dt, X))
    dA = np.linalg.norm(n, axis=2) * (0.5 * _WEIGHTS)  # the weights are fractions of ½
    return dA @ _NT


class MortarContact3DP2(QuadraticFacePairs, MortarContact3D):
    """Dual mortar contact of the curved boundary of a 3D P2 :class:`~fecontact.Solid` (the
    slave ``body``) with that of another (the ``master``); see the module docstring. One
    contact per slave boundary node, corners and edge nodes."""

    faces_of, shares_of = staticmethod(quadratic_triangles), staticmethod(triangle_shares)

    def __init__(self, body, master, restitution: float = 0.0, margin=None):
        super().__init__(body, master, restitution, margin)
        # no pointwise safeguard (mortar_safeguard), as for the 2D quadratic faces: its node
        # gaps are measured to the flat triangles split through the master's edge nodes, not
        # to the curved faces the weighted gaps hold the nodes on
        self.pointwise = self.master_rows = None

    def _integrate(self, e, z, hessian):
        """Jets of the faces' weighted gaps, coverage, covered weights and the quadrature
        (with each entry's dual coefficients and the coupled Hessians of faces covered in
        part) of the entries."""
        moments, mass_of, coverage, covered, quad = p2_triangle_integrals(z, hessian, self.margin)
        jets, A, coupled = covered_part_gaps(e, moments, mass_of, coverage, len(self.facets), DUALS)
        covered = counted_weights(e, coverage, covered, len(self.facets))
        return jets, coverage, covered, (*quad, A, coupled)

    def _slip_weights(self, quad, k: int) -> np.ndarray:
        """Weights (P, 12) of the local nodes' motion in node k's slip: ∫ Φ_k N_i dA on the
        slave face's nodes, −∫ Φ_k N_i(μ) dA on the master's (the projections frozen)."""
        st, mu, dA, A, _ = quad
        P, Q = dA.shape
        Ns = shape_functions("triangle", st.reshape(-1, 2)).reshape(P, Q, 6)
        Nm = shape_functions("triangle", mu.reshape(-1, 2)).reshape(P, Q, 6)
        w = np.einsum("pqk,pk->pq", Ns @ TRANSFORM.T, A[:, k]) * dA
        return np.concatenate([np.einsum("pq,pqi->pi", w, Ns), -np.einsum("pq,pqi->pi", w, Nm)], 1)
