"""Preconditioned CG behind the factorize seam (sparse solver "amg"): the direct solutions to
its tolerance, the fallback on indefinite matrices, hierarchy reuse, and whole runs."""

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fecontact import InputError, Model, simulate
from fecontact.bodies import Beam2D, LinearElastic, Material, Section, Solid, StVenantKirchhoff
from fecontact.linalg import LinearSolver, factorize
from fecontact.linalg.iterative import RTOL, TRUE_RESIDUAL
from fecontact.linalg.sparse_solvers import sparse_solver, use_sparse_solver
from fecontact.testing import case
from fecontact.time import StepStats, alpha_coefficients
from fecontact.time.constraints import StepFailure, factorize_or_fail

# the solver's promise: ‖b − A x‖ ≤ TRUE_RESIDUAL · RTOL · ‖b‖
PROMISE = TRUE_RESIDUAL * RTOL


@pytest.fixture
def amg():
    """A linear solver by AMG-CG that counts its own work, with "amg" the process default
    meanwhile."""
    before = sparse_solver()
    use_sparse_solver("amg")
    yield LinearSolver("amg")
    use_sparse_solver(before)


def work(solver) -> dict:
    """The CG work ``solver`` has counted."""
    return dataclasses.asdict(solver.iterative)


def iteration_matrix(model, h, q=None):
    """S = β′M + K_t at q (m) for the step h (s), ρ∞ = 0.5."""
    am, af, _, be = alpha_coefficients(0.5)
    bp = (1.0 - am) / (be * h * h * (1.0 - af))
    _, _, K = model.internal(np.zeros(model.n) if q is None else q)
    return model.iteration_sum(bp, K)


def box(divisions, material=None):
    """A 0.1 m × 0.1 m × 0.05 m block of P1 tetrahedra (rubber-like, E = 10 MPa)."""
    material = material or StVenantKirchhoff(E=1e7, nu=0.3, rho=1000.0)
    body = Solid.box([0.0, 0.0, 0.0], [0.1, 0.1, 0.05], divisions, material)
    return Model([body])


def condition_number(A) -> float:
    lmax = spla.eigsh(A, k=1, which="LA", return_eigenvectors=False)[0]
    lmin = spla.eigsh(A, k=1, sigma=0.0, which="LM", return_eigenvectors=False)[0]
    return lmax / lmin


def check_against_direct(A, b, x):
    """x solves A x = b as promised, and differs from the direct solution by at most what the
    residual allows: ‖δx‖/‖x‖ ≤ κ(A) ‖r‖/‖b‖."""
    kappa = condition_number(A)
    x_direct = spla.spsolve(A.tocsc(), b)
    for j in range(b.shape[1]):
        r = b[:, j] - A @ x[:, j]
        assert np.linalg.norm(r) <= PROMISE * np.linalg.norm(b[:, j])
        error = np.linalg.norm(x[:, j] - x_direct[:, j]) / np.linalg.norm(x_direct[:, j])
        assert error <= kappa * PROMISE


@pytest.mark.parametrize(
    "divisions, h, preconditioner",
    # at the wave-resolving step β′M dominates: the diagonal suffices; at 10 ms K_t does
    [((8, 8, 4), 1e-5, "diagonal"), ((9, 9, 5), 1e-2, "setups")],
)
def test_cg_solves_3d_elasticity_like_the_direct_factorization(amg, divisions, h, preconditioner):
    model = box(divisions)
    rng = np.random.default_rng(0)
    q = 1e-3 * rng.standard_normal(model.n)  # a deformed state: a nonlinear tangent K_t
    A = iteration_matrix(model, h, q)
    b = rng.standard_normal((model.n_free, 3))
    x = factorize(A, symmetric=True, solver=amg)(b)
    assert x.shape == b.shape
    check_against_direct(A, b, x)
    done = work(amg)
    assert done["solves"] == 3 and done["fallbacks"] == 0 and done[preconditioner] >= 1


