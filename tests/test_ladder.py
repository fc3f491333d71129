"""A linear model's iteration matrix at sizes met once (a split step's), solved without a
factorization each (fecontact.linalg.ladder): through the eigendecomposition, or by PCG from
a nearby size's factors, to the direct solve's round-off."""

import numpy as np
import scipy.sparse.linalg as spla

from fecontact import LinearElastic, Model, Solid
from fecontact.linalg import ladder


def plate(divisions=(12, 6)) -> Model:
    """A free linear plate: its rigid motions make K singular, S = aM + K is not."""
    body = Solid.rectangle([0.0, 0.0], [0.2, 0.1], divisions, LinearElastic(1e7, 0.3, 1000.0))
    return Model([body])


def relative(x, y) -> float:
    return float(np.max(np.abs(x - y)) / np.max(np.abs(y)))


def test_sizes_met_once_are_solved_as_a_direct_solve_does():
    model = plate()
    a_h = 1.0 / (0.25 * 1e-4**2)  # β′ of a step of 0.1 ms (1/s²)
    solve_h = model.iteration_matrix(a_h, 0.0)[1]  # the run's own step: factorized
    model.ladder.rungs[a_h] = solve_h  # (a rung, as on a model above SPECTRAL_LIMIT)
    sizes = a_h * np.array([1.01, 1.7, 0.6, 3.3, 6.0])
    b = np.random.default_rng(0).normal(size=(model.n_free, 3))
    for spectral in (False, True):
        grid = model.ladder
        grid.after = grid.counts["factorizations"] if spectral else None
        model.passing = True
        for a in sizes:
            S, solve, _ = model.iteration_matrix(a, 0.0)
            exact = spla.splu(S.tocsc()).solve(b)
            # round-off: the spectral solve's relative residual is about 1e-15 (a few times
            # the direct one's), PCG's at most ladder.TOLERANCE; 1e-11 leaves a 100-fold
            # margin on the error of either, far below any step's tolerance
            assert relative(solve(b), exact) < 1e-11
            assert relative(solve(b[:, 0]), exact[:, 0]) < 1e-11
            del model.iteration_cache[(a, 0.0)]
        model.passing = False
    counts = model.ladder.counts
    assert counts["spectral"] == 1
    # PCG: a/b within RATIO of a rung (1.01, 1.7, 0.6 from the step's; 6.0 from 3.3's)
    assert counts["pcg_solves"] > 0 and counts["pcg_refactorized"] == 0
    # (a contraction of 0.17 or better an iteration: 16 to 1e-13 at the worst ratio, 2)
    assert counts["pcg_iterations"] <= 17 * counts["pcg_solves"]
    # the factors on the ladder: the step's, and 3.3's (6.0 within RATIO of it)
    assert sorted(model.ladder.rungs) == [a_h, 3.3 * a_h]


