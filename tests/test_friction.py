"""Coulomb friction: the Alart–Curnier law, and the exact motions of a block on an incline,
a disk thrown on a plane and a rocking block that does not slide."""

import math

import numpy as np
import pytest

from fecontact import InputError
from fecontact.bodies import Beam2D, Material, Section
from fecontact.contact import Contact
from fecontact.contact.friction import solve_coulomb, tangent_basis
from fecontact.testing import G, case, trace


def _law(c, D, p, mu, nt, k=1.0):
    return solve_coulomb(
        np.asarray(c, float), D, np.asarray(p, float), k, np.asarray(mu), nt, tol=1e-13
    )


@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e6])
def test_one_contact_sticks_slips_or_opens_whatever_p_and_k(scale):
    """A unit mass (D = I) approaching at ġ_N = −1: it sticks when the slip rate it brings
    fits the cone (|ġ_T| ≤ μ), else slips with |Λ_T| = μ Λ_N against it; a separating one
    carries nothing. Exact answers, for p and k over twelve decades."""
    D = np.eye(2)
    for c, mu, x, status in [
        ((-1.0, 0.2), 0.3, (1.0, -0.2), 1),
        ((-1.0, 2.0), 0.3, (1.0, -0.3), 2),
        ((-1.0, -2.0), 0.3, (1.0, 0.3), 2),
        ((1.0, 2.0), 0.3, (0.0, 0.0), 0),
        ((-1.0, 2.0), 0.0, (1.0, 0.0), 2),
    ]:
        got, st, _ = _law(c, D, np.full(2, scale), [mu], 1, k=1.0 / scale)
        np.testing.assert_allclose(got / scale, x, atol=1e-12)
        assert st[0] == status


def test_three_dimensional_cone():
    """Three contacts of a random coupled 3D problem: every impulse in its disk, sticking
    contacts with zero slip rate, slipping ones with |Λ_T| = μ Λ_N opposite their slip."""
    rng = np.random.default_rng(3)
    B = rng.normal(size=(9, 6))
    D = 0.1 * B @ B.T + 0.1 * np.eye(9)
    c = rng.normal(size=9)
    mu = np.array([0.3, 0.5, 1.0])
    results = []
    for scale in (1e-2, 1.0, 1e2):
        x, status, _ = _law(c, D, scale / np.diag(D), mu, 2)
        results.append(x)
        w = (c + D @ x).reshape(3, 3)
        xs = x.reshape(3, 3)
        for j in range(3):
            xn, xt, wn, wt = xs[j, 0], xs[j, 1:], w[j, 0], w[j, 1:]
            # the solve stops at |w| ≤ 1e-13 on closed rows: a margin of ten
            assert xn >= 0.0 and wn >= -1e-12 and (xn == 0.0 or abs(wn) <= 1e-12)
            assert np.linalg.norm(xt) <= mu[j] * xn + 1e-12
            if status[j] == 1:
                np.testing.assert_allclose(wt, 0.0, atol=1e-12)
            elif status[j] == 2:
                np.testing.assert_allclose(xt, -mu[j] * xn * wt / np.linalg.norm(wt), atol=1e-10)
    # D's smallest eigenvalue is 0.1: x is within ten times w's tolerance
    np.testing.assert_allclose(results[0], results[2], rtol=0, atol=1e-11)


def _check_law(c, D, x, mu, tol):
    """One 3D contact's law at w = c + D x, to ``tol`` in units of w."""
    w = c + D @ x
    xn, xt, wn, wt = x[0], x[1:], w[0], w[1:]
    assert xn >= 0.0 and wn >= -tol and (xn == 0.0 or abs(wn) <= tol)
    cone = np.linalg.norm(xt)
    assert cone <= mu * xn * (1 + 1e-12) + 1e-300
    if xn > 0.0 and cone < mu * xn * (1 - 1e-9):
        np.testing.assert_allclose(wt, 0.0, atol=tol)  # stuck: no slip
    elif xn > 0.0:  # slipping: the slip along −Λ_T
        s = np.linalg.norm(wt)
        np.testing.assert_allclose(wt, -s * xt / cone, atol=tol)


