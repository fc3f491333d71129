"""Solid: exact tangents, patch tests, rigid motions, mass, mesh files and input rules."""

import importlib.util
from pathlib import Path

import meshio
import numpy as np
import pytest
import scipy.sparse as sp
import skfem
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

from fecontact import InputError
from fecontact.bodies.materials import LinearElastic, NeoHookean, StVenantKirchhoff
from fecontact.bodies.solid import Solid

MESHES = Path(__file__).resolve().parents[1] / "meshes"
YOUNG, NU, RHO = 5.0e6, 0.3, 1100.0
MATERIALS = {
    "linear": LinearElastic(E=YOUNG, nu=NU, rho=RHO),
    "svk": StVenantKirchhoff(E=YOUNG, nu=NU, rho=RHO),
    "neo-hookean": NeoHookean(E=YOUNG, nu=NU, rho=RHO),
}
# (cell, plane): 2D plane strain and plane stress on triangles and quads, 3D tets and hexes
SETTINGS = [
    ("triangle", "strain"),
    ("triangle", "stress"),
    ("quad", "strain"),
    ("quad", "stress"),
    ("tetra", None),
    ("hexahedron", None),
]


def small_solid(material, cell, plane, element="P1", divisions=None):
    if plane is None:
        return Solid.box(
            [0.0, 0.0, 0.0], [0.2, 0.1, 0.15], divisions or 1, material, cell=cell, element=element
        )
    return Solid.rectangle(
        [0.0, 0.0],
        [0.2, 0.1],
        divisions or (2, 1),
        material,
        cell=cell,
        element=element,
        plane=plane,
        thickness=0.01,
    )


def rotation(d, angle):
    c, s = np.cos(angle), np.sin(angle)
    R = np.eye(d)
    if d == 2:
        return np.array([[c, -s], [s, c]])
    axis = np.array([1.0, 2.0, 2.0]) / 3.0  # rotation about a skew axis (Rodrigues)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return R + s * K + (1 - c) * K @ K


def deformed_state(body, seed, rotate=True):
    """Displacement of a moderate random deformation, rotated by 30° when ``rotate``."""
    rng = np.random.default_rng(seed)
    X = body.X
    x = X + 0.03 * body.characteristic_length * rng.normal(size=X.shape)
    if rotate:
        x = x @ rotation(body.dim, np.pi / 6).T
    return (x - X).ravel()


def global_tangent(body, q):
    _, _, Ke = body.internal(q)
    rows = np.broadcast_to(body.element_dofs[:, :, None], Ke.shape).ravel()
    cols = np.broadcast_to(body.element_dofs[:, None, :], Ke.shape).ravel()
    return sp.coo_matrix((Ke.ravel(), (rows, cols)), shape=(body.ndof,) * 2).toarray()


def central_differences(fn, q, h):
    cols = []
    for j in range(len(q)):
        e = np.zeros_like(q)
        e[j] = h
        cols.append((fn(q + e) - fn(q - e)) / (2.0 * h))
    return np.array(cols).T


# -- exact derivatives -------------------------------------------------------------------------


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("cell,plane", SETTINGS)
@pytest.mark.parametrize("name", MATERIALS)
def test_tangent_matches_central_differences_of_internal_force(name, cell, plane, element):
    body = small_solid(MATERIALS[name], cell, plane, element)
    q = deformed_state(body, seed=7, rotate=name != "linear")
    K = global_tangent(body, q)
    h = 1e-6 * body.characteristic_length
    K_fd = central_differences(lambda x: body.internal(x, tangent=False)[1], q, h)
    assert np.max(np.abs(K - K_fd)) < 1e-6 * np.max(np.abs(K))
    assert np.allclose(K, K.T, rtol=0, atol=1e-12 * np.max(np.abs(K)))


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("cell,plane", SETTINGS)
@pytest.mark.parametrize("name", MATERIALS)
def test_internal_force_matches_central_differences_of_energy(name, cell, plane, element):
    body = small_solid(MATERIALS[name], cell, plane, element)
    q = deformed_state(body, seed=11, rotate=name != "linear")
    W, f, _ = body.internal(q, tangent=False)
    assert W == pytest.approx(body.energy(q), rel=1e-12)
    h = 1e-6 * body.characteristic_length
    f_fd = central_differences(lambda x: np.array([body.energy(x)]), q, h)[0]
    assert np.max(np.abs(f - f_fd)) < 1e-6 * np.max(np.abs(f))


# -- patch tests and rigid motions -----------------------------------------------------------


