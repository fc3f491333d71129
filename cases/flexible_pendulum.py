"""Flexible pendulum released horizontally, stopped by a rigid stop at (0, -0.3).

An aluminium strip pinned at the origin, lying along +x at t = 0 with a 0.14 kg mass at its
tip, falls under gravity. Its tip hits a rigid stop, the plane x = 0 through (0, -0.3)
(normal +x), and the beam rings at its first bending frequency.
"""

from fecontact import (
    Beam2D,
    Contact,
    IntegratorOptions,
    Material,
    Model,
    Plane,
    Section,
    Simulation,
    check_count,
    check_positive,
    check_range,
    node_probe,
    run_cli,
)

PARAMETERS = {
    "length": ("m", "beam length"),
    "n_elements": ("-", "number of beam elements"),
    "E": ("Pa", "Young's modulus"),
    "rho": ("kg/m^3", "density"),
    "nu": ("-", "Poisson's ratio"),
    "width": ("m", "section width"),
    "thickness": ("m", "section thickness (bending)"),
    "tip_mass": ("kg", "point mass on the tip node"),
    "restitution": ("-", "Newton's coefficient of restitution e_N in [0, 1]"),
    "gravity": ("m/s^2", "acceleration of gravity, along -y"),
    "rho_inf": ("-", "spectral radius at infinite frequency in [0, 1]"),
    "penalty_scale": ("-", "factor on the automatic augmentation parameter p"),
    "multiplier_scale": ("-", "factor on the multiplier scaling k"),
}


def build(
    length=0.3,
    n_elements=4,
    E=70e9,
    rho=2700.0,
    nu=0.33,
    width=0.02,
    thickness=0.002,
    tip_mass=0.14,
    restitution=0.0,
    gravity=9.81,
    rho_inf=0.5,
    penalty_scale=1.0,
    multiplier_scale=1.0,
):
    material = Material(E=E, rho=rho, nu=nu)
    section = Section.rectangle(width, thickness)
    check_positive("length", length)
    check_count("n_elements", n_elements)
    check_positive("tip_mass", tip_mass, allow_zero=True)
    check_range("restitution", restitution, 0.0, 1.0)
    check_positive("gravity", gravity, allow_zero=True)
    options = IntegratorOptions(
        rho_inf=rho_inf, penalty_scale=penalty_scale, multiplier_scale=multiplier_scale
    )
    beam = Beam2D.straight([0.0, 0.0], [length, 0.0], n_elements, material, section)
    beam.pin(0).add_mass(-1, tip_mass)
    wall = Plane([0.0, -0.3], [1.0, 0.0], extent=0.08)
    stop = Contact(beam, wall, nodes=[-1], restitution=restitution)
    model = Model([beam], [stop], gravity=(0.0, -gravity))
    probes = {f"tip_{q}": node_probe(model, beam, -1, q) for q in ("x", "y", "vx", "vy")}
    params = dict(locals())
    params = {k: params[k] for k in PARAMETERS}
    return Simulation(
        model,
        dt=1e-3,
        t_end=1.5,
        probes=probes,
        options=options,
        name="flexible_pendulum",
        parameters=params,
    )


if __name__ == "__main__":
    run_cli(build)
