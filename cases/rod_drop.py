"""Steel rod dropped obliquely onto a rigid floor: a 3D beam striking a plane.

A straight rod of circular section (``Beam3D``), inclined by ``angle`` from the horizontal in
the vertical plane along ``azimuth`` (its horizontal projection's direction from +x), falls
toward the floor z = 0 (gravity along −z) with its lower end's surface ``drop_height`` above
it, moving down at ``velocity``. Every node touches the floor through the section's surface
(clearance = radius): the lower end strikes first, the rod rotates and whips, then its upper
part slaps down. ``yaw_rate`` spins the rod about the vertical through its centre as it falls:
the motion leaves the vertical plane. Without spin it stays in that plane, where it is the
same drop of a ``Beam2D``.

Probes: ``low_z`` and ``high_z`` (heights of the two ends' centrelines, m), ``center_vz``
(velocity of the middle node, m/s) and ``low_vz`` (m/s).
"""

import numpy as np

from fecontact import Model, Param, Simulation, case, node_probe, run_cli
from fecontact.bodies import Beam3D, Material, Section
from fecontact.contact import Contact, Plane
from fecontact.scenes import IMPACT, ROD


@case(ROD, IMPACT)  # a steel rod; its contact's laws
def build(
    length=0.5, radius=0.005, n_elements=10, E=210e9, nu=0.3, rho=7850.0,
    angle=Param(30.0, "deg", "inclination of the rod from the horizontal", 0.0, 90.0),
    azimuth=Param(45.0, "deg", "direction of the rod's horizontal projection, from +x"),
    drop_height=Param.nonnegative(0.002, "m", "initial gap between the lower end and the floor"),
    velocity=Param.nonnegative(1.0, "m/s", "initial downward speed"),
    yaw_rate=Param(0.0, "rad/s", "initial spin about the vertical through the rod's centre"),
    restitution=0.0,
    friction=0.0,
):  # fmt: skip
    a, b = np.radians(angle), np.radians(azimuth)
    axis = np.array([np.cos(a) * np.cos(b), np.cos(a) * np.sin(b), np.sin(a)])
    low = np.array([0.0, 0.0, radius + drop_height])
    section = Section.circle(radius)
    rod = Beam3D.straight(
        low, low + length * axis, n_elements, Material(E, nu=nu, rho=rho), section
    )
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=length)
    touch = Contact(rod, floor, restitution=restitution, friction=friction, clearance=radius)
    model = Model([rod], [touch], gravity=(0.0, 0.0, -9.81))
    mid = n_elements // 2
    probes = {
        "low_z": node_probe(model, rod, 0, "z"),
        "high_z": node_probe(model, rod, -1, "z"),
        "center_vz": node_probe(model, rod, mid, "vz"),
        "low_vz": node_probe(model, rod, 0, "vz"),
    }
    # a fall at `velocity` plus a rigid spin ω = yaw_rate e_z about the rod's centre
    omega = np.array([0.0, 0.0, yaw_rate])
    v0 = np.zeros((rod.n_nodes, 6))
    v0[:, :3] = np.cross(omega, rod.X - rod.X.mean(axis=0)) + [0.0, 0.0, -velocity]
    v0[:, 3:] = omega
    return Simulation(model, dt=1e-4, t_end=0.25, probes=probes, name="rod_drop", v0=v0.ravel())


if __name__ == "__main__":
    run_cli(build)
