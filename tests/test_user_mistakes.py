"""Mistakes a user makes get one clear line naming what is wrong, before anything is written."""

import numpy as np
import pytest
from conftest import ROOT

from fecontact import (
    Ball,
    Beam2D,
    Beam3D,
    Circle,
    Contact,
    ConvexMesh,
    Disk,
    InputError,
    IntegratorOptions,
    LinearElastic,
    Material,
    Model,
    NodalLoad,
    Pin,
    Plane,
    Probe,
    Section,
    Simulation,
    Solid,
    node_probe,
    run,
    simulate,
)
from fecontact.cli.commands import main
from fecontact.time.state import INTEGRATORS, READERS

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
        Material(E=1e9, nu=0.5, rho=1e3)


def test_max_iterations_at_least_one():
    with pytest.raises(InputError, match="max_iterations"):
        IntegratorOptions(max_iterations=0)


@pytest.mark.parametrize(
    "options, words",
    [
        ({"integrator": "moreau", "smooth_contact": "on"}, "smooth_contact = 'on'"),
        ({"penalty_stiffness": 1e6}, "penalty_stiffness is an option of integrator 'penalty'"),
        ({"integrator": "moreau", "penalty_damping": 0.0}, "penalty_damping"),
    ],
)
def test_a_choice_of_another_integrator_is_refused(options, words):
    # (before: taken, and read by no step)
    with pytest.raises(InputError, match=words):
        IntegratorOptions(**options)


# a value off the default of every option that only some integrators read
OFF_DEFAULT = {
    "rho_inf": 0.3,
    "metric": "mass",
    "penalty_scale": 2.0,
    "multiplier_scale": 2.0,
    "impact_velocity": "step_start",
    "theta": 0.6,
    "penalty_stiffness": 1e6,
    "penalty_damping": 0.1,
    "smooth_contact": "off",
    "scheme": "energy-decaying",
    "impact_law": "poisson",
    "localize": False,
    "rtol": 1e-4,
    "energy_retakes": False,
}


@pytest.mark.parametrize("name", sorted(READERS))
def test_an_option_is_taken_by_its_integrators_and_refused_by_the_others(name):
    # (before: theta with nsga, rho_inf with moreau, localize=0 with penalty, ... were
    # taken and read by no step)
    for integrator in INTEGRATORS:
        options = {"integrator": integrator, name: OFF_DEFAULT[name]}
        if integrator in READERS[name]:
            assert getattr(IntegratorOptions(**options), name) == OFF_DEFAULT[name]
            continue
        with pytest.raises(InputError, match=f"{name}.*{integrator}"):
            IntegratorOptions(**options)


def test_an_option_no_step_reads_stops_the_command_line_before_any_file(tmp_path, capsys):
    out = tmp_path / "run"
    argv = ["run", "bouncing_ball", "--set", "theta=0.3", "--out", str(out), "--quiet"]
    one_line_error(capsys, argv, "theta", "moreau", "'nsga'")
    assert not out.exists()