def test_one_3d_contact_is_solved_exactly():
    """A lone 3D contact whose semi-smooth Newton oscillated between open and slip past its
    stick solution (a node of a block on a 20° incline, μ = 5, at 4 Δx/c): the exact local
    solve finds it, with no Gauss–Seidel; and 600 random ones (open, stick and slip, μ up to
    3) meet the law to round-off."""
    from fecontact.contact.stats import CoulombStats

    c = np.array([-6.5029077401371710e-07, 3.4205845085322717e-06, 2.1876015328093736e-07])
    D = np.array(
        [
            [8.5321647776232568e-06, 2.9550472914999995e-06, 4.0408369427910996e-07],
            [2.9550472914999999e-06, 7.6723784785050134e-06, 1.0325330976454126e-06],
            [4.0408369427910991e-07, 1.0325330976454128e-06, 8.7834500337327091e-06],
        ]
    )
    stats = CoulombStats()
    x, status, _ = solve_coulomb(
        c, D, 1.0 / np.diag(D), 1.0, np.array([5.0]), 2, tol=1e-13, stats=stats
    )
    assert stats.solves == 1 and stats.gauss_seidel_solves == 0 and status[0] == 1
    np.testing.assert_allclose(x, np.linalg.solve(D, -c), rtol=1e-12)
    rng = np.random.default_rng(7)
    seen = set()
    for _ in range(600):
        B = rng.normal(size=(3, 3))
        D = B @ B.T + 0.1 * np.eye(3)
        c, mu = rng.normal(size=3), rng.uniform(0.0, 3.0)
        x, status, _ = _law(c, D, 1.0 / np.diag(D), [mu], 2)
        seen.add(int(status[0]))
        # the law's rows are O(1) here: 1e-12 is round-off of the solve and the root
        _check_law(c, D, x, mu, 1e-12)
    assert seen == {0, 1, 2}


def test_tangents_complete_the_normal():
    n = np.array([[0.0, 1.0], [0.6, 0.8]])
    T = tangent_basis(n)
    np.testing.assert_allclose(T[0, 0], [1.0, 0.0])
    assert abs(T[1, 0] @ n[1]) < 1e-15
    n3 = np.array([[0.0, 0.0, 1.0], [0.48, 0.6, 0.64]])
    B = np.concatenate([tangent_basis(n3), n3[:, None]], axis=1)
    np.testing.assert_allclose(
        B @ B.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (2, 3, 3)), atol=1e-15
    )


def _block(**params):
    return case("sliding_block").build(**params)


def test_block_sticks_on_a_gentle_incline_without_drift():
    """tan 20° < 0.5: the block stays put. The predictor slides it by h²g sin α/2 each step;
    the position-level cone takes it back exactly, so over 10 s nothing accumulates (a step
    of 10 ms keeps the test short; the drift per step does not depend on it)."""
    r = trace(_block(incline=20.0, friction=0.5), dt=1e-2, t_end=10.0)
    assert r["status"] == "completed"
    assert np.max(np.abs(r["s"])) <= 1e-10
    assert np.max(np.abs(r["v"])) <= 1e-10


@pytest.mark.parametrize("incline,friction", [(30.0, 0.3), (45.0, 0.5), (20.0, 0.0)])
def test_block_slides_with_the_coulomb_acceleration(incline, friction):
    """tan α > μ: s = ½ g (sin α − μ cos α) t². A constant acceleration is integrated exactly
    by the step, so the distance matches to round-off of the 1000 steps."""
    r = trace(_block(incline=incline, friction=friction), dt=1e-3, t_end=1.0)
    a = math.radians(incline)
    acc = G * (math.sin(a) - friction * math.cos(a))
    np.testing.assert_allclose(r["s"], 0.5 * acc * r["t"] ** 2, rtol=1e-9, atol=1e-12)
    assert np.min(r["min_gap"]) >= -1e-12


@pytest.mark.parametrize("v0", [1.0, -1.0])
def test_thrown_block_stops_where_coulomb_says_and_stays(v0):
    """Thrown down (v₀ > 0) with tan α < μ it stops after v₀²/(2g(μ cos α − sin α)); thrown up,
    after v₀²/(2g(sin α + μ cos α)). The stop falls inside a step, so the distance is within
    v₀h of it (first order); then the block sticks."""
    h = 1e-3
    r = trace(_block(incline=20.0, friction=0.5, velocity=v0), dt=h, t_end=1.2)
    a = math.radians(20.0)
    d = G * (0.5 * math.cos(a) - math.sin(a)) if v0 > 0 else G * (math.sin(a) + 0.5 * math.cos(a))
    exact = math.copysign(v0**2 / (2 * d), v0)
    assert abs(r["s"][-1] - exact) <= abs(v0) * h
    rest = r["t"] > abs(v0) / d + 2 * h
    assert np.max(np.abs(r["v"][rest])) <= 1e-12
    assert np.ptp(r["s"][rest]) <= 1e-12


