"""Flexible pendulum in space: the founding case with the strip free to leave its plane.

The aluminium strip of ``flexible_pendulum`` (a ``Beam3D`` with the same section, mass,
elements and options), on a spherical pin at the origin, lies along +x at t = 0 with a 0.14 kg
mass at its tip and falls under gravity along −y. Its tip hits the stop, the plane x = 0
through (0, -0.3, 0) (normal +x). ``out_of_plane_velocity`` starts the strip turning rigidly
about the pin so that its tip moves along z at that speed: the swing leaves the x–y plane.
At 0 the motion stays in the plane and is the founding case's.
"""

import numpy as np

from fecontact import Model, Param, Simulation, case, node_probe, run_cli
from fecontact.bodies import Beam3D, Material, Section
from fecontact.contact import Contact, Plane
from fecontact.scenes import PENDULUM_STOP, STRIP


@case(STRIP, PENDULUM_STOP)  # an aluminium strip; its tip mass, stop and gravity
def build(
    length, n_elements, E, nu, rho, width, thickness, tip_mass, restitution, friction, gravity,
    out_of_plane_velocity=Param(0.0, "m/s", "initial tip speed along z (rigid turn)"),
):  # fmt: skip
    material = Material(E, nu=nu, rho=rho)
    section = Section.rectangle(width, thickness)
    beam = Beam3D.straight([0.0, 0.0, 0.0], [length, 0.0, 0.0], n_elements, material, section)
    beam.pin(0).add_mass(-1, tip_mass)
    wall = Plane([0.0, -0.3, 0.0], [1.0, 0.0, 0.0], extent=0.08)
    stop = Contact(beam, wall, nodes=[-1], restitution=restitution, friction=friction)
    model = Model([beam], [stop], gravity=(0.0, -gravity, 0.0))
    probes = {f"tip_{q}": node_probe(model, beam, -1, q) for q in ("x", "y", "z", "vx", "vy")}
    # a rigid turn about −y through the pin: v = ω × X with ω = (0, −w/L, 0), on every node
    omega = np.array([0.0, -out_of_plane_velocity / length, 0.0])
    v0 = np.zeros((beam.n_nodes, 6))
    v0[:, :3], v0[:, 3:] = np.cross(omega, beam.X), omega
    sim = Simulation(model, dt=1e-3, t_end=1.5, probes=probes, name="spatial_pendulum")
    return sim.replace(v0=v0.ravel()) if out_of_plane_velocity else sim


if __name__ == "__main__":
    run_cli(build)
