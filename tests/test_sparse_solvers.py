"""The sparse solver seam: direct by default (sparse Cholesky for symmetric systems when the
optional package is there, SuperLU otherwise), PARDISO for all when asked."""

import numpy as np
import pytest
import scipy.sparse as sp

from fecontact import InputError
from fecontact.linalg import factorize
from fecontact.linalg.sparse_solvers import sparse_solver, use_sparse_solver


def laplacian(n):
    """A sparse SPD matrix beyond the dense limit: the 2D five-point Laplacian plus I."""
    d = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    return (sp.kron(sp.eye(n), d) + sp.kron(d, sp.eye(n)) + sp.eye(n * n)).tocsr()


@pytest.fixture
def restore():
    before = sparse_solver()
    yield
    use_sparse_solver(before)


def test_direct_is_the_default_and_solves():
    assert sparse_solver() == "direct"
    A = laplacian(20)
    b = np.random.default_rng(0).standard_normal((400, 3))
    np.testing.assert_allclose(A @ factorize(A)(b), b, atol=1e-12)


@pytest.mark.parametrize("name", ["umfpack", "", None, 3])
def test_unknown_solver_is_an_input_error(name, restore):
    with pytest.raises(InputError, match="sparse solver must be one of direct, superlu, pardiso"):
        use_sparse_solver(name)


def test_pardiso_without_its_package_says_how_to_install(restore, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_pardiso(name, *args, **kwargs):
        if name == "pypardiso":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pardiso)
    with pytest.raises(InputError, match=r"fecontact\[pardiso\]"):
        use_sparse_solver("pardiso")
    assert sparse_solver() == "direct"


def test_pardiso_gives_superlu_s_solutions(restore):
    pytest.importorskip("pypardiso")
    A = laplacian(30)
    b = np.random.default_rng(1).standard_normal(900)
    x_superlu = factorize(A)(b)
    use_sparse_solver("pardiso")
    solve = factorize(A)
    np.testing.assert_allclose(solve(b), x_superlu, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(solve(2.0 * b), 2.0 * x_superlu, rtol=1e-10, atol=1e-12)
