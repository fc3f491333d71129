"""The sparse Cholesky path and the run's sparse solver record: the same answers as SuperLU to
round-off, SuperLU for what is not positive definite, and the cost model of "auto"."""

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse as sp

from fecontact import run
from fecontact.linalg import choice as choice_module
from fecontact.linalg import direct as direct_module
from fecontact.linalg import factorize
from fecontact.linalg.choice import FACTOR_MODEL, PLANAR_MODEL, RunPlan, SolverChoice
from fecontact.linalg.cholesky import CholeskyFactor
from fecontact.linalg.graph_growth import PLANAR_GROWTH, graph_growth
from fecontact.linalg.solver import IterativeStats
from fecontact.linalg.sparse_solvers import sparse_solver, use_sparse_solver
from fecontact.testing import case


@pytest.fixture
def restore():
    before = sparse_solver()
    yield
    use_sparse_solver(before)


def spd(n=50):
    """The 2D five-point Laplacian plus I (n² unknowns, symmetric positive definite)."""
    d = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    return (sp.kron(sp.eye(n), d) + sp.kron(d, sp.eye(n)) + sp.eye(n * n)).tocsr()


def test_cholesky_gives_superlu_s_solutions(restore):
    pytest.importorskip("pypardiso")
    A = spd()  # 2500 unknowns: above cholesky.MIN_UNKNOWNS
    b = np.random.default_rng(2).standard_normal((2500, 2))
    use_sparse_solver("superlu")
    x_lu = factorize(A, symmetric=True)(b)
    use_sparse_solver("direct")
    solve = factorize(A, symmetric=True)
    assert isinstance(solve, CholeskyFactor)
    x_chol = solve(b)
    # both backward stable and κ(A) < 9 (eigenvalues in (1, 9)): the solutions agree to a few
    # units of round-off; 1e-11 leaves a wide margin
    np.testing.assert_allclose(x_chol, x_lu, rtol=1e-11, atol=1e-13)


def test_indefinite_symmetric_matrices_go_to_superlu(restore):
    """A symmetric indefinite matrix (a buckling tangent) is refused by the Cholesky path and
    solved by SuperLU's symmetric mode, with or without the binding."""
    A = (spd() - 2.5 * sp.eye(2500)).tocsr()  # eigenvalues −1.49 … 6.49, none below 3e-3
    b = np.random.default_rng(3).standard_normal(2500)
    x = factorize(A, symmetric=True)(b)
    # backward stable: residual ~ ε ‖A‖ ‖x‖ ≤ 1e-16 · 6.5 · 330 ‖b‖, 1e-10 ‖b‖ leaves a margin
    assert np.linalg.norm(A @ x - b) <= 1e-10 * np.linalg.norm(b)


def test_without_the_binding_direct_is_superlu(restore, monkeypatch):
    A = spd()
    b = np.random.default_rng(4).standard_normal(2500)
    monkeypatch.setattr(direct_module, "cholesky_available", lambda: False)
    x = factorize(A, symmetric=True)(b)
    use_sparse_solver("superlu")
    np.testing.assert_array_equal(x, factorize(A, symmetric=True)(b))  # the same code path


def role_costs(linear, t_f, t_s, t_cg, steps=100):
    choice = SolverChoice("auto", RunPlan(steps, linear), "cholesky")
    role = choice.role(spd(4))
    role.t_f, role.t_s, role.t_cg = t_f, t_s, t_cg
    return choice.costs(role, factorized=False)[:2]


def test_auto_weighs_factorizations_against_solves():
    # 100 steps, 2 solves a step (the guess before the first step): a linear model pays one
    # factorization, a nonlinear one 3 a step (Newton iterations)
    assert role_costs(True, 1.0, 0.01, 0.1) == pytest.approx((1.0 + 2.0, 20.0))
    assert role_costs(False, 1.0, 0.01, 0.1) == pytest.approx((300.0 + 2.0, 20.0))
    # few steps make the one factorization of a linear model dearer than its CG solves
    assert role_costs(True, 10.0, 0.01, 0.1, steps=10) == pytest.approx((10.2, 2.0))


