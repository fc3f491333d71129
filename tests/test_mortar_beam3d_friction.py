"""Coulomb friction on the dual mortar pair of a 3D solid and a Beam3D's tube
(fecontact.contact.mortar_beam3d): the slip rows against central differences of the exact
slips, rows resolved on the solid's normal."""

import dataclasses

import numpy as np
import pytest
from test_mortar_beam3d import RUBBER, STEEL, R, bent_rod_on_block

from fecontact import Model, Solid, simulate
from fecontact.bodies import Beam3D, LinearElastic, Section
from fecontact.contact import Contact
from fecontact.contact.mortar_beam3d import MortarBeam3D
from fecontact.simulation import Simulation, run
from fecontact.testing import slip_derivative_errors
from fecontact.time.settings import IntegratorOptions
from fecontact.time.stats import StepStats

G = 9.81


def test_slip_rows_are_the_derivatives_of_the_exact_slips():
    """G_T d against central differences of the exact slips from q to q moved by ±εd on the
    group (every dof: the block's nodes, the beam's translations and its rotations composed
    on the right): the difference is the central rule's O(ε²) (measured 3.4e-6, 3.4e-8,
    3.4e-10 at ε = 1e-5, 1e-6, 1e-7 against rows of 1.8), and the slip rows act on the
    beam's rotations (a turning section moves the material point under a node, by its arm
    of about r: measured 0.84 r)."""
    pair, model, q = bent_rod_on_block(make=MortarBeam3D)
    pair.friction = 0.3
    dofs, W, T = pair.tangents(q)
    assert np.allclose(np.einsum("mti,msi->mts", T, T), np.eye(2), atol=1e-14)
    rotations = model.offset_of(pair.beam) + pair.beam.rotation_triples.ravel()
    turn = np.isin(dofs, rotations)[:, None, :].repeat(2, axis=1)
    assert np.abs(W[turn]).max() > 0.5 * R  # m/rad: the arm to the tube's surface, about r
    errors, rows = slip_derivative_errors(pair, model, q, T)
    assert errors[1] <= 1e-7 * rows
    assert errors[1] <= 0.02 * errors[0]  # second order: 100× per decade


# -- a block sliding on two fixed rods -------------------------------------------------------
HARD = LinearElastic(1e8, 0.3, rho=1000.0)


def block_on_rods(mu: float):
    """A block 4 × 4 × 2 cm (cells of 1 cm) lying on two clamped steel rods (r = 1 cm, along x,
    at y = ±5 mm: between two lines of the block's nodes, where the weighted gaps' stand-off
    is least; over a line of nodes it is highest and the block rolls off sideways). Settled
    at rest under gravity along −z with ρ∞ = 0 over 50 steps of 1 ms from the height where
    the least row is zero. The pairs are the weighted-distance rows (``MortarBeam3D``, named:
    the default on this face blends them toward the tube's tangent plane,
    ``fecontact.contact.tube_plane``).
    Returns the model, the block, the pairs and the settled state."""
    block = Solid.box([-0.02, -0.02, 0.0], [0.02, 0.02, 0.02], (4, 4, 2), HARD)
    rods = []
    for y in (-0.005, 0.005):
        rod = Beam3D.straight([-0.05, y, -R], [0.15, y, -R], 4, STEEL, Section.circle(R))
        for k in range(5):
            rod.clamp(k)
        rods.append(rod)
    pairs = [MortarBeam3D(block, rod, clearance=R) for rod in rods]
    for pair in pairs:
        pair.friction = mu
    model = Model([block, *rods], pairs, gravity=(0.0, 0.0, -G))
    q = np.zeros(model.n)
    lo, hi = -0.2 * R, 0.2 * R
    for _ in range(60):  # bisection on the height where the least row is zero
        q[: block.ndof].reshape(-1, 3)[:, 2] = 0.5 * (lo + hi)
        if min(p.gaps(q).min() for p in pairs) < 0.0:
            lo = 0.5 * (lo + hi)
        else:
            hi = 0.5 * (lo + hi)
    q[: block.ndof].reshape(-1, 3)[:, 2] = hi
    settled = list(simulate(model, 1e-3, 0.05, IntegratorOptions(rho_inf=0.0), q0=q))[-1]
    return model, block, pairs, settled


