"""Two elastic disks colliding head-on, without gravity (2D, plane strain).

Two identical disks of ``radius`` (``MeshTri.init_circle`` refined ``refinements`` times, P1
triangles), their centres on the x axis with ``gap`` between them, move toward each other at
``velocity`` each. Their contact is one dual mortar interface (``method="mortar"``, the
default between two solids): one weighted gap per boundary node of the left disk, integrated
over its boundary segments against the right disk's (:mod:`fecontact.contact.mortar`); it
keeps either disk out of the other, and the pair declared both ways (``two_pass`` = 1) is the
same interface. With ``method="node-to-surface"`` the boundary nodes of the left disk
contact the boundary segments of the right one (node-to-segment with the exact gap Hessian),
and with ``two_pass`` = 1 the right disk's nodes the left disk's segments too. Frictionless
contact forces are equal and opposite, so the total momentum stays zero; the disks stop,
then separate through their elasticity (e_N = ``restitution`` acts on the contact rows
only). Compressible Neo-Hookean material by default (``material="linear"`` or ``"svk"`` for
the others).

The boundary vertices of the two disks meet vertex to vertex on the x axis. Node-to-surface
contact breaks the symmetry there (a node picks one of two equally close segments): the
disks leave with a sideways speed of 51 %, 30 % and 9.4 % of the impact speed at refinements
1, 2 and 3; the mortar interface keeps it below 1e-8 (``vy_left``, ``vy_right``;
docs/explanation/mortar.md).

The step is the dilatational wave's transit time Δx/c across the shortest element edge. A
node that closes is stopped by the position correction and the velocity jump (and the
acceleration restarts from the state after it); from the next step on, while it stays
pressed, it carries a smooth contact force λ in the generalized-α Newton
(``fecontact/time/smooth_contact.py``), so the elastic forces of every step see the contact
zone as it is. Measured with node-to-surface contact at refinements 3
(``benchmarks/smooth_contact.py``): energy excess
during contact +0.002 % of the impact kinetic energy at Δx/c, +0.54 % at 4 Δx/c; exit speed
within 0.003 % of the run at Δx/16c. With ``smooth_contact="off"`` (corrections and
jumps alone) the nodes move into the other disk in every smooth step and are projected back,
the disks compress too far, and the excess is second order in the Courant number h c/Δx:
+0.27 % at Δx/16c, +7.1 % at Δx/4c, +137 % at Δx/c.

With an ``offset`` between the centres the impact is oblique, and with ``friction`` μ the
pressed nodes carry a smooth tangential force as well (Coulomb's law between the bodies): the
disks leave spinning the same way, and the total momentum still stays zero.

Probes: ``momentum`` (total x-momentum, kg·m/s per m of thickness), ``v_left`` and
``v_right`` (x-velocities of the centres of mass, m/s), ``vy_left`` and ``vy_right`` (their
y-velocities, m/s), ``gap`` (smallest constraint gap, m: a weighted gap for mortar, a
node-to-segment gap for node-to-surface; inf when no row is within the detection margin) and
``contact_force`` (Σ k Λ_j / h, N).
"""

import numpy as np

from fecontact import InputError, Model, Param, Probe, case, run_cli
from fecontact.bodies import Solid
from fecontact.contact import Contact
from fecontact.scenes import DISK, DROP, SOLID, contact_force_probe, solid_material, wave_simulation


@case(DISK, SOLID, DROP)
def build(
    radius, refinements, E, nu, rho, material, restitution, t_end=0.006,
    gap=Param.nonnegative(0.002, "m", "initial distance between the disks"),
    velocity=Param.positive(1.0, "m/s", "speed of each disk toward the other"),
    two_pass=Param.count(
        1, "1: also the right disk's nodes against the left disk (node-to-surface)", 0, 1
    ),
    offset=Param(0.0, "m", "the right disk's centre above the left one's (oblique impact)"),
    friction=Param.nonnegative(0.0, "-", "Coulomb's coefficient mu between the disks"),
    method=Param.choice("mortar", "contact discretization", ("mortar", "node-to-surface")),
):  # fmt: skip
    mat = solid_material(material, E, nu, rho)
    x0 = radius + 0.5 * gap
    left = Solid.disk([-x0, -0.5 * offset], radius, refinements, mat)
    right = Solid.disk([x0, 0.5 * offset], radius, refinements, mat)
    options = dict(restitution=restitution, friction=friction, method=method)
    pairs = [Contact(left, right, **options)]
    if two_pass:  # (a mortar interface declared both ways is one interface)
        pairs.append(Contact(right, left, **options))
    model = Model([left, right], pairs, gravity=(0.0, 0.0))
    if (start := float(np.min(model.contacts.gaps(np.zeros(model.n))))) < 0.0:
        # the vertex rows of a mortar interface on a coarse boundary read less than the true
        # distance (docs/explanation/mortar.md, stand-off): disks placed closer start inside
        raise InputError(
            f"gap: {gap:g} m starts the disks' {method} contact at {start:.3g} m on this mesh "
            "(below its stand-off); use a larger gap, more refinements or node-to-surface"
        )
    w = left.mass_matrix() @ left.translation_field((1.0, 0.0))  # x-momentum weights
    wy = left.mass_matrix() @ left.translation_field((0.0, 1.0))
    s0, s1 = model.body_slice(0), model.body_slice(1)
    probes = {
        "momentum": Probe(
            lambda m, st: float(w @ st.v[s0] + w @ st.v[s1]), "kg m/s", "total x-momentum"
        ),
        "v_left": Probe(lambda m, st: float(w @ st.v[s0]) / left.mass, "m/s", "left disk vx"),
        "v_right": Probe(lambda m, st: float(w @ st.v[s1]) / right.mass, "m/s", "right disk vx"),
        "vy_left": Probe(lambda m, st: float(wy @ st.v[s0]) / left.mass, "m/s", "left disk vy"),
        "vy_right": Probe(lambda m, st: float(wy @ st.v[s1]) / right.mass, "m/s", "right disk vy"),
        "gap": Probe(lambda m, st: float(np.min(m.contacts.gaps(st.q))), "m", "smallest gap"),
        "contact_force": contact_force_probe(),
    }
    v0 = model.translation(left, (velocity, 0.0)) + model.translation(right, (-velocity, 0.0))
    return wave_simulation(model, left, "two_disks", t_end, probes, v0)


if __name__ == "__main__":
    run_cli(build)
