"""Bouncing ball: a rigid disk dropped on a rigid plane, Newton's impact law.

The ball is a ``RigidBody2D`` with a ``Disk`` shape (uniform, I = m r²/2) whose lowest point
starts ``height`` above the plane y = 0, at rest. It falls under gravity and bounces with
restitution e: impacts at t₁ = √(2h₀/g), t_{k+1} = t_k + 2eᵏt₁, apex heights e^{2k} h₀, and
after the accumulation time t₁(1 + e)/(1 − e) it rests on the plane (DESIGN §8). The contact
acts on the centre: gap = y_c − r. Rotation is free but never excited (no friction).
"""

from fecontact import Contact, Model, Plane, Probe, Simulation, run_cli
from fecontact.bodies.rigid import Disk, RigidBody2D
from fecontact.errors import check_positive, check_range

PARAMETERS = {
    "height": ("m", "initial gap between the ball and the plane (0: resting on it)"),
    "restitution": ("-", "Newton's coefficient of restitution e_N in [0, 1]"),
    "mass": ("kg", "mass of the ball"),
    "radius": ("m", "radius of the ball"),
    "gravity": ("m/s^2", "acceleration of gravity (>= 0), along -y"),
}


def build(height=1.0, restitution=0.8, mass=1.0, radius=0.1, gravity=9.81):
    check_positive("height", height, allow_zero=True)
    check_range("restitution", restitution, 0.0, 1.0)
    check_positive("mass", mass)
    check_positive("radius", radius)
    check_positive("gravity", gravity, allow_zero=True)
    shape = Disk(radius)
    ball = RigidBody2D.uniform(mass, [0.0, radius + height], shape)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([ball], [Contact(ball, floor, restitution=restitution)], (0.0, -gravity))
    y0 = ball.position[1] - shape.radius
    probes = {
        "gap": Probe(lambda m, st: y0 + st.q[1], "m", "gap between the ball and the plane"),
        "vy": Probe(lambda m, st: st.v[1], "m/s", "vertical velocity of the ball"),
    }
    params = {k: v for k, v in locals().items() if k in PARAMETERS}
    return Simulation(
        model, dt=1e-3, t_end=5.0, probes=probes, name="bouncing_ball", parameters=params
    )


if __name__ == "__main__":
    run_cli(build)