def distorted(cell, dim, element="P1"):
    """A 3×3(×3) mesh of the unit square/cube with interior vertices moved by up to 12 % of
    the spacing: elements are no longer regular, so only consistency gives exact answers."""
    n = np.linspace(0.0, 1.0, 4)
    kinds = {"triangle": skfem.MeshTri, "quad": skfem.MeshQuad}
    kinds.update({"tetra": skfem.MeshTet, "hexahedron": skfem.MeshHex})
    mesh = kinds[cell].init_tensor(*[n] * dim)
    p = mesh.p.copy()
    inner = np.all((p > 1e-9) & (p < 1 - 1e-9), axis=0)
    p[:, inner] += 0.04 * np.random.default_rng(3).uniform(-1, 1, size=(dim, inner.sum()))
    return type(mesh)(p, mesh.t)


PATCH_CELLS = [("triangle", 2), ("quad", 2), ("tetra", 3), ("hexahedron", 3)]


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("cell,dim", PATCH_CELLS)
@pytest.mark.parametrize("name", MATERIALS)
def test_patch_test_homogeneous_deformation(name, cell, dim, element):
    """u = A X + b gives one stress everywhere and no force on interior nodes. The linear
    material at small strain; the nonlinear ones at 10 % strain, where it holds as exactly."""
    plane = "stress" if dim == 2 else "strain"
    mesh = distorted(cell, dim)
    body = Solid(mesh, MATERIALS[name], element=element, **({"plane": plane} if dim == 2 else {}))
    rng = np.random.default_rng(5)
    size = 1e-4 if name == "linear" else 0.1
    A = size * rng.uniform(-1, 1, size=(dim, dim))
    q = (body.X @ A.T + size * rng.uniform(-1, 1, size=dim)).ravel()
    sigma = body.stress(q)
    assert np.allclose(sigma, sigma[0, 0], rtol=0, atol=1e-9 * np.abs(sigma).max())
    _, f, _ = body.internal(q, tangent=False)
    boundary = np.zeros(body.n_nodes, dtype=bool)
    boundary[body.boundary_nodes()] = True
    F = body.nodal(f)
    assert np.abs(F[~boundary]).max() < 1e-11 * np.abs(F[boundary]).max()
    if name == "linear":
        eps = 0.5 * (A + A.T)
        lam, mu = MATERIALS[name].lame
        if dim == 2:  # plane stress
            lam = 2 * lam * mu / (lam + 2 * mu)
        expected = lam * np.trace(eps) * np.eye(dim) + 2 * mu * eps
        assert np.allclose(sigma[0, 0, :dim, :dim], expected, rtol=1e-10, atol=1e-10 * mu)


@pytest.mark.parametrize("cell,plane", SETTINGS)
@pytest.mark.parametrize("name", ["svk", "neo-hookean"])
def test_large_rigid_motion_is_stress_free(name, cell, plane):
    body = small_solid(MATERIALS[name], cell, plane, "P2", divisions=2)
    R = rotation(body.dim, np.deg2rad(70.0))
    q = (body.X @ R.T - body.X + np.arange(1, body.dim + 1)).ravel()
    W, f, Ke = body.internal(q)
    scale = YOUNG * body.volume
    assert abs(W) < 1e-14 * scale
    assert np.abs(f).max() < 1e-13 * YOUNG * body.characteristic_length**2
    assert np.allclose(body.cell_data(q)["stress_von_mises"], 0.0, atol=1e-9 * YOUNG)
    # the small-strain material is not frame invariant: the same motion strains it
    linear = small_solid(MATERIALS["linear"], cell, plane, "P2", divisions=2)
    assert linear.energy(q) > 0.1 * scale


@pytest.mark.parametrize("cell,plane", SETTINGS)
@pytest.mark.parametrize("name", ["svk", "neo-hookean"])
def test_nonlinear_materials_match_linear_for_tiny_strains(name, cell, plane):
    body = small_solid(MATERIALS[name], cell, plane)
    linear = small_solid(MATERIALS["linear"], cell, plane)
    q = 1e-7 * body.characteristic_length * np.random.default_rng(2).normal(size=body.ndof)
    _, f, Ke = body.internal(q)
    _, f_lin, Ke_lin = linear.internal(q)
    assert np.abs(f - f_lin).max() < 1e-5 * np.abs(f_lin).max()
    assert np.abs(Ke - Ke_lin).max() < 1e-5 * np.abs(Ke_lin).max()


