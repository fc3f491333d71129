"""Mesh files and the checks a mesh passes before any work: unmerged coincident nodes, nodes in
no element, connectivity of any integer type, gmsh physical groups as named node sets."""

import meshio
import numpy as np
import pytest
import skfem
from skfem.io.meshio import to_meshio

from fecontact import InputError, LinearElastic, Model, Solid
from fecontact.bodies.mesh_files import merge_nodes, read_mesh
from fecontact.contact import Contact, Plane
from fecontact.time import simulate

MAT = LinearElastic(E=1e6, nu=0.3, rho=1e3)


def two_unmerged_squares():
    """Two unit squares meshed apart side by side: the edge x = 1 holds 5 pairs of copies."""
    a = skfem.MeshTri.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 1, 5))
    p = np.hstack([a.p, a.p + [[1.0], [0.0]]])
    return skfem.MeshTri(p, np.hstack([a.t, a.t + a.p.shape[1]]))


def test_unmerged_coincident_nodes_are_refused_with_count_and_place():
    with pytest.raises(InputError, match=r"10 nodes coincide .* first at \(1, 0\)") as err:
        Solid(two_unmerged_squares(), MAT)
    assert "merge_nodes" in str(err.value) and "\n" not in str(err.value)


def test_merged_squares_are_one_connected_body():
    mesh = merge_nodes(two_unmerged_squares())
    body = Solid(mesh, MAT)
    one = Solid.rectangle([0, 0], [2, 1], (8, 4), MAT)
    assert body.n_nodes == one.n_nodes == 45
    # one outline of 24 segments (no inner boundary along x = 1) and the same area
    assert len(body.boundary_facets()) == 24 and body.volume == pytest.approx(2.0, rel=1e-14)


def test_merge_nodes_when_a_file_is_read(tmp_path):
    mesh = two_unmerged_squares()
    path = tmp_path / "two.vtu"
    meshio.write(path, meshio.Mesh(mesh.p.T, [("triangle", mesh.t.T)]))
    with pytest.raises(InputError, match="10 nodes coincide"):
        Solid.from_file(path, MAT)
    assert Solid.from_file(path, MAT, merge_nodes=True).n_nodes == 45


def test_a_node_in_no_element_is_named_not_taken_for_a_curved_cell():
    # the loose point is the last one: scikit-fem then counts one vertex fewer than points
    p = np.array([[0.0, 1.0, 0.0, 5.0], [0.0, 0.0, 1.0, 5.0]])
    with pytest.raises(InputError, match=r"1 node\(s\) belong to no element.*at \(5, 5\)"):
        Solid(skfem.MeshTri(p, np.array([[0, 1, 2]]).T), MAT)


INTEGER_TYPES = [np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32, np.int64, np.uint64]


@pytest.mark.parametrize("dtype", INTEGER_TYPES, ids=lambda t: t.__name__)
def test_connectivity_of_every_integer_type_loads(tmp_path, dtype):
    # meshio writes pygmsh meshes with UInt64 connectivity and reads it back as float64; one
    # cube of 6 tetrahedra: meshio writes the offsets (up to 24) in the connectivity's type
    mesh = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 2)] * 3)
    path = tmp_path / "box.vtu"
    meshio.write(path, meshio.Mesh(mesh.p.T, [("tetra", mesh.t.T.astype(dtype))]))
    again = read_mesh(path)
    np.testing.assert_array_equal(again.p, mesh.p)
    cells = {tuple(c) for c in np.sort(mesh.t, axis=0).T}  # (scikit-fem may reorder vertices)
    assert {tuple(c) for c in np.sort(again.t, axis=0).T} == cells


