"""Coulomb friction between a 2D solid and a Beam2D (fecontact.contact.beam_on_solid): the
solid's nodes slip on the beam's surface and the beam's nodes on the solid's boundary, each
against the point of the beam's section that touches (the section's turn moves it). Checked
against the slips' derivatives and a rigid motion, and against a body sliding under gravity:
a stop at μg, an incline held for tan α < μ and slid down at g(sin α − μ cos α) above, the
strip sliding on a block as the block on the strip, an oblique throw whose tangential impulse
stays in the cone, with friction's work never positive and nothing created, and the throw
between a clamped strip's nodes as on a plane."""

import numpy as np
import pytest

from fecontact import Beam2D, Contact, Material, Model, Probe, Section, Simulation, run, simulate
from fecontact.bodies import Solid
from fecontact.bodies.materials import LinearElastic
from fecontact.contact import Plane
from fecontact.testing import slip_derivative_errors
from fecontact.time import IntegratorOptions

STEEL = Material(210e9, rho=7850.0)
G, C, MU = 9.81, 0.005, 0.3  # gravity (m/s²), the strip's half thickness (m), Coulomb's μ


def clamped_strip():
    """A steel strip 1 m long, 2c thick, every node clamped: a flat face at y = ±c."""
    strip = Beam2D.straight([-0.5, 0.0], [0.5, 0.0], 20, STEEL, Section.rectangle(0.02, 2 * C))
    for i in range(strip.n_nodes):
        strip.clamp(i)
    return strip


def gravity(alpha):
    return (G * np.sin(alpha), -G * np.cos(alpha))


def block_on_strip(alpha=0.0, mu=MU):
    """A stiff 4 × 2 cm block (0.8 kg) resting on the clamped strip, gravity tilted by α."""
    strip = clamped_strip()
    block = Solid.rectangle([-0.02, C], [0.02, C + 0.02], (2, 1), LinearElastic(1e9, 0.3, 1e3))
    pair = Contact(block, strip, clearance=C, friction=mu)
    return Model([block, strip], [pair], gravity=gravity(alpha)), block


def strip_on_block(alpha=0.0):
    """A free 10 cm strip (4 elements) resting on a 1 m block clamped at its base."""
    block = Solid.rectangle([-0.5, -0.1], [0.5, 0.0], (10, 2), LinearElastic(1e9, 0.3, 1e3))
    block.fix(block.nodes_where(lambda x: x[1] < -0.1 + 1e-9))
    strip = Beam2D.straight([-0.05, C], [0.05, C], 4, STEEL, Section.rectangle(0.02, 2 * C))
    pair = Contact(block, strip, clearance=C, friction=MU)
    return Model([block, strip], [pair], gravity=gravity(alpha)), strip


def travel(model, body, speed, t_end=0.05, options=None):
    """Times and the mean x of ``body``'s nodes, thrown along x at ``speed`` (m/s)."""
    s = model.body_slice(model.bodies.index(body))
    v0 = model.translation(body, (speed, 0.0))
    ts, xs = [], []
    for st in simulate(model, 1e-3, t_end, options, v0=v0):
        ts.append(st.t)
        xs.append(body.positions(st.q[s]).mean(axis=0)[0])
    return np.array(ts), np.array(xs)


