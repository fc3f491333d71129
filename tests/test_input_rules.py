"""One test per input rule of the model-level API: a clear InputError naming the parameter."""

import numpy as np
import pytest

from fecontact import (
    Beam2D,
    Circle,
    Contact,
    InputError,
    IntegratorOptions,
    LinearElastic,
    Material,
    Model,
    NodalLoad,
    Pin,
    Plane,
    Point,
    Section,
    Simulation,
    Solid,
)
from fecontact.bodies.rigid import Disk, RigidBody2D
from fecontact.time import initial_state


def elastic():
    return LinearElastic(E=1e7, nu=0.3, rho=1000.0)


def beam():
    return Beam2D.straight(
        [0, 0], [1, 0], 4, Material(1e9, rho=1000.0), Section.rectangle(0.1, 0.01)
    )


@pytest.mark.parametrize(
    "make, word",
    [
        (lambda: Model([]), "bodies"),
        (lambda: Model([beam()], gravity=(0, 0, -9.81)), "gravity"),
        (lambda: Model([beam()], gravity=(np.nan, 0)), "gravity"),
        (lambda: Model([beam()], damping=(-1.0, 0.0)), "damping"),
        (lambda: Model([beam().clamp(0).clamp(1).clamp(2).clamp(3).clamp(4)]), "supports"),
        (lambda: Simulation(Model([beam()]), dt=0.0, t_end=1.0), "dt"),
        (lambda: Simulation(Model([beam()]), dt=1e-3, t_end=-1.0), "t_end"),
        (lambda: Simulation(Model([beam()]), dt=1e-3, t_end=1.0, output_interval=0), "output_"),
        (lambda: Simulation(Model([beam()]), dt=1e-3, t_end=1.0, name="a b"), "name"),
        (lambda: IntegratorOptions(rho_inf=-0.1), "rho_inf"),
        (lambda: IntegratorOptions(metric="lumped"), "metric"),
        (lambda: IntegratorOptions(penalty_scale=0.0), "penalty_scale"),
        (lambda: IntegratorOptions(multiplier_scale=np.inf), "multiplier_scale"),
        (lambda: IntegratorOptions(max_halvings=-1), "max_halvings"),
        (lambda: IntegratorOptions(integrator="euler"), "integrator"),
        (lambda: IntegratorOptions(theta=0.0), "theta"),
        (lambda: Pin(beam(), [0.5, 0.1]), "node"),
        (lambda: NodalLoad(beam(), 9, [1.0, 0.0, 0.0]), "node"),
        (lambda: NodalLoad(beam(), 0, [1.0, 0.0]), "value"),
        (lambda: Plane([0, 0], [0, 1], extent=-1.0), "extent"),
        (lambda: Circle([0, 0], 1.0, motion="up"), "motion"),
        (lambda: Point([0, np.nan]), "position"),
        (lambda: Contact(beam(), Circle([0, 0], 0.1), nodes=[], restitution=0.5), "nodes"),
        # magnitudes: squares and products of SI values stay far from overflow/underflow
        (lambda: Material(E=1e31, rho=1000.0), "E"),
        (lambda: Section(area=1e-31, inertia=1e-12), "area"),
        (lambda: Plane([0, 1e31], [0, 1]), "point"),
        # wrong types and shapes
        (lambda: Plane("origin", [0, 1]), "point"),
        (lambda: Point(0.0), "position"),
        (lambda: Pin(beam(), 0.0), "point"),
        (lambda: Model([beam()], damping=0.0), "damping"),
        (lambda: beam().pin("2"), "node"),
        (lambda: beam().pin(2.5), "node"),
        (lambda: NodalLoad(beam(), np.nan, [1.0, 0.0, 0.0]), "node"),
        (lambda: RigidBody2D(1.0, 1.0, [0, 0], angle=[0.1, 0.2], shape=Disk(0.1)), "angle"),
        (lambda: IntegratorOptions(max_iterations="30"), "max_iterations"),
        (lambda: IntegratorOptions(max_halvings=100), "max_halvings"),
        (lambda: IntegratorOptions(metric=["mass"]), "metric"),
        (lambda: Simulation(Model([beam()]), dt=1e-3, t_end=1.0, name=None), "name"),
        (
            lambda: Contact(RigidBody2D.uniform(1.0, [0, 1], Disk(0.1)), beam(), clearance=np.nan),
            "clearance",
        ),
        # mesh sizes a direct solver can take
        (lambda: Solid.disk([0, 0], 1.0, 10, elastic()), "refinements"),
        (lambda: Solid.disk([0, 0], 1.0, np.nan, elastic()), "refinements"),
        (lambda: Solid.ball([0, 0, 0], 1.0, 7, elastic()), "refinements"),
        (lambda: Solid.rectangle([0, 0], [1, 1], [2, 3, 4], elastic()), "divisions"),
        (lambda: Solid.rectangle([0, 0], [1, 1], 10**4, elastic()), "divisions"),
        (lambda: Solid(Solid.disk([0, 0], 1.0, 0, elastic()).mesh, elastic(), ["P1"]), "element"),
    ],
)
def test_model_level_input_rules(make, word):
    with pytest.raises(InputError, match=word):
        make()


def test_initial_penetration_is_an_input_error():
    b = beam()
    model = Model([b], [Contact(b, Plane([0, 0.01], [0, 1]))])
    with pytest.raises(InputError, match="penetrates"):
        initial_state(model)


def test_starting_exactly_in_contact_is_valid():
    b = beam()
    model = Model([b], [Contact(b, Plane([0, 0.0], [0, 1]))])
    assert initial_state(model).gaps.min() == 0.0


def test_initial_velocity_on_a_support_is_an_input_error():
    b = beam().pin(0)
    model = Model([b])
    v0 = np.zeros(model.n)
    v0[0] = 1.0
    with pytest.raises(InputError, match="v0"):
        initial_state(model, v0=v0)


def test_zero_where_allowed_may_be_tiny():
    """The lower magnitude bound is for strictly positive values: a tiny gap is a gap."""
    assert Point([0, 0], radius=1e-300).radius == 1e-300
