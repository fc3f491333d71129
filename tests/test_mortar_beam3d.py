"""Dual mortar contact of a 3D solid against a Beam3D's tube (fecontact.contact.mortar_beam3d):
rows against central differences, rows exact where the distance is linear, a rod resting on a
block, Newton's quadratic rate, a rod dropped across a block."""

import warnings

import numpy as np
import pytest

from fecontact import Model, Solid, simulate
from fecontact.bodies import Beam3D, LinearElastic, Material, Section
from fecontact.contact import Contact
from fecontact.contact.beam3d_solid import TubeSolidContact
from fecontact.contact.geometry import closest_facet_distance
from fecontact.contact.inside import Surface
from fecontact.contact.mortar_beam3d import MortarBeam3D
from fecontact.contact.polyline_distance import closest_on_polyline, region_labels, straight_runs
from fecontact.contact.tube_line_mortar import LINE_RATIO, TubeLineMortar, face_size
from fecontact.errors import InputError
from fecontact.rotations import exp
from fecontact.simulation import Simulation, run
from fecontact.testing import group_derivative_errors
from fecontact.time.settings import IntegratorOptions
from fecontact.time.state import initial_state

STEEL = Material(210e9, nu=0.3, rho=7850.0)
RUBBER = LinearElastic(1e7, 0.3, rho=1000.0)
R = 0.01


def placed(block, bar, pair, nodes, turns=None):
    """The model of ``block`` and ``bar`` and a q putting the bar's nodes at ``nodes`` (their
    rotation vectors ``turns``)."""
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))
    q = np.zeros(model.n)
    beam = q[model.offset_of(bar) :].reshape(-1, 6)
    beam[:, :3] = nodes - bar.X
    if turns is not None:
        beam[:, 3:] = turns
    return model, q


def bent_rod_on_block(cells=(6, 6, 2), depth=0.001, make=Contact, **options):
    """A rod of four elements bent at each joint (the middle node ``depth`` below r: pressed
    into the face), turned sections, over a block of ``cells`` whose nodes are moved by 1 mm
    at random; the pair made by ``make`` (the default: ``Contact``) with ``options``."""
    block = Solid.box([-0.1, -0.1, -0.05], [0.1, 0.1, 0.0], cells, RUBBER)
    nodes = np.array([[-0.09, -0.05, R + 0.002], [-0.03, -0.01, R], [0.02, 0.02, R - depth],
                      [0.05, 0.06, R + 0.003], [0.09, 0.07, R + 0.004]])  # fmt: skip
    bar = Beam3D.straight(nodes[0], nodes[-1], 4, STEEL, Section.circle(R))
    pair = make(block, bar, clearance=R, **options)
    rng = np.random.default_rng(0)
    model, q = placed(block, bar, pair, nodes, 0.1 * rng.normal(size=(5, 3)))
    q[: block.ndof] += 1e-3 * rng.normal(size=block.ndof)
    pair.detect_within(0.02)
    return pair, model, q


def test_the_distance_to_a_polyline_and_its_regions():
    """Against the least distance to 2001 points sampled on each segment, never below it and
    above it by at most the sampling's error (Δ/2)²/(2d), Δ ≤ 5e-5 m the spacing; a chain
    turning by less than KINK at a joint is one region there, a sharper joint and the ends
    are nodes' regions."""
    rng = np.random.default_rng(6)
    nodes = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0005], [0.25, 0.05, 0.0]])
    ends = np.stack([nodes[:-1], nodes[1:]], axis=1)
    x = rng.uniform([-0.05, -0.05, 0.01], [0.3, 0.1, 0.05], size=(200, 3))
    which, xi, d = closest_on_polyline(x, ends)
    s = np.linspace(0.0, 1.0, 2001)[:, None]
    samples = np.concatenate([a + s * (b - a) for a, b in ends])
    brute = np.linalg.norm(x[:, None, :] - samples[None], axis=2).min(axis=1)
    assert np.all(brute - d >= -1e-15) and np.all(brute - d <= 2.5e-5**2 / (2 * d) + 1e-15)
    segments = np.array([[0, 1], [1, 2], [2, 3]])
    run, joint = straight_runs(ends, segments, 4)
    assert list(run) == [0, 0, 1] and list(joint) == [-1, 0, -1, -1]  # 0.005 rad, then 45°
    labels = region_labels(which, xi, segments, (run, joint))
    cap = xi[which == 0] <= 0.0  # beyond the first end: node 0's cap
    assert np.all(labels[which == 0][cap] == -1) and np.all(labels[which == 0][~cap] == 0)


