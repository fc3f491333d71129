"""Elastic disk dropped on a rigid plane (2D, plane strain, Neo-Hookean by default).

A disk of ``radius`` (scikit-fem's ``MeshTri.init_circle`` refined ``refinements`` times, P1
triangles) starts with its lowest point ``drop_height`` above the plane y = 0, falling at
``velocity``, under gravity (9.81 m/s² along −y). Every boundary node is a contact node
against the plane (``NodeContact``, restitution e_N at the nodes); the disk bounces through
its own elasticity, its contact patch spreading over a few nodes. The material is a
compressible Neo-Hookean solid (``material="linear"`` or ``"svk"`` for the others).

Thrown at an angle (``slide_velocity`` along +x) with Coulomb ``friction`` μ at the
contact nodes, the disk is slowed along the plane and set spinning: over the impact the
tangential momentum changes by at most μ times the normal one (exactly that while every
contact node slips), and the work of friction is in ``history.csv``.

The step is the time Δx/c the dilatational wave takes to cross the shortest element edge:
nodes that stay in contact carry a smooth contact force in the generalized-α step (see
``two_disks``), and with ``friction`` a smooth tangential force under Coulomb's law too.
Measured on this disk: energy excess during contact 0.000 % of the impact kinetic energy,
rebound 0.96486 m/s against 0.96535 m/s at Δx/8c. Thrown at 2 m/s along and 1 m/s onto the
plane (2 refinements) the rebound is within 1.2 % of the run at Δx/16c for μ = 0.1 (every
node slips) and μ = 1 (nodes grip), with no energy excess above 0.06 %; the decoupled scheme
of corrections and jumps alone needed Δx/8c for that (at Δx/c it puts in 35 % and 67 %;
``benchmarks/smooth_friction.py``).

Probes: ``y_center`` and ``vy_center`` (height of the centre of mass, m, and its velocity,
m/s), ``vx_center`` (its velocity along the plane, m/s), ``omega`` (angular velocity about
the centre of mass, rad/s, counter-clockwise), ``gap`` (lowest point above the plane, m) and
``contact_force`` (Σ k Λ_j / h, N).
"""

from fecontact import Model, Param, case, run_cli
from fecontact.bodies import Solid
from fecontact.contact import Contact, Plane
from fecontact.scenes import (
    DISK,
    DROP,
    SOLID,
    centre_of_mass_probes,
    contact_force_probe,
    lowest_point_probe,
    solid_material,
    spin_probe,
    wave_simulation,
)


@case(DISK, SOLID, DROP)
def build(
    radius, refinements, E, nu, rho, material, drop_height, velocity, restitution, t_end,
    slide_velocity=Param(0.0, "m/s", "initial velocity along the plane (+x)", -1e3, 1e3),
    friction=Param.nonnegative(0.0, "-", "Coulomb's coefficient mu at the contact nodes"),
):  # fmt: skip
    disk = Solid.disk(
        [0.0, radius + drop_height], radius, refinements, solid_material(material, E, nu, rho)
    )
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([disk], [Contact(disk, floor, restitution=restitution, friction=friction)])
    probes = centre_of_mass_probes(model, disk, 1, radius + drop_height)
    probes["vx_center"] = centre_of_mass_probes(model, disk, 0)["vx_center"]
    probes["omega"] = spin_probe(model, disk)
    probes |= {"gap": lowest_point_probe(model, disk, 1), "contact_force": contact_force_probe()}
    v0 = model.translation(disk, (slide_velocity, -velocity))
    return wave_simulation(model, disk, "disk_drop", t_end, probes, v0)


if __name__ == "__main__":
    run_cli(build)
