"""Box stack: three boxes stacked on a plane, the top one knocked sideways.

Three uniform boxes (``RigidBody3D`` with ``Box`` shapes, sides ``side`` × ``side`` ×
``height``, the upper ones a little smaller) stand stacked on the plane z = 0. The top box starts
sliding along +x at ``knock`` (m/s). The boxes touch each other through convex pairs (GJK/EPA
and the face-clipping manifold: the four corners of a face on a face, frictionless; needs the
``collision`` extra) and the plane through their corners (Coulomb's ``friction``). At
``knock`` = 0 the stack rests; knocked, the top box slides off the middle one, tips over its
edge and falls to the plane.

Probes: ``z_bottom``, ``z_middle``, ``z_top`` (m), the heights of the three centres, ``x_top``
(m) and ``speed_top`` (m/s), the top box's position along x and speed, ``lowest_gap`` (m), the
smallest gap of all contacts.
"""

import numpy as np

from fecontact import Model, Param, Probe, Simulation, case, run_cli
from fecontact.bodies import Box, RigidBody3D
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)  # friction against the plane; gravity along -z
def build(
    side=Param.positive(0.2, "m", "side of the bottom box along x and y"),
    height=Param.positive(0.1, "m", "height of each box"),
    mass=Param.positive(1.0, "kg", "mass of each box (uniform)"),
    knock=Param(1.0, "m/s", "initial velocity of the top box along +x", -100.0, 100.0),
    friction=0.5, restitution=0.0, gravity=9.81,
    t_end=Param.positive(0.6, "s", "end time"),
):  # fmt: skip
    sizes = (1.0, 0.8, 0.6)  # each box narrower than the one below
    boxes = [
        RigidBody3D.uniform(mass, [0.0, 0.0, (k + 0.5) * height], Box(s * side, s * side, height))
        for k, s in enumerate(sizes)
    ]
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * side)
    contacts = [Contact(b, floor, restitution=restitution, friction=friction) for b in boxes]
    contacts += [
        Contact(boxes[i], boxes[j], restitution=restitution)
        for i in range(3)
        for j in range(i + 1, 3)
    ]
    model = Model(boxes, contacts, gravity=(0.0, 0.0, -gravity))
    v0 = np.zeros(18)
    v0[12] = knock

    def centre(k, i):
        return lambda m, st: float(boxes[k].center(st.q[6 * k : 6 * k + 6])[i])

    probes = {
        "z_bottom": Probe(centre(0, 2), "m", "height of the bottom box's centre"),
        "z_middle": Probe(centre(1, 2), "m", "height of the middle box's centre"),
        "z_top": Probe(centre(2, 2), "m", "height of the top box's centre"),
        "x_top": Probe(centre(2, 0), "m", "position of the top box's centre along x"),
        "speed_top": Probe(
            lambda m, st: float(np.linalg.norm(st.v[12:15])), "m/s", "top box's speed"
        ),
        "lowest_gap": Probe(lambda m, st: float(np.min(st.gaps)), "m", "smallest gap"),
    }
    return Simulation(model, dt=2e-3, t_end=t_end, probes=probes, v0=v0, name="box_stack")


if __name__ == "__main__":
    run_cli(build)
