"""The README's case example builds, checks its parameters and steps."""

import re

import pytest
from conftest import ROOT

from fecontact import InputError, simulate


def readme_case():
    text = (ROOT / "README.md").read_text()
    code = re.search(r"## Writing a case.*?```python\n(.*?)```", text, re.S).group(1)
    namespace = {"__name__": "readme_case"}
    exec(compile(code, "README.md", "exec"), namespace)
    return namespace["build"]


def test_readme_case_runs_and_checks_its_parameters():
    build = readme_case()
    sim = build(restitution=0.5)
    assert sim.parameters == {"length": 0.3, "restitution": 0.5}
    states = list(simulate(sim.model, sim.dt, 10 * sim.dt, sim.options))
    assert len(states) == 11
    with pytest.raises(InputError, match=r"restitution must be in \[0, 1\]"):
        build(restitution=1.5)
