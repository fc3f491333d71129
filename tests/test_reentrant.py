"""Runs own everything they count and solve with: two runs of different cases in two threads
of one process write the same histories and report the same statistics as the same runs
made one after the other."""

import json
import threading

import numpy as np

from fecontact import run
from fecontact.io.output import read_history
from fecontact.testing import case

# a frictional beam case whose smooth Newton globalizes (line-search cuts), and a solid case
# with smooth contact whose sparse matrices are factorized: every kind of count is non-zero
# in at least one of them
RUNS = {
    "flexible_pendulum": ({"restitution": 0.5}, 0.4),
    "two_disks": ({"refinements": 2}, 0.004),
}

# what differs between two runs of the same thing: the wall clock, and the peak resident
# memory, which is the process's (getrusage), shared by the threads
TIMINGS = (
    "wall_time_s",
    "time_per_step_s",
    "phase_times_s",
    "seconds",
    "setup_seconds",
    "peak_memory_mb",
)


def _without_timings(x):
    if isinstance(x, dict):
        return {k: _without_timings(v) for k, v in x.items() if k not in TIMINGS}
    return x


def _run(name, out, results):
    parameters, t_end = RUNS[name]
    sim = case(name).build(**parameters).replace(t_end=t_end)
    run(sim, out, frames=False, checkpoint_every=0)
    summary = json.loads((out / "summary.json").read_text())
    results[name] = (read_history(out / "history.csv"), _without_timings(summary))


def test_two_runs_in_two_threads_match_the_same_runs_made_serially(tmp_path):
    serial, threaded = {}, {}
    for name in RUNS:
        _run(name, tmp_path / "serial" / name, serial)
    threads = [
        threading.Thread(target=_run, args=(name, tmp_path / "threads" / name, threaded))
        for name in RUNS
    ]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert set(threaded) == set(RUNS)
    for name in RUNS:
        history, summary = serial[name]
        history_t, summary_t = threaded[name]
        assert list(history_t) == list(history)
        for column in history:  # the same arithmetic in the same order: identical bits
            np.testing.assert_array_equal(history_t[column], history[column], err_msg=column)
        assert summary_t == summary
    pendulum, disks = serial["flexible_pendulum"][1], serial["two_disks"][1]
    # the counts compared are not all zero: mixed, each run would count the other's too
    assert pendulum["smooth_newton"]["line_search_cuts"] > 0
    assert min(pendulum["smooth_newton"]["iterations"], disks["smooth_newton"]["iterations"]) > 0
    assert disks["sparse_factorizations"]["count"] > 0
    assert pendulum["sparse_factorizations"]["count"] == 0  # (a dense beam model)
