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
