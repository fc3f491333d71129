"""Coulomb friction in the smooth step (:class:`fecontact.time.coulomb.SmoothFriction`): an
elastic block on an incline (3D, the disk cone) that holds its grip without creeping, one
that slides with the momentum Coulomb's law allows, and an elastic disk thrown onto a plane
(2D) whose answer does not depend on the augmentation."""

import dataclasses

import numpy as np
import pytest

from fecontact import run
from fecontact.io.frames import frame_parts
from fecontact.scenes import centre_of_mass_probes, spin_probe
from fecontact.testing import G, case, trace
from fecontact.time import simulate


def incline(alpha_deg, mu, scheme="auto", **params):
    """``cases/elastic_block.py`` (a 0.1 × 0.1 × 0.05 m linear elastic block on an incline,
    at the step Δx/c) with ``smooth_contact`` = ``scheme``."""
    sim = case("elastic_block").build(incline=alpha_deg, friction=mu, **params)
    return sim.replace(options=dataclasses.replace(sim.options, smooth_contact=scheme))


def settled_states(sim):
    """The states of a run, and the largest motion (m) of the bottom nodes along the plane
    over its second half."""
    block, s = sim.model.bodies[0], sim.model.body_slice(0)
    bottom = sim.model.contacts.pairs[0].nodes
    states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options))
    half = np.array([block.positions(st.q[s])[bottom, :2] for st in states[len(states) // 2 :]])
    return states, float(np.max(np.linalg.norm(half - half[0], axis=2)))


@pytest.mark.parametrize("mu", [0.5, 0.8])
def test_a_block_on_a_gentle_incline_holds_without_creeping(mu):
    # tan 20° = 0.36 < μ: once the stiffness damping has let the block settle, every bottom
    # node is pressed inside the cone and must not move. Each step's slip is held to the
    # inner tolerance 0.1 tol_gap L ≈ 1.5e-14 m; 230 steps bound the drift by ~4e-12 m
    sim = incline(20.0, mu, damping=1e-4)
    states, slip = settled_states(sim)
    assert slip <= 1e-11
    last = states[-1]
    assert np.all(last.gaps >= -1e-12)
    # the smooth forces carry the block: Σλ_T = m g sin α along the slope, Σλ_N = m g cos α
    mass, a = sim.model.bodies[0].mass, np.radians(20.0)
    along = last.smooth.tangential[:, 0].sum()
    assert along == pytest.approx(-mass * G * np.sin(a), rel=1e-3)
    assert last.force.sum() == pytest.approx(mass * G * np.cos(a), rel=1e-3)
    # ... and the frames draw them: tangential_force (N) is the mean over the step, the
    # smooth force plus the jump's impulse over h (here ~1e-9 of it, the index-3 drift)
    data = next(iter(frame_parts(sim.model, last).values())).point_data
    mean = along + last.friction.impulse[:, 0].sum() / last.h
    assert data["tangential_force"][:, 0].sum() == pytest.approx(mean, rel=1e-12)


def test_the_decoupled_scheme_holds_the_same_block():
    # without the smooth force the corrections and jumps alone hold the pressed nodes: its
    # jumps strike nothing and take the drift out through S_t⁻¹ (impacts.resting_metric);
    # through M⁻¹ the block's interior moved over its face and the nodes walked down the
    # slope, 6.7e-5 m at μ = 0.5. Measured now 2.1e-22 m; the bound is the smooth force's
    _, slip = settled_states(incline(20.0, 0.5, "off", damping=1e-4))
    assert slip <= 1e-11


def test_a_block_thrown_down_a_steep_incline_slides_as_coulomb_says():
    # tan 30° > μ = 0.2 and thrown at 0.5 m/s: every pressed node slips down the slope, so
    # along it the plane takes μ times the momentum it gives normal to it,
    # v_x + μ v_z = v₀ + g (sin α − μ cos α) t. Nodes also slip a little sideways (the
    # Poisson spread of the compressed base), which takes a share 1 − cos θ ≈ θ²/2 off the
    # force along x: the bound 1e-5 m/s holds that share for θ up to a few milliradians
    # (measured 1.9e-6 m/s; the decoupled scheme gives 4e-4 m/s)
    mu, a, v0 = 0.2, np.radians(30.0), 0.5
    run = trace(incline(30.0, mu, velocity=v0))
    assert run["status"] == "completed" and run["halvings"].sum() == 0
    exact = v0 + G * (np.sin(a) - mu * np.cos(a)) * run["t"]
    assert np.max(np.abs(run["v"] + mu * run["vn"] - exact)) <= 1e-5
    assert np.min(run["min_gap"]) >= -1e-12


def test_smooth_friction_does_not_depend_on_p_and_k():
    """An elastic disk thrown at an angle with μ = 0.3 (nodes stick, slip and open): the
    augmentation p and the multiplier scale k steer the Newton path only."""
    sim = case("disk_drop").build(refinements=2, slide_velocity=1.0, friction=0.3, t_end=0.006)
    ref = trace(sim)
    assert ref["status"] == "completed"
    for p, k in [(1e-6, 1.0), (1e6, 1.0), (1.0, 1e-6), (1.0, 1e6)]:
        opts = dataclasses.replace(sim.options, penalty_scale=p, multiplier_scale=k)
        run = trace(sim.replace(options=opts))
        assert run["status"] == "completed"
        for probe in ("vx_center", "vy_center", "omega"):
            scale = np.max(np.abs(ref[probe]))
            # the laws are met to the gap tolerance (1e-12 of the size) at every step: the
            # answers agree far below the 1e-8 the rigid cases are held to
            np.testing.assert_allclose(run[probe], ref[probe], rtol=0, atol=1e-8 * scale)


def test_a_slide_s_friction_leaves_no_negative_numerical_dissipation(tmp_path):
    """An elastic disk thrown onto the plane at 2 m/s along it (μ = 0.5, e_N = 0) at ρ∞ = 1,
    where the generalized-α step is the trapezoidal rule: the energy the ledger books to the
    integrator must be the closing of a nondissipative scheme, near 0. With the friction
    work read as λ_T,n+1 × slip it was −0.203 J (of 4.24 J of friction), the overbooking
    h/2 Σ λ̇_T·w_T of a force that rises and falls with λ_N; with the mean of λ_T,n and
    λ_T,n+1 it is +5.1e-4 J."""
    sim = case("disk_drop").build(refinements=2, slide_velocity=2.0, friction=0.5, t_end=0.004)
    sim = sim.replace(options=dataclasses.replace(sim.options, rho_inf=1.0))
    ledger = run(sim, tmp_path, progress=False, frames=False)["energy_ledger"]
    friction = ledger["friction_dissipation"]
    assert friction > 1.0  # the disk slides through the whole contact
    # what is left is the step's O(h²) error, not round-off: 1.3e-4 of the friction here
    # (disk_drop's default mesh: 2.6e-4 J at h = 5e-5 s, 1.9e-5 J at h/4), 8 times below
    assert abs(ledger["numerical_dissipation"]) < 1e-3 * friction


def test_an_oblique_frictional_impact_between_two_disks():
    """Node-to-segment pairs with friction (``two_disks``, centres 4 cm apart across the
    line of approach, μ = 0.3) at the case's step Δx/c: the pair forces are equal and
    opposite, so both momentum components stay zero; the impact is point-symmetric, so both
    disks leave spinning the same way at the same rate; friction and e_N = 0 only take
    energy out."""
    sim = case("two_disks").build(
        refinements=2, offset=0.04, friction=0.3, t_end=0.01, method="node-to-surface"
    )
    model = sim.model
    left, right = model.bodies
    probes = {}
    for name, body in (("L", left), ("R", right)):
        for axis in (0, 1):
            probes |= centre_of_mass_probes(model, body, axis, name=name)
        probes[f"omega_{name}"] = spin_probe(model, body)
    run = trace(sim.replace(probes=probes))
    assert run["status"] == "completed" and run["halvings"].sum() == 0
    # momentum sums of two 1 kg/m bodies at 1 m/s: round-off is ~1e-16
    for axis in "xy":
        assert np.max(np.abs(run[f"v{axis}_L"] + run[f"v{axis}_R"])) <= 1e-12
    assert abs(run["vy_L"][-1]) > 0.1  # deflected
    assert run["omega_L"][-1] > 1.0  # friction spins the disks counter-clockwise ...
    # ... equally: the two meshes are one rotated by 180° (1e-9: the Newton tolerances)
    assert run["omega_R"][-1] == pytest.approx(run["omega_L"][-1], rel=1e-9)
    ke0 = run["kinetic"][0]
    assert np.max(run["total"] - run["total"][0]) <= 1e-3 * ke0
    assert run["total"][-1] < run["total"][0] - 0.01 * ke0
    assert np.min(run["min_gap"]) >= -1e-12


def test_a_ball_thrown_obliquely_slips_against_its_motion():
    """A 3D Neo-Hookean ball (``Solid.ball``, 2 refinements) thrown at (2, 0.5, −1) m/s onto
    a plane with μ = 0.1, at Δx/c: every pressed node slips against the motion along the
    plane, so the plane's tangential impulse is μ times its normal one and points against
    (2, 0.5). The patch's nodes slip in directions that differ by the spin the friction
    gives (measured: 3e-6 of the ratio, 5e-5 of the direction): bounds of 1e-4 and 1e-3."""
    from fecontact import Model, Simulation
    from fecontact.bodies import NeoHookean, Solid
    from fecontact.contact import Contact, Plane
    from fecontact.scenes import wave_step

    radius, mu = 0.05, 0.1
    ball = Solid.ball([0, 0, radius + 0.002], radius, 2, NeoHookean(E=1e7, nu=0.3, rho=1e3))
    model = Model([ball], [Contact(ball, Plane([0, 0, 0], [0, 0, 1.0]), friction=mu)])
    probes = {}
    for axis in range(3):
        probes |= centre_of_mass_probes(model, ball, axis)
    v0 = np.array([2.0, 0.5, -1.0])
    sim = Simulation(
        model, dt=wave_step(ball, 1.0), t_end=0.008, probes=probes, v0=model.translation(ball, v0)
    )
    run = trace(sim)
    assert run["status"] == "completed" and run["halvings"].sum() == 0
    v = np.array([run[f"v{a}_center"][-1] for a in "xyz"])
    tangential = ball.mass * (v[:2] - v0[:2])
    normal = ball.mass * (v[2] - v0[2] + G * run["t"][-1])
    assert normal > 0.0 and v[2] > 0.5  # it bounced
    assert np.linalg.norm(tangential) == pytest.approx(mu * normal, rel=1e-4)
    against = -v0[:2] / np.linalg.norm(v0[:2])
    np.testing.assert_allclose(tangential / np.linalg.norm(tangential), against, atol=1e-3)
    assert np.min(run["min_gap"]) >= -1e-12
