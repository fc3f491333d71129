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


def test_readme_snippets_run():
    """The 'Things a case often needs' block runs against a model that has its names."""
    from fecontact import (
        Beam2D,
        Contact,
        Disk,
        LinearElastic,
        Material,
        Model,
        Probe,
        RigidBody2D,
        Section,
        Simulation,
        Solid,
    )

    text = (ROOT / "README.md").read_text()
    code = re.search(r"Things a case often needs.*?```python\n(.*?)```", text, re.S).group(1)
    mat = LinearElastic(E=1e6, nu=0.3, rho=1e3)
    ball = Solid.disk([0.0, 0.2], 0.05, 1, mat)
    disk = RigidBody2D.uniform(1.0, [0.5, 0.2], Disk(0.05))
    section = Section.rectangle(0.05, 0.01)
    beam = Beam2D.straight([0, 0], [1, 0], 4, Material(E=2e11, rho=7850.0), section).pin(0)
    model = Model([ball, disk, beam], [])
    namespace = dict(locals())
    namespace.update(Simulation=Simulation, Solid=Solid, Contact=Contact, Probe=Probe)
    import os

    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        exec(compile(code, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    assert namespace["sim"].v0 is not None and namespace["plate"].thickness == 0.005