def _disk(**params):
    return case("rolling_disk").build(**params)


@pytest.mark.parametrize("v0,spin", [(2.0, 0.0), (1.3, 0.0), (2.0, 50.0), (1.0, 15.0)])
def test_disk_slips_then_rolls(v0, spin):
    """v = v₀ − μgt until t* = (v₀ + ω₀R)/(3μg), then rolling at (2v₀ − ω₀R)/3 with zero slip.
    The scheme sticks at the first step end past t*, so the rolling time is within one step
    (first order), and the rolling speed is exact."""
    mu, R, h = 0.3, 0.1, 1e-3
    r = trace(_disk(velocity=v0, spin=spin, friction=mu), dt=h, t_end=1.0)
    t_star = (v0 + spin * R) / (3 * mu * G)
    v_star = (2 * v0 - spin * R) / 3
    slip = np.abs(r["slip"])
    rolling = slip <= 1e-10 * v0
    t_roll = r["t"][np.argmax(rolling)]
    assert 0.0 <= t_roll - t_star <= h * (1 + 1e-9)
    assert np.all(rolling[r["t"] >= t_roll])
    after = r["t"] >= t_roll
    np.testing.assert_allclose(r["vx"][after], v_star, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(r["omega"][after], -v_star / R, rtol=1e-10, atol=1e-10)
    before = r["t"] < t_star - h
    np.testing.assert_allclose(r["vx"][before], v0 - mu * G * r["t"][before], rtol=1e-10)
    assert np.min(r["min_gap"]) >= -1e-12


@pytest.mark.parametrize(
    "name,params",
    [
        ("sliding_block", {"incline": 30.0, "friction": 0.3, "velocity": -0.5}),
        ("rolling_disk", {"velocity": 2.0, "spin": 30.0}),
    ],
)
def test_energy_balance_closes_with_the_work_of_friction(name, params, tmp_path):
    """E(t) − E(0) = −W_friction (history column ``friction_work``) to round-off: with no
    impact, the normal corrections of a rigid body in persistent contact do no net work."""
    from fecontact import run
    from fecontact.io.output import read_history

    sim = case(name).build(**params)
    summary = run(sim.replace(t_end=1.0), tmp_path, frames=False)
    assert summary["status"] == "completed" and summary["friction_solver"]["solves"] > 0
    hist = read_history(tmp_path / "history.csv")
    E, W = hist["total_energy"], hist["friction_work"]
    ke0 = max(hist["kinetic_energy"][0], 1.0)
    assert W[-1] > 0.1 * ke0
    # 1e-8 of the initial kinetic energy per second, the project's bar for rigid cases
    assert np.max(np.abs(E - E[0] + W)) <= 1e-8 * ke0 * hist["t"][-1]


@pytest.mark.parametrize(
    "name,params",
    [
        ("sliding_block", {"incline": 20.0, "friction": 0.5, "velocity": 1.0}),
        ("rolling_disk", {"velocity": 2.0, "spin": 50.0}),
        ("rocking_block", {"friction": 1.0}),
    ],
)
def test_friction_results_do_not_depend_on_p_and_k(name, params):
    """The augmentation p and the multiplier scale k steer the Newton path only."""
    sim = case(name).build(**params)
    probe = next(iter(sim.probes))
    ref = trace(sim, t_end=0.4)
    for p, k in [(1e-6, 1.0), (1e6, 1.0), (1.0, 1e-6), (1.0, 1e6)]:
        opts = sim.options
        other = sim.replace(
            options=type(opts)(**{**vars(opts), "penalty_scale": p, "multiplier_scale": k})
        )
        r = trace(other, t_end=0.4)
        assert r["status"] == "completed"
        scale = np.max(np.abs(ref[probe])) + 1e-3
        np.testing.assert_allclose(r[probe], ref[probe], rtol=0, atol=1e-8 * scale)


def test_rocking_block_with_friction_pivots_without_sliding():
    """μ = 1: a bottom corner that carries a normal impulse over two steps keeps its place
    along the plane; with μ = 0 the same corner slides. (A corner touching without a normal
    force carries no friction either, and may move.)"""
    sims = {mu: case("rocking_block").build(friction=mu) for mu in (0.0, 1.0)}
    slides = {}
    for mu, sim in sims.items():
        block = sim.model.bodies[0]
        xs, closed = [], []
        from fecontact.time import simulate

        for st in simulate(sim.model, sim.dt, 0.6, sim.options):
            xs.append(block.positions(st.q)[:2, 0])
            closed.append(st.impulse[:2] > 0.0 if st.impulse.size else np.zeros(2, bool))
        xs, closed = np.array(xs), np.array(closed)
        both = closed[1:] & closed[:-1]
        slides[mu] = np.max(np.abs(np.diff(xs, axis=0))[both])
    assert slides[1.0] <= 1e-12
    assert slides[0.0] > 1e-4


def test_no_friction_is_todays_path():
    """μ = 0 builds the frictionless pair: the model does not carry the friction rows."""
    sim = case("rocking_block").build()
    assert not sim.model.contacts.frictional


def test_friction_is_checked():
    with pytest.raises(InputError, match="friction must be >= 0"):
        case("rolling_disk").build(friction=-0.1)
    mat, sec = Material(E=1e9, nu=0.3, rho=1e3), Section.rectangle(0.01, 0.01)
    a = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 2, mat, sec)
    b = Beam2D.straight([1.1, 0.0], [2.0, 0.0], 2, mat, sec)
    # two bars end to end slip across their axis (tests/test_strip_friction.py)
    pair = Contact(a, b, friction=0.2)
    assert pair.frictional and pair.friction == 0.2


