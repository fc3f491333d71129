"""Obstacles in 3D: gaps, gradients and Hessians of Plane and Sphere against finite differences,
and node contacts of a 3D solid."""

import numpy as np
import pytest

from fecontact import Contact, InputError, Model
from fecontact.bodies.materials import StVenantKirchhoff
from fecontact.bodies.solid import Solid
from fecontact.contact.obstacles import Circle, Plane, Sphere

RNG = np.random.default_rng(42)


def fd_gradient(obstacle, x, h=1e-6):
    """Central differences of g and of ∂g/∂x with respect to every coordinate of x (m, d)."""
    m, d = x.shape
    dg = np.zeros((m, d))
    dG = np.zeros((m, d, d))
    for k in range(d):
        e = np.zeros(d)
        e[k] = h
        gp, Gp, _ = obstacle.gap(x + e)
        gm, Gm, _ = obstacle.gap(x - e)
        dg[:, k] = (gp - gm) / (2 * h)
        dG[:, :, k] = (Gp - Gm) / (2 * h)
    return dg, dG


def test_plane_3d_gap_gradient_hessian():
    plane = Plane([0.1, -0.2, 0.3], [1.0, 2.0, -2.0])
    assert plane.dim == 3 and np.allclose(plane.normal, [1 / 3, 2 / 3, -2 / 3])
    x = RNG.normal(size=(7, 3))
    g, G, H = plane.gap(x)
    assert np.allclose(g, (x - plane.point) @ plane.normal)
    dg, dG = fd_gradient(plane, x)
    assert np.allclose(G, dg, atol=1e-9) and H is None and np.allclose(dG, 0.0)


@pytest.mark.parametrize("inside", [False, True])
@pytest.mark.parametrize("cls", [Sphere, Circle])
def test_sphere_gap_gradient_hessian(cls, inside):
    c, R = np.array([0.2, -0.1, 0.5]), 0.7
    sphere = cls(c, R, inside=inside)
    assert sphere.dim == 3
    x = c + RNG.normal(size=(9, 3))
    g, G, H = sphere.gap(x)
    r = np.linalg.norm(x - c, axis=1)
    assert np.allclose(g, (R - r) if inside else (r - R))
    dg, dG = fd_gradient(sphere, x)
    assert np.allclose(G, dg, rtol=1e-7, atol=1e-9)
    assert np.allclose(H, dG, rtol=1e-6, atol=1e-8)
    assert np.allclose(H, H.transpose(0, 2, 1))
    assert np.allclose(np.einsum("mij,mj->mi", H, G), 0.0)  # no curvature along the normal


def test_plane_and_circle_2d_unchanged():
    plane = Plane([0.0, -0.3], [2.0, 0.0])
    x = RNG.normal(size=(5, 2))
    g, G, H = plane.gap(x)
    assert np.allclose(g, x[:, 0]) and np.allclose(G, [1.0, 0.0]) and H is None
    assert plane.outline(2.0).shape == (2, 2)
    circle = Circle([0.5, 0.5], 0.25, inside=True)
    g, G, H = circle.gap(x)
    dg, dG = fd_gradient(circle, x)
    assert H.shape == (5, 2, 2) and np.allclose(G, dg, atol=1e-8) and np.allclose(H, dG, atol=1e-6)


def test_outlines_in_3d():
    plane = Plane([0.0, 0.0, 1.0], [0.0, 1.0, 1.0])
    loop = plane.outline(2.0)
    assert loop.shape == (5, 3) and np.allclose(loop[0], loop[-1])
    assert np.allclose((loop - plane.point) @ plane.normal, 0.0)
    assert np.allclose(np.linalg.norm(np.diff(loop, axis=0), axis=1), 2.0)
    sphere = Sphere([1.0, 2.0, 3.0], 0.5)
    pts = sphere.outline(64)
    assert np.allclose(np.linalg.norm(pts - sphere.center, axis=1), 0.5)
    # a single polyline: consecutive points are neighbours on a great circle
    assert np.linalg.norm(np.diff(pts, axis=0), axis=1).max() < 1.01 * 2 * np.pi * 0.5 / 64


def test_dimension_rules():
    with pytest.raises(InputError, match="3 components"):
        Sphere([0.0, 0.0], 1.0)
    with pytest.raises(InputError, match="normal must have 3 components"):
        Plane([0.0, 0.0, 0.0], [0.0, 1.0])
    with pytest.raises(InputError, match="2 or 3 components"):
        Circle([0.0, 0.0, 0.0, 0.0], 1.0)
    with pytest.raises(InputError, match=r"\(m, 3\)"):
        Sphere([0.0, 0.0, 0.0], 1.0).gap(np.zeros((4, 2)))
    with pytest.raises(InputError, match=r"\(m, 2\)"):
        Plane([0.0, 0.0], [0.0, 1.0]).gap(np.zeros((4, 3)))


@pytest.mark.parametrize(
    "obstacle",
    [Plane([0.0, 0.0, -0.02], [0.1, 0.2, 1.0]), Sphere([0.0, 0.0, 0.0], 0.2, inside=True)],
    ids=["plane", "sphere-cavity"],
)
def test_node_contact_of_a_3d_solid_against_finite_differences(obstacle):
    """Through Model and Contact: gap gradients of boundary nodes of a ball w.r.t. all dofs."""
    ball = Solid.ball([0.0, 0.0, 0.1], 0.1, 1, StVenantKirchhoff(E=1e6, nu=0.3, rho=1000.0))
    pair = Contact(ball, obstacle)
    model = Model([ball], [pair], gravity=(0.0, 0.0, -9.81))
    q = 1e-3 * RNG.normal(size=model.n)
    g, dofs, G, H = pair.evaluate(q)
    assert len(g) == len(ball.boundary_nodes()) and G.shape == (len(g), 3)
    h = 1e-7
    for j in range(0, len(g), 7):
        for k in range(3):
            e = np.zeros(model.n)
            e[dofs[j, k]] = h
            dg = (pair.evaluate(q + e)[0][j] - pair.evaluate(q - e)[0][j]) / (2 * h)
            assert dg == pytest.approx(G[j, k], abs=1e-8)
    assert (H is None) == isinstance(obstacle, Plane)


@pytest.mark.parametrize("moving", [False, True])
@pytest.mark.parametrize("dim", [2, 3])
def test_gap_values_are_the_gaps_of_gap(dim, moving):
    """The gaps alone (contacts away from the obstacle need no derivatives) are those of the
    full evaluation, bit for bit, in 2D and 3D, fixed and moving, outside and inside."""
    motion = (lambda t: np.full(dim, 0.1 * t)) if moving else None
    obstacles = [
        Plane(np.zeros(dim), np.arange(1.0, dim + 1.0), motion=motion),
        Circle(np.full(dim, 0.2), 0.7, motion=motion),
        Circle(np.full(dim, 0.2), 0.7, inside=True, motion=motion),
    ]
    x = RNG.normal(size=(6, dim))
    for obstacle in obstacles:
        obstacle.time = 0.3
        assert np.array_equal(obstacle.gap_values(x), obstacle.gap(x)[0])
