"""Cells of a solid's mesh in meshio/VTK numbering, for VTU output."""

from __future__ import annotations

import numpy as np

from .meshes import ELEMENTS

__all__ = ["vtk_cells"]

# scikit-fem's hexahedron vertex order to VTK's (``skfem.io.meshio.HEX_MAPPING[:8]``, kept
# here so that writing frames does not import meshio)
_HEX_TO_VTK = [0, 3, 6, 2, 1, 5, 7, 4]
# VTK's higher-order nodes of P2 cells, each the mean of these corners (VTK corner numbering)
_VTK_P2_NODES = {
    "tri": [(0, 1), (1, 2), (2, 0)],
    "quad": [(0, 1), (1, 2), (2, 3), (3, 0), (0, 1, 2, 3)],
    "tet": [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)],
    "hex": [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4)]
    + [(0, 4), (1, 5), (2, 6), (3, 7)]
    + [(0, 3, 7, 4), (1, 2, 6, 5), (0, 1, 5, 4), (3, 2, 6, 7), (0, 1, 2, 3), (4, 5, 6, 7)]
    + [tuple(range(8))],
}


def vtk_cells(mesh, cell: str, X: np.ndarray, element_nodes: np.ndarray | None = None):
    """Cells over the body's nodes X (n, d): triangle, quad, tetra, hexahedron for P1
    (``element_nodes`` None), or triangle6, quad9, tetra10, hexahedron27 for P2, whose
    ``element_nodes`` (E, n_loc) are matched to VTK's higher-order nodes by position."""
    t = mesh.t.T.copy()
    if cell == "hex":
        t = t[:, _HEX_TO_VTK]
    elif cell in ("tri", "tet"):
        # scikit-fem sorts simplex vertices; VTK wants positive orientation (signed volumes)
        P = mesh.p.T
        edges = P[t[:, 1:]] - P[t[:, :1]]
        flip = np.linalg.det(edges) < 0.0
        t[flip, 1], t[flip, 2] = t[flip, 2], t[flip, 1].copy()
    names = ELEMENTS[cell]
    if element_nodes is None:
        return [(names[2], np.ascontiguousarray(t))]
    en = element_nodes
    extra = np.stack([X[t[:, list(c)]].mean(axis=1) for c in _VTK_P2_NODES[cell]], 1)
    dist = np.linalg.norm(extra[:, :, None, :] - X[en][:, None, :, :], axis=-1)
    pick = np.argmin(dist, axis=2)
    return [(names[3], np.hstack([t, np.take_along_axis(en, pick, axis=1)]))]
