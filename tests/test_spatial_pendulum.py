"""The founding case in space (cases/spatial_pendulum.py): in its plane it is the founding
case; out of it, it keeps the angular momentum about the vertical until it hits the stop."""

import dataclasses

import numpy as np
import pytest
from conftest import load_case

from fecontact import Model, Simulation, node_probe, rotations, simulate
from fecontact.bodies import Beam2D, Beam3D, Material, Section
from fecontact.contact import Contact, Plane
from fecontact.testing import trace


def decoupled(sim):
    """``sim`` with the decoupled contact phase (``smooth_contact="off"``)."""
    return sim.replace(options=dataclasses.replace(sim.options, smooth_contact="off"))


def twins(options, t_end):
    """The founding case and its twin in space, traced to ``t_end`` with ``options``."""
    flat = trace(options(load_case("flexible_pendulum").build()), t_end=t_end)
    space = trace(options(load_case("spatial_pendulum").build()), t_end=t_end)
    assert space["status"] == flat["status"] == "completed"
    assert space["impulse"].max() > 0.0
    return flat, space


def defaults(sim):
    return sim


@pytest.mark.parametrize("options, t_end", [(defaults, None), (decoupled, 0.4)])
def test_in_the_plane_it_is_the_founding_case(options, t_end):
    # at the defaults over the whole run (1.5 s: the strike at 0.319 s, the rebound, the
    # lasting contact), both taking the smooth force a step after the strike (their one
    # contact is at the strip's end); decoupled through the first impact and the rebound.
    # 1e-6 m is the bound asked of the twin. Measured: decoupled 2.4e-12 m; at the defaults
    # 1.3e-11 m (7.3e-7 m from the release at 0.327 s before the smooth step on the group
    # took the planar line search where the stiffness softens)
    flat, space = twins(options, t_end)
    for q in ("tip_x", "tip_y"):
        np.testing.assert_allclose(space[q], flat[q], rtol=0, atol=1e-6)
    assert np.abs(space["tip_z"]).max() == 0.0


def floor_pendulum(beam_class, e: float) -> Simulation:
    """The founding strip and tip mass released level against a floor under its pin (its
    tip strikes at 0.25 s, the strip at 56° to the floor: the strike rings its axial mode),
    as a ``Beam2D`` or a ``Beam3D``; probes of the tip along x and y."""
    dim = 2 if beam_class is Beam2D else 3
    at = np.zeros((2, dim))
    at[1, 0] = 0.3
    material = Material(70e9, nu=0.33, rho=2700.0)
    beam = beam_class.straight(at[0], at[1], 4, material, Section.rectangle(0.02, 0.002))
    beam.pin(0).add_mass(-1, 0.14)
    floor = Plane(-0.25 * np.eye(dim)[1], np.eye(dim)[1])
    model = Model([beam], [Contact(beam, floor, nodes=[-1], restitution=e)],
                  gravity=-9.81 * np.eye(dim)[1])  # fmt: skip
    probes = {f"tip_{q}": node_probe(model, beam, -1, q) for q in "xyz"[:dim]}
    return Simulation(model, dt=1e-3, t_end=0.4, probes=probes, name="floor_pendulum")


@pytest.mark.parametrize("e", [0.0, 1.0])
def test_struck_against_a_floor_in_the_plane_it_is_the_planar_strip(e):
    # the strike rings the strip's axial mode; both take the smooth force a step after it
    # (without that step the strip blew up at 0.26 s, planar and in space alike) and take a
    # release again without its force through S_t at the step's end. Measured over the
    # 0.4 s (strikes, releases and re-strikes): 6.4e-10 and 2.7e-11 m; with S_t at the
    # step's start in space 3.2e-4 and 1.1e-2 m. 1e-6 m is the bound asked of the twin
    flat = trace(floor_pendulum(Beam2D, e))
    space = trace(floor_pendulum(Beam3D, e))
    assert space["status"] == flat["status"] == "completed"
    assert (space["impulse"] > 0).sum() >= 4  # (the strike, re-strikes)
    for q in ("tip_x", "tip_y"):
        np.testing.assert_allclose(space[q], flat[q], rtol=0, atol=1e-6)
    assert np.abs(space["tip_z"]).max() == 0.0


def vertical_angular_momentum(beam, M, q, v):
    """Σ_ab M_ab x_a × v_b + Σ R_a (J Ω)_a along y, about the pin (kg·m²/s)."""
    p = (M @ v).reshape(-1, 6)
    L = np.cross(beam.positions(q), p[:, :3]).sum(axis=0)
    R = rotations.exp(q.reshape(-1, 6)[:, 3:])
    return (L + np.einsum("nij,nj->ni", R, p[:, 3:]).sum(axis=0))[1]


def test_out_of_the_plane_it_keeps_its_vertical_angular_momentum_until_the_stop():
    sim = load_case("spatial_pendulum").build(out_of_plane_velocity=0.5)
    model, beam = sim.model, sim.model.bodies[0]
    L, q = [], None
    for st in simulate(model, sim.dt, 0.25, sim.options, q0=sim.q0, v0=sim.v0):
        L.append(vertical_angular_momentum(beam, model.M_full, st.q, st.v))
        q = st.q
    L = np.array(L)
    # gravity along −y and the pin exert no moment about y; the step keeps L_y to O(h²)
    # (6e-5 measured at h = 1 ms)
    assert np.abs(L - L[0]).max() < 2e-4 * abs(L[0])
    assert beam.positions(q)[-1, 2] > 0.05  # the tip left the plane


def test_out_of_the_plane_it_runs_through_its_impacts():
    sim = load_case("spatial_pendulum").build(out_of_plane_velocity=0.5)
    # the tip strikes the stop at about 0.31 s; a run that drags (step halvings) is cut short
    run = trace(sim, t_end=0.45, max_wall=30.0)
    assert run["status"] == "completed", run["message"]
    assert run["impulse"].max() > 0.0
    assert run["min_gap"].min() >= -1e-9
    assert run["tip_z"].max() > 0.05
