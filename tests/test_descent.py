"""The smooth Newton descends the incremental potential Π at every update (issue: uphill
Newton steps after impacts, hidden by step halving)."""

import json
import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fecontact import Model
from fecontact.bodies import Beam2D, Material, Section
from fecontact.cli.commands import main
from fecontact.testing import CASES, case
from fecontact.time import simulate
from fecontact.time.descent import Armijo, descent_direction, energy_roundoff
from fecontact.time.stats import NewtonStats


class Pendulum:
    """One dof with W(θ) = k(1 − cos θ): S = β′m + k cos θ is negative past θ = π/2 when
    k > β′m, where Newton's direction points uphill."""

    free = np.array([0])
    free_slice = slice(0, 1)

    def __init__(self, k):
        self.k = k

    def strain_energy(self, q):
        return self.k * (1.0 - math.cos(q[0]))

    def update_size(self, dq):
        return float(np.max(np.abs(dq)))  # a rotation, in rad


def test_an_uphill_newton_direction_is_shifted_until_it_descends():
    bp, k, q_hat = 1.0, 50.0, 2.6  # S < 0 at the predictor
    model = Pendulum(k)
    q = np.array([q_hat])

    def parts(q):
        fi = np.array([k * math.sin(q[0])])
        r = bp * (q - q_hat) + fi
        S = np.array([[bp + k * math.cos(q[0])]])
        return r, fi, S, np.array([[k * math.cos(q[0])]])

    def potential(q):
        return 0.5 * bp * (q[0] - q_hat) ** 2 + model.strain_energy(q)

    r, fi, S, K = parts(q)
    assert S[0, 0] < 0 and r @ np.linalg.solve(S, -r) > 0  # plain Newton goes uphill
    stats = NewtonStats()
    for _ in range(40):
        r, fi, S, K = parts(q)
        if abs(r[0]) < 1e-12:
            break
        solve = lambda b, S=S: b / S[0, 0]  # noqa: E731
        dq, *test = descent_direction(
            model, r, fi, S, K, solve, np.array([[bp]]), 1e-14, 1.0, stats
        )
        if test[-1] is not None:  # the smooth step's deferred Armijo test
            armijo = Armijo(q[None].copy(), dq, *test, model.strain_energy(q), 1.0, 0.0)
            if not armijo.accepts(model.strain_energy(q + dq)):
                dq = armijo.backtrack(model, stats) * dq
        # every update descends (to the round-off of Π once Newton has converged)
        assert potential(q + dq) <= potential(q) + 1e-13 * potential(q)
        q = q + dq
    assert abs(r[0]) < 1e-12
    assert stats.shifted_directions > 0 and stats.iterations > 0
    # the stationary point reached is a minimum of Π (S > 0): plain Newton, which goes to
    # any stationary point, would climb to the maximum near θ = π
    assert bp + k * math.cos(q[0]) > 0


@pytest.mark.parametrize("restitution", [0.0, 0.5, 1.0])
def test_founding_case_keeps_every_step_at_h_1e_3(restitution):
    """Before the globalization, e_N = 0.5 halved two steps near t = 0.875 s and e_N = 1 one:
    the direction went uphill on the tip rotation right after the second impact."""
    sim = case("flexible_pendulum").build(restitution=restitution)
    halvings = sum(
        st.halvings
        for st in simulate(sim.model, 1e-3, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0)
    )
    assert halvings == 0


