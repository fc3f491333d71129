"""Beam2D: exact tangent, rigid-motion invariance, and the rolled-up cantilever."""

import dataclasses

import numpy as np
import pytest

from fecontact import Beam2D, InputError, LinearElastic, Material, Model, Section
from fecontact.statics import solve_static

MATERIAL = Material(E=70e9, nu=0.33, rho=2700.0)
SECTION = Section.rectangle(0.02, 0.002)


def beams():
    return {
        "straight": Beam2D.straight([0, 0], [0.3, 0], 4, MATERIAL, SECTION),
        "inclined": Beam2D.straight([0.1, -0.2], [0.4, 0.35], 5, MATERIAL, SECTION),
        "polyline": Beam2D.polyline(
            [[0, 0], [0.3, 0.1], [0.2, 0.5], [-0.1, 0.6]], [2, 3, 1], MATERIAL, SECTION
        ),
    }


def global_tangent(beam, q):
    _, _, Ke = beam.internal(q)
    K = np.zeros((beam.ndof, beam.ndof))
    for dofs, k in zip(beam.element_dofs, Ke, strict=True):
        K[np.ix_(dofs, dofs)] += k
    return K


def random_state(beam, seed):
    rng = np.random.default_rng(seed)
    q = 0.05 * rng.normal(size=beam.ndof)
    q[2::3] = rng.uniform(-np.pi, np.pi, beam.n_nodes)  # large rotations
    return q


@pytest.mark.parametrize("kind", ["straight", "inclined", "polyline"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_tangent_matches_central_differences(kind, seed):
    beam = beams()[kind]
    q = random_state(beam, seed)
    K = global_tangent(beam, q)
    eps = 1e-6
    K_fd = np.empty_like(K)
    for i in range(beam.ndof):
        dq = np.zeros(beam.ndof)
        dq[i] = eps
        K_fd[:, i] = (beam.internal(q + dq)[1] - beam.internal(q - dq)[1]) / (2 * eps)
    assert np.linalg.norm(K - K_fd) / np.linalg.norm(K) < 1e-6
    assert np.allclose(K, K.T, rtol=0, atol=1e-9 * np.abs(K).max())


@pytest.mark.parametrize("kind", ["straight", "polyline"])
def test_internal_force_is_energy_gradient(kind):
    beam = beams()[kind]
    q = random_state(beam, 7)
    _, f, _ = beam.internal(q)
    eps = 1e-7
    f_fd = np.array(
        [
            (beam.energy(q + eps * e) - beam.energy(q - eps * e)) / (2 * eps)
            for e in np.eye(beam.ndof)
        ]
    )
    assert np.linalg.norm(f - f_fd) / np.linalg.norm(f) < 1e-6


@pytest.mark.parametrize("kind", ["straight", "inclined", "polyline"])
def test_rigid_motion_gives_zero_strain_and_force(kind):
    beam = beams()[kind]
    angle, shift = 2.3, np.array([0.7, -1.1])
    R = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    q = np.zeros((beam.n_nodes, 3))
    q[:, :2] = beam.X @ R.T + shift - beam.X
    q[:, 2] = angle
    W, f, _ = beam.internal(q.ravel())
    EA = MATERIAL.E * SECTION.area
    assert abs(W) < 1e-20 * EA
    assert np.abs(f).max() < 1e-12 * EA
    for strain in beam.strains(q.ravel()):
        assert np.abs(strain).max() < 1e-14


@pytest.mark.parametrize("n_elements", [4, 16])
def test_cantilever_under_end_moment_rolls_into_a_circle(n_elements):
    """A tip moment 2πEI/L bends the clamped beam into a closed circle (exact for this
    element: constant curvature, equal chords)."""
    L = 1.0
    beam = Beam2D.straight(
        [0, 0], [L, 0], n_elements, Material(1e7, nu=0.3, rho=1.0), Section.rectangle(0.1, 0.01)
    ).clamp(0)
    model = Model([beam], gravity=(0, 0))
    EI = beam.material.E * beam.section.inertia
    load = np.zeros(model.n)
    load[-1] = 2 * np.pi * EI / L
    q = solve_static(model, load, steps=20)
    tip = beam.positions(q)[-1]
    assert np.linalg.norm(tip) < 1e-6 * L
    assert q[-1] == pytest.approx(2 * np.pi, rel=1e-9)
    # the nodes are the vertices of a regular polygon: equidistant from their centroid
    x = beam.positions(q)[:-1]
    r = np.linalg.norm(x - x.mean(axis=0), axis=1)
    assert np.allclose(r, L / (2 * n_elements * np.sin(np.pi / n_elements)), rtol=1e-8)


def test_mass_matrix_carries_beam_and_point_masses():
    beam = Beam2D.straight([0, 0], [0.3, 0], 4, MATERIAL, SECTION).add_mass(-1, 0.14)
    M = beam.mass_matrix()
    ones_x = beam.translation_field([1.0, 0.0])
    assert ones_x @ M @ ones_x == pytest.approx(beam.beam_mass + 0.14, rel=1e-12)
    assert np.all(np.linalg.eigvalsh(M.toarray()) > 0)


@pytest.mark.parametrize(
    "make, word",
    [
        (lambda: Material(E=-1.0, rho=1.0), "E"),
        (lambda: Material(E=1.0, rho=0.0), "rho"),
        (lambda: Material(E=1.0, nu=0.7, rho=1.0), "nu"),
        (lambda: Material(E=float("nan"), rho=1.0), "E"),
        (lambda: Section.rectangle(-0.02, 0.002), "width"),
        (lambda: Section(area=1e-4, inertia=0.0), "inertia"),
        (lambda: Beam2D.straight([0, 0], [0, 0], 4, MATERIAL, SECTION), "length"),
        (lambda: Beam2D.straight([0, 0], [1, 0], 0, MATERIAL, SECTION), "n_elements"),
        (lambda: Beam2D([[0, 0], [0, 0], [1, 0]], MATERIAL, SECTION), "nodes"),
        (lambda: Beam2D([[0, 0], [np.inf, 0]], MATERIAL, SECTION), "nodes"),
        (lambda: Beam2D.straight([0, 0], [1, 0], 2, MATERIAL, SECTION).pin(5), "node"),
        (lambda: Beam2D.straight([0, 0], [1, 0], 2, MATERIAL, SECTION).add_mass(0, -1), "mass"),
    ],
)
def test_bad_input_is_rejected_with_the_parameter_named(make, word):
    with pytest.raises(InputError, match=word):
        make()


def test_material_arguments_come_in_the_solids_order_and_only_E_by_position():
    """(E, nu, rho) as for ``LinearElastic``; a call by position in the order of earlier
    versions, Material(E, rho, nu), is an error rather than a density read as ν."""
    assert Material(70e9, nu=0.33, rho=2700.0) == Material(E=70e9, rho=2700.0, nu=0.33)
    for cls in (Material, LinearElastic):
        assert [f.name for f in dataclasses.fields(cls)] == ["E", "nu", "rho"]
    for args in [(70e9, 2700.0), (70e9, 2700.0, 0.33), (70e9, 0.33, 2700.0)]:
        with pytest.raises(TypeError, match="positional"):
            Material(*args)
