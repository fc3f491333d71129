"""Beam3D contact through its segments: tubes of the section's radius against spheres, rigid
balls and capsules, and other tubes (fecontact.contact.beam3d_pairs, .segment3d)."""

import numpy as np
import pytest

from fecontact import Model
from fecontact.bodies import Beam3D, Material, RigidBody3D, Section
from fecontact.bodies.shapes3d import Ball, Box, Capsule
from fecontact.contact import Contact, NodeContact, Sphere
from fecontact.contact.beam3d_pairs import TubeBeamContact, TubeRigidContact, TubeSphereContact
from fecontact.contact.segment3d import tube_distance
from fecontact.errors import InputError
from fecontact.rotations import compose

STEEL = Material(210e9, nu=0.3, rho=7850.0)
R_TUBE = 0.005


def rod(a, b, n=6):
    return Beam3D.straight(a, b, n, STEEL, Section.circle(R_TUBE))


# -- the distance of two segments and its derivatives ----------------------------------------
@pytest.mark.parametrize("k", [1, 2])
def test_segment_distance_derivatives_by_central_differences(k):
    """Gradient and Hessian against central differences of step 1e-6 of random segments and
    points (some parameters inside, some at their bounds): truncation 1e-12 relative, round-off
    of f/1e-6 ≈ 1e-10 on the Hessian."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        ends = rng.normal(size=(2 + k, 3))

        def f(y):
            Y = y.reshape(-1, 3)
            out = tube_distance(Y[None, :2], Y[None, 2:])
            return out[0][0], out[3][0], out[4][0]

        y = ends.ravel()
        _, G, H = f(y)
        for i in range(len(y)):
            d = np.zeros(len(y))
            d[i] = 1e-6
            (fp, Gp, _), (fm, Gm, _) = f(y + d), f(y - d)
            assert (fp - fm) / 2e-6 == pytest.approx(G[i], abs=1e-8)
            np.testing.assert_allclose((Gp - Gm) / 2e-6, H[:, i], atol=2e-7)


def test_crossing_and_parallel_segments_have_their_exact_closest_points():
    P = np.array([[[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]])
    crossing = np.array([[[0.0, -1.0, 0.3], [0.5, 1.0, 0.3]]])
    f, e, (xi, eta), _, _ = tube_distance(P, crossing)
    assert f[0] == pytest.approx(0.3, abs=1e-15)
    np.testing.assert_allclose(e[0], [0.0, 0.0, -1.0], atol=1e-15)
    assert (xi[0], eta[0]) == pytest.approx((0.625, 0.5), abs=1e-15)
    # parallel: the middle of the overlap [−0.5, 1] of the two, not an end
    parallel = np.array([[[-0.5, 0.0, 0.3], [2.0, 0.0, 0.3]]])
    f, e, (xi, eta), G, H = tube_distance(P, parallel)
    assert f[0] == pytest.approx(0.3, abs=1e-15)
    assert xi[0] == pytest.approx(0.625, abs=1e-15) and eta[0] == pytest.approx(0.3, abs=1e-15)
    assert np.all(np.isfinite(H)) and np.allclose(H, H.transpose(0, 2, 1), atol=1e-12)


# -- the pairs: their rows are the derivatives of their gaps ---------------------------------
def moved(model, q, d):
    """q ⊕ d: translations add, rigid rotation vectors compose on the right."""
    out = q + d
    for triple in model.rotations:
        out[triple] = compose(q[triple], d[triple])
    return out


def scenes():
    bar = rod([-0.3, 0.02, 0.11], [0.3, -0.03, 0.1])
    sphere = Sphere([0.01, 0.0, -0.2], 0.3)
    other = rod([0.05, -0.3, 0.125], [-0.02, 0.3, 0.12], n=5)
    ball = RigidBody3D.uniform(1.0, [0.02, 0.01, 0.05], Ball(0.05))
    capsule = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.04], Capsule(0.03, 0.4))
    return [
        ("sphere", [bar], lambda: Contact(bar, sphere, clearance=R_TUBE)),
        ("beam", [bar, other], lambda: Contact(bar, other, clearance=2 * R_TUBE)),
        ("ball", [bar, ball], lambda: Contact(bar, ball, clearance=R_TUBE)),
        ("capsule", [capsule, bar], lambda: Contact(capsule, bar, clearance=R_TUBE)),
    ]


@pytest.mark.parametrize("name", ["sphere", "beam", "ball", "capsule"])
def test_tube_rows_are_the_derivatives_of_the_gaps(name):
    """G against central differences of the gaps and H of G along every dof (rigid rotations
    in the body frame), step 1e-6: agreement to 1e-7 relative (truncation and round-off)."""
    bodies, make = next((b, m) for n, b, m in scenes() if n == name)
    pair = make()
    model = Model(bodies, [pair], gravity=(0.0, 0.0, 0.0))
    rng = np.random.default_rng(5)
    q = 1e-3 * rng.normal(size=model.n)
    for triple in model.rotations:
        q[triple] = [0.3, -0.5, 0.8]
    g, dofs, G, H = pair.evaluate(q)
    lam = rng.uniform(0.5, 1.0, size=pair.size)
    for j in np.unique(dofs):
        d = np.zeros(model.n)
        d[j] = 1e-6
        gp, dp, Gp, _ = pair.evaluate(moved(model, q, d))
        gm, dm, Gm, _ = pair.evaluate(moved(model, q, -d))
        assert np.array_equal(dp, dofs) and np.array_equal(dm, dofs)
        col = np.where(dofs == j, 1.0, 0.0)
        np.testing.assert_allclose((gp - gm) / 2e-6, np.sum(G * col, axis=1), atol=1e-8)
        dF = np.einsum("m,mk->mk", lam, Gp - Gm) / 2e-6
        assert np.allclose(dF, np.einsum("m,mkl,ml->mk", lam, H, col), atol=1e-5)


def test_the_registry_chooses_the_tube_pairs():
    bar = rod([0, 0, 0.1], [1, 0, 0.1])
    other = rod([0.5, -0.5, 0.2], [0.5, 0.5, 0.2])
    assert isinstance(Contact(bar, Sphere([0.5, 0, -1], 1.0)), TubeSphereContact)
    assert isinstance(Contact(bar, Sphere([0.5, 0, -1], 1.0), nodes=[1]), NodeContact)
    assert isinstance(Contact(bar, Sphere([0.5, 0, 0], 2.0, inside=True)), NodeContact)
    assert isinstance(Contact(bar, other, clearance=0.01), TubeBeamContact)
    ball = RigidBody3D.uniform(1.0, [0.5, 0, -1], Ball(0.5))
    assert isinstance(Contact(ball, bar), TubeRigidContact)
    with pytest.raises(InputError, match="clearance"):
        Contact(bar, other)
    with pytest.raises(InputError, match="Ball or a Capsule"):
        Contact(bar, RigidBody3D.uniform(1.0, [0.5, 0, -1], Box(1, 1, 1)))