def write_msh41(path, points, groups):
    """A gmsh ASCII 4.1 file as gmsh writes it: one entity per physical group, ``groups`` =
    [(name, dim, cells (m, k), gmsh element type)], the first the body's cells."""
    dim = groups[0][1]
    counts = [sum(g[1] == d for g in groups) for d in range(4)]
    box = " ".join(map(str, [*points.min(axis=0), *points.max(axis=0)]))
    n, total = len(points), sum(len(g[2]) for g in groups)
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(groups))]
    lines += [f'{d} {i + 1} "{name}"' for i, (name, d, _, _) in enumerate(groups)]
    lines += ["$EndPhysicalNames", "$Entities", " ".join(map(str, counts))]
    ids = [i for d in range(4) for i, g in enumerate(groups) if g[1] == d]
    # a point entity is its point and physical tag; the others a box, a tag and no boundary
    lines += [
        f"{i + 1} {' '.join(map(repr, map(float, points[groups[i][2][0, 0]])))} 1 {i + 1}"
        if groups[i][1] == 0
        else f"{i + 1} {box} 1 {i + 1} 0"
        for i in ids
    ]
    lines += ["$EndEntities", "$Nodes", f"1 {n} 1 {n}", f"{dim} 1 0 {n}"]
    lines += [str(i + 1) for i in range(n)] + [" ".join(map(repr, map(float, x))) for x in points]
    lines += ["$EndNodes", "$Elements", f"{len(groups)} {total} 1 {total}"]
    k = 1
    for i, (_, d, cells, kind) in enumerate(groups):
        lines.append(f"{d} {i + 1} {kind} {len(cells)}")
        lines += [" ".join(map(str, [k + j, *(c + 1)])) for j, c in enumerate(cells)]
        k += len(cells)
    path.write_text("\n".join([*lines, "$EndElements", ""]))


def sides(mesh, axis, value):
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    return mesh.facets[:, bf[np.abs(mid[axis] - value) < 1e-9]].T


@pytest.fixture
def block_msh(tmp_path):
    """A 0.2 x 0.1 m block whose bottom, top and cells are gmsh physical groups."""
    m = skfem.MeshTri.init_tensor(np.linspace(0, 0.2, 9), np.linspace(0.01, 0.11, 5))
    points = np.column_stack([m.p.T, np.zeros(m.p.shape[1])])
    groups = [("block", 2, m.t.T, 2), ("bottom", 1, sides(m, 1, 0.01), 1)]
    groups.append(("top", 1, sides(m, 1, 0.11), 1))
    write_msh41(tmp_path / "block.msh", points, groups)
    return tmp_path / "block.msh"


def test_physical_groups_are_named_boundaries_and_subdomains(block_msh):
    mesh = read_mesh(block_msh)
    assert sorted(mesh.boundaries) == ["bottom", "top"] and list(mesh.subdomains) == ["block"]
    body = Solid(mesh, MAT)
    np.testing.assert_array_equal(body.nodes_of("bottom"), body.nodes_where(lambda x: x[1] < 0.011))
    np.testing.assert_array_equal(body.nodes_of("top"), body.nodes_where(lambda x: x[1] > 0.109))
    np.testing.assert_array_equal(body.nodes_of("block"), np.arange(body.n_nodes))
    with pytest.raises(InputError, match=r"no group named 'side' \(its groups: 'bottom', 'top'"):
        body.fix("side")


def test_a_contact_surface_chosen_by_group_name(block_msh):
    """The block falls on a plane touching with its bottom group alone: the same run, to the
    bit, as with the same nodes chosen by their coordinates."""

    def run(nodes):
        body = Solid.from_file(block_msh, MAT)
        floor = Plane([0.0, 0.0], [0.0, 1.0])
        model = Model([body], [Contact(body, floor, nodes=nodes(body))], gravity=(0.0, -9.81))
        v0 = model.translation(body, (0.0, -1.0))
        return [s.q.copy() for s in simulate(model, 2e-3, 0.03, v0=v0)], model

    by_name, model = run(lambda b: "bottom")
    by_place, _ = run(lambda b: b.nodes_where(lambda x: x[1] < 0.011))
    np.testing.assert_array_equal(np.array(by_name), np.array(by_place))
    assert len(model.contacts.pairs[0].nodes) == 9
    # it hit the floor and came back up: the contact acted
    lowest = [np.min(model.bodies[0].positions(q)[:, 1]) for q in by_name]
    assert min(lowest) > -1e-9 and lowest[-1] > min(lowest)


