"""Elastic ball dropped on an elastic slab clamped at its base (3D, linear elastic).

A ball of ``radius`` (scikit-fem's ball refined ``refinements`` times, boundary nodes on the
sphere; P1 or P2 tetrahedra) starts with its lowest point ``drop_height`` above the top face of
a slab of ``width`` × ``width`` × ``thickness`` (``Solid.box``, ``divisions`` cells along its
sides, ``layers`` through its thickness, six tetrahedra each) whose bottom face is clamped. The
ball falls at ``velocity`` under ``gravity`` (m/s², along −z). Both bodies are linear elastic
of the same material.

The contact is node-to-surface both ways (the ball's boundary nodes against the slab's
boundary, and the slab's top nodes against the ball's), or one dual mortar interface
(``method="mortar"``: weighted gaps over the ball's boundary triangles).

The step is the dilatational wave's transit time Δx/c across the shortest distance between
the ball's nodes (the smaller body's; its shortest edge, half of it for P2).

Probes: ``z_center`` and ``vz_center`` (height of the ball's centre of mass above its start, m,
and its velocity, m/s), ``contact_force`` (N), ``gap`` (smallest contact gap, m) and
``penetration`` (the deepest boundary node of either body inside the other's discretized
boundary, m, by the inside/outside test of :mod:`fecontact.contact.inside` alone).
"""

import numpy as np

from fecontact import Model, Param, Probe, case, run_cli
from fecontact.bodies import LinearElastic, Solid
from fecontact.contact import Contact
from fecontact.contact.inside import Surface
from fecontact.scenes import (
    DROP,
    SOLID,
    centre_of_mass_probes,
    contact_force_probe,
    wave_simulation,
)


@case(DROP)
def build(
    drop_height, velocity, restitution,
    radius=Param.positive(0.05, "m", "radius of the ball"),
    refinements=Param.count(2, "uniform refinements of the ball mesh (8 * 8^n tetrahedra)", 0, 4),
    element=Param.choice("P1", "linear or quadratic tetrahedra (both bodies)", ("P1", "P2")),
    width=Param.positive(0.2, "m", "side of the slab's square top face"),
    thickness=Param.positive(0.04, "m", "thickness of the slab"),
    divisions=Param.count(10, "cells along each side of the slab", 1, 60),
    layers=Param.count(2, "cells through the slab's thickness", 1, 20),
    E=SOLID["E"],
    nu=SOLID["nu"],
    rho=SOLID["rho"],
    gravity=Param.nonnegative(9.81, "m/s^2", "acceleration of gravity, along -z"),
    method=Param.choice("mortar", "contact discretization", ("mortar", "node-to-surface")),
    passes=Param.count(2, "node-to-surface: 1 (the ball's nodes only) or 2 (both ways)", 1, 2),
    t_end=DROP["t_end"],
):  # fmt: skip
    mat = LinearElastic(E=E, nu=nu, rho=rho)
    half = 0.5 * width
    lower, upper = [-half, -half, -thickness], [half, half, 0.0]
    slab = Solid.box(lower, upper, (divisions, divisions, layers), mat, element=element)
    slab.fix(slab.nodes_where(lambda x: x[2] <= -thickness * (1.0 - 1e-9)))
    z0 = radius + drop_height
    ball = Solid.ball([0.0, 0.0, z0], radius, refinements, mat, element=element)
    pairs = [Contact(ball, slab, restitution=restitution, method=method)]
    if method == "node-to-surface" and passes == 2:
        top = slab.nodes_where(lambda x: x[2] >= -1e-9 * thickness)
        pairs.append(Contact(slab, ball, nodes=top, restitution=restitution, method=method))
    model = Model([ball, slab], pairs, (0.0, 0.0, -gravity))
    probes = centre_of_mass_probes(model, ball, 2, z0)
    probes |= {
        "contact_force": contact_force_probe(),
        "gap": Probe(lambda m, st: float(np.min(m.contacts.gaps(st.q))), "m", "smallest gap"),
        "penetration": _penetration_probe(model, ball, slab),
    }
    spacing = ball.min_edge_length / (2.0 if element == "P2" else 1.0)
    v0 = model.translation(ball, (0.0, 0.0, -velocity))
    return wave_simulation(model, ball, "ball_on_slab", t_end, probes, v0, spacing)


def _penetration_probe(model, ball, slab):
    """The deepest boundary node of either body inside the other's discretized boundary (m),
    by the inside/outside test alone (not the contact's gaps)."""
    surfaces = [Surface(body.contact_facets()) for body in (ball, slab)]
    nodes = [np.unique(body.contact_facets()) for body in (ball, slab)]

    def depth(m, st):
        x = [body.positions(st.q[m.body_slice(i)]) for i, body in enumerate((ball, slab))]
        return max(
            float(np.max(surfaces[1 - i].depths(x[1 - i], x[i][nodes[i]]), initial=0.0))
            for i in (0, 1)
        )

    return Probe(depth, "m", "deepest boundary node inside the other body")


if __name__ == "__main__":
    run_cli(build)
