"""What a user's workflow around a run needs: the history as a pandas table, progress in logs
and notebooks, sweeps on any scheduler, BLAS threads limited inside a run only."""

import importlib.util

import numpy as np
import pytest

from fecontact import load_run
from fecontact.cli import main


@pytest.fixture(scope="module")
def pendulum_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("pendulum")
    argv = ["run", "flexible_pendulum", "--t-end", "0.05", "--quiet", "--out", str(out)]
    assert main(argv) == 0
    return out


def test_history_and_probes_as_a_dataframe(pendulum_run):
    pd = pytest.importorskip("pandas")
    run = load_run(pendulum_run)
    frame = run.to_dataframe()
    assert isinstance(frame, pd.DataFrame) and frame.index.name == "t"
    np.testing.assert_array_equal(frame.index.to_numpy(), run.history["t"])
    for name in ("tip_x", "tip_y", "tip_vx", "tip_vy", "kinetic_energy"):
        np.testing.assert_array_equal(frame[name].to_numpy(), run.history[name])
    assert len(frame) == 51  # t = 0 and 50 steps of 1 ms
    units = frame.attrs["units"]
    assert units.keys() == set(frame.columns)  # (before: the probes' only)
    probes = {"tip_x": "m", "tip_y": "m", "tip_vx": "m/s", "tip_vy": "m/s"}
    assert probes.items() <= units.items()
    assert units["kinetic_energy"] == units["numerical_dissipation"] == "J"
    assert (units["min_gap"], units["impulse"], units["dt"], units["n_active"]) == (
        "m",
        "N·s",
        "s",
        "",
    )
    # a notebook shows the run, not its arrays (before: every history column in full)
    text = repr(run)
    assert text == (
        f"RunResult({str(run.out_dir)!r}: flexible_pendulum, completed, 51 history rows to "
        "t = 0.05 s, 6 frames of obstacle0, beam2d0)"
    )


def test_progress_in_a_log_is_a_line_per_tenth_of_the_run(tmp_path, capsys):
    """stderr is not a terminal here (as in a batch job's log): a line at the start, at every
    10 % of the end time and at the end, and no bar's carriage returns."""
    argv = ["run", "flexible_pendulum", "--t-end", "0.1", "--out", str(tmp_path)]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "\r" not in err
    lines = [line for line in err.splitlines() if line.startswith("flexible_pendulum: ")]
    assert "starts at t = 0 s (step 0), t_end = 0.1 s" in lines[0]
    assert [line.split()[1] for line in lines[1:-1]] == [f"{p}%" for p in range(10, 100, 10)]
    for line, p in zip(lines[1:-1], range(10, 100, 10), strict=True):
        t = float(line.split("t = ")[1].split()[0])
        assert p / 1000 <= t < p / 1000 + 0.0011  # the first step at or past the tenth
    assert lines[-1].startswith("flexible_pendulum: ends at t = 0.1 s, step 100")


def test_progress_of_a_resumed_run_starts_where_it_resumes(tmp_path, capsys):
    argv = ["run", "flexible_pendulum", "--out", str(tmp_path), "--checkpoint-every", "50"]
    assert main([*argv, "--t-end", "0.06", "--quiet"]) == 0
    capsys.readouterr()
    assert main([*argv, "--t-end", "0.1", "--resume"]) == 0
    lines = [x for x in capsys.readouterr().err.splitlines() if x.startswith("flexible")]
    assert "resumes at t = 0.05 s (step 50)" in lines[0]
    assert [line.split()[1] for line in lines[1:-1]] == ["60%", "70%", "80%", "90%"]


def test_a_notebook_gets_a_bar(monkeypatch):
    import io

    from fecontact.io import progress

    assert not progress.in_notebook()  # pytest is no Jupyter kernel
    monkeypatch.setattr(progress, "in_notebook", lambda: True)
    stream = io.StringIO()
    bar = progress.RunProgress("case", t_end=1.0, dt=0.1, stream=stream)
    assert bar.bar is not None and bar.bar.total == 10  # tqdm.auto's bar, not log lines
    bar.close()
    assert "case: starts" not in stream.getvalue()


