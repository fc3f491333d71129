"""Rigid bodies in space on the Lie-group generalized-α step, against exact solutions."""

import numpy as np
import pytest
from scipy.special import ellipj, ellipk

from fecontact import Ball, Box, Capsule, Cylinder, InputError, Model, RigidBody3D
from fecontact.rotations import exp, log
from fecontact.time.configuration import plus
from fecontact.time.simulate import simulate

J = np.array([1.0, 2.0, 3.0])  # kg m², principal moments, the intermediate axis y


def euler_exact(W0):
    """Ω(t) of the torque-free body J with Ω₀ = (0, Ω₂, Ω₃), L² > 2E J₂ (Landau & Lifshitz,
    Mechanics §37): Ω = (A₁ cn τ, A₂ sn τ, A₃ dn τ), τ = λt + K(k), and its period 4K/λ."""
    J1, J2, J3 = J
    E2, L2 = W0 @ (J * W0), np.sum((J * W0) ** 2)
    lam = np.sqrt((J3 - J2) * (L2 - E2 * J1) / (J1 * J2 * J3))
    k2 = (J2 - J1) * (E2 * J3 - L2) / ((J3 - J2) * (L2 - E2 * J1))
    K = ellipk(k2)
    A = np.sqrt(
        [
            (E2 * J3 - L2) / (J1 * (J3 - J1)),
            (E2 * J3 - L2) / (J2 * (J3 - J2)),
            (L2 - E2 * J1) / (J3 * (J3 - J1)),
        ]
    )

    def omega(t):
        sn, cn, dn, _ = ellipj(lam * t + K, k2)
        return A * np.array([cn, sn, dn])

    return omega, 4.0 * K / lam


def free_body(h, t_end, W0):
    body = RigidBody3D(1.0, J, [0.0, 0.0, 0.0], Box(1.0, 1.0, 1.0))
    model = Model([body], gravity=(0.0, 0.0, 0.0))
    return model, list(simulate(model, h, t_end, v0=np.r_[0.0, 0.0, 0.0, W0]))


def test_plus_composes_rotation_vectors_on_the_right_and_adds_the_rest():
    body = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Ball(0.1))
    model = Model([body], gravity=(0.0, 0.0, 0.0))
    q = np.r_[1.0, 2.0, 3.0, 0.3, -0.2, 0.1]
    d = np.r_[0.1, 0.2, 0.3, -0.4, 0.5, 0.6]
    out = plus(model, q, d)
    assert np.array_equal(out[:3], q[:3] + d[:3])
    assert np.allclose(exp(out[3:]), exp(q[3:]) @ exp(d[3:]), atol=1e-15)
    assert np.linalg.norm(log(exp(out[3:]))) <= np.pi


def test_a_rotation_held_in_some_components_only_is_refused():
    body = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Ball(0.1)).fix("rx")
    with pytest.raises(InputError, match="rotation vector"):
        Model([body])


def test_shapes_give_their_classical_inertia():
    m = 3.0
    assert np.allclose(Ball(0.5).inertia(m), 0.4 * m * 0.25 * np.eye(3))
    assert np.allclose(np.diag(Box(1.0, 2.0, 3.0).inertia(m)), m / 12 * np.array([13, 10, 5]))
    assert np.allclose(np.diag(Cylinder(1.0, 2.0).inertia(m)), m * np.array([7 / 12, 7 / 12, 0.5]))
    # a capsule of zero length is a ball, and a long thin one a rod
    assert np.allclose(Capsule(0.5, 1e-9).inertia(m), Ball(0.5).inertia(m), rtol=1e-6)
    rod = Capsule(1e-4, 2.0).inertia(m)
    assert rod[0, 0] == pytest.approx(m * 4.0 / 12.0, rel=1e-3)


def test_dzhanibekov_flip_has_the_period_of_the_elliptic_solution():
    """Spun near its intermediate axis, the body flips every half period 2K/λ; at h = 2 ms
    the measured half period is within 3e-6 of the exact one (asked: 1e-3)."""
    W0 = np.array([0.0, 5.0, 0.05])
    _, T = euler_exact(W0)
    _, states = free_body(2e-3, 0.9 * T, W0)
    t = np.array([s.t for s in states])
    w = np.array([s.v[4] for s in states])
    down = np.flatnonzero((w[:-1] > 0) & (w[1:] <= 0))[0]
    up = np.flatnonzero((w[:-1] < 0) & (w[1:] >= 0))[0]

    def crossing(i):  # linear interpolation: its error O(h²) is far below the tolerance
        return t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])

    assert crossing(up) - crossing(down) == pytest.approx(T / 2, rel=1e-3)
    E = [0.5 * s.v[3:] @ (J * s.v[3:]) for s in states]
    # the energy error of the step, O(h²) over the fast flips (measured 1.4e-5 at h = 2 ms)
    assert np.ptp(E) / E[0] < 1e-4


def test_free_body_converges_at_second_order():
    """Errors of Ω at t = 2 s against the elliptic solution for h = 4, 2, 1 ms: slope 2."""
    W0 = np.array([0.0, 5.0, 0.05])
    omega, _ = euler_exact(W0)
    err = []
    for h in (4e-3, 2e-3, 1e-3):
        _, states = free_body(h, 2.0, W0)
        err.append(np.abs(states[-1].v[3:] - omega(2.0)).max())
    slopes = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all((slopes > 1.9) & (slopes < 2.1)), (err, slopes)


@pytest.mark.parametrize(
    "options, name",
    [
        ({"integrator": "moreau"}, "integrator"),
        ({"integrator": "penalty"}, "integrator"),
        ({"scheme": "energy-decaying"}, "scheme"),
    ],
)
def test_other_integrators_refuse_rotations_in_space_by_name(options, name):
    from fecontact import Contact, IntegratorOptions, Plane

    body = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.6], Box(1.0, 1.0, 1.0))
    floor = Contact(body, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), friction=0.3)
    model = Model([body], [floor], gravity=(0.0, 0.0, 0.0))
    with pytest.raises(InputError, match=name):
        next(simulate(model, 1e-3, 0.01, IntegratorOptions(**options)))


def test_single_vector_paths_of_the_rotations_agree_with_the_vectorised_ones():
    from fecontact.rotations import compose, tangent

    rng = np.random.default_rng(7)
    for scale in (1e-9, 1e-5, 0.3, 3.0):
        psi, delta = rng.normal(size=(2, 3)) * scale
        assert np.allclose(exp(psi), exp(psi[None])[0], rtol=0, atol=1e-15)
        assert np.allclose(tangent(psi), tangent(psi[None])[0], rtol=0, atol=1e-15)
        assert np.allclose(compose(psi, delta), compose(psi[None], delta[None])[0], atol=1e-15)
