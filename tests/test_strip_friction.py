"""Coulomb friction between two Beam2D strips (fecontact.contact.beam_sides): a strip's nodes
slip on the other strip's two-sided surface, each touching point moved by its own section's
turn. Checked against the slips' derivatives and a rigid motion, and against a short strip
sliding on a clamped long one under gravity: a stop at μg with friction's work μ m g s, an
incline held for tan α < μ and slid down at g(sin α − μ cos α) above, the same under
Moreau–Jean and without the smooth-contact path, and p, k moving nothing but the solves'
round-off; a tilted strip landing on a clamped strip as on a plane. Two bars end to end
slip across their axis: on a clamped bar as on a plane, on a free one keeping momentum with
a tangential impulse μ times the normal one."""

import numpy as np
import pytest

from fecontact import Beam2D, Contact, Material, Model, Probe, Section, Simulation, run, simulate
from fecontact.contact import Plane
from fecontact.testing import slip_derivative_errors
from fecontact.time import IntegratorOptions

STEEL = Material(210e9, rho=7850.0)
G, MU = 9.81, 0.3  # gravity (m/s²), Coulomb's μ
C, C2 = 0.005, 0.002  # half thicknesses (m) of the long strip and of the short one
PLANE = Plane([0.0, 0.0], [1.0, 0.0])  # the face x = 0


def strips(alpha=0.0, both=False):
    """A short steel strip (10 cm, 4 elements, 4 mm thick) resting on a clamped long one (1 m,
    20 elements, 10 mm thick), gravity tilted by α: the short strip's nodes on the long
    strip's surface (``both``: and the long strip's on the short one's)."""
    long = Beam2D.straight([-0.5, 0.0], [0.5, 0.0], 20, STEEL, Section.rectangle(0.02, 2 * C))
    for i in range(long.n_nodes):
        long.clamp(i)
    y = C + C2
    short = Beam2D.straight([-0.05, y], [0.05, y], 4, STEEL, Section.rectangle(0.02, 2 * C2))
    pairs = [Contact(short, long, clearance=C + C2, friction=MU)]
    if both:
        pairs.append(Contact(long, short, clearance=C + C2, friction=MU))
    gravity = (G * np.sin(alpha), -G * np.cos(alpha))
    return Model([short, long], pairs, gravity=gravity), short


def travel(model, body, speed, t_end=0.05, options=None):
    """Times and the mean x of ``body``'s nodes, thrown along x at ``speed`` (m/s)."""
    s = model.body_slice(model.bodies.index(body))
    v0 = model.translation(body, (speed, 0.0))
    ts, xs = [], []
    for st in simulate(model, 1e-3, t_end, options, v0=v0):
        ts.append(st.t)
        xs.append(body.positions(st.q[s]).mean(axis=0)[0])
    return np.array(ts), np.array(xs)


def rigidly_moved(model, q, phi, shift):
    """q_n: the configuration q turned back by ``phi`` (rad) and shifted back by ``shift``
    (m), every body (the sections' rotations too): q is q_n moved rigidly."""
    R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    q_n = np.zeros(model.n)
    for i, body in enumerate(model.bodies):
        s = model.body_slice(i)
        qs = q[s].reshape(-1, 3).copy()
        qs[:, :2] = (body.positions(q[s]) - shift) @ R - body.X
        qs[:, 2] -= phi
        q_n[s] = qs.ravel()
    return q_n, R