def test_linear_body_assembles_its_stiffness_once():
    body = small_solid(MATERIALS["linear"], "tetra", None, divisions=2)
    assert body.linear
    q = np.random.default_rng(0).normal(size=body.ndof) * 1e-4
    W, f, Ke = body.internal(q)
    assert Ke is body.internal(2 * q)[2]  # the same stored element matrices
    K = body.stiffness_matrix()
    assert np.allclose(f, K @ q) and W == pytest.approx(0.5 * q @ K @ q)
    assert abs(K - K.T).max() < 1e-9 * abs(K).max()
    with pytest.raises(InputError, match="nonlinear"):
        small_solid(MATERIALS["svk"], "tetra", None).stiffness_matrix()


@pytest.mark.parametrize("element,order", [("P1", 1), ("P2", 2)])
@pytest.mark.parametrize("cell,plane", [("triangle", "strain"), ("tetra", None)])
def test_stiffness_and_mass_equal_scikit_fem_vector_forms(cell, plane, element, order):
    """The node-major dof order equals ElementVector's: the matrices must match skfem's."""
    body = small_solid(MATERIALS["linear"], cell, plane, element, divisions=2)
    scalar = type(body.basis.elem)
    vb = skfem.Basis(body.mesh, skfem.ElementVector(scalar()), intorder=2 * order)
    K = linear_elasticity(*lame_parameters(YOUNG, NU)).assemble(vb) * body.thickness
    M = skfem.BilinearForm(lambda u, v, w: RHO * dot(u, v)).assemble(vb) * body.thickness
    assert abs(body.stiffness_matrix() - K).max() < 1e-10 * abs(K).max()
    assert abs(body.mass_matrix() - M).max() < 1e-12 * abs(M).max()


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("cell,plane", SETTINGS)
def test_mass_sums_to_density_volume_dimension(cell, plane, element):
    body = small_solid(MATERIALS["svk"], cell, plane, element, divisions=2)
    M = body.mass_matrix()
    volume = 0.2 * 0.1 * (0.15 if plane is None else 0.01)
    assert body.volume == pytest.approx(volume, rel=1e-12)
    assert M.sum() == pytest.approx(RHO * volume * body.dim, rel=1e-12)
    g = body.translation_field([0.0, -9.81] + [0.0] * (body.dim - 2))
    assert (M @ g).reshape(-1, body.dim).sum(axis=0)[1] == pytest.approx(-9.81 * RHO * volume)


def test_neo_hookean_inverted_state_has_infinite_energy():
    body = small_solid(MATERIALS["neo-hookean"], "triangle", "strain")
    q = (body.X * [[-1.0, 1.0]] - body.X).ravel()  # mirror image: det F = -1 everywhere
    W, f, Ke = body.internal(q)
    assert W == np.inf and np.all(np.isnan(f)) and np.all(np.isnan(Ke))
    assert body.energy(q) == np.inf


def test_stress_output_uniaxial_plane_stress():
    body = small_solid(MATERIALS["linear"], "quad", "stress", divisions=(4, 2))
    strain = 1e-4
    u = np.zeros_like(body.X)
    u[:, 0] = strain * body.X[:, 0]
    u[:, 1] = -NU * strain * body.X[:, 1]  # free lateral contraction: σ = diag(E ε, 0, 0)
    data = body.cell_data(u.ravel())
    assert data["stress_von_mises"].shape == (body.n_elements,)
    assert np.allclose(data["stress_von_mises"], YOUNG * strain, rtol=1e-10)
    assert np.allclose(data["pressure"], -YOUNG * strain / 3, rtol=1e-10)


# -- geometry and output ----------------------------------------------------------------------


@pytest.mark.parametrize("element", ["P1", "P2"])
@pytest.mark.parametrize("cell,plane", SETTINGS)
def test_vtk_cells_have_positive_sizes_summing_to_the_volume(cell, plane, element):
    pv = pytest.importorskip("pyvista")
    body = small_solid(MATERIALS["linear"], cell, plane, element, divisions=2)
    ((kind, conn),) = body.cells()
    assert conn.shape[0] == body.n_elements
    pts = np.zeros((body.n_nodes, 3))
    pts[:, : body.dim] = body.X
    grid = pv.from_meshio(meshio.Mesh(pts, [(kind, conn)]))
    sizes = grid.compute_cell_sizes()["Volume" if body.dim == 3 else "Area"]
    assert np.all(sizes > 0)
    assert sizes.sum() * (body.thickness if body.dim == 2 else 1.0) == pytest.approx(body.volume)


