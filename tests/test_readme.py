"""The README's commands and case example, and the case-writing guide's snippets, run."""

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

    text = (ROOT / "docs" / "howto" / "write_a_case.md").read_text()
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
        exec(compile(code, "write_a_case.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    assert namespace["sim"].v0 is not None and namespace["plate"].thickness == 0.005


def readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    setup = re.search(r"## Set-up(.*?)\n## ", text, re.S).group(1)
    return re.findall(r"```\n(.*?)\n```", setup, re.S)


def test_readme_set_up_is_two_commands_that_install_what_they_use():
    """The first installs the render extra its --render needs; the second the test extra,
    whose dependencies are every extra the tests import."""
    first, second = readme_commands()
    assert first == 'pip install -e ".[render]" && fecontact run flexible_pendulum --render'
    assert second == 'pip install -e ".[test]" && pytest'
    ci = (ROOT / ".ci" / "run").read_text()
    assert 'pip install -e ".[test]"' in ci


@pytest.mark.slow
def test_readme_first_command_runs_from_any_folder(tmp_path, monkeypatch):
    """``fecontact run flexible_pendulum --render`` as written, shortened to 0.05 s."""
    pytest.importorskip("pyvista")
    from fecontact.cli import main

    command = readme_commands()[0].split(" && ")[1].split()
    assert command[0] == "fecontact"
    monkeypatch.chdir(tmp_path)
    assert main([*command[1:], "--t-end", "0.05", "--quiet"]) == 0
    out = tmp_path / "out" / "flexible_pendulum"
    assert (out / "summary.json").is_file() and (out / "animation.gif").is_file()


def test_readme_is_a_front_page():
    """At most 250 lines; every page it links to exists."""
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 250
    links = re.findall(r"\]\(((?:docs)/[^)]+)\)", text)
    assert len(links) >= 10
    for link in links:
        assert (ROOT / link).is_file(), link
