"""Pieces that cases share: materials by name, the step of an elastic body from its wave
speed, the simulation of an elastic impact, and the probes most impacts are read with."""

from __future__ import annotations

import numpy as np

from .bodies.beam import Beam2D, Material, Section
from .bodies.materials import LinearElastic, NeoHookean, StVenantKirchhoff
from .params import Param
from .simulation import Probe, Simulation

__all__ = [
    "BAR",
    "DISK",
    "DROP",
    "GRAVITY",
    "IMPACT",
    "MATERIALS",
    "SOLID",
    "PENDULUM_STOP",
    "ROD",
    "STRIP",
    "axial_bar",
    "axial_velocity_probe",
    "wave_transit",
    "centre_of_mass_probes",
    "contact_force_probe",
    "lowest_point_probe",
    "solid_material",
    "wave_simulation",
    "wave_step",
]

MATERIALS = {"neo-hookean": NeoHookean, "linear": LinearElastic, "svk": StVenantKirchhoff}
"""Solid materials by the names cases take: compressible Neo-Hookean, linear elastic and
St Venant–Kirchhoff."""


def solid_material(name: str, E: float, nu: float, rho: float):
    """The material ``name`` (a key of ``MATERIALS``) with Young's modulus E (Pa), Poisson's
    ratio ν and density ρ (kg/m³)."""
    return MATERIALS[name](E=E, nu=nu, rho=rho)


def wave_step(body, fraction: float, spacing: float | None = None) -> float:
    """``fraction`` of the time (s) the dilatational wave takes to cross the node ``spacing``
    (m; default the body's shortest edge)."""
    spacing = body.min_edge_length if spacing is None else spacing
    return fraction * spacing / body.material.wave_speed


def wave_simulation(
    model,
    body,
    name: str,
    t_end: float,
    probes: dict,
    v0,
    spacing: float | None = None,
    frames: int = 40,
) -> Simulation:
    """The ``Simulation`` of an elastic body's impact: ``name``, end time ``t_end`` (s), the
    initial velocity ``v0`` (one value a dof of the model, m/s) and ``probes``; the step is the
    time the dilatational wave of ``body`` takes to cross one node ``spacing`` (``wave_step``:
    by default the body's shortest edge), and ``frames`` frames are written over the run."""
    return Simulation(
        model,
        dt=wave_step(body, 1.0, spacing),
        t_end=t_end,
        probes=probes,
        output_interval=t_end / frames,
        name=name,
        v0=v0,
    )


def contact_force_probe(what: str = "contact force") -> Probe:
    """Σ λ_j + k Λ_j / h (N): the mean contact force over the step, smooth and impulsive."""
    return Probe(
        lambda m, st: float(st.mean_force().sum()),
        "N",
        f"{what} lambda + k Lambda / h (mean over the step)",
    )


def centre_of_mass_probes(model, body, axis: int, start: float = 0.0, name: str = "center"):
    """Position (from ``start``, m) and velocity (m/s) of the body's centre of mass along the
    coordinate ``axis``, as probes ``<x|y|z>_<name>`` and ``v<x|y|z>_<name>``."""
    e = np.eye(body.dim)[axis]
    w = body.mass_matrix() @ body.translation_field(e)  # momentum weights along the axis
    s, letter = model.slice_of(body), "xyz"[axis]
    return {
        f"{letter}_{name}": Probe(
            lambda m, st: start + w @ st.q[s] / body.mass, "m", "centre of mass position"
        ),
        f"v{letter}_{name}": Probe(
            lambda m, st: w @ st.v[s] / body.mass, "m/s", "centre of mass velocity"
        ),
    }


def spin_probe(model, body) -> Probe:
    """Angular velocity ω = L/I (rad/s, counter-clockwise) of a 2D solid about its centre of
    mass c: L = Σ_a r_a × (M v)_a and I = Σ_a r_a·(M r)_a, r = x − c, with the consistent
    mass M (∫ρ N_a N_b = M_ab: exact for the interpolated motion)."""
    s = model.slice_of(body)
    M = body.mass_matrix()

    def omega(m, st):
        x = body.positions(st.q[s])
        r = x - body.nodal(M @ x.ravel()).sum(axis=0) / body.mass
        p = body.nodal(M @ st.v[s])
        L = np.sum(r[:, 0] * p[:, 1] - r[:, 1] * p[:, 0])
        return float(L / np.sum(r * body.nodal(M @ r.ravel())))

    return Probe(omega, "rad/s", "angular velocity about the centre of mass, counter-clockwise")


def lowest_point_probe(model, body, axis: int) -> Probe:
    """The smallest coordinate (m) along ``axis`` of the body's nodes: its height above a
    floor through the origin."""
    s = model.slice_of(body)
    return Probe(
        lambda m, st: float(body.positions(st.q[s])[:, axis].min()), "m", "lowest point height"
    )


def axial_bar(start, end, n_elements: int, E: float, rho: float, area: float, linear=False):
    """A straight bar from ``start`` to ``end`` (m) for axial waves: a ``Beam2D`` of square
    section ``area`` (m²; bending plays no part in the axial problem), Young's modulus E (Pa)
    and density ρ (kg/m³)."""
    section = Section(area=area, inertia=area**2 / 12.0)
    return Beam2D.straight(start, end, n_elements, Material(E, rho=rho), section, linear)


