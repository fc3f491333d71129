"""Mesh files read with meshio, with their named groups, and nodes that must be merged.

A file's cells of the body's dimension make the mesh; its gmsh physical groups (``gmsh:physical``
cell data named by ``field_data``, as gmsh and meshio write them) and meshio cell sets become the
mesh's named ``subdomains`` (groups of cells) and ``boundaries`` (groups of boundary facets), the
scikit-fem names a :class:`~fecontact.bodies.Solid` then looks up: ``body.nodes_of("top")``,
``body.fix("bottom")``, ``Contact(body, plane, nodes="top")``. Groups of gmsh points (and,
in 3D, of edges) name the nodes they hold: :func:`read_mesh_and_points` gives their
coordinates, which :meth:`Solid.from_file <fecontact.bodies.Solid.from_file>` turns into the
body's ``node_groups``.

Coincident nodes that no cell joins are two surfaces, not one: the mesh checks refuse them, and
:func:`merge_nodes` (or ``read_mesh(..., merge_nodes=True)``) merges them.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import numpy as np
import skfem

from ..errors import InputError, check_kind, check_positive
from .meshes import ELEMENTS, check_point, coincident_nodes

__all__ = ["group_nodes", "merge_nodes", "nodes_at", "read_mesh", "read_mesh_and_points"]

_VOLUME = {names[k]: cell for cell, names in ELEMENTS.items() for k in (2, 3)}
_DIM = {"tri": 2, "quad": 2, "tet": 3, "hex": 3}
# the dimension of meshio's cell kinds, by the name before the node count ("wedge15": wedge)
_KIND_DIM = {"vertex": 0, "line": 1, "triangle": 2, "quad": 2, "polygon": 2}
_KIND_DIM |= {k: 3 for k in ("tetra", "hexahedron", "wedge", "pyramid", "polyhedron")}
# the facet cells meshio names for each kind of cell: boundary groups are made of these
_FACETS = {
    "tri": ("line", "line3"),
    "quad": ("line", "line3"),
    "tet": ("triangle", "triangle6"),
    "hex": ("quad", "quad9"),
}


def read_mesh(path, scale: float = 1.0, offset=None, merge_nodes: bool = False):
    """A mesh file read with meshio (any format it knows: .msh, .vtu, .vtk, .xdmf, ...), its
    coordinates multiplied by ``scale`` and then shifted by ``offset`` (m, d components). The
    dimension comes from the cells: tetrahedra or hexahedra make a 3D mesh, else triangles or
    quadrilaterals a 2D one; other cells (gmsh geometry points, edges) are dropped, and so are
    the points no cell uses. Named groups become ``mesh.boundaries`` and ``mesh.subdomains``.

    ``merge_nodes`` merges coincident points (closer than 1e-8 of the diagonal of their bounding
    box) first: a mesh made of parts meshed apart, whose shared faces were not merged.
    """
    return read_mesh_and_points(path, scale, offset, merge_nodes)[0]


def read_mesh_and_points(path, scale: float = 1.0, offset=None, merge_nodes: bool = False):
    """(mesh, points) of a mesh file: the mesh of :func:`read_mesh`, and the groups of gmsh
    points (``vertex`` cells), in 3D of edges (``line``, ``line3`` cells), and meshio's point
    sets (an Abaqus NSET) as {name: coordinates (m, d) in m, scaled and shifted as the mesh}:
    a pinned corner, a loaded edge, which are neither facets nor cells of the body."""
    import meshio  # lazily: mesh I/O only when a file is read

    check_kind("path", path, (str, os.PathLike), "a mesh file's path")
    data = _read(Path(path))
    blocks = [(c.type, _integer_cells(c.data, c.type)) for c in data.cells]
    kind, volume = _volume_blocks(blocks, Path(path).name)
    cell = _VOLUME[kind]
    points, index = _used_points(data.points, volume, merge_nodes)
    _check_plane(points, _DIM[cell], Path(path).name, data.points)
    _check_thickness(points, kind, Path(path).name)
    groups = _groups(data, blocks, cell, _group_names(Path(path), data), Path(path).name)
    conn, cell_of = _unique_cells(index[np.concatenate([c for _, c in volume])])
    renumbered = meshio.Mesh(points, [(kind, conn)])
    scale = check_positive("scale", scale)
    mesh = _from_meshio(renumbered, cell).scaled(scale)
    shift = np.zeros(mesh.dim())
    if offset is not None:
        shift = check_point("offset", offset, mesh.dim())
        mesh = mesh.translated(shift)
    places = {
        name: _places(name, ids, index, points[:, : mesh.dim()]) * scale + shift
        for name, ids in _point_ids(data, groups, blocks).items()
    }  # scaled, then shifted, as scikit-fem does it to the mesh: the same coordinates
    return _named(mesh, groups, index, blocks, (kind, cell_of)), places


# odd 63-bit weights of a row hash (fixed: a file reads the same every time); 27 nodes at most
_ROW_WEIGHTS = np.random.default_rng(2026).integers(1, 2**62, size=27, dtype=np.int64) | 1


def _unique_cells(conn: np.ndarray):
    """(cells, cell_of): each cell of ``conn`` (m, k) once, in the order of their first
    listing, and each listed cell's index among them. MSH 2.2 lists a cell once per physical
    group holding it (a subdomain inside the body's group): read twice, its mass and stiffness
    were counted twice (the mesh checks refused the copies as overlapping cells)."""
    key = np.sort(conn, axis=1)
    # rows of distinct hashes are distinct: a file without copies costs one 1D sort (0.6 s
    # for 1e6 tetrahedra, against 2.6 s for the rows' sort below and 5.7 s for np.unique's),
    # and only a file with equal hashes goes on to the exact comparison
    hashed = np.sort(key @ _ROW_WEIGHTS[: key.shape[1]])  # (int64, wrapping)
    if not np.any(hashed[1:] == hashed[:-1]):
        return conn, np.arange(len(conn))
    order = np.lexsort(key.T[::-1])
    new = np.ones(len(conn), dtype=bool)
    new[1:] = np.any(key[order[1:]] != key[order[:-1]], axis=1)
    group = np.cumsum(new) - 1  # of each row in sorted order: its cell
    first = np.full(group[-1] + 1, len(conn))
    np.minimum.at(first, group, order)
    same = np.empty(len(conn), dtype=int)
    same[order] = group
    rank = np.argsort(np.argsort(first))  # the rank of each cell's first listing
    return conn[np.sort(first)], rank[same]


def _point_ids(data, groups, blocks) -> dict[str, np.ndarray]:
    """{name: the file's point indices} of the groups of points and edges, and of the point
    sets whose names no other group takes."""
    ids = {
        name: np.concatenate([blocks[b][1][rows].ravel() for b, rows in members])
        for name, members in groups["points"].items()
    }
    taken = set(ids) | set(groups["boundaries"]) | set(groups["subdomains"])
    for name, rows in (data.point_sets or {}).items():
        if not name.startswith("gmsh:") and name not in taken:
            ids[name] = np.asarray(rows, dtype=int).ravel()
    return ids


def _places(name: str, ids, index, points) -> np.ndarray:
    """The coordinates, as read, of the file's points ``ids`` of a group."""
    ids = np.unique(ids)
    if ids.size and (ids.min() < 0 or ids.max() >= len(index)):
        raise InputError(f"point group {name!r} refers to points the file does not have")
    if np.any(index[ids] < 0):
        raise InputError(f"point group {name!r} has points that no cell of the body uses")
    return points[index[ids]]


def _volume_blocks(blocks, name: str):
    """The kind of the body's cells (the highest dimension found) and the blocks of them."""
    _check_cell_kinds(blocks, name)
    volume = [(kind, conn) for kind, conn in blocks if kind in _VOLUME]
    if not volume:
        raise InputError(
            f"{name} has no {', '.join(_VOLUME)} cells "
            f"(found {', '.join(kind for kind, _ in blocks) or 'none'})"
        )
    kind = max((kind for kind, _ in volume), key=lambda k: _DIM[_VOLUME[k]])
    mixed = {k for k, _ in volume if k != kind and _DIM[_VOLUME[k]] == _DIM[_VOLUME[kind]]}
    if mixed:
        raise InputError(f"{name} mixes {kind} cells with {', '.join(sorted(mixed))}")
    return kind, [(k, conn) for k, conn in volume if k == kind]


def _check_cell_kinds(blocks, name: str) -> None:
    """``InputError`` for cells of a kind a Solid cannot take (prisms, pyramids, serendipity
    quad8 and hexahedron20, cubic cells, polygons) of the body's dimension or above: left out,
    they would leave holes in the body (boundary-layer prisms under tetrahedra, say)."""
    dims = {kind: _KIND_DIM.get(re.match(r"[a-z]*", kind).group(), 0) for kind, _ in blocks}
    top = max((dims[kind] for kind, _ in blocks if kind in _VOLUME), default=2)
    other = sorted({kind for kind, _ in blocks if dims[kind] >= top and kind not in _VOLUME})
    if other:
        raise InputError(
            f"{name} has {', '.join(other)} cells, which a Solid does not take (it takes "
            f"{', '.join(_VOLUME)}): mesh with those alone (in gmsh, no prisms or pyramids, "
            "Mesh.SecondOrderIncomplete = 0)"
        )


# gmsh writes only the elements of physical groups (unless Mesh.SaveAll = 1): a 3D model whose
# groups are surfaces alone gives a file of triangles, which would read as a 2D body
_NO_VOLUME = (
    "a 3D mesh saved without its volume? (gmsh saves only the elements of physical groups: "
    "add one of the volume, or set Mesh.SaveAll = 1)"
)


def _check_plane(points: np.ndarray, dim: int, name: str, every: np.ndarray) -> None:
    """``InputError`` for a 2D mesh (triangles, quadrilaterals) whose points do not share one
    z, to 1e-8 of their bounding box's diagonal: the body is planar, in x and y, and its z
    would be dropped (a surface in space flattened, a mesh drawn in the xz plane collapsed);
    or whose file holds points, unused, off that plane (``every``: all the file's points)."""
    if dim != 2 or points.shape[1] < 3:
        return
    z = points[:, 2]
    size = float(np.linalg.norm(np.ptp(points, axis=0)))
    if np.ptp(z) > 1e-8 * size:
        raise InputError(
            f"{name}: a 2D mesh (triangles, quadrilaterals) lies in the xy plane, but its "
            f"points' z spans [{z.min():g}, {z.max():g}] m: a surface in space, a mesh "
            f"drawn in another plane (draw it in x and y), or {_NO_VOLUME}"
        )
    off = np.abs(np.asarray(every, dtype=float)[:, 2] - z[0])
    if off.max() > 1e-8 * size:
        raise InputError(
            f"{name}: its cells are triangles or quadrilaterals in the plane z = {z[0]:g} m, "
            f"but other points of the file lie {off.max():g} m from it: {_NO_VOLUME}"
        )


def _check_thickness(points: np.ndarray, kind: str, name: str) -> None:
    """``InputError`` for 3D cells whose points share one x, y or z (to 1e-8 of the mesh's
    size): a flat body, whose every cell is degenerate (the mesh check would name cell 0)."""
    if _DIM[_VOLUME[kind]] != 3:
        return
    span = np.ptp(points, axis=0)
    flat = np.flatnonzero(span <= 1e-8 * float(np.linalg.norm(span)))
    if flat.size:
        raise InputError(
            f"{name}: its {kind} cells all lie in the plane {'xyz'[flat[0]]} = "
            f"{points[0, flat[0]]:g} m: a 3D body needs a thickness (a planar body is meshed "
            "with triangles or quadrilaterals in the xy plane)"
        )


def merge_nodes(mesh, tol: float | None = None):
    """The linear (P1) scikit-fem ``mesh`` with its coincident vertices merged: vertices closer
    than ``tol`` (m; default 1e-8 of the
    diagonal of the bounding box) become one, the first of them.
    Quadratic meshes are merged when their file is read: ``read_mesh(..., merge_nodes=True)``."""
    if mesh.doflocs.shape[1] != mesh.nvertices or not isinstance(mesh, skfem.Mesh):
        raise InputError("merge_nodes takes a linear scikit-fem mesh; merge quadratic ones with "
                         "read_mesh(..., merge_nodes=True)")  # fmt: skip
    first = _merged(mesh.p.T, tol)
    used = np.unique(first[mesh.t])
    index = np.full(mesh.p.shape[1], -1)
    index[used] = np.arange(len(used))
    return type(mesh)(mesh.p[:, used], index[first[mesh.t]])


def group_nodes(mesh, basis, name: str, node_groups=None) -> np.ndarray:
    """The nodes (dofs of the scalar ``basis``) of the group ``name``: those listed in
    ``node_groups`` ({name: nodes}), else those on the mesh's facets for a boundary
    (``mesh.boundaries``), those of its cells for a subdomain (``mesh.subdomains``)."""
    node_groups = node_groups or {}
    if name in node_groups:
        return np.asarray(node_groups[name], dtype=int)
    boundaries, subdomains = mesh.boundaries or {}, mesh.subdomains or {}
    if name in boundaries:
        return np.unique(basis.get_dofs(boundaries[name]).all())
    if name in subdomains:
        return np.unique(basis.element_dofs[:, subdomains[name]])
    names = sorted(boundaries) + sorted(subdomains) + sorted(node_groups)
    raise InputError(
        f"nodes: the mesh has no group named {name!r} (its groups: "
        f"{', '.join(map(repr, names)) or 'none'})"
    )


def nodes_at(X: np.ndarray, places: np.ndarray, name: str) -> np.ndarray:
    """The nodes, among those at ``X`` (n, d), at the coordinates ``places`` (m, d), sorted;
    ``InputError`` naming the group ``name`` where no node is within 1e-9 of the bounding
    box's diagonal (coordinates of the same file, scaled alike: equal to round-off)."""
    from scipy.spatial import cKDTree

    size = float(np.linalg.norm(np.ptp(X, axis=0)))
    gap, nodes = cKDTree(X).query(places)
    if np.any(gap > 1e-9 * size):
        far = places[np.argmax(gap)]
        raise InputError(f"group {name!r}: no node at ({', '.join(f'{c:g}' for c in far)})")
    return np.unique(nodes)


def _read(path: Path):
    import meshio

    known = meshio.extension_to_filetypes
    suffix = path.suffix.lower()
    if suffix not in known and "".join(path.suffixes[-2:]).lower() not in known:
        raise InputError(
            f"unknown mesh file format {suffix or '(no extension)'!r} of {path.name}; "
            "meshio reads " + ", ".join(sorted(known))
        )
    if not path.is_file():
        raise InputError(f"mesh file not found: {path}")
    if path.stat().st_size == 0:
        raise InputError(f"cannot read mesh file {path.name}: the file is empty")
    said = io.StringIO()  # meshio prints why a reader failed, then exits with status 1
    try:
        with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
            # .msh is also an ANSYS extension; meshio would try (and print) that reader first
            return meshio.read(path, file_format="gmsh" if suffix == ".msh" else None)
    except (Exception, SystemExit) as err:  # meshio raises many types, even SystemExit
        lines = [line for line in said.getvalue().splitlines() if line.strip()]
        text = lines[-1].removeprefix("Error: ") if isinstance(err, SystemExit) and lines else ""
        why = (text or str(err) or type(err).__name__).splitlines()[0][:100]
        raise InputError(f"cannot read mesh file {path.name}: {why}") from None


def _integer_cells(conn, kind: str) -> np.ndarray:
    """Connectivity as int64, whatever integer type the file held. meshio reads a VTU's UInt64
    connectivity (what it writes for pygmsh meshes) as float64: whole numbers below 2⁵³ are
    exact in it, so they convert back exactly."""
    conn = np.asarray(conn)
    if conn.dtype.kind in "iu":
        if conn.size and (conn.min() < 0 or conn.max() > np.iinfo(np.int64).max):
            raise InputError(f"{kind} connectivity holds node numbers out of range")
        return conn.astype(np.int64)
    whole = np.isfinite(conn) & (conn == np.round(conn)) & (conn >= 0) & (conn < 2.0**53)
    if conn.dtype.kind != "f" or not whole.all():
        raise InputError(f"{kind} connectivity must hold node numbers, got {conn.dtype} values")
    return conn.astype(np.int64)


def _used_points(points, volume, merge: bool):
    """The points the cells use, and each file point's index among them (−1: unused); with
    ``merge``, coincident points first map to the first of them."""
    first = _merged(points, None) if merge else None
    conn = np.concatenate([c.ravel() for _, c in volume])
    if conn.max() >= len(points):
        raise InputError(f"cells refer to point {int(conn.max())}; the file has {len(points)}")
    used = np.unique(conn if first is None else first[conn])
    index = np.full(len(points), -1)
    index[used] = np.arange(len(used))
    if first is not None:
        index = index[first]
    return np.asarray(points[used], dtype=float), index


def _merged(points, tol) -> np.ndarray:
    """For each point, the first point within ``tol`` of it, transitively (itself if none)."""
    import scipy.sparse as sp

    points = np.asarray(points, dtype=float)
    _, pairs = coincident_nodes(points, tol)
    n = len(points)
    graph = sp.coo_matrix((np.ones(len(pairs)), pairs.T), shape=(n, n))
    _, label = sp.csgraph.connected_components(graph, directed=False)
    first = np.full(label.max() + 1, n)
    np.minimum.at(first, label, np.arange(n))
    return first[label]


def _from_meshio(data, cell: str):
    from skfem.io.meshio import from_meshio

    try:
        return from_meshio(data)
    except (ValueError, IndexError) as err:  # cells over fewer than their points, say
        raise InputError(f"cannot build a {cell} mesh from the file's cells: {err}") from None


def _groups(data, blocks, cell: str, names, file: str) -> dict[str, dict[str, list]]:
    """Named groups of the file's cells: {"boundaries"|"subdomains"|"points": {name:
    [(block, rows)]}}, from gmsh physical tags (named by ``names``: (tag, dimension, name))
    and meshio cell sets. ``InputError`` for a name given to cells of two of these kinds
    (facets and cells, say: gmsh lets one name a group of each dimension): the name would mean
    either, and a boundary's nodes, a contact's, are not a subdomain's."""
    tagged = _tagged(data, [kind for kind, _ in blocks], names)
    volume = {k for k, c in _VOLUME.items() if c == cell}
    lines = ("line", "line3") if _DIM[cell] == 3 else ()
    sorts = {"boundaries": set(_FACETS[cell]), "subdomains": volume, "points": {"vertex", *lines}}
    groups = {key: {} for key in sorts}
    for name, members in tagged.items():
        kinds = {blocks[b][0] for b, rows in members if len(rows)}
        key = next((key for key, allowed in sorts.items() if kinds and kinds <= allowed), None)
        if key is not None:
            groups[key][name] = members
        elif kinds:
            _refuse_mixed(file, name, kinds, sorts)
    return groups


def _refuse_mixed(file: str, name: str, kinds: set, sorts: dict) -> None:
    """``InputError`` for the group ``name`` whose cells (of ``kinds``) are of no one kind of
    ``sorts``, saying which kinds a group can be made of."""
    said = {"boundaries": "facets", "subdomains": "cells of the body", "points": "points"}
    kinds_of = "; ".join(f"{said[key]}: {', '.join(sorted(k))}" for key, k in sorts.items())
    raise InputError(
        f"{file}: group {name!r} holds {', '.join(sorted(kinds))} cells, which are not of one "
        f"kind of group ({kinds_of}): give each kind its own name (in gmsh, one name per "
        "physical group's dimension)"
    )


def _tagged(data, kinds: list[str], names) -> dict[str, list]:
    """{name: [(block, rows)]} of the gmsh physical groups and the meshio cell sets."""
    tagged = _physical_groups(data, kinds, names)
    for name, rows in (data.cell_sets or {}).items():
        if not name.startswith("gmsh:") and name not in tagged:
            tagged[name] = [(b, np.asarray(r, int)) for b, r in _present(rows)]
    return tagged


def _present(rows):
    return [(b, r) for b, r in enumerate(rows) if r is not None]


def _physical_groups(data, kinds: list[str], named) -> dict[str, list]:
    """{name: [(block, rows)]} of the gmsh physical tags of the blocks of cells of ``kinds``.
    A tag is a name in its dimension only: gmsh numbers each dimension's groups apart
    (``Physical Line(1)`` and ``Physical Surface(1)``), and ``named`` gives each name its
    (tag, dimension) (−1: any). Unnamed: "physical<tag>", or "physical<tag>_<dim>d" where two
    dimensions use the tag."""
    by_tag = {tag: name for tag, dim, name in named if dim < 0}  # given without a dimension
    names = {(tag, dim): name for tag, dim, name in named}
    blocks = data.cell_data.get("gmsh:physical", [None] * len(kinds))
    dims = [_KIND_DIM.get(re.match(r"[a-z]*", kind).group(), -1) for kind in kinds]
    shared = _shared_tags(dims, blocks)
    tagged: dict[str, list] = {}
    for b, (dim, tags) in enumerate(zip(dims, blocks, strict=True)):
        for tag in _tags(tags):
            unnamed = f"physical{tag}_{dim}d" if tag in shared else f"physical{tag}"
            name = names.get((tag, dim), by_tag.get(tag, unnamed))
            tagged.setdefault(name, []).append((b, np.flatnonzero(tags == tag)))
    return tagged


def _shared_tags(dims: list[int], blocks) -> set[int]:
    """The physical tags that cells of more than one dimension carry."""
    used = {(t, d) for d, tags in zip(dims, blocks, strict=True) for t in _tags(tags)}
    tags = [t for t, _ in used]
    return {t for t in tags if tags.count(t) > 1}


def _tags(tags) -> list[int]:
    """The distinct physical tags of a block (none when it has no tags); 0 is none: what
    gmsh writes for the cells of no physical group when it saves them all (Mesh.SaveAll)."""
    return [] if tags is None else [int(t) for t in np.unique(tags) if t != 0]


def _group_names(path: Path, data) -> list[tuple[int, int, str]]:
    """(tag, dimension, name) of the gmsh physical groups: a .msh file's ``$PhysicalNames``
    as written, else meshio's ``field_data`` (dimension −1 where it gives none). meshio keys
    ``field_data`` by name, so of two groups of one name in two dimensions (gmsh allows it) it
    keeps the last, and the other group went on unnamed, as "physical<tag>"."""
    if path.suffix.lower() == ".msh":
        return _physical_names(path)
    fields = [(k, v) for k, v in (data.field_data or {}).items() if np.size(v) >= 1]
    return [(int(v[0]), int(v[1]) if np.size(v) > 1 else -1, k) for k, v in fields]


# a line of $PhysicalNames: dimension, tag, "name" (which may hold spaces)
_NAME_LINE = re.compile(rb'\s*(\d+)\s+(\d+)\s+"(.*)"\s*$')


def _physical_names(path: Path) -> list[tuple[int, int, str]]:
    """The ``$PhysicalNames`` of a gmsh file (MSH 2.2 or 4.1, ASCII or binary: the section is
    text in both, and comes before the binary sections, where the scan stops)."""
    names, inside = [], False
    with open(path, "rb") as f:
        for line in f:
            if line.startswith((b"$Entities", b"$Nodes", b"$Elements", b"$EndPhysicalNames")):
                break
            found = _NAME_LINE.match(line) if inside else None
            if found:
                dim, tag, name = found.groups()
                names.append((int(tag), int(dim), name.decode("utf-8", "replace")))
            inside = inside or line.startswith(b"$PhysicalNames")
    return names


def _named(mesh, groups, index, blocks, volume):
    """``mesh`` with the file's groups as scikit-fem boundaries (facet indices) and subdomains
    (cell indices: ``volume`` = (kind, cell_of), the cells of that kind numbered in file order,
    as meshio joins them, are the mesh's cells ``cell_of``)."""
    if not groups["boundaries"] and not groups["subdomains"]:
        return mesh
    volume_kind, cell_of = volume
    start = np.cumsum([0] + [len(c) if k == volume_kind else 0 for k, c in blocks])
    subdomains = {
        name: np.unique(cell_of[np.concatenate([start[b] + rows for b, rows in members])])
        for name, members in groups["subdomains"].items()
    }
    corners = mesh.facets.shape[0]
    boundaries = {}
    for name, members in groups["boundaries"].items():
        conn = index[np.concatenate([blocks[b][1][rows, :corners] for b, rows in members])]
        if np.any(conn < 0):
            raise InputError(f"boundary {name!r} has points that no cell of the body uses")
        boundaries[name] = _facet_indices(mesh, conn, name)
    return mesh.with_boundaries(boundaries).with_subdomains(subdomains)


def _facet_indices(mesh, conn: np.ndarray, name: str) -> np.ndarray:
    """Indices among the ``mesh``'s facets (k, F) of the facet cells ``conn`` (m, k), whatever
    their vertex order. Where some are not faces of the cells because the file holds copies
    of nodes (parts meshed apart: a facet on one copy, the cells on the other), the error says
    so, as the mesh checks would have."""
    facets = mesh.facets
    both = np.concatenate([np.sort(facets.T, axis=1), np.sort(conn, axis=1)])
    _, ids = np.unique(both, axis=0, return_inverse=True)
    ids = ids.ravel()
    of_id = np.full(ids.max() + 1, -1)
    of_id[ids[: facets.shape[1]]] = np.arange(facets.shape[1])
    found = of_id[ids[facets.shape[1] :]]
    if np.any(found < 0):
        copies = len(coincident_nodes(mesh.p.T)[1])
        why = (
            f": the mesh has {copies} pair(s) of coincident nodes (parts meshed apart, not "
            "merged): read it with merge_nodes=True"
            if copies
            else ""
        )
        raise InputError(f"boundary {name!r} has facets that are not faces of the cells{why}")
    return np.unique(found)
