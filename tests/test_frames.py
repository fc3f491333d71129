"""Frames as ParaView and PyVista users expect them: the reference mesh with displacement and
velocity fields, the Cauchy stress tensor of solids, the contact pressure on their surface."""

import numpy as np
import pytest
import pyvista
from conftest import ROOT

from fecontact import LinearElastic, Solid
from fecontact.cli import main
from fecontact.io.output import deformed, load_run


def run_case(tmp_path, case, *settings, fmt="vtu"):
    out = tmp_path / case
    args = ["run", str(ROOT / "cases" / f"{case}.py"), "--quiet", "--out", str(out)]
    args += ["--format", fmt]
    assert main([*args, *(a for s in settings for a in ("--set", s))]) == 0
    return load_run(out)


def von_mises(s: np.ndarray) -> np.ndarray:
    """From the components (xx, yy, zz, xy[, yz, xz]) of a symmetric stress."""
    xx, yy, zz, xy = s[:, 0], s[:, 1], s[:, 2], s[:, 3]
    yz, xz = (s[:, 4], s[:, 5]) if s.shape[1] == 6 else (0.0, 0.0)
    normal = (xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2
    return np.sqrt(0.5 * normal + 3.0 * (xy**2 + yz**2 + xz**2))


def tributary_areas(mesh) -> np.ndarray:
    """Each point's share (m²) of the surface triangles of ``mesh``, found by VTK."""
    surface = mesh.extract_surface(pass_pointid=True, algorithm="dataset_surface").triangulate()
    ids = np.asarray(surface.point_data["vtkOriginalPointIds"])
    tri = surface.faces.reshape(-1, 4)[:, 1:]
    x = np.asarray(surface.points)[tri]
    area = 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
    return np.bincount(ids[tri].ravel(), np.repeat(area / 3.0, 3), minlength=mesh.n_points)


@pytest.fixture(scope="module", params=["vtu", "vtkhdf"])
def ball_run(tmp_path_factory, request):
    out = tmp_path_factory.mktemp(request.param)
    return run_case(out, "ball_drop", "refinements=1", fmt=request.param)


def test_points_are_the_reference_and_displacement_gives_the_deformed_shape(ball_run):
    frames = ball_run.frames()
    first = frames[0][1]["solid0"]
    np.testing.assert_array_equal(first.point_data["displacement"], 0.0)
    history = ball_run.history
    for t, parts in frames:
        ball = parts["solid0"]
        np.testing.assert_array_equal(ball.points, first.points)
        assert ball.point_data["velocity"].shape == (ball.n_points, 3)
        # the lowest point of the deformed ball is the case's "gap" probe at that time
        row = int(np.argmin(np.abs(history["t"] - t)))
        assert history["t"][row] == pytest.approx(t, abs=1e-15)
        lowest = np.min(deformed(ball).points[:, 2])
        assert lowest == pytest.approx(history["gap"][row], abs=1e-14)


def test_the_stress_tensor_gives_the_von_mises_scalar(ball_run):
    loaded = [parts["solid0"] for _, parts in ball_run.frames() if parts["solid0"]]
    ball = max(loaded, key=lambda m: np.max(m.cell_data["stress_von_mises"]))
    stress = np.asarray(ball.cell_data["stress"])
    assert stress.shape == (ball.n_cells, 6) and np.max(np.abs(stress)) > 1e3
    # one quadrature point per P1 tetrahedron: the scalar is von Mises of the tensor, and
    # -tr/3 the pressure, to round-off of stresses of this size
    scale = np.max(np.abs(stress))
    np.testing.assert_allclose(
        von_mises(stress), ball.cell_data["stress_von_mises"], atol=1e-12 * scale
    )
    np.testing.assert_allclose(
        -stress[:, :3].mean(axis=1), ball.cell_data["pressure"], atol=1e-12 * scale
    )


def test_cauchy_stress_is_symmetric_and_2d_has_four_components():
    rng = np.random.default_rng(3)
    mat = LinearElastic(E=1e6, nu=0.3, rho=1e3)
    for body in (Solid.rectangle([0, 0], [1, 1], 3, mat, cell="quad"),
                 Solid.box([0, 0, 0], [1, 1, 1], 2, mat, cell="hexahedron")):  # fmt: skip
        q = 1e-3 * rng.standard_normal(body.ndof)
        sigma = body.stress(q)
        np.testing.assert_allclose(
            sigma, np.swapaxes(sigma, -1, -2), atol=1e-12 * np.abs(sigma).max()
        )
        data = body.cell_data(q)
        assert data["stress"].shape == (body.n_elements, 4 if body.dim == 2 else 6)
        # several quadrature points: von Mises averaged point by point bounds that of the mean
        assert np.all(von_mises(data["stress"]) <= data["stress_von_mises"] * (1 + 1e-12))


def test_contact_pressure_integrates_to_the_contact_force(ball_run):
    history = ball_run.history
    hits = 0
    for t, parts in ball_run.frames():
        ball = parts["solid0"]
        force = np.asarray(ball.point_data["contact_force"])
        pressure = np.asarray(ball.point_data["contact_pressure"])
        total = np.linalg.norm(force.sum(axis=0))
        area = tributary_areas(ball)
        assert np.all(pressure[area == 0.0] == 0.0)
        # the same lumped weights, found by VTK from the written cells: Σ p_a A_a = |Σ f_a| (every
        # node pushed along +z by the plane)
        assert np.sum(pressure * area) == pytest.approx(total, rel=1e-8, abs=1e-12)
        row = int(np.argmin(np.abs(history["t"] - t)))
        assert total == pytest.approx(history["contact_force"][row], rel=1e-8, abs=1e-12)
        hits += total > 0.0
    assert hits >= 3  # frames in contact were checked


def test_a_2d_solid_carries_four_stress_components_and_its_pressure(tmp_path):
    run = run_case(tmp_path, "disk_drop", "refinements=1")
    disk = run.frames([-1])[0][1]["solid0"]
    assert disk.cell_data["stress"].shape == (disk.n_cells, 4)
    np.testing.assert_allclose(
        von_mises(np.asarray(disk.cell_data["stress"])),
        disk.cell_data["stress_von_mises"],
        atol=1e-12 * np.abs(disk.cell_data["stress"]).max(),
    )
    assert "contact_pressure" in disk.point_data


def test_the_pvd_parts_are_named_as_blocks(ball_run):
    blocks = ball_run.multiblock(-1)
    assert isinstance(blocks, pyvista.MultiBlock) and blocks.keys() == ["obstacle0", "solid0"]


def test_vtkhdf_frames_hold_the_same_data_as_vtu(tmp_path):
    runs = [run_case(tmp_path / f, "ball_drop", "refinements=1", fmt=f) for f in ("vtu", "vtkhdf")]
    assert sorted(p.name for p in (tmp_path / "vtkhdf" / "ball_drop").iterdir()) == [
        "ball_drop.frames.json",
        "ball_drop_obstacle0.vtkhdf",
        "ball_drop_solid0.vtkhdf",
        "history.csv",
        "summary.json",
    ]
    vtu, hdf = (r.frames() for r in runs)
    assert [t for t, _ in vtu] == [t for t, _ in hdf] and len(vtu) > 30
    for (_, a), (_, b) in zip(vtu, hdf, strict=True):
        for name, mesh in a.items():
            other = b[name]
            np.testing.assert_array_equal(other.points, mesh.points)
            np.testing.assert_array_equal(other.cell_connectivity, mesh.cell_connectivity)
            np.testing.assert_array_equal(other.celltypes, mesh.celltypes)
            for data, data_b in (
                (mesh.point_data, other.point_data),
                (mesh.cell_data, other.cell_data),
            ):
                assert sorted(data.keys()) == sorted(data_b.keys())
                for key in data:
                    np.testing.assert_array_equal(data_b[key], data[key])


def test_vtkhdf_geometry_is_written_once_unless_it_moves(tmp_path):
    """Steps point to the one copy of the geometry; a part whose points move gets a new copy
    from then on (a moving obstacle's outline), and a resumed series cuts both back."""
    import h5py

    from fecontact.io.vtkhdf import VTKHDFSeries, read_step
    from fecontact.io.vtu import body_mesh

    tri = [("triangle", np.array([[0, 1, 2], [1, 3, 2]]))]
    square = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])

    def mesh(t, shift=0.0):
        u = np.full((4, 2), t)
        return body_mesh(square + shift, tri, {"displacement": u}, {"s": [np.array([t, 2 * t])]})

    series = VTKHDFSeries(tmp_path, "case")
    for t, shift in [(0.0, 0.0), (0.1, 0.0), (0.2, 0.5), (0.3, 0.5)]:
        series.write_frame(t, {"plate": mesh(t, shift)})
    series.close()
    path = tmp_path / "case_plate.vtkhdf"
    with h5py.File(path) as f:
        root = f["VTKHDF"]
        assert root["Points"].shape == (8, 3) and list(root["NumberOfPoints"]) == [4, 4]
        assert list(root["Steps/PartOffsets"]) == [0, 0, 1, 1]
        assert list(root["Steps/PointOffsets"]) == [0, 0, 4, 4]
        assert root["PointData/displacement"].shape == (16, 3)
    for step, (t, shift) in enumerate([(0.0, 0.0), (0.1, 0.0), (0.2, 0.5), (0.3, 0.5)]):
        m = read_step(path, step)
        np.testing.assert_array_equal(m.points[:, :2], square + shift)
        np.testing.assert_array_equal(m.point_data["displacement"][:, 0], t)
        np.testing.assert_array_equal(m.cell_data["s"], [t, 2 * t])
    again = VTKHDFSeries(tmp_path, "case")
    again.resume(0.15)
    assert again.times == [0.0, 0.1]
    again.write_frame(0.2, {"plate": mesh(0.25, 0.7)})
    again.close()
    with h5py.File(path) as f:
        assert f["VTKHDF/Points"].shape == (8, 3) and f["VTKHDF/Steps"].attrs["NSteps"] == 3
        assert list(f["VTKHDF/Steps/PartOffsets"]) == [0, 0, 1]
        assert f["VTKHDF/PointData/displacement"].shape == (12, 3)
    np.testing.assert_array_equal(read_step(path, 2).points[:, :2], square + 0.7)
    np.testing.assert_array_equal(read_step(path, 2).point_data["displacement"][:, 0], 0.25)
    np.testing.assert_array_equal(read_step(path, 1).point_data["displacement"][:, 0], 0.1)


