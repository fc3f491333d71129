"""Meshes of solid bodies: generators, the checks a mesh must pass, and its oriented
boundary (files are read in :mod:`fecontact.bodies.mesh_files`).

Cell kinds are scikit-fem's reference domains: triangles and quadrilaterals (2D),
tetrahedra and hexahedra (3D), with linear or quadratic (P2) geometry.
"""

from __future__ import annotations

import logging
from contextlib import contextmanager
from dataclasses import replace

import numpy as np
import skfem

from ..errors import MIN_MAGNITUDE, InputError, check_count, check_finite, check_positive

__all__ = [
    "ELEMENTS",
    "MAX_CELLS",
    "ball_mesh",
    "box_mesh",
    "cell_kind",
    "check_cells",
    "disk_mesh",
    "facet_normals",
    "graded_ball_mesh",
    "mesh_bases",
    "min_edge_length",
    "oriented_boundary",
    "coincident_nodes",
    "rectangle_mesh",
    "split_quadratic",
]

ELEMENTS = {
    "tri": (skfem.ElementTriP1, skfem.ElementTriP2, "triangle", "triangle6"),
    "quad": (skfem.ElementQuad1, skfem.ElementQuad2, "quad", "quad9"),
    "tet": (skfem.ElementTetP1, skfem.ElementTetP2, "tetra", "tetra10"),
    "hex": (skfem.ElementHex1, skfem.ElementHex2, "hexahedron", "hexahedron27"),
}
"""Scalar Lagrange elements (P1, P2) of each reference cell, and the cell's meshio names."""
# one point for P1 simplices, whose deformation gradient is constant over the cell
_MIDPOINT = {
    "tri": (np.full((2, 1), 1.0 / 3.0), np.array([0.5])),
    "tet": (np.full((3, 1), 0.25), np.array([1.0 / 6.0])),
}
MAX_CELLS = 2**21  # grid bodies: a mesh of about 1e6 nodes is the most a direct solver takes
_REFDOMS = {"RefTri": "tri", "RefQuad": "quad", "RefTet": "tet", "RefHex": "hex"}


def cell_kind(mesh) -> str:
    """The cell kind ("tri", "quad", "tet", "hex") of a scikit-fem mesh, after the checks every
    body's mesh must pass: a known cell, not empty, finite coordinates, a size (bounding box
    diagonal) of at least ``MIN_MAGNITUDE``, every node in a cell,
    no coincident vertices left unmerged."""
    if not isinstance(mesh, skfem.Mesh):
        # a file's path or a meshio.Mesh is the common slip: say where those go
        hint = "; read a mesh file with Solid.from_file(path, material)"
        raise InputError(f"mesh must be a scikit-fem Mesh, got {type(mesh).__name__}{hint}")
    cell = _REFDOMS.get(mesh.elem.refdom.__name__)
    if cell is None:
        raise InputError(
            f"mesh must have triangles, quadrilaterals, tetrahedra or hexahedra, got "
            f"{type(mesh).__name__}"
        )
    if mesh.t.shape[1] == 0 or mesh.p.shape[1] == 0:
        raise InputError("mesh is empty: it has no elements")
    check_finite("mesh coordinates", mesh.p)
    extent = float(np.linalg.norm(np.ptp(mesh.p, axis=1)))
    if extent < MIN_MAGNITUDE:
        # (else the coincident-node check below would blame unmerged nodes)
        raise InputError(
            f"mesh size (the diagonal of its bounding box) must be at least "
            f"{MIN_MAGNITUDE:g} m, got {extent:g} m"
        )
    _check_loose_nodes(mesh, cell)
    _check_coincident(mesh)
    return cell


def _check_loose_nodes(mesh, cell: str) -> None:
    # a linear mesh's nodes are its vertices; a quadratic one's vertices come first (scikit-fem)
    linear = mesh.elem is ELEMENTS[cell][0]
    n = mesh.doflocs.shape[1] if linear else mesh.nvertices
    unused = np.bincount(mesh.t.ravel(), minlength=n) == 0
    if np.any(unused):
        i = int(np.argmax(unused))
        raise InputError(
            f"mesh: {int(unused.sum())} node(s) belong to no element, the first is vertex {i} "
            f"at {_point(mesh.p[:, i])} (mesh.remove_unused_nodes() drops such points)"
        )


