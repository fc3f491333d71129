"""An output folder holds one run at a time: a lock taken before the case is built, a second
run into the folder refused in one line naming the running one, stale locks taken over."""

import json
import os
import subprocess
import sys
import time

import pytest
from conftest import ROOT

from fecontact.cli import main
from fecontact.io.run_lock import LOCK_FILE, hold_folder


def test_two_runs_started_at_once_into_one_folder(tmp_path):
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"}
    # (long enough that the second run starts while it runs, even on a loaded machine)
    first = ["run", "flexible_pendulum", "--t-end", "6", "--quiet", "--out", str(out)]
    proc = subprocess.Popen(
        [sys.executable, "-m", "fecontact", *first], env=env, stderr=subprocess.PIPE, text=True
    )
    deadline = time.monotonic() + 60
    while not (out / LOCK_FILE).exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    second = ["run", "flexible_pendulum", "--t-end", "0.01", "--quiet", "--out", str(out)]
    done = subprocess.run(
        [sys.executable, "-m", "fecontact", *second], env=env, capture_output=True, text=True
    )
    err = done.stderr.strip()
    assert done.returncode == 2 and "\n" not in err, err
    assert "in use by a run of case flexible_pendulum" in err and f"process {proc.pid}" in err
    assert proc.wait(timeout=300) == 0, proc.stderr.read()
    # the first run is whole: its own summary, its history from t = 0 to the end, its frames
    summary = json.loads((out / "summary.json").read_text())
    assert summary["case"] == "flexible_pendulum" and summary["status"] == "completed"
    assert len((out / "history.csv").read_text().splitlines()) == 1 + 6001
    assert summary["t_end"] == 6
    assert not (out / LOCK_FILE).exists()


def test_a_lock_left_by_a_dead_process_is_taken_over(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], text=True,
                          capture_output=True).stdout  # fmt: skip
    tmp_path.joinpath(LOCK_FILE).write_text(
        json.dumps({"pid": int(dead), "host": os.uname().nodename, "case": "x", "started": ""})
    )
    argv = ["run", "bouncing_ball", "--t-end", "0.01", "--quiet", "--out", str(tmp_path)]
    assert main(argv) == 0
    assert not (tmp_path / LOCK_FILE).exists()


def test_the_holder_may_enter_again_and_a_mistake_leaves_no_folder(tmp_path):
    out = tmp_path / "new"
    with hold_folder(out, "a"):
        with hold_folder(out, "a"):  # the command line, then run() inside it
            assert (out / LOCK_FILE).is_file()
        assert (out / LOCK_FILE).is_file()  # still held by the outer one
    assert not out.exists()  # nothing was written: the folder it made is gone again
    with pytest.raises(ValueError), hold_folder(out, "a"):
        raise ValueError
    assert not out.exists()


def test_the_lock_is_taken_before_build(tmp_path, capsys):
    """A folder held by another live process is refused before the case is built (a build
    that fails would say so otherwise)."""
    holder = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        record = {"pid": holder.pid, "host": os.uname().nodename, "case": "other", "started": ""}
        (tmp_path / LOCK_FILE).write_text(json.dumps(record))
        argv = ["run", "flexible_pendulum", "--quiet", "--set", "n_elements=0", "--out"]
        assert main([*argv, str(tmp_path)]) == 2
        err = capsys.readouterr().err
        assert "in use by a run of case other" in err and "build() failed" not in err
    finally:
        holder.kill()
        holder.wait()
