"""A 3D beam striking a plane (cases/rod_drop.py): without spin it is the same drop of a
Beam2D in the rod's vertical plane; with spin, the floor and gravity, both vertical, leave the
angular momentum about the vertical unchanged through the impacts."""

import dataclasses

import numpy as np
import pytest
from conftest import load_case

from fecontact import (
    Beam2D,
    Contact,
    Material,
    Model,
    Plane,
    Section,
    Simulation,
    node_probe,
    rotations,
    simulate,
)
from fecontact.testing import trace
from fecontact.time import settings


def planar_twin(sim):
    """The drop of ``sim`` as a Beam2D in the rod's vertical plane (abscissa along the
    azimuth, ordinate z)."""
    p = sim.parameters
    a, r = np.radians(p["angle"]), p["radius"]
    low = np.array([0.0, r + p["drop_height"]])
    high = low + p["length"] * np.array([np.cos(a), np.sin(a)])
    material = Material(p["E"], nu=p["nu"], rho=p["rho"])
    rod = Beam2D.straight(low, high, p["n_elements"], material, Section.circle(r))
    floor = Contact(rod, Plane([0.0, 0.0], [0.0, 1.0]), clearance=r)
    model = Model([rod], [floor], gravity=(0.0, -9.81))
    probes = {"low_z": node_probe(model, rod, 0, "y"), "high_z": node_probe(model, rod, -1, "y")}
    v0 = model.translation(rod, (0.0, -p["velocity"]))
    return Simulation(model, dt=sim.dt, t_end=sim.t_end, probes=probes, name="twin", v0=v0)


def test_without_spin_the_drop_is_the_planar_one():
    """At the defaults (the smooth contact force, which neither rod, met along its length by
    a fixed floor, settles: ``settles``) and with the decoupled contact phase."""
    sim = load_case("rod_drop").build().replace(t_end=0.06)  # the end's impact and the whip
    for contact in ("auto", "off"):
        run = sim.replace(options=dataclasses.replace(sim.options, smooth_contact=contact))
        twin = planar_twin(run)
        twin = twin.replace(options=dataclasses.replace(twin.options, smooth_contact=contact))
        space, plane = trace(run), trace(twin)
        assert space["status"] == plane["status"] == "completed"
        assert (space["impulse"] > 0).sum() > 5
        # the same equations in another dof order: the Newton and contact iterations stop at
        # their tolerances at different points (7.5e-10 and 8.0e-10 m apart at the defaults
        # over 0.06 s, 8.4e-7 m over the whole 0.25 s; decoupled 9e-8 m over 0.25 s, measured)
        for q in ("low_z", "high_z"):
            np.testing.assert_allclose(space[q], plane[q], rtol=0, atol=1e-6)
        assert space["min_gap"].min() >= -1e-9


@pytest.mark.parametrize("settle", [True, False])
def test_with_the_smooth_force_the_drop_is_the_planar_one_under_one_settling_rule(
    settle, monkeypatch
):
    """With the smooth contact force (the default of beams), both rods settling a step after
    each closing or neither (``settles``, fecontact/time/settings.py): the same run in
    another dof order."""
    monkeypatch.setattr(settings, "settles", lambda model, smooth: smooth and settle)
    sim = load_case("rod_drop").build().replace(t_end=0.06)
    space, plane = trace(sim), trace(planar_twin(sim))
    assert space["status"] == plane["status"] == "completed"
    assert (space["impulse"] > 0).sum() > 5
    # the Newton iterations stop at their tolerances at different points: 4.0e-10 and
    # 5.7e-10 m apart settling, 7.5e-10 and 8.0e-10 m not (measured, 0.06 s)
    for q in ("low_z", "high_z"):
        np.testing.assert_allclose(space[q], plane[q], rtol=0, atol=1e-6)


