"""The smooth Newton descends the incremental potential Π at every update (issue: uphill
Newton steps after impacts, hidden by step halving)."""

import json
import math

import numpy as np
import pytest

from fecontact.cli.commands import main
from fecontact.testing import CASES, case
from fecontact.time import simulate
from fecontact.time.descent import Armijo, descent_direction
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
            armijo = Armijo(q[None].copy(), dq, *test, model.strain_energy(q), 1.0)
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
    assert set(counts) == {"iterations", "line_search_cuts", "shifted_directions"}
    # every smooth Newton update of the run went through the globalization (the last
    # iteration of a step only evaluates the residual)
    assert 400 <= counts["iterations"] < summary["newton_iterations_total"]
    assert summary["step_halvings"] == 0