def _check_coincident(mesh) -> None:
    # unmerged copies of a node leave the cells on either side unjoined, and so each copy on
    # the boundary: checking the boundary vertices finds every one
    nodes = mesh.boundary_nodes()
    _, pairs = coincident_nodes(mesh.p[:, nodes].T)
    if len(pairs):
        # two vertices of one cell that coincide make a degenerate cell: check_cells names it
        pairs = pairs[~_share_a_cell(mesh.t, nodes[pairs])]
    if len(pairs):
        copies = np.unique(pairs)
        raise InputError(
            f"mesh: {len(copies)} nodes coincide with another node that no element joins them "
            f"to, the first at {_point(mesh.p[:, nodes[copies[0]]])}: parts of the body are not "
            "connected there; merge them with fecontact.bodies.mesh_files.merge_nodes(mesh) "
            "or Solid.from_file(..., merge_nodes=True)"
        )


def _share_a_cell(t: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """Whether the two vertices of each pair (p, 2) belong to one cell of ``t`` (k, E)."""
    import scipy.sparse as sp

    cells = np.broadcast_to(np.arange(t.shape[1]), t.shape).ravel()
    incidence = sp.csr_matrix((np.ones(t.size), (t.ravel(), cells)), (t.max() + 1, t.shape[1]))
    return (
        np.asarray(incidence[pairs[:, 0]].multiply(incidence[pairs[:, 1]]).sum(axis=1)).ravel() > 0
    )


def coincident_nodes(points: np.ndarray, tol: float | None = None):
    """The tolerance (m) and the pairs (p, 2) of ``points`` (n, d) closer than it: ``tol``, by
    default 1e-8 of the diagonal of the points' bounding box (exact copies, and copies written
    with round-off)."""
    from scipy.spatial import cKDTree

    points = np.asarray(points, dtype=float)
    if tol is None:
        tol = 1e-8 * float(np.linalg.norm(np.ptp(points, axis=0)))
    pairs = cKDTree(points).query_pairs(tol, output_type="ndarray")
    return tol, pairs.reshape(-1, 2)


def _point(x) -> str:
    return "(" + ", ".join(f"{float(c):.6g}" for c in x) + ")"


def disk_mesh(center, radius: float, refinements: int):
    """Disk of ``radius`` (m) at ``center`` (2-vector, m), triangles refined ``refinements``
    times (4^refinements × 8 elements; at most 9: 2^21 elements)."""
    c = check_point("center", center, 2)
    r = check_positive("radius", radius)
    m = skfem.MeshTri.init_circle(check_count("refinements", refinements, 0, 9))
    return m.scaled(r).translated(c)


@contextmanager
def _quiet_refinement():
    """scikit-fem's adaptive refinement builds its arrays in Fortran order and logs each copy
    to C order as a warning (beyond 1000 cells): a detail of its own, not of the user's mesh,
    which printed through a quiet run."""
    log = logging.getLogger("skfem.mesh.mesh")
    level = log.level
    log.setLevel(logging.ERROR)
    try:
        yield
    finally:
        log.setLevel(level)


def ball_mesh(center, radius: float, refinements: int, quadratic: bool = False):
    """Ball of ``radius`` (m) at ``center`` (3-vector, m), tetrahedra refined ``refinements``
    times (8^refinements × 8 elements; at most 6: 2^21 elements), boundary vertices on the
    sphere; ``quadratic`` cells (isoparametric) put the boundary's edge nodes on it too."""
    c = check_point("center", center, 3)
    r = check_positive("radius", radius)
    kind = skfem.MeshTet2 if quadratic else skfem.MeshTet
    return kind.init_ball(check_count("refinements", refinements, 0, 6)).scaled(r).translated(c)


def graded_ball_mesh(
    center, radius: float, spacing: float, toward, grading: float = 0.5, base: int = 3,
    quadratic: bool = False,
):  # fmt: skip
    """Ball of ``radius`` (m) at ``center`` (3-vector, m) whose tetrahedra grow from ``spacing``
    (m) at the point ``toward`` (3-vector, m; where the contact will be) by ``grading`` times
    the distance from it: scikit-fem's ``init_ball(base)``, each tetrahedron bisected
    (conforming adaptive bisection) until its longest edge is below spacing + grading × its
    centroid's distance from ``toward``; each round's new boundary vertices are moved radially
    onto the sphere, as ``init_ball`` places its own. ``quadratic`` cells (isoparametric) put
    the boundary's edge nodes on the sphere too. Raises ``InputError`` if a projection onto
    the sphere would invert a cell (spacing too coarse for the curvature)."""
    c = check_point("center", center, 3)
    r, h = check_positive("radius", radius), check_positive("spacing", spacing)
    target = check_point("toward", toward, 3)
    grading = check_positive("grading", grading, allow_zero=True)
    mesh = skfem.MeshTet.init_ball(check_count("base", base, 0, 6)).scaled(r).translated(c)
    while True:
        p = mesh.p[:, mesh.t]
        edges = [np.linalg.norm(p[:, i] - p[:, j], axis=0) for i, j in _TET_EDGES]
        distance = np.linalg.norm(p.mean(axis=1) - target[:, None], axis=0)
        marked = np.flatnonzero(np.max(edges, axis=0) > h + grading * distance)
        if marked.size == 0:
            break
        with _quiet_refinement():
            mesh = mesh.refined(marked)
        before = np.sign(_volumes(mesh.p, mesh.t))
        mesh = skfem.MeshTet(_on_sphere(mesh.p, mesh.boundary_nodes(), c, r), mesh.t)
        # the projection moves a vertex by about Δx²/(8R): no cell may turn inside out
        if np.any(np.sign(_volumes(mesh.p, mesh.t)) != before):
            raise InputError(f"spacing = {h:g} m: projecting the boundary inverted a cell")
    if not quadratic:
        return mesh
    curved = skfem.MeshTet2.from_mesh(mesh)
    nodes = curved.dofs.get_facet_dofs(curved.boundary_facets()).flatten()
    return replace(curved, doflocs=_on_sphere(curved.doflocs, nodes, c, r))


_TET_EDGES = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]


