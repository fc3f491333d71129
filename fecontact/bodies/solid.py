r"""Elastic solids on scikit-fem meshes: 2D plane strain / plane stress and 3D.

Total Lagrangian. The unknowns are the nodal displacements u (m) from the reference
configuration X, ordered node by node, dof = d·node + component (d = 2 or 3); the nodes are the
dofs of the scalar Lagrange element (P1: the mesh vertices; P2 adds edge, face and cell nodes).
With the shape functions N_a and their reference gradients ∇N_a,

    F = I + Σ_a u_a ⊗ ∇N_a,    E = ½(FᵀF − I)    (the linear material uses ε = sym(F − I)),

the strain energy is W(q) = ∫ W(E) dV, the internal force f_ai = ∫ P_iJ ∂_J N_a dV with
P = F S (the linear material: P = σ), and the element tangent is its exact Hessian

    K_aibk = ∫ ∂_J N_a A_iJkL ∂_L N_b dV,   A_iJkL = F_iI ℂ_IJKL F_kK + δ_ik S_JL.

The material (:mod:`fecontact.materials`) gives W, S = ∂W/∂E and ℂ = ∂S/∂E. In 2D, integrals
over the area are multiplied by ``thickness`` (m): energies in J, forces in N, for plane strain
as well as for plane stress.

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

from pathlib import Path

import numpy as np
import scipy.sparse as sp
import skfem
from skfem.models.poisson import mass as _mass_form

from ..errors import InputError, check_count, check_finite, check_positive
from .base import BodyDefaults
from .materials import PLANES

__all__ = ["Solid"]

# scalar Lagrange elements (P1, P2) of each reference cell, and the cell's meshio names
_ELEMENTS = {
    "tri": (skfem.ElementTriP1, skfem.ElementTriP2, "triangle", "triangle6"),
    "quad": (skfem.ElementQuad1, skfem.ElementQuad2, "quad", "quad9"),
    "tet": (skfem.ElementTetP1, skfem.ElementTetP2, "tetra", "tetra10"),
    "hex": (skfem.ElementHex1, skfem.ElementHex2, "hexahedron", "hexahedron27"),
}
# scikit-fem's hexahedron vertex order to VTK's (``skfem.io.meshio.HEX_MAPPING[:8]``, kept
# here so that importing the solid does not import meshio)
MAX_CELLS = 2**21  # grid bodies: a mesh of about 1e6 nodes is the most a direct solver takes
_HEX_TO_VTK = [0, 3, 6, 2, 1, 5, 7, 4]
_REFDOMS = {"RefTri": "tri", "RefQuad": "quad", "RefTet": "tet", "RefHex": "hex"}
_MIDPOINT = {
    "tri": (np.full((2, 1), 1.0 / 3.0), np.array([0.5])),
    "tet": (np.full((3, 1), 0.25), np.array([1.0 / 6.0])),
}
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


class Solid(BodyDefaults):
    """Elastic body on a scikit-fem mesh (``MeshTri``, ``MeshQuad``: 2D; ``MeshTet``,
    ``MeshHex``: 3D).

    Parameters
    ----------
    mesh : the reference configuration, coordinates in m.
    material : :class:`~fecontact.materials.LinearElastic`, ``StVenantKirchhoff`` or
        ``NeoHookean``.
    element : "P1" (linear/bilinear/trilinear) or "P2" (quadratic) Lagrange elements.
    plane : 2D only: "strain" (E₃₃ = 0) or "stress" (S₃₃ = 0).
    thickness : 2D only: out-of-plane thickness in m (> 0); energies, forces and masses are
        those of the slab.

    Supports (``fix``) are chainable. Node indices may be negative (−1 is the last node).
    """

    def __init__(self, mesh, material, element: str = "P1", plane: str = "strain", thickness=1.0):
        if not isinstance(mesh, skfem.Mesh):
            raise InputError(f"mesh must be a scikit-fem Mesh, got {type(mesh).__name__}")
        cell = _REFDOMS.get(mesh.elem.refdom.__name__)
        if cell is None:
            raise InputError(
                f"mesh must have triangles, quadrilaterals, tetrahedra or hexahedra, got "
                f"{type(mesh).__name__}"
            )
        if mesh.t.shape[1] == 0 or mesh.p.shape[1] == 0:
            raise InputError("mesh is empty: it has no elements")
        check_finite("mesh coordinates", mesh.p)
        unused = np.bincount(mesh.t.ravel(), minlength=mesh.nvertices) == 0
        if np.any(unused):
            raise InputError(
                f"mesh: vertex {int(np.argmax(unused))} belongs to no element "
                "(mesh.remove_unused_nodes() drops such points)"
            )
        if not all(hasattr(material, a) for a in ("response", "rho", "linear")):
            raise InputError(f"material must be a fecontact material, got {material!r}")
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

        order = 1 if element == "P1" else 2
        scalar = _ELEMENTS[cell][order - 1]()
        quadrature = {"quadrature": _MIDPOINT[cell]} if order == 1 and cell in _MIDPOINT else {}
        # a degenerate cell makes scikit-fem divide by zero; _check_cells then reports it
        with np.errstate(divide="ignore", invalid="ignore"):
            self._basis = skfem.Basis(mesh, scalar, intorder=2 * order, **quadrature)
            self._mass_basis = skfem.Basis(mesh, scalar, intorder=2 * order)
        self._check_cells()
        b = self._basis
        self.X = np.ascontiguousarray(b.doflocs.T)
        self._enodes = np.ascontiguousarray(b.element_dofs.T)  # (E, n_loc)
        # scikit-fem's layout with the points last and elements innermost: ∇N_a as
        # (n_loc, d, Q, E) and dV = weight · |det ∂x/∂ξ| · thickness as (Q, E)
        grads = np.stack([phi[0].grad for phi in b.basis])
        self._G = np.ascontiguousarray(grads.swapaxes(-1, -2))
        self._w = np.ascontiguousarray(b.dx.T) * self.thickness
        d = self.dim
        self.element_dofs = (d * self._enodes[:, :, None] + np.arange(d)).reshape(
            len(self._enodes), -1
        )
        self._K = self._Ke = None
        if self.linear:
            _, _, CC = material.response(np.zeros((d, d) + self._w.shape), self.plane)
            self._Ke = self._element_tangent(None, CC, None)
            rows = np.broadcast_to(self.element_dofs[:, :, None], self._Ke.shape)
            cols = np.broadcast_to(self.element_dofs[:, None, :], self._Ke.shape)
            self._K = sp.csr_matrix(
                (self._Ke.ravel(), (rows.ravel(), cols.ravel())), shape=(self.ndof, self.ndof)
            )

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def from_file(cls, path, material, scale: float = 1.0, offset=None, **options) -> Solid:
        """Read a mesh file with meshio (any format it knows: .msh, .vtu, .vtk, .xdmf, ...).

        The coordinates are multiplied by ``scale`` and then shifted by ``offset`` (m, d
        components). ``options`` are those of :class:`Solid` (element, plane, thickness). The
        dimension comes from the cells: tetrahedra or hexahedra make a 3D body, else triangles
        or quadrilaterals a 2D one.
        """
        import meshio  # lazily: mesh I/O only when a file is read
        from skfem.io.meshio import from_meshio

        path = Path(path)
        known = meshio.extension_to_filetypes
        suffix = path.suffix.lower()
        if suffix not in known and "".join(path.suffixes[-2:]).lower() not in known:
            raise InputError(
                f"unknown mesh file format {suffix or '(no extension)'!r} of {path.name}; "
                "meshio reads " + ", ".join(sorted(known))
            )
        if not path.is_file():
            raise InputError(f"mesh file not found: {path}")
        try:
            # .msh is also an ANSYS extension; meshio would try (and print) that reader first
            data = meshio.read(path, file_format="gmsh" if suffix == ".msh" else None)
        except Exception as err:  # meshio raises many types for corrupt files
            raise InputError(f"cannot read mesh file {path.name}: {err}") from None
        kinds = [names[k] for names in _ELEMENTS.values() for k in (2, 3)]
        blocks = [(c.type, c.data) for c in data.cells if c.type in kinds]
        if not blocks:
            raise InputError(
                f"{path.name} has no {', '.join(kinds)} cells "
                f"(found {', '.join(c.type for c in data.cells) or 'none'})"
            )
        # keep the cells only, and the points they use: files often carry others (gmsh
        # geometry points, boundary lines)
        used = np.unique(np.concatenate([conn.ravel() for _, conn in blocks]))
        index = np.full(len(data.points), -1)
        index[used] = np.arange(len(used))
        data = meshio.Mesh(data.points[used], [(kind, index[conn]) for kind, conn in blocks])
        mesh = from_meshio(data)
        mesh = mesh.scaled(check_positive("scale", scale))
        if offset is not None:
            mesh = mesh.translated(_check_point("offset", offset, mesh.dim()))
        return cls(mesh, material, **options)

    @classmethod
    def disk(cls, center, radius: float, refinements: int, material, **options) -> Solid:
        """Disk of ``radius`` (m) at ``center`` (2-vector, m), triangles refined
        ``refinements`` times (4^refinements × 8 elements; at most 9: 2^21 elements)."""
        c = _check_point("center", center, 2)
        r = check_positive("radius", radius)
        m = skfem.MeshTri.init_circle(check_count("refinements", refinements, 0, 9))
        return cls(m.scaled(r).translated(c), material, **options)

    @classmethod
    def ball(cls, center, radius: float, refinements: int, material, **options) -> Solid:
        """Ball of ``radius`` (m) at ``center`` (3-vector, m), tetrahedra refined
        ``refinements`` times (8^refinements × 8 elements; at most 6: 2^21 elements), boundary
        vertices on the sphere. With ``element="P2"`` the cells are quadratic (isoparametric)
        with the boundary's edge nodes on the sphere too: the surface is curved, not a
        polyhedron."""
        c = _check_point("center", center, 3)
        r = check_positive("radius", radius)
        kind = skfem.MeshTet2 if options.get("element") == "P2" else skfem.MeshTet
        m = kind.init_ball(check_count("refinements", refinements, 0, 6))
        return cls(m.scaled(r).translated(c), material, **options)

    @classmethod
    def rectangle(cls, lower, upper, divisions, material, cell="triangle", **options) -> Solid:
        """Rectangle between corners ``lower`` and ``upper`` (m) with ``divisions`` = n or
        (n_x, n_y) cells per side; ``cell`` "triangle" (two per square) or "quad"."""
        axes = _grid_axes(lower, upper, divisions, 2)
        kinds = {"triangle": skfem.MeshTri, "quad": skfem.MeshQuad}
        if cell not in kinds:
            raise InputError(f"cell must be 'triangle' or 'quad', got {cell!r}")
        return cls(kinds[cell].init_tensor(*axes), material, **options)

    @classmethod
    def box(cls, lower, upper, divisions, material, cell="tetra", **options) -> Solid:
        """Box between corners ``lower`` and ``upper`` (m) with ``divisions`` = n or
        (n_x, n_y, n_z) cells per side; ``cell`` "tetra" (six per cube) or "hexahedron"."""
        axes = _grid_axes(lower, upper, divisions, 3)
        kinds = {"tetra": skfem.MeshTet, "hexahedron": skfem.MeshHex}
        if cell not in kinds:
            raise InputError(f"cell must be 'tetra' or 'hexahedron', got {cell!r}")
        return cls(kinds[cell].init_tensor(*axes), material, **options)

    def _check_cells(self):
        """Reject degenerate, folded and inverted cells (see the module docstring)."""
        mesh, b = self.mesh, self._basis
        corners = mesh.elem.refdom.p if self.cell in ("quad", "hex") else np.zeros((self.dim, 0))
        det = b.mapping.detDF(np.hstack([b.X, corners]))
        scale = np.median(np.abs(det))
        tol = 1e-10 * scale
        sign = np.sign(det[:, :1])
        bad = np.any(det * sign <= tol, axis=1)
        if np.any(bad):
            e = int(np.argmax(bad))
            raise InputError(
                f"mesh: element {e} (nodes {mesh.t[:, e].tolist()}) is degenerate or folded: "
                f"the Jacobian determinant of its map vanishes or changes sign inside it (from "
                f"{det[e].min():.3e} to {det[e].max():.3e}; typical magnitude {scale:.3e})"
            )
        # two cells sharing a facet must lie on either side of it; a flipped cell does not
        f2t = mesh.f2t
        inner = np.flatnonzero(f2t[1] >= 0)
        if inner.size == 0:
            return
        P = mesh.p.T
        fx = P[mesh.facets[:, inner].T]  # (F, facet vertex, d)
        n = _facet_normals(fx)
        centroid = P[mesh.t].mean(axis=0)
        x0 = fx.mean(axis=1)
        s1 = np.einsum("fi,fi->f", centroid[f2t[0, inner]] - x0, n)
        s2 = np.einsum("fi,fi->f", centroid[f2t[1, inner]] - x0, n)
        overlap = s1 * s2 >= 0.0
        if np.any(overlap):
            counts = np.bincount(f2t[:, inner[overlap]].ravel(), minlength=mesh.t.shape[1])
            e = int(np.argmax(counts))
            raise InputError(
                f"mesh: element {e} (nodes {mesh.t[:, e].tolist()}) is inverted: it overlaps "
                f"its neighbours across {counts[e]} facet(s)"
            )

    # -- supports ----------------------------------------------------------------------------
    def node_index(self, node: int) -> int:
        """Validated node index in [0, n_nodes); negative indices count from the end."""
        n = self.n_nodes
        if not _is_int(node) or not -n <= int(node) < n:
            raise InputError(f"node must be an integer in [{-n}, {n - 1}], got {node!r}")
        return int(node) % n

    def _nodes(self, nodes) -> np.ndarray:
        return np.array([self.node_index(i) for i in np.atleast_1d(nodes).ravel()], dtype=int)

    def fix(self, nodes, components=None) -> Solid:
        """Fix the displacement ``components`` (None: all; else indices 0 = x, 1 = y, 2 = z) of
        ``nodes`` at zero."""
        idx = self._nodes(nodes)
        comps = range(self.dim) if components is None else np.atleast_1d(components)
        for c in comps:
            if not _is_int(c) or not 0 <= int(c) < self.dim:
                raise InputError(f"components must be in 0..{self.dim - 1}, got {c!r}")
            self.fixed.update((self.dim * idx + int(c)).tolist())
        return self

    def nodes_where(self, condition) -> np.ndarray:
        """Nodes whose reference coordinates satisfy ``condition(x)``; x has shape (d, n) as in
        scikit-fem (``lambda x: x[1] < 1e-9``: the nodes on y = 0)."""
        mask = np.asarray(condition(self.X.T), dtype=bool)
        if mask.shape != (self.n_nodes,):
            raise InputError(f"condition must return {self.n_nodes} booleans, got {mask.shape}")
        return np.flatnonzero(mask)

    # -- sizes -------------------------------------------------------------------------------
    @property
    def dofs_per_node(self) -> int:
        return self.dim

    @property
    def n_nodes(self) -> int:
        return len(self.X)

    @property
    def ndof(self) -> int:
        return self.dim * len(self.X)

    @property
    def n_elements(self) -> int:
        return len(self._enodes)

    @property
    def volume(self) -> float:
        """Reference volume in m³ (2D: area × thickness)."""
        return float(self._mass_basis.dx.sum() * self.thickness)

    @property
    def mass(self) -> float:
        """Total mass in kg."""
        return self.material.rho * self.volume

    linear_kinematics = True
    """Node positions are linear in the dofs (x = X + u)."""

    @property
    def characteristic_length(self) -> float:
        """Diagonal of the bounding box of the reference configuration, m."""
        return float(np.linalg.norm(self.X.max(axis=0) - self.X.min(axis=0)))

    @property
    def min_edge_length(self) -> float:
        """Shortest edge of the reference mesh's cells (between vertices), m."""
        mesh = self.mesh
        edges = mesh.facets if self.dim == 2 else mesh.edges
        return float(np.min(np.linalg.norm(np.diff(mesh.p[:, edges], axis=1)[:, 0], axis=0)))

    # -- kernels -----------------------------------------------------------------------------
    def _displacement_gradient(self, q):
        """H = ∇u as (d, d, Q, E)."""
        Ue = np.asarray(q, dtype=float).reshape(-1, self.dim).T[:, self._enodes.T]
        return np.einsum("iae,ajqe->ijqe", Ue, self._G)

    def _strain(self, H):
        """F (None for the linear material) and the strain E of the material."""
        Ht = H.swapaxes(0, 1)
        if self.linear:
            return None, 0.5 * (H + Ht)
        F = H.copy()
        for i in range(self.dim):
            F[i, i] += 1.0
        return F, 0.5 * (H + Ht + np.einsum("kiqe,kjqe->ijqe", H, H))

    def _barrier_hit(self, F) -> bool:
        return F is not None and self.material.barrier and np.any(_det(F) <= 0.0)

    def _element_tangent(self, F, CC, S):
        """K_e (E, n_loc·d, n_loc·d) from A_iJkL = F_iI ℂ_IJKL F_kK + δ_ik S_JL (F = I when
        None, no S term when None)."""
        if F is None:
            A = np.broadcast_to(CC, CC.shape[:4] + self._w.shape)
        else:
            FC = np.einsum("iI...,IJKL...->iJKL...", F, CC)
            A = np.einsum("iJKL...,kK...->iJkL...", FC, F)
        if S is not None:
            for i in range(self.dim):
                A[i, :, i] += S
        AG = np.einsum("iJkL...,bL...->Jibk...", A, self._G)  # (J, i, b, k, Q, E)
        # element-major from here: one batched matmul per element, contracting over the
        # quadrature points and J together, writes K_e contiguous as Pattern reads it
        n_el, n = self._G.shape[-1], self.element_dofs.shape[1]
        AG = np.ascontiguousarray(AG.transpose(5, 4, 0, 1, 2, 3)).reshape(n_el, -1, n * self.dim)
        Gw = np.ascontiguousarray((self._G * self._w).transpose(3, 0, 2, 1)).reshape(
            n_el, len(self._G), -1
        )
        return np.matmul(Gw, AG).reshape(n_el, n, n)

    def internal(self, q: np.ndarray, tangent: bool = True):
        """Strain energy W (J), internal force ∂W/∂q (N, (ndof,)) and element tangents
        ∂²W/∂q² (E, n_loc·d, n_loc·d) in N/m (None unless ``tangent``).

        Neo-Hookean bodies with an inverted element (det F ≤ 0) return W = inf and NaN forces.
        """
        if self.linear:
            f = self._K @ q
            return 0.5 * float(q @ f), f, self._Ke if tangent else None
        F, E = self._strain(self._displacement_gradient(q))
        if self._barrier_hit(F):
            Ke = np.full(self._Ke_shape(), np.nan) if tangent else None
            return np.inf, np.full(self.ndof, np.nan), Ke
        W, S, CC = self.material.response(E, self.plane, tangent)
        P = np.einsum("iIqe,IJqe->iJqe", F, S)
        fe = np.einsum("qe,iJqe,aJqe->eai", self._w, P, self._G)
        f = np.bincount(self.element_dofs.ravel(), fe.ravel(), minlength=self.ndof)
        Ke = self._element_tangent(F, CC, S) if tangent else None
        return float(np.sum(self._w * W)), f, Ke

    def inverted(self, q: np.ndarray) -> bool:
        """Whether q inverts an element (det F ≤ 0) of a body whose energy forbids it."""
        if self.linear or not self.material.barrier:
            return False
        return self._barrier_hit(self._strain(self._displacement_gradient(q))[0])

    def _Ke_shape(self):
        n = self.element_dofs.shape[1]
        return (self.n_elements, n, n)

    def energy(self, q: np.ndarray) -> float:
        """Strain energy W(q) in J (inf for an inverted Neo-Hookean element)."""
        if self.linear:
            return 0.5 * float(q @ (self._K @ q))
        F, E = self._strain(self._displacement_gradient(q))
        if self._barrier_hit(F):
            return np.inf
        W = self.material.response(E, self.plane, tangent=False)[0]
        return float(np.sum(self._w * W))

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

    # -- stress ------------------------------------------------------------------------------
    def stress(self, q: np.ndarray) -> np.ndarray:
        """Cauchy stress σ (Pa, tension positive) at the quadrature points, (E, Q, 3, 3).

        In 2D, σ₃₃ is the out-of-plane stress (zero in plane stress). The linear material gives
        σ = S (small strains).
        """
        return np.moveaxis(self._cauchy(q), (0, 1), (-2, -1)).swapaxes(0, 1)

    def _cauchy(self, q):
        F, E = self._strain(self._displacement_gradient(q))
        d = self.dim
        E3 = np.zeros((3, 3) + E.shape[2:])
        E3[:d, :d] = E
        F3 = np.zeros_like(E3)
        for i in range(3):
            F3[i, i] = 1.0
        if d == 2:
            E3[2, 2] = self.material.out_of_plane(E, self.plane)[0]
            F3[2, 2] = np.sqrt(1.0 + 2.0 * E3[2, 2])
        S = self.material.response3(E3, tangent=False)[1]
        if self.linear:
            return S
        F3[:d, :d] = F
        return np.einsum("iIqe,IJqe,jJqe->ijqe", F3, S, F3) / _det(F3)

    def cell_data(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Per-cell output: ``stress_von_mises`` (Pa), √(3/2 s:s) with s the deviator of σ,
        and ``pressure`` −tr σ/3 (Pa), both averaged over the cell."""
        sigma = self._cauchy(q)
        p = -(sigma[0, 0] + sigma[1, 1] + sigma[2, 2]) / 3.0
        s = sigma.copy()
        for i in range(3):
            s[i, i] += p
        vm = np.sqrt(1.5 * np.sum(s * s, axis=(0, 1)))
        w = self._w / self._w.sum(axis=0)
        return {"stress_von_mises": np.sum(w * vm, axis=0), "pressure": np.sum(w * p, axis=0)}

    # -- geometry and output -----------------------------------------------------------------
    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current node coordinates X + u (m), shape (n_nodes, d)."""
        return self.X + np.asarray(q).reshape(-1, self.dim)

    def nodal(self, x: np.ndarray) -> np.ndarray:
        """A dof vector viewed per node, (n_nodes, d)."""
        return np.asarray(x).reshape(-1, self.dim)

    def boundary_nodes(self) -> np.ndarray:
        """Nodes on the boundary (vertices and, for P2, the boundary edge/face nodes)."""
        return np.unique(self._basis.get_dofs(self.mesh.boundary_facets()).all())

    def contact_nodes(self, nodes=None) -> np.ndarray:
        """Validated node indices (the boundary nodes when ``nodes`` is None)."""
        if nodes is None:
            return self.boundary_nodes()
        return self._nodes(nodes)

    def node_translation_dofs(self, nodes) -> np.ndarray:
        """(len(nodes), d) local dof indices of the displacement of ``nodes``."""
        return self.dim * self._nodes(nodes)[:, None] + np.arange(self.dim)

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Positions x (m, d) of ``nodes``, their local dofs (m, d), ∂x/∂q (m, d, d) and
        ∂²x/∂q² (None: linear)."""
        dofs = self.dim * nodes[:, None] + np.arange(self.dim)
        x = self.X[nodes] + q[dofs]
        return x, dofs, np.repeat(np.eye(self.dim)[None], len(nodes), axis=0), None

    def boundary_facets(self) -> np.ndarray:
        """Boundary facets as rows of vertex node indices, numbered so that the normal points
        out of the body: 2D segments (a, b) with outward normal (t_y, −t_x), t = x_b − x_a (the
        boundary runs counter-clockwise); 3D triangles or quadrilaterals with outward normal by
        the right-hand rule. P2 nodes inside the facets are not listed."""
        return self._oriented_boundary()[1]

    def _oriented_boundary(self):
        """Indices of the boundary facets in the mesh and their outward-numbered vertices."""
        mesh = self.mesh
        bf = mesh.boundary_facets()
        facets = mesh.facets[:, bf].T.copy()
        P = mesh.p.T
        x = P[facets]
        inside = P[mesh.t[:, mesh.f2t[0, bf]]].mean(axis=0) - x.mean(axis=1)
        flip = np.einsum("fi,fi->f", _facet_normals(x), inside) > 0.0
        facets[flip] = facets[flip, ::-1]
        return bf, facets

    def contact_facets(self) -> np.ndarray:
        """The boundary as flat pieces for node-to-surface contact, numbered like
        :meth:`boundary_facets` (outward normal): 2D segments (n, 2), 3D triangles (n, 3).

        P2 facets are first split through their edge nodes (and the face node of a
        hexahedron's face): a segment into 2 segments, a triangle into 4 triangles, a
        quadrilateral into 4 quadrilaterals. Quadrilaterals (a, b, c, d) are then split along
        the diagonal a–c into (a, b, c) and (a, c, d).
        """
        bf, facets = self._oriented_boundary()
        if self.element == "P2":
            facets = self._split_quadratic(bf, facets)
        if facets.shape[1] == 4:
            facets = np.concatenate([facets[:, [0, 1, 2]], facets[:, [0, 2, 3]]])
        return np.ascontiguousarray(facets)

    def _split_quadratic(self, bf, facets):
        """Sub-facets of P2 boundary facets through their mid-edge and mid-face nodes."""
        mesh, b = self.mesh, self._basis
        n = mesh.nvertices
        if self.dim == 2:
            m = b.facet_dofs[0, bf]
            return np.concatenate([np.stack([facets[:, 0], m], 1), np.stack([m, facets[:, 1]], 1)])
        edges = np.sort(mesh.edges, axis=0)
        keys = edges[0].astype(np.int64) * n + edges[1]
        order = np.argsort(keys)

        def mid(i, j):
            a, c = facets[:, i], facets[:, j]
            k = np.minimum(a, c).astype(np.int64) * n + np.maximum(a, c)
            return b.edge_dofs[0, order[np.searchsorted(keys, k, sorter=order)]]

        if facets.shape[1] == 3:
            a, c, d = facets.T
            ab, bc, ca = mid(0, 1), mid(1, 2), mid(2, 0)
            parts = [(a, ab, ca), (ab, c, bc), (ca, bc, d), (ab, bc, ca)]
        else:
            a, c, d, e = facets.T
            ab, bc, cd, da = mid(0, 1), mid(1, 2), mid(2, 3), mid(3, 0)
            o = b.facet_dofs[0, bf]
            parts = [(a, ab, o, da), (ab, c, bc, o), (o, bc, d, cd), (da, o, cd, e)]
        return np.concatenate([np.stack(p, axis=1) for p in parts])

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """Nodal fields for output: ``displacement`` (m) and ``velocity`` (m/s), (n_nodes, d)."""
        return {"displacement": self.nodal(q), "velocity": self.nodal(v)}

    def cells(self) -> list[tuple[str, np.ndarray]]:
        """Cells for VTU output in meshio/VTK numbering: triangle, quad, tetra, hexahedron
        (P1) or triangle6, quad9, tetra10, hexahedron27 (P2), over the body's nodes."""
        t = self.mesh.t.T.copy()
        if self.cell == "hex":
            t = t[:, _HEX_TO_VTK]
        elif self.cell in ("tri", "tet"):
            # scikit-fem sorts simplex vertices; VTK wants positive orientation (signed volumes)
            P = self.mesh.p.T
            edges = P[t[:, 1:]] - P[t[:, :1]]
            flip = np.linalg.det(edges) < 0.0
            t[flip, 1], t[flip, 2] = t[flip, 2], t[flip, 1].copy()
        names = _ELEMENTS[self.cell]
        if self.element == "P1":
            return [(names[2], np.ascontiguousarray(t))]
        X, en = self.X, self._enodes
        extra = np.stack([X[t[:, list(c)]].mean(axis=1) for c in _VTK_P2_NODES[self.cell]], 1)
        dist = np.linalg.norm(extra[:, :, None, :] - X[en][:, None, :, :], axis=-1)
        pick = np.argmin(dist, axis=2)
        return [(names[3], np.hstack([t, np.take_along_axis(en, pick, axis=1)]))]


def _det(A: np.ndarray) -> np.ndarray:
    """Determinants of 2×2 or 3×3 matrices A (d, d, *points)."""
    if len(A) == 2:
        return A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    return (
        A[0, 0] * (A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1])
        - A[0, 1] * (A[1, 0] * A[2, 2] - A[1, 2] * A[2, 0])
        + A[0, 2] * (A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0])
    )


