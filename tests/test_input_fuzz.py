"""Property test: random parameters fed to every case builder either build a simulation whose
first steps run, or stop with a one-line InputError that names a parameter — never another
exception, never a model that silently holds a bad value.

The draws (seeded, so every run tries the same ones) mix the defaults scaled by 1e±3 (valid
and meant to run) with zeros, negatives, NaN, ±inf, 1e±300, integers that are too large or
not integers, and wrong types (strings, None, booleans, lists).
"""

import inspect
import math
import re

import numpy as np
import pytest
from conftest import ROOT, load_case

from fecontact import InputError, Param, SolverError, simulate

CASES = sorted(p.stem for p in (ROOT / "cases").glob("*.py"))
DRAWS = 60


def candidates(default):
    """Values to try for a parameter whose default is ``default``."""
    wrong_types = ["abc", None, True, [1.0]]
    if isinstance(default, str):
        return [default, "xyz", "", 1.0, None]
    if isinstance(default, int):
        return [default, default + 1, 0, -1, 2.5, float(default), math.nan, 10**12, "3"]
    scale = abs(default) or 1.0
    return [
        default,
        scale * 1e3,
        scale * 1e-3,
        0.0,
        -scale,
        math.nan,
        math.inf,
        -math.inf,
        1e300,
        1e-300,
    ] + wrong_types


def defaults(build) -> dict:
    """Each parameter's default, whether declared as a ``Param`` or plainly."""
    return {
        name: p.default.default if isinstance(p.default, Param) else p.default
        for name, p in inspect.signature(build).parameters.items()
    }


def draws(build, rng, n):
    values = defaults(build)
    names = list(values)
    for _ in range(n):
        keys = rng.choice(names, size=rng.integers(1, 4), replace=False)
        yield {str(k): (c := candidates(values[k]))[rng.integers(len(c))] for k in keys}


def accepted(value, default) -> bool:
    """A value a builder may accept: a finite real number, or a string for a string
    parameter (its allowed names are the case's business)."""
    if isinstance(default, str):
        return isinstance(value, str)
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


@pytest.mark.parametrize("name", CASES)
def test_case_builders_reject_bad_parameters_cleanly(name):
    case = load_case(name)
    params = defaults(case.build)
    rng = np.random.default_rng(sum(map(ord, name)))
    for overrides in draws(case.build, rng, DRAWS):
        try:
            sim = case.build(**overrides)
        except InputError as err:
            message = str(err)
            assert "\n" not in message, (overrides, message)
            named = re.match(r"(\w+)", message).group(1)
            assert named in params, (overrides, message)
            continue
        for key, value in overrides.items():
            assert accepted(value, params[key]), (overrides, "accepted")
        try:
            for st in simulate(sim.model, sim.dt, 3 * sim.dt, sim.options, q0=sim.q0, v0=sim.v0):
                assert np.all(np.isfinite(st.q)) and np.all(np.isfinite(st.v)), overrides
        except SolverError as err:
            # the step of the case cannot follow this motion (an impact far faster than
            # the waves, say): a run-time failure that reports where it stopped
            assert "at t =" in str(err), (overrides, str(err))
