"""Every body class provides the ``Body`` protocol, and the protocol lists every member the
package uses on a body of any kind: a recording run of the cases sees no other member
called from outside ``fecontact.bodies``, but for the few a kind's own contact pairs, joints
and statics use."""

import inspect
import sys

import numpy as np
import pytest
from conftest import load_case

import fecontact
from fecontact import (
    Beam2D,
    Beam3D,
    Box,
    Contact,
    Disk,
    IntegratorOptions,
    LinearElastic,
    Material,
    Model,
    Plane,
    PointMass,
    Polygon,
    RigidBody2D,
    RigidBody3D,
    Section,
    Simulation,
    Solid,
)
from fecontact.bodies.base import Body, BodyDefaults, EnergyConsistentBody


def bodies():
    mat = LinearElastic(E=1e6, nu=0.3, rho=1e3)
    steel = Material(2e11, rho=7850.0)
    return [
        Beam2D.straight([0, 0], [1, 0], 3, steel, Section.circle(0.01)),
        Beam2D.straight([0, 0], [1, 0], 3, steel, Section.circle(0.01), linear=True),
        Beam3D.straight([0, 0, 0], [1, 0, 0], 3, steel, Section.circle(0.01)),
        Solid.disk([0, 0], 0.1, 0, mat),
        Solid.rectangle([0, 0], [1, 1], (2, 2), mat, cell="quad"),
        Solid.box([0, 0, 0], [1, 1, 1], (1, 1, 1), mat),
        Solid.disk([0, 0], 0.1, 0, mat, element="P2"),
        RigidBody2D.uniform(1.0, [0, 0], Disk(0.1)),
        RigidBody2D.uniform(1.0, [0, 0], Polygon.box(0.2, 0.1)),
        PointMass(1.0, [0.0, 0.0]),
        RigidBody3D.uniform(1.0, [0, 0, 0], Box(0.2, 0.1, 0.3)),
    ]


def protocol_members(protocol) -> set[str]:
    return {n for n in dir(protocol) if not n.startswith("_")} | set(
        getattr(protocol, "__annotations__", {})
    )


def subclasses(cls):
    for sub in cls.__subclasses__():
        yield sub
        yield from subclasses(sub)


def test_the_bodies_checked_here_are_every_body_class_of_the_package():
    """A new body class joins ``bodies()`` above, and so this file's checks."""
    concrete = {c for c in subclasses(BodyDefaults) if c.__module__.startswith("fecontact.")}
    concrete = {c for c in concrete if not any(s in concrete for s in c.__subclasses__())}
    assert concrete == {type(b) for b in bodies()}


@pytest.mark.parametrize("body", bodies(), ids=lambda b: type(b).__name__)
def test_every_body_provides_the_protocol_with_its_signatures(body):
    assert isinstance(body, Body)
    for name in protocol_members(Body):
        declared = inspect.getattr_static(Body, name, None)
        if not callable(declared):
            continue
        want = list(inspect.signature(declared).parameters)[1:]
        have = list(inspect.signature(getattr(body, name)).parameters)
        assert have == want, f"{type(body).__name__}.{name}{tuple(have)}: protocol {want}"
    assert (
        isinstance(body.ndof, int)
        and body.ndof == body.dofs_per_node * body.n_nodes
        or (body.rigid_frame and body.ndof == body.dofs_per_node)
    )
    assert body.mass > 0.0 and body.characteristic_length > 0.0
    assert body.mass_matrix().shape == (body.ndof, body.ndof)
    assert body.translation_field(np.ones(body.dim)).shape == (body.ndof,)
    assert body.rigid_modes().shape[0] == body.ndof
    W, f, _ = body.internal(np.zeros(body.ndof))
    assert W == 0.0 and body.energy(np.zeros(body.ndof)) == 0.0 and f.shape == (body.ndof,)
    if body.energy_consistent:
        assert isinstance(body, EnergyConsistentBody)


