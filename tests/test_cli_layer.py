"""The command line as its own layer: the console script's entry points, ``--version``, the
bundled cases by name, and run options that are also case parameters."""

import json
import subprocess
import sys

import pytest
from conftest import ROOT

import fecontact
from fecontact.cli import bundled_cases, main


def test_version_is_the_package_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"fecontact {fecontact.__version__}"


def test_python_dash_m_reaches_the_same_command(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "fecontact", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0 and done.stdout.strip() == f"fecontact {fecontact.__version__}"


def test_the_console_script_entry_point_is_main():
    project = pytest.importorskip("tomllib").loads((ROOT / "pyproject.toml").read_text())
    scripts = project["project"]["scripts"]
    module, _, name = scripts["fecontact"].partition(":")
    __import__(module)
    assert getattr(sys.modules[module], name) is main


def test_cases_lists_every_case_file(capsys):
    assert main(["cases"]) == 0
    listed = [line.split()[0] for line in capsys.readouterr().out.splitlines()]
    assert listed == sorted(p.stem for p in (ROOT / "cases").glob("*.py"))
    assert set(bundled_cases()) == set(listed)


def test_a_bundled_case_runs_by_name_from_any_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["run", "bouncing_ball", "--t-end", "0.01", "--quiet"]) == 0
    summary = json.loads((tmp_path / "out" / "bouncing_ball" / "summary.json").read_text())
    assert summary["status"] == "completed" and summary["steps"] == 10
    assert main(["info", "flexible_pendulum"]) == 0
    assert "tip_mass" in capsys.readouterr().out


def test_an_unknown_case_name_lists_the_bundled_ones(capsys):
    assert main(["run", "no_such_case", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no_such_case" in err and "flexible_pendulum" in err


def test_t_end_given_twice_is_refused(tmp_path, capsys):
    argv = ["run", "two_disks", "--quiet", "--out", str(tmp_path), "--set", "t_end=0.001"]
    assert main([*argv, "--t-end", "0.002"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--t-end and --set t_end" in err
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("name", ["friction", "max_iterations"])
def test_a_set_name_given_twice_is_refused_as_a_sweep_refuses_it(tmp_path, capsys, name):
    argv = ["run", "flexible_pendulum", "--quiet", "--out", str(tmp_path)]
    assert main([*argv, "--set", f"{name}=3", "--set", f"{name}=2"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and f"--set {name} is given twice" in err
    assert not any(tmp_path.iterdir())


def test_the_summary_records_the_end_time_that_ran(tmp_path):
    """two_disks takes t_end as a parameter; --t-end replaces it, and the record says so."""
    argv = ["run", "two_disks", "--quiet", "--out", str(tmp_path), "--set", "refinements=0"]
    assert main([*argv, "--t-end", "0.0005"]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["t_end"] == summary["parameters"]["t_end"] == 0.0005