def test_slip_rows_are_the_derivatives_of_the_slips_and_a_rigid_motion_slips_nothing():
    # an upper strip of 7 elements over a lower one of 5, both bent and turned by q; the
    # clearance splits as the two rectangles' half thicknesses
    rng = np.random.default_rng(0)
    lower = Beam2D.straight([0.0, 0.0], [0.3, 0.0], 5, STEEL, Section.rectangle(0.02, 2 * C))
    upper = Beam2D.straight(
        [-0.015, C + C2 + 1e-4], [0.315, C + C2 + 1e-4], 7, STEEL, Section.rectangle(0.02, 2 * C2)
    )
    pair = Contact(upper, lower, clearance=C + C2, friction=MU)
    model = Model([upper, lower], [pair], gravity=(0.0, 0.0))
    assert pair.node_arm == pytest.approx(C2) and pair.beam_arm == pytest.approx(C)
    q = 1e-3 * rng.normal(size=model.n)
    q[2::3] = 0.05 * rng.normal(size=model.n // 3)  # the sections turned by some 3°
    _, _, T = pair.tangents(q)
    errors, scale = slip_derivative_errors(pair, model, q, T)
    # second order: measured 1.2e-7 → 1.2e-9 from ε = 1e-5 to 1e-6; the round-off of a
    # difference over 2ε, 1e-16/1e-6, is far below either
    assert scale > 1.0 and errors[1] < 2e-8 and errors[0] > 50.0 * errors[1]
    q_n, R = rigidly_moved(model, q, 0.3, np.array([0.05, -0.02]))
    g = pair.evaluate(q)[0]
    held = np.isfinite(g) & (np.abs(T).sum(axis=(1, 2)) > 0.0)
    n = np.stack([-T[held, 0, 1], T[held, 0, 0]], axis=1)
    expected = -g[held] * np.einsum("md,md->m", T[held, 0], n @ R)
    assert held.sum() >= 6  # (the upper strip's nodes over the lower one)
    # round-off on coordinates of order 0.3 m (measured 3.5e-17 m); leaving either
    # section's arm out would leave its turn of 0.3 rad in the slip, some 6e-4 m
    assert np.abs(pair.slips(q, q_n, T)[held, 0] - expected).max() < 1e-15


# -- closed forms ----------------------------------------------------------------------------
PATHS = {
    "nsga": None,
    "moreau": IntegratorOptions(integrator="moreau"),
    "decoupled": IntegratorOptions(smooth_contact="off"),
}


@pytest.mark.parametrize("path", PATHS)
def test_a_strip_thrown_along_a_clamped_strip_decelerates_at_mu_g(path):
    ts, xs = travel(*strips(), 0.5, options=PATHS[path])
    exact = 0.5 * ts - 0.5 * MU * G * ts**2
    # measured 1.4e-14, 1.6e-14 and 1.3e-14 m on 0.021 m: the round-off of 50 steps' sums
    # (the clamped strip does not yield, the stiff short one barely bends)
    assert np.abs(xs - exact).max() < 1e-12


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("tan_alpha", [0.255, 0.423])
def test_an_incline_holds_below_the_friction_angle_and_slides_above(path, tan_alpha):
    alpha = np.arctan(tan_alpha)
    model, short = strips(alpha)
    ts, xs = travel(model, short, 0.0, t_end=0.03, options=PATHS[path])
    a = max(G * (np.sin(alpha) - MU * np.cos(alpha)), 0.0)
    # held: 1.1e-12, 2.3e-12 and 1.9e-12 m of settling as the released strip takes its
    # weight on its nodes (no creep); sliding: 7e-15 to 1.4e-14 m on a slide of 0.5 mm
    assert np.abs(xs - 0.5 * a * ts**2).max() < 1e-10


def test_friction_books_mu_m_g_times_the_slide_and_creates_nothing(tmp_path):
    model, short = strips()
    v0 = model.translation(short, (0.5, 0.0))
    summary = run(Simulation(model, 1e-3, 0.05, v0=v0, name="slide"), tmp_path, frames=False)
    ledger = summary["energy_ledger"]
    slide = 0.5 * 0.05 - 0.5 * MU * G * 0.05**2
    # measured 3.5e-9 relative: the strip's settling on its nodes in the first step
    assert ledger["friction_dissipation"] == pytest.approx(MU * short.mass * G * slide, rel=1e-7)
    assert summary["friction_work"] == pytest.approx(ledger["friction_dissipation"])
    assert ledger["created"] == 0.0 and not summary["warnings"]


def test_the_strips_declared_both_ways_slide_alike():
    # the long strip's nodes under the short one's surface take rows too, flat on flat:
    # rows of one relative motion, the weight shared between the two pairs
    ts, xs = travel(*strips(both=True), 0.5)
    # measured 1.8e-14 m on 0.021 m (1.4e-14 declared one way): round-off
    assert np.abs(xs - (0.5 * ts - 0.5 * MU * G * ts**2)).max() < 1e-12


def test_the_runs_do_not_depend_on_p_and_k():
    ref = travel(*strips(), 0.5, t_end=0.02)[1]
    for p, k in ((1e3, 1.0), (1.0, 1e-2)):
        options = IntegratorOptions(penalty_scale=p, multiplier_scale=k)
        xs = travel(*strips(), 0.5, t_end=0.02, options=options)[1]
        # measured 3.0e-18 m (p × 1000), 1.7e-18 m (k ÷ 100) on 0.01 m: round-off
        assert np.abs(xs - ref).max() < 1e-12


def test_a_tilted_strip_dropped_on_the_clamped_strip_lands_as_on_a_plane():
    # a 20 cm strip tilted by 10°, 2 mm above the clamped strip's face, thrown at (1, −1) m/s,
    # μ = 0.5: it lands on its lower end, turns and slides; the clamped strip's sections
    # hold still, so its face is the plane y = c and the dropped strip's rows are its nodes'
    # rows on that plane, the touching points at −c₂ n moved by the sections' turns
    ends = []
    for on_plane in (False, True):
        long = strips()[0].bodies[1]
        a, lift = np.radians(10.0), 0.002
        centre = np.array([0.0, C + C2 + 0.1 * np.sin(a) + lift])
        d = 0.1 * np.array([np.cos(a), np.sin(a)])
        strip = Beam2D.straight(centre - d, centre + d, 8, STEEL, Section.rectangle(0.02, 2 * C2))
        if on_plane:
            pair = Contact(strip, Plane([0.0, C], [0.0, 1.0]), clearance=C2, friction=0.5)
        else:
            pair = Contact(strip, long, clearance=C + C2, friction=0.5)
        model = Model([strip, long][: 2 - on_plane], [pair], gravity=(0.0, -G))
        v0 = model.translation(strip, (1.0, -1.0))
        *_, st = simulate(model, 1e-4, 0.02, v0=v0)
        s = model.body_slice(0)
        ends.append((st.q[s], st.v[s], float(st.friction.work)))
    (q, v, work), (q_plane, v_plane, work_plane) = ends
    assert work > 0.01  # J: the strip slid on its lower end, and then on its face
    # measured 4.4e-16 (m, rad) on turns of 0.24 rad, 2.1e-10 (m/s, rad/s) on section rates
    # of 106 rad/s (the ringing of the bent strip), 2.4e-14 relative on the work: the
    # round-off of the two runs' solves, not a difference of their rows
    assert np.abs(q - q_plane).max() < 1e-14
    assert np.abs(v - v_plane).max() < 1e-10 * np.abs(v).max()
    assert work == pytest.approx(work_plane, rel=1e-12)


# -- two bars end to end ---------------------------------------------------------------------
def bar_strike(partner, tmp_path, options=None):
    """A 10 cm steel bar thrown end first at (−0.2, 2) m/s from 10 μm off ``partner`` (a 1 m
    bar, clamped or free, its end at the origin; or a Plane there), μ = 0.1, no gravity: the
    run's summary and the history of the momenta along and across the axis of the bar (px0,
    py0) and of a free partner (px1, py1)."""
    bar = Beam2D.straight([1e-5, 0.0], [0.10001, 0.0], 4, STEEL, Section.rectangle(0.02, 0.01))
    other = [partner] if isinstance(partner, Beam2D) else []
    nodes = None if other else [0]
    pair = Contact(bar, partner, nodes=nodes, friction=0.1)
    model = Model([bar, *other], [pair], gravity=(0.0, 0.0))
    v0 = model.translation(bar, (-0.2, 2.0))
    probes = {}
    for i, body in enumerate(model.bodies):
        if len(body.fixed) == body.ndof:  # (a clamped partner: no momentum)
            continue
        for axis, name in enumerate("xy"):
            probes[f"p{name}{i}"] = momentum(model, i, axis)
    sim = Simulation(model, 1e-6, 1.5e-4, v0=v0, probes=probes, name="strike")
    if options is not None:
        sim = sim.replace(options=options)
    summary = run(sim, tmp_path, frames=False)
    history = np.genfromtxt(tmp_path / "history.csv", delimiter=",", names=True)
    return summary, history


def momentum(model, i, axis):
    """The momentum (kg·m/s) of body i along ``axis``."""
    s = model.body_slice(i)
    M = model.M[s][:, s]
    return Probe(lambda m, st: (M @ st.v[s])[axis::3].sum(), "kg·m/s")


def long_bar(clamped):
    bar = Beam2D.straight([-1.0, 0.0], [0.0, 0.0], 10, STEEL, Section.rectangle(0.02, 0.01))
    for i in range(bar.n_nodes if clamped else 0):
        bar.clamp(i)
    return bar


def test_a_bar_struck_end_first_on_a_clamped_bar_slides_as_on_a_plane(tmp_path):
    # the bar's end node against the clamped bar's end: the node on a plane across the axis
    runs = [bar_strike(p, tmp_path / str(i)) for i, p in enumerate((long_bar(True), PLANE))]
    (summary, history), (plane_summary, plane_history) = runs
    for name in ("px0", "py0"):
        # measured 0 (the same solves): round-off of the sums
        assert np.abs(history[name] - plane_history[name]).max() < 1e-15
    assert summary["friction_work"] == pytest.approx(plane_summary["friction_work"], rel=1e-12)
    dx, dy = (history[k][-1] - history[k][0] for k in ("px0", "py0"))
    assert dx > 0.05  # kg·m/s: the bar struck and bounced (−0.2 m/s × 0.157 kg, and back)
    # sliding all along, the tangential impulse is μ times the normal one, but for three
    # steps of the generalized-α step as the strike begins, below the cone (on the plane the
    # same): measured −0.099972
    assert dy / dx == pytest.approx(-0.1, rel=1e-3)


def test_two_free_bars_struck_end_to_end_keep_their_momentum(tmp_path):
    options = IntegratorOptions(integrator="moreau")
    summary, history = bar_strike(long_bar(False), tmp_path, options)
    for axis in "xy":
        total = history[f"p{axis}0"] + history[f"p{axis}1"]
        # the pair's impulses act equal and opposite on the two ends: round-off of 0.3 kg·m/s
        assert np.abs(total - total[0]).max() < 1e-14
    dx, dy = (history[k][-1] - history[k][0] for k in ("px0", "py0"))
    assert dx > 0.02  # kg·m/s: the bar struck the free bar and left it
    # sliding all along, the tangential impulse is μ times the normal one: measured
    # −0.1 + 2.5e-15 under Moreau–Jean (−0.0998 under the generalized-α step, whose steps
    # where the strike begins and ends take less than the cone, as on a plane)
    assert dy / dx == pytest.approx(-0.1, rel=1e-12)
    ledger = summary["energy_ledger"]
    assert summary["friction_work"] > 0.0  # (dissipated: friction's work is its negative)
    assert ledger["friction_dissipation"] == pytest.approx(summary["friction_work"])
    assert ledger["created"] < 1e-5 * ledger["scale"] and not summary["warnings"]
