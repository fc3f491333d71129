"""Flexible pendulum released horizontally, stopped by a rigid stop at (0, -0.3).

An aluminium strip pinned at the origin, lying along +x at t = 0 with a 0.14 kg mass at its
tip, falls under gravity. Its tip hits a rigid stop, the plane x = 0 through (0, -0.3)
(normal +x), and the beam rings at its first bending frequency. With ``friction`` the tip
rubs along the stop (Coulomb).
"""

from fecontact import Model, Simulation, case, node_probe, run_cli
from fecontact.bodies import Beam2D, Material, Section
from fecontact.contact import Contact, Plane
from fecontact.scenes import PENDULUM_STOP, STRIP


@case(STRIP, PENDULUM_STOP)  # an aluminium strip; its tip mass, stop and gravity
def build(
    length, n_elements, E, nu, rho, width, thickness, tip_mass, restitution, friction, gravity,
):  # fmt: skip
    material = Material(E, nu=nu, rho=rho)
    section = Section.rectangle(width, thickness)
    beam = Beam2D.straight([0.0, 0.0], [length, 0.0], n_elements, material, section)
    beam.pin(0).add_mass(-1, tip_mass)
    wall = Plane([0.0, -0.3], [1.0, 0.0], extent=0.08)
    stop = Contact(beam, wall, nodes=[-1], restitution=restitution, friction=friction)
    model = Model([beam], [stop], gravity=(0.0, -gravity))
    probes = {f"tip_{q}": node_probe(model, beam, -1, q) for q in ("x", "y", "vx", "vy")}
    return Simulation(model, dt=1e-3, t_end=1.5, probes=probes, name="flexible_pendulum")


if __name__ == "__main__":
    run_cli(build)
