"""Tumbling box: a box thrown spinning onto a rough plane, coming to rest on a face.

A uniform box (``RigidBody3D`` with a ``Box`` of sides ``a`` × ``b`` × ``c``) starts with its
centre at ``height`` above the plane z = 0, tilted, moving along +x at ``velocity`` and
spinning at ``spin`` (rad/s, body frame). Its eight corners meet the plane (one contact each,
Coulomb's ``friction`` and Newton's ``restitution``): it bounces, tumbles, slides and comes to
rest with a face on the plane.

Probes: ``z`` (m) and ``speed`` (m/s) of the centre, ``omega`` (rad/s, |Ω|), ``lowest`` (m,
the lowest corner's height) and ``upright`` (the largest |cosine| between a body axis and the
vertical: 1 when the box lies on a face).
"""

import numpy as np

from fecontact import (
    Box,
    Contact,
    InputError,
    Model,
    Param,
    Plane,
    Probe,
    RigidBody3D,
    Simulation,
    case,
    run_cli,
)
from fecontact.rotations import exp
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)  # gravity along -z
def build(
    a=Param.positive(0.2, "m", "side along the body x axis"),
    b=Param.positive(0.15, "m", "side along the body y axis"),
    c=Param.positive(0.1, "m", "side along the body z axis"),
    mass=Param.positive(1.0, "kg", "mass of the box (uniform)"),
    height=Param.positive(0.3, "m", "initial height of the centre"),
    velocity=Param(1.0, "m/s", "initial velocity of the centre along +x", -100.0, 100.0),
    spin=Param(8.0, "rad/s", "initial spin about the body axis (1, 2, 3)/|(1, 2, 3)|", -1e3, 1e3),
    friction=0.5, restitution=0.2, gravity=9.81,
    t_end=Param.positive(3.0, "s", "end time"),
):  # fmt: skip
    box = RigidBody3D.uniform(mass, [0.0, 0.0, height], Box(a, b, c))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=1.0)
    contact = Contact(box, floor, restitution=restitution, friction=friction)
    model = Model([box], [contact], gravity=(0.0, 0.0, -gravity))
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    q0 = np.r_[0.0, 0.0, 0.0, 0.3, -0.4, 0.2]  # tilted: a corner lands first
    v0 = np.r_[velocity, 0.0, 0.0, spin * axis]
    lowest = float(box.point_positions(q0, np.arange(8))[:, 2].min())
    if lowest <= 0.0:  # the tilted box's lowest corner, before any work
        raise InputError(
            f"height: the lowest corner starts at z = {lowest:.4g} m, on or below the plane; "
            f"give a height above {height - lowest:.4g} m for these sides a, b, c"
        )

    def corners(st):
        return box.point_positions(st.q, np.arange(8))

    probes = {
        "z": Probe(lambda m, st: float(box.center(st.q)[2]), "m", "height of the centre"),
        "speed": Probe(lambda m, st: float(np.linalg.norm(st.v[:3])), "m/s", "centre speed"),
        "omega": Probe(lambda m, st: float(np.linalg.norm(st.v[3:])), "rad/s", "spin rate"),
        "lowest": Probe(lambda m, st: float(corners(st)[:, 2].min()), "m", "lowest corner"),
        "upright": Probe(
            lambda m, st: float(np.abs(exp(st.q[3:])[2]).max()), "-", "face-down measure"
        ),
    }
    return Simulation(model, dt=1e-3, t_end=t_end, probes=probes, q0=q0, v0=v0, name="tumbling_box")


if __name__ == "__main__":
    run_cli(build)