def test_a_3d_boundary_group_fixes_its_nodes(tmp_path):
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 3)] * 3)
    groups = [("cube", 3, m.t.T, 4), ("base", 2, sides(m, 2, 0.0), 2)]
    write_msh41(tmp_path / "cube.msh", m.p.T, groups)
    body = Solid.from_file(tmp_path / "cube.msh", MAT).fix("base")
    base = body.nodes_where(lambda x: x[2] < 1e-9)
    assert len(base) == 9 and body.fixed == {int(i) * 3 + k for i in base for k in range(3)}


def test_a_p2_boundary_group_holds_its_edge_nodes(tmp_path):
    """A gmsh 2.2 file of triangle6 cells whose bottom is a physical group of line3 cells."""
    m = skfem.MeshTri2.from_mesh(skfem.MeshTri.init_tensor(np.linspace(0, 1, 4), [0.0, 0.5, 1.0]))
    bf = m.boundary_facets()
    bottom = bf[m.doflocs[1, m.facets[:, bf]].max(axis=0) < 1e-9]
    line3 = np.column_stack([m.facets[:, bottom].T, m.nvertices + bottom])  # edge node last
    triangle6 = to_meshio(m).cells[0].data
    tags = [np.full(len(triangle6), 1), np.full(len(line3), 2)]
    mesh = meshio.Mesh(
        m.doflocs.T,
        [("triangle6", triangle6), ("line3", line3)],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"body": np.array([1, 2]), "bottom": np.array([2, 1])},
    )
    mesh.write(tmp_path / "p2.msh", file_format="gmsh22")
    body = Solid.from_file(tmp_path / "p2.msh", MAT, element="P2")
    nodes = body.nodes_of("bottom")
    np.testing.assert_array_equal(nodes, body.nodes_where(lambda x: x[1] < 1e-9))
    assert len(nodes) == 7  # 4 vertices and 3 edge nodes


@pytest.mark.parametrize("z", ["curved", "xz plane"])
def test_a_2d_mesh_off_the_xy_plane_is_refused_by_its_z(tmp_path, z):
    # (before: z dropped, a curved surface flattened and a mesh in the xz plane collapsed)
    mesh = skfem.MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    x, y = mesh.p
    points = np.c_[x, y, x * y] if z == "curved" else np.c_[x, 0 * x, y]
    path = tmp_path / "surface.msh"
    meshio.write(path, meshio.Mesh(points, [("triangle", mesh.t.T)]), file_format="gmsh22")
    with pytest.raises(InputError, match=r"surface.msh: a 2D mesh .* z spans \[0, 1\] m"):
        read_mesh(path)
    points[:, 1:] = np.c_[y, np.full_like(x, 0.3)]  # the same mesh in the plane z = 0.3
    meshio.write(path, meshio.Mesh(points, [("triangle", mesh.t.T)]), file_format="gmsh22")
    np.testing.assert_array_equal(read_mesh(path).p, mesh.p)


def test_groups_of_points_and_3d_edges_name_their_nodes(tmp_path):
    """gmsh point and edge physical groups (a corner to pin, an edge to hold) in a 4.1 file
    of the body scaled from mm and shifted: nodes found by place, listed with the others."""
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 10, 3)] * 3)
    corner = np.flatnonzero(np.all(m.p.T == [10, 0, 0], axis=1))[:, None]
    edge = m.edges[:, np.all(m.p[1:, m.edges].max(axis=1) < 1e-9, axis=0)].T  # y = z = 0
    groups = [("cube", 3, m.t.T, 4), ("corner", 0, corner, 15), ("edge", 1, edge, 1)]
    write_msh41(tmp_path / "cube.msh", m.p.T, groups)
    body = Solid.from_file(tmp_path / "cube.msh", MAT, scale=1e-3, offset=[0, 0, 1])
    np.testing.assert_array_equal(
        body.nodes_of("corner"),
        body.nodes_where(
            lambda x: (np.abs(x[0] - 0.01) < 1e-12) & (x[1] < 1e-12) & (np.abs(x[2] - 1) < 1e-12)
        ),
    )
    along = body.nodes_where(lambda x: (x[1] < 1e-12) & (np.abs(x[2] - 1) < 1e-12))
    np.testing.assert_array_equal(body.nodes_of("edge"), along)
    assert len(along) == 3 and body.fix("corner").fixed == {
        3 * body.nodes_of("corner")[0] + k for k in range(3)
    }
    with pytest.raises(
        InputError, match=r"no group named 'tip' \(its groups: 'cube', 'corner', 'edge'"
    ):
        body.nodes_of("tip")


