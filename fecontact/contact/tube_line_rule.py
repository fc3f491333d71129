"""The rule of a :class:`~fecontact.contact.tube_line_mortar.TubeLineMortar`'s rows over a
step: the weights of its centreline points in each row, chosen per segment at the step's start.

Over one plane face of the solid (:func:`~fecontact.contact.plane_faces.plane_faces`) the
plane gap φ is affine along a straight segment, and the dual weights (2 − 3ξ, 3ξ − 1) read the
tube's own gap at each node. A segment whose points lie over two faces crosses an edge, where
φ bends: up over a convex edge (the larger of the two faces' plane gaps), and the dual
functions' negative lobes weigh its far, larger part (a level rod 2 mm above a block's face,
5 cm beyond its edges, read −0.50 mm); down over a concave one, read above the node's gap.
Such a segment gives each of its two rows its node's own gap instead (the segment's first and
last point moved to its ends, weight ℓ / 2 L_i): the value the dual weights give where φ is
affine, so a row is continuous where the choice changes over one face. The choice is made
once per step from the positions at its start, never inside Newton's iteration.
"""

from __future__ import annotations

import numpy as np

from .facet_search import FacetSearch
from .plane_faces import plane_faces

__all__ = ["StepRule", "gauss_rule"]


def gauss_rule(pieces: int):
    """Points ξ (P,) and weights (P,) summing to 1 of the composite two-point Gauss rule."""
    x, w = np.polynomial.legendre.leggauss(2)
    left = np.arange(pieces)[:, None] / pieces
    return (left + (x + 1.0) / (2.0 * pieces)).ravel(), np.tile(w / (2.0 * pieces), pieces)


class StepRule:
    """Per segment (S) of ``segments`` with reference lengths ``ell`` (S,) over nodes carrying
    ``length`` (n_b,): the points ``t`` (S, P) and ``weights`` (S, P, 2) in the row of each end
    over a step, dual unless ``over_edge`` (module docstring); ``pieces`` of two points each
    over the boundary triangles ``facets`` of ``solid``."""

    def __init__(self, solid, facets, segments, ell, length, pieces: int):
        self.xi, w = gauss_rule(pieces)
        phi = np.stack([2.0 - 3.0 * self.xi, 3.0 * self.xi - 1.0], axis=1)  # (P, 2)
        # (S, P, 2) the weights w ℓ Φ_e / L of each point in the row of each end
        self.dual = w[None, :, None] * ell[:, None, None] * phi[None] / length[segments][:, None, :]
        self.nodal = np.zeros_like(self.dual)  # each end's node's own gap, ℓ / 2 L_i of it
        self.nodal[:, 0, 0] = ell / (2.0 * length[segments[:, 0]])
        self.nodal[:, -1, 1] = ell / (2.0 * length[segments[:, 1]])
        self.face = plane_faces(solid.positions(np.zeros(solid.ndof)), facets)
        self.search = FacetSearch(facets)  # (of the points at a step's start)
        self.over_edge = np.zeros(len(segments), bool)
        self.weights, self.t = self.dual, np.broadcast_to(self.xi, self.dual.shape[:2])
        self.decided = False

    def reset(self) -> None:
        self.search.reset()
        self.decided = False

    def choose(self, f: np.ndarray) -> bool:
        """The step's rule from the closest triangle f (S, P; −1: none) of each dual point at
        its start; whether it changed."""
        self.decided = True
        face = self.face[np.maximum(f, 0)]
        top = np.where(f >= 0, face, -1).max(axis=1)
        over = np.where(f >= 0, face, len(self.face)).min(axis=1) < top
        if np.array_equal(over, self.over_edge):
            return False
        self.over_edge = over
        self.weights = np.where(over[:, None, None], self.nodal, self.dual)
        t = np.tile(self.xi, (len(over), 1))
        t[over, 0], t[over, -1] = 0.0, 1.0
        self.t = t
        return True
