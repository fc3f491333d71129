"""Linear models: constant stiffness, built and factorized once per step size."""

import numpy as np
import pytest
from conftest import load_case

from fecontact import (
    Beam2D,
    Contact,
    InputError,
    IntegratorOptions,
    LinearElastic,
    Material,
    Model,
    Plane,
    Section,
    Solid,
    simulate,
)
from fecontact.time import StepStats


def test_iteration_matrix_is_factorized_once_over_a_long_linear_run():
    # t_{n+1} − t_n = (n + 1)·dt − n·dt varies in its last bits; the step must stay the
    # nominal dt, or every variant refactorizes and stays in the caches
    body = Solid.rectangle(
        [0.0, 0.01], [0.2, 0.06], (4, 2), LinearElastic(E=1e6, nu=0.3, rho=1000.0)
    )
    for localize in (False, "auto"):
        model = Model([body], [Contact(body, Plane([0.0, 0.0], [0.0, 1.0]))])
        stats = StepStats()
        options = IntegratorOptions(localize=localize)
        states = list(simulate(model, 1e-3, 0.3, options, stats=stats))
        assert sum(st.impulse.sum() > 0 for st in states) > 10  # it lands and rests
        assert len({st.h for st in states[1:]}) == 1
        # (localized: the split steps' own factorizations are dropped after their step)
        assert len(model.iteration_cache) == 1
        # one set of columns per kind at the one step size: M⁻¹Gᵀ (velocity jumps), S⁻¹Gᵀ
        # (the smooth contact force) and H⁻¹Gᵀ (position corrections). Localized, the
        # closings are corrected in the split steps, whose columns are dropped too; only a
        # step left whole (a counted fallback) may correct a closing at the full step
        kinds = sorted(key[0] for key in model.column_cache)
        if not localize:
            assert kinds == ["mass", "smooth", "stiffness"]
            continue
        assert {"mass", "smooth"} <= set(kinds) <= {"mass", "smooth", "stiffness"}
        if not sum(stats.localization.fallbacks.values()):
            assert kinds == ["mass", "smooth"]


MATERIAL = Material(E=70e9, nu=0.33, rho=2700.0)
SECTION = Section.rectangle(0.02, 0.002)


def test_linear_beam_is_the_second_order_expansion_of_the_exact_one():
    exact = Beam2D.polyline([[0, 0], [0.3, 0.1], [0.2, 0.5]], [2, 3], MATERIAL, SECTION)
    linear = Beam2D.polyline([[0, 0], [0.3, 0.1], [0.2, 0.5]], [2, 3], MATERIAL, SECTION, True)
    assert linear.linear and not exact.linear
    K0 = exact.internal(np.zeros(exact.ndof))[2]
    np.testing.assert_array_equal(linear.internal(np.zeros(linear.ndof))[2], K0)
    K = linear.stiffness_matrix()
    q = 1e-4 * np.random.default_rng(0).normal(size=linear.ndof)
    W, f, Ke = linear.internal(q)
    assert Ke is linear.internal(2 * q)[2]  # stored, not reassembled
    np.testing.assert_allclose(f, K @ q, rtol=1e-14)
    assert W == pytest.approx(0.5 * q @ K @ q, rel=1e-14) == linear.energy(q)
    # the exact beam agrees to second order in q: W − W_lin = O(|q|³)
    for s in (1.0, 0.5):
        err = abs(exact.energy(s * q) - linear.energy(s * q))
        assert err < 1e-3 * linear.energy(s * q)
    ratio = abs(exact.energy(q) - linear.energy(q)) / abs(
        exact.energy(0.5 * q) - linear.energy(0.5 * q)
    )
    assert 7.0 < ratio < 9.0
    with pytest.raises(InputError, match="geometrically exact"):
        exact.stiffness_matrix()
    with pytest.raises(InputError, match="linear"):
        Beam2D.straight([0, 0], [1, 0], 2, MATERIAL, SECTION, linear="yes")


def test_axial_bar_impact_is_the_same_with_linear_and_exact_kinematics():
    # along its axis the exact strains are Γ = u', γ = κ = 0: the energy is quadratic, the
    # transverse dofs stay at zero, and both beams follow the same equations
    runs = {}
    for kinematics in ("linear", "exact"):
        sim = load_case("impacting_bar").build(n_elements=20, kinematics=kinematics)
        states = simulate(sim.model, sim.dt, 2.5, sim.options, v0=sim.v0)
        runs[kinematics] = [
            (st.q.copy(), st.v.copy(), st.impulse.sum(), st.force.sum(), st.pressed().any())
            for st in states
        ]
    # a long contact (held by the smooth force and the jumps' impulses), then release
    assert sum(pressed for *_, pressed in runs["linear"]) > 50
    for (q1, v1, i1, f1, _), (q2, v2, i2, f2, _) in zip(runs["linear"], runs["exact"], strict=True):
        np.testing.assert_allclose(q1, q2, rtol=0, atol=1e-13)
        np.testing.assert_allclose(v1, v2, rtol=0, atol=1e-12)
        assert i1 == pytest.approx(i2, rel=1e-10, abs=1e-16)
        assert f1 == pytest.approx(f2, rel=1e-10, abs=1e-12)
        assert not q1.reshape(-1, 3)[:, 1:].any()
    with pytest.raises(InputError, match="kinematics"):
        load_case("impacting_bar").build(kinematics="small")