def test_a_p2_edge_group_holds_its_middle_nodes_and_a_2d_point_group_its_node(tmp_path):
    m = skfem.MeshTet2.from_mesh(skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 2)] * 3))
    on_x = np.all(m.doflocs[1:, m.edges].max(axis=1) < 1e-9, axis=0)  # the edge y = z = 0
    line3 = np.column_stack([m.edges[:, on_x].T, m.nvertices + np.flatnonzero(on_x)])
    tetra10 = to_meshio(m).cells[0].data
    tags = [np.full(len(tetra10), 1), np.full(len(line3), 2)]
    mesh = meshio.Mesh(
        m.doflocs.T,
        [("tetra10", tetra10), ("line3", line3)],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"body": np.array([1, 3]), "edge": np.array([2, 1])},
    )
    mesh.write(tmp_path / "p2.msh", file_format="gmsh22", binary=True)
    body = Solid.from_file(tmp_path / "p2.msh", MAT, element="P2")
    along = body.nodes_where(lambda x: (x[1] < 1e-9) & (x[2] < 1e-9))
    assert len(along) == 3 and np.array_equal(body.nodes_of("edge"), along)
    # 2D: a point group (gmsh writes a vertex cell); lines stay boundaries there
    square = skfem.MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    points = np.column_stack([square.p.T, np.zeros(9)])
    tags = [np.full(8, 1), np.array([2])]
    mesh = meshio.Mesh(
        points,
        [("triangle", square.t.T), ("vertex", np.array([[8]]))],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"body": np.array([1, 2]), "tip": np.array([2, 0])},
    )
    mesh.write(tmp_path / "square.msh", file_format="gmsh22")
    body = Solid.from_file(tmp_path / "square.msh", MAT)
    assert body.nodes_of("tip").tolist() == [8] and body.X[8].tolist() == [1.0, 1.0]


@pytest.mark.parametrize("kind", ["wedge", "quad8"])
def test_cells_a_solid_cannot_take_are_refused_not_dropped(tmp_path, kind):
    """Prisms under tetrahedra (a gmsh boundary layer), serendipity quad8 beside triangles:
    left out, the body had a hole (the tetrahedron alone, 1/6 of the volume, was the body)."""
    if kind == "wedge":
        points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1.0]])
        cells = [("tetra", np.array([[0, 1, 2, 3]])), ("wedge", np.array([[0, 1, 2, 3, 4, 5]]))]
    else:
        x = [0, 1, 1, 0, 2, 2, 1.5, 2, 1.5, 1]
        points = np.column_stack([x, [0, 0, 1, 1, 0, 1, 0, 0.5, 1, 0.5], np.zeros(10)])
        quad8 = np.array([[1, 4, 5, 2, 6, 7, 8, 9]])
        cells = [("triangle", np.array([[0, 1, 2], [0, 2, 3]])), ("quad8", quad8)]
    meshio.write(tmp_path / "mixed.msh", meshio.Mesh(points, cells), file_format="gmsh22")
    with pytest.raises(InputError, match=f"mixed.msh has {kind} cells, which a Solid does not"):
        Solid.from_file(tmp_path / "mixed.msh", MAT)


