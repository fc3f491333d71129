"""Steps chosen by a tolerance (IntegratorOptions.rtol, fecontact.time.adaptive): rows at the
requested times, the dt column, the error against exact solutions falling with rtol, rejected
steps counted, and rtol=None unchanged."""

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sl

from fecontact import Model, Simulation, run
from fecontact.bodies import Disk, RigidBody2D
from fecontact.bodies.beam import Beam2D, Material, Section
from fecontact.cli.commands import main
from fecontact.errors import InputError
from fecontact.io.output import load_run, read_history
from fecontact.testing import G, ball_exact_gap
from fecontact.time import IntegratorOptions, StepStats, simulate

ROOT = Path(__file__).resolve().parents[1]
# impact localization, where the package has it (an option of its own)


def cantilever(steps_per_period: float, rtol=None, periods: float = 2.0):
    """A linear steel cantilever (1 m, 4 elements) released from its first mode shape (tip
    1 mm): its exact motion is q(t) = φ cos(ωt). Returns (simulation, φ, ω)."""
    section = Section(area=1e-4, inertia=1e-8 / 12.0)
    beam = Beam2D.straight([0, 0], [1, 0], 4, Material(2e11, rho=7800), section, True).clamp(0)
    model = Model([beam], [], (0.0, 0.0))
    K = model.internal(np.zeros(model.n))[2]
    dense = [x.toarray() if hasattr(x, "toarray") else x for x in (K, model.M)]
    w2, modes = sl.eigh(*dense)
    omega, phi = np.sqrt(w2[0]), np.zeros(model.n)
    phi[model.free] = 1e-3 * modes[:, 0] / np.max(np.abs(modes[:, 0]))
    period = 2 * np.pi / omega
    sim = Simulation(
        model,
        dt=period / steps_per_period,
        t_end=periods * period,
        options=IntegratorOptions(rtol=rtol),
        q0=phi,
        name="cantilever",
    )
    return sim, phi, omega


def rows_and_error(sim, phi, omega):
    """(rows (t, q), all steps, the largest error of q over the rows (m), stats)."""
    stats, rows, steps = StepStats(), [], 0
    states = simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, stats=stats)
    for st in states:
        steps += 1
        if not st.substep:
            rows.append((st.t, st.h, np.max(np.abs(st.q - phi * np.cos(omega * st.t)))))
    rows = np.array(rows)
    return rows, steps - 1, rows[:, 2].max(), stats


def test_the_error_falls_with_rtol_on_a_free_vibration():
    errors, steps = [], []
    for rtol in (1e-5, 1e-6, 1e-7, 1e-8):
        rows, n, err, _ = rows_and_error(*cantilever(20, rtol))
        errors.append(err)
        steps.append(n)
    fixed = rows_and_error(*cantilever(20))[2]
    # the local estimate is O(h³): a tenfold rtol takes 10^(1/3) ≈ 2.2 times the steps and
    # the global O(h²) error falls by about 10^(2/3) ≈ 4.6; the binary ladder rounds the step
    # to a power of two, so only the direction is asserted, and a twofold fall at least
    assert all(b < a / 2 for a, b in zip(errors, errors[1:], strict=False)), errors
    assert all(b > a for a, b in zip(steps, steps[1:], strict=False)), steps
    assert errors[-1] < fixed / 10


def test_rows_land_on_the_requested_times_with_their_dt():
    sim, phi, omega = cantilever(20, 1e-7)
    rows, n, _, stats = rows_and_error(sim, phi, omega)
    # one row per dt, at n·dt as with fixed steps (the same floating-point expression)
    expected = np.minimum(np.arange(len(rows)) * sim.dt, sim.t_end)
    np.testing.assert_array_equal(rows[:, 0], expected)
    assert rows[0, 1] == 0.0
    assert np.all(rows[1:, 1] <= sim.dt) and rows[1:, 1].min() < sim.dt
    # every step is dt·2^-k: the ladder of one factorization per rung
    k = np.log2(sim.dt / rows[1:, 1])
    np.testing.assert_allclose(k, np.round(k), atol=1e-12)
    assert n > len(rows) - 1
    assert len(sim.model.iteration_cache) <= 11


def test_rejected_steps_are_counted_in_the_summary(tmp_path):
    # four steps a period: the first step of dt misses rtol = 1e-6 by far and is taken again
    sim, phi, omega = cantilever(4, 1e-6, periods=0.5)
    summary = run(sim, tmp_path, frames=False)
    assert summary["status"] == "completed"
    assert summary["steps_rejected"] >= 1
    control = summary["step_control"]
    assert summary["steps_rejected"] == control["rejected_error"] + control["rejected_failure"]
    assert summary["dt_min"] <= summary["dt_max"] <= sim.dt and summary["dt_min"] < sim.dt
    history = read_history(tmp_path / "history.csv")
    assert summary["steps"] > len(history["t"]) - 1
    assert history["dt"][1:].min() >= summary["dt_min"]


