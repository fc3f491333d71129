"""Checkpoints: an interrupted run resumed from its last checkpoint equals an uninterrupted
run, row for row and frame for frame."""

import numpy as np
import pytest
from conftest import ROOT

import fecontact.io.run_frames as run_frames  # (the frame writer of a run)
from fecontact import load_run
from fecontact.cli.commands import main

CASE = str(ROOT / "cases" / "flexible_pendulum.py")
ARGS = ["--quiet", "--t-end", "0.6", "--checkpoint-every", "150", "--set", "restitution=0.5"]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref")
    assert main(["run", CASE, "--out", str(out), *ARGS]) == 0
    return out


def same_run(a, b):
    assert (a / "history.csv").read_text() == (b / "history.csv").read_text()
    ra, rb = load_run(a), load_run(b)
    assert ra.summary["impacts"] == rb.summary["impacts"]
    assert ra.summary["steps"] == rb.summary["steps"]
    assert ra.summary["energy_balance"] == rb.summary["energy_balance"]
    fa, fb = ra.frames(), rb.frames()
    assert [t for t, _ in fa] == [t for t, _ in fb]
    for (_, pa), (_, pb) in zip(fa, fb, strict=True):
        for name in pa:
            assert np.array_equal(pa[name].points, pb[name].points)
            for field in pb[name].point_data:  # (the points are the reference configuration)
                assert np.array_equal(pa[name].point_data[field], pb[name].point_data[field])


def interrupt_frames_after(monkeypatch, t_stop: float):
    """Ctrl-C from the frame writer once the run passes ``t_stop`` (s); returns the writer, to
    put back before resuming."""
    frame_parts = run_frames.frame_parts

    def interrupt_late(model, st):
        if st.t > t_stop:
            raise KeyboardInterrupt
        return frame_parts(model, st)

    monkeypatch.setattr(run_frames, "frame_parts", interrupt_late)
    return frame_parts


def test_resume_after_ctrl_c_equals_uninterrupted_run(reference, tmp_path, monkeypatch):
    out = tmp_path / "interrupted"
    frame_parts = interrupt_frames_after(monkeypatch, 0.52)
    assert main(["run", CASE, "--out", str(out), *ARGS]) == 130
    partial = load_run(out)
    assert partial.summary["status"] == "interrupted"
    assert 0.5 < partial.frames()[-1][0] <= 0.52  # every frame so far stays readable
    monkeypatch.setattr(run_frames, "frame_parts", frame_parts)
    assert main(["run", CASE, "--out", str(out), "--resume", *ARGS]) == 0
    same_run(reference, out)


def test_extend_a_finished_run(reference, tmp_path):
    out = tmp_path / "short"
    short = [a if a != "0.6" else "0.45" for a in ARGS]
    assert main(["run", CASE, "--out", str(out), *short]) == 0
    assert main(["run", CASE, "--out", str(out), "--resume", *ARGS]) == 0
    same_run(reference, out)


def test_resume_refuses_other_parameters(reference, tmp_path, capsys):
    assert main(["run", CASE, "--out", str(reference), "--resume", *ARGS, "--set", "E=7e11"]) == 2
    assert "other parameters" in capsys.readouterr().err
    assert main(["run", CASE, "--out", str(tmp_path / "none"), "--resume", *ARGS]) == 2


@pytest.mark.parametrize("integrator", ["nsga", "moreau", "penalty"])
def test_every_integrator_resumes_identically(integrator, tmp_path):
    """The rocking block starts on a corner, in contact, and is still sliding on it at the
    resume time: the penalty law's stiffness there, fixed from the corner's effective mass
    where the contact first closed (at t = 0; it changes with the angle), travels in the
    checkpoint instead of being derived again from the angle at the resume time."""
    args = ["--checkpoint-every", "25", "--set", f"integrator={integrator}"]
    resumes_identically("rocking_block", args, "0.1", "0.05", tmp_path)


@pytest.mark.parametrize("friction", [0.0, 0.3])
def test_smooth_contact_forces_resume_identically(friction, tmp_path):
    """The smooth contact forces λ (and, with friction, λ_T) are the warm start and the
    persistent set of the next step: they travel in the checkpoint (two disks in contact at
    the resume time, obliquely with friction)."""
    args = ["--checkpoint-every", "10", "--set", "refinements=1"]
    if friction:
        args += ["--set", "offset=0.03", "--set", f"friction={friction}"]
    resumes_identically("two_disks", args, "0.004", "0.003", tmp_path)


def test_energy_decaying_step_resumes_identically(tmp_path):
    """The energy-decaying step carries the smooth step's strain increment Δε_n of every
    element into the next step: it travels in the checkpoint (the pendulum resumed after its
    first impact)."""
    args = ["--checkpoint-every", "50", "--set", "restitution=0.5"]
    args += ["--set", "scheme=energy-decaying", "--set", "rho_inf=0.8"]
    resumes_identically("flexible_pendulum", args, "0.3", "0.2", tmp_path)


def resumes_identically(name, args, end, half, tmp_path):
    """Run case ``name`` to ``end`` (s) in one go, and to ``half`` then resumed to ``end``:
    the same history, impacts and frames."""
    case = str(ROOT / "cases" / f"{name}.py")
    whole, resumed = tmp_path / "whole", tmp_path / "resumed"
    assert main(["run", case, "--out", str(whole), "--quiet", "--t-end", end, *args]) == 0
    assert main(["run", case, "--out", str(resumed), "--quiet", "--t-end", half, *args]) == 0
    resume = ["--resume", "--quiet", "--t-end", end, *args]
    assert main(["run", case, "--out", str(resumed), *resume]) == 0
    same_run(whole, resumed)


def test_resume_vtkhdf_frames_after_ctrl_c(tmp_path, monkeypatch):
    """Transient VTKHDF files are cut back to the checkpoint and continued: the same frames as
    an uninterrupted run, and as its VTU frames."""
    vtkhdf = [*ARGS, "--format", "vtkhdf"]
    assert main(["run", CASE, "--out", str(tmp_path / "whole"), *vtkhdf]) == 0
    assert main(["run", CASE, "--out", str(tmp_path / "vtu"), *ARGS]) == 0
    out = tmp_path / "interrupted"
    frame_parts = interrupt_frames_after(monkeypatch, 0.52)
    assert main(["run", CASE, "--out", str(out), *vtkhdf]) == 130
    assert 0.5 < load_run(out).frames([-1])[0][0] <= 0.52
    monkeypatch.setattr(run_frames, "frame_parts", frame_parts)
    assert main(["run", CASE, "--out", str(out), "--resume", *vtkhdf]) == 0
    same_run(tmp_path / "whole", out)
    same_run(tmp_path / "vtu", out)