def test_rigid_modes_are_the_null_space_of_the_stiffness():
    """The near-null space the models hand to AMG: rigid motions carry no strain energy."""
    rubber = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
    solid3 = Solid.box([0, 0, 0], [0.2, 0.1, 0.1], (4, 2, 2), rubber)
    solid2 = Solid.rectangle([0, 0], [0.2, 0.1], (8, 4), rubber)
    beam = Beam2D.straight(
        [0, 0], [1.0, 0.5], 50, Material(E=2e11, nu=0.3, rho=7850.0), Section.rectangle(0.02, 0.01)
    )
    for body, k in ((solid3, 6), (solid2, 3), (beam, 3)):
        model = Model([body])
        _, _, K = model.internal(np.zeros(model.n))
        B = model.rigid_modes
        assert B.shape == (model.n_free, k) and np.linalg.matrix_rank(B) == k
        # round-off of sums of ~30 terms of size |K||B|: 1e-12 is far above it
        scale = abs(K).max() * np.abs(B).max()
        assert np.abs(K @ B).max() <= 1e-12 * scale


def laplacian(n):
    """The 2D five-point Laplacian plus I (n² unknowns): eigenvalues in (1, 9)."""
    d = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    return (sp.kron(sp.eye(n), d) + sp.kron(d, sp.eye(n)) + sp.eye(n * n)).tocsr()


@pytest.mark.parametrize("shift", [4.0, 6.0])
def test_an_indefinite_matrix_falls_back_to_the_direct_solve_and_is_counted(amg, shift):
    # shift 4: eigenvalues on both sides of 0 with a positive diagonal (1); shift 6: a negative
    # diagonal, caught before CG
    A = (laplacian(20) - shift * sp.eye(400)).tocsr()
    b = np.random.default_rng(1).standard_normal(400)
    solve = factorize(A, symmetric=True, solver=amg)
    x = solve(b)
    np.testing.assert_allclose(A @ x, b, atol=1e-10 * np.linalg.norm(b))
    assert amg.factorizations.count == 1  # the fallback's
    np.testing.assert_allclose(solve(2.0 * b), 2.0 * x, rtol=1e-12)
    assert amg.factorizations.count == 1  # the fallback's factors are kept
    done = work(amg)
    assert done["fallbacks"] == 1 and done["solves"] == 0


def test_a_failing_fallback_is_a_failed_step(amg):
    # a zero on the diagonal: no CG, and SuperLU meets an exactly zero pivot
    A = sp.diags(np.r_[np.ones(199), 0.0]).tocsr()
    solve = factorize_or_fail(A, 1.0, symmetric=True, solver=amg)
    with pytest.raises(StepFailure, match="singular"):
        solve(np.ones(200))


def test_a_hierarchy_serves_its_pattern_until_a_matrix_needs_a_new_one(amg):
    model = box((10, 10, 5))
    S1, S2 = iteration_matrix(model, 1e-2), iteration_matrix(model, 1.2e-2)
    b = np.random.default_rng(2).standard_normal(model.n_free)
    x1 = factorize(S1, symmetric=True, solver=amg)(b)
    assert work(amg)["setups"] == 1  # the diagonal is not enough at this step
    x2 = factorize(S2, symmetric=True, solver=amg)(b)  # the next step size: same pattern, reused
    assert work(amg)["setups"] == 1
    # the same pattern scaled over four decades: the hierarchy of S1 serves it badly
    D = sp.diags(10.0 ** np.random.default_rng(3).uniform(-2, 2, model.n_free))
    S3 = (D @ S1 @ D).tocsr()
    x3 = factorize(S3, symmetric=True, solver=amg)(b)
    done = work(amg)
    assert done["setups"] == 2  # rebuilt for S3
    # with pyamg 5.4 the new hierarchy solves S3; with pyamg 5.1 (on SciPy 1.9) CG still needs
    # more than MAX_ITERATIONS on it and the direct solve takes over: counted either way
    assert done["solves"] + done["fallbacks"] == 3 and done["fallbacks"] <= 1
    for A, x in ((S1, x1), (S2, x2)):
        assert np.linalg.norm(b - A @ x) <= PROMISE * np.linalg.norm(b)
    # S3 by CG meets the promise; by the direct fallback, a backward-stable solve: its
    # residual is bounded by round-off times |S3| |x| (κ(S3) is 1e8 times κ(S1))
    bound = PROMISE * np.linalg.norm(b)
    if done["fallbacks"]:
        bound = max(bound, 1e4 * np.finfo(float).eps * spla.norm(S3) * np.linalg.norm(x3))
    assert np.linalg.norm(b - S3 @ x3) <= bound


