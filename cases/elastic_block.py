"""Elastic block on an incline with Coulomb friction (3D, P1 tetrahedra).

A box of ``length`` × ``length`` × ``height`` (``Solid.box``, ``divisions`` cells along its
sides, half as many through its height, six tetrahedra each) rests with its bottom face on a
rigid plane inclined by ``incline`` (degrees), every bottom node a contact node with
Coulomb's ``friction`` μ (the 3D disk cone). The model is written in the incline's frame:
x down the slope, z normal to it, gravity (g sin α, 0, −g cos α). The block starts
unstressed, thrown down the slope at ``velocity``; ``damping`` (s) is a stiffness-
proportional Rayleigh damping that lets the ringing of the sudden load settle.

The motion Coulomb's law gives the centre of mass: with tan α ≤ μ the block holds, its
pressed nodes stuck (once it has settled, they do not move: no creep); with tan α > μ it
slides, and while every pressed node slips down the slope the plane takes μ times along it
what it gives normal to it, v + μ v_n = v₀ + g(sin α − μ cos α) t. Pressed nodes carry a
smooth normal and tangential force in the generalized-α step at the step Δx/c (see
``two_disks``), where the decoupled scheme of corrections and jumps lets a held block creep
down the slope (``benchmarks/smooth_friction.py``).

Probes: ``s`` and ``v`` (distance, m, and speed, m/s, of the centre of mass down the slope),
``vn`` (its velocity normal to the slope, m/s), ``creep`` (the largest distance a bottom
node has moved along the plane since t = 0, m) and ``contact_force`` (N).
"""

import numpy as np

from fecontact import Model, Param, Probe, case, run_cli
from fecontact.bodies import Solid
from fecontact.contact import Contact, Plane
from fecontact.scenes import (
    SOLID,
    centre_of_mass_probes,
    contact_force_probe,
    solid_material,
    wave_simulation,
)


@case(SOLID)
def build(
    E, nu, rho, material="linear",
    incline=Param(20.0, "deg", "slope of the plane", 0.0, 80.0),
    friction=Param.nonnegative(0.5, "-", "Coulomb's coefficient mu at the bottom nodes"),
    velocity=Param(0.0, "m/s", "initial speed along the slope, positive down the slope"),
    length=Param.positive(0.1, "m", "side of the square base"),
    height=Param.positive(0.05, "m", "height of the block"),
    divisions=Param.count(4, "cells along each side of the base (half as many in height)", 2, 40),
    damping=Param.nonnegative(0.0, "s", "stiffness-proportional Rayleigh damping beta"),
    gravity=Param.nonnegative(9.81, "m/s^2", "acceleration of gravity"),
    t_end=Param.positive(0.1, "s", "end time"),
):  # fmt: skip
    alpha = np.radians(incline)
    cells = (divisions, divisions, max(divisions // 2, 1))
    mat = solid_material(material, E, nu, rho)
    block = Solid.box([0.0, 0.0, 0.0], [length, length, height], cells, mat)
    bottom = block.nodes_where(lambda x: x[2] <= 1e-9 * height)
    slope = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * length)
    contact = Contact(block, slope, nodes=bottom, friction=friction)
    g = (gravity * np.sin(alpha), 0.0, -gravity * np.cos(alpha))
    model = Model([block], [contact], g, damping=(0.0, damping))
    probes = _probes(model, block, bottom)
    v0 = model.translation(block, (velocity, 0.0, 0.0))
    return wave_simulation(model, block, "elastic_block", t_end, probes, v0)


def _probes(model, block, bottom):
    along, normal = centre_of_mass_probes(model, block, 0), centre_of_mass_probes(model, block, 2)
    s = model.body_slice(0)
    x0 = block.positions(np.zeros(block.ndof))[bottom, :2]

    def creep(m, st):
        return float(np.linalg.norm(block.positions(st.q[s])[bottom, :2] - x0, axis=1).max())

    return {
        "s": along["x_center"],
        "v": along["vx_center"],
        "vn": normal["vz_center"],
        "creep": Probe(creep, "m", "largest motion of a bottom node along the plane"),
        "contact_force": contact_force_probe(),
    }


if __name__ == "__main__":
    run_cli(build)
