"""What an elastic solid writes in its frames: the Cauchy stress per cell (tensor, von Mises,
pressure), its cells in VTK numbering, and the boundary area each node carries (a lumped
contact pressure is a node's contact force over it)."""

from __future__ import annotations

import numpy as np

from .elasticity import cauchy_stress, cell_invariants
from .meshes import facet_normals
from .vtk_cells import vtk_cells

__all__ = ["SolidOutput", "STRESS_COMPONENTS"]

STRESS_COMPONENTS = {2: ("xx", "yy", "zz", "xy"), 3: ("xx", "yy", "zz", "xy", "yz", "xz")}
"""Components of the ``stress`` cell data: VTK's symmetric-tensor order in 3D (ParaView reads
six components as a symmetric tensor); in 2D the in-plane ones and σ_zz (plane strain)."""
_INDEX = {"x": 0, "y": 1, "z": 2}


class SolidOutput:
    """Output of a :class:`~fecontact.bodies.Solid` (mixed into it)."""

    def __repr__(self) -> str:
        # (a notebook shows it: what the mesh file gave, to check before a run)
        planar = f" plane {self.plane}, thickness {self.thickness:g} m," if self.dim == 2 else ""
        groups = [*(self.mesh.boundaries or {}), *(self.mesh.subdomains or {}), *self.node_groups]
        return (
            f"Solid({self.dim}D,{planar} {self.n_nodes} nodes, {self.n_elements} cells "
            f"({self.element} {self.cell}), volume {self.volume:.6g} m³, mass {self.mass:.6g} kg; "
            f"groups: {', '.join(groups) or 'none'})"
        )

    def stress(self, q: np.ndarray) -> np.ndarray:
        """Cauchy stress σ (Pa, tension positive) at the quadrature points, (E, Q, 3, 3).

        In 2D, σ₃₃ is the out-of-plane stress (zero in plane stress). The linear material gives
        σ = S (small strains).
        """
        return np.moveaxis(self._cauchy(q), (0, 1), (-2, -1)).swapaxes(0, 1)

    def _cauchy(self, q):
        return cauchy_stress(self.material, self.plane, *self._strain(q))

    def cell_data(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Per-cell output, averaged over the cell: ``stress`` (Pa, (E, 4) in 2D, (E, 6) in 3D,
        components :data:`STRESS_COMPONENTS`), ``stress_von_mises`` (Pa) √(3/2 s:s) with s the
        deviator of σ, and ``pressure`` −tr σ/3 (Pa). The von Mises stress is averaged
        point by point: on cells of one quadrature point (P1 simplices) it is that of
        ``stress``; on others it is at least that (von Mises is convex in σ)."""
        sigma = self._cauchy(q)
        dV = self._quad.dV
        mean = np.einsum("ijqe,qe->eij", sigma, dV / dV.sum(axis=0))
        pairs = [(_INDEX[c[0]], _INDEX[c[1]]) for c in STRESS_COMPONENTS[self.dim]]
        tensor = np.stack([mean[:, i, j] for i, j in pairs], axis=1)
        return {"stress": tensor, **cell_invariants(sigma, dV)}

    def cells(self) -> list[tuple[str, np.ndarray]]:
        """Cells for VTU output in meshio/VTK numbering: triangle, quad, tetra, hexahedron
        (P1) or triangle6, quad9, tetra10, hexahedron27 (P2), over the body's nodes."""
        en = None if self.element == "P1" else self._quad.nodes
        return vtk_cells(self.mesh, self.cell, self.X, en)

    def tributary_areas(self) -> np.ndarray:
        """Boundary area (m²; 2D: length × thickness) each node carries, (n_nodes,): each flat
        piece of :meth:`contact_facets` shared equally among its vertices; zero inside."""
        if getattr(self, "_tributary", None) is None:
            facets = self.contact_facets()
            x = self.X[facets]
            size = np.linalg.norm(facet_normals(x), axis=1) / (1.0 if self.dim == 2 else 2.0)
            share = np.repeat(size * self.thickness / facets.shape[1], facets.shape[1])
            self._tributary = np.bincount(facets.ravel(), share, minlength=self.n_nodes)
        return self._tributary