def test_mortar_rows_are_the_derivatives_of_the_weighted_gaps():
    """G against central differences of the rows along every dof (the solid's nodes, the
    beam's translations and rotations, composed on the right), the curvature against those
    of G. Step 1e-7: the closest point of a quadrature point changes region (an end cap, the
    concave side of a bent joint, where D's gradient jumps) within 1e-6 of some points,
    which a step of 1e-6 crosses (8e-5 measured there); at 1e-7 the errors are 3.2e-10 and
    3.8e-9 against a largest curvature of 53 (bounds 1e-8 and 1e-6 relative)."""
    pair, model, q = bent_rod_on_block()
    assert isinstance(pair, MortarBeam3D)
    g, dofs, _, _ = pair.evaluate(q)
    rows = np.flatnonzero(np.isfinite(g))
    assert len(rows) >= 50 and g[rows].min() < 0.0
    rotations = model.offset_of(pair.beam) + pair.beam.rotation_triples.ravel()
    assert not np.isin(dofs, rotations).any()  # a circular tube ignores the sections' turn
    solid = np.unique(dofs[rows][:, : pair.dofs.shape[1] - pair.beam.n_nodes * 3])
    beam = model.offset_of(pair.beam) + pair.beam.node_translation_dofs(None).ravel()
    some = np.random.default_rng(4).choice(solid, 40, replace=False)  # of 300: time
    along = np.concatenate([some, beam, rotations[:3]])
    err_g, err_h = group_derivative_errors(pair, model, q, along, 1e-7)
    assert err_g <= 1e-8 and err_h <= 1e-6


def test_rows_are_the_nodes_own_distances_where_the_distance_is_linear():
    """The rod's axis lies in the plane of the block's side face y = 0.04 m, above the block:
    on that face D = z_axis − z − r is linear, so the row of each node whose triangles all lie
    on it is its own D (biorthogonality, ∫ Φ_j λ_k dA₀ = δ_jk |e|₀/3) to round-off, with the
    face's nodes moved within its plane (any in-plane strain) and everything turned and moved
    rigidly."""
    block = Solid.box([0.0, -0.04, -0.04], [0.1, 0.04, 0.0], (4, 4, 3), RUBBER)
    bar = Beam3D.straight([-0.02, 0.04, 0.015], [0.12, 0.04, 0.015], 5, STEEL,
                          Section.circle(R))  # fmt: skip
    pair = MortarBeam3D(block, bar, clearance=R, margin=1.0)
    X = block.X
    side = np.all(np.abs(X[pair.facets][..., 1] - 0.04) < 1e-12, axis=1)
    inner = np.setdiff1d(pair.facets[side], pair.facets[~side])  # nodes with side triangles only
    assert len(inner) >= 6
    rng = np.random.default_rng(3)
    x = X.copy()
    on = np.abs(X[:, 1] - 0.04) < 1e-12
    x[on] += 2e-3 * rng.normal(size=(on.sum(), 3)) * [1.0, 0.0, 1.0]  # in the face's plane
    Rt, shift = exp(np.array([0.3, -0.2, 0.5])), np.array([0.01, -0.02, 0.03])
    nodes = bar.X @ Rt.T + shift
    model, q = placed(block, bar, pair, nodes)
    q[: block.ndof] = (x @ Rt.T + shift - X).ravel()
    rows = np.searchsorted(pair.nodes, inner)
    d = pair.node_distances(q)[rows]
    assert d.min() > 0.0
    np.testing.assert_allclose(pair.gaps(q)[rows], d, rtol=1e-12, atol=1e-15)