def on_an_incline(mu: float, slope: float, h: float = 1e-3, t: float = 0.02):
    """The block settled on the rods (:func:`block_on_rods`), then gravity turned at once by
    ``slope`` (rad) about y (an incline rising along −x) and the run continued for ``t`` (s) in
    steps of ``h`` (s) with ρ∞ = 0, so that the load's turn is resolved in steps much shorter
    than the runs that follow. Returns the tilted model, the block and the states of the turn
    (the first is the settled state)."""
    model, block, pairs, settled = block_on_rods(mu)
    gravity = (G * np.sin(slope), 0.0, -G * np.cos(slope))
    model = Model(model.bodies, pairs, gravity=gravity)
    options = IntegratorOptions(rho_inf=0.0)
    return model, block, list(simulate(model, h, t, options, q0=settled.q, v0=settled.v))


def along(block, model, states, axis=0):
    """The block's centre of mass and its velocity along ``axis`` (m, m/s) over ``states``."""
    w = block.mass_matrix() @ block.translation_field(np.eye(3)[axis]) / block.mass
    n = block.ndof
    return np.array([w @ s.q[:n] for s in states]), np.array([w @ s.v[:n] for s in states])


def stopping(h: float, mu=0.3, v0=0.5):
    """The block on the rods launched at v0 along them: its centre's travel and velocity
    over the run, and the states."""
    model, block, pairs, st = block_on_rods(mu)
    v = st.v + model.translation(block, (v0, 0.0, 0.0))
    states = list(simulate(model, h, 1.3 * v0 / (mu * G), IntegratorOptions(rho_inf=0.0),
                           q0=st.q, v0=v))  # fmt: skip
    x, vx = along(block, model, states)
    return x - x[0], vx, states


def test_a_block_sliding_along_two_rods_stops_where_coulomb_says():
    """μ = 0.3, v₀ = 0.5 m/s, h = 1 ms: while it slides the deceleration is μg to 1e-6
    (measured 2.1e-7: Σ c_j λ_j is the weight, the rows' load resolved on the block's face,
    across the rods' axes), and it stops after v₀²/(2μg) = 42.4737 mm to 1e-6 m, below the
    ½ μ g h² = 1.47 µm a step whose friction missed the positions would leave (measured 5.0e-8
    m short with one and with two BLAS threads, the same to all digits; after 20 ms the centre
    is within 2.6e-9 m of v₀t − ½μgt²: the friction sets in without a transient), at rest to
    1e-9 m/s."""
    exact = 0.5**2 / (2 * 0.3 * G)
    h = 1e-3
    x, vx, states = stopping(h)
    assert abs(x[-1] - exact) <= 1e-6
    assert abs(vx[-1]) <= 1e-9
    t = np.array([s.t for s in states])
    sliding = (t > 0.02) & (t < 0.12)
    np.testing.assert_allclose(np.diff(vx)[sliding[1:]] / h, -0.3 * G, rtol=1e-6)


