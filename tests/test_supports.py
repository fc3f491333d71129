"""One vocabulary for supports on every body: ``fix([node(s),] *components)`` with the
components named as the body's dofs (x, y, z, theta) or given by index; all when none."""

import pytest

from fecontact import Beam2D, InputError, LinearElastic, Material, Section, Solid
from fecontact.bodies.rigid import Disk, PointMass, RigidBody2D


def beam():
    return Beam2D.straight(
        [0, 0], [1, 0], 2, Material(E=1e9, nu=0.3, rho=1e3), Section.circle(0.01)
    )


def test_beam_pin_and_clamp_are_fix_with_components():
    assert beam().fix(1, "x", "y").fixed == beam().pin(1).fixed == {3, 4}
    assert beam().fix(-1).fixed == beam().clamp(-1).fixed == {6, 7, 8}
    assert beam().fix(0, "theta", 1).fixed == {1, 2}


def test_solid_fix_by_name_or_index():
    body = Solid.rectangle([0, 0], [1, 1], 1, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    assert body.fix([0, 2], "y").fixed == {1, 5}
    body = Solid.rectangle([0, 0], [1, 1], 1, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    assert body.fix(1, components=[0]).fixed == {2}
    with pytest.raises(InputError, match="components must be among x, y"):
        body.fix(0, "z")


def test_rigid_bodies_fix_their_frame():
    disk = RigidBody2D(1.0, 0.1, [0, 1], shape=Disk(0.1))
    assert disk.fix().fixed == {0, 1, 2}
    assert PointMass(1.0, [0, 0]).fix("y").fixed == {1}
    with pytest.raises(InputError, match="components must be among x, y, theta"):
        RigidBody2D(1.0, 0.1, [0, 1], shape=Disk(0.1)).fix("rotation")
