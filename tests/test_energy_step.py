"""The energy-decaying smooth step (fecontact.time.energy_step) and its discrete gradient
(fecontact.bodies.beam_energy): exact energy identities, second order, no growth where
generalized-α blows up, and its input rules."""

import dataclasses

import numpy as np
import pytest
from test_checkpoint import resumes_identically
from test_resting import flat_work

from fecontact import Contact, Model, Plane
from fecontact.bodies import Beam2D, Material, Section
from fecontact.bodies.beam_energy import beam_energy_force, element_strains
from fecontact.bodies.beam_kernels import beam_internal
from fecontact.errors import InputError
from fecontact.testing import case, observed_order, trace
from fecontact.time import IntegratorOptions, simulate
from fecontact.time.energy_step import dissipation

MATERIAL = Material(E=70e9, nu=0.33, rho=2700.0)
SECTION = Section.rectangle(0.02, 0.002)
ENERGY = {"scheme": "energy-decaying"}


def strip(n=5):
    return Beam2D.straight([0.0, 0.0], [0.3, 0.1], n, MATERIAL, SECTION)


def random_pair(beam, seed=0):
    """Two configurations with rotations of order 1 rad and strains of order 1e-2."""
    rng = np.random.default_rng(seed)
    scale = np.tile([1e-2, 1e-2, 1.0], beam.ndof // 3)
    q0 = rng.normal(size=beam.ndof) * scale
    return q0, q0 + rng.normal(size=beam.ndof) * scale


def test_the_discrete_gradient_is_exact():
    """f̄·(q₁ − q₀) = W(q₁) − W(q₀) + χΣℓΔε·C(Δε − d) to round-off, at large rotations, and
    f̄(q, q) is the internal force."""
    beam = strip()
    el, n = beam._el, beam.ndof
    q0, q1 = random_pair(beam)
    W0, f0, _ = beam_internal(el, q0, n, False)
    W1 = beam_internal(el, q1, n, False)[0]
    d = np.random.default_rng(1).normal(size=(len(el.ell), 3)) * 1e-3
    de = element_strains(el, q1) - element_strains(el, q0)
    for chi in (0.0, 0.3):
        f, _ = beam_energy_force(el, q0, q1, chi, d, n, tangent=False)
        work = W1 - W0 + chi * np.sum(el.ell[:, None] * de * el.C * (de - d))
        # each side sums energies of order |W|: round-off of a few ulps of them
        assert f @ (q1 - q0) == pytest.approx(work, rel=1e-12, abs=1e-12 * (W0 + W1))
    f_same, _ = beam_energy_force(el, q0, q0, 0.0, 0.0, n, tangent=False)
    assert np.allclose(f_same, f0, rtol=0, atol=1e-12 * np.abs(f0).max())


def test_the_tangent_is_the_derivative():
    """The complex-step tangent against central differences (truncation ~ε^(2/3) of the
    force scale), and half the internal tangent where q₁ = q₀ (the midpoint's own)."""
    beam = strip()
    el, n = beam._el, beam.ndof
    q0, q1 = random_pair(beam, seed=2)
    d = np.full((len(el.ell), 3), 1e-3)
    f, Ke = beam_energy_force(el, q0, q1, 0.2, d, n)
    K = np.zeros((n, n))
    for dofs, k in zip(el.dofs, Ke, strict=True):
        K[np.ix_(dofs, dofs)] += k
    J = np.empty((n, n))
    for i in range(n):
        step = 1e-7 * (1.0 if i % 3 == 2 else 0.1)
        dq = np.eye(n)[i] * step
        up = beam_energy_force(el, q0, q1 + dq, 0.2, d, n, False)[0]
        down = beam_energy_force(el, q0, q1 - dq, 0.2, d, n, False)[0]
        J[:, i] = (up - down) / (2 * step)
    assert np.abs(J - K).max() <= 1e-6 * np.abs(K).max()
    _, Kh = beam_energy_force(el, q0, q0, 0.0, 0.0, n)
    Kt = beam_internal(el, q0, n, True)[2]
    assert np.allclose(2 * Kh, Kt, rtol=0, atol=1e-12 * np.abs(Kt).max())


def swinging_strip(n=4):
    """The founding pendulum without its stop: a pinned strip with a 0.14 kg tip mass falling
    from the horizontal, in free flight with large rotations."""
    beam = Beam2D.straight([0.0, 0.0], [0.3, 0.0], n, MATERIAL, SECTION)
    beam.pin(0).add_mass(-1, 0.14)
    return Model([beam], gravity=(0.0, -9.81))


def energies(model, states):
    return np.array(
        [
            model.kinetic_energy(s.v) + model.strain_energy(s.q) + model.potential_energy(s.q)
            for s in states
        ]
    )


def test_rho_inf_one_conserves_energy():
    """ρ∞ = 1 is the energy-conserving midpoint step: over 0.3 s of swinging (the strip's
    axial mode at hω ≈ 7.9 included) the energy stays at its start to the Newton tolerance
    (1e-8 of the forces, over 300 steps) while 0.43 J turn into kinetic energy."""
    model = swinging_strip()
    opts = IntegratorOptions(rho_inf=1.0, **ENERGY)
    states = list(simulate(model, 1e-3, 0.3, opts))
    E = energies(model, states)
    peak = max(model.kinetic_energy(s.v) for s in states)
    assert peak > 0.3
    assert np.abs(E - E[0]).max() <= 1e-6 * peak


@pytest.mark.parametrize("rho_inf", [0.5, 0.8])
def test_the_modified_energy_never_grows(rho_inf):
    """H = E + (η/2)|Δv|²_M + (χ/2)Σℓ|Δε|²_C does not grow over any step (module docstring
    of energy_step), at a constant step; E itself may, by the stored second differences."""
    model = swinging_strip()
    beam = model.bodies[0]
    chi = eta = dissipation(rho_inf)
    opts = IntegratorOptions(rho_inf=rho_inf, **ENERGY)
    states = list(simulate(model, 1e-3, 0.3, opts))
    E = energies(model, states)
    C, ell = beam._el.C, beam._el.ell
    H = []
    for k in range(1, len(states)):
        dv = states[k].v - states[k - 1].v
        de = beam.element_strains(states[k].q) - beam.element_strains(states[k - 1].q)
        stored = 0.5 * eta * dv @ (model.M_full @ dv) + 0.5 * chi * np.sum(ell * (C * de**2).T)
        H.append(E[k] + stored)
    H = np.array(H)
    peak = max(model.kinetic_energy(s.v) for s in states)
    # the Newton tolerance bounds what each step leaves of its balance (see above)
    assert np.diff(H).max() <= 1e-7 * peak
    assert H[-1] < H[0]  # and the stiff modes are damped


def test_second_order_in_free_flight():
    """The tip of a softer strip (E / 1000: every mode resolved, hω ≤ 0.6) after 0.2 s of
    swinging converges at order 2 against h/32 (measured 2.11, 2.05)."""
    beam = Beam2D.straight([0, 0], [0.3, 0], 4, Material(E=7e7, nu=0.33, rho=2700.0), SECTION)
    beam.pin(0).add_mass(-1, 0.14)
    model = Model([beam], gravity=(0.0, -9.81))
    opts = IntegratorOptions(rho_inf=0.8, **ENERGY)

    def tip(h):
        *_, last = simulate(model, h, 0.2, opts)
        return beam.positions(last.q)[-1]

    hs = [2e-3, 1e-3, 5e-4]
    ref = tip(hs[-1] / 16)
    err = [np.linalg.norm(tip(h) - ref) for h in hs]
    assert observed_order(hs, err) == pytest.approx(2.0, abs=0.15)


@pytest.mark.parametrize("dt", [1.1e-3, 1.5e-3])
def test_the_pendulum_keeps_its_energy_where_generalized_alpha_blows_up(dt):
    """e_N = 1, ρ∞ = 0.8: generalized-α blows up at these steps (at 0.37 s and 1.05 s,
    README); the energy-decaying step runs 3 s with its energy never 1 % of the peak kinetic
    energy above the start (measured: 0 at both steps)."""
    sim = case("flexible_pendulum").build(restitution=1.0)
    sim = sim.replace(options=dataclasses.replace(sim.options, rho_inf=0.8, **ENERGY))
    r = trace(sim, dt=dt, t_end=3.0)
    assert r["status"] == "completed"  # (a step halved to converge counts as any)
    growth = (r["total"].max() - r["total"][0]) / r["kinetic"].max()
    assert growth <= 0.01
    assert r["min_gap"].min() >= -1e-12 * 0.3


@pytest.mark.parametrize(
    "change, why",
    [
        ({"rho_inf": 0.2}, "rho_inf"),
        ({"integrator": "moreau"}, "nsga"),
        ({"smooth_contact": "on"}, "smooth_contact"),
    ],
)
def test_the_scheme_states_where_it_applies(change, why):
    sim = case("flexible_pendulum").build()
    # (the scheme given to another integrator is refused as the options are made)
    with pytest.raises(InputError, match=f"scheme = 'energy-decaying'.*{why}"):
        next(simulate(sim.model, 1e-3, 0.01, dataclasses.replace(sim.options, **ENERGY, **change)))


def test_solids_and_linear_beams_are_refused():
    for name in ("two_disks",):
        sim = case(name).build()
        opts = dataclasses.replace(sim.options, smooth_contact="off", **ENERGY)
        with pytest.raises(InputError, match="Beam2D"):
            next(simulate(sim.model, sim.dt, sim.dt, opts))
    beam = Beam2D.straight([0, 0], [0.3, 0], 4, MATERIAL, SECTION, linear=True).clamp(0)
    with pytest.raises(InputError, match="Beam2D"):
        next(simulate(Model([beam]), 1e-3, 1e-3, IntegratorOptions(**ENERGY)))


def test_a_resumed_run_is_the_same(tmp_path):
    """q_{n−1} travels in the checkpoint: a resumed run equals the run in one go."""
    args = ["--checkpoint-every", "100", "--set", "scheme=energy-decaying"]
    args += ["--set", "restitution=1", "--set", "rho_inf=0.8"]
    resumes_identically("flexible_pendulum", args, "0.45", "0.35", tmp_path)


def test_no_blow_up_warning_for_the_energy_decaying_step():
    """The warning of ρ∞ > 0.5 with elastic impacts on a flexible body is generalized-α's;
    it names the energy-decaying step as the way out, which itself does not warn."""
    sim = case("flexible_pendulum").build(restitution=1.0)
    alpha = sim.replace(options=dataclasses.replace(sim.options, rho_inf=0.8))
    assert any("energy-decaying" in w for w in alpha.warnings())
    energy = sim.replace(options=dataclasses.replace(sim.options, rho_inf=0.8, **ENERGY))
    assert not any("blow up" in w for w in energy.warnings())


def test_rho_inf_one_is_warned_of():
    sim = case("flexible_pendulum").build()
    energy = sim.replace(options=dataclasses.replace(sim.options, rho_inf=1.0, **ENERGY))
    assert any("massless rotations" in w for w in energy.warnings())


def test_a_beam_rests_on_a_plane():
    """A 20-element strip lying flat on a plane under gravity, every node in contact, 3 s:
    gaps at zero, no velocity, work per step flat (as generalized-α, tests/test_resting.py;
    measured: gaps ≥ −4e-21 m, speeds ≤ 7e-13 m/s, 3 iterations every step)."""
    beam = Beam2D.straight([0, 0], [0.4, 0], 20, MATERIAL, SECTION)
    model = Model([beam], [Contact(beam, Plane([0, 0], [0, 1]))])
    states = list(simulate(model, 1e-3, 3.0, IntegratorOptions(**ENERGY)))[1:]
    gaps = np.array([st.gaps for st in states])
    assert gaps.min() >= -1e-10 and np.abs(gaps).max() <= 1e-10
    assert max(np.abs(st.v).max() for st in states) < 1e-10
    assert flat_work(np.array([st.newton_iterations for st in states]))
