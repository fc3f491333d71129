"""Property test: random parameters fed to the case builders either build a simulation or
stop with a clear InputError naming a parameter — never another exception."""

import inspect
import math

import pytest
from conftest import load_case
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fecontact import InputError

CASES = ["flexible_pendulum"]

values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-10, max_value=10),
    st.integers(min_value=-5, max_value=50),
    st.sampled_from(["abc", "", "1e3", "stiffness"]),
    st.none(),
)


@pytest.mark.parametrize("name", CASES)
def test_case_builders_reject_bad_parameters_cleanly(name):
    case = load_case(name)
    params = list(inspect.signature(case.build).parameters)

    @settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(st.dictionaries(st.sampled_from(params), values, min_size=1, max_size=4))
    def check(overrides):
        try:
            sim = case.build(**overrides)
        except InputError as err:
            message = str(err)
            assert "\n" not in message
            assert any(p in message for p in params) or "must" in message
            return
        # accepted: every accepted value is a finite number
        for key, value in overrides.items():
            assert isinstance(value, (int, float)) and math.isfinite(value), (key, value)
        assert sim.dt > 0 and sim.t_end > 0

    check()
