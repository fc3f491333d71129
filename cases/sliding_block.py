"""Sliding block: a rigid box on an incline with Coulomb friction.

A uniform box (``RigidBody2D`` with ``Polygon.box``) rests with its bottom face on the plane
through the origin inclined by ``incline`` (degrees, descending toward +x), and starts with
``velocity`` along the slope (m/s, positive down the slope). Both bottom corners carry Coulomb
friction μ = ``friction``. The exact motion (as long as the box does not tip, which holds for
the default proportions): it sticks at rest when tan α ≤ μ; otherwise it slides down with
a = g(sin α − μ cos α). Thrown down with tan α < μ, it stops after v₀²/(2g(μ cos α − sin α));
thrown up, after v₀²/(2g(sin α + μ cos α)).

Probes: ``s``, the distance travelled down the slope (m), and ``v``, the speed down the
slope (m/s).
"""

import numpy as np

from fecontact import Model, Param, Probe, Simulation, case, run_cli
from fecontact.bodies import Polygon, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)
def build(
    incline=Param(20.0, "deg", "slope of the plane, descending toward +x", 0.0, 80.0),
    friction=0.5,
    velocity=Param(0.0, "m/s", "initial speed along the slope, positive down the slope"),
    width=Param.positive(0.2, "m", "box width along the slope"),
    height=Param.positive(0.1, "m", "box height"),
    mass=Param.positive(1.0, "kg", "box mass (uniform density)"),
    gravity=9.81,
):
    alpha = np.radians(incline)
    down = np.array([np.cos(alpha), -np.sin(alpha)])  # unit vector down the slope
    normal = np.array([np.sin(alpha), np.cos(alpha)])
    shape = Polygon.box(width, height)
    # the bottom face on the plane: the box turned by −α, its centre half a height above
    block = RigidBody2D.uniform(mass, 0.5 * height * normal, shape, angle=-alpha)
    v0 = velocity * down
    slope = Plane([0.0, 0.0], normal)
    contact = Contact(block, slope, restitution=0.0, friction=friction)
    model = Model([block], [contact], (0.0, -gravity))
    probes = {
        "s": Probe(lambda m, st: float(st.q[:2] @ down), "m", "distance down the slope"),
        "v": Probe(lambda m, st: float(st.v[:2] @ down), "m/s", "speed down the slope"),
    }
    return Simulation(
        model,
        dt=1e-3,
        t_end=1.0,
        probes=probes,
        v0=block.velocity(*v0),
        name="sliding_block",
    )


if __name__ == "__main__":
    run_cli(build)
