"""The fecontact command: runs, outputs, and every input error as exit status 2."""

import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT
from scipy.special import ellipk

from fecontact import load_run
from fecontact.cli import main, parse_value
from fecontact.simulation import HISTORY_COLUMNS

CASE = str(ROOT / "cases" / "flexible_pendulum.py")


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    status = main(
        ["run", CASE, "--out", str(out), "--t-end", "0.35", "--quiet", "--output-interval", "0.05"]
    )
    assert status == 0
    return out


def test_run_writes_frames_history_and_summary(short_run):
    files = sorted(p.name for p in short_run.iterdir())
    assert "flexible_pendulum.pvd" in files
    assert "history.csv" in files and "summary.json" in files
    run = load_run(short_run)
    for column in HISTORY_COLUMNS + ("tip_x", "tip_y", "tip_vx", "tip_vy"):
        assert np.all(np.isfinite(run.history[column]) | (column == "min_gap"))
    assert len(run.history["t"]) == 351
    s = run.summary
    for key in (
        "steps",
        "wall_time_s",
        "time_per_step_s",
        "phase_times_s",
        "sparse_factorizations",
        "newton_iterations_total",
        "newton_iterations_max",
        "max_penetration",
        "energy_initial",
        "energy_final",
        "impacts",
        "parameters",
        "versions",
    ):
        assert key in s
    assert s["steps"] == 350 and s["status"] == "completed"
    assert {"assembly", "solve", "contact", "output"} <= set(s["phase_times_s"])
    compute = s["wall_time_s"] - s["phase_times_s"]["output"]
    assert s["time_per_step_s"] == pytest.approx(compute / s["steps"])
    assert s["sparse_factorizations"] == {"count": 0, "seconds": 0.0}  # 15 dofs: dense
    assert s["parameters"]["tip_mass"] == 0.14
    assert s["max_penetration"] <= 1e-10
    # the rigid pendulum (J = m_tip L² + m_beam L²/3) hits at K(sin 45°)/ω₀ = 0.318576 s; the
    # strip's bending delays its tip by less than a step here, and the impact is known to the
    # step that detects it: within two steps of h = 1e-3
    L, m_tip, m_beam, g = 0.3, 0.14, 2700.0 * 0.02 * 0.002 * 0.3, 9.81
    omega0 = np.sqrt(g * (m_tip * L + m_beam * L / 2) / (m_tip * L**2 + m_beam * L**2 / 3))
    assert abs(s["impacts"][0]["time"] - ellipk(0.5) / omega0) <= 2e-3
    # frames at the output interval and at the first impact, with real times, readable by
    # pyvista
    times = [t for t, _ in run.frames()]
    expected = np.sort(np.r_[np.arange(0, 0.35, 0.05), 0.35, s["impacts"][0]["time"]])
    assert np.allclose(times, expected)
    t, parts = run.frames([-1])[0]
    beam = next(m for name, m in parts.items() if "obstacle" not in name)
    assert beam.point_data["displacement"].shape == (5, 3)
    # points: the reference configuration; plus the displacement: the deformed shape
    assert np.allclose(beam.points[:, 0], np.linspace(0.0, 0.3, 5))
    assert np.all(beam.points[:, 1] == 0)
    tip = (beam.points + beam.point_data["displacement"])[-1, :2]
    assert np.allclose(tip, [run.history["tip_x"][-1], run.history["tip_y"][-1]])
    assert beam.n_cells == 4


def test_info_lists_parameters_with_units(capsys):
    assert main(["info", CASE]) == 0
    out = capsys.readouterr().out
    for name, unit in [("length", "m"), ("E", "Pa"), ("tip_mass", "kg"), ("restitution", "-")]:
        line = next(row for row in out.splitlines() if row.split()[:1] == [name])
        assert unit in line.split()
    # an option only some integrators read is listed with them
    assert "theta (moreau)" in out and "rho_inf (nsga, penalty)" in out