def _on_sphere(points: np.ndarray, nodes: np.ndarray, center, radius: float) -> np.ndarray:
    """``points`` (3, n) with ``nodes`` moved radially onto the sphere (``center``, ``radius``)."""
    x = points.copy()
    d = x[:, nodes] - center[:, None]
    x[:, nodes] = center[:, None] + radius * d / np.linalg.norm(d, axis=0)
    return x


def _volumes(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Signed volumes of the tetrahedra (m³; the sign is the vertex order's orientation)."""
    a, b, c = (p[:, t[i]] - p[:, t[0]] for i in (1, 2, 3))
    return np.einsum("ij,ij->j", np.cross(a, b, axis=0), c) / 6.0


def rectangle_mesh(lower, upper, divisions, cell: str = "triangle"):
    """Rectangle between corners ``lower`` and ``upper`` (m) with ``divisions`` = n or
    (n_x, n_y) cells per side; ``cell`` "triangle" (two per square) or "quad"."""
    axes = _grid_axes(lower, upper, divisions, 2)
    kinds = {"triangle": skfem.MeshTri, "quad": skfem.MeshQuad}
    if cell not in kinds:
        raise InputError(f"cell must be 'triangle' or 'quad', got {cell!r}")
    return kinds[cell].init_tensor(*axes)


def box_mesh(lower, upper, divisions, cell: str = "tetra"):
    """Box between corners ``lower`` and ``upper`` (m) with ``divisions`` = n or
    (n_x, n_y, n_z) cells per side; ``cell`` "tetra" (six per cube) or "hexahedron"."""
    axes = _grid_axes(lower, upper, divisions, 3)
    kinds = {"tetra": skfem.MeshTet, "hexahedron": skfem.MeshHex}
    if cell not in kinds:
        raise InputError(f"cell must be 'tetra' or 'hexahedron', got {cell!r}")
    return kinds[cell].init_tensor(*axes)


def mesh_bases(mesh, cell: str, element: str):
    """scikit-fem bases of the scalar Lagrange ``element`` ("P1", "P2") on the mesh: one for
    the stiffness (one-point rule on P1 simplices) and one for the mass (exact rule)."""
    order = 1 if element == "P1" else 2
    scalar = ELEMENTS[cell][order - 1]()
    quadrature = {"quadrature": _MIDPOINT[cell]} if order == 1 and cell in _MIDPOINT else {}
    # a degenerate cell makes scikit-fem divide by zero; check_cells then reports it
    with np.errstate(divide="ignore", invalid="ignore"):
        try:
            stiffness = skfem.Basis(mesh, scalar, intorder=2 * order, **quadrature)
            mass = skfem.Basis(mesh, scalar, intorder=2 * order)
        except Exception as err:  # scikit-fem's plain Exception for a degenerate map
            raise InputError(
                f"mesh: an element is degenerate or folded (scikit-fem: {err})"
            ) from None
    return stiffness, mass


def check_cells(mesh, basis, cell: str) -> None:
    """Reject degenerate, folded and inverted cells: the Jacobian determinant of each cell's
    map must keep one sign (at the quadrature points and, for quadrilaterals and hexahedra,
    the corners), and two cells sharing a facet must lie on either side of it."""
    dim = mesh.dim()
    corners = mesh.elem.refdom.p if cell in ("quad", "hex") else np.zeros((dim, 0))
    det = basis.mapping.detDF(np.hstack([basis.X, corners]))
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
    f2t = mesh.f2t
    inner = np.flatnonzero(f2t[1] >= 0)
    if inner.size == 0:
        return
    P = mesh.p.T
    fx = P[mesh.facets[:, inner].T]  # (F, facet vertex, d)
    n = facet_normals(fx)
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


def oriented_boundary(mesh):
    """Indices of the boundary facets in the mesh and their vertices numbered so that the
    normal (:func:`facet_normals`) points out of the body."""
    bf = mesh.boundary_facets()
    facets = mesh.facets[:, bf].T.copy()
    P = mesh.p.T
    x = P[facets]
    inside = P[mesh.t[:, mesh.f2t[0, bf]]].mean(axis=0) - x.mean(axis=1)
    flip = np.einsum("fi,fi->f", facet_normals(x), inside) > 0.0
    facets[flip] = facets[flip, ::-1]
    return bf, facets


def split_quadratic(mesh, basis, bf, facets):
    """Sub-facets of P2 boundary facets ``facets`` (mesh facets ``bf``) through their mid-edge
    and mid-face nodes: a segment into 2 segments, a triangle into 4 triangles, a
    quadrilateral into 4 quadrilaterals, numbered like the facet."""
    n = mesh.nvertices
    if mesh.dim() == 2:
        m = basis.facet_dofs[0, bf]
        return np.concatenate([np.stack([facets[:, 0], m], 1), np.stack([m, facets[:, 1]], 1)])
    edges = np.sort(mesh.edges, axis=0)
    keys = edges[0].astype(np.int64) * n + edges[1]
    order = np.argsort(keys)

    def mid(i, j):
        a, c = facets[:, i], facets[:, j]
        k = np.minimum(a, c).astype(np.int64) * n + np.maximum(a, c)
        return basis.edge_dofs[0, order[np.searchsorted(keys, k, sorter=order)]]

    if facets.shape[1] == 3:
        a, c, d = facets.T
        ab, bc, ca = mid(0, 1), mid(1, 2), mid(2, 0)
        parts = [(a, ab, ca), (ab, c, bc), (ca, bc, d), (ab, bc, ca)]
    else:
        a, c, d, e = facets.T
        ab, bc, cd, da = mid(0, 1), mid(1, 2), mid(2, 3), mid(3, 0)
        o = basis.facet_dofs[0, bf]
        parts = [(a, ab, o, da), (ab, c, bc, o), (o, bc, d, cd), (da, o, cd, e)]
    return np.concatenate([np.stack(p, axis=1) for p in parts])


def facet_normals(x: np.ndarray) -> np.ndarray:
    """Normals (F, d) of facets with vertex coordinates x (F, k, d), not normalised: segments
    (a, b) → (t_y, −t_x); triangles (b − a) × (c − a); quadrilaterals (c − a) × (d − b)."""
    if x.shape[2] == 2:
        t = x[:, 1] - x[:, 0]
        return np.stack([t[:, 1], -t[:, 0]], axis=1)
    if x.shape[1] == 3:
        return np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    return np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])


def min_edge_length(mesh) -> float:
    """Shortest edge (m) between the vertices of the mesh's cells."""
    edges = mesh.facets if mesh.dim() == 2 else mesh.edges
    return float(np.min(np.linalg.norm(np.diff(mesh.p[:, edges], axis=1)[:, 0], axis=0)))


def check_point(name: str, value, dim: int) -> np.ndarray:
    """A finite point of ``dim`` components (m)."""
    x = check_finite(name, value).ravel()
    if x.shape != (dim,):
        raise InputError(f"{name} must have {dim} components, got {x.shape[0]}")
    return x


def _grid_axes(lower, upper, divisions, dim):
    lo, hi = check_point("lower", lower, dim), check_point("upper", upper, dim)
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