def test_beam_mass_counts_its_point_masses():
    beam = Beam2D.straight([0, 0], [2, 0], 4, Material(1e9, rho=1e3), Section(1e-3, 1e-8))
    assert beam.mass == pytest.approx(2.0)  # ρ A L = 1e3 · 1e-3 · 2 kg
    M = beam.add_mass(-1, 0.5).mass_matrix()
    e = beam.translation_field((1.0, 0.0))
    assert beam.mass == pytest.approx(e @ M @ e, rel=1e-12) == pytest.approx(2.5)


# Members that contact pairs, joints and statics use on the body kinds they are made for
# (a beam's centreline segments, a solid's boundary facets, a rigid body's frame), and that the
# frames use on continua (the boundary area each node carries, for the contact pressure).
KIND_MEMBERS = {
    Beam2D: {
        "X",
        "segments",
        "node_translation_dofs",
        "locate",
        "section",  # two strips share their clearance by their sections' thickness
    },
    Solid: {
        "X",
        "material",
        "min_edge_length",
        "contact_facets",
        "node_translation_dofs",
        "boundary_nodes",
        "stiffness_matrix",
        "tributary_areas",
        "thickness",  # a 2D mortar interface's pressure area
        "element",  # two P2 solids meet on their quadratic faces (mortar)
    },
    RigidBody2D: {"shape", "position", "center", "orientation", "to_frame", "frame_point_function"},
    PointMass: {"position"},
    RigidBody3D: {
        "shape",
        "position",
        "center",
        "rotation",
        "to_frame",
        "frame_point_kinematics",
        "frame_point_function",
        "point_positions_frame",
    },
}


def short_runs():
    """Simulations covering every body kind with its contacts, joints, friction, the
    energy-decaying step and the output."""
    case = load_case
    point = PointMass(1.0, [0.0, 0.01], size=0.05)
    drop = Model([point], [Contact(point, Plane([0, 0], [0, 1]), restitution=0.5)], (0, -9.81))
    return [
        case("flexible_pendulum").build(restitution=0.5, friction=0.3).replace(t_end=0.35),
        case("flexible_pendulum")
        .build()
        .replace(t_end=0.02, options=IntegratorOptions(scheme="energy-decaying")),
        case("disk_on_beam").build().replace(t_end=0.12),
        case("disk_drop").build(refinements=1, friction=0.3, t_end=0.004),
        case("ball_drop").build(refinements=0, t_end=0.003),
        case("two_disks").build(refinements=1, t_end=0.003),
        case("two_bars").build(n_elements=10),
        case("rigid_pendulum").build().replace(t_end=0.6),
        case("rocking_block").build().replace(t_end=0.2),
        case("elastic_block").build(divisions=2, t_end=0.01, velocity=0.5),
        Simulation(drop, dt=1e-3, t_end=0.1, name="point_drop"),
        case("heavy_top").build(dt=1e-3, t_end=0.05),
        case("tumbling_box").build(t_end=0.25),
    ]


@pytest.mark.slow
def test_the_package_uses_no_body_member_the_protocol_does_not_declare(tmp_path, monkeypatch):
    seen: dict[type, set[str]] = {}

    def recording(self, name):
        caller = sys._getframe(1).f_globals.get("__name__", "")
        if caller.startswith("fecontact.") and not caller.startswith("fecontact.bodies."):
            seen.setdefault(type(self), set()).add(name)
        return object.__getattribute__(self, name)

    monkeypatch.setattr(BodyDefaults, "__getattribute__", recording, raising=False)
    for i, sim in enumerate(short_runs()):
        fecontact.run(sim, tmp_path / str(i), checkpoint_every=0)
    assert set(seen) == {Beam2D, Solid, RigidBody2D, PointMass, RigidBody3D}
    declared = protocol_members(Body) | protocol_members(EnergyConsistentBody)
    for cls, names in seen.items():
        names = {n for n in names if not (n.startswith("__") and n.endswith("__"))}
        assert names - declared - KIND_MEMBERS[cls] == set(), cls.__name__