def test_mortar_is_the_default_and_the_options_are_checked_by_name():
    """Mortar for a 3D solid and a Beam3D named either way: the solid's rows on faces of
    cells finer than LINE_RATIO radii, the beam's rows on coarser ones (here 10 cm cells
    against a 1 cm tube); ``method="node-to-surface"`` keeps the beam's nodes against the
    boundary (either way); ``nodes``, no radius and bad options refused with the parameter's
    name before any work; friction taken."""
    block = Solid.box([-0.1, -0.1, -0.05], [0.1, 0.1, 0.0], (2, 2, 1), RUBBER)
    fine = Solid.box([-0.1, -0.1, -0.05], [0.1, 0.1, 0.0], (16, 16, 4), RUBBER)
    assert face_size(fine) < LINE_RATIO * R <= face_size(block)
    bar = Beam3D.straight([-0.05, 0.0, 0.02], [0.05, 0.0, 0.02], 2, STEEL, Section.circle(R))
    for a, b in ((block, bar), (bar, block)):
        pair = Contact(a, b, clearance=R)
        assert isinstance(pair, TubeLineMortar) and pair.body is block and pair.clearance == R
        assert isinstance(Contact(a, b, clearance=R, method="node-to-surface"), TubeSolidContact)
    for a, b in ((fine, bar), (bar, fine)):
        pair = Contact(a, b, clearance=R)
        assert isinstance(pair, MortarBeam3D) and pair.body is fine and pair.clearance == R
    with pytest.raises(InputError, match="nodes: a mortar contact"):
        Contact(block, bar, nodes=[0], clearance=R)
    with pytest.raises(InputError, match="clearance"):
        Contact(block, bar)
    assert Contact(block, bar, clearance=R, friction=0.3).friction == 0.3
    with pytest.raises(InputError, match="subdivisions"):
        MortarBeam3D(block, bar, clearance=R, subdivisions=0)
    with pytest.raises(InputError, match="restitution"):
        Contact(block, bar, clearance=R, restitution=1.5)
    with pytest.raises(InputError, match="method"):
        Contact(block, bar, clearance=R, method="segments")


def test_rows_left_out_are_beyond_the_margin():
    """A row reported +inf (its node farther than margin + REACH × its longest edge) has a
    weighted gap above the margin, and the rows kept are those of the whole integral."""
    _, model, q = bent_rod_on_block()
    block, bar = model.bodies
    everything = MortarBeam3D(block, bar, clearance=R, margin=1.0)
    Model([block, bar], [everything], gravity=(0.0, 0.0, 0.0))
    full = everything.gaps(q)
    for margin in (1e-3, 3e-3, 8e-3):
        pair = MortarBeam3D(block, bar, clearance=R, margin=margin)
        Model([block, bar], [pair], gravity=(0.0, 0.0, 0.0))
        g = pair.gaps(q)
        kept = np.isfinite(g)
        assert 0 < kept.sum() < pair.size
        np.testing.assert_allclose(g[kept], full[kept], rtol=0, atol=1e-15)
        assert np.all(full[~kept] > margin)


def rod_resting_on_block(n_rod: int):
    """A steel rod (r = 2 cm, ``n_rod`` elements) lying along x on a rubber block 0.1 × 0.08 ×
    0.04 m (10 × 8 × 2 cells of 1 cm: finer than r) over its whole length, its base clamped
    and its two x faces on rollers (a slice of a long slab), the rod held in y (a rod on a
    flat face has no lateral stiffness); gravity, brought to rest by ρ∞ = 0 at steps far
    beyond the periods. Returns the pair, the final state and the model."""
    L, r = 0.1, 0.02
    block = Solid.box([0.0, -0.04, -0.04], [L, 0.04, 0.0], (10, 8, 2), RUBBER)
    block.fix(block.nodes_where(lambda x: x[2] <= -0.04 + 1e-9))
    block.fix(block.nodes_where(lambda x: (x[0] <= 1e-9) | (x[0] >= L - 1e-9)), "x")
    bar = Beam3D.straight([0.0, 0.0, r + 1e-3], [L, 0.0, r + 1e-3], n_rod, STEEL,
                          Section.circle(r))  # fmt: skip
    for k in range(n_rod + 1):
        bar.fix(k, "y")
    bar.fix(0, "x")
    pair = Contact(block, bar, clearance=r)
    model = Model([block, bar], [pair], gravity=(0.0, 0.0, -9.81))
    st = list(simulate(model, 1e-2, 0.3, IntegratorOptions(rho_inf=0.0)))[-1]
    return pair, st, model


