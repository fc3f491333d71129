"""Rigid disk dropped on a simply supported flexible beam.

A steel strip (``Beam2D``, pinned at both ends, along +x from 0 to ``length``) carries a rigid
disk (``RigidBody2D`` with a ``Disk``) dropped from rest with its lowest point ``drop_height``
above the beam's top face, its centre at x = ``position`` × length. The disk strikes the
beam's centreline offset by half the thickness (``DiskBeamContact``: the contact point slides
along the elements), bounces, and excites the bending modes; both fall under gravity from the
undeformed, unloaded configuration.

The default odd number of elements puts the disk over the middle of an element. Over a node
the disk comes to rest in the kink of the centreline against both elements at once: two nearly
parallel constraints, whose multipliers are ill-determined (the position correction may then
fail to settle to its increment tolerance).

Probes: ``disk_y`` and ``disk_vy`` (centre height, m, and velocity, m/s), ``gap`` (smallest
disk-to-beam gap, m) and ``beam_mid_uy`` (deflection of the beam at mid-span, m).
"""

import numpy as np

from fecontact import Model, Param, Probe, Simulation, case, run_cli
from fecontact.bodies import Beam2D, Disk, Material, RigidBody2D, Section
from fecontact.contact import Contact
from fecontact.scenes import STRIP


@case(STRIP)  # a steel strip: span, elements, E, rho, width, thickness
def build(
    length=1.0, n_elements=21, E=210e9, rho=7850.0, width=0.05, thickness=0.01,
    disk_mass=Param.positive(1.0, "kg", "mass of the disk (uniform)"),
    radius=Param.positive(0.05, "m", "radius of the disk"),
    drop_height=Param.nonnegative(0.05, "m", "initial gap between the disk and the beam's top"),
    position=Param(0.5, "-", "disk centre's abscissa as a fraction of the span", 0, 1, (0, 0)),
    restitution=Param.fraction(0.0, "Newton's coefficient of restitution e_N"),
):  # fmt: skip
    material = Material(E, rho=rho)
    section = Section.rectangle(width, thickness)
    beam = Beam2D.straight([0.0, 0.0], [length, 0.0], n_elements, material, section)
    beam.pin(0).pin(-1)
    center = [position * length, 0.5 * thickness + drop_height + radius]
    disk = RigidBody2D.uniform(disk_mass, center, Disk(radius))
    hit = Contact(disk, beam, restitution=restitution, clearance=0.5 * thickness)
    model = Model([beam, disk], [hit])
    s = model.body_slice(1)
    # mid-span deflection, interpolated between the nodes around x = L/2
    x_nodes = beam.X[:, 0]
    k = min(int(np.searchsorted(x_nodes, 0.5 * length)), n_elements) - 1
    w_mid = (x_nodes[k + 1] - 0.5 * length) / (x_nodes[k + 1] - x_nodes[k])
    uy = beam.node_translation_dofs([k, k + 1])[:, 1]
    probes = {
        "disk_y": Probe(lambda m, st: center[1] + st.q[s][1], "m", "height of the disk centre"),
        "disk_vy": Probe(lambda m, st: st.v[s][1], "m/s", "vertical velocity of the disk"),
        "gap": Probe(lambda m, st: float(np.min(st.gaps)), "m", "gap between disk and beam"),
        "beam_mid_uy": Probe(
            lambda m, st: w_mid * st.q[uy[0]] + (1.0 - w_mid) * st.q[uy[1]],
            "m",
            "deflection of the beam at mid-span",
        ),
    }
    return Simulation(model, dt=2e-4, t_end=0.5, probes=probes, name="disk_on_beam")


if __name__ == "__main__":
    run_cli(build)
