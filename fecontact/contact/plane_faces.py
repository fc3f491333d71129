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

__all__ = ["plane_faces"]


def plane_faces(X: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """The face (an int per triangle) of each boundary triangle ``tri`` (T, 3; numbered
    outward) with reference node positions ``X`` (n, 3)."""
    pairs = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    third = np.concatenate([tri[:, 2], tri[:, 0], tri[:, 1]])
    owner = np.tile(np.arange(len(tri)), 3)
    key = np.sort(pairs, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, third, owner = key[order], third[order], owner[order]
    twin = np.flatnonzero(np.all(key[1:] == key[:-1], axis=1))  # two triangles share it
    t = tri[owner[twin]]
    n = np.cross(X[t[:, 1]] - X[t[:, 0]], X[t[:, 2]] - X[t[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    a, b = X[key[twin, 0]], X[key[twin, 1]]
    below = -np.einsum("mi,mi->m", X[third[twin + 1]] - a, n)
    joined = np.abs(below) <= CONVEX * np.linalg.norm(b - a, axis=1)
    i, j = owner[twin][joined], owner[twin + 1][joined]
    graph = coo_matrix((np.ones(len(i)), (i, j)), shape=(len(tri), len(tri)))
    return connected_components(graph, directed=False)[1]
