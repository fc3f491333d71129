"""Rigid pendulum released horizontally against a stop at the vertical.

A uniform rigid bar of ``length`` L and ``mass`` m is pinned at the origin (a ``Pin`` joint:
a bilateral constraint enforced at position and velocity level), released at rest along +x,
and swings down under gravity until its free end hits a stop: the plane x = 0 acting on the
free end. A uniform bar is a physical pendulum with ω₀² = 3g/(2L), so the exact first impact
is at K(sin 45°)/ω₀ and, after an impact with restitution e, the amplitude obeys
1 − cos θ_{k+1} = e²(1 − cos θ_k) with impacts 2K(sin(θ_k/2))/ω₀ apart.

Probes: ``theta`` (rad) measured from the downward vertical, positive on the free side (+x),
and ``omega`` = dθ/dt (rad/s).
"""

import numpy as np

from fecontact import Model, Param, Pin, Probe, Simulation, case, run_cli
from fecontact.bodies import Polygon, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)
def build(
    length=Param.positive(1.0, "m", "length of the bar"),
    mass=Param.positive(1.0, "kg", "mass of the bar"),
    restitution=0.5, gravity=9.81,
):  # fmt: skip
    L = length
    # the bar is a line (I = mL²/12 about its centre); a thin diamond with a vertex at each
    # end gives it a contact point on its axis and an outline to draw
    w = 0.02 * L
    diamond = Polygon([[-L / 2, 0.0], [0.0, -w / 2], [L / 2, 0.0], [0.0, w / 2]])
    bar = RigidBody2D(mass, mass * L**2 / 12.0, [L / 2, 0.0], shape=diamond)
    wall = Plane([0.0, -L], [1.0, 0.0], extent=0.2 * L)
    stop = Contact(bar, wall, nodes=[2], restitution=restitution)
    model = Model([bar], [stop], gravity=(0.0, -gravity), joints=[Pin(bar, [0.0, 0.0])])
    probes = {
        "theta": Probe(
            lambda m, st: float(np.pi / 2 + st.q[2]), "rad", "angle from the downward vertical"
        ),
        "omega": Probe(lambda m, st: float(st.v[2]), "rad/s", "angular velocity"),
    }
    return Simulation(model, dt=1e-3, t_end=3.0, probes=probes, name="rigid_pendulum")


if __name__ == "__main__":
    run_cli(build)