def test_summary_reports_the_globalization(tmp_path):
    out = tmp_path / "run"
    args = ["run", str(CASES / "flexible_pendulum.py"), "--quiet", "--out", str(out)]
    assert main([*args, "--t-end", "0.4", "--checkpoint-every", "0"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    counts = summary["smooth_newton"]
    assert set(counts) == {
        "iterations",
        "line_search_cuts",
        "shifted_directions",
        "roundoff_accepts",
    }
    # every smooth Newton update of the run went through the globalization (the last
    # iteration of a step only evaluates the residual)
    assert 400 <= counts["iterations"] < summary["newton_iterations_total"]
    assert summary["step_halvings"] == 0


def bent_strip(amplitude: float):
    """A pinned 1 m steel strip (20 elements) bent to amplitude·sin(πx): the model, its
    dofs q, strain energy (J), internal force and tangent on the free dofs."""
    steel = Material(210e9, nu=0.3, rho=7850.0)
    strip = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 20, steel, Section.rectangle(0.05, 0.002))
    model = Model([strip.pin(0).pin(-1)], gravity=(0.0, 0.0))
    x = strip.X[:, 0]
    q = np.zeros(model.n)
    q[1::3] = amplitude * np.sin(np.pi * x)
    q[2::3] = amplitude * np.pi * np.cos(np.pi * x)
    W, f, K = model.internal(q)
    return model, q, W, f[model.free], sp.csc_matrix(K)


def newton_test(model, q, W, fi, K, r, stretch: float = 1.0):
    """The Armijo test of ``stretch`` times Newton's update −K⁻¹r for Π = W + (r − fi)·q
    (residual r at q), with its round-off floor δ."""
    dq = -stretch * spla.spsolve(K, r)
    floor = energy_roundoff(model, W)
    return Armijo(q[None].copy(), dq, float((r - fi) @ dq), 0.0, float(r @ dq), W, 1.0, floor)


@pytest.mark.parametrize("amplitude", [0.005, 0.02, 0.05])
def test_an_update_at_the_strain_energys_round_off_is_taken_whole(amplitude):
    """Near convergence (residual 1e-7 of the internal forces) Newton's update predicts a
    decrease of Π far below the round-off δ of W's change: the change read along it is
    round-off, of either sign, and bounded by δ (measured: 0.06 of it at most). The test
    takes the update whole, and counts it where it passed only by δ."""
    model, q, W, fi, K = bent_strip(amplitude)
    armijo = newton_test(model, q, W, fi, K, 1e-7 * fi)
    assert 0.0 < -armijo.slope < 0.1 * armijo.floor  # Π's first-order change: round-off
    qt = q.copy()
    for s in 0.5 ** np.arange(11):
        qt[model.free] = q[model.free] + s * armijo.dq
        change = s * armijo.lin + model.strain_energy(qt) - W
        # Π is quadratic up to O(|dq|³) here: its change is s·slope(1 − s/2)
        assert abs(change - s * armijo.slope * (1.0 - 0.5 * s)) <= armijo.floor
    qt[model.free] = q[model.free] + armijo.dq
    stats = NewtonStats()
    assert armijo.accepts(model.strain_energy(qt), stats)
    no_floor = armijo._replace(floor=0.0)
    if not no_floor.accepts(model.strain_energy(qt)):  # (the round-off read an increase)
        assert stats.roundoff_accepts == 1


def test_an_update_at_round_off_failed_the_test_without_its_floor():
    """The bent strip at 5 mm (W = 0.066 J, δ = 1.5e-12 J), residual 1e-7 of the forces:
    Newton's update predicts −9.6e-16 J and W's change reads +7.8e-14 J (measured), so the
    test without δ cut it ten times, to s = 2⁻¹⁰, a cut no physics asked for."""
    model, q, W, fi, K = bent_strip(0.005)
    armijo = newton_test(model, q, W, fi, K, 1e-7 * fi)
    qt = q.copy()
    qt[model.free] = q[model.free] + armijo.dq
    W1 = model.strain_energy(qt)
    assert not armijo._replace(floor=0.0).accepts(W1)
    stats = NewtonStats()
    assert armijo.accepts(W1, stats) and stats.roundoff_accepts == 1


def test_a_real_increase_is_still_cut():
    """Three times Newton's update on the bent strip overshoots a quadratic Π: the change
    at s = 1 is +1.5 a (a = rᵀK⁻¹r), far above δ; s = ½ gives −0.375 a and is taken."""
    model, q, W, fi, K = bent_strip(0.02)
    armijo = newton_test(model, q, W, fi, K, 1e-3 * fi, stretch=3.0)
    assert -armijo.slope > 1e6 * armijo.floor
    qt = q.copy()
    qt[model.free] = q[model.free] + armijo.dq
    stats = NewtonStats()
    assert not armijo.accepts(model.strain_energy(qt), stats)
    assert armijo.backtrack(model, stats) == 0.5
    assert stats.roundoff_accepts == 0 and stats.line_search_cuts == 1
