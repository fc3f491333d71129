"""Kane's double pendulum: two rigid bars on pins whose free end strikes a rough floor.

Two uniform bars of ``length`` L and ``mass`` m (thin lines, I = mL²/12): the first is
pinned to the ground at O = (0, ``height``) and to the second at its other end (``Pin``
joints). Released at rest with the first bar at ``angle1`` and the second at ``angle2``
(degrees, counter-clockwise from +x), they fall under gravity until the free end of the second
bar strikes the floor y = 0, with restitution e_N and Coulomb friction μ: the configuration
with which Kane & Levinson (1985) showed that Newton's kinematic restitution with friction
can raise the energy (Glocker, Multibody Syst. Dyn., 2013, Parts I and II). At the strike
the normal and tangential motions of the contact point couple: the end's slip stops and the
end sticks while the normal impulse pushes it back. With Newton's law and e_N = 1, μ = 0.5
the run ends 1.13 J above its start, made by the kinematic restitution (friction takes
0.028 J); with ``--set impact_law=poisson`` the impact loses energy.

Probes: ``tip_x``, ``tip_y`` (m) of the striking end, and ``energy`` (J), the total
mechanical energy T + V_gravity.
"""

import numpy as np

from fecontact import InputError, Model, Param, Pin, Probe, Simulation, case, run_cli
from fecontact.bodies import Polygon, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)  # at the floor; gravity along -y
def build(
    length=Param.positive(1.0, "m", "length of each bar"),
    mass=Param.positive(1.0, "kg", "mass of each bar"),
    height=Param.positive(1.5, "m", "height of the ground pin above the floor"),
    angle1=Param(10.0, "deg", "initial angle of the pinned bar, from +x", -360.0, 360.0),
    angle2=Param(-135.0, "deg", "initial angle of the striking bar, from +x", -360.0, 360.0),
    restitution=1.0, friction=0.5, gravity=9.81,
):  # fmt: skip
    L, m = length, mass
    angle1, angle2 = np.radians(angle1), np.radians(angle2)
    w = 0.02 * L  # a thin diamond: a vertex at each end of the bar's axis
    diamond = Polygon([[-L / 2, 0.0], [0.0, -w / 2], [L / 2, 0.0], [0.0, w / 2]])
    O = np.array([0.0, height])
    d1 = np.array([np.cos(angle1), np.sin(angle1)])
    d2 = np.array([np.cos(angle2), np.sin(angle2)])
    J = O + L * d1
    tip = J + L * d2
    if tip[1] <= 0.0:
        raise InputError(
            f"height: the free end starts at y = {tip[1]:.4g} m, on or below the floor; "
            f"give a height above {height - tip[1]:.4g} m for these angles and length"
        )
    upper = RigidBody2D(m, m * L**2 / 12.0, O + 0.5 * L * d1, angle=angle1, shape=diamond)
    lower = RigidBody2D(m, m * L**2 / 12.0, J + 0.5 * L * d2, angle=angle2, shape=diamond)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    strike = Contact(lower, floor, nodes=[2], restitution=restitution, friction=friction)
    model = Model(
        [upper, lower],
        [strike],
        gravity=(0.0, -gravity),
        joints=[Pin(upper, O), Pin(upper, J, lower)],
    )

    o = model.offset_of(lower)

    def end(st):  # the centre c₀ + u and the axis at φ₀ + θ of the striking bar
        phi = angle2 + st.q[o + 2]
        return lower.position + st.q[o : o + 2] + 0.5 * L * np.array([np.cos(phi), np.sin(phi)])

    probes = {
        "tip_x": Probe(lambda m_, st: float(end(st)[0]), "m", "striking end, x"),
        "tip_y": Probe(lambda m_, st: float(end(st)[1]), "m", "striking end, y"),
        "energy": Probe(
            lambda m_, st: float(m_.kinetic_energy(st.v) + m_.potential_energy(st.q)),
            "J",
            "kinetic plus gravity energy",
        ),
    }
    # h = 2.5e-4 s: the smooth steps of the chain after the strike then move its energy by
    # under 1e-6 of the peak kinetic energy (5.9e-6 J; 2e-4 J at h = 1e-3 s, rho_inf = 0)
    return Simulation(model, dt=2.5e-4, t_end=1.0, probes=probes, name="kane_chain")


if __name__ == "__main__":
    run_cli(build)
