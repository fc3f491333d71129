"""Dual multipliers of quadratic faces (the basis transformation of Popp, Wohlmuth, Gee & Wall
2012, ``fecontact.contact.mortar_p2``), and what P2 bodies get from mortar contact today: the
patch test on P2 blocks split into linear facets (a strict expected failure, measured)."""

import numpy as np
import pytest

from fecontact.bodies import Solid
from fecontact.contact import Contact
from fecontact.contact.mortar_p2 import (
    dual_coefficients,
    reference_rule,
    shape_functions,
    transformation,
)
from fecontact.errors import InputError
from fecontact.model import Model
from fecontact.scenes import solid_material
from fecontact.statics import solve_static_contact

KINDS = ("segment", "triangle")
# a face of varying measure density (a curved face): J ∝ 1 + 0.3 ξ, 1 + 0.3 λ₂ − 0.2 λ₃
CURVED = {
    "segment": lambda p: 1.0 + 0.3 * p,
    "triangle": lambda p: 1.0 + 0.3 * p[:, 0] - 0.2 * p[:, 1],
}


def integrals(kind, jac=None):
    """Φ (m, n), Ñ (m, n), N (m, n) at the rule's points and their weights (m,)."""
    points, w = reference_rule(kind)
    if jac is not None:
        jac = jac(points)
        w = w * jac
    A, T = dual_coefficients(kind, jacobian=jac)
    N = shape_functions(kind, points)
    Nt = N @ T.T
    return Nt @ A.T, Nt, N, w


def test_corner_functions_of_the_quadratic_triangle_integrate_to_zero():
    """Why the transformation: without it (α = 0) the triangle's corners carry no weight."""
    points, w = reference_rule("triangle")
    D = shape_functions("triangle", points).T @ w
    # the exact values: 0 at the corners, 1/3 of the area at the edge nodes (round-off)
    assert np.allclose(D, [0, 0, 0, 1 / 3, 1 / 3, 1 / 3], rtol=0, atol=1e-15)
    with pytest.raises(InputError, match="integrates to"):
        dual_coefficients("triangle", alpha=0.0)


