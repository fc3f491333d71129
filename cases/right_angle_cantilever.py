"""Simo & Vu-Quoc's right-angle cantilever struck out of its plane (J. C. Simo and L. Vu-Quoc,
On the dynamics in space of rods undergoing large motions: a geometrically exact approach,
Comput. Methods Appl. Mech. Eng. 66, 125–161, 1988): a flexible L swinging and twisting in
space.

Two legs of length 10 m in the x–y plane, from the clamped root (0, 10, 0) to the elbow
(10, 10, 0) and on to the free tip (10, 0, 0), with the paper's EA = GA = 10⁶ N,
EI = GJ = 10³ N·m², ρA = 1 kg/m and rotary inertia per length diag(20, 10, 10) kg·m about the
section's axis (torsion) and its two bending axes: the torsional one is the sum of the two
bending ones, as for any section (a section of area 0.012 m², E = 10⁶/0.012 Pa, ν = 0, shear
factor 2, ρ = 1/0.012 kg/m³ gives the stiffnesses). A force along z, fixed in direction, at the
elbow rises linearly to ``peak_force`` at t = 1 s and falls back to zero at t = 2 s; then the L
swings and twists freely, its energy constant (at ``rho_inf`` = 1, without dissipation).

Probes: ``elbow_z`` and ``tip_z`` (m), the displacements along z.

Checked against (docs/validation/beam3d.md): the linearised L's modal solution while it moves
little (at these defaults 1.9 % of the elbow's rise off it up to t = 1 s, order 2 in h and the
mesh); an independent implementation's extremes (to its printed 0.01 m, at the same steps);
the published tip and elbow curves (twelve features of the figure as digitized point by point:
times within 0.22 s, heights within 0.21 m up to 16 s and 0.59 m after, at 8 elements a leg and
h = 0.025 s); and its own convergence (the tip within 0.18 m of the converged history over the
first 10 s at these defaults, 0.009 m at 16 elements a leg and h = 0.0125 s).
"""

import numpy as np

from fecontact import (
    IntegratorOptions,
    Model,
    NodalLoad,
    Param,
    Simulation,
    case,
    node_probe,
    run_cli,
)
from fecontact.bodies import Beam3D, Material, Section

# Simo & Vu-Quoc's figure of the tip and elbow histories (1988), as digitized in the dynLattice
# project's reference data (points every 0.6 s along the tip's curve, every 0.5 s along the
# elbow's): each feature (t in s, height in m), an extremum at the vertex of the parabola through
# its three points, a crossing of zero interpolated linearly. Another digitization of the
# figure reads a tip curve that leads by 0.7-1.1 s; it is not the stated problem's
# (docs/validation/beam3d.md: its tip rises 0.93 m by t = 1.54 s, where the stated problem's is
# at 0.04 m, 0.02 m in the linear solution).
FIGURE = {
    "tip": {
        "max": (7.58, 8.09),
        "down": (11.32, 0.0),
        "min": (15.96, -9.67),
        "up": (20.02, 0.0),
        "max2": (26.00, 6.93),
    },
    "elbow": {
        "max": (3.04, 5.51),
        "min": (10.71, -3.87),
        "up": (12.69, 0.0),
        "max2": (13.78, 1.14),
        "min2": (17.09, -1.41),
        "min3": (20.75, -2.76),
        "max3": (25.16, 6.09),
    },
}


@case
def build(
    n_per_leg=Param.count(4, "elements per leg"),
    peak_force=Param.nonnegative(50.0, "N", "peak of the triangular force pulse at the elbow"),
    rho_inf=Param.fraction(1.0, "spectral radius at infinite frequency"),
    dt=Param.positive(0.05, "s", "time step"),
    t_end=Param.positive(30.0, "s", "end time"),
):
    side2 = 12e-3  # a²: EI/EA = a²/12 = 10⁻³ m²
    material = Material(1e6 / side2, nu=0.0, rho=1.0 / side2)
    # GA = 2 G A = E A with ν = 0; GJ = E I with J = 2I
    section = Section(area=side2, inertia=side2**2 / 12, shear_factor=2.0, torsion=side2**2 / 6)
    s = np.linspace(0.0, 1.0, n_per_leg + 1)[:, None]
    root, elbow, tip = np.array([[0.0, 10.0, 0.0], [10.0, 10.0, 0.0], [10.0, 0.0, 0.0]])
    nodes = np.vstack([root + s * (elbow - root), elbow + s[1:] * (tip - elbow)])
    beam = Beam3D(nodes, material, section, rotary_inertia=(20.0, 10.0, 10.0)).clamp(0)

    def pulse(t):
        f = np.zeros(6)
        f[2] = peak_force * max(0.0, 1.0 - abs(t - 1.0))
        return f

    model = Model([beam], loads=[NodalLoad(beam, n_per_leg, pulse)], gravity=(0.0, 0.0, 0.0))
    probes = {
        "elbow_z": node_probe(model, beam, n_per_leg, "z"),
        "tip_z": node_probe(model, beam, -1, "z"),
    }
    options = IntegratorOptions(rho_inf=rho_inf)
    return Simulation(
        model, dt=dt, t_end=t_end, probes=probes, name="right_angle_cantilever", options=options
    )


if __name__ == "__main__":
    run_cli(build)