def test_a_notebook_without_ipywidgets_gets_the_text_bar_without_a_warning():
    # (before: tqdm.auto warned "IProgress not found" into the cell, then drew the text bar)
    import subprocess
    import sys

    code = """
import sys, types, warnings
import IPython
for name in ("ipykernel", "ipykernel.zmqshell"):  # a Jupyter kernel, as tqdm sees one
    sys.modules[name] = types.ModuleType(name)
IPython.get_ipython = lambda: types.SimpleNamespace(config={"IPKernelApp": {}})
from fecontact.io import progress
warnings.simplefilter("always")
bar = progress.RunProgress("case", t_end=1.0, dt=0.1, stream=sys.stderr)
bar.close()
print(type(bar.bar).__module__)
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0 and "Warning" not in done.stderr, done.stderr
    widgets = importlib.util.find_spec("ipywidgets") is not None
    assert done.stdout.split() == ["tqdm.notebook" if widgets else "tqdm.std"]


def test_blas_threads_are_limited_inside_a_run_only(tmp_path):
    """Import sets no environment variable; a run steps with one BLAS thread and gives the
    pool back afterwards (threadpoolctl). Checked in a fresh interpreter with a clean
    environment, BLAS pools of 2 threads."""
    import subprocess
    import sys

    from conftest import ROOT

    code = """
import os, json
import fecontact
from threadpoolctl import threadpool_info, threadpool_limits
from fecontact import Probe, run
from fecontact.testing import case

def blas():
    return max(p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas")

threadpool_limits(limits=2, user_api="blas")
inside = []
sim = case("bouncing_ball").build()
probe = Probe(lambda m, st: inside.append(blas()) or 0.0, "-", "BLAS threads")
sim = sim.replace(t_end=0.003, probes={**sim.probes, "threads": probe})
run(sim, os.environ["OUT"], frames=False)
print(json.dumps([os.environ.get("OPENBLAS_NUM_THREADS"), sorted(set(inside)), blas()]))
"""
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT), "OUT": str(tmp_path)}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    import json

    assert json.loads(done.stdout.splitlines()[-1]) == [None, [1], 2]


def test_a_sweep_with_a_relative_out_on_a_scheduler(tmp_path, monkeypatch):
    """The scheduler's workers run in another folder than the command: a relative --out is
    made absolute before the runs are submitted."""
    pytest.importorskip("distributed")
    from dask.distributed import LocalCluster

    (tmp_path / "workers").mkdir()
    (tmp_path / "here").mkdir()
    monkeypatch.chdir(tmp_path / "workers")  # the workers start, and stay, here
    with LocalCluster(n_workers=1, threads_per_worker=1, dashboard_address=":0") as cluster:
        monkeypatch.chdir(tmp_path / "here")
        argv = ["sweep", "bouncing_ball", "--set", "restitution=0,1", "--t-end", "0.05"]
        argv += ["--quiet", "--scheduler", cluster.scheduler_address, "--out", "sweep"]
        assert main(argv) == 0
    rows = (tmp_path / "here" / "sweep" / "sweep.csv").read_text().splitlines()
    assert len(rows) == 3 and all(",completed," in row for row in rows[1:])
    assert not (tmp_path / "workers" / "sweep").exists()


def test_a_sweep_in_a_log_says_each_run_done(tmp_path, capsys):
    pytest.importorskip("distributed")
    argv = ["sweep", "bouncing_ball", "--set", "restitution=0,1", "--t-end", "0.05"]
    assert main([*argv, "--workers", "1", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    assert "\r" not in captured.err
    lines = [x for x in captured.err.splitlines() if x.startswith("sweep: ")]
    assert lines == ["sweep: 1 of 2 runs done, 0 failed", "sweep: 2 of 2 runs done, 0 failed"]
    assert "2 runs (2 run now, 0 failed)" in captured.out
