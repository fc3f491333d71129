r"""Poisson's impact law: single impacts on a rough floor against closed-form outcomes, the
cases where it must give Newton's answer, the decompression solver, and Kane's chain.

Closed forms. A rigid body (mass m, inertia I about its centre) strikes the floor y = 0 at
a point r = (r_x, r_y) from its centre, with centre velocity (u, −V) and spin ω (no
gravity). With impulses (P_T, P_N) at the point, along +x and +y,

    Δv = (P_T, P_N)/m,   Δω = (r_x P_N − r_y P_T)/I,

the normal rate ġ = v_y + ω r_x and the slip s = v_x − ω r_y change by D (P_N, P_T) with

    D_NN = 1/m + r_x²/I,   D_TT = 1/m + r_y²/I,   D_NT = −r_x r_y/I.

The two-phase law as implemented: compression from (ġ₀ = −V, s₀) with Newton's law at
e = 0 and Coulomb's law on the slip at its end; decompression with P_N,d ≥ e P_N,c, again
with Coulomb's law on the slip at its end.

*Disk* (radius R, I = mR²/2, r = (0, −R)): D_NT = 0, D_NN = 1/m, D_TT = 3/m, so the
compression takes P_N,c = mV and the slip falls by 3/m per unit tangential impulse, which
is at most μ mV: it slips through (P_T,c = −μ mV) if s₀ > 3μV, else it stops (P_T,c =
−m s₀/3). The decompression takes P_N,d = e mV (nothing presses the slip back) and
P_T,d = −min(s_c, 3μ e V) m/3. In all: P_N = (1 + e) mV and P_T = −m min(s₀, 3μ(1+e)V)/3,
i.e. slip that continues (s₀ > 3μ(1 + e)V), stops in restitution, or stops in compression
(s₀ ≤ 3μV). Routh's continuous slip (Stronge, Impact Mechanics, ch. 5) gives the same:
with D_NT = 0 the slip falls linearly in the normal impulse and stays zero once it stops.

*Bar* (length L, I = mL²/12, striking with its end r = −(L/2)(cos θ, sin θ), θ = 45°,
falling without spin, u = 0.5 m/s, V = 1 m/s, μ = 0.5, e = 0.5): D_NN = D_TT = 2.5/m,
D_NT = −1.5/m. Compression: the sticking impulse P = −D⁻¹(ġ₀, s₀) lies inside the cone,
so the contact ends the compression stuck. Decompression from ġ = s = 0 with P_N ≥ f =
e P_N,c: sticking would need |P_T| = (|D_NT|/D_TT) f = 0.6 f > μ f, so it slips; slip
forward (P_T = −μ f) would leave the slip rate at (D_NT − μ D_TT) f < 0, against the
assumption, while slip backward (P_T = +μ f) leaves (D_NT + μ D_TT) f < 0: the slip
reverses, at the floor P_N,d = f (ġ⁺ = (D_NN + μ D_NT) f > 0). Routh's continuous slip
differs: the forward slip stops at P₁ = s₀/(μ D_TT − D_NT) within the compression, reverses
(μ < |D_NT|/D_TT: no stick), the compression ends at ġ = 0, and the decompression adds
e times the compression's normal impulse with the slip still backward; it ends with a
different velocity and both lose energy. The test uses the configuration at which the
law acts (the position correction turns the bar by about 1e-5 rad).
"""

import numpy as np
import pytest

from fecontact import InputError, Model, Pin, Simulation, run
from fecontact.bodies import Box, Disk, Polygon, RigidBody2D, RigidBody3D
from fecontact.contact import Contact, Plane
from fecontact.contact.restitution import solve_decompression
from fecontact.testing import case, trace
from fecontact.time import IntegratorOptions, simulate

MU, E = 0.3, 0.5
R, MASS = 0.1, 1.0


def _disk(u, V, spin, law, integrator="nsga", e=E, mu=MU):
    disk = RigidBody2D.uniform(MASS, (0.0, R + 1e-4), Disk(R))
    floor = Contact(disk, Plane([0.0, 0.0], [0.0, 1.0]), restitution=e, friction=mu)
    model = Model([disk], [floor], (0.0, 0.0))
    opts = IntegratorOptions(impact_law=law, integrator=integrator)
    states = list(simulate(model, 1e-3, 3e-3, opts, v0=disk.velocity(u, -V, spin)))
    return model, states