def _facet_normals(x: np.ndarray) -> np.ndarray:
    """Normals (F, d) of facets with vertex coordinates x (F, k, d), not normalised: segments
    (a, b) → (t_y, −t_x); triangles (b − a) × (c − a); quadrilaterals (c − a) × (d − b)."""
    if x.shape[2] == 2:
        t = x[:, 1] - x[:, 0]
        return np.stack([t[:, 1], -t[:, 0]], axis=1)
    if x.shape[1] == 3:
        return np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    return np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])


def _is_int(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _check_point(name: str, value, dim: int) -> np.ndarray:
    x = check_finite(name, value).ravel()
    if x.shape != (dim,):
        raise InputError(f"{name} must have {dim} components, got {x.shape[0]}")
    return x


def _grid_axes(lower, upper, divisions, dim):
    lo, hi = _check_point("lower", lower, dim), _check_point("upper", upper, dim)
    if np.any(hi <= lo):
        raise InputError(f"upper must exceed lower in every component, got {lower}, {upper}")
    try:
        per_axis = np.broadcast_to(np.asarray(divisions, dtype=object), (dim,))
    except ValueError:
        raise InputError(f"divisions must be one count or {dim}, got {divisions!r}") from None
    n = [check_count("divisions", k, 1, MAX_CELLS) for k in per_axis]
    if np.prod(n, dtype=float) > MAX_CELLS:
        raise InputError(f"divisions must give at most {MAX_CELLS} cells, got {divisions!r}")
    return [np.linspace(lo[i], hi[i], n[i] + 1) for i in range(dim)]