@pytest.mark.parametrize(
    "body",
    [
        Solid.disk([0.1, 0.2], 0.5, 2, MATERIALS["linear"]),
        Solid.rectangle([0, 0], [2, 1], 3, MATERIALS["linear"], cell="quad"),
        Solid.ball([0, 0, 1], 0.5, 1, MATERIALS["linear"]),
        Solid.box([0, 0, 0], [2, 1, 1], 2, MATERIALS["linear"], cell="hexahedron"),
        Solid.box([0, 0, 0], [2, 1, 1], 2, MATERIALS["linear"], cell="tetra"),
    ],
    ids=["disk", "quads", "ball", "hexes", "tets"],
)
def test_boundary_facets_point_outward(body):
    """Divergence theorem: ∮ x·n dA = d V only if every facet normal points outward."""
    facets = body.boundary_facets()
    x = body.X[facets]
    if body.dim == 2:
        t = x[:, 1] - x[:, 0]
        n_area = np.stack([t[:, 1], -t[:, 0]], axis=1)
    elif facets.shape[1] == 3:
        n_area = 0.5 * np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    else:
        n_area = 0.5 * np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])
    flux = np.einsum("fi,fi->", x.mean(axis=1), n_area) * (body.thickness if body.dim == 2 else 1)
    assert flux == pytest.approx(body.dim * body.volume, rel=1e-12)
    assert set(np.unique(facets)) <= set(body.boundary_nodes())


def test_contact_nodes_default_to_the_boundary():
    for element in ("P1", "P2"):
        body = Solid.disk([0.0, 0.0], 0.05, 2, MATERIALS["linear"], element=element)
        nodes = body.contact_nodes()
        n_vertices = len(body.mesh.boundary_nodes())
        assert len(nodes) == n_vertices * (1 if element == "P1" else 2)
        # vertices on the circle, P2 edge nodes at the middle of the polygon's sides
        r = np.linalg.norm(body.X[nodes], axis=1)
        assert np.allclose(np.sort(r)[-n_vertices:], 0.05)
        assert np.all(r >= 0.05 * np.cos(np.pi / n_vertices) - 1e-15)
    assert np.array_equal(body.contact_nodes([0, -1]), [0, body.n_nodes - 1])


def test_point_kinematics_and_output_fields():
    body = Solid.ball([0, 0, 0], 1.0, 1, MATERIALS["svk"])
    q = np.random.default_rng(1).normal(size=body.ndof)
    nodes = np.array([0, 5, 7])
    x, dofs, J, H = body.point_kinematics(q, nodes)
    assert np.allclose(x, body.positions(q)[nodes]) and H is None
    assert np.array_equal(dofs, body.node_translation_dofs(nodes))
    assert np.array_equal(J, np.broadcast_to(np.eye(3), (3, 3, 3)))
    data = body.point_data(q, 2 * q)
    assert data["displacement"].shape == (body.n_nodes, 3)
    assert np.allclose(data["velocity"], 2 * body.nodal(q))


def test_supports_are_chainable_and_validated():
    body = Solid.rectangle([0, 0], [1, 1], 2, MATERIALS["linear"])
    left = body.nodes_where(lambda x: x[0] < 1e-9)
    assert len(left) == 3
    assert body.fix(left, components=0).fix(-1) is body
    last = body.n_nodes - 1
    assert body.fixed == {2 * int(i) for i in left} | {2 * last, 2 * last + 1}
    with pytest.raises(InputError, match="components"):
        body.fix(0, components=2)
    with pytest.raises(InputError, match="node"):
        body.fix(body.n_nodes)
    with pytest.raises(InputError, match="3 components"):
        Solid.ball([0, 0, 0], 1.0, 0, MATERIALS["linear"]).translation_field([0.0, -9.81])


# -- mesh files ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "name,dim,cell,measure",
    [("disk", 2, "tri", np.pi), ("ball", 3, "tet", 4 / 3 * np.pi), ("bar", 2, "quad", 0.05)],
)
def test_shipped_meshes_load(name, dim, cell, measure):
    body = Solid.from_file(MESHES / f"{name}.msh", MATERIALS["svk"], scale=0.1, offset=[1.0] * dim)
    assert body.dim == dim and body.cell == cell
    # polygonal disk and ball are slightly smaller than the curved ones
    assert body.volume == pytest.approx(measure * 0.1**dim, rel=0.12)
    assert np.allclose(body.X.min(axis=0), 1.0 - (0.0 if name == "bar" else 0.1))


