"""Light installs: the core runs a case without the extras (rendering, sweeps, AMG, pandas),
and a command that needs a missing extra says in one line which one installs it."""

import subprocess
import sys
import textwrap

import pytest
from conftest import ROOT

EXTRAS = ["pyvista", "vtk", "vtkmodules", "matplotlib", "PIL", "imageio", "imageio_ffmpeg"]
EXTRAS += ["dask", "distributed", "pyamg", "pypardiso", "pandas", "h5py"]

BLOCKER = f"""
import importlib.abc, sys

class Blocker(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in {EXTRAS!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)

sys.meta_path.insert(0, Blocker())
"""


def without_extras(code: str, cwd) -> subprocess.CompletedProcess:
    """Run ``code`` in a fresh interpreter in which no extra can be imported."""
    script = BLOCKER + textwrap.dedent(code)
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", "OPENBLAS_NUM_THREADS": "1"}
    return subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=cwd, env=env
    )


def test_the_core_runs_a_case_without_any_extra(tmp_path):
    done = without_extras(
        """
        import sys
        import fecontact
        from fecontact.cli import main
        status = main(["run", "flexible_pendulum", "--t-end", "0.01", "--quiet"])
        loaded = sorted({m.split(".")[0] for m in sys.modules} & set(EXTRAS))
        print(status, loaded)
        """.replace("EXTRAS", repr(EXTRAS)),
        tmp_path,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[0] == "0 []"
    assert (tmp_path / "out" / "flexible_pendulum" / "summary.json").is_file()


@pytest.mark.parametrize(
    "argv, extra",
    [
        (["run", "flexible_pendulum", "--t-end", "0.01", "--quiet", "--render"], "render"),
        (["sweep", "flexible_pendulum", "--set", "restitution=0,1", "--quiet"], "sweep"),
        (["render", "."], "render"),
    ],
)
def test_a_missing_extra_is_one_line_naming_it(tmp_path, argv, extra):
    done = without_extras(
        f"import sys\nfrom fecontact.cli import main\nsys.exit(main({argv!r}))", tmp_path
    )
    err = done.stderr.strip()
    assert done.returncode == 2 and "\n" not in err, err
    assert f'pip install "fecontact[{extra}]"' in err
    assert not (tmp_path / "out").exists()  # said before any run


def test_the_amg_solver_names_its_extra(tmp_path):
    done = without_extras(
        """
        import fecontact
        from fecontact.linalg.sparse_solvers import use_sparse_solver
        try:
            use_sparse_solver("amg")
        except fecontact.InputError as err:
            print(err)
        """,
        tmp_path,
    )
    assert 'pip install "fecontact[amg]"' in done.stdout, done.stderr


def test_pandas_is_named_when_missing(tmp_path):
    from fecontact.cli import main

    out = tmp_path / "run"
    assert main(["run", "bouncing_ball", "--t-end", "0.005", "--quiet", "--out", str(out)]) == 0
    done = without_extras(
        f"""
        import fecontact
        try:
            fecontact.load_run({str(out)!r}).to_dataframe()
        except fecontact.InputError as err:
            print(err)
        """,
        tmp_path,
    )
    assert 'pip install "fecontact[pandas]"' in done.stdout, done.stderr


def test_the_test_extra_installs_every_extra_the_tests_use():
    project = pytest.importorskip("tomllib").loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = project["optional-dependencies"]
    core = " ".join(project["dependencies"])
    assert "pyvista" not in core and "dask" not in core and "pyamg" not in core
    test = extras["test"][0]
    for name in ("mp4", "sweep", "amg", "pandas", "vtkhdf"):
        assert name in test
    assert "fecontact[render]" in extras["mp4"]
