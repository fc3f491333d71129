"""Rolling disk: a uniform rigid disk thrown along a horizontal plane with Coulomb friction.

The disk (``RigidBody2D`` with a ``Disk``, I = mR²/2) starts touching the plane y = 0
(gap 0), moving along +x at ``velocity`` with angular velocity ``spin`` (rad/s,
counter-clockwise; positive spin is backspin for a disk moving along +x). Its contact point
slips at v + ωR, so friction μ = ``friction`` decelerates it and turns it: v = v₀ − μgt,
ω = ω₀ − 2μgt/R, until the slip stops at t* = (v₀ + ω₀R)/(3μg); from then on it rolls at
v = (2v₀ − ω₀R)/3 (backwards when ω₀R > 2v₀), ω = −v/R.

Probes: ``x`` (m) and ``vx`` (m/s) of the centre, ``omega`` (rad/s, counter-clockwise) and
``slip``, the slip speed v + ωR of the contact point (m/s).
"""

from fecontact import Model, Param, Probe, Simulation, case, run_cli
from fecontact.bodies import Disk, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)
def build(
    radius=Param.positive(0.1, "m", "disk radius"),
    mass=Param.positive(1.0, "kg", "disk mass (uniform)"),
    velocity=Param(2.0, "m/s", "initial speed of the centre along +x"),
    spin=Param(0.0, "rad/s", "initial angular velocity, counter-clockwise (backspin > 0)"),
    friction=0.3,
    gravity=9.81,
):
    disk = RigidBody2D.uniform(mass, (0.0, radius), Disk(radius))
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    contact = Contact(disk, floor, restitution=0.0, friction=friction)
    model = Model([disk], [contact], (0.0, -gravity))
    probes = {
        "x": Probe(lambda m, st: float(st.q[0]), "m", "centre position"),
        "vx": Probe(lambda m, st: float(st.v[0]), "m/s", "centre velocity"),
        "omega": Probe(lambda m, st: float(st.v[2]), "rad/s", "angular velocity"),
        "slip": Probe(
            lambda m, st: float(st.v[0] + st.v[2] * radius), "m/s", "slip of the contact point"
        ),
    }
    return Simulation(
        model,
        dt=1e-3,
        t_end=1.0,
        probes=probes,
        v0=disk.velocity(velocity, 0.0, spin),
        name="rolling_disk",
    )


if __name__ == "__main__":
    run_cli(build)
