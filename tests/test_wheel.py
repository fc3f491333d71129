"""The wheel: built from the source tree, installed into a fresh environment, it carries the
bundled cases and runs one from any folder."""

import os
import shutil
import subprocess
import sys
import zipfile

import pytest
from conftest import ROOT

SOURCES = ["pyproject.toml", "setup.py", "README.md", "LICENSE", "fecontact", "cases"]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    """A wheel built from a copy of the source tree (the tree itself stays clean)."""
    tree = tmp_path_factory.mktemp("source")
    for name in SOURCES:
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, tree / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy(src, tree / name)
    dist = tmp_path_factory.mktemp("dist")
    build = [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q"]
    done = subprocess.run([*build, "-w", str(dist), str(tree)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    (path,) = dist.glob("fecontact-*.whl")
    return path


def test_the_wheel_carries_every_case_file_and_the_package(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for case in (ROOT / "cases").glob("*.py"):
        assert f"fecontact/cases/{case.name}" in names
    for module in (ROOT / "fecontact").rglob("*.py"):
        assert module.relative_to(ROOT).as_posix() in names
    assert not any(n.startswith("cases/") for n in names)  # one place: fecontact/cases


@pytest.mark.slow
def test_a_wheel_install_runs_a_bundled_case_from_another_folder(wheel, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = venv / "bin" / "python"
    install = [str(python), "-m", "pip", "install", "--no-deps", "-q", str(wheel)]
    done = subprocess.run(install, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["OPENBLAS_NUM_THREADS"] = "1"

    def call(*argv):
        done = subprocess.run(argv, capture_output=True, text=True, cwd=elsewhere, env=env)
        assert done.returncode == 0, done.stderr
        return done.stdout

    where = call(str(python), "-c", "import fecontact; print(fecontact.__file__)")
    assert where.startswith(str(venv))  # the wheel's copy, not the source tree
    call(str(venv / "bin" / "fecontact"), "run", "flexible_pendulum", "--t-end", "0.01", "--quiet")
    assert (elsewhere / "out" / "flexible_pendulum" / "summary.json").is_file()
    assert "flexible_pendulum" in call(str(venv / "bin" / "fecontact"), "cases")
    code = "from fecontact.testing import case; print(case('bouncing_ball').build().name)"
    assert call(str(python), "-c", code).strip() == "bouncing_ball"