def test_a_rod_resting_on_a_block_carries_its_weight():
    """At rest: the rows in contact hold to round-off, the vertical forces of the rows on the
    rod, Σ λ_j ∂g_j/∂z, equal its weight (measured 4.5e-12 relative; bound 1e-9) and the
    block takes the same; along the interior of the block the line load on the block's
    columns of nodes is the rod's weight per length within 8 % (measured 4.4–6.8 %: the face's
    edge nodes x = 0, L carry almost nothing, as their dual functions span the end faces too,
    where the tube is farther, and their neighbours carry 30 % more)."""
    pair, st, model = rod_resting_on_block(5)
    block, bar = pair.body, pair.beam
    assert np.abs(st.v).max() < 1e-6  # at rest
    w = STEEL.rho * np.pi * 0.02**2 * 9.81  # weight per length (N/m)
    lam = st.mean_force()
    g, dofs, G, _ = pair.evaluate(st.q)
    on = lam > 0.0
    assert on.sum() >= 8 and np.abs(g[on]).max() < 1e-12
    f = np.zeros(model.n)
    np.add.at(f, dofs, lam[:, None] * G)
    rod = f[model.offset_of(bar) :].reshape(-1, 6)[:, 2]
    assert rod.sum() == pytest.approx(w * 0.1, rel=1e-9)
    fz = f[: block.ndof].reshape(-1, 3)[:, 2]
    assert -fz.sum() == pytest.approx(w * 0.1, rel=1e-9)
    columns = [-fz[np.isclose(block.X[:, 0], x)].sum() / (w * 0.01) for x in np.arange(2, 9) / 100]
    np.testing.assert_allclose(columns, 1.0, rtol=0.08)


def newton_residuals():
    """Newton's method on the projection of the block and the rod pressed 1 mm into it onto
    the weighted gaps' surface: min ½|q − q₀|² over every dof subject to g_j(q) = 0 on the
    rows pressed at q₀, the rows' exact curvature in the matrix (the weighted-distance rows,
    ``MortarBeam3D``). |r| per iteration."""
    block = Solid.box([-0.05, -0.05, -0.03], [0.05, 0.05, 0.0], (8, 8, 2), RUBBER)
    a, b = np.array([-0.06, -0.02, R - 1e-3]), np.array([0.06, 0.03, R - 2e-3])
    bar = Beam3D.straight(a, b, 3, STEEL, Section.circle(R))
    pair = MortarBeam3D(block, bar, clearance=R)
    model, q0 = placed(block, bar, pair, bar.X)
    g, dofs, _, _ = pair.evaluate(q0)
    rows = np.flatnonzero(g < 0.0)
    assert len(rows) >= 3
    n = model.n
    q, lam, out = q0.copy(), np.zeros(len(rows)), []
    for _ in range(8):
        g, dofs, Gv, _ = pair.evaluate(q)
        G = np.zeros((len(rows), n))
        np.add.at(G, (np.arange(len(rows))[:, None], dofs[rows]), Gv[rows])
        r = np.concatenate([q - q0 + G.T @ lam, g[rows]])
        out.append(np.linalg.norm(r))
        if out[-1] < 1e-14:
            break
        C = np.zeros((n, n))
        H = pair.hessians(q, rows)
        np.add.at(C, (dofs[rows][:, :, None], dofs[rows][:, None, :]), lam[:, None, None] * H)
        S = np.block([[np.eye(n) + C, G.T], [G, np.zeros((len(rows),) * 2)]])
        step = np.linalg.solve(S, -r)
        q += step[:n]
        lam += step[n:]
    return np.array(out)


def test_newton_converges_quadratically_with_the_rows_curvature():
    """|r_{k+1}| ≤ C |r_k|² with C of the order of the curvature (1/m): measured 5.2e-3,
    6.7e-5, 4.5e-8, 4.7e-14, 2.6e-18."""
    r = newton_residuals()
    assert r[-1] < 1e-13 * max(1.0, r[0]) or r[-1] < 1e-14
    rates = r[2:] / r[1:-1] ** 2
    assert len(r) <= 7
    assert np.all(rates[r[2:] > 1e-13] < 1e3)


def rod_drop(method=None, options=None, t_end=0.003, out=None):
    """A steel rod (r = 1 cm, 16 cm, 8 elements), 1 mm above a rubber block 0.1 × 0.1 ×
    0.03 m (8 × 8 × 2 cells, base clamped), across it at 30° and beyond its top edges, falling
    at 1 m/s under gravity, at h = 0.1 ms. Returns the states and the model (or, with
    ``out``, the run's summary)."""
    block = Solid.box([-0.05, -0.05, -0.03], [0.05, 0.05, 0.0], (8, 8, 2), RUBBER)
    block.fix(block.nodes_where(lambda x: x[2] <= -0.03 + 1e-9))
    d = np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0)), 0.0])
    c = np.array([0.003, -0.002, R + 0.001])
    bar = Beam3D.straight(c - 0.08 * d, c + 0.08 * d, 8, STEEL, Section.circle(R))
    model = Model([block, bar], [Contact(block, bar, clearance=R, method=method)],
                  gravity=(0.0, 0.0, -9.81))  # fmt: skip
    v0 = model.translation(bar, (0.0, 0.0, -1.0))
    if out is not None:
        sim = Simulation(model, dt=1e-4, t_end=t_end, name="rod_on_block", v0=v0,
                         output_interval=t_end)  # fmt: skip
        return run(sim, out, frames=False, checkpoint_every=0)
    return list(simulate(model, 1e-4, t_end, options or IntegratorOptions(), v0=v0)), model


