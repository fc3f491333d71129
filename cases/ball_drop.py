"""Elastic ball dropped on a rigid plane (3D, P1 or P2 tetrahedra, linear elastic).

A ball of ``radius`` (scikit-fem's ``MeshTet.init_ball`` refined ``refinements`` times,
boundary nodes on the sphere; with ``element`` = "P2" quadratic isoparametric cells whose
boundary is curved, ``MeshTet2.init_ball``) starts with its lowest point ``drop_height``
above the plane z = 0, falling at ``velocity``, under ``gravity`` (m/s², along −z). Every
boundary node is a contact node against the plane (``NodeContact``, restitution e_N at the
nodes). The material is linear elastic (constant stiffness: the iteration matrix is
factorized once).

For a slow impact the contact follows Hertz's theory (``benchmarks/hertz.py``): duration
t_c = 2.87 (m²/(R E*² v))^{1/5} with E* = E/(1 − ν²) against a rigid plane.

The step is an eighth of the dilatational wave's transit time across the shortest distance
between nodes (the shortest edge; half of it for P2) (see ``disk_drop``: the transient energy
excess during contact, +6 % of the impact kinetic energy here, is +26 % at twice the step).
Sizes: ``refinements`` 2, 3, 4 give 387, 2499 and 18051 dofs with P1; 1, 2, 3 give the same
with P2.

Probes: ``z_center`` and ``vz_center`` (height of the centre of mass, m, and its velocity,
m/s), ``gap`` (lowest point above the plane, m) and ``contact_force`` (Σ k Λ_j / h, N).
"""

from fecontact import (
    Contact,
    IntegratorOptions,
    LinearElastic,
    Model,
    Plane,
    Probe,
    Simulation,
    Solid,
    run_cli,
)
from fecontact.errors import InputError, check_count, check_positive, check_range

PARAMETERS = {
    "radius": ("m", "radius of the ball"),
    "refinements": ("-", "uniform refinements of the ball mesh (8 * 8^n tetrahedra), 0..4"),
    "element": ("-", "P1 (linear tetrahedra) or P2 (quadratic, curved boundary)"),
    "E": ("Pa", "Young's modulus"),
    "nu": ("-", "Poisson's ratio"),
    "rho": ("kg/m^3", "density"),
    "drop_height": ("m", "initial gap between the ball and the plane (>= 0)"),
    "velocity": ("m/s", "initial downward speed (>= 0)"),
    "restitution": ("-", "Newton's coefficient e_N at the contact nodes, in [0, 1]"),
    "gravity": ("m/s^2", "acceleration of gravity, along -z (0: none, as in Hertz's theory)"),
    "rho_inf": ("-", "spectral radius at infinite frequency in [0, 1]"),
    "t_end": ("s", "end time"),
}


def build(
    radius=0.05,
    refinements=2,
    element="P1",
    E=1e7,
    nu=0.3,
    rho=1000.0,
    drop_height=0.002,
    velocity=1.0,
    restitution=0.0,
    gravity=9.81,
    rho_inf=0.5,
    t_end=0.008,
):
    mat = LinearElastic(E=E, nu=nu, rho=rho)
    check_positive("radius", radius)
    check_count("refinements", refinements, 0, 4)
    check_positive("drop_height", drop_height, allow_zero=True)
    check_positive("velocity", velocity, allow_zero=True)
    check_range("restitution", restitution, 0.0, 1.0)
    check_positive("gravity", gravity, allow_zero=True)
    check_positive("t_end", t_end)
    options = IntegratorOptions(rho_inf=rho_inf)
    z0 = radius + drop_height
    if not isinstance(element, str) or element not in ("P1", "P2"):
        raise InputError(f"element must be 'P1' or 'P2', got {element!r}")
    ball = Solid.ball([0.0, 0.0, z0], radius, refinements, mat, element=element)
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * radius)
    contact = Contact(ball, floor, restitution=restitution)
    model = Model([ball], [contact], gravity=(0.0, 0.0, -gravity))
    w = ball.mass_matrix() @ ball.translation_field((0.0, 0.0, 1.0))  # z-momentum weights
    probes = {
        "z_center": Probe(lambda m, st: z0 + w @ st.q / ball.mass, "m", "centre of mass height"),
        "vz_center": Probe(lambda m, st: w @ st.v / ball.mass, "m/s", "centre of mass velocity"),
        "gap": Probe(
            lambda m, st: float(ball.positions(st.q)[:, 2].min()), "m", "lowest point height"
        ),
        "contact_force": Probe(
            lambda m, st: float(st.impulse.sum() / st.h) if st.h > 0 else 0.0,
            "N",
            "plane force k Lambda / h (mean over the step)",
        ),
    }
    params = {k: v for k, v in locals().items() if k in PARAMETERS}
    spacing = ball.min_edge_length / (2.0 if element == "P2" else 1.0)
    dt = 0.125 * spacing / mat.wave_speed
    return Simulation(
        model,
        dt=dt,
        t_end=t_end,
        probes=probes,
        options=options,
        output_interval=t_end / 40,
        name="ball_drop",
        parameters=params,
        v0=model.translation(ball, (0.0, 0.0, -velocity)),
    )


if __name__ == "__main__":
    run_cli(build)
