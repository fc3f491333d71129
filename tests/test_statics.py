"""A linear solid pressed on a plane (the discrete Signorini problem) and the graded ball mesh
that resolves its contact patch."""

import numpy as np
import pytest

from fecontact import InputError, LinearElastic, Plane, Solid
from fecontact.bodies.meshes import graded_ball_mesh
from fecontact.statics import static_contact

R, E, NU, RHO = 0.05, 1e7, 0.3, 1000.0


def hertz_approach(force):
    """Hertz's approach δ (m) of a sphere of radius R on a rigid plane under ``force`` (N)."""
    e_star = E / (1.0 - NU**2)
    return (3.0 * force / (4.0 * e_star * np.sqrt(R))) ** (2.0 / 3.0)


@pytest.fixture(scope="module")
def pressed():
    """A ball graded to a fifth of Hertz's contact radius, under a body force of 1 N."""
    force = 1.0
    a = np.sqrt(R * hertz_approach(force))
    mesh = graded_ball_mesh([0.0, 0.0, R], R, a / 5.0, [0.0, 0.0, 0.0], 0.5, 2)
    ball = Solid(mesh, LinearElastic(E=E, nu=NU, rho=RHO))
    M, ez = ball.mass_matrix(), ball.translation_field((0.0, 0.0, 1.0))
    load = -(force / ball.mass) * (M @ ez)
    u, touching = static_contact(
        ball, load, Plane([0, 0, 0], [0, 0, 1.0]), 3 * hertz_approach(force)
    )
    return ball, load, u, touching, force


def test_the_plane_carries_the_load_with_compressive_reactions_and_no_gap(pressed):
    ball, load, u, touching, force = pressed
    z = ball.X[:, 2] + u[2::3]
    # round-off of a 1e-4 m approach through a solve of condition ~1e6: 1e-12 R is far above it
    assert z.min() >= -1e-12 * R
    np.testing.assert_allclose(z[touching], 0.0, atol=1e-12 * R)
    # the multipliers: (K + ε M) u = f + Gᵀ r, ε = 1e-6 E/(ρ L²) the default hold, L = R
    hold = 1e-6 * E / (RHO * R**2) * ball.mass_matrix()
    nodal = ((ball.stiffness_matrix() + hold) @ u - load).reshape(-1, 3)
    free = np.setdiff1d(np.arange(len(z)), touching)
    # reactions only where the ball touches, normal to the plane and pushing: elsewhere and
    # tangentially round-off of forces of 1 N through a solve of condition ~1e6
    assert np.abs(nodal[free]).max() < 1e-8 * force
    assert np.abs(nodal[touching, :2]).max() < 1e-8 * force
    assert touching.size > 3 and np.all(nodal[touching, 2] > 0.0)
    # they balance the load but for the hold's share ε m δ (1e-4 here)
    assert nodal[touching, 2].sum() == pytest.approx(force + (hold @ u)[2::3].sum(), rel=1e-9)
    assert nodal[touching, 2].sum() == pytest.approx(force, rel=1e-3)


def test_the_approach_is_hertz_s_to_the_mesh_and_finite_size_error(pressed):
    ball, load, u, touching, force = pressed
    M, ez = ball.mass_matrix(), ball.translation_field((0.0, 0.0, 1.0))
    delta = -(M @ ez) @ u / ball.mass
    # a/R = 0.03 and five cells across the patch radius: within 10 % (the finite ball's own
    # law is 5 % stiffer than Hertz's half-space here, benchmarks/results/hertz_static.md)
    assert delta == pytest.approx(hertz_approach(force), rel=0.10)


def test_the_graded_ball_meets_its_spacing_and_stays_on_the_sphere():
    spacing, toward = 2e-3, np.array([0.0, 0.0, 0.0])
    mesh = graded_ball_mesh([0.0, 0.0, R], R, spacing, toward, 0.5, 2)
    p = mesh.p[:, mesh.t]
    longest = np.max(
        [np.linalg.norm(p[:, i] - p[:, j], axis=0) for i in range(4) for j in range(i)], axis=0
    )
    distance = np.linalg.norm(p.mean(axis=1) - toward[:, None], axis=0)
    assert np.all(longest <= spacing + 0.5 * distance)
    boundary = mesh.p[:, mesh.boundary_nodes()] - np.array([[0.0], [0.0], [R]])
    np.testing.assert_allclose(np.linalg.norm(boundary, axis=0), R, rtol=1e-12)
    assert mesh.t.shape[1] > 8 * 8**2  # refined beyond init_ball(2) near the pole


def test_graded_ball_input_is_checked():
    with pytest.raises(InputError, match="spacing"):
        graded_ball_mesh([0, 0, 0], R, -1.0, [0, 0, -R])
    with pytest.raises(InputError, match="toward"):
        graded_ball_mesh([0, 0, 0], R, 1e-2, [0, 0])