# -- the rows --------------------------------------------------------------------------------
def test_slip_rows_are_the_derivatives_of_the_slips_and_a_rigid_motion_slips_nothing():
    # a strip over a block, both moved by q: the block's top nodes on the strip's surface
    # (the pair) and the strip's nodes on the block's face (its companion)
    rng = np.random.default_rng(0)
    block = Solid.rectangle([0.0, -0.1], [0.3, 0.0], (3, 1), LinearElastic(1e8, 0.3, 1e3))
    strip = Beam2D.straight(
        [-0.015, 0.006], [0.315, 0.006], 8, STEEL, Section.rectangle(0.02, 0.01)
    )
    pair = Contact(block, strip, clearance=0.005, friction=MU)
    model = Model([block, strip], [pair], gravity=(0.0, 0.0))
    rows = pair.companions[0]
    rows.detect_within(0.02)
    q = 1e-3 * rng.normal(size=model.n)
    # q_n: the configuration q turned by 0.3 rad and shifted, both bodies (θ too)
    phi, shift = 0.3, np.array([0.05, -0.02])
    R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    q_n = np.zeros(model.n)
    sb, ss = model.body_slice(0), model.body_slice(1)
    q_n[sb] = ((block.positions(q[sb]) - shift) @ R - block.X).ravel()
    qs = q[ss].reshape(-1, 3).copy()
    qs[:, :2] = (strip.positions(q[ss]) - shift) @ R - strip.X
    qs[:, 2] -= phi
    q_n[ss] = qs.ravel()
    for p in (pair, rows):
        _, _, T = p.tangents(q)
        errors, scale = slip_derivative_errors(p, model, q, T)
        # second order: measured 8.3e-7 → 8.3e-9 (the pair), 1.3e-7 → 1.3e-9 (its companion)
        # from ε = 1e-5 to 1e-6; the round-off of a difference over 2ε, 1e-16/1e-6, is far
        # below either
        assert scale > 1.0 and errors[1] < 2e-8 and errors[0] > 50.0 * errors[1]
        # a rigid motion moves a row's touching point with its partner's: what remains is
        # the node's gap g n turned, −g T·Rᵀn, zero where the point touches
        g = p.evaluate(q)[0]
        held = np.isfinite(g) & (np.abs(T).sum(axis=(1, 2)) > 0.0)
        assert held.sum() >= 8  # (top nodes, strip nodes over the face)
        n = np.stack([-T[held, 0, 1], T[held, 0, 0]], axis=1)
        expected = -g[held] * np.einsum("md,md->m", T[held, 0], n @ R)
        # round-off on coordinates of order 0.3 m
        assert np.abs(p.slips(q, q_n, T)[held, 0] - expected).max() < 1e-15


# -- closed forms ----------------------------------------------------------------------------
def test_a_block_thrown_along_a_clamped_strip_decelerates_at_mu_g():
    ts, xs = travel(*block_on_strip(), 0.5)
    exact = 0.5 * ts - 0.5 * MU * G * ts**2
    # measured 3.2e-10 m on 0.021 m, in the first steps: the block's elastic feet under μ m g
    assert np.abs(xs - exact).max() < 1e-8


def test_a_strip_thrown_along_a_block_decelerates_at_mu_g():
    ts, xs = travel(*strip_on_block(), 0.5)
    exact = 0.5 * ts - 0.5 * MU * G * ts**2
    # measured 1.1e-8 m on 0.021 m, in the first steps: the block's top, sheared by the
    # strip's friction
    assert np.abs(xs - exact).max() < 1e-7


@pytest.mark.parametrize("build", [block_on_strip, strip_on_block])
@pytest.mark.parametrize("tan_alpha", [0.255, 0.423])
def test_an_incline_holds_below_the_friction_angle_and_slides_above(build, tan_alpha):
    alpha = np.arctan(tan_alpha)
    model, body = build(alpha)
    ts, xs = travel(model, body, 0.0, t_end=0.03)
    a = max(G * (np.sin(alpha) - MU * np.cos(alpha)), 0.0)
    # held: the settling of the released body on its elastic partner (measured 3.5e-8 m for
    # the strip on the block's sheared top, 1.1e-9 m for the block, the same over 0.1 s: no
    # creep); sliding: 1.1e-8 m and 2.9e-10 m on a slide of 0.5 mm
    assert np.abs(xs - 0.5 * a * ts**2).max() < 1e-7


def test_friction_books_mu_m_g_times_the_slide_and_creates_nothing(tmp_path):
    model, block = block_on_strip()
    v0 = model.translation(block, (0.5, 0.0))
    summary = run(Simulation(model, 1e-3, 0.05, v0=v0, name="slide"), tmp_path, frames=False)
    ledger = summary["energy_ledger"]
    slide = 0.5 * 0.05 - 0.5 * MU * G * 0.05**2
    # measured 1.1e-5 relative (2.6e-6 at h/2, 4.8e-6 at h/4: not a truncation error of h)
    assert ledger["friction_dissipation"] == pytest.approx(MU * block.mass * G * slide, rel=1e-4)
    assert ledger["created"] == 0.0 and not summary["warnings"]


def test_the_runs_do_not_depend_on_p_and_k():
    ref = travel(*block_on_strip(), 0.5, t_end=0.02)[1]
    for p, k in ((1e3, 1.0), (1.0, 1e-2)):
        options = IntegratorOptions(penalty_scale=p, multiplier_scale=k)
        xs = travel(*block_on_strip(), 0.5, t_end=0.02, options=options)[1]
        # measured 7.4e-11 m (p × 1000), 7.8e-14 m (k ÷ 100) on 0.01 m: the solves'
        # tolerances
        assert np.abs(xs - ref).max() < 1e-9