@pytest.mark.parametrize("faces", [(0.0,), (0.0, 1.0)])
def test_a_3d_mesh_saved_without_its_volume_is_not_read_as_2d(tmp_path, faces):
    """gmsh saves only the elements of physical groups: a cube whose groups are its bottom
    (and top) faces gives triangles alone, and the bottom alone would read as a 2D square."""
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 3)] * 3)
    triangles = np.vstack([sides(m, 2, z) for z in faces])
    tags = [np.ones(len(triangles), int)]
    data = meshio.Mesh(
        m.p.T,
        [("triangle", triangles)],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"faces": np.array([1, 2])},
    )
    data.write(tmp_path / "cube.msh", file_format="gmsh22")
    with pytest.raises(InputError, match=r"cube.msh: .* 3D mesh saved without its volume"):
        Solid.from_file(tmp_path / "cube.msh", MAT)


def test_an_abaqus_node_set_names_its_nodes(tmp_path):
    """meshio's point sets (Abaqus *NSET) are groups of nodes as gmsh points are."""
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 3)] * 3)
    base = np.flatnonzero(m.p[2] < 1e-9)
    sets = {"BASE": base, "TIP": np.array([26])}
    meshio.write(tmp_path / "cube.inp", meshio.Mesh(m.p.T, [("tetra", m.t.T)], point_sets=sets))
    body = Solid.from_file(tmp_path / "cube.inp", MAT)
    np.testing.assert_array_equal(body.nodes_of("BASE"), body.nodes_where(lambda x: x[2] < 1e-9))
    assert body.X[body.nodes_of("TIP")].tolist() == [[1.0, 1.0, 1.0]]


def test_physical_tags_are_numbered_per_dimension_as_gmsh_numbers_them(tmp_path):
    """``Physical Line(1) = ...; Physical Surface(1) = ...;`` in a .geo file: two groups of
    tag 1, told apart by their dimension (one name took both, mixed, and both were lost)."""
    m = skfem.MeshTri.init_tensor(np.linspace(0, 0.2, 5), np.linspace(0.0, 0.1, 3))
    bottom = sides(m, 1, 0.0)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "2"]
    lines += ['1 1 "bottom"', '2 1 "block"', "$EndPhysicalNames", "$Nodes", str(m.p.shape[1])]
    lines += [f"{i + 1} {x:.17g} {y:.17g} 0" for i, (x, y) in enumerate(m.p.T)]
    lines += ["$EndNodes", "$Elements", str(len(bottom) + m.t.shape[1])]
    cells = [(1, c) for c in bottom] + [(2, c) for c in m.t.T]  # gmsh types: line, triangle
    lines += [f"{k + 1} {t} 2 1 1 {' '.join(map(str, c + 1))}" for k, (t, c) in enumerate(cells)]
    (tmp_path / "plate.msh").write_text("\n".join([*lines, "$EndElements", ""]))
    body = Solid.from_file(tmp_path / "plate.msh", MAT)
    assert list(body.mesh.boundaries) == ["bottom"] and list(body.mesh.subdomains) == ["block"]
    np.testing.assert_array_equal(body.nodes_of("bottom"), body.nodes_where(lambda x: x[1] < 1e-9))


def test_unnamed_physical_tags_of_two_dimensions_are_two_groups(tmp_path):
    m = skfem.MeshTri.init_tensor(np.linspace(0, 0.2, 5), np.linspace(0.0, 0.1, 3))
    bottom = sides(m, 1, 0.0)
    tags = [np.ones(len(bottom), int), np.ones(m.t.shape[1], int), np.zeros(1, int)]
    data = meshio.Mesh(
        np.column_stack([m.p.T, np.zeros(m.p.shape[1])]),
        [("line", bottom), ("triangle", m.t.T), ("vertex", np.array([[0]]))],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
    )
    data.write(tmp_path / "plate.msh", file_format="gmsh22")
    body = Solid.from_file(tmp_path / "plate.msh", MAT)
    # tag 0, a cell of no group that gmsh saves with Mesh.SaveAll, names no group
    assert list(body.mesh.boundaries) == ["physical1_1d"] and body.node_groups == {}
    assert list(body.mesh.subdomains) == ["physical1_2d"]


