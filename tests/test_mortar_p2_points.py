"""The P2 faces' polynomials at integration points by their own partials
(fecontact.contact.mortar_p2_points) against the same polynomials multiplied out in Jets."""

import numpy as np

from fecontact.contact.dual_numbers import Jet
from fecontact.contact.mortar_p2 import shape_functions
from fecontact.contact.mortar_p2_points import polynomials, slave_surface

N = 36  # the pair's coordinates
_P = np.random.default_rng(9).uniform(0.0, 0.5, (10, 2))
_M = np.stack(
    [np.ones(10), _P[:, 0], _P[:, 1], _P[:, 0] ** 2, _P[:, 0] * _P[:, 1], _P[:, 1] ** 2], 1
)
_C = np.linalg.lstsq(_M, shape_functions("triangle", _P), rcond=None)[0]  # N_k = Σ_m C_mk mono_m


def _points(B: int, seed: int):
    """Points (s, t) as Jets of the first variables: nonlinear functions of them, so that
    their gradients and Hessians are dense."""
    rng = np.random.default_rng(seed)
    z = rng.uniform(0.1, 0.4, (B, N))
    v = Jet.variables(z, True)
    s = v[0] * v[20] + v[3] * v[3] * 0.5 + v[30].sqrt()
    t = v[1] * v[25] - v[4] * v[19] * v[33] + 0.3
    return z, v, s, t


def _monomials(s, t):
    return [s * 0.0 + 1.0, s, t, s * s, s * t, t * t]


def _close(a, b):
    # the two evaluations sum the same terms in other orders: round-off of the largest term
    # (entries of order 1 here, 36 × 36 Hessians of products of a few factors; measured
    # 6.8e-16, a margin of 150 for other BLAS and summation orders)
    return np.max(np.abs(a - b)) <= 1e-13 * max(np.max(np.abs(b)), 1.0)


def test_polynomials_match_their_products_of_jets():
    _, _, s, t = _points(40, 0)
    A = np.random.default_rng(1).normal(size=(6, 5))
    v, g, h = polynomials(A, s, t)
    mono = _monomials(s, t)
    for j in range(5):
        f = sum(mono[m] * A[m, j] for m in range(6))
        assert _close(v[:, j], f.v) and _close(g[:, j], f.g) and _close(h[:, j], f.h)
    v1, g1, h1 = polynomials(A, s, t, hessian=False)
    assert h1 is None and np.array_equal(v1, v) and np.array_equal(g1, g)


def test_slave_surface_matches_the_nodes_multiplied_out_in_jets():
    """x = Σ_k N_k(s, t) x_k and its tangents, the nodes x_k the first 18 variables: the
    terms of the nodes' own motion included."""
    z, var, s, t = _points(30, 2)
    X = z[:, :18].reshape(-1, 6, 3)
    x, xs, xt = slave_surface(_C, X, s, t)
    mono = _monomials(s, t)
    ds = [s * 0.0, s * 0.0 + 1.0, s * 0.0, s * 2.0, t, s * 0.0]
    dt = [s * 0.0, s * 0.0, s * 0.0 + 1.0, s * 0.0, s, t * 2.0]
    for basis, got in ((mono, x), (ds, xs), (dt, xt)):
        N = [sum(basis[m] * _C[m, k] for m in range(6)) for k in range(6)]
        for d in range(3):
            want = sum(N[k] * var[3 * k + d] for k in range(6))
            assert _close(got[d].v, want.v) and _close(got[d].g, want.g)
            assert _close(got[d].h, want.h)
