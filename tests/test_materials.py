"""Materials: stresses and tangents are exact derivatives, plane reductions, input rules."""

import math

import numpy as np
import pytest

from fecontact import InputError
from fecontact.bodies.materials import LinearElastic, NeoHookean, StVenantKirchhoff

MATERIALS = {
    "linear": LinearElastic(E=2.0e9, nu=0.3, rho=1200.0),
    "svk": StVenantKirchhoff(E=2.0e9, nu=0.3, rho=1200.0),
    "neo-hookean": NeoHookean(E=2.0e9, nu=0.3, rho=1200.0),
}


def random_strain(d, n, size, seed):
    """n symmetric strains (d, d, n) with entries of order ``size``."""
    A = size * np.random.default_rng(seed).normal(size=(d, d, n))
    return 0.5 * (A + A.swapaxes(0, 1))


def directional(fn, E, D, h):
    return (fn(E + h * D) - fn(E - h * D)) / (2.0 * h)


@pytest.mark.parametrize("name", MATERIALS)
@pytest.mark.parametrize("plane", [None, "strain", "stress"])
def test_stress_and_tangent_are_derivatives(name, plane):
    mat = MATERIALS[name]
    d = 3 if plane is None else 2
    E = random_strain(d, 6, 0.1, seed=1)
    D = random_strain(d, 6, 1.0, seed=2)
    W, S, CC = mat.response(E, plane)
    CC = np.broadcast_to(CC, (d, d, d, d, 6))
    h = 1e-6
    dW = directional(lambda X: mat.response(X, plane, tangent=False)[0], E, D, h)
    dS = directional(lambda X: mat.response(X, plane, tangent=False)[1], E, D, h)
    assert np.allclose(dW, np.einsum("ijn,ijn->n", S, D), rtol=1e-7, atol=1e-9 * mat.E)
    assert np.allclose(dS, np.einsum("ijkln,kln->ijn", CC, D), rtol=1e-6, atol=1e-7 * mat.E)
    # major and minor symmetries of ℂ
    assert np.allclose(CC, CC.transpose(2, 3, 0, 1, 4), atol=1e-9 * mat.E)
    assert np.allclose(CC, CC.transpose(1, 0, 2, 3, 4), atol=1e-9 * mat.E)


@pytest.mark.parametrize("name", MATERIALS)
def test_plane_strain_is_the_3d_response_with_zero_out_of_plane_strain(name):
    mat = MATERIALS[name]
    E2 = random_strain(2, 5, 0.05, seed=3)
    E3 = np.zeros((3, 3, 5))
    E3[:2, :2] = E2
    W2, S2, _ = mat.response(E2, "strain")
    W3, S3, _ = mat.response(E3)
    assert np.allclose(W2, W3) and np.allclose(S2, S3[:2, :2])
    E33, S33 = mat.out_of_plane(E2, "strain")
    assert np.all(E33 == 0.0) and np.allclose(S33, S3[2, 2])


@pytest.mark.parametrize("name", MATERIALS)
def test_plane_stress_has_zero_out_of_plane_stress(name):
    mat = MATERIALS[name]
    E2 = random_strain(2, 5, 0.1, seed=4)
    E33, S33 = mat.out_of_plane(E2, "stress")
    assert np.max(np.abs(S33)) <= 1e-12 * mat.E
    assert np.all(E33 * np.trace(E2) <= 0.0)  # Poisson contraction opposes the in-plane dilation


def test_linear_plane_stress_is_hooke_with_reduced_lame_constant():
    mat = MATERIALS["linear"]
    eps = np.array([[1e-4, 3e-5], [3e-5, -2e-5]])[:, :, None]
    _, S, _ = mat.response(eps, "stress")
    Y, nu = mat.E, mat.nu
    expected_11 = Y / (1.0 - nu**2) * (eps[0, 0] + nu * eps[1, 1])
    assert S[0, 0, 0] == pytest.approx(expected_11[0], rel=1e-12)
    assert S[0, 1, 0] == pytest.approx(Y / (1.0 + nu) * eps[0, 1, 0], rel=1e-12)


@pytest.mark.parametrize("plane", [None, "strain", "stress"])
@pytest.mark.parametrize("name", ["svk", "neo-hookean"])
def test_nonlinear_materials_reduce_to_hooke_for_small_strains(name, plane):
    d = 3 if plane is None else 2
    E = random_strain(d, 4, 1e-7, seed=5)
    S_lin = MATERIALS["linear"].response(E, plane)[1]
    S = MATERIALS[name].response(E, plane)[1]
    assert np.allclose(S, S_lin, rtol=1e-5, atol=1e-5 * np.abs(S_lin).max())


def test_neo_hookean_uniaxial_stretch_matches_closed_form():
    mat = MATERIALS["neo-hookean"]
    lam, mu = mat.lame
    s = 1.2  # F = diag(s, 1, 1): C = diag(s², 1, 1), J = s
    E = np.zeros((3, 3, 1))
    E[0, 0] = 0.5 * (s * s - 1.0)
    W, S, _ = mat.response(E)
    assert S[0, 0, 0] == pytest.approx(mu * (1 - 1 / s**2) + lam * np.log(s) / s**2, rel=1e-12)
    assert S[1, 1, 0] == pytest.approx(lam * np.log(s), rel=1e-12)
    assert W[0] == pytest.approx(
        0.5 * mu * (s * s - 1 - 2 * np.log(s)) + 0.5 * lam * np.log(s) ** 2
    )


def test_lame_constants_and_wave_speed():
    mat = LinearElastic(E=210e9, nu=0.3, rho=7800.0)
    lam, mu = mat.lame
    assert mu == pytest.approx(210e9 / 2.6)
    assert lam == pytest.approx(210e9 * 0.3 / (1.3 * 0.4))
    assert mat.wave_speed == pytest.approx(math.sqrt((lam + 2 * mu) / 7800.0))
    assert LinearElastic.linear and not StVenantKirchhoff.linear and not NeoHookean.linear


# -- input rules: one test per rule ------------------------------------------------------------


@pytest.mark.parametrize("cls", [LinearElastic, StVenantKirchhoff, NeoHookean])
@pytest.mark.parametrize("E", [-1.0, 0.0])
def test_young_modulus_must_be_positive(cls, E):
    with pytest.raises(InputError, match="E must be > 0"):
        cls(E=E, nu=0.3, rho=1000.0)


@pytest.mark.parametrize("rho", [0.0, -5.0])
def test_density_must_be_positive(rho):
    with pytest.raises(InputError, match="rho must be > 0"):
        NeoHookean(E=1e6, nu=0.3, rho=rho)


@pytest.mark.parametrize("nu", [-1.0, -1.5, 0.5, 0.7])
def test_poisson_ratio_must_lie_in_open_interval(nu):
    with pytest.raises(InputError, match=r"nu must be in \(-1, 0.5\)"):
        StVenantKirchhoff(E=1e6, nu=nu, rho=1000.0)


@pytest.mark.parametrize("field", ["E", "nu", "rho"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, "soft"])
def test_parameters_must_be_finite_numbers(field, bad):
    values = {"E": 1e6, "nu": 0.3, "rho": 1000.0, field: bad}
    with pytest.raises(InputError, match=field):
        LinearElastic(**values)