def plate_msh(path, physical_names, tags=(1, 1)):
    """A 0.2 × 0.1 m plate of triangles in MSH 2.2 ASCII, written as gmsh writes it: its
    bottom lines carry the physical tag ``tags[0]``, its triangles ``tags[1]``."""
    m = skfem.MeshTri.init_tensor(np.linspace(0, 0.2, 5), np.linspace(0.0, 0.1, 3))
    bottom = sides(m, 1, 0.0)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames"]
    lines += [str(len(physical_names)), *physical_names, "$EndPhysicalNames"]
    lines += ["$Nodes", str(m.p.shape[1])]
    lines += [f"{i + 1} {x:.17g} {y:.17g} 0" for i, (x, y) in enumerate(m.p.T)]
    lines += ["$EndNodes", "$Elements", str(len(bottom) + m.t.shape[1])]
    cells = [(1, tags[0], c) for c in bottom] + [(2, tags[1], c) for c in m.t.T]
    lines += [
        f"{k + 1} {t} 2 {tag} 1 {' '.join(map(str, c + 1))}" for k, (t, tag, c) in enumerate(cells)
    ]
    path.write_text("\n".join([*lines, "$EndElements", ""]))
    return path


def test_a_name_given_to_groups_of_two_dimensions_is_refused_by_name(tmp_path):
    """gmsh lets one name a physical group of each dimension: ``Physical Curve("plate")`` and
    ``Physical Surface("plate")``. meshio keys the names by name, so one of the two groups
    went on unnamed ("physical2") and "plate" named the other alone; were both kept, the name
    would mean a boundary or a subdomain, whose nodes differ. Refused, naming the group."""
    names = ['1 1 "plate"', '2 2 "plate"']
    path = plate_msh(tmp_path / "plate.msh", names, tags=(1, 2))
    with pytest.raises(InputError, match=r"plate.msh: group 'plate' holds line, triangle cells"):
        Solid.from_file(path, MAT)
    # one name per dimension, with a space in it: both groups as they are named
    path = plate_msh(tmp_path / "plate.msh", ['1 1 "bottom edge"', '2 2 "plate"'], tags=(1, 2))
    body = Solid.from_file(path, MAT)
    assert list(body.mesh.boundaries) == ["bottom edge"] and list(body.mesh.subdomains) == ["plate"]


def test_physical_names_of_a_binary_file_are_read(tmp_path):
    """A binary MSH 2.2 file: ``$PhysicalNames`` is text before the binary sections."""
    m = skfem.MeshTri.init_tensor(np.linspace(0, 0.2, 5), np.linspace(0.0, 0.1, 3))
    bottom = sides(m, 1, 0.0)
    tags = [np.full(len(bottom), 3), np.full(m.t.shape[1], 7)]
    data = meshio.Mesh(
        np.column_stack([m.p.T, np.zeros(m.p.shape[1])]),
        [("line", bottom), ("triangle", m.t.T)],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"bottom": np.array([3, 1]), "plate": np.array([7, 2])},
    )
    data.write(tmp_path / "plate.msh", file_format="gmsh22", binary=True)
    body = Solid.from_file(tmp_path / "plate.msh", MAT)
    assert list(body.mesh.boundaries) == ["bottom"] and list(body.mesh.subdomains) == ["plate"]
    np.testing.assert_array_equal(body.nodes_of("bottom"), body.nodes_where(lambda x: x[1] < 1e-9))