def test_auto_outside_a_run_factorizes_directly():
    """Without a run there is no plan to weigh the costs with: "auto" takes the direct path
    (the choice within a run: tests/test_solver_choice.py)."""
    solver = LinearSolver("auto")
    S = iteration_matrix(box((8, 8, 4)), 1e-4)  # 1215 dofs
    b = np.ones(S.shape[0])
    x = factorize(S, symmetric=True, solver=solver)(b)
    assert solver.factorizations.count == 1
    assert work(solver)["solves"] == 0
    # a direct solve: residual at round-off (κ(S) ≤ 1e4 here, 1e-10 leaves a margin)
    assert np.linalg.norm(S @ x - b) <= 1e-10 * np.linalg.norm(b)


def test_amg_without_pyamg_says_how_to_install(monkeypatch):
    before = sparse_solver()
    hide_pyamg(monkeypatch)
    with pytest.raises(InputError, match=r'pip install "fecontact\[amg\]"'):
        use_sparse_solver("amg")
    assert sparse_solver() == before


def ball(solver):
    """(q per step, smallest gap per step, sim, the run's statistics) of the 3D ball (2499
    dofs) touching the plane at 1 m/s, its first 60 steps, built anew (a linear model keeps
    its solver's factors), with ``solver`` the process default when the run starts."""
    use_sparse_solver(solver)
    sim = case("ball_drop").build(refinements=3, drop_height=0.0)
    sim = sim.replace(t_end=60 * sim.dt)
    model, stats = sim.model, StepStats()
    states = list(simulate(model, sim.dt, sim.t_end, sim.options, v0=sim.v0, stats=stats))
    q = np.array([st.q for st in states])
    gaps = np.array([model.contacts.gaps(st.q).min() for st in states])
    return q, gaps, sim, stats


def test_ball_drop_runs_the_same_with_cg_and_with_the_direct_solver(amg):
    q_cg, gaps_cg, sim, stats = ball("amg")
    assert stats.iterative.solves > 0 and stats.iterative.fallbacks == 0
    assert stats.factorizations.count == 0
    q_lu, gaps_lu, _, stats = ball("superlu")
    assert stats.iterative.solves == 0 and stats.factorizations.count > 0
    # zero penetration both ways (gap tolerance 1e-12 of the model size)
    size = sim.model.length
    assert gaps_cg.min() >= -1e-12 * size and gaps_lu.min() >= -1e-12 * size
    assert gaps_cg.min() <= 1e-6 * size  # and the ball is on the plane
    # each solve leaves a relative error ≤ κ(S) · PROMISE, and the steps add them up
    kappa = condition_number(iteration_matrix(sim.model, sim.dt))
    steps = len(q_cg) - 1
    bound = steps * kappa * PROMISE * np.abs(q_lu).max()
    assert np.abs(q_cg - q_lu).max() <= bound


def test_auto_without_pyamg_takes_the_direct_path_and_says_so(monkeypatch, tmp_path):
    """ "auto" without pyamg has one path, the direct one: it is accepted (it used to raise,
    and from FECONTACT_SPARSE_SOLVER at ``import fecontact``), the run solves directly, the
    ladder included, and its record says why."""
    from fecontact import run

    before = sparse_solver()
    hide_pyamg(monkeypatch)
    try:
        use_sparse_solver("auto")
        sim = case("disk_drop").build(material="linear", drop_height=8e-5)  # closes in step 2
        s = run(sim.replace(t_end=6 * sim.dt), tmp_path, frames=False, checkpoint_every=0)
    finally:
        use_sparse_solver(before)
        monkeypatch.undo()
    record = s["sparse_solver"]
    assert s["status"] == "completed" and s["iterative_solver"]["solves"] == 0
    assert "pyamg" in record["reason"] and not record["decisions"]
    assert sum(f["count"] for f in record["factorizations"].values()) >= 1


def hide_pyamg(monkeypatch) -> None:
    """Make ``import pyamg`` fail for the rest of the test, as where it is not installed."""
    import builtins

    real_import = builtins.__import__

    def no_pyamg(name, *args, **kwargs):
        if name == "pyamg":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pyamg)