def beam_nodes_inside(model, states) -> float:
    """How deep (m, ≥ 0) the beam's nodes ever lie below the plane of the block's boundary
    triangle closest to them (the deformed block; none of the solver's gaps)."""
    block, bar = model.bodies
    tri, deepest = block.contact_facets(), 0.0
    for st in states:
        xb, x = block.positions(st.q[: block.ndof]), bar.positions(st.q[block.ndof :])
        dist, g = closest_facet_distance(
            np.repeat(x, len(tri), 0), np.tile(xb[tri], (len(x), 1, 1))
        )
        k = np.argmin(dist.reshape(len(x), -1), axis=1)
        deepest = max(deepest, -float(g.reshape(len(x), -1)[np.arange(len(x)), k].min()))
    return max(deepest, 0.0)


def test_a_rod_dropped_across_a_block_stays_out_and_creates_no_energy(tmp_path):
    """No step halved; the rod strikes and leaves; no slave node inside the tube beyond the
    stand-off of the weighted gaps (measured 0 m; bound 0.1 H²/r with H the face's edge, the
    largest stand-off measured on a rod over a face, 0.081 H²/r); no beam node inside the
    block; the energy ledger's ``created`` ≤ 1e-3 of its ``scale`` (measured 0). The block's
    top edges cross the tube between its nodes, which the beam's nodes alone do not see."""
    summary = rod_drop(out=tmp_path)
    assert summary["status"] == "completed" and summary["step_halvings"] == 0
    ledger = summary["energy_ledger"]
    assert 0.0 <= ledger["created"] <= 1e-3 * ledger["scale"]
    states, model = rod_drop()
    H = 0.1 / 8
    depth = max(model.contacts.watches[0].depth(s.q)[0] for s in states)
    assert depth <= 0.1 * H**2 / R
    assert beam_nodes_inside(model, states) == 0.0
    assert any(s.mean_force().sum() > 0.0 or s.impulse.sum() > 0.0 for s in states)
    bar_vz = states[-1].v[model.offset_of(model.bodies[1]) :].reshape(-1, 6)[:, 2]
    assert bar_vz.mean() > 0.0  # it has rebounded


@pytest.fixture(scope="module")
def rod_drop_base():
    """The rod drop at the default p and k over 1.5 ms, run once for both changes."""
    return rod_drop(t_end=0.0015)[0]