def test_a_boundary_on_copies_of_nodes_says_merge_nodes(tmp_path):
    """Two squares meshed apart with a bottom line group: the group's facet joining them lies
    on one copy of a shared node, the cells on the other. Its error named the facets alone."""
    m = two_unmerged_squares()
    p = np.column_stack([m.p.T, np.zeros(m.p.shape[1])])
    first_bottom = sides(skfem.MeshTri(m.p[:, :25], m.t[:, :32]), 1, 0.0)
    at = [int(np.flatnonzero(np.hypot(*(m.p - [[x], [0.0]])) < 1e-12)[0]) for x in (1.0, 1.25)]
    across = np.array([at])  # from the left square's (1, 0) to the right's (1.25, 0)
    bottom = np.vstack([first_bottom, across])
    tags = [np.ones(len(bottom), int), np.full(m.t.shape[1], 2)]
    meshio.Mesh(
        p,
        [("line", bottom), ("triangle", m.t.T)],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"bottom": np.array([1, 1]), "squares": np.array([2, 2])},
    ).write(tmp_path / "squares.msh", file_format="gmsh22")
    with pytest.raises(InputError, match=r"5 pair\(s\) of coincident nodes .* merge_nodes=True"):
        Solid.from_file(tmp_path / "squares.msh", MAT)
    body = Solid.from_file(tmp_path / "squares.msh", MAT, merge_nodes=True)
    assert body.volume == pytest.approx(2.0, rel=1e-14)
    assert len(body.nodes_of("bottom")) == 6


@pytest.mark.parametrize("path", [None, 3, ["a.msh"]])
def test_a_path_of_the_wrong_kind_is_named(path):
    # (a TypeError from pathlib before)
    with pytest.raises(InputError, match=r"^path must be a mesh file's path, got"):
        Solid.from_file(path, MAT)


def test_cells_listed_once_per_physical_group_are_one_cell(tmp_path):
    """MSH 2.2 lists a cell once per physical group that holds it: with ``Physical
    Surface("plate")`` and ``Physical Surface("left")`` over the same surface, the left half's
    triangles come twice. The copies were refused as overlapping cells ("element 1 ... is
    inverted"); read as one, the body is the plate and "left" its left half."""
    m = skfem.MeshTri.init_tensor(np.linspace(0, 0.2, 5), np.linspace(0.0, 0.1, 3))
    left = m.t.T[m.p[0, m.t].mean(axis=0) < 0.1]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "2"]
    lines += ['2 1 "plate"', '2 2 "left"', "$EndPhysicalNames", "$Nodes", str(m.p.shape[1])]
    lines += [f"{i + 1} {x:.17g} {y:.17g} 0" for i, (x, y) in enumerate(m.p.T)]
    cells = [(1, c) for c in m.t.T] + [(2, c) for c in left]
    lines += ["$EndNodes", "$Elements", str(len(cells))]
    lines += [f"{k + 1} 2 2 {t} 1 {' '.join(map(str, c + 1))}" for k, (t, c) in enumerate(cells)]
    (tmp_path / "plate.msh").write_text("\n".join([*lines, "$EndElements", ""]))
    body = Solid.from_file(tmp_path / "plate.msh", MAT)
    assert body.n_elements == m.t.shape[1] and body.volume == pytest.approx(0.02, rel=1e-14)
    assert body.mass == pytest.approx(1e3 * 0.02, rel=1e-14)
    plate, half = body.mesh.subdomains["plate"], body.mesh.subdomains["left"]
    assert len(plate) == m.t.shape[1] and len(half) == len(left)
    centres = body.mesh.p[:, body.mesh.t[:, half]].mean(axis=1)
    assert np.all(centres[0] < 0.1)


def test_a_flat_3d_mesh_is_refused_as_flat(tmp_path):
    """Tetrahedra all in the plane z = 0.5: the mesh check named "element 0 ... degenerate"."""
    m = skfem.MeshTri.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    points = np.column_stack([m.p.T, np.full(m.p.shape[1], 0.5)])
    tets = np.column_stack([m.t.T, np.roll(m.t.T, 1, axis=0)[:, :1]])
    meshio.write(tmp_path / "flat.msh", meshio.Mesh(points, [("tetra", tets)]), "gmsh22")
    with pytest.raises(InputError, match=r"flat.msh: its tetra cells all lie in the plane z = 0.5"):
        Solid.from_file(tmp_path / "flat.msh", MAT)