def test_auto_measures_cg_only_where_it_could_win():
    """The first solve of a pattern is CG with the diagonal, stopped where it would cost more
    than the direct path estimated: at once for the one factorization of a small linear model
    (then factorized), not for a large nonlinear one refactorized at every Newton iteration
    (CG converges within its allowance: the CG path, measured)."""
    calls = []
    path = recording_paths(calls)

    for linear, n, expected in ((True, 4, "direct"), (False, 300, "cg")):
        choice = SolverChoice("auto", RunPlan(100, linear), "cholesky")
        A = spd(n)
        choice.role(A).product = 1e-3  # s: the unit of the estimates, fixed for the test
        choice.auto(A, path("direct"), path("cg"))(np.ones(A.shape[0]))
        assert calls[-1] == expected
        assert choice.decisions[0]["path"] == expected


def test_the_run_records_its_solver_and_auto_agrees_with_direct(tmp_path, restore):
    """The 3D ball (387 dofs) touching the plane, 8 steps, with each sparse solver: the summary
    says which path solved and why, and "auto" gives the direct answer to CG's tolerance."""
    finals = {}
    for name in ("direct", "auto"):
        use_sparse_solver(name)
        # a new model each time: a linear model keeps its factorized iteration matrix
        sim = case("ball_drop").build(refinements=2, drop_height=0.0)
        sim = sim.replace(t_end=8 * sim.dt)
        s = run(sim.replace(name=name), tmp_path / name, frames=False, checkpoint_every=0)
        record = s["sparse_solver"]
        assert record["name"] == name and record["reason"]
        assert record["peak_memory_mb"] > 0.0
        history = np.genfromtxt(tmp_path / name / "history.csv", delimiter=",", skip_header=1)
        finals[name] = history[-1]
        assert s["status"] == "completed"
    assert s["sparse_solver"]["decisions"][0]["reason"]  # "auto" said what it chose and why
    # CG solves to 1e-10 relative residual: κ(S) ≤ 1e4 here leaves 1e-5 relative in each
    # solve at worst, far below the history's rounding of contact quantities
    np.testing.assert_allclose(finals["auto"], finals["direct"], rtol=1e-5, atol=1e-9)


def test_auto_weighs_a_pattern_first_met_after_the_first_step(tmp_path, restore):
    """A linear disk (290 dofs) that closes on the plane in its second step: the located
    closing brings iteration matrices of new step sizes, patterns met after the first step,
    whose solves a step are not yet measured (their rate is then the guess, not 0 over the
    steps done: "auto" divided by it)."""
    use_sparse_solver("auto")
    sim = case("disk_drop").build(material="linear", drop_height=8e-5)  # 1.5 v h: step 2
    s = run(sim.replace(t_end=6 * sim.dt), tmp_path, frames=False, checkpoint_every=0)
    assert s["status"] == "completed" and s["localized_impacts"] >= 1
    decisions = s["sparse_solver"]["decisions"]
    assert decisions and max(d["step"] for d in decisions) >= 1  # a pattern met late


def test_auto_weighs_the_columns_in_hand():
    """A block of right-hand sides (the contact rows' S⁻¹Gᵀ, a column a touching node and
    direction) costs CG a solve a column and a factor little: on the CG path, such a block is
    weighed with its columns and sends the matrix to the direct path (a 45,602-dof 2D block at
    20 Δx/c ran a 302-column block by AMG-CG: 2.9 times the direct path's time)."""
    calls = []
    path = recording_paths(calls)

    choice = SolverChoice("auto", RunPlan(10, True), "superlu")
    A = spd(30)
    role = choice.role(A)
    # measured (s): a factorization, a solve with it, a CG solve (over 10 solves)
    role.t_f, role.t_s, role.t_cg = 1.0, 1e-3, 1e-2
    role.cg_solves = role.cg_timed = 10
    solve = choice.auto(A, path("direct"), path("cg"))
    solve(np.ones(900))  # 1 + 10 steps x 2 solves: CG 0.21 s against 1.02 s
    assert calls == ["cg"]
    # the vector's own (instant) solve took the mean CG column to about 9.1e-3 s; 200 columns
    # more: CG 2.0 s against 1.22 s
    solve(np.ones((900, 200)))
    assert calls == ["cg", "direct"]
    assert "200 columns now" in choice.decisions[-1]["reason"]


