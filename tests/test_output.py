"""Output files: .pvd/.vtu time series, history.csv, summary.json and reading a run back."""

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import pyvista

from fecontact.io.output import (
    STANDARD_COLUMNS,
    HistoryWriter,
    PVDWriter,
    line_mesh,
    load_run,
    write_json,
)

TIMES = [0.0, 0.01, 0.025, 0.1]
REFERENCE = np.column_stack([np.linspace(0.0, 0.3, 5), np.zeros(5)])
CONNECTIVITY = np.column_stack([np.arange(4), np.arange(1, 5)])


def beam_at(t):
    """A planar beam bending down, 2D points and vectors as a solver would hand them over."""
    displacement = np.column_stack([np.zeros(5), -t * REFERENCE[:, 0]])
    velocity = np.column_stack([np.zeros(5), -REFERENCE[:, 0]])
    return line_mesh(
        REFERENCE + displacement,
        CONNECTIVITY,
        {"displacement": displacement, "velocity": velocity, "gap": np.full(5, t)},
    )


def stop_mesh():
    return line_mesh([[0.0, -0.3], [0.0, -0.4]], [[0, 1]])


def pvd_times(pvd):
    root = ET.parse(pvd).getroot()  # raises on invalid XML
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return sorted({float(ds.get("timestep")) for ds in root.iter("DataSet")})


def leftovers(folder):
    return [p.name for p in folder.iterdir() if p.name.startswith(".") or "tmp" in p.name]


def test_line_mesh_pads_planar_points_and_vectors():
    mesh = beam_at(0.5)
    assert mesh.points.shape == (5, 3)
    np.testing.assert_array_equal(mesh.points[:, 2], 0.0)
    assert mesh.point_data["displacement"].shape == (5, 3)
    assert mesh.point_data["gap"].shape == (5,)
    assert mesh.cells[0].type == "line"
    with pytest.raises(ValueError, match="outside"):
        line_mesh(REFERENCE, [[0, 5]])
    with pytest.raises(ValueError, match="rows"):
        line_mesh(REFERENCE, CONNECTIVITY, {"velocity": np.zeros((4, 2))})
    with pytest.raises(ValueError, match="snake_case"):
        line_mesh(REFERENCE, CONNECTIVITY, {"contactForce": np.zeros((5, 2))})


def test_pvd_series_read_by_pyvista_with_times_parts_and_data(tmp_path):
    writer = PVDWriter(tmp_path / "run", "pendulum")
    writer.write_static("stop", stop_mesh())
    for k, t in enumerate(TIMES):
        writer.write_frame(t, {"beam": beam_at(t)})
        assert pvd_times(writer.pvd) == TIMES[: k + 1]
    assert writer.times == TIMES and writer.n_frames == 4

    reader = pyvista.get_reader(str(writer.pvd))
    assert reader.number_time_points == 4
    np.testing.assert_array_equal(reader.time_values, TIMES)
    for i, t in enumerate(TIMES):
        reader.set_active_time_point(i)
        blocks = reader.read()
        assert blocks.n_blocks == 2  # the static stop is listed at every time
        beam = next(b for b in blocks if b.n_points == 5)
        stop = next(b for b in blocks if b.n_points == 2)
        expected = beam_at(t)
        np.testing.assert_allclose(beam.points, expected.points)
        assert beam.point_data["displacement"].shape == (5, 3)
        np.testing.assert_allclose(
            beam.point_data["displacement"], expected.point_data["displacement"]
        )
        np.testing.assert_allclose(beam.point_data["gap"], t)
        np.testing.assert_allclose(stop.points[:, 1], [-0.3, -0.4])

    files = sorted(p.name for p in (tmp_path / "run").iterdir())
    assert files == [
        "pendulum.pvd",
        "pendulum_beam_00000.vtu",
        "pendulum_beam_00001.vtu",
        "pendulum_beam_00002.vtu",
        "pendulum_beam_00003.vtu",
        "pendulum_stop.vtu",
    ]

    run = load_run(tmp_path / "run")
    assert run.parts == ["stop", "beam"] and run.static_parts == ["stop"]
    np.testing.assert_array_equal(run.times, TIMES)
    frames = run.frames()
    assert [t for t, _ in frames] == TIMES
    t, parts = frames[2]
    np.testing.assert_allclose(parts["beam"].points, beam_at(t).points)
    assert parts["stop"] is frames[0][1]["stop"]  # a static part is read once
    assert run.reader().number_time_points == 4