def _disk_exact(u, V, spin):
    s0 = u + spin * R
    P_N = (1 + E) * MASS * V
    P_T = -MASS * min(s0, 3 * MU * (1 + E) * V) / 3  # (s0 > 0 in the cases below)
    return np.array([u + P_T / MASS, -V + P_N / MASS, spin + 2 * P_T / (MASS * R)])


@pytest.mark.parametrize("integrator", ["nsga", "moreau"])
@pytest.mark.parametrize(
    "spin, regime",
    [(10.0, "continues"), (0.0, "stops in restitution"), (-5.0, "stops in compression")],
)
def test_disk_strikes_a_rough_floor(integrator, spin, regime):
    """u = V = 1 m/s: s₀ = 1 + 0.1 ω against 3μV = 0.9 and 3μ(1 + e)V = 1.35 m/s."""
    u, V = 1.0, 1.0
    s0 = u + spin * R
    assert {
        "continues": s0 > 3 * MU * (1 + E) * V,
        "stops in restitution": 3 * MU * V < s0 <= 3 * MU * (1 + E) * V,
        "stops in compression": s0 <= 3 * MU * V,
    }[regime]
    model, states = _disk(u, V, spin, "poisson", integrator)
    v = states[-1].v
    exact = _disk_exact(u, V, spin)
    # one impulse solved in closed form per case of the law: round-off of a few operations
    np.testing.assert_allclose(v, exact, rtol=1e-12, atol=1e-12 * np.abs(exact).max())
    assert model.kinetic_energy(v) <= model.kinetic_energy(states[0].v)
    # friction's share, Routh's: with D_NT = 0 the slip falls linearly in P_T in each phase,
    # so it takes the slip's kinetic energy, (s₀² − s⁺²)/(2 D_TT) = m (s₀² − s⁺²)/6
    s1 = v[0] + v[2] * R
    friction = MASS * (s0**2 - s1**2) / 6
    np.testing.assert_allclose(states[-1].friction.work, friction, rtol=1e-12)


def _bar(u, V, law, mu=0.5, e=0.5, theta=np.pi / 4, L=1.0):
    w = 0.02 * L
    diamond = Polygon([[-L / 2, 0.0], [0.0, -w / 2], [L / 2, 0.0], [0.0, w / 2]])
    c = 0.5 * L * np.array([np.cos(theta), np.sin(theta)]) + [0.0, 1e-4]
    bar = RigidBody2D(MASS, MASS * L**2 / 12, c, angle=theta, shape=diamond)
    end = Contact(bar, Plane([0.0, 0.0], [0.0, 1.0]), nodes=[0], restitution=e, friction=mu)
    model = Model([bar], [end], (0.0, 0.0))
    opts = IntegratorOptions(impact_law=law)
    states = list(simulate(model, 1e-3, 1e-3, opts, v0=bar.velocity(u, -V, 0.0)))
    return model, states, bar


def _delassus(phi, L=1.0):
    I = MASS * L**2 / 12
    rx, ry = -0.5 * L * np.cos(phi), -0.5 * L * np.sin(phi)
    D = np.array([[1 / MASS + rx**2 / I, -rx * ry / I], [-rx * ry / I, 1 / MASS + ry**2 / I]])
    return D, rx, ry, I


def _velocities(u, V, P_N, P_T, rx, ry, I):
    return np.array([u + P_T / MASS, -V + P_N / MASS, (rx * P_N - ry * P_T) / I])