def test_the_eigendecomposition_is_made_after_n_over_32_factorizations():
    model = plate()
    grid_after = -(-model.n_free // ladder.SPECTRAL_AFTER)  # ceil
    a_h = 1.0 / (0.25 * 1e-4**2)
    # (no size of the run's own yet: its first steps, in free flight, converged at their
    # predictor; the split's sizes are counted all the same)
    model.passing = True
    for k in range(grid_after + 2):
        model.iteration_matrix(a_h * 4.0 ** (k + 1), 0.0)
    counts = model.ladder.counts
    assert model.ladder.after == grid_after
    assert counts["factorizations"] == grid_after and counts["spectral"] == 1


def test_a_contact_update_in_the_modes_is_the_update_through_the_factors():
    """A persistent contact's Newton update at a size solved through the eigendecomposition
    is made in the modes, Φᵀ G_jᵀ kept per contact (SmoothContacts._modal_update): the
    update and the multipliers are those of the Schur complement through S(a)'s own factors,
    at the first size and at another that takes the kept columns."""
    from types import SimpleNamespace

    from fecontact.contact.stats import ContactStats
    from fecontact.time.smooth_contact import SmoothContacts

    model = plate()
    n, rng = model.n_free, np.random.default_rng(1)
    G = np.zeros((4, n))  # four contacts, constant gradients on a few dofs each
    for j in range(4):
        G[j, rng.choice(n, 3, replace=False)] = rng.normal(size=3)
    g = np.array([-1e-6, 2e-6, -3e-6, 1e-3])  # the last open: outside the active set
    contacts = SimpleNamespace(
        linearize=lambda q, P, w: (g[P], G[P], None), affine=True, linear=True
    )
    fake = SimpleNamespace(contacts=contacts, joints=SimpleNamespace(size=0, linear=True))
    fake.n_free, fake.column_cache = n, {}
    opts = SimpleNamespace(stats=SimpleNamespace(contact=ContactStats()))
    a_h = 1.0 / (0.25 * 1e-4**2)
    model.iteration_matrix(a_h, 0.0)  # (the ladder, with the run's own size)
    model.ladder.after = 0  # (the eigendecomposition at the next size met once)
    r = rng.normal(size=n)
    for a, only in ((1.7 * a_h, False), (0.3 * a_h, False), (0.8 * a_h, True)):
        if only:  # (one contact pressed, its kept column: the most common located impact)
            g[:] = [1e-3, -2e-6, 1e-3, 1e-3]
        spectral = model.ladder.solver(a, None)
        assert type(spectral) is ladder.Spectral
        S = model.iteration_sum(a, model.ladder.K)
        exact = spla.splu(S.tocsc()).solve
        updates = []
        for solve, key in ((spectral, (a, 0.0)), (exact, None)):
            force0 = np.array([0.0, 2.0, 0.0, 0.0] if only else [1.0, 2.0, 0.0, 0.0])
            sc = SmoothContacts(fake, np.arange(4), force0, opts)
            sc.update(np.zeros(n), False)
            updates.append((sc.schur_update(fake, r.copy(), solve, key), sc.lam.copy()))
        (dq, lam), (dq_exact, lam_exact) = updates
        # round-off: the spectral solve's relative residual is about 1e-15, the 3 × 3 Schur
        # complement of random rows well conditioned; 1e-11, as above, leaves a wide margin
        assert relative(dq, dq_exact) < 1e-11 and relative(lam, lam_exact) < 1e-11
        assert np.count_nonzero(lam) == (1 if only else 3)
        assert sorted(model.ladder.projected) == [0, 1, 2]  # (kept once, at every size)


def test_old_rungs_are_made_again_where_pcg_takes_them():
    """Every size met once that is factorized becomes a rung; beyond ``LIVE`` of them the
    oldest drop their factors (a run that locates hundreds of instants held them all) and
    make them again, from the same S(a), where PCG takes one: the solve is the one the kept
    factors gave, to the bit."""
    a_h = 1.0 / (0.25 * 1e-4**2)
    sizes = a_h * 2.5 ** np.arange(ladder.LIVE + 3)  # (each beyond RATIO of the others)
    b = np.random.default_rng(2).normal(size=(plate().n_free, 2))
    solves = []
    for retire in (False, True):
        model = plate()
        solve = model.iteration_matrix(sizes[0], 0.0)[1]  # the run's own step: factorized
        grid = model.ladder
        grid.after = None  # (rungs, as on a model above SPECTRAL_LIMIT)
        grid.keep(sizes[0], solve)
        if not retire:
            grid.assemble = None  # (every rung keeps its factors)
        model.passing = True
        for a in sizes[1:]:
            model.iteration_matrix(a, 0.0)
        kept = [r for r in grid.rungs.values() if type(r) is not ladder._Remade]
        assert len(grid.rungs) == sizes.size
        assert len(kept) == (ladder.LIVE + 1 if retire else sizes.size)  # (+ the run's own)
        a = 1.2 * sizes[1]  # (PCG from the oldest rung of a size met once)
        solves.append(grid.solver(a, model.iteration_sum(a, grid.K))(b))
        assert grid.counts["rungs_remade"] == int(retire)
        assert grid.counts["pcg_solves"] == 1 and grid.counts["pcg_refactorized"] == 0
    np.testing.assert_array_equal(solves[0], solves[1])