def test_the_run_records_the_factorization_of_its_mass(tmp_path, restore):
    """The initial acceleration's solve with M is the run's: made with the run's solver, so
    that its record counts the mass's factorization (a linear disk in free flight makes no
    other; it used to be made before the run, with the model's own solver, and left out)."""
    use_sparse_solver("direct")
    sim = case("disk_drop").build(material="linear")  # 290 dofs, 2 mm above the plane
    s = run(sim.replace(t_end=3 * sim.dt), tmp_path, frames=False, checkpoint_every=0)
    assert s["sparse_solver"]["factorizations"]["superlu"]["count"] == 1
    assert s["sparse_factorizations"]["count"] == 1


def test_one_role_per_sparsity_pattern():
    """The iteration matrices of two step sizes are sums with index arrays of their own: one
    pattern, one role, whose measured costs the second size weighs with (each size of a split
    step used to start a role of its own on estimates: a 66,050-dof disk at 50 Δx/c probed
    CG and then factorized for each of its 8 sizes of the first step)."""
    choice = SolverChoice("auto", RunPlan(10, True), "superlu")
    A = spd(20)
    B = (2.0 * A).tocsr()  # the same pattern in new arrays
    assert B.indices is not A.indices
    assert choice.role(B) is choice.role(A)
    C = (A + sp.eye(400, k=3)).tocsr()  # another pattern
    assert choice.role(C) is not choice.role(A)
    assert len(choice.record()["roles"]) == 2


def test_auto_weighs_a_size_met_once_over_its_step():
    """The iteration matrix of a size of a split step serves that step only: weighed over the
    rest of the run, each such size was factorized (17 factorizations on a 66,050-dof disk at
    50 Δx/c where "direct" made 7 from its ladder, 1.85x "amg")."""
    calls = []
    path = recording_paths(calls)

    choice = SolverChoice("auto", RunPlan(100, True), "superlu")
    A = spd(30)
    role = choice.role(A)
    role.t_f, role.t_s, role.t_cg = 1.0, 1e-3, 1e-2  # measured (s)
    role.cg_solves = role.cg_timed = 10
    # one step, 1 + 2 solves: CG 0.03 s against 1.003 s
    choice.auto(A, path("direct"), path("cg"), once=True)(np.ones(900))
    # the rest of the run, 1 + 100 steps x 2 solves (the instant solve above took CG's mean
    # to about 9.1e-3 s): CG 1.83 s against 1.2 s
    choice.auto(A, path("direct"), path("cg"))(np.ones(900))
    assert calls == ["cg", "direct"]


def recording_paths(calls: list):
    """Path factories for ``SolverChoice.auto``: each adds its name to ``calls`` when the
    choice makes it, and solves as the identity."""

    def path(name):
        def make():
            calls.append(name)
            return lambda b: b

        return make

    return path


def grid(n: int, dim: int):
    """The (2·dim + 1)-point Laplacian on n^dim points: the graph of a planar (dim 2) or a
    volume (dim 3) mesh."""
    d = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    A = d
    for _ in range(dim - 1):
        A = sp.kron(A, sp.eye(n)) + sp.kron(sp.eye(A.shape[0]), d)
    return A.tocsr()


def test_the_graph_s_growth_tells_planar_from_volume():
    """The unknowns within graph distance r grow like r² on a planar grid, like r³ on a volume
    one (the count stops at 3,000 unknowns, r = 39 and 13: the lattice's lower-order terms
    keep the readings near 1.95 and 2.8, both 0.45 or more from the threshold); a matrix
    too small to read gives None."""
    planar, volume = graph_growth(grid(120, 2)), graph_growth(grid(25, 3))
    assert planar < PLANAR_GROWTH - 0.2 and 1.8 < planar
    assert volume > PLANAR_GROWTH + 0.3 and volume < 3.0
    assert graph_growth(spd(50)) is None  # 2,500 unknowns: the count would reach the edges


