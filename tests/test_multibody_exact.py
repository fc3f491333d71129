"""Rigid bodies in space beyond the cases against closed forms (benchmarks/explore_multibody.py
measures more of them): a torque-free flip on the minor-axis side of the separatrix, a top
released nearly upright above the sleeping threshold, a rod struck off its centre."""

import numpy as np
import pytest
from conftest import load_case
from scipy.special import ellipk

from fecontact import Box, Capsule, Contact, IntegratorOptions, Model, RigidBody3D
from fecontact.time.simulate import simulate

G = 9.81


def test_flip_on_the_minor_side_of_the_separatrix_has_the_elliptic_half_period():
    """Ω₀ = (0.3, 6, 0): L² < 2E J₂, so J₁ and J₃ swap roles in λ and k. At h = 2 ms the
    mean interval between sign changes of Ω₂ is within 1.3e-7 of 2K(k)/λ; asked 1e-5, well
    under the second-order step's (Ωh)² = 1.4e-4 and far from a first-order error (Ωh)."""
    body = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Box(0.3, 0.2, 0.1))
    J, W0 = np.diag(body.J), np.array([0.3, 6.0, 0.0])
    E2, L2 = W0 @ (J * W0), np.sum((J * W0) ** 2)
    assert L2 < E2 * J[1]
    lam = np.sqrt((J[1] - J[0]) * (E2 * J[2] - L2) / np.prod(J))
    k2 = (J[2] - J[1]) * (L2 - E2 * J[0]) / ((J[1] - J[0]) * (E2 * J[2] - L2))
    half = 2.0 * ellipk(k2) / lam  # 2.939 s
    model = Model([body], gravity=(0.0, 0.0, 0.0))
    states = list(simulate(model, 2e-3, 3.3 * half, v0=np.r_[0.0, 0.0, 0.0, W0]))
    t, w = np.array([s.t for s in states]), np.array([s.v[4] for s in states])
    i = np.flatnonzero(np.sign(w[:-1]) != np.sign(w[1:]))
    cross = t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])
    assert len(cross) == 3
    assert np.mean(np.diff(cross)) == pytest.approx(half, rel=1e-5)


def test_a_top_released_near_upright_above_the_threshold_nutates_to_the_cubics_root():
    """Released at θ₀ = 0.01 rad spinning at 1.5 ω_c (ω_c = 2√(A_O mgℓ)/C): the nutation's
    bottom u₁ is the lower root of b(1 − u²) = β²(u₀ − u), 1 − u₁ = 2β²(1 − u₀)/(s + √D),
    s = β² − 2b. At h = 0.5 ms the largest tilt is within 2.6e-4 of it (asked 2e-3: the
    nutation's period is 90 steps, so an O(h²) phase error of 1e-4 per period)."""
    top = load_case("heavy_top")
    sim = top.build()
    body, arm = sim.model.bodies[0], sim.parameters["arm"]
    A_O, C = body.J[0, 0] + body.mass * arm**2, body.J[2, 2]
    mgl = body.mass * G * arm
    spin, tilt = 1.5 * 2.0 * np.sqrt(A_O * mgl) / C, 0.01
    b, beta2 = 2.0 * mgl / A_O, (C * spin / A_O) ** 2
    s, w0 = beta2 - 2.0 * b, 2.0 * np.sin(0.5 * tilt) ** 2
    w1 = 2.0 * beta2 * w0 / (s + np.sqrt(s * s + 4.0 * b * beta2 * w0))
    theta_max = 2.0 * np.arcsin(np.sqrt(0.5 * w1))  # 0.013416 rad
    sim = top.build(tilt=tilt, spin=spin, dt=5e-4, t_end=0.5)
    states = simulate(sim.model, sim.dt, sim.t_end, q0=sim.q0, v0=sim.v0)
    theta = max(float(np.arccos(top.top_axis(st)[2])) for st in states)
    assert theta == pytest.approx(theta_max, rel=2e-3)