def test_with_spin_the_vertical_angular_momentum_holds_through_the_impacts():
    sim = load_case("rod_drop").build(yaw_rate=20.0)
    model, rod = sim.model, sim.model.bodies[0]

    def vertical_momentum(q, v):
        p = (model.M_full @ v).reshape(-1, 6)
        R = rotations.exp(q.reshape(-1, 6)[:, 3:])
        L = np.cross(rod.positions(q), p[:, :3]) + np.einsum("nij,nj->ni", R, p[:, 3:])
        return L.sum(axis=0)[2]

    L, steps = [], round(sim.t_end / sim.dt)
    for st in simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0):
        L.append(vertical_momentum(st.q, st.v))
        # a run that drags (step halvings, each adding steps) is cut short: four times the
        # fixed step's count leaves room for the impacts' halvings, not for a run that stalls
        assert len(L) <= 4 * steps, f"t = {st.t:g} s after {len(L)} steps"
    # frictionless impulses and gravity are vertical: no moment about the vertical. What is
    # left is the smooth step's own drift, largest in the steps that reach the floor (2.3e-5
    # relative at the default step, measured; 4.9e-4 when the position correction moved the
    # nodes without holding the rod's angular momentum)
    assert np.abs(np.array(L) - L[0]).max() < 1e-4 * abs(L[0])


def test_the_correction_holds_the_momentum_about_the_common_normal_only():
    """A spinning rod moved by a correction (tilted, as the stiffness metric moves it): the
    held increment returns L·n to its value before the correction, keeps the linear momentum
    and is a rigid rotation about n through the centre; contacts with two normals hold
    nothing."""
    from fecontact.time.correction import MomentumKept

    sim = load_case("rod_drop").build(yaw_rate=20.0)
    model, rod = sim.model, sim.model.bodies[0]
    kept = MomentumKept(model)
    q_tilde, v = np.zeros(model.n), sim.v0.copy()
    q = q_tilde.copy()
    # tilted by 2 mrad about the horizontal axis across the rod through its centre
    a = np.array([-1.0, 1.0, 0.0]) / np.sqrt(2.0)
    X = rod.positions(q_tilde)
    q.reshape(-1, 6)[:, :3] = np.cross(2e-3 * a, X - X.mean(axis=0))
    q.reshape(-1, 6)[:, 3:] = 2e-3 * a
    n = np.array([0.0, 0.0, 1.0])
    G = np.zeros((2, model.n_free))
    G[0, 2], G[1, 8] = 1.0, 1.0  # two nodes pushed along +z
    dv = kept(q_tilde, q, v, G)

    def momenta(q, v):
        p = (model.M_full @ v).reshape(-1, 6)
        R = rotations.exp(q.reshape(-1, 6)[:, 3:])
        L = np.cross(rod.positions(q), p[:, :3]) + np.einsum("nij,nj->ni", R, p[:, 3:])
        return L.sum(axis=0), p[:, :3].sum(axis=0)

    (L0, P0), (L1, _), (L2, P2) = momenta(q_tilde, v), momenta(q, v), momenta(q, v + dv)
    assert abs((L1 - L0) @ n) > 1e-4 * abs(L0 @ n)  # the correction alone moved L·n
    # (round-off of sums over 11 nodes of products of order 1e-2)
    assert abs((L2 - L0) @ n) < 1e-14 * abs(L0 @ n)
    np.testing.assert_allclose(P2, P0, rtol=0, atol=1e-15)
    w = dv.reshape(-1, 6)
    spin = np.einsum("nij,nj->ni", rotations.exp(q.reshape(-1, 6)[:, 3:]), w[:, 3:])
    x = rod.positions(q)
    c = (x[1:] + x[:-1]).sum(axis=0) / (2 * (len(x) - 1))  # the centre of a uniform rod
    np.testing.assert_allclose(spin, np.outer(spin[:, 2], n), atol=1e-15)  # about n,
    np.testing.assert_allclose(w[:, :3], np.cross(spin, x - c), atol=1e-15)  # rigidly, about c
    G[1, 8], G[1, 6] = 0.0, 1.0  # the second contact pushes along x: no common normal
    assert not kept(q_tilde, q, v, G).any()