def test_the_factorization_estimate_follows_the_graph():
    """Before a factorization is measured, a planar graph's is estimated by the planar law, a
    volume graph's by the volume law (which overestimated the 66,050-dof disks' 6.6 and 27 times,
    so that "auto" kept CG where the direct path was the faster), and the reason says which."""
    choice = SolverChoice("auto", RunPlan(10, True), "superlu")
    for A, law in ((grid(120, 2), PLANAR_MODEL), (grid(25, 3), FACTOR_MODEL)):
        role = choice.role(A)
        role.product, role.t_cg = 1e-3, 1.0  # s: the unit of the estimates, fixed for the test
        direct, _, how = choice.costs(role, factorized=False)
        (kf, qf), (ks, qs) = law["superlu"]
        scale = A.shape[0] / 1e4
        # one factorization and 10 steps x 2 solves (the guess before a step is over)
        assert direct == pytest.approx(1e-3 * (kf * scale**qf + 20 * ks * scale**qs))
        assert ("planar law" in how) == (law is PLANAR_MODEL)
    growths = [role["graph_growth"] for role in choice.record()["roles"]]
    assert growths[0] < PLANAR_GROWTH < growths[1]


def test_auto_times_cg_without_its_first_hierarchy(monkeypatch):
    """A role's first AMG hierarchy (and the diagonal's trial before it) is paid once, like a
    factorization: the solve that built it stands for CG's cost only until the next is timed,
    which replaces it (its 0.155 s against about a fifth of it for the next solves of a
    66,050-dof disk's S_t made "auto" leave CG). A later rebuild is a running cost and is
    averaged in. Times come from a clock the solves advance: exact."""
    clock = [0.0]
    now = SimpleNamespace(perf_counter=lambda: clock[0], process_time=lambda: clock[0])
    monkeypatch.setattr(choice_module, "time", now)
    stats = IterativeStats()
    choice = SolverChoice("auto", RunPlan(100, True), "superlu", iterative=stats)
    A = spd(30)
    role = choice.role(A)
    role.product, role.t_f, role.t_cg = 1e-3, 100.0, 1.0  # a dear factorization: CG's path
    costs = iter([(0.1, 0.09), (0.002, 0.0), (0.05, 0.04)])  # (seconds, of it setting up)

    def cg():
        def solve(b):
            seconds, setup = next(costs)
            clock[0] += seconds
            stats.setup_seconds += setup
            return b

        return solve

    solve = choice.auto(A, lambda: pytest.fail("factorized"), cg)
    expected = (0.01, 0.002, 0.026)  # the first without its setup; replaced; averaged
    for t_cg in expected:
        solve(np.ones(900))
        assert role.t_cg == pytest.approx(t_cg)
    assert (role.cg_solves, role.cg_timed, role.setups) == (3, 2, 2)


def test_auto_probes_a_size_met_once():
    """A size of a split step is smaller than the role's step and better conditioned: CG
    with the diagonal is tried on it (here on the first column of a block) before the role's
    CG cost, its first matrix's, sends it to a factorization of its own (a 66,050-dof P2
    disk factorized 5 sizes where one and CG for the others took half the time)."""
    calls = []
    path = recording_paths(calls)

    choice = SolverChoice("auto", RunPlan(100, True), "superlu")
    A = spd(30)  # κ < 9: the diagonal converges in a few dozen iterations
    role = choice.role(A)
    role.product, role.t_f, role.t_s, role.t_cg = 1e-3, 1.0, 1e-3, 1.0  # s, measured
    # weighed on the role's costs alone: direct 1.004 s against CG 4 x 1 s
    choice.auto(A, path("direct"), path("cg"), once=True)(np.ones((900, 2)))
    assert calls == ["cg"]
    assert choice.decisions[-1]["reason"].startswith("CG with the diagonal solved")