def test_make_meshes_reproduces_the_shipped_files(tmp_path):
    spec = importlib.util.spec_from_file_location("make_meshes", MESHES / "make_meshes.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for name, mesh in module.meshes().items():
        module.write(mesh, tmp_path / name)
        assert (tmp_path / name).read_bytes() == (MESHES / name).read_bytes(), name


def test_from_file_round_trip_keeps_hexahedra(tmp_path):
    body = Solid.box([0, 0, 0], [0.2, 0.1, 0.1], (2, 1, 1), MATERIALS["linear"], cell="hexahedron")
    ((kind, conn),) = body.cells()
    meshio.write(tmp_path / "box.vtu", meshio.Mesh(body.X, [(kind, conn)]))
    again = Solid.from_file(tmp_path / "box.vtu", MATERIALS["linear"])
    assert again.cell == "hex" and again.volume == pytest.approx(body.volume)
    assert abs(again.stiffness_matrix() - body.stiffness_matrix()).max() < 1e-6


@pytest.mark.parametrize("cell,plane", SETTINGS)
def test_quadratic_mesh_files_give_isoparametric_p2_bodies(tmp_path, cell, plane):
    """triangle6, quad9, tetra10 and hexahedron27 files: P2 on the file's own geometry, stress
    free under a rigid rotation; P1 on curved cells is refused."""
    body = small_solid(MATERIALS["svk"], cell, plane, "P2", divisions=2)
    ((kind, conn),) = body.cells()
    points = np.zeros((body.n_nodes, 3))
    points[:, : body.dim] = body.X
    meshio.write(tmp_path / "p2.vtu", meshio.Mesh(points, [(kind, conn)]))
    options = {} if plane is None else {"plane": plane, "thickness": 0.01}
    again = Solid.from_file(tmp_path / "p2.vtu", MATERIALS["svk"], element="P2", **options)
    assert again.n_nodes == body.n_nodes and again.volume == pytest.approx(body.volume)
    R = rotation(body.dim, 1.0)
    q = (again.X @ R.T - again.X).ravel()
    assert abs(again.energy(q)) < 1e-14 * YOUNG * again.volume
    with pytest.raises(InputError, match="curved"):
        Solid.from_file(tmp_path / "p2.vtu", MATERIALS["svk"], element="P1", **options)


# -- input rules: one test per rule ------------------------------------------------------------


def test_unknown_mesh_file_format(tmp_path):
    path = tmp_path / "body.xyz"
    path.write_text("1 2 3\n")
    with pytest.raises(InputError, match="unknown mesh file format '.xyz'"):
        Solid.from_file(path, MATERIALS["linear"])


def test_missing_mesh_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        Solid.from_file(tmp_path / "nothing.msh", MATERIALS["linear"])


def test_mesh_file_without_supported_cells(tmp_path):
    path = tmp_path / "lines.vtu"
    meshio.write(path, meshio.Mesh(np.eye(3), [("line", np.array([[0, 1], [1, 2]]))]))
    with pytest.raises(InputError, match=r"lines.vtu has no triangle, .* cells \(found line\)"):
        Solid.from_file(path, MATERIALS["linear"])


def test_empty_mesh():
    mesh = skfem.MeshTri(np.zeros((2, 0)), np.zeros((3, 0), dtype=np.int64))
    with pytest.raises(InputError, match="empty"):
        Solid(mesh, MATERIALS["linear"])


def test_inverted_element_is_named():
    mesh = skfem.MeshTri.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 1, 4))
    p = mesh.p.copy()
    i = int(np.argmin(np.linalg.norm(p.T - [1 / 3, 1 / 3], axis=1)))
    p[:, i] = [0.9, 0.5]  # pushed through its neighbours: two triangles flip over
    with pytest.raises(InputError, match=r"element \d+ \(nodes .*\) is inverted"):
        Solid(skfem.MeshTri(p, mesh.t), MATERIALS["linear"])


def test_folded_quadrilateral_is_named():
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    p = mesh.p.copy()
    i = int(np.argmin(np.linalg.norm(p.T - [0.5, 0.5], axis=1)))
    p[:, i] = [0.95, 0.95]  # non-convex cells: det ∂x/∂ξ changes sign at a corner
    with pytest.raises(InputError, match=r"element \d+ .* degenerate or folded"):
        Solid(skfem.MeshQuad(p, mesh.t), MATERIALS["linear"])