def test_bar_strikes_with_its_end_and_the_slip_reverses():
    u, V, mu, e = 0.5, 1.0, 0.5, 0.5
    model, states, bar = _bar(u, V, "poisson", mu, e)
    # the impact is located: it acts at the instant of touching, before the bar turns
    D, rx, ry, I = _delassus(bar.angle)
    assert mu < abs(D[0, 1]) / D[1, 1]  # sticking is outside the cone: the slip reverses
    # compression: stuck at its end, inside the cone
    Pc = np.linalg.solve(D, [V, -u])
    assert Pc[0] > 0 and abs(Pc[1]) < mu * Pc[0]
    # decompression at the floor, slipping backward
    f = e * Pc[0]
    assert (D[1, 0] + mu * D[1, 1]) * f < 0 and (D[0, 0] + mu * D[0, 1]) * f > 0
    P_N, P_T = Pc[0] + f, Pc[1] + mu * f
    exact = _velocities(u, V, P_N, P_T, rx, ry, I)
    v = states[-1].v
    np.testing.assert_allclose(v, exact, rtol=1e-12, atol=1e-12 * np.abs(exact).max())
    slip = v[0] - v[2] * ry
    assert u > 0 and slip < 0  # the slip reversed
    T0, T1 = model.kinetic_energy(states[0].v), model.kinetic_energy(v)
    assert T1 <= T0
    # Routh's continuous slip: forward slip stops at P1, backward after; kinetic e
    P1 = u / (mu * D[1, 1] - D[1, 0])
    g1 = -V + (D[0, 0] - mu * D[0, 1]) * P1
    assert g1 < 0  # the slip stops within the compression
    P_c = P1 - g1 / (D[0, 0] + mu * D[0, 1])
    P_N_r = (1 + e) * P_c
    routh = _velocities(u, V, P_N_r, -mu * P1 + mu * (P_N_r - P1), rx, ry, I)
    # they differ: (0.629, -0.378, -2.095) against (0.671, -0.345, -2.057)
    assert np.max(np.abs(routh - exact)) > 0.03
    assert model.kinetic_energy(routh) <= T0
    # friction's share. Compression: its end (stuck, P_T,c along the pre-impact slip) is
    # out of Routh's reach (sticking needs 0.6 > μ of the cone), so the tangential impulse
    # is read as acting after the normal one, on the slip it drives back: ½ D_TT P_T,c².
    # Decompression: from stuck, one direction of impulse: −½ P_T,d s⁺ (s⁺ < 0 < P_T,d).
    s_plus = (D[1, 0] + mu * D[1, 1]) * f
    assert abs(slip - s_plus) <= 1e-12 * abs(s_plus)
    friction = 0.5 * D[1, 1] * Pc[1] ** 2 - 0.5 * mu * f * s_plus
    np.testing.assert_allclose(states[-1].friction.work, friction, rtol=1e-10)
    assert friction > 0.0
    # Routh's process dissipates by friction ½μP₁u forward, then μ(P_N − P₁)|s⁺|/2 backward
    routh_slip = routh[0] - routh[2] * ry
    routh_friction = 0.5 * mu * P1 * u + 0.5 * mu * (P_N_r - P1) * abs(routh_slip)
    assert routh_friction > 0.0  # (0.035 J against the two-phase law's 0.0079 J)


@pytest.mark.parametrize("mu, e", [(0.0, 0.7), (0.5, 0.0), (0.3, 0.0)])
def test_newton_and_poisson_agree_where_they_must(mu, e):
    """A frictionless single contact (ġ⁺ = −e ġ⁻ either way) and e = 0 (the compression
    alone is Newton's law): the same velocities to round-off, on the bar (coupled rows)."""
    out = {}
    for law in ("newton", "poisson"):
        out[law] = _bar(0.5, 1.0, law, mu, e)[1][-1].v
    scale = np.abs(out["newton"]).max()
    np.testing.assert_allclose(out["poisson"], out["newton"], rtol=0, atol=1e-14 * scale)