def test_a_failing_step_is_a_rejection_taken_again_lower(tmp_path):
    # one Newton iteration does not converge the geometrically exact cantilever's large
    # swing at dt; the control retakes it on lower rungs instead of halving
    section = Section(area=1e-4, inertia=1e-8 / 12.0)
    beam = Beam2D.straight([0, 0], [1, 0], 4, Material(2e9, rho=7800), section).clamp(0)
    model = Model([beam], [], (0.0, -9.81))
    opts = IntegratorOptions(rtol=1e-3, max_iterations=3)
    sim = Simulation(model, dt=0.05, t_end=0.2, options=opts, name="drooping")
    summary = run(sim, tmp_path, frames=False)
    assert summary["status"] == "completed"
    assert summary["step_control"]["rejected_failure"] >= 1
    assert summary["step_halvings"] == 0


def test_frames_keep_their_times_between_the_rows(tmp_path):
    # four steps a period, substeps down to dt/8, frames every dt/5: before, each frame was
    # the first substep at or after its time (off the rows and the interval)
    sim, phi, omega = cantilever(4, 1e-6, periods=0.5)
    sim = sim.replace(output_interval=sim.dt / 5)
    assert run(sim, tmp_path, progress=False)["status"] == "completed"
    done = load_run(tmp_path)
    times, rows = np.asarray(done.times), done.history["t"]
    # k·interval to the round-off of the time (1e-15 s on 0.06 s)
    np.testing.assert_allclose(times, np.arange(11) * sim.output_interval, rtol=0, atol=1e-15)
    assert list(times[::5]) == list(rows)  # a frame at a row's time is that row
    body, tip, amplitude = sim.model.bodies[0], [], 0.0
    for t, parts in done.frames():
        q = (phi * np.cos(omega * t))[sim.model.body_slice(0)]
        exact = body.point_data(q, np.zeros_like(q))["displacement"]
        shown = np.asarray(parts["beam2d0"].point_data["displacement"])[:, :2]
        tip.append(np.abs(shown - exact).max())
        amplitude = max(amplitude, np.abs(exact).max())
    # interpolated frames: 1.45e-2 of the 7.06e-4 m amplitude at most, the rows 1.22e-2 (the
    # steps' error); the same arithmetic on any machine, round-off far below the margin
    assert max(tip) <= 0.02 * amplitude


def test_fixed_steps_write_their_step_in_the_dt_column(tmp_path):
    out = tmp_path / "ball"
    args = ["run", str(ROOT / "cases" / "bouncing_ball.py"), "--quiet", "--out", str(out)]
    assert main([*args, "--t-end", "0.0105", "--checkpoint-every", "0"]) == 0
    history = read_history(out / "history.csv")
    np.testing.assert_array_equal(history["dt"][1:-1], 1e-3)
    assert history["dt"][0] == 0.0
    assert history["dt"][-1] == pytest.approx(5e-4, rel=1e-9)  # the last, shorter step
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps_rejected"] == 0 and summary["dt_max"] == 1e-3


def test_rtol_from_the_command_line(tmp_path):
    case = str(ROOT / "cases" / "bouncing_ball.py")
    args = ["run", case, "--quiet", "--t-end", "0.01", "--checkpoint-every", "0"]
    assert main([*args, "--out", str(tmp_path / "a"), "--rtol", "1e-6"]) == 0
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert summary["options"]["rtol"] == 1e-6
    assert main([*args, "--out", str(tmp_path / "b"), "--set", "rtol=1e-6"]) == 0
    with pytest.raises(InputError, match="--rtol and --set rtol"):
        from fecontact.cli.run import split_overrides

        class Args:
            set = ["rtol=1e-6"]
            rtol = 1e-6

        split_overrides(lambda: None, Args())


@pytest.mark.parametrize(
    "changes, match",
    [
        ({"rtol": 0.0}, r"rtol must be in \(0, 1\)"),
        ({"rtol": 1.5}, r"rtol must be in \(0, 1\)"),
        ({"rtol": 1e-6, "integrator": "moreau"}, "rtol needs the generalized-alpha step"),
        ({"rtol": 1e-6, "scheme": "energy-decaying"}, "rtol needs the generalized-alpha step"),
    ],
)
def test_bad_rtol_is_refused(changes, match):
    with pytest.raises(InputError, match=match):
        IntegratorOptions(**changes)


