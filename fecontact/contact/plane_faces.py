"""The plane faces of a 3D solid's boundary: its triangles joined across every edge whose two
triangles are coplanar in the reference configuration, so that the plane gap of points over one
face is affine along a straight line, and bends only where a line passes from one face to
another over an edge (convex: the gap bends up; concave: down).

Coplanar: the third vertex of one triangle lies within
:data:`~fecontact.contact.beam3d_edges.CONVEX` of the edge's length of the other's plane
(the convexity test of :class:`~fecontact.contact.beam3d_edges.SolidEdges`, both ways).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .beam3d_edges import CONVEX
from .geometry import edge_folds

__all__ = ["plane_faces"]


def plane_faces(X: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """The face (an int per triangle) of each boundary triangle ``tri`` (T, 3; numbered
    outward) with reference node positions ``X`` (n, 3)."""
    edges, _, owners, below = edge_folds(X, tri)
    a, b = X[edges[:, 0]], X[edges[:, 1]]
    joined = np.abs(below) <= CONVEX * np.linalg.norm(b - a, axis=1)
    i, j = owners[joined, 0], owners[joined, 1]
    graph = coo_matrix((np.ones(len(i)), (i, j)), shape=(len(tri), len(tri)))
    return connected_components(graph, directed=False)[1]
