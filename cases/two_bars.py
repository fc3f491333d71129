"""Two identical elastic bars end to end on one axis: the striker hits the target at rest.

Two straight ``Beam2D`` bars (axial behaviour only, no gravity) lie on the x axis: the striker
from x = −gap − length to x = −gap moves at ``velocity`` toward the target, from x = 0 to
x = length, at rest. The striker's front end node meets the target's rear end node through an
end-to-end contact with its normal along the axis (``NodeNodeContact``: g = x_target − x_striker
at the two ends). With the wave speed c = √(E/ρ), the exact solution (DESIGN §8) keeps the
ends together for 2L/c after the gap closes, under the constant force ρ c v₀ A / 2; then the
striker stops and the target moves on at v₀ (total momentum / total mass of one bar), neither
vibrating.

Probes: ``gap`` between the ends (m), ``contact_force`` k Λ/h (N, mean over the step),
``v_striker`` and ``v_target`` (m/s, momentum / mass of each bar).
"""

import numpy as np

from fecontact import (
    Beam2D,
    Contact,
    IntegratorOptions,
    Material,
    Model,
    Probe,
    Section,
    Simulation,
    run_cli,
)
from fecontact.errors import check_count, check_positive, check_range

PARAMETERS = {
    "length": ("m", "length L of each bar"),
    "E": ("Pa", "Young's modulus"),
    "rho": ("kg/m^3", "density"),
    "area": ("m^2", "cross-section area A"),
    "velocity": ("m/s", "initial speed v0 of the striker toward the target (> 0)"),
    "gap": ("m", "initial distance between the two ends (>= 0)"),
    "n_elements": ("-", "number of elements of each bar"),
    "restitution": ("-", "Newton's coefficient e_N between the ends (the exact solution: 0)"),
    "rho_inf": ("-", "spectral radius at infinite frequency in [0, 1]"),
}


def build(
    length=1.0,
    E=1.0,
    rho=1.0,
    area=1.0,
    velocity=0.1,
    gap=0.0,
    n_elements=100,
    restitution=0.0,
    rho_inf=0.5,
):
    material = Material(E, rho)
    check_positive("length", length)
    check_positive("area", area)
    check_positive("velocity", velocity)
    check_positive("gap", gap, allow_zero=True)
    check_count("n_elements", n_elements)
    check_range("restitution", restitution, 0.0, 1.0)
    options = IntegratorOptions(rho_inf=rho_inf)
    # a square section: bending stiffness plays no part in the axial problem
    section = Section(area=area, inertia=area**2 / 12.0)
    striker = Beam2D.straight([-gap - length, 0.0], [-gap, 0.0], n_elements, material, section)
    target = Beam2D.straight([0.0, 0.0], [length, 0.0], n_elements, material, section)
    hit = Contact(striker, target, nodes=(-1, 0), restitution=restitution)
    model = Model([striker, target], [hit], gravity=(0.0, 0.0))
    ux = np.arange(0, striker.ndof, 3)  # axial dofs of one bar, node by node
    px = (striker.mass_matrix() @ striker.translation_field((1.0, 0.0)))[ux]  # momentum weights
    mass = px.sum()
    o = model.offset_of(target)
    probes = {
        "gap": Probe(
            lambda m, st: float(hit.evaluate(st.q)[0][0]), "m", "gap between the two bar ends"
        ),
        "contact_force": Probe(
            lambda m, st: float(st.impulse.sum() / st.h) if st.h > 0 else 0.0,
            "N",
            "contact force k Lambda / h (mean over the step)",
        ),
        "v_striker": Probe(lambda m, st: float(px @ st.v[ux]) / mass, "m/s", "striker velocity"),
        "v_target": Probe(lambda m, st: float(px @ st.v[o + ux]) / mass, "m/s", "target velocity"),
    }
    params = {k: v for k, v in locals().items() if k in PARAMETERS}
    c = np.sqrt(E / rho)
    dx = length / n_elements
    # two steps per element transit time Δx/c, as for the bar against a wall; the run shows
    # the contact (2L/c after the gap closes) and half as long again of free flight
    return Simulation(
        model,
        dt=0.5 * dx / c,
        t_end=gap / velocity + 3.0 * length / c,
        probes=probes,
        options=options,
        output_interval=0.05 * length / c,
        name="two_bars",
        parameters=params,
        v0=model.translation(striker, (velocity, 0.0)),
    )


if __name__ == "__main__":
    run_cli(build)
