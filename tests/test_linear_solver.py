"""Factorizations of large linear models: done once per run, in the symmetric mode of SuperLU.

A linear elastic solid has a constant iteration matrix S = β′M + K: a run of many steps must
factorize it once (and the mass once), however its time step rounds, and must not reassemble
it. Symmetric factorizations must solve as accurately as the general ones.
"""

import numpy as np
import pytest
import scipy.sparse as sp

import fecontact.integrator as integrator
import fecontact.model as model_module
from fecontact import Contact, LinearElastic, Model, Plane, Solid, simulate
from fecontact.linalg import factorize


def counted(monkeypatch):
    """Count the calls of ``factorize`` from the model and the integrator."""
    calls = []

    def wrapper(A, symmetric=False):
        calls.append((A.shape[0], symmetric))
        return factorize(A, symmetric)

    monkeypatch.setattr(model_module, "factorize", wrapper)
    monkeypatch.setattr(integrator, "factorize", wrapper)
    return calls


def falling_ball(refinements=2):
    mat = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
    ball = Solid.ball([0.0, 0.0, 0.05], 0.05, refinements, mat)
    model = Model([ball], [Contact(ball, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]))])
    return model, model.translation(ball, (0.0, 0.0, -1.0))


def test_linear_solid_in_contact_factorizes_once_per_run(monkeypatch):
    model, v0 = falling_ball()
    assert model.n_free > 120  # sparse factorizations
    calls = counted(monkeypatch)
    assembled = []
    assemble = model.pattern.assemble
    monkeypatch.setattr(model.pattern, "assemble", lambda v: assembled.append(1) or assemble(v))
    # n·dt − (n − 1)·dt is not dt to the last bit for this dt: the step must still be dt
    dt = 1e-5 / 3.0
    steps = list(simulate(model, dt, 60 * dt, v0=v0))
    assert len(steps) == 61
    assert sum(np.count_nonzero(st.impulse) for st in steps) > 0  # contact was resolved
    # the mass (initial acceleration, velocity jumps) and S, each once and symmetric
    assert calls == [(model.n_free, True)] * 2
    assert len(assembled) == 1
    assert len(model._iteration_matrices) == 1


def test_column_cache_solves_only_for_new_contacts(monkeypatch):
    """H⁻¹G_jᵀ and M⁻¹G_jᵀ are kept per contact: the right-hand sides solved with the
    factors after the first step are one per step (the smooth step) plus one per contact
    that becomes a candidate for the first time, per metric."""
    model, v0 = falling_ball()
    S, solve_S, C = model.iteration_matrix(*_bp_gp(model, 1e-5))
    columns = []

    def solve(b):
        b = np.asarray(b)
        columns.append(1 if b.ndim == 1 else b.shape[1])
        return solve_S(b)

    model._iteration_matrices[next(iter(model._iteration_matrices))] = (S, solve, C)
    states = list(simulate(model, 1e-5, 40e-5, v0=v0))
    seen = set()
    for st in states:
        seen.update(st.candidates.tolist())
    steps = len(states) - 1
    assert sum(columns) <= steps + len(seen)
    assert len(model.column_cache[("stiffness", *_bp_gp(model, 1e-5))]) == len(seen)


def _bp_gp(model, h):
    c = integrator._Coefficients(integrator.IntegratorOptions().rho_inf, h)
    return c.bp, c.gp


@pytest.mark.parametrize("n", [50, 400])
def test_symmetric_factorization_solves_like_the_general_one(n):
    """Positive definite and indefinite symmetric matrices (a buckling tangent), dense and
    sparse: the symmetric mode returns the same solution to round-off."""
    rng = np.random.default_rng(3)
    A = sp.random(n, n, density=8.0 / n, random_state=rng)
    A = A + A.T + sp.diags(rng.uniform(-1.0, 1.0, n))
    B = rng.standard_normal((n, 3))
    for shift in (0.0, 20.0):  # indefinite, then positive definite
        As = (A + shift * sp.identity(n)).tocsc()
        x_general = factorize(As)(B)
        x_symmetric = factorize(As, symmetric=True)(B)
        assert np.allclose(As @ x_symmetric, B, atol=1e-9 * np.abs(B).max())
        assert np.allclose(x_symmetric, x_general, rtol=1e-8, atol=1e-10)