def axial_velocity_probe(model, bar, text: str, node=None) -> Probe:
    """The bar's axial momentum over its mass (m/s), or the axial velocity of ``node``."""
    ux = np.arange(0, bar.ndof, 3) + model.offset_of(bar)  # axial dofs, node by node
    if node is not None:
        return Probe(lambda m, st: st.v[ux[node]], "m/s", text)
    px = (bar.mass_matrix() @ bar.translation_field((1.0, 0.0)))[ux - ux[0]]
    mass = px.sum()
    return Probe(lambda m, st: float(px @ st.v[ux]) / mass, "m/s", text)


def wave_transit(
    length: float, n_elements: int, E: float, rho: float, gap: float, v0: float
) -> dict[str, float]:
    """The ``Simulation`` times of a bar impact (c = √(E/ρ)): the step ``dt``, half the
    element transit time Δx/c; the end ``t_end``, through the closing of the ``gap`` at
    ``v0``, the contact (2L/c) and half as long again of free flight; and a frame every
    twentieth of the bar's transit time L/c (``output_interval``)."""
    c = np.sqrt(E / rho)
    return {
        "dt": 0.5 * (length / n_elements) / c,
        "t_end": gap / v0 + 3.0 * length / c,
        "output_interval": 0.05 * length / c,
    }


BAR = {
    "length": Param.positive(1.0, "m", "length L of each bar"),
    "E": Param.positive(1.0, "Pa", "Young's modulus"),
    "rho": Param.positive(1.0, "kg/m^3", "density"),
    "area": Param.positive(1.0, "m^2", "cross-section area A"),
    "velocity": Param.positive(0.1, "m/s", "initial speed v0 of the striking bar"),
    "gap": Param.nonnegative(0.0, "m", "initial distance between the ends that meet"),
    "n_elements": Param.count(100, "number of elements of each bar"),
    "restitution": Param.fraction(0.0, "Newton's coefficient e_N where the ends meet (exact: 0)"),
}
"""The wave-propagation bars (parameter group of ``case``): geometry, material in units where
the wave speed c = √(E/ρ) is 1, and the impact."""

SOLID = {
    "E": Param.positive(1e7, "Pa", "Young's modulus"),
    "nu": Param(0.3, "-", "Poisson's ratio", -1.0, 0.5, (False, False)),
    "rho": Param.positive(1000.0, "kg/m^3", "density"),
    "material": Param.choice("neo-hookean", "solid material", MATERIALS),
}
"""A soft rubber-like solid: the elastic bodies' material (parameter group of ``case``)."""

STRIP = {
    "length": Param.positive(0.3, "m", "beam length"),
    "n_elements": Param.count(4, "number of beam elements"),
    "E": Param.positive(70e9, "Pa", "Young's modulus"),
    "nu": Param(0.33, "-", "Poisson's ratio", -1.0, 0.5, (False, False)),
    "rho": Param.positive(2700.0, "kg/m^3", "density"),
    "width": Param.positive(0.02, "m", "section width"),
    "thickness": Param.positive(0.002, "m", "section thickness (bending)"),
}
"""A straight metal strip (``Beam2D`` of rectangular section; parameter group of ``case``):
aluminium by default."""

IMPACT = {
    "restitution": Param.fraction(0.0, "Newton's coefficient of restitution e_N"),
    "friction": Param.nonnegative(0.0, "-", "Coulomb's coefficient mu"),
}
"""The laws of a contact: Newton's impact law and Coulomb's friction (parameter group of
``case``)."""

GRAVITY = {
    "gravity": Param.nonnegative(9.81, "m/s^2", "acceleration of gravity, along -y (2D), -z (3D)")
}
"""The acceleration of gravity, along the vertical axis of the model's space (parameter group
of ``case``)."""

PENDULUM_STOP = {
    "tip_mass": Param.nonnegative(0.14, "kg", "point mass on the tip node"),
    **IMPACT,
    **GRAVITY,
}
"""The founding case's tip mass, its stop's laws and gravity (parameter group of ``case``)."""

ROD = {
    "length": Param.positive(0.5, "m", "rod length"),
    "radius": Param.positive(0.005, "m", "radius of the circular section"),
    "n_elements": Param.count(10, "number of beam elements"),
    "E": Param.positive(210e9, "Pa", "Young's modulus"),
    "nu": Param(0.3, "-", "Poisson's ratio", -1.0, 0.5, (False, False)),
    "rho": Param.positive(7850.0, "kg/m^3", "density"),
}
"""A steel rod of circular section: ``Beam3D.straight`` (parameter group of ``case``)."""

DISK = {
    "radius": Param.positive(0.05, "m", "radius of the disk (of each disk)"),
    "refinements": Param.count(3, "uniform refinements of the disk mesh (4 * 4^n triangles)", 0, 6),
}
"""A 2D elastic disk's mesh: ``Solid.disk`` (parameter group of ``case``)."""

DROP = {
    "drop_height": Param.nonnegative(0.002, "m", "initial gap between the body and the plane"),
    "velocity": Param.nonnegative(1.0, "m/s", "initial downward speed"),
    "restitution": Param.fraction(0.0, "Newton's coefficient e_N at the contact nodes"),
    "t_end": Param.positive(0.008, "s", "end time"),
}
"""An elastic body thrown onto a rigid plane (parameter group of ``case``)."""