@pytest.mark.parametrize("change", [{"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}])
def test_the_rod_drop_is_independent_of_p_and_k(change, rod_drop_base):
    """p × 1000 and k / 100 change the trajectory by round-off (bound 1e-8 of the radius;
    measured 1.4e-12 and 1.0e-12 of it)."""
    base = rod_drop_base
    other = rod_drop(options=IntegratorOptions(**change), t_end=0.0015)[0]
    assert any(np.any(s.lam > 0.0) or np.any(s.impulse > 0.0) for s in base)
    diff = max(np.max(np.abs(a.q - b.q)) for a, b in zip(base, other, strict=True))
    assert diff <= 1e-8 * R


def rod_over_coarse_block(lift, at=(0.0, 0.0), solid_rows=False):
    """A steel rod (r = 5 mm, 10 cm, 4 elements) ``lift`` (m) above (below: into) the top face
    of a rubber block 0.6 m wide in 4 × 4 cells (15 cm triangles, 30 times the tube's radius),
    its middle over ``at``; its base clamped. The pair: the default (the beam's rows), or
    with ``solid_rows`` the solid's (``MortarBeam3D``)."""
    r = 0.005
    block = Solid.box([-0.3, -0.3, -0.04], [0.3, 0.3, 0.0], (4, 4, 2), RUBBER)
    block.fix(block.nodes_where(lambda x: x[2] <= -0.04 + 1e-9))
    c = np.array([*at, r + lift])
    d = np.array([0.05, 0.015, 0.0])
    bar = Beam3D.straight(c - d, c + d, 4, STEEL, Section.circle(r))
    pair = MortarBeam3D(block, bar, clearance=r) if solid_rows else Contact(block, bar, clearance=r)
    model = Model([block, bar], [pair], (0.0, 0.0, -9.81))
    return model, pair


def test_a_rod_above_a_coarse_block_is_admitted():
    """2 mm above the face, no node inside the tube and no point of the tube inside the block.
    The default pair (the beam's rows) reads every row at the tube's own gap, 2 mm to
    round-off, and starts without a warning. The solid's rows read down to −3.9 mm (the dual
    functions' negative lobes on triangles 30 times the tube's radius): their start check
    reads every exact gap ≥ 2 mm and warns of the stand-off."""
    model, pair = rod_over_coarse_block(0.002)
    assert isinstance(pair, TubeLineMortar)
    q = np.zeros(model.n)
    np.testing.assert_allclose(pair.gaps(q), 0.002, rtol=0, atol=1e-15)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        initial_state(model)
    model, pair = rod_over_coarse_block(0.002, solid_rows=True)
    rows = pair.gaps(q)
    assert rows.min() < -0.003
    exact = pair.admissible_gaps(q, rows)
    # the tube's lowest line is 2 mm above the flat face: the exact gaps to round-off
    assert exact.min() == pytest.approx(0.002, abs=1e-12)
    with pytest.warns(UserWarning, match="stand-off"):
        initial_state(model)


@pytest.mark.parametrize("solid_rows", [False, True])
@pytest.mark.parametrize("depth", [0.001, 0.003])
def test_a_rod_inside_a_coarse_block_is_refused(depth, solid_rows):
    """The tube over a node of the coarse face, ``depth`` (m) into it: refused, naming the
    contact and the depth: the beam's rows read it (the tube's own gap), the solid's by the
    node's depth in the tube (their rows read −20 mm there: the stand-off and the depth
    together)."""
    model, pair = rod_over_coarse_block(-depth, solid_rows=solid_rows)
    q = np.zeros(model.n)
    rows = pair.gaps(q)
    assert pair.admissible_gaps(q, rows).min() == pytest.approx(-depth, abs=1e-12)
    with pytest.raises(InputError, match=rf"contact \d+ penetrates by {depth:.3e} m"):
        next(simulate(model, 1e-4, 1e-4))


def test_a_tube_deeper_in_the_solid_than_its_rows_is_refused():
    """A tube 1 mm into a face between the nodes (a fine face: 1 cm cells; no node inside),
    whose weighted-distance rows (``MortarBeam3D``) read −0.62 mm, is refused by the shallower
    of the two depths; the same tube resting where its least row is zero, dipping between the
    nodes by the rows' own stand-off, is admitted. (The default rows on this face, blended
    toward the tangent plane, read the tube's exact depth: ``tests/test_tube_line_mortar``.)"""
    block = Solid.box([-0.05, -0.05, -0.02], [0.05, 0.05, 0.0], (10, 10, 2), RUBBER)
    model = None
    for lift in (-0.001, 0.0):
        bar = Beam3D.straight([-0.03, 0.005, R + lift], [0.03, 0.005, R + lift], 6, STEEL,
                              Section.circle(R))  # fmt: skip
        model = Model([block, bar], [MortarBeam3D(block, bar, clearance=R)], (0, 0, -9.81))
        pair = model.contacts.pairs[0]
        q = np.zeros(model.n)
        rows = pair.gaps(q)
        exact = pair.admissible_gaps(q, rows)
        assert pair.node_distances(q)[np.isfinite(rows)].min() > 0.0  # no node inside
        if lift < 0.0:
            tube = Surface(block.contact_facets()).signed_distance(block.X, bar.X, pad=R)[0]
            assert tube.min() - R == pytest.approx(-0.001, rel=1e-9)
            assert exact.min() == pytest.approx(rows.min(), rel=1e-12)
            assert -0.001 < rows.min() < -0.0005
            with pytest.raises(InputError, match=rf"penetrates by {-rows.min():.3e} m"):
                initial_state(model)
    # lowered until the least row is zero (bisection): the tube dips into the face, admitted
    beam = q[model.offset_of(bar) :].reshape(-1, 6)
    lo, hi = -0.2 * R, 0.0
    for _ in range(60):
        beam[:, 2] = 0.5 * (lo + hi)
        lo, hi = (lo, beam[0, 2]) if pair.gaps(q).min() >= 0.0 else (beam[0, 2], hi)
    beam[:, 2] = hi
    rows = pair.gaps(q)
    assert 0.0 <= rows.min() < 1e-12
    assert pair.admissible_gaps(q, rows).min() >= 0.0
    centre = bar.X + beam[:, :3]
    assert Surface(block.contact_facets()).signed_distance(block.X, centre, pad=R)[0].min() < R
