"""Case parameters: declared once, in the signature or in a group shared by several cases."""

import inspect

import pytest

from fecontact import InputError, Model, Param, Simulation, case
from fecontact.bodies import Beam2D, Material, Section

GROUP = {
    "length": Param.positive(0.3, "m", "beam length"),
    "n_elements": Param.count(4, "number of beam elements"),
}


def beam_case(length, n_elements):
    section = Section.rectangle(0.02, 0.002)
    beam = Beam2D.straight(
        [0.0, 0.0], [length, 0.0], n_elements, Material(70e9, rho=2700.0), section
    )
    return Simulation(Model([beam], []), dt=1e-3, t_end=1e-3)


@case(GROUP)
def from_group(length, n_elements=8, label=Param.choice("a", "a label", ("a", "b"))):
    return beam_case(length, n_elements)


def test_a_group_declares_unit_range_and_default_that_the_case_may_replace():
    declared = {n: p.default for n, p in inspect.signature(from_group).parameters.items()}
    assert declared["length"] == GROUP["length"]
    assert declared["n_elements"].default == 8  # the case's own default, the group's range
    assert (
        declared["n_elements"].low == 1 and declared["n_elements"].text == GROUP["n_elements"].text
    )
    assert declared["label"].choices == ("a", "b")
    assert from_group().parameters == {"length": 0.3, "n_elements": 8, "label": "a"}


@pytest.mark.parametrize(
    "values, word",
    [({"length": -1.0}, "length"), ({"n_elements": 0}, "n_elements"), ({"size": 1}, "size")],
)
def test_a_group_parameter_is_checked_before_any_work(values, word):
    with pytest.raises(InputError, match=word):
        from_group(**values)


def test_a_plain_default_outside_any_group_passes_unchecked():
    @case
    def plain(length=Param.positive(0.3, "m", "beam length"), n_elements=2):
        return beam_case(length, n_elements)

    assert plain(n_elements=3).model.bodies[0].n_nodes == 4
    assert "n_elements" not in plain().parameters


def test_a_replaced_default_outside_the_group_s_range_is_refused_when_the_case_loads():
    with pytest.raises(InputError, match="n_elements"):

        @case(GROUP)
        def wrong(length, n_elements=0):
            return beam_case(length, n_elements)