def disk_throw(mu, tmp_path):
    """An elastic disk (r = 5 cm) thrown at (2, −1) m/s onto the clamped strip, no gravity:
    the disk's momentum change along and across the strip, and the run's summary."""
    strip = clamped_strip()
    disk = Solid.disk([0.0, C + 0.0501], 0.05, 2, LinearElastic(1e7, 0.3, 1e3))
    pair = Contact(disk, strip, clearance=C, friction=mu)
    model = Model([disk, strip], [pair], gravity=(0.0, 0.0))
    v0 = model.translation(disk, (2.0, -1.0))
    s = model.body_slice(0)
    M = model.M[s][:, s]

    def momentum(axis):
        return Probe(lambda m, st: (M @ st.v[s])[axis::2].sum(), "kg·m/s")

    probes = {"px": momentum(0), "py": momentum(1)}
    sim = Simulation(model, 1e-4, 0.012, v0=v0, probes=probes, name="throw")
    summary = run(sim, tmp_path, frames=False)
    history = np.genfromtxt(tmp_path / "history.csv", delimiter=",", names=True)
    dP = [history[k][-1] - history[k][0] for k in ("px", "py")]
    return dP, summary


@pytest.mark.parametrize("mu", [0.1, 1.0])
def test_an_oblique_throw_takes_a_tangential_impulse_inside_the_cone(mu, tmp_path):
    dP, summary = disk_throw(mu, tmp_path)
    tangential, normal = dP
    assert normal > 10.0  # kg·m/s per m: the disk struck the strip and left it
    # each row's |Λ_T| ≤ μΛ_N in its own frame; the strip's nodes' rows push along the
    # disk's facets, tilted from the strip (frictionless: +0.0035 ΔP_n along the strip).
    # Measured −0.0953 ΔP_n at μ = 0.1 (every node slips), −0.537 at μ = 1 (nodes grip)
    assert -mu * normal < tangential < -0.09 * normal
    ledger = summary["energy_ledger"]
    assert summary["friction_work"] > 0.0  # (dissipated: friction's work is its negative)
    assert ledger["friction_dissipation"] == pytest.approx(summary["friction_work"])
    assert not summary["warnings"]
    # the strip's nodes' rows and the disk's nodes' rows meet under the disk: at μ = 1
    # Newton stopped short on two solves, which the law's cases solved (Gauss–Seidel before)
    assert summary["friction_solver"]["gauss_seidel_solves"] == 0
    # measured 0.0168 J created of 19.1 J at μ = 0.1, 0 at μ = 1; the frictionless throw
    # creates 0.0149 J (the pair's impact without friction, as before)
    assert ledger["created"] < 1e-3 * ledger["scale"]


def test_a_disk_on_a_clamped_strip_between_its_nodes_is_a_disk_on_a_plane():
    # a strip of 3 elements: no strip node comes under the disk during the throw, so the
    # disk's node rows alone hold it, on the strip's flat face at y = c, slipping against
    # the clamped sections' points (μ = 1: nodes stick and slip in turn)
    strip = Beam2D.straight([-0.5, 0.0], [0.5, 0.0], 3, STEEL, Section.rectangle(0.02, 2 * C))
    for i in range(strip.n_nodes):
        strip.clamp(i)
    ends = []
    for partner, clearance in ((strip, C), (Plane([0.0, C], [0.0, 1.0]), 0.0)):
        disk = Solid.disk([0.0, C + 0.0501], 0.05, 2, LinearElastic(1e7, 0.3, 1e3))
        bodies = [disk, strip] if partner is strip else [disk]
        pair = Contact(disk, partner, clearance=clearance, friction=1.0)
        model = Model(bodies, [pair], gravity=(0.0, 0.0))
        v0 = model.translation(disk, (2.0, -1.0))
        *_, st = simulate(model, 1e-4, 0.012, v0=v0)
        s = model.body_slice(0)
        ends.append((st.q[s], st.v[s]))
    (q, v), (q_plane, v_plane) = ends
    # measured 2.3e-16 m and 3.2e-13 m/s on velocities of 3 m/s: round-off of the solves
    assert np.abs(q - q_plane).max() < 1e-13
    assert np.abs(v - v_plane).max() < 1e-10
