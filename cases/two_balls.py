"""Two identical elastic balls colliding head-on (3D, linear elastic, no gravity).

Two balls of ``radius`` on the x axis, ``gap`` × ``radius`` apart, move toward each other at
``velocity`` each. Their meshes are graded toward the point of first contact (``graded_ball_mesh``:
scikit-fem's ball refined ``base`` times, then cells of ``spacing`` × ``radius`` at that
point, growing by ``grading`` times the distance from it); with ``graded=0`` the ball refined
``base`` times, uniform. ``element``: P1, or P2 (quadratic cells with a curved boundary).
The right ball's mesh is the left one's turned half a turn about the z axis (its nodes meet
the left ball's node on node), then by ``rotate`` degrees about the x axis (the impact
axis), so that no node meets a node. With ``against="plane"`` the right ball is replaced by
the rigid plane of symmetry x = 0.

The contact is one dual mortar interface (``method="mortar"``: weighted gaps over the left
ball's boundary triangles, :mod:`fecontact.contact.mortar3d`), or node-to-surface both ways
(``"node-to-surface"``). By symmetry each ball meets the other exactly as it would meet a
rigid plane at x = 0 at ``velocity``: no sideways motion, the same rebound (compare with
``against="plane"``, ``benchmarks/mortar.py``).

The step is the dilatational wave's transit time Δx/c across the shortest distance between
nodes (the shortest edge; half of it for P2).

Probes: each ball's centre-of-mass velocity ``vx_left``, ``vy_left``, ``vz_left``,
``vx_right``, ... (m/s), ``gap`` (smallest contact gap, m) and ``contact_force`` (N).
"""

import dataclasses

import numpy as np

from fecontact import InputError, Model, Param, case, run_cli
from fecontact.bodies import LinearElastic, Solid
from fecontact.bodies.meshes import ball_mesh, graded_ball_mesh
from fecontact.contact import Contact, Plane
from fecontact.scenes import SOLID, centre_of_mass_probes, contact_force_probe, wave_simulation


def _turned(mesh, angle_x: float):
    """The mesh turned half a turn about z, then by ``angle_x`` (rad) about x."""
    c, s = np.cos(angle_x), np.sin(angle_x)
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ np.diag([-1.0, -1.0, 1.0])
    return dataclasses.replace(mesh, doflocs=R @ mesh.doflocs)


@case
def build(
    radius=Param.positive(0.05, "m", "radius of each ball"),
    spacing=Param.positive(0.08, "-", "cell size at the point of first contact / radius"),
    grading=Param.nonnegative(0.5, "-", "growth of the cell size with the distance from it"),
    base=Param.count(2, "refinements of the ball mesh (before the grading)", 1, 4),
    graded=Param.count(1, "1: graded toward the contact; 0: init_ball refined base times", 0, 1),
    element=Param.choice("P1", "linear or quadratic tetrahedra", ("P1", "P2")),
    E=SOLID["E"],
    nu=SOLID["nu"],
    rho=SOLID["rho"],
    velocity=Param.positive(1.0, "m/s", "speed of each ball toward the other"),
    gap=Param.nonnegative(0.004, "-", "initial distance between the balls / radius"),
    rotate=Param(30.0, "deg", "the right ball's mesh turned about the impact axis"),
    method=Param.choice("mortar", "contact discretization", ("mortar", "node-to-surface")),
    against=Param.choice(
        "ball", "the right body: the ball, or the rigid plane x = 0", ("ball", "plane")
    ),
    restitution=Param.fraction(0.0, "Newton's e_N at the contact"),
    t_end=Param.positive(0.008, "s", "end time (the contact lasts about 6.2 ms)"),
):  # fmt: skip
    mat = LinearElastic(E=E, nu=nu, rho=rho)
    x0 = radius * (1.0 + 0.5 * gap)
    toward = [-0.5 * gap * radius, 0.0, 0.0]
    if graded:
        mesh = graded_ball_mesh([-x0, 0.0, 0.0], radius, spacing * radius, toward, grading, base,
                                quadratic=element == "P2")  # fmt: skip
    else:
        mesh = ball_mesh([-x0, 0.0, 0.0], radius, base, quadratic=element == "P2")
    left = Solid(mesh, mat, element=element)
    if against == "plane":  # the plane of symmetry: each ball's rigid partner
        plane = Plane([0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], extent=4.0 * radius)
        model = Model([left], [Contact(left, plane, restitution=restitution)], (0.0, 0.0, 0.0))
        bodies = ((left, "left"),)
    else:
        right = Solid(_turned(mesh, np.radians(rotate)), mat, element=element)
        pairs = [Contact(left, right, restitution=restitution, method=method)]
        if method == "node-to-surface":
            pairs.append(Contact(right, left, restitution=restitution, method=method))
        model = Model([left, right], pairs, gravity=(0.0, 0.0, 0.0))
        bodies = ((left, "left"), (right, "right"))
        start = float(np.min(model.contacts.gaps(np.zeros(model.n))))
        if start < -1e-12 * radius:  # (round-off of a node-to-surface gap at gap = 0 admitted)
            # the rows of a mortar interface between faceted spheres read less than the true
            # distance near the pole (its stand-off): balls placed closer start inside
            raise InputError(
                f"gap: {gap:g} radii start the balls' {method} contact at {start:.3g} m on "
                "these meshes (inside); give a larger gap or a finer spacing"
            )
    probes = {}
    for body, name in bodies:
        for axis in range(3):
            probes |= {
                k: p
                for k, p in centre_of_mass_probes(model, body, axis, name=name).items()
                if k.startswith("v")
            }
    probes["gap"] = _gap_probe()
    probes["contact_force"] = contact_force_probe()
    spacing_nodes = left.min_edge_length / (2.0 if element == "P2" else 1.0)
    v0 = model.translation(left, (velocity, 0.0, 0.0))
    if against == "ball":
        v0 += model.translation(right, (-velocity, 0.0, 0.0))
    return wave_simulation(model, left, "two_balls", t_end, probes, v0, spacing_nodes, frames=20)


def _gap_probe():
    from fecontact import Probe

    return Probe(lambda m, st: float(np.min(m.contacts.gaps(st.q))), "m", "smallest gap")


if __name__ == "__main__":
    run_cli(build)