def test_a_rod_struck_off_its_centre_turns_as_newtons_law_gives():
    """A capsule rod falling flat at v onto a held capsule post d = 0.2 m off its centre,
    e = 0.5, no friction: its angular momentum about the centre after the impact is
    −P d, P = (1 + e)v/(1/m + d²/I). The located impact leaves it 2.8e-12 off; asked 1e-9
    (gravity exerts no torque about the centre, so nothing of the step's order enters)."""
    e, d, z0 = 0.5, 0.2, 0.031
    rod = RigidBody3D.uniform(1.0, [0.0, 0.0, z0], Capsule(0.01, 0.5))
    post = RigidBody3D.uniform(10.0, [d, 0.0, -0.15], Capsule(0.02, 0.3)).fix()
    model = Model([rod, post], [Contact(rod, post, restitution=e)], gravity=(0.0, 0.0, -G))
    q0, v0 = np.zeros(model.n), np.zeros(model.n)
    q0[4], v0[2] = np.pi / 2, -1.0  # the axis along x, falling at 1 m/s
    last = list(simulate(model, 1e-3, 0.02, q0=q0, v0=v0))[-1]
    v = np.sqrt(1.0 + 2.0 * G * (z0 - 0.03))  # at the touch, 1 mm lower
    inertia = rod.J[0, 0]
    P = (1.0 + e) * v / (1.0 / rod.mass + d * d / inertia)
    H = rod.rotation(last.q[:6]) @ (rod.J @ last.v[3:6])
    assert H[1] == pytest.approx(-P * d, rel=1e-9)
    assert abs(H[0]) < 1e-12 and abs(H[2]) < 1e-12  # struck under its axis: a turn about y


def test_a_rod_struck_while_sliding_across_a_post_sticks_under_newtons_law():
    """The rod of the test above, sliding at 0.5 m/s across the post (μ = 0.3), started so
    that it is over the post's apex at the touch. The impact sticks (|P_T| = 0.71 μ P_N):
    P = D⁻¹(u⁺ − u⁻) with u⁺ = (0, 0, e v), D = I/m − [r]× J⁻¹[r]× at r = (d, 0, −radius), so
    friction along x, a radius below the axis, turns the rod about y too: H_y = (r × P)_y,
    1.6e-3 off the frictionless −P d. Frictional impacts of rigid bodies are not located:
    the step holding the touch ends 15 μs after it, where the rod has slid 7.4 μm over the
    cap (a normal tilted by 2.5e-4 rad); H there is 5.3e-5 off r × P. With the acceleration
    restarted after the impact (smooth_contact "on") ten steps later it is 6.4e-5 off; with
    the decoupled step (the default "off" of rigid bodies) too, now that its v̇ and a follow
    the gyroscopic torque through the jump (1.0e-2 before: the step after the impact
    integrated the torque of the new spin, 20.8 rad/s about the axis, from the pre-impact
    acceleration, an O(h) error; docs/validation/multibody.md). Asked 2e-4, 4 times the
    step-end offset, 8 times under the frictionless answer's."""
    e, d, z0, mu, vy = 0.5, 0.2, 0.031, 0.3, 0.5
    rod = RigidBody3D.uniform(1.0, [0.0, 0.0, z0], Capsule(0.01, 0.5))
    post = RigidBody3D.uniform(10.0, [d, 0.0, -0.15], Capsule(0.02, 0.3)).fix()
    contact = Contact(rod, post, restitution=e, friction=mu)
    model = Model([rod, post], [contact], gravity=(0.0, 0.0, -G))
    v = np.sqrt(1.0 + 2.0 * G * (z0 - 0.03))  # at the touch, 1 mm lower
    q0, v0 = np.zeros(model.n), np.zeros(model.n)
    q0[1], q0[4], v0[1:3] = -vy * (v - 1.0) / G, np.pi / 2, (vy, -1.0)
    R = rod.rotation(q0[:6])
    r = np.array([d, 0.0, -0.01])
    rx = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
    D = np.eye(3) / rod.mass - rx @ np.linalg.solve(R @ rod.J @ R.T, rx)
    P = np.linalg.solve(D, np.array([0.0, -vy, (1.0 + e) * v]))
    assert np.hypot(P[0], P[1]) < mu * P[2]  # stuck: Coulomb's law holds the stuck impulse
    exact = np.cross(r, P)
    for smooth, steps, rel in (("off", 10, 2e-4), ("on", 10, 2e-4)):
        opts = IntegratorOptions(smooth_contact=smooth)
        states = list(simulate(model, 1e-3, steps * 1e-3, opts, q0=q0, v0=v0))
        H = rod.rotation(states[-1].q[:6]) @ (rod.J @ states[-1].v[3:6])
        assert np.linalg.norm(H - exact) < rel * np.linalg.norm(exact), smooth