def test_a_resumed_run_with_rtol_matches_the_uninterrupted_one(tmp_path):
    sim, _, _ = cantilever(4, 1e-6, periods=1.0)
    whole = run(sim, tmp_path / "a")
    run(sim.replace(t_end=sim.dt * 2), tmp_path / "b", checkpoint_every=1)
    resumed = run(sim, tmp_path / "b", resume=True)
    a, b = (read_history(tmp_path / x / "history.csv") for x in "ab")
    for column in ("t", "dt", "total_energy"):
        np.testing.assert_array_equal(a[column], b[column])
    assert resumed["steps"] == whole["steps"]
    # the run rejects its first step of dt only; the resumed part starts on the rung the
    # checkpoint carries (State.h_next), not from dt again
    assert whole["steps_rejected"] >= 1 and resumed["steps_rejected"] == 0


def thrown_ball(rtol):
    """A ball thrown up at 3 m/s without a floor: the exact parabola."""
    ball = RigidBody2D.uniform(1.0, [0.0, 0.0], Disk(0.1))
    model = Model([ball], [], (0.0, -G))
    v0 = np.array([0.5, 3.0, 0.0])
    sim = Simulation(model, 1e-3, 1.0, options=IntegratorOptions(rtol=rtol), v0=v0)
    states = list(simulate(model, sim.dt, sim.t_end, sim.options, v0=v0))
    t = np.array([st.t for st in states])
    y = np.array([st.q[1] for st in states])
    return states, np.max(np.abs(y - (3.0 * t - 0.5 * G * t**2)))


def test_free_flight_is_exact_and_keeps_the_largest_step():
    # generalized-α integrates a constant acceleration exactly: the estimate is round-off
    states, err = thrown_ball(1e-9)
    assert err < 1e-13
    assert all(st.h == 1e-3 for st in states[1:]) and not any(st.substep for st in states)


def test_bouncing_ball_to_1e_8_with_rtol():
    spec = importlib.util.spec_from_file_location("ball", ROOT / "cases" / "bouncing_ball.py")
    case = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(case)
    sim = case.build(height=1.0, mass=1.0, restitution=0.8)
    opts = IntegratorOptions(rtol=1e-9, localize=True)
    rows = [
        (st.t, st.q[1])
        for st in simulate(sim.model, 1e-3, 3.0, opts, q0=sim.q0, v0=sim.v0)
        if not st.substep
    ]
    t, y = np.array(rows).T
    assert np.max(np.abs(1.0 + y - ball_exact_gap(t))) <= 1e-8


def test_minus_is_the_inverse_of_plus_on_rotation_vectors():
    # q0 ⊕ Δ ⊖ q0 = Δ: the body-frame increment back to round-off, for rotations up to 2.9 rad
    from fecontact.bodies import Beam3D
    from fecontact.time.configuration import minus, plus

    beam = Beam3D.straight(
        [0, 0, 0], [1, 0, 0], 2, Material(2e11, nu=0.3, rho=7800), Section.circle(0.01)
    )
    model = Model([beam], [], (0.0, 0.0, 0.0))
    rng = np.random.default_rng(3)
    q0 = rng.uniform(-1.0, 1.0, model.n) * np.tile([0.1, 0.1, 0.1, 1.6, 1.6, 1.6], 3)
    dq = rng.uniform(-0.3, 0.3, model.n)
    np.testing.assert_allclose(minus(model, plus(model, q0, dq), q0), dq, atol=1e-14)


def test_a_beam_turning_out_of_its_plane_keeps_the_largest_step():
    """The spatial pendulum thrown out of its plane, before it reaches the stop (0.3 s): a
    smooth swing that its planar twin crosses at dt = 1 ms under rtol = 1e-4. The error
    estimate measures a rotation by its body-frame increment: the difference of the rotation
    vectors departs from h Ω at O(h) once the axis turns, and halved the steps down to
    0.125 ms (1651 steps instead of 300)."""
    spec = importlib.util.spec_from_file_location("sp", ROOT / "cases" / "spatial_pendulum.py")
    case = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(case)
    sim = case.build(out_of_plane_velocity=0.5)
    opts = IntegratorOptions(rtol=1e-4)
    states = list(simulate(sim.model, 1e-3, 0.3, opts, q0=sim.q0, v0=sim.v0))
    assert states[-1].t == pytest.approx(0.3, abs=1e-12)
    assert all(st.h == 1e-3 for st in states[1:]) and not any(st.substep for st in states)
