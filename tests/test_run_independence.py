"""A run depends on its inputs alone: run again on the same Simulation, or on a new Simulation
of the same model, it gives the first run's numbers to the bit.

What a run makes for itself stays with the run: a linear model's factorizations per step
size, its contact columns and the ladder that solves the sizes of split steps
(:mod:`fecontact.linalg.ladder`). Kept on the model, an earlier run's rungs gave a later run's
split sizes other preconditioners (or an exact factor instead of PCG), and their round-off
carried on from the first located impact: 2e-15 m/s there on the two balls below.
"""

import numpy as np
import pytest
from conftest import load_case

from fecontact.time import simulate

# (case, its parameters, end time in s): linear solids whose impacts are located in their
# steps with the split sizes solved by PCG from the ladder's rungs (more than 600 free dofs),
# each run past its first located impact
CASES = [
    pytest.param("two_balls", {"base": 1}, 1.5e-4, id="two_balls_3d"),
    pytest.param("two_disks", {"material": "linear", "refinements": 4}, 1.5e-3, id="two_disks_2d"),
]


def history(sim) -> list[tuple]:
    """Every state of a run of ``sim``: t, q, v, v̇, a, the gaps and the impulses."""
    out = []
    for st in simulate(sim.model, sim.dt, sim.t_end, sim.options, None, sim.q0, sim.v0):
        out.append(tuple(np.copy(x) for x in (st.t, st.q, st.v, st.vd, st.a, st.gaps, st.impulse)))
    return out


def assert_same(first: list, again: list) -> None:
    assert len(again) == len(first)
    for step, (x, y) in enumerate(zip(first, again, strict=True)):
        for name, a, b in zip(("t", "q", "v", "vd", "a", "gaps", "impulse"), x, y, strict=True):
            # bit for bit: the same inputs, the same operations
            assert np.array_equal(a, b), f"step {step}: {name} differs"


@pytest.mark.parametrize(("case", "params", "t_end"), CASES)
def test_a_run_again_on_the_same_model_gives_the_same_numbers(case, params, t_end):
    sim = load_case(case).build(**params, t_end=t_end)
    first = history(sim)
    assert any(np.any(st[6] > 0.0) for st in first)  # the bodies met
    assert sim.model.ladder is not None and sim.model.ladder.rungs  # split sizes were solved
    assert_same(first, history(sim))  # the same Simulation again
    assert_same(first, history(sim.replace()))  # a new Simulation of the same model
