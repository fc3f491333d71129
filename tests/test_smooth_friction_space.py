"""Friction with rotations in space under the smooth contact force (``smooth_contact`` "on",
and "auto" on a model with a Solid): the persistent contacts' Coulomb law is solved on its
Delassus matrix through the Lie-group step's own factors. A ball launched sliding ends
rolling at 5/7 of its speed at the exact time; the tumbling box comes to rest on a face."""

import dataclasses

import numpy as np
import pytest
from conftest import load_case

from fecontact import Ball, Contact, IntegratorOptions, Model, Plane, RigidBody3D
from fecontact.bodies import Solid
from fecontact.bodies.materials import LinearElastic
from fecontact.time import uses_smooth_contact
from fecontact.time.simulate import simulate

R_BALL, V0, MU, G = 0.1, 2.0, 0.3, 9.81
T_STAR = 2 * V0 / (7 * MU * G)  # the slip ends: v = 5v₀/7


def rolling(options=None, with_solid=False, t_end=0.3):
    """The ball of ``test_rigid3d_contact.rolling``; ``with_solid``: an elastic block rests
    on the plane beside it (a continuum: ``smooth_contact="auto"`` resolves to "on")."""
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, R_BALL], Ball(R_BALL))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    bodies, contacts = [ball], [Contact(ball, floor, friction=MU)]
    if with_solid:
        block = Solid.box(
            [1.0, 1.0, 0.0], [1.1, 1.1, 0.1], 1, LinearElastic(E=1e6, nu=0.3, rho=1000.0)
        )
        bodies.append(block)
        contacts.append(Contact(block, floor))
    model = Model(bodies, contacts, gravity=(0.0, 0.0, -G))
    v0 = np.zeros(model.n)
    v0[0] = V0
    opts = options or IntegratorOptions()
    states = list(simulate(model, 1e-3, t_end, opts, v0=v0))
    t = np.array([s.t for s in states])
    v = np.array([s.v[0] for s in states])
    w = np.array([(ball.rotation(s.q[:6]) @ s.v[3:6])[1] for s in states])  # spatial ω_y
    return model, states, t, v, w


def test_a_ball_sliding_under_the_smooth_contact_force_ends_rolling_at_five_sevenths():
    """smooth_contact "on": the plane carries the ball by the smooth forces λ_N = mg and,
    while it slides, λ_T = μmg against the slip; v = v₀ − μgt to round-off (constant
    forces), the slip stops in the step holding t* and the ball rolls on at 5v₀/7 with
    λ_T → 0."""
    model, states, t, v, w = rolling(IntegratorOptions(smooth_contact="on"))
    assert uses_smooth_contact(model, IntegratorOptions(smooth_contact="on"))
    assert np.abs(v - np.where(t < T_STAR, V0 - MU * G * t, 5 * V0 / 7)).max() < 1e-12
    rolls = t[np.flatnonzero(np.abs(v - R_BALL * w) < 1e-10)[0]]
    assert T_STAR <= rolls < T_STAR + 1e-3
    sliding = states[50].smooth
    assert sliding.normal[0] == pytest.approx(G, rel=1e-12)
    assert np.linalg.norm(sliding.tangential[0]) == pytest.approx(MU * G, rel=1e-12)
    assert np.abs(states[-1].smooth.tangential[0]).max() < 1e-9  # rolling: no friction
    assert all(s.impulse.max(initial=0.0) == 0.0 for s in states[1:])  # no correction


def test_auto_with_a_solid_in_the_model_rolls_the_ball_the_same():
    """A Solid in the model makes "auto" resolve to the smooth force; the ball beside it
    rolls out of its slide as alone. 1e-9 m/s: the block's Newton iterations stop at their
    increment tolerance and the ball shares them (measured 1.9e-10)."""
    model, states, t, v, w = rolling(with_solid=True)
    assert uses_smooth_contact(model, IntegratorOptions())
    assert np.abs(v - np.where(t < T_STAR, V0 - MU * G * t, 5 * V0 / 7)).max() < 1e-9
    rolls = t[np.flatnonzero(np.abs(v - R_BALL * w) < 1e-10)[0]]
    assert T_STAR <= rolls < T_STAR + 1e-3
    assert states[50].smooth.normal[0] == pytest.approx(G, rel=1e-9)


def test_the_smooth_rolling_ball_is_independent_of_p_and_k():
    on = IntegratorOptions(smooth_contact="on")
    _, _, _, v, _ = rolling(on, t_end=0.25)
    for p, k in ((10.0, 1.0), (0.1, 1.0), (1.0, 10.0), (1.0, 0.1)):
        opts = dataclasses.replace(on, penalty_scale=p, multiplier_scale=k)
        assert np.abs(rolling(opts, t_end=0.25)[3] - v).max() < 1e-12, (p, k)


@pytest.mark.slow
def test_the_tumbling_box_under_the_smooth_contact_force_rests_on_a_face(tmp_path):
    """cases/tumbling_box.py with smooth_contact "on", 0.5 s (its 19 impacts end by 0.313 s):
    it rests on its largest face, never penetrates, and creates 6.8e-7 J of its 2.69 J
    scale (2.06e-4 J with the decoupled contact phase: the smooth force holds the resting
    corners instead of a correction every step)."""
    import fecontact

    sim = load_case("tumbling_box").build(t_end=0.5)
    sim = dataclasses.replace(sim, options=IntegratorOptions(smooth_contact="on"))
    summary = fecontact.run(sim, tmp_path, checkpoint_every=0, frames=False)
    from fecontact.io.output import read_history

    history = read_history(tmp_path / "history.csv")
    assert summary["status"] == "completed"
    assert summary["smooth_contact_force"] is True
    assert np.min(history["min_gap"]) >= -1e-9
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 1e-5 * ledger["scale"]
    assert history["upright"][-1] == pytest.approx(1.0, abs=1e-9)
    assert history["z"][-1] == pytest.approx(0.05, abs=1e-9)
    assert history["speed"][-1] < 1e-6 and history["omega"][-1] < 1e-6
