"""Joints (bilateral constraints), Rayleigh damping and time-dependent loads."""

import numpy as np
import pytest

from fecontact import (
    Beam2D,
    Contact,
    InputError,
    IntegratorOptions,
    Material,
    Model,
    NodalLoad,
    Pin,
    Plane,
    Section,
    simulate,
)

MATERIAL = Material(E=70e9, nu=0.33, rho=2700.0)
SECTION = Section.rectangle(0.02, 0.002)


def pendulum(with_pin: bool, **model_kw):
    beam = Beam2D.straight([0, 0], [0.3, 0], 4, MATERIAL, SECTION).add_mass(-1, 0.14)
    joints = [Pin(beam, [0, 0])] if with_pin else []
    if not with_pin:
        beam.pin(0)
    stop = Contact(beam, Plane([0, -0.3], [1, 0]), nodes=[-1])
    return beam, Model([beam], [stop], joints=joints, **model_kw)


def test_pin_joint_reproduces_the_pinned_support():
    """A Pin to the ground and a Dirichlet pin give the same motion, through an impact; the
    joint holds at position and velocity level to solver tolerance at every step. Taken
    with the decoupled contact phase: with the smooth force (the default of beams) the
    stop's row borders the Newton matrix with the joint's rows in one model and alone in
    the other, each iteration stopping at its own tolerance, and the tips differ by 2.4e-7 m
    after the impact (the joint holds the same)."""
    beam_a, ma = pendulum(False)
    beam_b, mb = pendulum(True)
    decoupled = IntegratorOptions(smooth_contact="off")
    tip_a = [beam_a.positions(s.q)[-1] for s in simulate(ma, 1e-3, 0.4, decoupled)]
    viol_q, viol_v, tip_b = [], [], []
    for s in simulate(mb, 1e-3, 0.4, decoupled):
        tip_b.append(beam_b.positions(s.q)[-1])
        viol_q.append(np.abs(s.q[:2]).max())
        viol_v.append(np.abs(s.v[:2]).max())
    assert max(viol_q) < 1e-10 and max(viol_v) < 1e-10
    assert np.max(np.abs(np.array(tip_a) - np.array(tip_b))) < 1e-7


def test_pin_between_two_beams_keeps_them_joined():
    """Two beams hinged end to end fall under gravity from a pinned support: the hinge
    points coincide and move together at every step."""
    a = Beam2D.straight([0, 0], [0.2, 0], 3, MATERIAL, SECTION).pin(0)
    b = Beam2D.straight([0.2, 0], [0.4, 0], 3, MATERIAL, SECTION).add_mass(-1, 0.05)
    model = Model([a, b], joints=[Pin(a, [0.2, 0], b)])
    for s in simulate(model, 1e-3, 0.3):
        qa, qb = s.q[: a.ndof], s.q[a.ndof :]
        va, vb = s.v[: a.ndof], s.v[a.ndof :]
        assert np.allclose(a.positions(qa)[-1], b.positions(qb)[0], atol=1e-10, rtol=0)
        assert np.allclose(va[-3:-1], vb[:2], atol=1e-9, rtol=0)
    # the double pendulum has swung down
    assert b.positions(qb)[-1][1] < -0.2


def test_pin_must_sit_on_a_node():
    beam = Beam2D.straight([0, 0], [0.3, 0], 4, MATERIAL, SECTION)
    with pytest.raises(InputError, match="node"):
        Pin(beam, [0.01, 0])


def test_rayleigh_damping_decays_free_vibration():
    """A cantilever released from a static deflection under a removed tip load vibrates;
    with mass-proportional damping α its amplitude decays like exp(−α t / 2)."""
    beam = Beam2D.straight([0, 0], [0.3, 0], 8, MATERIAL, SECTION).clamp(0)
    alpha = 20.0
    load = NodalLoad(beam, -1, lambda t: np.array([0.0, -1.0 if t < 0.05 else 0.0, 0.0]))
    model = Model([beam], gravity=(0, 0), damping=(alpha, 0.0), loads=[load])
    tip = np.array([(s.t, s.q[-2]) for s in simulate(model, 2e-4, 0.6)])
    late = tip[tip[:, 0] > 0.1]
    t_split = 0.35
    amp1 = np.abs(late[late[:, 0] < t_split, 1]).max()
    amp2 = np.abs(late[late[:, 0] >= t_split, 1]).max()
    # peaks of the two windows are about 0.25 s apart: ratio exp(−α/2 · Δt) with Δt ≈ 0.25 s
    ratio = amp2 / amp1
    assert np.exp(-alpha / 2 * 0.3) < ratio < np.exp(-alpha / 2 * 0.2)


def test_time_dependent_load_moves_the_tip_statically():
    """A slowly ramped tip load on a damped cantilever ends at the linear static deflection
    P L³ / (3 E I) (plus the small shear part P L / (κ G A))."""
    L, P = 0.3, 0.2
    beam = Beam2D.straight([0, 0], [L, 0], 16, MATERIAL, SECTION).clamp(0)
    load = NodalLoad(beam, -1, lambda t: np.array([0.0, -P * min(t / 0.5, 1.0), 0.0]))
    model = Model([beam], gravity=(0, 0), damping=(200.0, 0.0), loads=[load])
    *_, last = simulate(model, 1e-3, 1.5)
    EI = MATERIAL.E * SECTION.inertia
    GA = MATERIAL.G * SECTION.area * SECTION.shear_factor
    exact = P * L**3 / (3 * EI) + P * L / GA
    assert -last.q[-2] == pytest.approx(exact, rel=2e-3)


def test_moving_plane_pushes_a_resting_beam():
    """A floor rising at constant speed V under a beam lying on it carries the beam along:
    no penetration, and the beam's velocity equals V once it rides on the floor."""
    from fecontact import Contact, Plane

    V = 0.5
    beam = Beam2D.straight([0, 0], [0.3, 0], 6, MATERIAL, SECTION)
    floor = Plane([0, -0.01], [0, 1], motion=lambda t: np.array([0.0, V * t]))
    model = Model([beam], [Contact(beam, floor)])
    states = list(simulate(model, 1e-3, 0.1))
    for st in states:
        assert st.gaps.min() >= -1e-12
    assert np.allclose(states[-1].v[1::3], V, rtol=1e-6)
    # the floor reaches the beam at t = 0.01/V = 0.02 s; the beam then rides at y = V t − 0.01
    assert beam.positions(states[-1].q)[:, 1] == pytest.approx(V * 0.1 - 0.01, abs=1e-9)


def test_moving_obstacle_validation():
    from fecontact import Plane

    with pytest.raises(InputError, match="motion"):
        Plane([0, 0], [0, 1], motion=3.0)
