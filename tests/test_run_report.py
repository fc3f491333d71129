"""What a run reports of its halvings, its shortest sub-step, its warnings and a failure:
counts named for what they count, every warning printed also in ``summary.json``."""

import json
import math

import numpy as np
import pytest
from conftest import ROOT

from fecontact import load_run, run
from fecontact.cli import main
from fecontact.errors import SolverError
from fecontact.testing import load_case, trace
from fecontact.time import IntegratorOptions
from fecontact.time.acceleration_form import AccelerationForm

CASE = str(ROOT / "cases" / "flexible_pendulum.py")
# ρ∞ = 1 and e_N = 1: the strip rings after the first impact (t ≈ 0.32 s) and steps whose
# predictor turns a node by more than a quarter turn are halved (docs: explanation/stability);
# the steps that create energy kept as they are (energy_retakes=0: taken again at ρ∞ = 0, the
# strip no longer rings, and the run halves no step)
RINGING = ["--set", "rho_inf=1", "--set", "restitution=1", "--set", "energy_retakes=0", "--quiet"]


def test_halvings_and_the_steps_halved_are_said_apart_by_cause(tmp_path, capsys):
    out = tmp_path / "p"
    assert main(["run", CASE, "--out", str(out), "--t-end", "0.33", *RINGING]) == 0
    err = capsys.readouterr().err
    s = json.loads((out / "summary.json").read_text())
    halvings, steps, turns = s["step_halvings"], s["halved_steps"], s["beam_turns"]
    assert 0 < steps < halvings  # (some step halved more than once)
    # every halving here is the turn bound's: none for Newton, none retaken for a penetration
    assert turns["halvings"] == halvings and turns["halved_steps"] == steps
    assert turns["refused"] >= halvings and s["penetration_retakes"] == 0
    # the shortest sub-step is dt over a power of two, below the steps dt_min reports
    assert math.log2(s["dt"] / s["dt_substep_min"]).is_integer()
    assert s["dt_substep_min"] < s["dt_min"] == s["dt"]
    (said,) = [w for w in s["warnings"] if w.startswith("halvings:")]
    assert f"{steps} step(s) of dt = 0.001 s were halved {halvings} time(s)" in said
    assert f"{halvings} for a beam node turned by more than a quarter turn" in said
    assert "did not converge" not in said and f"sub-steps of {s['dt_substep_min']:.3g} s" in said
    # each warning printed once, the settings' (before the run) among them, and all of them
    # in summary.json
    assert any(w.startswith("rho_inf = 1 with restitution > 0") for w in s["warnings"])
    printed = [line for line in err.splitlines() if line.startswith("fecontact: warning: ")]
    assert sorted(printed) == sorted(f"fecontact: warning: {w}" for w in s["warnings"])


def test_a_run_resumed_keeps_its_halvings(tmp_path):
    """The halvings, the steps halved and the shortest sub-step are counted with the states:
    a run resumed from a checkpoint reports what the run taken whole does."""
    whole, part = tmp_path / "whole", tmp_path / "part"
    args = ["run", CASE, "--checkpoint-every", "325", *RINGING]
    assert main([*args, "--out", str(whole), "--t-end", "0.33"]) == 0
    assert main([*args, "--out", str(part), "--t-end", "0.326"]) == 0
    assert main([*args, "--out", str(part), "--t-end", "0.33", "--resume"]) == 0
    a, b = load_run(whole).summary, load_run(part).summary
    keys = ("step_halvings", "halved_steps", "dt_substep_min")
    assert [a[k] for k in keys] == [b[k] for k in keys]
    assert a["beam_turns"]["halvings"] == b["beam_turns"]["halvings"]


def test_a_step_refused_for_its_turn_fails_without_a_residual(tmp_path, capsys):
    """At h = 1e-2 the predictor of the step after the ringing starts turns a node beyond a
    quarter turn at every halving: the run fails saying so, with no Newton residual."""
    out = tmp_path / "p"
    args = ["run", CASE, "--out", str(out), "--t-end", "0.4", "--dt", "0.01", *RINGING]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert "beam turn bound at t = " in err and "after 6 step halvings" in err
    assert "refused before its correction: the predictor turns a beam node by" in err
    assert "residual" not in err and "Newton did not converge" not in err
    s = load_run(out).summary
    assert s["status"] == "failed" and s["message"].startswith("beam turn bound")
    # the failed step's halvings, all of them for the turn, counted with the others'
    # (measured: 42 of 43 halvings for the turn, in 2 of the 3 steps halved, the failed
    # step's six among them)
    turns = s["beam_turns"]
    assert f"(step {s['failed_step']})" in s["message"] and s["failed_step"] == s["steps"] + 1
    assert turns["halvings"] >= 6 and turns["halved_steps"] >= 1
    assert s["step_halvings"] >= turns["halvings"] and s["halved_steps"] >= turns["halved_steps"]