def test_a_block_on_rods_holds_below_atan_mu_and_slides_above_at_the_exact_rate():
    """μ = 0.3 (atan μ = 0.2915 rad), the rods along the slope, gravity turned at once after
    settling and the turn resolved in steps of 1 ms (:func:`on_an_incline`). At θ = 0.25 rad
    the block holds: the turn moves it by its elastic compliance (measured 4.33e-8 m with one
    and with two BLAS threads, against the estimate 2.0e-8 m of the sudden load's test below;
    its centre's height moves by 7.5e-9 m: it does not bounce), bound twice one step's slide
    under the unopposed load, g sin θ h² = 2.4 µm; then it does not move over the next second
    in steps of 10 ms (measured 1.4e-14 m at most with one and two threads; bound 1e-11 m,
    round-off of positions of 0.01 m over 110 steps). At θ = 0.35 rad it slides down at
    g(sin θ − μ cos θ) = 0.599254 m/s² from the first step after the turn (measured 8.9e-7
    relative with one and two threads; bound 1e-5), the block pitched under it."""
    model, block, turn = on_an_incline(0.3, 0.25)
    x, _ = along(block, model, turn)
    z, _ = along(block, model, turn, axis=2)
    # the turn's move: below twice one step's slide under the unopposed load, ½ g sin θ h²
    assert abs(x[-1] - x[0]) <= G * np.sin(0.25) * 1e-3**2
    # no bounce: the centre's height moves by less than the block's whole elastic compression
    # under its weight, ρgH²/E = 3.9e-8 m, with the lines' local compression on top (×2.5)
    assert np.abs(z - z[0]).max() <= 1e-7
    st = turn[-1]
    states = list(simulate(model, 1e-2, 1.1, IntegratorOptions(rho_inf=0.0), q0=st.q,
                           v0=st.v))  # fmt: skip
    x, vx = along(block, model, states)
    assert np.abs(x - x[0]).max() <= 1e-11 and abs(vx[-1]) <= 1e-10
    theta = 0.35
    model, block, turn = on_an_incline(0.3, theta)
    st = turn[-1]
    h = 1e-3
    states = list(simulate(model, h, 0.1, IntegratorOptions(rho_inf=0.0), q0=st.q, v0=st.v))
    _, vx = along(block, model, states)
    np.testing.assert_allclose(np.diff(vx) / h, G * (np.sin(theta) - 0.3 * np.cos(theta)),
                               rtol=1e-5)  # fmt: skip


def test_a_sudden_load_inside_the_cone_moves_the_block_on_rods_by_its_elastic_compliance():
    """The block settled on the rods (μ = 0.3), then gravity turned at once by θ = 0.25 rad
    (tan θ = 0.255 < μ) and the run made in steps of h = 10 ms, with one and with two BLAS
    threads: between two steps of one run (the upright run carried on at 10 ms first), and
    as a new run started from the settled state (:func:`fecontact.time.coulomb.frictional_start`).
    The block holds: its centre moves by the elastic compliance of the load's path only. The
    rods are clamped at every node (they do not deflect here), so the estimate is the
    block's: F = m g sin θ = 0.0777 N shears the 2 cm layer over its 16 cm² base,
    γ = F/(A G) = 1.26e-6 with G = E/(2(1 + ν)), and moves its centre by γ H/2 = 1.26e-8 m;
    the load enters along the two 4 cm lines of contact, q = 0.97 N/m, whose line moves
    against the block's body by 2(1 − ν²) q ln(L/c)/(π E) = 7.8e-9 m (Johnson, Contact
    Mechanics §2.2; L = 2 cm the block's half width, c = 5 mm half a cell, the rows'
    reach): 2.0e-8 m in all. Measured 3.56e-8 m both ways with one and with two threads,
    all of it in the first step: the settled rows carry a sideways squeeze of up to 0.2 of
    their cone, and those the turned load brings to the cone's edge creep by up to 3.4e-8 m
    before the load settles over the others (at θ = 0.1 rad the move is 9.4e-9 m, 1.1 times
    the estimate); bound 2.5 times the estimate, 5e-8 m. One step's slide under the
    unopposed load would be ½ g sin θ h² = 1.2e-4 m (a new run's start in the mass metric
    slid 2.2 mm, rocking: docs/explanation/friction.md). No smooth step is taken again for
    a release and no Newton step is cut (measured none), and the block is at rest within
    1e-10 m/s after 0.3 s (measured 5e-14 and 3e-13 m/s)."""
    from threadpoolctl import threadpool_limits

    theta, h = 0.25, 1e-2
    model, block, pairs, settled = block_on_rods(0.3)
    tilted = Model(model.bodies, pairs, gravity=(G * np.sin(theta), 0.0, -G * np.cos(theta)))
    options = IntegratorOptions(rho_inf=0.0)
    for threads in (1, 2):
        with threadpool_limits(limits=threads, user_api="blas"):
            start = dataclasses.replace(settled, t=0.0, step=0)
            upright = list(simulate(model, h, 0.1, options, start=start))[-1]
            start = dataclasses.replace(upright, t=0.0, step=0)
            stats = StepStats(), StepStats()
            runs = (
                [start, *simulate(tilted, h, 0.3, options, start=start, stats=stats[0])],
                list(simulate(tilted, h, 0.3, options, q0=settled.q, v0=settled.v,
                              stats=stats[1])),
            )  # fmt: skip
        for states, counts in zip(runs, stats, strict=True):
            x, vx = along(block, model, states)
            assert np.abs(x - x[0]).max() <= 5e-8
            assert abs(vx[-1]) <= 1e-10
            assert counts.releases == 0 and counts.newton.line_search_cuts == 0


