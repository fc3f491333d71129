"""The ConvexMesh shape: volume, centre and inertia of the solid hull against closed forms."""

import numpy as np
import pytest

from fecontact import Box, ConvexMesh, InputError, RigidBody3D


def test_a_cube_mesh_has_the_box_volume_and_inertia_with_extra_interior_points():
    box = Box(0.3, 0.2, 0.1)
    rng = np.random.default_rng(1)
    inside = (rng.random((20, 3)) - 0.5) * box.sides * 0.9
    shifted = np.vstack([box.vertices, inside]) + [1.0, -2.0, 0.5]
    mesh = ConvexMesh(shifted)
    assert len(mesh.vertices) == 8
    np.testing.assert_allclose(mesh.offset, [1.0, -2.0, 0.5], rtol=0, atol=1e-15)
    assert mesh.volume == pytest.approx(box.volume, rel=1e-14)
    # the tetrahedra sum is exact: round-off only
    np.testing.assert_allclose(mesh.inertia(2.0), box.inertia(2.0), rtol=0, atol=1e-15)


def test_the_unit_tetrahedron_has_its_closed_form_centre_and_inertia():
    P = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    mesh = ConvexMesh(P)
    assert mesh.volume == pytest.approx(1.0 / 6.0, rel=1e-14)
    np.testing.assert_allclose(mesh.offset, [0.25, 0.25, 0.25], atol=1e-15)
    # closed form about the right-angle vertex: ∫x² dV = 1/60, ∫xy dV = 1/120; mass 6 is
    # density 36, then the parallel axes to the centre
    m = 6.0
    S0 = 36.0 * (np.full((3, 3), 1.0 / 120.0) + np.eye(3) / 120.0)
    S = S0 - m * np.outer(mesh.offset, mesh.offset)
    np.testing.assert_allclose(mesh.inertia(m), np.trace(S) * np.eye(3) - S, atol=1e-14)


def test_a_rotated_box_mesh_gives_the_rotated_tensor_and_a_body():
    c, s = np.cos(0.4), np.sin(0.4)
    Q = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    box = Box(0.3, 0.2, 0.1)
    mesh = ConvexMesh(box.vertices @ Q.T)
    np.testing.assert_allclose(mesh.inertia(1.0), Q @ box.inertia(1.0) @ Q.T, atol=1e-15)
    body = RigidBody3D.uniform(1.0, [0.0, 0.0, 1.0], mesh)
    P, T = body.shape.surface()
    # outward triangles: the divergence theorem gives the volume back
    a, b, cc = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    assert np.einsum("ti,ti->", a, np.cross(b, cc)) / 6.0 == pytest.approx(box.volume, rel=1e-13)


def test_flat_or_too_few_points_are_refused():
    with pytest.raises(InputError, match="points"):
        ConvexMesh([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    with pytest.raises(InputError, match="no volume"):
        ConvexMesh([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
