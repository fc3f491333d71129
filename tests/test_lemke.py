"""Lemke's complementary pivoting (:func:`fecontact.contact.lemke.lemke`) against the
complementary bases enumerated, on regular and on singular matrices."""

import itertools

import numpy as np

from fecontact.contact.lemke import lemke


def complementary_solutions(M, q):
    """Every solution z of the LCP (M, q) at a complementary basis, by enumeration."""
    n, out = len(q), []
    for closed in itertools.product((False, True), repeat=n):
        c = np.flatnonzero(closed)
        z = np.zeros(n)
        if c.size:
            z[c] = np.linalg.lstsq(M[np.ix_(c, c)], -q[c], rcond=None)[0]
        w = q + M @ z
        if z.min() >= -1e-12 and w.min() >= -1e-12 and np.allclose(w[c], 0.0, atol=1e-12):
            out.append(z)
    return out


def test_a_positive_definite_lcp_has_its_one_solution():
    """M = AᵀA + I is positive definite: the solution is unique, and the enumeration finds
    it; Lemke's z agrees to round-off (1e-12 of the unit-sized entries)."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        A = rng.normal(size=(6, 6))
        M, q = A.T @ A + np.eye(6), rng.normal(size=6)
        z, _ = lemke(M, q)
        (expected,) = complementary_solutions(M, q)
        assert np.max(np.abs(z - expected)) <= 1e-12 * np.max(np.abs(expected), initial=1.0)


def test_redundant_rows_with_friction_are_solved_at_any_scale():
    """Four points of one plane on two dofs (M = G S Gᵀ with rank 2, made nonsymmetric by a
    friction-like term μ G S Tᵀ, μ = 0.3), loaded so that a solution exists: z ≥ 0, w ≥ 0
    and zᵀw = 0 to round-off of the largest w (1e-12), at the units of a Delassus matrix
    (1e-5) as at unit scale (the pivots are scaled)."""
    G = np.array([[1.0, 0.5], [1.0, -0.5], [1.0, 0.2], [1.0, -0.9]])
    T = np.array([[0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [0.0, 1.0]])
    M = G @ G.T + 0.3 * G @ T.T
    q = -G @ np.array([1.0, 0.1])
    for scale in (1.0, 1e-5):
        z, _ = lemke(scale * M, scale * q)
        assert z is not None
        w = scale * (q + M @ z)
        bound = 1e-12 * np.max(np.abs(scale * q))
        assert z.min() >= 0.0 and w.min() >= -bound
        assert np.max(np.abs(z * w)) <= bound * np.max(z)
