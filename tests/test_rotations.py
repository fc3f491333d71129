"""SO(3) by rotation vectors: exp and log invert each other, composition is the matrix
product, and the right tangent is the derivative of exp, checked against finite differences
and closed forms (rotations about a fixed axis add)."""

import math

import numpy as np
import pytest

from fecontact import rotations as so3

RNG = np.random.default_rng(7)


def _vectors(n, largest=np.pi):
    axis = RNG.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    angles = np.concatenate(
        [[0.0, 1e-9, 1e-5, 1e-3, largest - 1e-6, largest], RNG.uniform(0, largest, n - 6)]
    )
    return axis * angles[:, None]


def test_exp_is_a_rotation_about_the_axis():
    psi = _vectors(50)
    R = so3.exp(psi)
    # orthogonal with det 1, and the axis is fixed (round-off of a few ulps of 1)
    assert np.allclose(R @ R.swapaxes(1, 2), np.eye(3), atol=1e-14)
    assert np.allclose(np.linalg.det(R), 1.0, atol=1e-14)
    assert np.allclose(np.einsum("nij,nj->ni", R, psi), psi, atol=1e-14)
    # a quarter turn about z takes x to y
    assert np.allclose(so3.exp([0.0, 0.0, np.pi / 2]) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])


def test_log_inverts_exp_up_to_a_half_turn():
    psi = _vectors(200, largest=np.pi - 1e-6)
    # near θ = π the vector is determined to ~1e-16/|π − θ|; elsewhere to round-off
    assert np.allclose(so3.log(so3.exp(psi)), psi, atol=1e-9, rtol=0)
    small = _vectors(20, largest=1e-3)
    assert np.allclose(so3.log(so3.exp(small)), small, atol=1e-17, rtol=1e-12)


def test_log_of_a_half_turn_is_a_half_turn():
    for axis in np.eye(3):
        psi = so3.log(so3.exp(np.pi * axis))
        assert np.isclose(np.linalg.norm(psi), np.pi)
        assert np.allclose(so3.exp(psi), so3.exp(np.pi * axis), atol=1e-14)


def test_compose_is_the_matrix_product():
    psi, delta = _vectors(100), _vectors(100)
    out = so3.compose(psi, delta)
    assert np.all(np.linalg.norm(out, axis=1) <= np.pi + 1e-12)
    assert np.allclose(so3.exp(out), so3.exp(psi) @ so3.exp(delta), atol=1e-13)


def test_rotations_about_one_axis_add():
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    assert np.allclose(so3.compose(0.3 * axis, 0.4 * axis), 0.7 * axis, atol=1e-15)
    # past a half turn the vector wraps to the other side: 2.0 + 2.0 rad = 4 − 2π about the axis
    assert np.allclose(so3.compose(2.0 * axis, 2.0 * axis), (4.0 - 2 * np.pi) * axis, atol=1e-14)


@pytest.mark.parametrize("scale", [1e-6, 1e-2, 1.0, 3.0])
def test_tangent_is_the_derivative_of_exp(scale):
    psi = _vectors(10, largest=scale)[6:] if scale < 1 else RNG.normal(size=(4, 3)) * scale / 2
    delta = RNG.normal(size=(len(psi), 3))
    eps = 1e-6
    # central differences of exp(ψ)ᵀ exp(ψ + εδ): error O(ε²) ~ 1e-12 relative
    dR = (so3.exp(psi + eps * delta) - so3.exp(psi - eps * delta)) / (2 * eps)
    body = so3.vee(so3.exp(psi).swapaxes(1, 2) @ dR)
    assert np.allclose(body, np.einsum("nij,nj->ni", so3.tangent(psi), delta), atol=1e-8)


def test_tangent_inverse():
    psi = np.concatenate([_vectors(30, largest=3.0), np.zeros((1, 3))])
    eye = so3.tangent(psi) @ so3.tangent_inverse(psi)
    assert np.allclose(eye, np.eye(3), atol=1e-12)


def test_hat_and_vee():
    w, a = RNG.normal(size=(5, 3)), RNG.normal(size=(5, 3))
    assert np.allclose(np.einsum("nij,nj->ni", so3.hat(w), a), np.cross(w, a))
    assert np.allclose(so3.vee(so3.hat(w)), w)


def test_one_vector_and_many_agree_and_the_coefficients_have_no_cancellation():
    # the single-vector paths (math) and the vectorised ones: the same formulas, to round-off
    psi = _vectors(40)
    for f in (so3.exp, so3.tangent):
        many, one = f(psi), np.array([f(p) for p in psi])
        assert np.abs(many - one).max() <= 1e-15
    delta = _vectors(40, largest=0.3)[::-1]
    pairs = np.array([so3.compose(p, d) for p, d in zip(psi, delta, strict=True)])
    kept = so3.compose_quaternions(so3.quaternions(psi), delta)  # q_n's quaternions kept
    assert np.abs(kept - so3.compose(psi, delta)).max() == 0.0
    assert np.allclose(kept, pairs, atol=1e-14, rtol=0)
    # T's ψ̃² coefficient c = (θ − sin θ)/θ³, below and above the switch from its series
    # (θ² = 1/16), against 25 terms of Σ (−θ²)^k/(2k + 3)! (below 1e-16 at θ ≤ 2): with
    # ψ = θ (1, 1, 0)/√2, T_01 = c ψ_x ψ_y = c θ²/2
    theta = np.array([1e-8, 1e-4, 2e-4, 1e-3, 0.2, 0.2499, 0.2501, 0.5, 2.0])
    exact = sum((-(theta**2)) ** k / math.factorial(2 * k + 3) for k in range(25))
    T = so3.tangent(theta[:, None] * np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0))
    np.testing.assert_allclose(2.0 * T[:, 0, 1] / theta**2, exact, rtol=1e-13, atol=0)


def test_right_increments_compose_and_give_the_tangent_of_the_increment():
    # a Newton iteration's increments on fixed rotations: ψ ⊕ Δ and T(Δ) as compose and
    # tangent, through both branches of T's ψ̃² coefficient (θ² = 1/16) and up to a half turn
    psi = _vectors(40)
    increments = so3.RightIncrements(psi)
    for largest in (1e-6, 0.2, 0.3, np.pi):
        delta = _vectors(40, largest=largest)[::-1]
        # the same formulas but for the order of the quaternion product's sums: round-off of
        # a few ulps of angles up to π
        np.testing.assert_allclose(
            increments.compose(delta), so3.compose(psi, delta), rtol=0, atol=1e-14
        )
        np.testing.assert_allclose(increments.tangent(), so3.tangent(delta), rtol=0, atol=1e-15)


@pytest.mark.parametrize(
    "shapes", [((3,), (3,)), ((7, 3), (3,)), ((3,), (7, 3)), ((5, 1, 3), (1, 4, 3))]
)
def test_cross_is_numpys_to_the_bit_and_matches_hat(shapes):
    # the same products and differences in the same order as numpy.cross: equal bits, which
    # keeps every run that used numpy.cross unchanged
    rng = np.random.default_rng(3)
    a, b = (rng.standard_normal(s) * 10.0 ** rng.integers(-8, 8, s) for s in shapes)
    assert np.array_equal(so3.cross(a, b), np.cross(a, b))
    # and it is w̃ a: einsum may sum the products in another order (or fused), a few ulps of
    # components below 30 here
    w, v = rng.standard_normal((2, 9, 3))
    np.testing.assert_allclose(so3.cross(w, v), np.einsum("nij,nj->ni", so3.hat(w), v), atol=1e-13)