def test_render_draws_the_deformed_bodies(ball_run, monkeypatch):
    """``render`` warps each frame by its displacement: the ball it draws at the last frame
    is the deformed one, not the reference mesh the file holds."""
    import fecontact.io.render as render

    drawn = []
    real = render._add_part

    def spy(pyvista, plotter, mesh, static, *args, **kwargs):
        drawn.append((static, np.asarray(mesh.points).copy()))
        return real(pyvista, plotter, mesh, static, *args, **kwargs)

    monkeypatch.setattr(render, "_add_part", spy)
    frames = ball_run.frames()
    i = int(np.argmax([np.abs(p["solid0"].point_data["displacement"]).max() for _, p in frames]))
    t, parts = frames[i]
    ball = parts["solid0"]
    assert np.max(np.abs(ball.point_data["displacement"])) > 1e-3  # a fall of 2 mm and more
    written = render.render_run(ball_run.out_dir, [t], animation=False)
    assert [p.suffix for p in written] == [".png", ".png"] and all(p.is_file() for p in written)
    moving = [points for static, points in drawn if not static]
    np.testing.assert_array_equal(moving[0], deformed(ball).points)


def test_auto_format_is_vtkhdf_for_large_3d_models_only(tmp_path):
    from types import SimpleNamespace

    from fecontact.io.output import AUTO_VTKHDF_DOFS, frame_format

    big3d = SimpleNamespace(dim=3, n=AUTO_VTKHDF_DOFS)
    assert frame_format("auto", big3d) == "vtkhdf"
    assert frame_format("auto", SimpleNamespace(dim=3, n=AUTO_VTKHDF_DOFS - 1)) == "vtu"
    assert frame_format("auto", SimpleNamespace(dim=2, n=10**6)) == "vtu"
    assert frame_format("vtu", big3d) == "vtu"
    # a resumed run keeps the format of the frames it continues
    assert frame_format("vtkhdf", big3d, tmp_path / "case.pvd") == "vtu"
    assert frame_format("vtu", big3d, tmp_path / "case.frames.json") == "vtkhdf"
    with pytest.raises(ValueError, match="format must be"):  # an InputError
        frame_format("xdmf", big3d)


def test_without_h5py_auto_writes_vtu_and_vtkhdf_names_the_extra(monkeypatch, tmp_path, capsys):
    from types import SimpleNamespace

    import fecontact.io.output as output

    monkeypatch.setattr(output, "_has_h5py", lambda: False)
    assert output.frame_format("auto", SimpleNamespace(dim=3, n=10**5)) == "vtu"
    args = ["run", str(ROOT / "cases" / "disk_drop.py"), "--quiet", "--format", "vtkhdf"]
    assert main([*args, "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "fecontact[vtkhdf]" in err
    assert not (tmp_path / "run").exists()  # refused before any file


def test_a_sweep_passes_the_format_to_its_runs(tmp_path):
    case = str(ROOT / "cases" / "rigid_pendulum.py")
    args = ["sweep", case, "--set", "dt=1e-3,2e-3", "--t-end", "0.05", "--workers", "1"]
    assert main([*args, "--quiet", "--format", "vtkhdf", "--out", str(tmp_path)]) == 0
    indices = sorted(tmp_path.glob("**/*.frames.json"))
    assert len(indices) == 2 and not list(tmp_path.glob("**/*.pvd"))
    assert all(len(load_run(i.parent).times) > 1 for i in indices)