def _pinned_chain():
    """Three thin bars joined end to end by two pins, released tilted above a floor with
    μ = 0.3, e_N = 0.5 (9 dofs): its velocity jumps reach Coulomb laws on which Newton
    stalls, both ends slipping with |R/p| ≈ 1e-6 that no Newton step reduces."""
    from fecontact import Model, Pin
    from fecontact.bodies import Polygon, RigidBody2D
    from fecontact.contact import Plane

    L, w = 0.5, 0.02
    diamond = Polygon([[-L / 2, 0.0], [0.0, -w / 2], [L / 2, 0.0], [0.0, w / 2]])
    bodies, ends = [], [np.array([0.0, 0.6])]
    for a in (0.3, -0.2, 0.4):
        d = np.array([np.cos(a), np.sin(a)])
        bodies.append(RigidBody2D(1.0, L**2 / 12, ends[-1] + 0.5 * L * d, angle=a, shape=diamond))
        ends.append(ends[-1] + L * d)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    contacts = [Contact(b, floor, restitution=0.5, friction=0.3) for b in bodies]
    joints = [Pin(bodies[i], ends[i + 1], bodies[i + 1]) for i in range(2)]
    return Model(bodies, contacts, gravity=(0.0, -G), joints=joints)


def test_a_stalled_coulomb_newton_stops_at_once_with_the_same_motion(monkeypatch):
    """Newton stopped at the first step forced in full that moves the multipliers by
    round-off (its remaining iterations are round-off too) hands the fallbacks the same law
    as the 50 iterations did: the chain's motion is the same bit for bit, for fewer cuts."""
    import fecontact.contact.coulomb_newton as coulomb_newton
    from fecontact.time import simulate
    from fecontact.time.stats import StepStats

    runs = {}
    for stop in (True, False):
        if not stop:
            monkeypatch.setattr(coulomb_newton, "_round_off_move", lambda x, start: False)
        stats = StepStats()
        states = [
            np.concatenate([st.q, st.v]) for st in simulate(_pinned_chain(), 1e-3, 0.4, stats=stats)
        ]
        runs[stop] = np.array(states), stats.contact.coulomb
    (moved, stopped), (kept, full) = runs[True], runs[False]
    assert stopped.stalled_newtons >= 1 and full.stalled_newtons == 0
    assert stopped.line_search_cuts < full.line_search_cuts
    np.testing.assert_array_equal(moved, kept)
