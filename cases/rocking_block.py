"""Rocking block: a rigid box released tilted on one corner of a plane.

A uniform box (``RigidBody2D`` with ``Polygon.box``) stands on the plane y = 0 on its bottom-
left corner, tilted counter-clockwise by ``angle`` (less than atan(width/height), so it falls
back). Without friction (the default) the corner slides while the box rotates; the box lands
flat on both bottom corners at once (a two-corner impact resolved with Newton's law at each
corner), then rocks on alternate corners with decreasing amplitude (restitution < 1). The
contacts act on all four vertices; the top ones never come near. With ``friction`` μ large
enough the corners do not slide: the box pivots about them.

Probes: ``angle`` of the box (rad, counter-clockwise), ``gap_left`` and ``gap_right``, the
heights of the bottom corners above the plane (m), and ``omega`` (rad/s).
"""

import numpy as np

from fecontact import InputError, Model, Param, Probe, Simulation, case, run_cli
from fecontact.bodies import Polygon, RigidBody2D
from fecontact.bodies.rigid import rotation
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)
def build(
    width=Param.positive(0.2, "m", "box width"),
    height=Param.positive(0.4, "m", "box height"),
    mass=Param.positive(1.0, "kg", "box mass (uniform density)"),
    angle=Param(
        0.1,
        "rad",
        "initial tilt, counter-clockwise, below atan(width/height)",
        0.0,
        np.pi / 2,
        (False, False),
    ),
    restitution=0.5,
    friction=0.0,
    gravity=9.81,
):
    # below atan(width/height) the centre of mass lies over the support: the box falls back
    if angle >= np.arctan2(width, height):
        raise InputError(
            f"angle must be in (0, atan(width/height)) = (0, "
            f"{np.arctan2(width, height):.6g}), got {angle!r}"
        )
    shape = Polygon.box(width, height)
    center = -rotation(angle) @ shape.vertices[0]  # the bottom-left corner on the origin
    block = RigidBody2D.uniform(mass, center, shape, angle=angle)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model(
        [block],
        [Contact(block, floor, restitution=restitution, friction=friction)],
        (0.0, -gravity),
    )

    def corner_gap(k):
        return lambda m, st: float(block.positions(st.q)[k, 1])

    probes = {
        "angle": Probe(lambda m, st: angle + st.q[2], "rad", "angle of the box"),
        "omega": Probe(lambda m, st: st.v[2], "rad/s", "angular velocity of the box"),
        "gap_left": Probe(corner_gap(0), "m", "height of the bottom-left corner"),
        "gap_right": Probe(corner_gap(1), "m", "height of the bottom-right corner"),
    }
    return Simulation(model, dt=1e-3, t_end=1.0, probes=probes, name="rocking_block")


if __name__ == "__main__":
    run_cli(build)