def test_rotation_probe_of_a_solid_node_is_refused_at_once():
    body = Solid.rectangle([0, 0], [1, 1], 1, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    model = Model([body])
    with pytest.raises(InputError, match="rotation"):
        node_probe(model, body, 0, "rotation")


def test_the_same_body_twice():
    b = beam()
    with pytest.raises(InputError, match="twice"):
        Model([b, b])


def model_arguments():
    b = beam().pin(0)
    plane = Plane([0, -1], [0, 1])
    return [
        ({"bodies": b}, "bodies must be a list, each entry a body .*; got Beam2D"),
        ({"bodies": [b, plane]}, r"bodies\[1\] must be a body .*, got Plane"),
        ({"bodies": [b], "contacts": [plane]}, r"contacts\[0\] must be a pair made by Contact"),
        ({"bodies": [b], "contacts": Contact(b, plane)}, "contacts must be a list"),
        ({"bodies": [b], "joints": [b]}, r"joints\[0\] must be a joint .*, got Beam2D"),
        ({"bodies": [b], "loads": [np.zeros(3)]}, r"loads\[0\] must be a NodalLoad"),
        ({"bodies": 5}, "bodies must be a list, each entry a body .*; got int"),
    ]


@pytest.mark.parametrize("k", range(7))
def test_model_arguments_of_the_wrong_kind_name_the_argument_and_entry(k):
    keywords, words = model_arguments()[k]
    with pytest.raises(InputError, match=words):
        Model(**keywords)


def arguments_of_the_wrong_kind():
    solid = LinearElastic(E=1e6, nu=0.3, rho=1e3)
    model = Model([beam().pin(0)])
    steel, tube = Material(E=2e11, rho=7800.0), Section.circle(0.01)
    options = {"rho_inf": 0.5}
    return [
        (lambda: Beam2D.straight([0, 0], [1, 0], 2, solid, tube), "material must be a beam Mat"),
        (lambda: Beam3D.straight([0, 0, 0], [1, 0, 0], 2, steel, 1.0), "section must be a Sec"),
        (lambda: Beam2D.straight(5.0, [1, 0], 2, steel, tube), "start must have 2 components"),
        (lambda: Contact(0.5, Plane([0, 0], [0, 1])), "body must be a body .*, got float"),
        (lambda: Pin(None, [0, 0]), "body must be a body .*, got NoneType"),
        (lambda: Simulation(beam(), dt=1e-3, t_end=0.01), "model must be a Model"),
        (lambda: Simulation(model, 1e-3, 0.01, options=options), "options must be an Integ"),
        (lambda: Ball(0.1, n_rim=float("nan")), r"n_rim must be an integer in \[8, "),
        (lambda: Disk(0.1, n_outline="48"), r"n_outline must be an integer in \[8, "),
        (lambda: ConvexMesh("x"), "points must be real numbers"),
        (lambda: Circle([0, 0], 1.0, inside="no"), "inside must be True or False, got str"),
        (lambda: Plane([0, 0], [0, 1], velocity=lambda t: [0, 1]), "give motion"),
        (lambda: Solid("block.msh", solid), "got str; read a mesh file with Solid.from_file"),
        (lambda: Solid.rectangle([0, 0], [1, 1], 1, steel), "material must be a solid's mat"),
    ]  # fmt: skip


@pytest.mark.parametrize("k", range(14))
def test_arguments_of_the_wrong_kind_are_named_with_what_they_take(k):
    make, words = arguments_of_the_wrong_kind()[k]
    with pytest.raises(InputError, match=words):
        make()


def test_a_body_left_out_of_the_model_is_named_whatever_refers_to_it():
    b, other = beam().pin(0), beam()
    model = Model([b])
    for refer in (
        lambda: node_probe(model, other, 0, "x"),  # a ValueError of list.index
        lambda: model.translation(other, [0.0, 1.0]),  # said "a contact refers to ..."
        lambda: Model([b], loads=[NodalLoad(other, 0, [0.0, 1.0, 0.0])]),
    ):
        with pytest.raises(InputError, match="a Beam2D that is not among the model's bodies"):
            refer()
    with pytest.raises(InputError, match=r"^vector must have 2 components, got 3$"):
        model.translation(b, [0.0, 0.0, 1.0])


def run_mistakes(tmp_path):
    def loaded(value):
        b = beam().pin(0)
        return Simulation(Model([b], loads=[NodalLoad(b, 2, value)]), dt=1e-3, t_end=0.003)

    def probed(fn):
        return Simulation(Model([beam().pin(0)]), 1e-3, 0.003, probes={"p": Probe(fn, "m")})

    sim, out = loaded(lambda t: [0.0, -1.0, 0.0]), tmp_path / "out"
    return [
        (lambda: run(loaded(lambda t: [np.nan * t, 0.0, 0.0]), out), "load on node 2 at t = 0 s"),
        (lambda: run(loaded(lambda t: [1.0, 0.0]), out), "load on node 2 .* 3 components"),
        (lambda: run(probed(lambda m, st: "abc"), out), "probe 'p' must return a number"),
        (lambda: run(probed(lambda m, st: [1.0, 2.0]), out), "probe 'p' must return a number"),
        (lambda: Probe(3.0, "m"), "fn must be a function"),
        (lambda: Simulation(sim.model, 1e-3, 0.01, probes={"p": 3.0}), r"probes\['p'\] must be"),
        (lambda: run(sim, None), "out_dir must be a folder path, got NoneType"),
        (lambda: run(sim, out, progress="no"), "progress must be True or False, got str"),
        (lambda: run(sim, out, checkpoint_every=-1), "checkpoint_every must be an integer in"),
    ]


@pytest.mark.parametrize("k", range(9))
def test_loads_probes_and_run_arguments_of_the_wrong_kind_are_named(tmp_path, k):
    # a NaN load diverged as "an element inverts", a string probe failed in the csv writer
    make, words = run_mistakes(tmp_path)[k]
    with pytest.raises(InputError, match=words):
        make()


@pytest.mark.parametrize("name", ["t", "a,b", "total_energy", ""])
def test_probe_names_clashing_with_history_columns(name):
    model = Model([beam().pin(0)])
    probe = Probe(lambda m, st: 0.0, "m")
    with pytest.raises(InputError, match="probe names"):
        Simulation(model, dt=1e-3, t_end=0.01, probes={name: probe})


def test_a_step_longer_than_the_run_is_said(tmp_path, capsys):
    # the run ends before the first impact (0.319 s): what is tested is the warning and the
    # single step, not the strip's impact taken in a halved step of 0.125 s (the tip 0.3 m
    # into the stop; that run completed before the velocity followed the correction's strain,
    # 0.066 J above its start after the impact, and fails 8 ms later since)
    argv = ["run", CASE, "--quiet", "--dt", "1", "--t-end", "0.3", "--out", str(tmp_path)]
    assert main(argv) == 0
    assert "longer than the run" in capsys.readouterr().err


def case_file(tmp_path, body):
    path = tmp_path / "mycase.py"
    path.write_text(
        "from fecontact import Beam2D, Material, Model, Section, Simulation\n\n" + body + "\n"
    )
    return str(path)


@pytest.mark.parametrize(
    "body, words",
    [
        ("def build():\n    raise RuntimeError('boom')", ("mycase", "boom", "--debug")),
        ("def build():\n    return 42", ("mycase", "Simulation", "int")),
        ("def build(a):\n    return a", ("mycase", "build() failed")),
    ],
)
def test_a_failing_build_is_one_line(tmp_path, capsys, body, words):
    one_line_error(capsys, ["run", case_file(tmp_path, body), "--out", str(tmp_path / "o")], *words)
    assert not (tmp_path / "o").exists()


def test_debug_shows_the_users_traceback(tmp_path):
    path = case_file(tmp_path, "def build():\n    raise RuntimeError('boom')")
    with pytest.raises(RuntimeError, match="boom"):
        main(["run", path, "--debug", "--out", str(tmp_path / "o")])


@pytest.mark.parametrize("content", [b"", b"garbage", b"PK\x03\x04truncated"])
def test_a_broken_checkpoint_is_one_line(tmp_path, capsys, content):
    args = ["run", CASE, "--quiet", "--t-end", "0.01", "--out", str(tmp_path)]
    assert main(args) == 0
    (tmp_path / "checkpoint.npz").write_bytes(content)
    one_line_error(capsys, [*args, "--resume"], "checkpoint")


@pytest.mark.parametrize("content", ["", "garbage\n", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"])
def test_an_unreadable_mesh_is_one_line(tmp_path, content):
    path = tmp_path / "bad.msh"
    path.write_text(content)
    with pytest.raises(InputError, match="bad.msh") as err:
        Solid.from_file(path, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    assert "\n" not in str(err.value)


def test_nan_in_a_large_array_is_named_without_the_array():
    body = Solid.rectangle([0, 0], [1, 1], 8, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    model = Model([body], gravity=(0.0, 0.0))
    v0 = np.zeros(model.n)
    v0[5] = np.nan
    with pytest.raises(InputError) as err:
        next(simulate(model, 1e-3, 0.01, v0=v0))
    assert len(str(err.value)) <= 200 and "entry 5" in str(err.value)


def test_runs_never_mix(tmp_path, capsys):
    out = tmp_path / "run"
    args = ["--quiet", "--t-end", "0.02", "--out", str(out)]
    assert main(["run", CASE, *args, "--output-interval", "0.001"]) == 0
    many = len(list(out.glob("*.vtu")))
    assert main(["run", CASE, *args]) == 0  # the same case again: a clean start
    assert len(list(out.glob("*.vtu"))) < many
    other = str(ROOT / "cases" / "bouncing_ball.py")
    one_line_error(capsys, ["run", other, *args], "flexible_pendulum", "--overwrite")
    assert main(["run", other, *args, "--overwrite"]) == 0
    assert [p.stem for p in out.glob("*.pvd")] == ["bouncing_ball"]


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    out = tmp_path_factory.mktemp("finished")
    assert main(["run", CASE, "--quiet", "--t-end", "0.03", "--out", str(out)]) == 0
    return out


def testrender_targets_that_are_not_a_run(finished, tmp_path, capsys):
    one_line_error(capsys, ["render", str(finished / "history.csv")], "run folder or its .pvd")
    empty = tmp_path / "empty.pvd"
    empty.write_text("")
    one_line_error(capsys, ["render", str(empty)], "render")
    plain = tmp_path / "plain.pvd"
    plain.write_text('<VTKFile type="UnstructuredGrid"></VTKFile>')
    one_line_error(capsys, ["render", str(plain)], "Collection")


def test_render_of_a_run_with_a_missing_or_junk_frame(finished, tmp_path, capsys):
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(finished, copy)
    frames = sorted(copy.glob("flexible_pendulum_beam2d0_*.vtu"))
    frames[-1].unlink()
    one_line_error(capsys, ["render", str(copy)], frames[-1].name, "missing")
    frames[-1].write_text("junk")
    one_line_error(capsys, ["render", str(copy)], frames[-1].name, "not a VTU")


def test_render_takes_the_pvd_it_is_given_among_several(finished, tmp_path):
    import shutil

    copy = tmp_path / "two"
    shutil.copytree(finished, copy)
    shutil.copy(copy / "flexible_pendulum.pvd", copy / "other.pvd")
    from fecontact.cli.commands import render_target

    assert render_target(copy / "other.pvd").name == "other.pvd"


def test_resume_to_an_earlier_end_is_refused(tmp_path, capsys):
    args = ["run", CASE, "--quiet", "--checkpoint-every", "10", "--out", str(tmp_path)]
    assert main([*args, "--t-end", "0.05"]) == 0
    history = (tmp_path / "history.csv").read_text()
    one_line_error(capsys, [*args, "--t-end", "0.02", "--resume"], "past t_end")
    assert (tmp_path / "history.csv").read_text() == history


def test_a_tiny_mass_is_blamed_on_the_mass():
    from fecontact import Disk, RigidBody2D

    with pytest.raises(InputError, match="^mass"):
        RigidBody2D.uniform(1e-29, [0.0, 0.0], Disk(0.1))


def test_rho_inf_one_with_plastic_impacts_warns(tmp_path, capsys):
    argv = ["run", CASE, "--quiet", "--t-end", "0.01", "--set", "rho_inf=1", "--out", str(tmp_path)]
    assert main(argv) == 0
    assert "restitution 0" in capsys.readouterr().err


def test_summary_counts_least_squares_multipliers(tmp_path):
    import json

    assert main(["run", CASE, "--quiet", "--t-end", "0.01", "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["least_squares_multipliers"] == 0  # one contact: never redundant


def test_a_degenerate_quad_is_named():
    import skfem

    corners = np.array([[0, 1, 1, 0], [0, 0, 0, 0]], float)
    mesh = skfem.MeshQuad(corners, np.array([[0], [1], [2], [3]]))
    with pytest.raises(InputError, match="degenerate"):
        Solid(mesh, LinearElastic(E=1e6, nu=0.3, rho=1e3))


def test_redundant_joints_are_refused_before_the_run():
    from fecontact import Pin

    with pytest.raises(InputError, match="already"):
        b = beam()
        Model([b], joints=[Pin(b, [0, 0]), Pin(b, [0, 0])])
    with pytest.raises(InputError, match="already"):
        b = beam().clamp(0)
        Model([b], joints=[Pin(b, [0, 0])])
    b = beam()
    Model([b], joints=[Pin(b, [0, 0])])  # one pin alone holds


def test_a_full_disk_mid_run_is_one_line_and_keeps_a_readable_index(tmp_path, monkeypatch, capsys):
    import errno

    import fecontact.io.pvd as output  # the .pvd writer writes the frames
    from fecontact.cli.commands import main
    from fecontact.io.output import load_run
    from fecontact.testing import CASES

    real, calls = output.write_vtu, {"n": 0}

    def fills_up(path, mesh):
        calls["n"] += 1
        if calls["n"] > 4:  # the disk is full from the fifth file on
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return real(path, mesh)

    monkeypatch.setattr(output, "write_vtu", fills_up)
    out = tmp_path / "run"
    args = ["run", str(CASES / "bouncing_ball.py"), "--quiet", "--out", str(out)]
    assert main([*args, "--t-end", "0.5", "--checkpoint-every", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "No space left on device" in err[0] and len(err[0]) <= 200
    # the frames written before stay listed and readable; the summary says it failed
    run = load_run(out)
    assert 1 <= len(run.times) <= 4
    assert run.summary["status"] == "failed" and "No space left" in run.summary["message"]


def test_an_output_folder_that_cannot_be_made_is_one_line(tmp_path, monkeypatch, capsys):
    from pathlib import Path

    from fecontact.cli.commands import main
    from fecontact.testing import CASES

    def refuse(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(Path, "mkdir", refuse)
    args = ["run", str(CASES / "bouncing_ball.py"), "--quiet", "--out", str(tmp_path / "no")]
    assert main([*args, "--t-end", "0.01"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Permission denied" in err[0]


def test_a_case_file_not_named_py_is_one_line(tmp_path, capsys):
    text = tmp_path / "pendulum.txt"
    text.write_text((ROOT / "cases" / "flexible_pendulum.py").read_text())
    one_line_error(capsys, ["run", str(text), "--quiet", "--out", str(tmp_path)], ".py")
    one_line_error(capsys, ["info", str(text)], ".py")


def test_resume_with_a_history_shorter_than_the_checkpoint(tmp_path, capsys):
    args = ["run", CASE, "--quiet", "--checkpoint-every", "10", "--out", str(tmp_path)]
    assert main([*args, "--t-end", "0.025"]) == 0
    history = tmp_path / "history.csv"
    history.write_text("".join(history.read_text().splitlines(keepends=True)[:6]))
    one_line_error(capsys, [*args, "--t-end", "0.05", "--resume"], "history.csv", "holds 5 rows")


def test_resume_with_a_frame_deleted_is_refused(tmp_path, capsys):
    args = ["run", CASE, "--quiet", "--checkpoint-every", "20", "--out", str(tmp_path)]
    assert main([*args, "--t-end", "0.025", "--output-interval", "0.005"]) == 0
    frames = sorted(tmp_path.glob("flexible_pendulum_beam2d0_*.vtu"))
    frames[1].unlink()
    resume = [*args, "--t-end", "0.05", "--output-interval", "0.005", "--resume"]
    one_line_error(capsys, resume, frames[1].name, "missing")


def test_render_of_a_run_missing_a_middle_frame(tmp_path, capsys):
    args = ["run", CASE, "--quiet", "--t-end", "0.03", "--output-interval", "0.005"]
    assert main([*args, "--out", str(tmp_path)]) == 0
    frames = sorted(tmp_path.glob("flexible_pendulum_beam2d0_*.vtu"))
    frames[len(frames) // 2].unlink()
    one_line_error(capsys, ["render", str(tmp_path)], frames[len(frames) // 2].name, "missing")


def test_resume_refuses_another_case_files_checkpoint(tmp_path, capsys):
    """Two files that build a case of the same name and parameters, one with the stop moved:
    the second does not continue the first one's checkpoint."""
    source = (ROOT / "cases" / "flexible_pendulum.py").read_text()
    first, moved = tmp_path / "first.py", tmp_path / "moved.py"
    first.write_text(source)
    assert "Plane([0.0, -0.3]" in source
    moved.write_text(source.replace("Plane([0.0, -0.3]", "Plane([0.0, -0.29]"))
    out = str(tmp_path / "out")
    args = ["--quiet", "--checkpoint-every", "10", "--out", out]
    assert main(["run", str(first), *args, "--t-end", "0.02"]) == 0
    one_line_error(
        capsys, ["run", str(moved), *args, "--t-end", "0.04", "--resume"], "another case file"
    )
    assert main(["run", str(first), *args, "--t-end", "0.04", "--resume"]) == 0
    import json

    record = json.loads((tmp_path / "out" / "summary.json").read_text())["case_file"]
    assert record["file"] == str(first.resolve()) and len(record["sha256"]) == 64


def test_sweep_quiet_still_names_the_failed_runs(tmp_path, capsys):
    pytest.importorskip("distributed")
    argv = ["sweep", "bouncing_ball", "--set", "max_iterations=1,30", "--t-end", "0.6"]
    assert main([*argv, "--quiet", "--workers", "1", "--out", str(tmp_path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = [x for x in captured.err.splitlines() if x.startswith("fecontact:")]
    assert "max_iterations=1" in line and "failed" in line and "converge" in line


@pytest.mark.slow
def test_ctrl_c_during_a_sweep_is_one_line(tmp_path):
    """SIGINT to the command while its runs go on: one line, status 130, completed runs kept
    and sweep.csv written (the same sweep again continues)."""
    pytest.importorskip("distributed")
    import signal
    import subprocess
    import sys
    import time

    argv = [sys.executable, "-m", "fecontact", "sweep", "bouncing_ball", "--quiet"]
    argv += ["--set", "restitution=0,0.5", "--t-end", "30", "--workers", "1", "--out", "s"]
    # the child starts with Ctrl-C's default disposition, as from a terminal: a child inherits
    # an ignored SIGINT (a background job's, or one a library set in this process), and then
    # Python installs no KeyboardInterrupt handler at all
    proc = subprocess.Popen(
        argv,
        cwd=tmp_path,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob("s/*/history.csv")) and time.monotonic() < deadline:
        time.sleep(0.2)  # until a run is under way
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=120)[1]
    lines = [x for x in err.splitlines() if x.strip()]
    assert proc.returncode == 130, err
    assert len(lines) == 1 and "interrupted" in lines[0] and "Traceback" not in err, err
    assert (tmp_path / "s" / "sweep.csv").is_file()


@pytest.mark.parametrize("content, why", [("", "the file is empty"), ("garbage\n", "as gmsh")])
def test_an_unreadable_mesh_says_why_and_prints_nothing(tmp_path, capfd, content, why):
    # meshio prints its reader's complaint and exits with status 1: the message said ": 1"
    path = tmp_path / "bad.msh"
    path.write_text(content)
    with pytest.raises(InputError, match=why):
        Solid.from_file(path, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    assert capfd.readouterr() == ("", "")


@pytest.mark.parametrize("size", [0.0, 1e-40])
def test_a_mesh_of_no_size_is_named(size):
    import skfem

    mesh = skfem.MeshTri()  # (before: "nodes coincide", for a mesh whose nodes are all one)
    with pytest.raises(InputError, match=r"mesh size .* at least 1e-30 m"):
        Solid(skfem.MeshTri(mesh.p * size, mesh.t), LinearElastic(E=1e6, nu=0.3, rho=1e3))


def test_options_the_model_cannot_take_are_refused_before_any_file(tmp_path, capsys):
    import skfem

    body = Solid(skfem.MeshTri(), LinearElastic(E=1e6, nu=0.3, rho=1e3))
    sim = Simulation(Model([body]), 1e-3, 1e-2, options=IntegratorOptions(scheme="energy-decaying"))
    with pytest.raises(InputError, match="energy-decaying"):
        run(sim, tmp_path / "o", frames=False)
    assert not (tmp_path / "o").exists()


def test_a_run_stopped_by_an_unexpected_error_is_not_completed(tmp_path):
    import json

    def faulty(model, state):  # a probe with a fault that shows at the third step
        return state.q[0] if state.step < 3 else {}["missing"]

    sim = Simulation(Model([beam()], gravity=(0, -9.81)), 1e-3, 1e-2)
    sim = sim.replace(probes={"tip": Probe(faulty, "m")})
    with pytest.raises(KeyError, match="missing"):
        run(sim, tmp_path, frames=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "failed" and "KeyError" in summary["message"]


def test_sigterm_ends_a_run_as_ctrl_c_does(tmp_path):
    # a scheduler's time limit: before, the process died with no summary, its lock left and
    # the .pvd short of the frames written in the last second
    import json
    import os
    import signal

    from fecontact.io.termination import Terminated

    def terminating(model, state):  # the signal arrives in the third step
        if state.step == 3:
            os.kill(os.getpid(), signal.SIGTERM)
        return state.q[0]

    sim = Simulation(Model([beam()], gravity=(0, -9.81)), 1e-3, 1e-2, output_interval=1e-3)
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated):
        run(sim.replace(probes={"tip": Probe(terminating, "m")}), tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert (summary["status"], summary["message"]) == ("interrupted", "terminated by SIGTERM")
    assert not (tmp_path / ".fecontact.lock").exists()
    # the frames before the step recorded when the signal came (t = 0, 1, 2 ms), all listed
    assert len(list(tmp_path.glob("*.vtu"))) == 3
    assert (tmp_path / "simulation.pvd").read_text().count("<DataSet") == 3
    assert signal.getsignal(signal.SIGTERM) is before  # the handler is the run's alone


def test_a_stop_before_the_first_step_says_nothing_was_written(tmp_path, capsys, monkeypatch):
    import fecontact.simulation as simulation

    def ctrl_c(model, options):  # Ctrl-C while the run checks its model, before any file
        raise KeyboardInterrupt

    monkeypatch.setattr(simulation, "check_options", ctrl_c)
    out = tmp_path / "run"
    assert main(["run", CASE, "--quiet", "--t-end", "0.01", "--out", str(out)]) == 130
    # (before: "results so far are in <out>", a folder that did not exist)
    assert "stopped before the run wrote anything" in capsys.readouterr().err
    assert not out.exists()


def test_friction_left_out_by_the_penalty_baseline_is_said(capsys):
    # (before: a frictional model ran frictionless with penalty, friction_work 0, unsaid)
    from fecontact.testing import case

    sim = case("sliding_block").build()
    penalty = sim.replace(options=IntegratorOptions(integrator="penalty"))
    assert not [w for w in sim.warnings() if "friction" in w]
    assert any("'penalty' has no friction" in w for w in penalty.warnings())


@pytest.mark.parametrize("integrator", ["moreau", "penalty"])
def test_moving_obstacles_kept_in_place_by_the_baselines_are_said(integrator):
    # (before: a floor rising at 0.5 m/s stayed at its t = 0 place under the baselines, unsaid)
    from fecontact import Contact, Disk, Plane, RigidBody2D

    disk = RigidBody2D.uniform(1.0, (0.0, 0.1), Disk(0.1))
    floor = Plane([0.0, 0.0], [0.0, 1.0], motion=lambda t: np.array([0.0, 0.5 * t]))
    sim = Simulation(Model([disk], [Contact(disk, floor)]), dt=1e-3, t_end=0.01)
    assert not [w for w in sim.warnings() if "moving obstacles" in w]
    baseline = sim.replace(options=IntegratorOptions(integrator=integrator))
    assert any("keeps moving obstacles where they are at t = 0" in w for w in baseline.warnings())