def test_interrupted_run_leaves_readable_pvd_with_complete_frames(tmp_path):
    folder = tmp_path / "run"
    writer = PVDWriter(folder, "case")
    writer.write_static("stop", stop_mesh())
    with pytest.raises(RuntimeError, match="interrupted"):
        for k, t in enumerate(TIMES):
            if k == 2:
                raise RuntimeError("interrupted")
            writer.write_frame(t, {"beam": beam_at(t)})
    reader = pyvista.get_reader(str(writer.pvd))
    np.testing.assert_array_equal(reader.time_values, TIMES[:2])
    assert leftovers(folder) == []


def test_pvd_index_is_rewritten_at_its_interval_and_on_flush(tmp_path):
    # replacing the .pvd costs milliseconds on ext4: a run rewrites it at most every
    # index_interval seconds, and flushes it when it stops
    writer = PVDWriter(tmp_path, "case", index_interval=3600.0)
    for t in TIMES:
        writer.write_frame(t, {"beam": beam_at(t)})
    assert pvd_times(writer.pvd) == TIMES[:1]
    assert len(list(tmp_path.glob("case_beam_*.vtu"))) == len(TIMES)
    writer.flush()
    np.testing.assert_array_equal(pyvista.get_reader(str(writer.pvd)).time_values, TIMES)
    mtime = writer.pvd.stat().st_mtime_ns
    writer.flush()  # nothing new: not rewritten
    assert writer.pvd.stat().st_mtime_ns == mtime
    assert leftovers(tmp_path) == []