def test_newton_and_poisson_agree_on_a_frictionless_chain_bounce():
    """Kane's chain without friction: one contact, joints; the runs agree to round-off."""
    sim = case("kane_chain").build(friction=0.0, restitution=0.8)
    runs = [
        trace(sim.replace(options=IntegratorOptions(impact_law=law)), t_end=0.6)
        for law in ("newton", "poisson")
    ]  # noqa: E501
    assert runs[0]["status"] == runs[1]["status"] == "completed"
    assert runs[0]["impulse"].max() > 0.0
    np.testing.assert_allclose(runs[1]["total"], runs[0]["total"], rtol=0, atol=1e-10)


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_kane_chain_friction_dissipates_as_in_routh(e):
    """Kane's strike: the slip (0.497 m/s) stops on the cone's edge within the compression
    and the end then sticks (|D̂_TN|/D̂_TT = 0.453 < μ = 0.5, D̂ the chain's Delassus matrix
    at the end with the pins condensed), through the decompression too. Routh's process
    then ends where the one-step law does, and friction takes ½ μ P₁ |s⁻| with
    P₁ = |s⁻|/(μ D̂_TT − σ D̂_TN), the same under both laws at every e_N: 0.028 J."""
    sim = case("kane_chain").build(restitution=e)
    work = {}
    for law in ("newton", "poisson"):
        opts = IntegratorOptions(impact_law=law)
        states = list(simulate(sim.model, sim.dt, 0.42, opts, q0=sim.q0, v0=sim.v0))
        w = np.array([0.0 if st.friction is None else st.friction.work for st in states])
        assert np.all(np.diff(w) >= 0.0)  # friction takes energy at every step
        work[law] = w[-1]
    # the compressions are one solve, the decompressions stick: round-off apart
    assert work["poisson"] == pytest.approx(work["newton"], rel=1e-12)
    # Routh's closed form from the chain at the strike: D̂ at q_{n+1}; the slip s⁻ the jump
    # starts from is the smooth step's, which the step-start slip used here misses by the
    # slip's change over one step, O(h) (0.6 %: 1.2 % in this quadratic, measured): 2 %
    m = sim.model
    strike = next(i for i, st in enumerate(states) if st.impulse.sum() > 0)
    q, closed = states[strike].q, np.array([0])
    G = m.contacts.jacobian(q, closed)[1]
    GT = m.contacts.tangent_jacobian(q, closed)[0][0]
    Gb = m.joints.jacobian(q, m.joints.all)[1]
    Gb = Gb.toarray() if hasattr(Gb, "toarray") else np.asarray(Gb)
    A = np.vstack([G, GT, Gb])
    Dfull = A @ m.solve_M(A.T).reshape(len(m.free), -1)
    Dh = Dfull[:2, :2] - Dfull[:2, 2:] @ np.linalg.pinv(Dfull[2:, 2:]) @ Dfull[2:, :2]
    mu = 0.5
    assert abs(Dh[1, 0]) / Dh[1, 1] < mu  # the stick holds inside the cone
    s0 = float((GT @ states[strike - 1].v[m.free])[0])
    P1 = abs(s0) / (mu * Dh[1, 1] - np.sign(s0) * Dh[1, 0])
    assert work["newton"] == pytest.approx(0.5 * mu * P1 * abs(s0), rel=2e-2)


def test_kane_chain_newton_gains_and_poisson_does_not():
    """e_N = 1, μ = 0.5: Newton's law ends 1.13 J above the start (friction's work −1.14 J),
    Poisson's below it, its energy falling below its running maximum by ≤ 1e-6 of the
    peak kinetic energy."""
    sim = case("kane_chain").build()
    out = {}
    for law in ("newton", "poisson"):
        out[law] = trace(sim.replace(options=IntegratorOptions(impact_law=law)))
        assert out[law]["status"] == "completed"
    gain = out["newton"]["total"][-1] - out["newton"]["total"][0]
    assert 1.0 < gain < 1.3
    D = out["poisson"]["total"][0] - out["poisson"]["total"]
    created = np.max(np.maximum.accumulate(D) - D)
    assert D[-1] > 0.0
    assert created <= 1e-6 * out["poisson"]["kinetic"].max()


def test_decompression_solver_holds_the_law():
    """Random coupled 2D contacts with floors: bound, complementarity, cone, slip against
    the impulse; a zero floor on a separating contact gives no impulse."""
    rng = np.random.default_rng(5)
    for _ in range(20):
        B = rng.normal(size=(6, 6))
        D = B @ B.T / 6 + 0.2 * np.eye(6)
        c = rng.normal(size=6)
        mu = rng.uniform(0.0, 1.0, 3)
        floor = rng.uniform(0.0, 1.0, 3) * (rng.uniform(size=3) > 0.3)
        x, status, _ = solve_decompression(c, D, mu, 1, floor, 1e-13)
        w = (c + D @ x).reshape(3, 2)
        xs = x.reshape(3, 2)
        for j in range(3):
            xn, xt, wn, wt = xs[j, 0], xs[j, 1], w[j, 0], w[j, 1]
            # Gauss–Seidel stops at a change of w ≤ 1e-13: ten times that as margin
            assert xn >= floor[j] - 1e-12 and wn >= -1e-12
            assert xn - floor[j] <= 1e-12 or abs(wn) <= 1e-12
            assert abs(xt) <= mu[j] * xn + 1e-12
            if abs(xt) < mu[j] * xn - 1e-12:
                assert abs(wt) <= 1e-12
            else:
                assert wt * xt <= 1e-12


def test_impact_law_is_checked():
    with pytest.raises(InputError, match="impact_law"):
        IntegratorOptions(impact_law="stronge")
    with pytest.raises(InputError, match="^impact_law = 'poisson' needs integrator"):
        IntegratorOptions(impact_law="poisson", integrator="penalty")


