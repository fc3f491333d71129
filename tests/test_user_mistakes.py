"""Mistakes a user makes get one clear line naming what is wrong, before anything is written."""

import pytest
from conftest import ROOT

from fecontact import (
    Beam2D,
    InputError,
    IntegratorOptions,
    LinearElastic,
    Material,
    Model,
    Probe,
    Section,
    Simulation,
    Solid,
    node_probe,
)
from fecontact.io.cli import main

CASE = str(ROOT / "cases" / "flexible_pendulum.py")


def beam():
    return Beam2D.straight([0, 0], [1, 0], 2, Material(E=1e9, rho=1e3), Section.circle(0.01))


def one_line_error(capsys, argv, *words):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and len(err) <= 200 and all(w in err for w in words), err


def test_out_that_is_a_file_or_under_a_file(tmp_path, capsys):
    f = tmp_path / "taken"
    f.write_text("x")
    one_line_error(capsys, ["run", CASE, "--quiet", "--t-end", "0.01", "--out", str(f)], "out")
    under = f / "run"
    one_line_error(capsys, ["run", CASE, "--quiet", "--t-end", "0.01", "--out", str(under)], "out")


def test_info_into_a_closed_pipe_is_quiet():
    import subprocess
    import sys

    cmd = f"{sys.executable} -m fecontact info {CASE} | head -n 1"
    done = subprocess.run(cmd, shell=True, capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0 and "Traceback" not in done.stderr


def test_poisson_ratio_of_a_beam_is_below_a_half():
    with pytest.raises(InputError, match=r"nu must be in \(-1, 0.5\)"):
        Material(E=1e9, rho=1e3, nu=0.5)


def test_max_iterations_at_least_one():
    with pytest.raises(InputError, match="max_iterations"):
        IntegratorOptions(max_iterations=0)


def test_rotation_probe_of_a_solid_node_is_refused_at_once():
    body = Solid.rectangle([0, 0], [1, 1], 1, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    model = Model([body])
    with pytest.raises(InputError, match="rotation"):
        node_probe(model, body, 0, "rotation")


def test_the_same_body_twice():
    b = beam()
    with pytest.raises(InputError, match="twice"):
        Model([b, b])


@pytest.mark.parametrize("name", ["t", "a,b", "total_energy", ""])
def test_probe_names_clashing_with_history_columns(name):
    model = Model([beam().pin(0)])
    probe = Probe(lambda m, st: 0.0, "m")
    with pytest.raises(InputError, match="probe names"):
        Simulation(model, dt=1e-3, t_end=0.01, probes={name: probe})


def test_a_step_longer_than_the_run_is_said(tmp_path, capsys):
    argv = ["run", CASE, "--quiet", "--dt", "1", "--t-end", "0.5", "--out", str(tmp_path)]
    assert main(argv) == 0
    assert "longer than the run" in capsys.readouterr().err
