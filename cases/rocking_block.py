"""Rocking block: a rigid box released tilted on one corner of a frictionless plane.

A uniform box (``RigidBody2D`` with ``Polygon.box``) stands on the plane y = 0 on its
bottom-left corner, tilted counter-clockwise by ``angle`` (less than atan(width/height), so it
falls back). Without friction the corner slides while the box rotates; the box lands flat on
both bottom corners at once (a two-corner impact resolved with Newton's law at each corner),
then rocks on alternate corners with decreasing amplitude (restitution < 1). The contacts act
on all four vertices; the top ones never come near.

Probes: ``angle`` of the box (rad, counter-clockwise), ``gap_left`` and ``gap_right``, the
heights of the bottom corners above the plane (m), and ``omega`` (rad/s).
"""

import numpy as np

from fecontact import (
    Contact,
    Model,
    Plane,
    Probe,
    Simulation,
    check_positive,
    check_range,
    run_cli,
)
from fecontact.bodies.rigid import Polygon, RigidBody2D, rotation

PARAMETERS = {
    "width": ("m", "box width"),
    "height": ("m", "box height"),
    "mass": ("kg", "box mass (uniform density)"),
    "angle": ("rad", "initial tilt, counter-clockwise, in (0, atan(width/height))"),
    "restitution": ("-", "Newton's coefficient of restitution e_N in [0, 1] at the corners"),
    "gravity": ("m/s^2", "acceleration of gravity (>= 0), along -y"),
}


def build(width=0.2, height=0.4, mass=1.0, angle=0.1, restitution=0.5, gravity=9.81):
    check_positive("width", width)
    check_positive("height", height)
    check_positive("mass", mass)
    # atan(width/height): the centre of mass lies over the support, the box falls back
    check_range("angle", angle, 0.0, np.arctan2(width, height), (False, False))
    check_range("restitution", restitution, 0.0, 1.0)
    check_positive("gravity", gravity, allow_zero=True)
    shape = Polygon.box(width, height)
    # the bottom-left corner (vertex 0) on the origin
    center = -rotation(angle) @ shape.vertices[0]
    block = RigidBody2D.uniform(mass, center, shape, angle=angle)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([block], [Contact(block, floor, restitution=restitution)], (0.0, -gravity))

    def corner_gap(k):
        return lambda m, st: float(block.positions(st.q)[k, 1])

    probes = {
        "angle": Probe(lambda m, st: angle + st.q[2], "rad", "angle of the box"),
        "omega": Probe(lambda m, st: st.v[2], "rad/s", "angular velocity of the box"),
        "gap_left": Probe(corner_gap(0), "m", "height of the bottom-left corner"),
        "gap_right": Probe(corner_gap(1), "m", "height of the bottom-right corner"),
    }
    params = {k: v for k, v in locals().items() if k in PARAMETERS}
    return Simulation(
        model, dt=1e-3, t_end=1.0, probes=probes, name="rocking_block", parameters=params
    )


if __name__ == "__main__":
    run_cli(build)