def test_decompression_solver_in_3d():
    """Random coupled 3D contacts (disk cones) with floors, and a joint row: the bound, the
    complementarity, the cone, no slip inside it and slip against the impulse on its edge,
    and the joint's rate zero."""
    rng = np.random.default_rng(7)
    for _ in range(10):
        B = rng.normal(size=(7, 7))
        D = B @ B.T / 7 + 0.3 * np.eye(7)
        c = rng.normal(size=7)
        mu = rng.uniform(0.1, 1.0, 2)
        floor = rng.uniform(0.0, 1.0, 2)
        x, status, _ = solve_decompression(c, D, mu, 2, floor, 1e-12)
        w = c + D @ x
        assert abs(w[6]) <= 1e-12
        for j in range(2):
            xn, xt = x[3 * j], x[3 * j + 1 : 3 * j + 3]
            wn, wt = w[3 * j], w[3 * j + 1 : 3 * j + 3]
            # the projection iteration stops at an update of w ≤ 1e-13: margins of 1e-10
            assert xn >= floor[j] - 1e-12 and wn >= -1e-10
            assert xn - floor[j] <= 1e-10 or abs(wn) <= 1e-10
            assert np.linalg.norm(xt) <= mu[j] * xn + 1e-12
            if np.linalg.norm(xt) < mu[j] * xn * (1 - 1e-9):
                assert np.linalg.norm(wt) <= 1e-10
            else:  # on the edge: the impulse opposes the slip
                assert np.linalg.norm(np.cross(np.r_[xt, 0], np.r_[wt, 0])) <= 1e-9
                assert xt @ wt <= 1e-10


@pytest.mark.parametrize("nt", [1, 2])
def test_friction_in_a_phase_never_does_positive_work(nt):
    """Random coupled contacts (and a joint row) under Coulomb's law at the end of a phase
    (the decompression solver's outcomes, floors and all): the energy the tangential
    impulses take is ≥ 0 whichever reading applies, and it is Routh's where the slip does
    not couple to the normal motion (one contact, D_NT = 0, the slip kept or stopped)."""
    from fecontact.contact.restitution import friction_dissipation

    rng = np.random.default_rng(11 + nt)
    b = 1 + nt
    for _ in range(200):
        m = int(rng.integers(1, 4))
        n = m * b + 1
        B = rng.normal(size=(n, n))
        D = B @ B.T / n + 0.2 * np.eye(n)
        c = rng.normal(size=n)
        mu = rng.uniform(0.05, 1.0, m)
        floor = rng.uniform(0.0, 1.0, m) * (rng.uniform(size=m) > 0.3)
        x, _, _ = solve_decompression(c, D, mu, nt, floor, 1e-13)
        w = c + D @ x
        # Coulomb's law holds to the solver's 1e-13 in w: that, times the impulses, is the
        # round-off a reading that vanishes can show
        slack = 1e-11 * (1 + np.abs(x).max())
        assert friction_dissipation(x, c, w, D, mu, nt, 1e-12) >= -slack
    # one 2D contact, D_NT = 0: the slip's kinetic energy (s0² − s⁺²)/(2 D_TT)
    D = np.diag([2.0, 3.0])
    for s0, floor in ((1.0, 0.1), (1.0, 2.0), (-0.5, 1.0)):
        c = np.array([0.0, s0])
        x, _, _ = solve_decompression(c, D, [0.3], 1, [floor], 1e-14)
        s1 = (c + D @ x)[1]
        expected = (s0**2 - s1**2) / (2 * D[1, 1])
        got = friction_dissipation(x, c, c + D @ x, D, [0.3], 1, 1e-12)
        assert got == pytest.approx(expected, rel=1e-12)


def _pinned_bars(shared: bool, mu: float):
    """Three bars pinned end to end, released tilted above a floor (e_N = 1, friction
    ``mu``), the floor meeting each bar's end vertices. ``shared``: both bars' vertices at
    a pin meet it (two rows of one normal rate), else only the first bar's."""
    L, w = 0.5, 0.02
    diamond = Polygon([[-L / 2, 0.0], [0.0, -w / 2], [L / 2, 0.0], [0.0, w / 2]])
    bars, ends = [], [np.array([0.0, 0.6])]
    for a in (0.3, -0.2, 0.4):
        d = np.array([np.cos(a), np.sin(a)])
        bars.append(RigidBody2D(1.0, L**2 / 12, ends[-1] + 0.5 * L * d, angle=a, shape=diamond))
        ends.append(ends[-1] + L * d)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    nodes = [[0, 2], [0, 2], [0, 2]] if shared else [[0, 2], [2], [2]]
    contacts = [
        Contact(b, floor, nodes=n, restitution=1.0, friction=mu)
        for b, n in zip(bars, nodes, strict=True)
    ]
    pins = [Pin(bars[i], ends[i + 1], bars[i + 1]) for i in range(2)]
    return Model(bars, contacts, (0.0, -9.81), joints=pins)


