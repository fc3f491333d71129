r"""Elastic solids on scikit-fem meshes: 2D plane strain / plane stress and 3D.

Total Lagrangian. The unknowns are the nodal displacements u (m) from the reference
configuration X, ordered node by node, dof = d·node + component (d = 2 or 3); the nodes are the
dofs of the scalar Lagrange element (P1: the mesh vertices; P2 adds edge, face and cell nodes).
With the shape functions N_a and their reference gradients ∇N_a,

    F = I + Σ_a u_a ⊗ ∇N_a,    E = ½(FᵀF − I)    (the linear material uses ε = sym(F − I)),

the strain energy is W(q) = ∫ W(E) dV, the internal force f_ai = ∫ P_iJ ∂_J N_a dV with
P = F S (the linear material: P = σ), and the element tangent is its exact Hessian

    K_aibk = ∫ ∂_J N_a A_iJkL ∂_L N_b dV,   A_iJkL = F_iI ℂ_IJKL F_kK + δ_ik S_JL.

The material (:mod:`fecontact.bodies.materials`) gives W, S = ∂W/∂E and ℂ = ∂S/∂E. In 2D,
integrals over the area are multiplied by ``thickness`` (m): energies in J, forces in N, for
plane strain as well as for plane stress.

Every call works on arrays of all elements and quadrature points at once, from the basis data
scikit-fem computes once (gradients ∇N_a, weights dV); the kinematics are computed once per
call. The linear material assembles its constant stiffness once. Quadrature: one point for P1
simplices (F constant: exact for any material), 2×2(×2) Gauss for bilinear/trilinear cells,
second order for P2 simplices, 3×3(×3) for biquadratic/triquadratic cells. The mass matrix is
consistent, ρ ∫ N_a N_b dV ⊗ I_d, exact.

Meshes with quadratic cells (triangle6, quad9, tetra10, hexahedron27 files) take element "P2":
the displacement then uses the shape functions of the geometry (isoparametric).

Reference elements may be numbered in either orientation (scikit-fem sorts simplex vertices);
an element whose Jacobian vanishes or changes sign inside it (degenerate, folded), or that
overlaps a neighbour (inverted), is rejected when the body is built.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem.helpers import det
from skfem.models.poisson import mass as _mass_form

from ..errors import InputError, check_finite, check_kind, check_positive
from .elasticity import (
    Quadrature,
    deformation,
    displacement_gradient,
    element_tangent,
    internal_force,
)
from .materials import PLANES, SolidMaterial
from .mesh_files import group_nodes, nodes_at, read_mesh_and_points
from .meshes import (
    ball_mesh,
    box_mesh,
    cell_kind,
    check_cells,
    disk_mesh,
    mesh_bases,
    min_edge_length,
    oriented_boundary,
    rectangle_mesh,
    split_quadratic,
)
from .nodal import NodalTranslations
from .solid_output import SolidOutput

__all__ = ["Solid"]


class Solid(SolidOutput, NodalTranslations):
    """Elastic body on a scikit-fem mesh (``MeshTri``, ``MeshQuad``: 2D; ``MeshTet``,
    ``MeshHex``: 3D).

    Parameters
    ----------
    mesh : the reference configuration, coordinates in m.
    material : :class:`~fecontact.bodies.materials.LinearElastic`, ``StVenantKirchhoff`` or
        ``NeoHookean``.
    element : "P1" (linear/bilinear/trilinear) or "P2" (quadratic) Lagrange elements.
    plane : 2D only: "strain" (E₃₃ = 0) or "stress" (S₃₃ = 0).
    thickness : 2D only: out-of-plane thickness in m (> 0); energies, forces and masses are
        those of the slab.

    Supports (``fix``) are chainable. Node indices may be negative (−1 is the last node).
    ``node_groups`` ({name: node indices}) names nodes beside the mesh's boundaries and
    subdomains: a mesh file's groups of points and 3D edges (:meth:`from_file`).
    """

    continuum = True

    def __init__(self, mesh, material, element: str = "P1", plane: str = "strain", thickness=1.0):
        cell = cell_kind(mesh)
        what = "a solid's material (LinearElastic, StVenantKirchhoff, NeoHookean)"
        check_kind("material", material, SolidMaterial, what)
        if not isinstance(element, str) or element not in ("P1", "P2"):
            raise InputError(f"element must be 'P1' or 'P2', got {element!r}")
        if element == "P1" and mesh.doflocs.shape[1] != mesh.nvertices:
            raise InputError(
                f"mesh has curved (quadratic) cells ({type(mesh).__name__}): use element='P2', "
                "whose displacements follow the same shape functions as the geometry"
            )
        self.dim = mesh.dim()
        if self.dim == 2:
            if not isinstance(plane, str) or plane not in PLANES:
                raise InputError(f"plane must be 'strain' or 'stress', got {plane!r}")
            self.plane = plane
            self.thickness = check_positive("thickness", thickness)
        else:
            if plane != "strain" or thickness != 1.0:
                raise InputError("plane and thickness apply to 2D meshes only")
            self.plane, self.thickness = None, 1.0
        self.mesh = mesh
        self.material = material
        self.element = element
        self.cell = cell
        self.linear = bool(material.linear)
        """Constant stiffness (linear material): internal(q) = K q; factor once."""
        self.fixed: set[int] = set()
        self.node_groups: dict[str, np.ndarray] = {}

        self._basis, self._mass_basis = mesh_bases(mesh, cell, element)
        check_cells(mesh, self._basis, cell)
        self.X = np.ascontiguousarray(self._basis.doflocs.T)
        self._quad = Quadrature.of(self._basis, self.thickness)
        self.element_dofs = self._quad.dofs
        self._K = self._Ke = None
        if self.linear:
            d, dV = self.dim, self._quad.dV
            _, _, CC = material.response(np.zeros((d, d) + dV.shape), self.plane)
            self._Ke = element_tangent(self._quad, None, CC, None)
            rows = np.broadcast_to(self.element_dofs[:, :, None], self._Ke.shape)
            cols = np.broadcast_to(self.element_dofs[:, None, :], self._Ke.shape)
            self._K = sp.csr_matrix(
                (self._Ke.ravel(), (rows.ravel(), cols.ravel())), shape=(self.ndof, self.ndof)
            )

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def from_file(cls, path, material, scale=1.0, offset=None, merge_nodes=False, **options):
        """Solid on a mesh file read with meshio (:func:`fecontact.bodies.mesh_files.read_mesh`:
        coordinates times ``scale`` (> 0), then shifted by ``offset`` (m); ``merge_nodes``
        merges coincident points first); ``options`` are those of :class:`Solid` (element,
        plane, thickness). The file's named groups (gmsh physical groups) name nodes: those of
        facets and cells through the mesh, those of points and 3D edges as ``node_groups``."""
        mesh, places = read_mesh_and_points(path, scale, offset, merge_nodes)
        body = cls(mesh, material, **options)
        body.node_groups = {name: nodes_at(body.X, x, name) for name, x in places.items()}
        return body

    @classmethod
    def disk(cls, center, radius: float, refinements: int, material, **options) -> Solid:
        """Disk of ``radius`` (m) at ``center`` (2-vector, m), triangles refined
        ``refinements`` times (4 · 4^refinements triangles; at most 9: 2^20 triangles)."""
        return cls(disk_mesh(center, radius, refinements), material, **options)

    @classmethod
    def ball(cls, center, radius: float, refinements: int, material, **options) -> Solid:
        """Ball of ``radius`` (m) at ``center`` (3-vector, m), tetrahedra refined
        ``refinements`` times (8^refinements × 8 elements; at most 6: 2^21 elements), boundary
        vertices on the sphere. With ``element="P2"`` the cells are quadratic (isoparametric)
        with the boundary's edge nodes on the sphere too: the surface is curved, not a
        polyhedron."""
        mesh = ball_mesh(center, radius, refinements, options.get("element") == "P2")
        return cls(mesh, material, **options)

    @classmethod
    def rectangle(cls, lower, upper, divisions, material, cell="triangle", **options) -> Solid:
        """Rectangle between corners ``lower`` and ``upper`` (m) with ``divisions`` = n or
        (n_x, n_y) cells per side; ``cell`` "triangle" (two per square) or "quad"."""
        return cls(rectangle_mesh(lower, upper, divisions, cell), material, **options)

    @classmethod
    def box(cls, lower, upper, divisions, material, cell="tetra", **options) -> Solid:
        """Box between corners ``lower`` and ``upper`` (m) with ``divisions`` = n or
        (n_x, n_y, n_z) cells per side; ``cell`` "tetra" (six per cube) or "hexahedron"."""
        return cls(box_mesh(lower, upper, divisions, cell), material, **options)

    @property
    def n_elements(self) -> int:
        return len(self._quad.nodes)

    @property
    def basis(self):
        """The scalar scikit-fem basis of each displacement component (P1 or P2 on the mesh,
        dofs in the order of the nodes ``X``)."""
        return self._basis

    @property
    def volume(self) -> float:
        """Reference volume in m³ (2D: area × thickness)."""
        return float(self._mass_basis.dx.sum() * self.thickness)

    @property
    def stiffness_volume(self) -> float:
        """∫E dV of the solid (J)."""
        return self.material.E * self.volume

    @property
    def mass(self) -> float:
        """Total mass in kg."""
        return self.material.rho * self.volume

    @property
    def min_edge_length(self) -> float:
        """Shortest edge of the reference mesh's cells (between vertices), m."""
        return min_edge_length(self.mesh)

    # -- kernels -----------------------------------------------------------------------------
    def _strain(self, q):
        """F (None for the linear material) and the material's strain at q."""
        return deformation(displacement_gradient(self._quad, q), self.linear)

    def _barrier_hit(self, F) -> bool:
        return F is not None and self.material.barrier and np.any(det(F) <= 0.0)

    def internal(self, q: np.ndarray, tangent: bool = True):
        """Strain energy W (J), internal force ∂W/∂q (N, (ndof,)) and element tangents
        ∂²W/∂q² (E, n_loc·d, n_loc·d) in N/m (None unless ``tangent``).

        Neo-Hookean bodies with an inverted element (det F ≤ 0) return W = inf and NaN forces.
        """
        if self.linear:
            f = self._K @ q
            return 0.5 * float(q @ f), f, self._Ke if tangent else None
        F, E = self._strain(q)
        if self._barrier_hit(F):
            Ke = np.full(self._Ke_shape(), np.nan) if tangent else None
            return np.inf, np.full(self.ndof, np.nan), Ke
        W, S, CC = self.material.response(E, self.plane, tangent)
        f = internal_force(self._quad, F, S, self.ndof)
        Ke = element_tangent(self._quad, F, CC, S) if tangent else None
        return float(np.sum(self._quad.dV * W)), f, Ke

    def inverted(self, q: np.ndarray) -> bool:
        """Whether q inverts an element (det F ≤ 0) of a body whose energy forbids it."""
        if self.linear or not self.material.barrier:
            return False
        return self._barrier_hit(self._strain(q)[0])

    def _Ke_shape(self):
        n = self.element_dofs.shape[1]
        return (self.n_elements, n, n)

    def energy(self, q: np.ndarray) -> float:
        """Strain energy W(q) in J (inf for an inverted Neo-Hookean element)."""
        if self.linear:
            return 0.5 * float(q @ (self._K @ q))
        F, E = self._strain(q)
        if self._barrier_hit(F):
            return np.inf
        W = self.material.response(E, self.plane, tangent=False)[0]
        return float(np.sum(self._quad.dV * W))

    def stiffness_matrix(self) -> sp.csr_matrix:
        """Constant stiffness K (N/m, ndof × ndof, no supports) of a linear body."""
        if not self.linear:
            raise InputError("stiffness_matrix: the material is nonlinear; use internal(q)")
        return self._K

    def mass_matrix(self) -> sp.csr_matrix:
        """Consistent mass (kg): ρ ∫ N_a N_b dV ⊗ I_d in the node-major dof order."""
        m = _mass_form.assemble(self._mass_basis) * (self.material.rho * self.thickness)
        return sp.kron(m, sp.identity(self.dim), format="csr")

    def translation_field(self, vector) -> np.ndarray:
        """Dof vector with ``vector`` (d components) on every node (gravity force: M @ this)."""
        v = check_finite("vector", vector).ravel()
        if v.shape != (self.dim,):
            raise InputError(
                f"vector must have {self.dim} components for a {self.dim}D solid, got {v.shape[0]}"
                " (3D models need a 3-component gravity)"
            )
        return np.tile(v, self.n_nodes)

    # -- geometry and output -----------------------------------------------------------------
    def boundary_nodes(self) -> np.ndarray:
        """Nodes on the boundary (vertices and, for P2, the boundary edge/face nodes)."""
        return np.unique(self._basis.get_dofs(self.mesh.boundary_facets()).all())

    def nodes_of(self, nodes) -> np.ndarray:
        """Validated node indices of one node, a sequence of them, or the name of a group of
        the mesh (:func:`~fecontact.bodies.mesh_files.group_nodes`: a gmsh physical group)."""
        if isinstance(nodes, str):
            if nodes in self.node_groups:  # set by hand too: checked as any node list
                return super().nodes_of(self.node_groups[nodes])
            return group_nodes(self.mesh, self._basis, nodes, self.node_groups)
        return super().nodes_of(nodes)

    def contact_nodes(self, nodes=None) -> np.ndarray:
        """Validated node indices (the boundary nodes when ``nodes`` is None)."""
        if nodes is None:
            return self.boundary_nodes()
        return self.nodes_of(nodes)

    def boundary_facets(self) -> np.ndarray:
        """Boundary facets as rows of vertex node indices, numbered so that the normal points
        out of the body: 2D segments (a, b) with outward normal (t_y, −t_x), t = x_b − x_a (the
        boundary runs counter-clockwise); 3D triangles or quadrilaterals with outward normal by
        the right-hand rule. P2 nodes inside the facets are not listed."""
        return oriented_boundary(self.mesh)[1]

    def contact_facets(self) -> np.ndarray:
        """The boundary as flat pieces for node-to-surface contact, numbered like
        :meth:`boundary_facets` (outward normal): 2D segments (n, 2), 3D triangles (n, 3).

        P2 facets are first split through their edge nodes (and the face node of a
        hexahedron's face): a segment into 2 segments, a triangle into 4 triangles, a
        quadrilateral into 4 quadrilaterals. Quadrilaterals (a, b, c, d) are then split along
        the diagonal a–c into (a, b, c) and (a, c, d).
        """
        bf, facets = oriented_boundary(self.mesh)
        if self.element == "P2":
            facets = split_quadratic(self.mesh, self._basis, bf, facets)
        if facets.shape[1] == 4:
            facets = np.concatenate([facets[:, [0, 1, 2]], facets[:, [0, 2, 3]]])
        return np.ascontiguousarray(facets)
