"""``fecontact sweep``: the product of parameter values on Dask, each run as ``fecontact run``
would do it, in its own folder, with one row per run in ``sweep.csv``."""

import csv
import json
import shutil

import pytest

from fecontact.cli.commands import main
from fecontact.testing import CASES

CASE = str(CASES / "flexible_pendulum.py")
RIGID = str(CASES / "rigid_pendulum.py")
# the summary figures of a run that do not depend on the machine's speed
FIGURES = ("status", "steps", "energy_final", "max_penetration", "newton_iterations_total")


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def summary(folder):
    return json.loads((folder / "summary.json").read_text())


def test_sweep_gives_the_figures_of_serial_runs(tmp_path):
    sweep = ["sweep", CASE, "--set", "restitution=0,0.5", "--set", "dt=1e-3,2e-3"]
    out = tmp_path / "sweep"
    assert main([*sweep, "--t-end", "0.4", "--workers", "2", "--quiet", "--out", str(out)]) == 0
    rows = read_rows(out / "sweep.csv")
    assert [(r["restitution"], r["dt"]) for r in rows] == [
        ("0", "0.001"),
        ("0", "0.002"),
        ("0.5", "0.001"),
        ("0.5", "0.002"),
    ]
    for row in rows:
        e, dt = row["restitution"], row["dt"]
        alone = tmp_path / f"serial-{e}-{dt}"
        run = ["run", CASE, "--set", f"restitution={e}", "--dt", dt, "--t-end", "0.4"]
        assert main([*run, "--quiet", "--out", str(alone)]) == 0
        serial = summary(alone)
        for key in FIGURES:  # written at full precision: the same runs give the same digits
            assert row[key] == str(serial[key]), key
        # the extremes of the probes over the run
        assert float(row["tip_x_max"]) == pytest.approx(0.3, rel=1e-3)
        assert float(row["tip_y_min"]) < -0.29


def test_a_second_call_runs_only_what_is_missing_and_failures_are_recorded(tmp_path):
    out = tmp_path / "sweep"
    args = ["sweep", CASE, "--set", "max_iterations=1,30", "--t-end", "0.4", "--quiet"]
    assert main([*args, "--workers", "2", "--out", str(out)]) == 1  # one run failed
    rows = read_rows(out / "sweep.csv")
    assert [r["status"] for r in rows] == ["failed", "completed"]
    assert "Newton did not converge" in rows[0]["message"]
    done = out / "max_iterations=30" / "summary.json"
    stamp = done.stat().st_mtime_ns
    assert main([*args, "--workers", "1", "--out", str(out)]) == 1  # the failed one again
    assert done.stat().st_mtime_ns == stamp  # the completed run was not repeated
    assert [r["status"] for r in read_rows(out / "sweep.csv")] == ["failed", "completed"]


def test_sweep_on_a_running_scheduler(tmp_path):
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster:
        out = tmp_path / "sweep"
        args = ["sweep", CASE, "--set", "restitution=0,1", "--t-end", "0.35", "--quiet"]
        assert main([*args, "--scheduler", cluster.scheduler_address, "--out", str(out)]) == 0
    rows = read_rows(out / "sweep.csv")
    assert [r["status"] for r in rows] == ["completed", "completed"]
    assert float(rows[1]["energy_final"]) > float(rows[0]["energy_final"])  # e = 1 keeps more


def test_a_deleted_run_is_the_only_one_run_again(tmp_path):
    out = tmp_path / "sweep"
    args = ["sweep", RIGID, "--set", "restitution=0,0.5,1", "--t-end", "0.05", "--quiet"]
    assert main([*args, "--workers", "2", "--out", str(out)]) == 0
    first = read_rows(out / "sweep.csv")
    stamps = {p.parent.name: p.stat().st_mtime_ns for p in out.glob("*/summary.json")}
    assert sorted(stamps) == ["restitution=0", "restitution=0.5", "restitution=1"]
    shutil.rmtree(out / "restitution=0.5")
    assert main([*args, "--workers", "2", "--out", str(out)]) == 0
    again = {p.parent.name: p.stat().st_mtime_ns for p in out.glob("*/summary.json")}
    assert sorted(again) == sorted(stamps)
    assert [k for k in stamps if again[k] != stamps[k]] == ["restitution=0.5"]
    rows = read_rows(out / "sweep.csv")  # the same figures, rebuilt from the summaries
    for key in ("restitution", "status", "steps", "energy_final", "theta_min", "omega_max"):
        assert [r[key] for r in rows] == [r[key] for r in first], key


def test_the_longest_runs_go_first(tmp_path):
    # one worker runs one task at a time: the order of the summaries is the order of the runs
    out = tmp_path / "sweep"
    args = ["sweep", RIGID, "--set", "dt=2e-3,5e-4,1e-3", "--t-end", "0.05", "--quiet"]
    assert main([*args, "--workers", "1", "--out", str(out)]) == 0
    done = sorted(out.glob("*/summary.json"), key=lambda p: p.stat().st_mtime_ns)
    assert [p.parent.name for p in done] == ["dt=5e-4", "dt=1e-3", "dt=2e-3"]
    # sweep.csv keeps the order of the product
    assert [r["dt"] for r in read_rows(out / "sweep.csv")] == ["0.002", "0.0005", "0.001"]


@pytest.mark.parametrize(
    "bad, words",
    [
        (["--set", "restitution=0,x"], "restitution"),
        (["--set", "restitution=0,x,2"], "restitution"),
        (["--set", "rho_inf=0.5,1.5"], "rho_inf"),
        (["--set", "restitution=0,2"], "restitution"),
        (["--set", "colour=red,blue"], "unknown parameter 'colour'"),
        (["--set", "dt=1e-3,", "--t-end", "0.1"], "empty value"),
        (["--set", "dt=1e-3,2e-3", "--dt", "1e-3"], "--dt and --set dt"),
        (["--set", "restitution=0,1", "--workers", "0"], "--workers"),
    ],
)
def test_bad_sweeps_stop_before_any_run(tmp_path, capsys, bad, words):
    out = tmp_path / "sweep"
    assert main(["sweep", CASE, *bad, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0]
    assert not out.exists()