@pytest.mark.parametrize(
    "args, word",
    [
        (["--set", "E=-1"], "E"),
        (["--set", "length=-1"], "length"),
        (["--set", "restitution=1.5"], "restitution"),
        (["--set", "restitution=-0.5"], "restitution"),
        (["--set", "E=nan"], "E"),
        (["--set", "rho=inf"], "rho"),
        (["--set", "tip_mass=-0.1"], "mass"),
        (["--set", "n_elements=0"], "n_elements"),
        (["--set", "rho_inf=1.5"], "rho_inf"),
        (["--set", "metric=diagonal"], "metric"),
        (["--set", "bogus=1"], "bogus"),
        (["--set", "E"], "NAME=VALUE"),
        (["--dt", "0"], "dt"),
        (["--dt", "-1e-3"], "dt must be > 0"),  # (argparse took "-1e-3" for an option)
        (["--t-end", "-inf"], "t_end must be finite"),
        (["--t-end", "nan"], "t_end"),
        (["--output-interval", "0"], "output_interval"),
        (["--dt", "abc"], "dt"),
    ],
)
def test_bad_input_exits_2_with_one_line(tmp_path, capsys, args, word):
    out = tmp_path / "out"
    assert main(["run", CASE, "--out", str(out), "--quiet", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err
    assert not out.exists()  # stopped before any work


def test_unknown_name_lists_the_known_ones(capsys):
    main(["run", CASE, "--set", "lenght=1"])
    err = capsys.readouterr().err
    assert "length" in err and "restitution" in err


def test_missing_case_file_exits_2(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.py")]) == 2
    assert "not found" in capsys.readouterr().err
    assert main(["info", str(tmp_path / "nope.py")]) == 2
    assert main(["render", str(tmp_path / "nothing")]) == 2


def test_set_values_parse_as_int_float_or_string():
    assert parse_value("4") == 4 and isinstance(parse_value("4"), int)
    assert parse_value("7e10") == 7e10
    assert np.isnan(parse_value("nan")) and parse_value("inf") == np.inf
    assert parse_value("mass") == "mass"


def test_run_that_fails_midway_keeps_its_frames(tmp_path, capsys):
    """Too few Newton iterations and no step halving: the run stops after the impact, with
    exit status 1, the time and step in the message, and a readable partial .pvd."""
    out = tmp_path / "fail"
    status = main(
        [
            "run",
            CASE,
            "--out",
            str(out),
            "--quiet",
            "--set",
            "max_iterations=3",
            "--set",
            "max_halvings=0",
        ]
    )
    assert status == 1
    err = capsys.readouterr().err
    assert "t = " in err and "step" in err and "residual" in err
    run = load_run(out)
    assert run.summary["status"] == "failed"
    assert 0.3 < run.history["t"][-1] < 1.5
    frames = run.frames()
    assert len(frames) >= 30
    assert frames[-1][0] <= run.history["t"][-1]
    assert not list(out.glob("*.tmp*"))


def test_case_file_runs_as_a_script(tmp_path):
    out = tmp_path / "script"
    proc = subprocess.run(
        [sys.executable, CASE, "--t-end", "0.02", "--quiet", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "summary.json").read_text())["steps"] == 20
    bad = subprocess.run(
        [sys.executable, CASE, "--set", "E=-5"], capture_output=True, text=True, timeout=120
    )
    assert bad.returncode == 2 and "Traceback" not in bad.stderr


def test_render_a_finished_run(short_run, capsys):
    assert main(["render", str(short_run / "flexible_pendulum.pvd")]) == 0
    for name in (
        "snapshot_start.png",
        "snapshot_impact.png",
        "snapshot_end.png",
        "history.png",
        "animation.gif",
    ):
        assert (short_run / name).stat().st_size > 1000


def test_unstable_settings_are_warned_about(tmp_path, capsys):
    out = tmp_path / "warn"
    args = ["run", CASE, "--out", str(out), "--quiet", "--t-end", "0.01"]
    assert main([*args, "--set", "rho_inf=0.9", "--set", "restitution=1"]) == 0
    assert "warning: rho_inf = 0.9" in capsys.readouterr().err
    assert main([*args, "--set", "metric=mass"]) == 0
    assert "warning: metric = mass" in capsys.readouterr().err
    assert main(args) == 0
    assert "warning" not in capsys.readouterr().err


def test_import_is_light():
    """Rendering, plotting, mesh I/O and progress libraries load only when used."""
    heavy = {"pyvista", "vtk", "matplotlib", "meshio", "tqdm", "imageio"}
    code = f"import sys, fecontact; print(sorted(set(sys.modules) & {heavy!r}))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_a_quiet_run_of_graded_balls_prints_nothing(tmp_path):
    """The graded ball's refinement goes through scikit-fem's adaptive bisection, which logs
    its own array copies as warnings: a quiet run must not pass them on."""
    cmd = [sys.executable, "-m", "fecontact", "run", "two_balls", "--t-end", "1e-4"]
    done = subprocess.run(
        [*cmd, "--quiet", "--out", str(tmp_path)], capture_output=True, text=True, cwd=ROOT
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "" and done.stderr == ""
