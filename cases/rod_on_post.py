"""Steel rod swung horizontally onto a vertical post: a 3D beam striking a rigid body between
its nodes.

A straight rod of circular section (``Beam3D``, pinned at its root, the origin) starts along
+x, horizontal, turning about the vertical at ``spin`` (rad/s) under gravity (−z), so that it
sweeps round while it falls. A post, a held ``RigidBody3D`` ``Capsule`` standing along z (radius
``post_radius``, from ``post_bottom`` up to ``post_top``, its axis at ``post_distance`` from the
root in the direction ``post_azimuth`` from +x), is in its way. The rod touches the post through
its section's surface: each segment's closest point to the post's axis
(:class:`fecontact.contact.beam3d_pairs.TubeRigidContact`), so the post strikes the rod between
its nodes, where node contact would let it through (a chord of the tube misses a post thinner
than an element).

Probes: ``tip_x``, ``tip_y``, ``tip_z`` (the free end's centreline, m), ``tip_vt`` (its speed
about the vertical, m/s, positive in the sense of the spin) and ``post_force`` (the contact
force on the rod, Σ k Λ_j / h, N).
"""

import numpy as np

from fecontact import InputError, Model, Param, Probe, Simulation, case, node_probe, run_cli
from fecontact.bodies import Beam3D, Material, RigidBody3D, Section
from fecontact.bodies.shapes3d import Capsule
from fecontact.contact import Contact
from fecontact.scenes import ROD, contact_force_probe


@case(ROD)  # a steel rod
def build(
    length=0.5, radius=0.005, n_elements=10, E=210e9, nu=0.3, rho=7850.0,
    spin=Param(10.0, "rad/s", "initial rate of turn of the rod about the vertical"),
    post_distance=Param.positive(0.325, "m", "distance of the post's axis from the root"),
    post_azimuth=Param(60.0, "deg", "direction of the post from +x, about +z"),
    post_radius=Param.positive(0.02, "m", "radius of the post"),
    post_bottom=Param(-0.5, "m", "height of the post's lower cap centre"),
    post_top=Param(0.2, "m", "height of the post's upper cap centre"),
    restitution=Param.fraction(0.0, "Newton's coefficient of restitution e_N"),
):  # fmt: skip
    if not post_top > post_bottom:
        raise InputError(f"post_top must lie above post_bottom ({post_bottom} m), got {post_top}")
    _check_post_clear(length, radius, post_distance, post_azimuth, post_radius,
                      (post_bottom, post_top))  # fmt: skip
    material = Material(E, nu=nu, rho=rho)
    rod = Beam3D.straight([0, 0, 0], [length, 0, 0], n_elements, material, Section.circle(radius))
    rod.pin(0)
    a = np.radians(post_azimuth)
    centre = [post_distance * np.cos(a), post_distance * np.sin(a), 0.5 * (post_bottom + post_top)]
    post = RigidBody3D.uniform(1.0, centre, Capsule(post_radius, post_top - post_bottom)).fix()
    hit = Contact(rod, post, restitution=restitution, clearance=radius)
    model = Model([rod, post], [hit], gravity=(0.0, 0.0, -9.81))
    tip = rod.n_nodes - 1

    def tangential(m, st):
        x = rod.positions(st.q[: rod.ndof])[tip]
        v = st.v[: rod.ndof].reshape(-1, 6)[tip, :3]
        return float((x[0] * v[1] - x[1] * v[0]) / max(np.hypot(x[0], x[1]), 1e-12))

    probes = {
        "tip_x": node_probe(model, rod, tip, "x"),
        "tip_y": node_probe(model, rod, tip, "y"),
        "tip_z": node_probe(model, rod, tip, "z"),
        "tip_vt": Probe(tangential, "m/s", "tip speed about the vertical, in the sense of spin"),
        "post_force": contact_force_probe("contact force of the post on the rod"),
    }
    # a rigid turn ω = spin e_z about the root
    omega = np.array([0.0, 0.0, spin])
    v0 = np.zeros((rod.n_nodes, 6))
    v0[:, :3] = np.cross(omega, rod.X)
    v0[:, 3:] = omega
    v = np.concatenate([v0.ravel(), np.zeros(6)])
    return Simulation(model, dt=1e-4, t_end=0.3, probes=probes, name="rod_on_post", v0=v)


def _check_post_clear(length, radius, distance, azimuth, post_radius, heights) -> None:
    """The post must start clear of the rod: the closest points of the rod's axis (x in
    [0, length] at z = 0) and of the post's axis (vertical, z in ``heights``) lie farther
    apart than post_radius + radius."""
    a = np.radians(azimuth)
    foot = distance * np.array([np.cos(a), np.sin(a)])
    x = np.clip(foot[0], 0.0, length)
    z = np.clip(0.0, *heights)
    apart = float(np.sqrt((foot[0] - x) ** 2 + foot[1] ** 2 + z**2))
    if apart <= post_radius + radius:
        raise InputError(
            f"post_distance, post_azimuth, post_radius: the post's axis starts {apart:.4g} m "
            f"from the rod's, within post_radius + rod radius = {post_radius + radius:.4g} m "
            "(the post would start inside the rod); move the post or make it thinner"
        )


if __name__ == "__main__":
    run_cli(build)