def test_failed_write_keeps_previous_pvd_and_no_temporary_file(tmp_path, monkeypatch):
    folder = tmp_path / "run"
    writer = PVDWriter(folder, "case")
    writer.write_frame(0.0, {"beam": beam_at(0.0)})
    before = writer.pvd.read_text()
    real_write = Path.write_text

    def write_half_then_fail(self, text, *args, **kwargs):
        if self.suffix != ".vtu":
            return real_write(self, text, *args, **kwargs)
        real_write(self, text[: len(text) // 2])  # a torn file, as a kill mid-write leaves it
        raise OSError("disk full")

    monkeypatch.setattr(Path, "write_text", write_half_then_fail)
    with pytest.raises(OSError, match="disk full"):
        writer.write_frame(0.5, {"beam": beam_at(0.5)})
    assert writer.pvd.read_text() == before
    assert writer.times == [0.0]
    assert leftovers(folder) == []
    assert not (folder / "case_beam_00001.vtu").exists()

    monkeypatch.setattr(Path, "write_text", real_write)
    writer.write_frame(0.5, {"beam": beam_at(0.5)})
    np.testing.assert_array_equal(pyvista.get_reader(str(writer.pvd)).time_values, [0.0, 0.5])


def test_static_part_added_after_frames_is_listed_at_every_time(tmp_path):
    writer = PVDWriter(tmp_path, "case")
    writer.write_frame(0.0, {"beam": beam_at(0.0)})
    writer.write_frame(0.1, {"beam": beam_at(0.1)})
    writer.write_static("stop", stop_mesh())
    root = ET.parse(writer.pvd).getroot()
    listed = [(float(d.get("timestep")), d.get("name")) for d in root.iter("DataSet")]
    assert sorted(listed) == [(0.0, "beam"), (0.0, "stop"), (0.1, "beam"), (0.1, "stop")]
    assert load_run(tmp_path).static_parts == ["stop"]


def test_pvd_writer_rejects_bad_times_and_names(tmp_path):
    writer = PVDWriter(tmp_path, "case")
    writer.write_frame(0.1, {"beam": beam_at(0.1)})
    with pytest.raises(ValueError, match="increase"):
        writer.write_frame(0.1, {"beam": beam_at(0.1)})
    with pytest.raises(ValueError, match="increase"):
        writer.write_frame(math.nan, {"beam": beam_at(0.1)})
    with pytest.raises(ValueError, match="part name"):
        writer.write_frame(0.2, {"../beam": beam_at(0.2)})
    with pytest.raises(ValueError, match="moving part"):
        writer.write_static("beam", stop_mesh())
    assert pvd_times(writer.pvd) == [0.1]


def test_history_round_trip_with_inf_nan_and_bools(tmp_path):
    columns = [*STANDARD_COLUMNS, "tip_x"]
    rows = [
        [0.0, 1.5, 0.0, -2.0, -0.5, math.inf, False, 0.0, 0, 0.0, 0.3],
        [1e-3, 1.25, 0.1, -2.1, -0.75, 1e-9, True, 0.012, 3, 1e-3, np.float64(0.1)],
        [2e-3, np.nan, 0.2, -2.2, -np.inf, -math.inf, np.bool_(True), 0.0, np.int64(2), 1e-3,
         1 / 3],
    ]  # fmt: skip
    with HistoryWriter(tmp_path / "history.csv", columns, flush_every=2) as history:
        history.write(dict(zip(columns, rows[0], strict=True)))
        history.write(rows[1])
        history.write(rows[2])
    text = (tmp_path / "history.csv").read_text()
    assert text.splitlines()[0] == ",".join(columns)
    assert text.splitlines()[1] == "0.0,1.5,0.0,-2.0,-0.5,inf,0,0.0,0,0.0,0.3"
    assert text.splitlines()[2] == "0.001,1.25,0.1,-2.1,-0.75,1e-09,1,0.012,3,0.001,0.1"
    assert text.splitlines()[3] == f"0.002,nan,0.2,-2.2,-inf,-inf,1,0.0,2,0.001,{1 / 3!r}"
    assert "True" not in text and "np." not in text

    PVDWriter(tmp_path, "case").write_frame(0.0, {"beam": beam_at(0.0)})
    history = load_run(tmp_path).history
    assert list(history) == columns
    expected = np.array(rows, dtype=float)
    for j, column in enumerate(columns):
        assert history[column].dtype == float
        np.testing.assert_array_equal(history[column], expected[:, j])  # exact, nan == nan
    assert history["n_active"].tolist() == [0.0, 1.0, 1.0]


def test_history_rejects_rows_that_do_not_fit_the_header(tmp_path):
    with HistoryWriter(tmp_path / "h.csv", ["t", "x"]) as history:
        with pytest.raises(ValueError, match="missing"):
            history.write({"t": 0.0})
        with pytest.raises(ValueError, match="unknown"):
            history.write({"t": 0.0, "y": 1.0})
        with pytest.raises(ValueError, match="expected 2"):
            history.write([0.0, 1.0, 2.0])
        with pytest.raises(ValueError):
            history.write([0.0, "fast"])


def test_history_line_cut_by_a_kill_is_ignored(tmp_path):
    (tmp_path / "history.csv").write_text("t,x\n0.0,1.0\n0.001,2.0\n0.002,3")
    PVDWriter(tmp_path, "case").write_frame(0.0, {"beam": beam_at(0.0)})
    history = load_run(tmp_path).history
    np.testing.assert_array_equal(history["x"], [1.0, 2.0])


def reject_constant(name):
    raise ValueError(f"non-strict JSON constant {name}")


def test_write_json_is_strict_and_load_run_restores_non_finite(tmp_path):
    data = {
        "steps": np.int64(1500),
        "max_penetration": np.float64(-0.0),
        "energy_final": math.nan,
        "min_gap": np.inf,
        "bounds": np.array([-np.inf, 1.0]),
        "phase_times_s": {"assembly": np.float32(0.5)},
        "converged": np.bool_(True),
        "impacts": [{"time": 0.318, "contact": "stop", "impulse": 0.25}],
        "label": "inf-norm",
    }
    path = write_json(tmp_path / "summary.json", data)
    text = path.read_text()
    strict = json.loads(text, parse_constant=reject_constant)
    assert strict["min_gap"] == "inf" and strict["energy_final"] == "nan"
    assert strict["bounds"] == ["-inf", 1.0]
    assert strict["steps"] == 1500 and strict["converged"] is True
    assert text.startswith('{\n  "steps": 1500')
    assert leftovers(tmp_path) == []

    PVDWriter(tmp_path, "case").write_frame(0.0, {"beam": beam_at(0.0)})
    summary = load_run(tmp_path).summary
    assert summary["min_gap"] == math.inf
    assert math.isnan(summary["energy_final"])
    assert summary["bounds"] == [-math.inf, 1.0]
    assert summary["phase_times_s"]["assembly"] == 0.5
    assert summary["impacts"][0]["contact"] == "stop"
    assert summary["label"] == "inf-norm"


def test_load_run_accepts_pvd_path_and_reports_missing_or_ambiguous_pvd(tmp_path):
    folder = tmp_path / "out"
    with pytest.raises(FileNotFoundError, match="out"):
        load_run(folder)
    folder.mkdir()
    with pytest.raises(FileNotFoundError, match=r"no \.pvd file in .*out"):
        load_run(folder)
    writer = PVDWriter(folder, "a")
    writer.write_frame(0.0, {"beam": beam_at(0.0)})
    run = load_run(writer.pvd)
    assert run.pvd == writer.pvd and run.history == {} and run.summary == {}
    PVDWriter(folder, "b").write_frame(0.0, {"beam": beam_at(0.0)})
    with pytest.raises(FileNotFoundError, match="2 .pvd files"):
        load_run(folder)


def test_a_run_without_frames_loads_its_history(tmp_path, capsys):
    from fecontact import run as run_sim
    from fecontact.cli.cases import load_case
    from fecontact.cli.commands import main

    out = tmp_path / "ball"
    sim = load_case("bouncing_ball").build().replace(t_end=0.005)
    assert run_sim(sim, out, progress=False, frames=False)["status"] == "completed"
    # (before: "no .pvd file: not a run output folder", its history unreachable)
    run = load_run(out)
    assert run.pvd is None and len(run.times) == 0 and run.frames() == []
    assert run.history["t"].size == 6 and run.summary["status"] == "completed"
    assert repr(run).endswith("bouncing_ball, completed, 6 history rows to t = 0.005 s, no frames)")
    assert main(["render", str(out)]) == 2
    assert "holds no frames" in capsys.readouterr().err


def test_a_plane_is_drawn_under_the_whole_motion(tmp_path):
    """The block slides about 1.5 m down a 30° incline: the plane's outline covers where it
    went, not 2 model sizes around the plane's point."""
    from fecontact.cli.commands import main
    from fecontact.io.output import load_run
    from fecontact.testing import CASES

    out = tmp_path / "slide"
    args = ["run", str(CASES / "sliding_block.py"), "--quiet", "--out", str(out)]
    assert main([*args, "--set", "incline=30", "--set", "friction=0.2"]) == 0
    run = load_run(out)
    plane = pyvista.read(next(out.glob("*obstacle*.vtu"))).points[:, :2]
    direction = (plane[1] - plane[0]) / np.linalg.norm(plane[1] - plane[0])
    reach = np.sort(plane @ direction)
    for _, parts in run.frames():
        block = next(m for name, m in parts.items() if "obstacle" not in name).points[:, :2]
        along = block @ direction
        assert reach[0] <= along.min() and along.max() <= reach[1]


def test_history_rows_reach_the_file_within_their_wall_time(tmp_path):
    # a run killed hard keeps the rows written before the last flush: with 100 rows a flush,
    # a 3D ball killed at 5 s had frames to t = 2.4 ms and a history of its header alone
    path = tmp_path / "h.csv"
    with HistoryWriter(path, ["t", "x"], flush_seconds=0.0) as history:
        history.write([0.0, 1.0])
        assert path.read_text().splitlines() == ["t,x", "0.0,1.0"]
    with HistoryWriter(path, ["t", "x"], flush_seconds=3600.0) as history:
        history.write([0.0, 1.0])
        assert path.read_text().splitlines() == ["t,x"]  # (buffered: 100 rows, or an hour)
