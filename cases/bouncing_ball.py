"""Bouncing ball: a rigid disk dropped on a rigid plane, Newton's impact law.

The ball is a ``RigidBody2D`` with a ``Disk`` shape (uniform, I = m r²/2) whose lowest point
starts ``height`` above the plane y = 0, at rest. It falls under gravity and bounces with
restitution e: impacts at t₁ = √(2h₀/g), t_{k+1} = t_k + 2eᵏt₁, apex heights e^{2k} h₀, and
after the accumulation time t₁(1 + e)/(1 − e) it rests on the plane. The contact
acts on the centre: gap = y_c − r. Rotation is free but never excited (no friction).
"""

from fecontact import Model, Param, Probe, Simulation, case, run_cli
from fecontact.bodies import Disk, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.scenes import GRAVITY, IMPACT


@case(IMPACT, GRAVITY)
def build(
    height=Param.nonnegative(1.0, "m", "initial gap between the ball and the plane"),
    restitution=0.8,
    mass=Param.positive(1.0, "kg", "mass of the ball"),
    radius=Param.positive(0.1, "m", "radius of the ball"),
    gravity=9.81,
):
    shape = Disk(radius)
    ball = RigidBody2D.uniform(mass, [0.0, radius + height], shape)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([ball], [Contact(ball, floor, restitution=restitution)], (0.0, -gravity))
    y0 = ball.position[1] - shape.radius
    probes = {
        "gap": Probe(lambda m, st: y0 + st.q[1], "m", "gap between the ball and the plane"),
        "vy": Probe(lambda m, st: st.v[1], "m/s", "vertical velocity of the ball"),
    }
    return Simulation(model, dt=1e-3, t_end=5.0, probes=probes, name="bouncing_ball")


if __name__ == "__main__":
    run_cli(build)