def test_the_sliding_block_creates_no_energy_and_is_independent_of_p_and_k(tmp_path):
    """The block launched along the rods (μ = 0.3, v₀ = 0.5 m/s) to rest: the ledger's
    ``created`` ≤ 1e-3 of its ``scale`` (measured 8.6e-7 of it) and friction dissipates the
    launch's kinetic energy ½mv₀² to 2e-4 (measured 1.0e-5); p × 1000 and k / 100 change the
    first 50 ms of the trajectory by round-off (bound 1e-8 of r; measured 2.0e-11 and 2.5e-11
    of it)."""
    model, block, _, st = block_on_rods(0.3)
    v = st.v + model.translation(block, (0.5, 0.0, 0.0))
    options = IntegratorOptions(rho_inf=0.0)
    sim = Simulation(model, dt=1e-3, t_end=0.22, name="block_on_rods", q0=st.q, v0=v,
                     options=options, output_interval=0.22)  # fmt: skip
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    ledger = summary["energy_ledger"]
    assert 0.0 <= ledger["created"] <= 1e-3 * ledger["scale"]
    kinetic = 0.5 * block.mass * 0.5**2
    assert ledger["friction_dissipation"] == pytest.approx(kinetic, rel=2e-4)
    base = list(simulate(model, 1e-3, 0.05, options, q0=st.q, v0=v))
    for change in ({"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}):
        other = list(simulate(model, 1e-3, 0.05, IntegratorOptions(rho_inf=0.0, **change),
                              q0=st.q, v0=v))  # fmt: skip
        diff = max(np.max(np.abs(a.q - b.q)) for a, b in zip(base, other, strict=True))
        assert diff <= 1e-8 * R


def test_a_rod_rolling_on_a_face_slips_at_no_row():
    """A rod along y over a block's top face (overhanging its edges), its sections turned by
    0.7 rad about the axis, rolling along x (V = ω h, h its axis' height over the face): the
    material point under every slave node moves along the face's normal only (ω × (x_j −
    p_j) = V x̂ − ωX ẑ for a node X ahead), so every row's slip is zero to round-off. Rows
    tangent to the tube's own (tilted) normal at the node would read the normal motion as
    slip (up to 0.089 V at the rows within 0.5 mm, measured), braking a rolling rod; and sliding
    without spin every row slips at c_j V."""
    block = Solid.box([-0.05, -0.05, -0.02], [0.05, 0.05, 0.0], (8, 8, 1), HARD)
    z = R + 2e-4
    bar = Beam3D.straight([0.003, -0.08, z], [0.003, 0.08, z], 4, STEEL, Section.circle(R))
    pair = Contact(block, bar, clearance=R, friction=0.3)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.02)
    q = np.zeros(model.n)
    ob = model.offset_of(bar)
    q[ob:].reshape(-1, 6)[:, 3:] = [0.0, 0.7, 0.0]
    dofs, W, T = pair.tangents(q)
    c = np.einsum("mti,mti->m", W[:, :, :3], T) / 2  # the rows' scale c_j
    rows = np.flatnonzero(c > 0.0)
    assert len(rows) >= 20
    V = 0.1
    v = np.zeros(model.n)
    beam = v[ob:].reshape(-1, 6)
    beam[:, 0], beam[:, 4] = V, V / z  # Ω body-frame: a turn about y keeps ŷ
    slip = np.einsum("mtk,mk->mt", W, v[dofs])
    assert np.abs(slip[rows]).max() <= 1e-12 * V
    beam[:, 4] = 0.0
    slip = np.einsum("mtk,mk->mt", W, v[dofs])
    np.testing.assert_allclose(np.linalg.norm(slip[rows], axis=1), c[rows] * V, rtol=1e-12)


def oblique_drop(options=None, out=None, t_end=0.003, solid_rows=True):
    """The rod drop of the frictionless tests (r = 1 cm, 8 elements, across a rubber block at
    30°, overhanging its top edges, h = 0.1 ms) thrown at (0.5, 0, −1) m/s with μ = 0.3: its
    states (or, with ``out``, the run's summary). The weighted-distance rows (``MortarBeam3D``)
    with ``solid_rows``, else the default pair."""
    block = Solid.box([-0.05, -0.05, -0.03], [0.05, 0.05, 0.0], (8, 8, 2), RUBBER)
    block.fix(block.nodes_where(lambda x: x[2] <= -0.03 + 1e-9))
    d = np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0)), 0.0])
    c = np.array([0.003, -0.002, R + 0.001])
    bar = Beam3D.straight(c - 0.08 * d, c + 0.08 * d, 8, STEEL, Section.circle(R))
    if solid_rows:  # the weighted-distance rows, named (the default blends them: tube_plane)
        pair = MortarBeam3D(block, bar, clearance=R)
        pair.friction = 0.3
    else:
        pair = Contact(block, bar, clearance=R, friction=0.3)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, -G))
    v0 = model.translation(bar, (0.5, 0.0, -1.0))
    if out is not None:
        sim = Simulation(model, dt=1e-4, t_end=t_end, name="oblique_rod", v0=v0,
                         output_interval=t_end)  # fmt: skip
        return run(sim, out, frames=False, checkpoint_every=0)
    return list(simulate(model, 1e-4, t_end, options or IntegratorOptions(), v0=v0))


def test_an_oblique_frictional_rod_drop_creates_no_energy_and_is_independent_of_p_and_k(
    tmp_path,
):
    """Impacts and persistent contact with friction, sticking and slipping rows: completed
    without halving, the ledger's ``created`` ≤ 1e-3 of ``scale`` (measured 0; friction
    dissipates 10 % of the scale); p × 1000 and k / 100 change the trajectory by round-off
    (bound 1e-8 of r; measured 4.1e-10 and 2.9e-14 of it)."""
    summary = oblique_drop(out=tmp_path, t_end=0.006)
    assert summary["status"] == "completed" and summary["step_halvings"] == 0
    ledger = summary["energy_ledger"]
    assert 0.0 <= ledger["created"] <= 1e-3 * ledger["scale"]
    base = oblique_drop()
    status = np.concatenate([s.friction.status for s in base if s.friction is not None])
    assert np.any(status == 1) and np.any(status == 2)
    for change in ({"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}):
        other = oblique_drop(IntegratorOptions(**change))
        diff = max(np.max(np.abs(a.q - b.q)) for a, b in zip(base, other, strict=True))
        assert diff <= 1e-8 * R