def test_a_struck_chain_restarts_its_joints_pull_and_conserves_at_rho_one(tmp_path):
    """The three pinned bars at e_N = 1 without friction, ρ∞ = 1 (no dissipation of the
    step's own), h = 2 ms, 0.6 s: the jump changes the joints' quadratic terms
    −vᵀ∇²g_b v, and v̇ and a take that change (fecontact.time.spin_restart). Started from the
    pre-impact v̇ instead, the step after each strike made energy: numerical dissipation
    −4.2e-2 J and 1.12e-2 of the scale created (measured); restarted 1.3e-2 J and 1.7e-3,
    falling as h² (docs/explanation/energy_ledger.md). The bound 3e-3 lies halfway in
    log between the two."""
    sim = Simulation(
        _pinned_bars(False, 0.0), dt=2e-3, t_end=0.6, options=IntegratorOptions(rho_inf=1.0)
    )
    ledger = run(sim, tmp_path / "chain", progress=False, frames=False)["energy_ledger"]
    assert ledger["numerical_dissipation"] > 0.0
    assert ledger["created"] < 3e-3 * ledger["scale"]


@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_poisson_restitutes_a_pin_struck_on_two_rows(mu):
    """The middle bar's pins strike the floor at 0.364 and 0.376 s: each pin is two rows of
    one normal rate, the vertices of the two bars it joins. Poisson's law must restitute
    the percussion whatever share of it the solver gives each row: the chain moves as the
    one whose floor meets one vertex per pin (before, the compression shared 2.40 N s as
    1.18 + 1.21, the percussion as 0 + 2.40, and the rows restituted 1.21 N s: the chain
    lost 3.0 J of its 19 J at e_N = 1 without friction, 4.6 J with μ = 0.5)."""
    opts = IntegratorOptions(impact_law="poisson")
    end = {}
    for shared in (True, False):
        states = list(simulate(_pinned_bars(shared, mu), 1e-3, 0.38, opts))
        assert max(np.count_nonzero(st.impulse) for st in states) >= 2 * shared
        end[shared] = states[-1].v
    # each jump holds its law to tol_gap / h = 1e-9 m/s; 1e-8 m/s of velocities of 5 m/s
    np.testing.assert_allclose(end[True], end[False], rtol=0, atol=1e-8)


def test_decompression_settles_on_the_dependent_corners_of_a_face():
    """A box landing flat on a rough floor: four corners, 12 rows on 6 dofs, every corner
    stuck after the compression, the floors uneven. Each contact's projection starts from
    its last impulses, so that a sweep that changes nothing changes w by nothing (from
    (floor, 0) at every sweep the solves stopped a few tenths of the tolerance from the
    fixed point, and the sweeps changed w by 3.4e-10 m/s against 3.1e-10 forever)."""
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.02], Box(0.3, 0.04, 0.04))
    floor = Contact(box, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), restitution=1.0, friction=0.5)
    model = Model([box], [floor], (0.0, 0.0, -9.81))
    q = np.zeros(model.n)
    g, G = model.contacts.linearize(q, np.arange(model.contacts.size))[:2]
    closed = np.flatnonzero(np.abs(g) < 1e-12)
    assert closed.size == 4
    GT = model.contacts.tangent_jacobian(q, closed)[0]
    A = np.concatenate([np.asarray(G)[closed, None], GT], axis=1).reshape(-1, model.n)
    D = A @ model.solve_M(A.T).reshape(model.n, -1)
    floors = np.array([0.2424, 0.2424, 0.2624, 0.2624])  # N s: e_N times the percussion
    tol = 3e-10
    x, status, sweeps = solve_decompression(np.zeros(12), D, np.full(4, 0.5), 2, floors, tol, 100)
    assert sweeps < 100 and np.all(status == 1)
    w = D @ x
    # the law to its tolerance: the sweeps stop at a change of w below tol
    assert (
        np.all(x[::3] >= floors - 1e-12)
        and np.linalg.norm(w.reshape(4, 3)[:, 1:], axis=1).max() <= 10 * tol
    )
