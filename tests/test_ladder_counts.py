"""The work a linear model's ladder does at sizes met once (fecontact.linalg.ladder) is counted
once in the run's localization statistics, however the calls that count it nest: localized
steps inside sub-steps, inside a split at a release, inside steps taken aside (which put the
ladder's deciding counts back so the run decides as without them)."""

import dataclasses
from collections import Counter
from types import SimpleNamespace

import numpy as np
import pytest
from test_ladder import plate

from fecontact.linalg import ladder
from fecontact.testing import case
from fecontact.time import StepStats, correction, simulate, substeps, terms
from fecontact.time.aside import taken_aside
from fecontact.time.localize import cache_keys, drop_caches
from fecontact.time.stats import Localization

A_H = 1.0 / (0.25 * 1e-4**2)  # β′ of a step of 0.1 ms (1/s²)


@pytest.fixture
def tally(monkeypatch) -> Counter:
    """The ladder's work, counted where it is done, by the names of ``Ladder.counts``; with
    the factorizations of a retaken step's sub-step sizes (the run's own kind of size)."""
    made, retaking = Counter(), []
    Pre, Remade, Ladder = ladder._Preconditioned, ladder._Remade, ladder.Ladder

    def factor(self, a, S, call=Ladder.factor):
        made["factorizations"] += 1
        return call(self, a, S)

    def keep(self, a, solve, call=Ladder.keep):
        made["factorizations"] += bool(retaking)
        return call(self, a, solve)

    def retaken(self, *args, call=substeps.Releases._retaken):
        retaking.append(True)
        try:
            return call(self, *args)
        finally:
            retaking.pop()

    def decompose(self, call=Ladder._decompose):
        made["spectral"] += 1
        return call(self)

    def pcg(self, B, call=Pre._pcg):
        before = self.ladder.counts["pcg_iterations"]  # (this solve's own iterations)
        made["pcg_solves"] += 1
        out = call(self, B)
        made["pcg_iterations"] += self.ladder.counts["pcg_iterations"] - before
        return out

    def refactorized(self, b, call=Pre.__call__):
        exact = self.exact
        out = call(self, b)
        made["pcg_refactorized"] += exact is None and self.exact is not None
        return out

    def remade(self, b, call=Remade.__call__):
        made["rungs_remade"] += self.solve is None
        return call(self, b)

    def curved(*args, call=correction.curved_factors):
        out = call(*args)
        made["curvature_factorizations"] += out is not None
        return out

    def held(model, *args, call=terms.held_curvature):
        counts = model.ladder.counts if model.ladder is not None else {}
        before = counts.get("curvature_reuse_fallbacks", 0)  # (this call's own refusal)
        out = call(model, *args)
        made["curvature_reuses"] += out is not None
        made["curvature_reuse_fallbacks"] += counts.get("curvature_reuse_fallbacks", 0) - before
        return out

    for cls, name, f in (
        (Ladder, "factor", factor),
        (Ladder, "keep", keep),
        (substeps.Releases, "_retaken", retaken),
        (Ladder, "_decompose", decompose),
        (Pre, "_pcg", pcg),
        (Pre, "__call__", refactorized),
        (Remade, "__call__", remade),
        (correction, "curved_factors", curved),
        (terms, "curved_factors", curved),  # (imported there by name)
        (terms, "held_curvature", held),
    ):
        monkeypatch.setattr(cls, name, f)
    return made


def counted(stats: Localization) -> dict:
    """The localization ``stats``' counts of the ladder's work, by the ladder's names."""
    return {"factorizations": stats.factorizations, **stats.ladder}


def test_nested_calls_and_steps_aside_count_each_factorization_once(tally):
    model = plate()
    model.iteration_matrix(A_H, 0.0)  # the run's own step: the ladder
    model.ladder.after = None  # (rungs, as on a model above SPECTRAL_LIMIT)
    model.passing = True
    sizes = iter(A_H * 2.5 ** np.arange(1, 7))  # (each beyond RATIO of the others: factorized)
    st = SimpleNamespace(q=np.zeros(model.n), v=np.zeros(model.n))
    stats = Localization()
    outer = cache_keys(model, stats)
    model.iteration_matrix(next(sizes), 0.0)
    inner = cache_keys(model, stats)
    model.iteration_matrix(next(sizes), 0.0)
    drop_caches(model, inner, stats)
    with taken_aside(model, st, 1e-4, stats):
        model.iteration_matrix(next(sizes), 0.0)
        nested = cache_keys(model, stats)
        model.iteration_matrix(next(sizes), 0.0)
        drop_caches(model, nested, stats)
    model.iteration_matrix(next(sizes), 0.0)
    drop_caches(model, outer, stats)
    assert tally["factorizations"] == 5
    assert counted(stats) == {key: tally[key] for key in counted(stats)}
    assert model.ladder.counts["factorizations"] == 3  # (the two aside put back: they decide)


def test_a_run_counts_the_ladder_work_it_did(tally):
    """The coarse two balls at 10 m/s (1,122 dofs: PCG from rungs) to 0.25 ms with
    ``localize=True``, whose chattering contacts are taken in localized sub-steps: located
    impacts inside sub-steps inside retaken steps (measured: 24 located, 6 steps subdivided).
    (Under "auto" the run took one retake in sub-steps until the 3D mortar pairs' facing
    weight; with it the coarse balls need none.)"""
    sim = case("two_balls").build(velocity=10.0, spacing=0.2, base=1)
    options = dataclasses.replace(sim.options, localize=True)
    stats = StepStats()
    for _ in simulate(sim.model, sim.dt, 2.5e-4, options, q0=sim.q0, v0=sim.v0, stats=stats):
        pass
    assert stats.localization.subdivided >= 1  # (the nesting this test is about)
    assert counted(stats.localization) == {key: tally[key] for key in counted(stats.localization)}