def test_degenerate_element_is_named():
    p = np.array([[0.0, 1.0, 2.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    mesh = skfem.MeshTri(p, np.array([[0, 1, 3], [0, 1, 2]]).T, sort_t=False)
    with pytest.raises(InputError, match=r"element 1 \(nodes \[0, 1, 2\]\) is degenerate"):
        Solid(mesh, MATERIALS["linear"])


def test_vertex_outside_every_element():
    p = np.array([[0.0, 1.0, 5.0, 0.0], [0.0, 0.0, 5.0, 1.0]])
    with pytest.raises(InputError, match="belong to no element, the first is vertex 2"):
        Solid(skfem.MeshTri(p, np.array([[0, 1, 3]]).T), MATERIALS["linear"])


def test_mesh_files_drop_unused_points(tmp_path):
    points = np.array([[0.0, 0.0, 0.0], [9.0, 9.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    meshio.write(tmp_path / "tri.vtu", meshio.Mesh(points, [("triangle", np.array([[0, 2, 3]]))]))
    body = Solid.from_file(tmp_path / "tri.vtu", MATERIALS["linear"])
    assert body.n_nodes == 3 and body.volume == pytest.approx(0.5)


def test_non_finite_coordinates():
    mesh = skfem.MeshTri()
    p = mesh.p.copy()
    p[0, 1] = np.nan
    with pytest.raises(InputError, match="finite"):
        Solid(skfem.MeshTri(p, mesh.t), MATERIALS["linear"])


@pytest.mark.parametrize("thickness", [0.0, -0.01, np.nan])
def test_thickness_must_be_positive(thickness):
    with pytest.raises(InputError, match="thickness"):
        Solid(skfem.MeshTri(), MATERIALS["linear"], plane="stress", thickness=thickness)


@pytest.mark.parametrize(
    "options,match",
    [
        ({"element": "P3"}, "element"),
        ({"plane": "axisymmetric"}, "plane"),
    ],
)
def test_element_and_plane_choices(options, match):
    with pytest.raises(InputError, match=match):
        Solid(skfem.MeshTri(), MATERIALS["linear"], **options)


def test_plane_options_are_2d_only():
    with pytest.raises(InputError, match="2D meshes only"):
        Solid(skfem.MeshTet(), MATERIALS["linear"], plane="stress")


def test_material_and_mesh_types():
    with pytest.raises(InputError, match="material"):
        Solid(skfem.MeshTri(), {"E": 1.0})
    with pytest.raises(InputError, match="scikit-fem Mesh"):
        Solid(np.zeros((3, 2)), MATERIALS["linear"])


@pytest.mark.parametrize(
    "builder,args",
    [
        (Solid.disk, ([0, 0], -1.0, 2)),
        (Solid.disk, ([0, 0, 0], 1.0, 2)),
        (Solid.ball, ([0, 0, 0], 1.0, -1)),
        (Solid.rectangle, ([0, 0], [1, -1], 2)),
        (Solid.box, ([0, 0, 0], [1, 1, 1], 0)),
    ],
)
def test_builder_arguments(builder, args):
    with pytest.raises(InputError):
        builder(*args, MATERIALS["linear"])


def test_quadratic_ball_is_curved():
    """P2 balls are isoparametric: every boundary node lies on the sphere, and the volume
    error is far below the polyhedral P1 ball's of the same refinement."""
    center, radius = np.array([0.1, -0.2, 0.3]), 0.05
    mat = MATERIALS["linear"]
    p1 = Solid.ball(center, radius, 2, mat)
    p2 = Solid.ball(center, radius, 2, mat, element="P2")
    r = np.linalg.norm(p2.X[p2.boundary_nodes()] - center, axis=1)
    assert np.allclose(r, radius, rtol=1e-14)
    exact = 4.0 / 3.0 * np.pi * radius**3
    assert abs(p2.volume / exact - 1.0) < 0.1 * abs(p1.volume / exact - 1.0)


def test_a_disk_has_the_triangles_its_docstring_says():
    """4 · 4^n triangles after n refinements (the docstring and the case parameter say so)."""
    from fecontact.scenes import DISK

    mat = LinearElastic(E=1e6, nu=0.3, rho=1e3)
    for n in range(4):
        assert Solid.disk([0.0, 0.0], 1.0, n, mat).mesh.t.shape[1] == 4 * 4**n
    assert "4 · 4^refinements triangles" in Solid.disk.__doc__
    assert "(4 * 4^n triangles)" in DISK["refinements"].text