@pytest.mark.filterwarnings("ignore::UserWarning")  # (the run's warnings, read below)
def test_the_benchmarks_trace_carries_the_energy_check(tmp_path):
    """The pendulum at g = 981 m/s² (impact at 24.7 m/s) and h = 1e-3 completes with its
    energy doubled (docs: explanation/stability) where its steps that create energy are kept
    as they are (energy_retakes=0; taken again, it creates 0.79 % of its scale): the trace of
    ``simulate`` says so as the run's summary does, with the same words."""
    sim = load_case("flexible_pendulum").build(gravity=981.0, restitution=0.5)
    sim = sim.replace(t_end=0.15, options=IntegratorOptions(energy_retakes=False))
    tr = trace(sim)
    summary = run(sim, tmp_path / "g", frames=False)
    assert tr["status"] == summary["status"] == "completed"
    energy = [w for w in summary["warnings"] if "integration is unstable" in w]
    assert energy and [w for w in tr["warnings"] if "integration is unstable" in w] == energy


def test_the_benchmarks_trace_counts_the_energy_retakes(tmp_path):
    """The same pendulum with its steps that create energy taken again at ρ∞ = 0 (the
    default): the trace of ``simulate`` counts the retakes the run's summary counts, so that
    the stability matrix shows them (benchmarks/stability.py, column ``retakes``)."""
    sim = load_case("flexible_pendulum").build(gravity=981.0, restitution=0.5)
    sim = sim.replace(t_end=0.15)
    tr = trace(sim)
    with pytest.warns(UserWarning, match="energy: the run created"):  # (0.79 % of its scale)
        summary = run(sim, tmp_path / "g", frames=False)
    assert summary["energy_retakes"] > 0  # (20, 10 of them in halves: measured)
    assert tr["energy_retakes"] == summary["energy_retakes"]
    assert tr["energy_retake_halves"] == summary["energy_retake_halves"]


@pytest.mark.parametrize("cli", [True, False])
def test_a_run_that_keeps_its_step_warns_of_no_halving(tmp_path, capsys, cli):
    """The founding pendulum (ρ∞ = 0.5, e_N = 0.5) keeps its step: no halving, and
    dt_substep_min is dt."""
    out = tmp_path / "p"
    if cli:
        assert main(["run", CASE, "--out", str(out), "--t-end", "0.05", "--quiet"]) == 0
        assert "warning" not in capsys.readouterr().err
        s = load_run(out).summary
    else:
        sim = load_case("flexible_pendulum").build().replace(t_end=0.05)
        s = run(sim, out, frames=False)
    assert s["step_halvings"] == s["halved_steps"] == 0 and s["warnings"] == []
    assert s["dt_substep_min"] == s["dt_min"] == s["dt"]


def test_a_failed_step_counts_its_halvings_and_names_one_step(tmp_path, capsys):
    """The disk thrown at 443 m/s (four times its wave speed) stops in its first step, an
    element inverted at every halving: summary.json counts that step's six halvings, down to
    dt/64, and names it, as the error and the last line do, step 1 (a step is numbered by
    the row it ends on; the run's last state is step 0)."""
    sim = load_case("disk_drop").build(refinements=2, velocity=443.0)
    with pytest.raises(SolverError) as failure:
        run(sim, tmp_path / "d", frames=False, checkpoint_every=0, progress=True)
    assert failure.value.step == 1 and "(step 1)" in str(failure.value)
    assert "after 6 step halvings" in str(failure.value)
    s = json.loads((tmp_path / "d" / "summary.json").read_text())
    assert s["status"] == "failed" and s["steps"] == 0 and s["failed_step"] == 1
    assert s["step_halvings"] == 6 and s["halved_steps"] == 1
    assert s["penetration_retakes"] == 0 and s["beam_turns"]["halvings"] == 0
    assert s["dt_substep_min"] == pytest.approx(sim.dt / 64, rel=1e-12)
    assert any(w.startswith("halvings: 1 step(s)") for w in s["warnings"])
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert "stops (failed) in step 1 at t = 0 s" in last


def test_a_non_finite_update_fails_its_step_which_is_halved(tmp_path, monkeypatch):
    """A Newton update that lost its numbers (a solve returning NaN) fails its step at once,
    as a residual that diverged does: the step is halved and counted, and no term is
    evaluated at a non-finite iterate (a contact's neighbour search raised a ValueError
    there and stopped the run)."""
    plain, calls = AccelerationForm._plain_update, []

    def lost(form):
        calls.append(None)
        dq = plain(form)
        return np.full_like(dq, np.nan) if len(calls) == 2 else dq

    monkeypatch.setattr(AccelerationForm, "_plain_update", lost)
    out = tmp_path / "p"  # (the disks' mortar rows are evaluated at every iterate)
    assert main(["run", "two_disks", "--out", str(out), "--t-end", "5e-4", "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert len(calls) > 2 and s["step_halvings"] == 1 and s["halved_steps"] == 1
    (said,) = [w for w in s["warnings"] if w.startswith("halvings:")]
    assert "1 for a solve that did not converge" in said
    history = load_run(out).history
    assert all(np.isfinite(np.asarray(column, dtype=float)).all() for column in history.values())
