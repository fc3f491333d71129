"""Two identical elastic bars end to end on one axis: the striker hits the target at rest.

Two straight ``Beam2D`` bars (axial behaviour only, no gravity) lie on the x axis: the striker
from x = −gap − length to x = −gap moves at ``velocity`` toward the target, from x = 0 to
x = length, at rest. The striker's front end node meets the target's rear end node through an
end-to-end contact with its normal along the axis (``NodeNodeContact``: g = x_target − x_striker
at the two ends). With the wave speed c = √(E/ρ), the exact solution keeps the
ends together for 2L/c after the gap closes, under the constant force ρ c v₀ A / 2; then the
striker stops and the target moves on at v₀ (total momentum / total mass of one bar), neither
vibrating.

Probes: ``gap`` between the ends (m), ``contact_force`` k Λ/h (N, mean over the step),
``v_striker`` and ``v_target`` (m/s, momentum / mass of each bar).
"""

import numpy as np

from fecontact import InputError, Model, Probe, Simulation, case, run_cli
from fecontact.contact import Contact
from fecontact.scenes import BAR, axial_bar, axial_velocity_probe, contact_force_probe, wave_transit


@case(BAR)
def build(length, E, rho, area, velocity, gap, n_elements, restitution):
    c = np.sqrt(E / rho)
    if velocity > 1.2 * c:
        # the strain where the ends meet is v/(2c); the discrete front overshoots it, and only
        # the end nodes hold each other: at 0.7 (v = 1.4 c) the next nodes pass by
        # 0.78 mm, at 0.6 by none (n = 100, the case's step)
        raise InputError(
            f"velocity must be at most 1.2 times the bars' wave speed, 1.2 sqrt(E/rho) = "
            f"{1.2 * c:.4g} m/s, got "
            f"{velocity:g}: the strain v/(2c) where the ends meet, overshot by the discrete "
            "front, would push the nodes next to the ends through each other"
        )
    striker = axial_bar([-gap - length, 0.0], [-gap, 0.0], n_elements, E, rho, area)
    target = axial_bar([0.0, 0.0], [length, 0.0], n_elements, E, rho, area)
    hit = Contact(striker, target, nodes=(-1, 0), restitution=restitution)
    model = Model([striker, target], [hit], gravity=(0.0, 0.0))
    probes = {
        "gap": Probe(lambda m, st: float(hit.evaluate(st.q)[0][0]), "m", "gap between the ends"),
        "contact_force": contact_force_probe(),
        "v_striker": axial_velocity_probe(model, striker, "striker velocity"),
        "v_target": axial_velocity_probe(model, target, "target velocity"),
    }
    v0 = model.translation(striker, (velocity, 0.0))
    times = wave_transit(length, n_elements, E, rho, gap, velocity)
    return Simulation(model, probes=probes, name="two_bars", v0=v0, **times)


if __name__ == "__main__":
    run_cli(build)