@pytest.mark.parametrize("kind", KINDS)
def test_transformed_basis_integrates_positively_and_sums_to_one(kind):
    points, w = reference_rule(kind)
    Nt = shape_functions(kind, points) @ transformation(kind).T
    assert np.allclose(Nt.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    expected = {"segment": [1 / 6, 1 / 6, 2 / 3], "triangle": [2 / 15] * 3 + [1 / 5] * 3}
    assert np.allclose(Nt.T @ w, expected[kind], rtol=0, atol=1e-15)
    T = transformation(kind, 0.2)
    # invertible: the same space, only the nodal unknowns change
    assert np.linalg.cond(T) < 10.0


@pytest.mark.parametrize("curved", [False, True])
@pytest.mark.parametrize("kind", KINDS)
def test_dual_functions_are_biorthogonal_and_reproduce_a_uniform_pressure(kind, curved):
    Phi, Nt, N, w = integrals(kind, CURVED[kind] if curved else None)
    D = Nt.T @ w
    # ∫ Φ_j Ñ_k = δ_jk ∫ Ñ_k: exact rule, so to round-off (1e-13 of weights of order 0.1)
    assert np.allclose((Phi * w[:, None]).T @ Nt, np.diag(D), rtol=0, atol=1e-13)
    assert np.allclose(Phi.sum(axis=1), 1.0, rtol=0, atol=1e-12)  # Σ Φ_j = 1
    # a uniform pressure z_j = p puts on each node k of the original basis its consistent
    # load p ∫ N_k (corners of the triangle 0, edge nodes 1/3 of the area)
    p = 1e5
    forces = p * (Phi.sum(axis=1) * w) @ N  # Σ_j z_j ∫ Φ_j N_k
    assert np.allclose(forces, p * (N.T @ w), rtol=1e-13, atol=1e-9)


@pytest.mark.parametrize("kind", KINDS)
def test_weighted_gaps_read_the_transformed_nodal_values(kind):
    """A quadratic gap field g = Σ N_k g_k: its weighted gaps over ∫Ñ_j are the nodal values
    in the transformed basis, (T⁻ᵀ g)_j; a uniform gap reads itself at every node."""
    Phi, Nt, N, w = integrals(kind, CURVED[kind])
    rng = np.random.default_rng(3)
    g = rng.normal(size=N.shape[1])
    read = (Phi * w[:, None]).T @ (N @ g) / (Nt.T @ w)
    T = transformation(kind)
    assert np.allclose(read, np.linalg.solve(T.T, g), rtol=0, atol=1e-12)
    uniform = (Phi * w[:, None]).T @ np.full(len(w), 0.25) / (Nt.T @ w)
    assert np.allclose(uniform, 0.25, rtol=0, atol=1e-14)


def test_bad_input():
    with pytest.raises(InputError, match="kind"):
        transformation("quad")
    with pytest.raises(InputError, match="alpha"):
        transformation("triangle", 0.5)
    with pytest.raises(InputError, match="jacobian"):
        dual_coefficients("segment", jacobian=np.ones(2))


def pressed_p2_blocks(n_lower: int, n_upper: int, p: float = 1e5):
    """The 2D patch test of ``fecontact.testing.pressed_blocks`` on P2 triangles: the upper
    block loaded by its consistent P2 nodal forces p L (1/6, 2/3, 1/6) per top edge. Returns
    the nodal pressures of the contact face over p and the largest displacement error of the
    upper block relative to the exact linear field."""
    E_LOW, E_UP, NU = 1e7, 3e7, 0.3
    mats = [solid_material("linear", E, NU, 1e3) for E in (E_LOW, E_UP)]
    lower = Solid.rectangle([0, 0], [1, 0.5], (n_lower, 3), mats[0], element="P2")
    upper = Solid.rectangle([0, 0.5], [1, 1.0], (n_upper, 3), mats[1], element="P2")
    lower.fix(lower.nodes_where(lambda x: x[1] < 1e-9), "y")
    for b in (lower, upper):
        b.fix(b.nodes_where(lambda x: x[0] < 1e-9), "x")
    pair = Contact(upper, lower, method="mortar")
    model = Model([lower, upper], [pair], gravity=(0.0, 0.0))
    load = np.zeros(model.n)
    top = upper.nodes_where(lambda x: x[1] > 1 - 1e-9)
    top = top[np.argsort(upper.X[top, 0])]  # corner, mid, corner, ... along the top
    o = model.offset_of(upper)
    for a, m, b in zip(top[:-2:2], top[1:-1:2], top[2::2], strict=True):
        length = upper.X[b, 0] - upper.X[a, 0]
        load[o + 2 * np.array([a, m, b]) + 1] -= p * length * np.array([1 / 6, 2 / 3, 1 / 6])
    q, lam = solve_static_contact(model, load, small=True)
    nodes, z = pair.nodal_pressure(lam)
    X = upper.X
    ux = NU * (1 + NU) * p / E_UP * X[:, 0]
    uy = -(1 - NU**2) * p * (0.5 / E_LOW + (X[:, 1] - 0.5) / E_UP)
    exact = np.stack([ux, uy], axis=1)
    error = np.max(np.abs(q[model.body_slice(1)] - exact.ravel())) / np.max(np.abs(exact))
    return z[np.abs(X[nodes, 1] - 0.5) < 1e-9] / p, error


@pytest.mark.xfail(strict=True, reason="P2 faces enter mortar split into linear facets")
def test_p2_patch_test_uniform_pressure():
    """Acceptance 1 on P2 blocks: not met today. The P2 boundary is split through its mid
    nodes into linear facets, whose dual functions put the load (¼, ½, ¼) of an edge on its
    (corner, mid, corner) nodes where the P2 body's uniform stress needs (1/6, 2/3, 1/6).
    Measured (7/5 cells): pressures 0.86-1.19 p, displacement error 1.9 % (P1: 4e-15);
    3D P2 boxes (4/3 cells): 0.57-1.23 p, 5.9 %. The basis transformation above is the part
    of the remedy that is built."""
    pressure, error = pressed_p2_blocks(7, 5)
    assert np.max(np.abs(pressure - 1.0)) <= 1e-8
    assert error <= 1e-8
