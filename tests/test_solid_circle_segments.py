"""A 2D solid's boundary segments against a rigid Circle seen from outside: a peg narrower
than a boundary edge stays out between two nodes (node rows let it 4 mm in), and a peg right
under a node is held by one row, not by the two segments meeting there."""

import numpy as np
import pytest

from fecontact import Model
from fecontact.bodies import LinearElastic, Solid
from fecontact.contact import Circle, Contact
from fecontact.contact.contact_set import candidates
from fecontact.contact.node_pairs import NodeContact
from fecontact.contact.segment_pairs import SegmentCircleContact
from fecontact.simulation import Simulation, run
from fecontact.testing import gap_derivatives_error
from fecontact.time import IntegratorOptions, simulate

R = 0.05
SOFT = LinearElastic(1e6, 0.3, rho=1000.0)


def disk_at_peg(under: bool, mu: float, restitution: float = 0.0, off: float = 0.0):
    """A disk (R, 41 boundary nodes, edges 12.5 mm) along x onto a fixed peg of R/5 on the
    line of its pole node (``under``; ``off`` (m) off it) or half an edge off it (between two
    nodes)."""
    disk = Solid.disk([-1.2 * R - 0.001, 0.0], R, 2, SOFT)
    circle = Circle([0.0, off if under else 0.5 * disk.min_edge_length], 0.2 * R)
    pair = Contact(disk, circle, friction=mu, restitution=restitution)
    return disk, circle, Model([disk], [pair], (0.0, 0.0))


def peg_depth(disk, circle, q) -> float:
    """The peg's depth into the boundary polygon from the exact geometry: its radius less its
    centre's distance to the nearest boundary segment (the centre never crosses the boundary
    here: the depth stays below the radius)."""
    x = disk.positions(q[: disk.ndof])
    facets = disk.boundary_facets()
    a, b = x[facets[:, 0]], x[facets[:, 1]]
    t, c = b - a, circle.center
    s = np.clip(np.einsum("md,md->m", c - a, t) / np.einsum("md,md->m", t, t), 0.0, 1.0)
    return circle.radius - float(np.min(np.linalg.norm(a + s[:, None] * t - c, axis=1)))


def test_the_pair_is_chosen_once_by_the_kind_of_circle_and_mesh():
    disk = Solid.disk([0.0, 0.0], R, 1, SOFT)
    pair = Contact(disk, Circle([0.0, 0.07], 0.01))
    assert isinstance(pair, SegmentCircleContact) and pair.size == len(disk.boundary_facets())
    # a convex cavity cannot enter between nodes; named nodes are the user's rows
    assert isinstance(Contact(disk, Circle([0.0, 0.0], 0.1, inside=True)), NodeContact)
    named = Contact(disk, Circle([0.0, 0.07], 0.01), nodes=disk.boundary_nodes())
    assert isinstance(named, NodeContact) and named.watch() is not None
    # a P2 boundary is curved: its nodes, with the watch on the chords
    p2 = Contact(Solid.disk([0.0, 0.0], R, 1, SOFT, element="P2"), Circle([0.0, 0.07], 0.01))
    assert isinstance(p2, NodeContact) and p2.watch() is not None


@pytest.mark.parametrize("seed", [0, 1])
def test_segment_gap_derivatives_on_a_deformed_disk(seed):
    disk, _, model = disk_at_peg(False, 0.0)
    pair = model.contacts.pairs[0]
    q = 1e-3 * np.random.default_rng(seed).normal(size=model.n)
    # central differences at eps = 1e-7: O(eps²) truncation, O(1e-16/eps) round-off
    err_g, err_h = gap_derivatives_error(pair, q)
    assert err_g < 1e-7 and err_h < 1e-6


def test_a_node_under_the_peg_has_one_row():
    disk, circle, model = disk_at_peg(True, 0.0)
    pair = model.contacts.pairs[0]
    q = np.zeros(model.n)
    # the pole node onto the peg
    q[: disk.ndof] = model.translation(disk, (0.001, 0.0))[: disk.ndof]
    g = pair.gaps(q)
    pole = np.argmax(disk.positions(q[: disk.ndof])[:, 0])
    at_pole = g[np.any(pair.segments == pole, axis=1)]
    # the pole node touches the peg (g = 0 to round-off) and both segments at it reach it
    # there: one row holds it, the other reads no row (+inf)
    assert np.isclose(g.min(), 0.0, atol=1e-15) and np.isclose(np.min(at_pole), 0.0, atol=1e-15)
    assert np.count_nonzero(np.isclose(g, 0.0, atol=1e-15)) == 1
    assert np.sort(at_pole)[1] == np.inf


@pytest.mark.parametrize("under", [False, True])
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_a_thin_peg_stays_out_of_the_boundary(under, mu, tmp_path):
    disk, circle, model = disk_at_peg(under, mu)
    v0 = model.translation(disk, (1.0, 0.0))
    deepest = max(peg_depth(disk, circle, st.q) for st in simulate(model, 1e-4, 0.008, v0=v0))
    # node rows let the peg 4.0 mm in between two nodes; the segments hold the gap to the
    # correction's tolerance (1e-12 of the model's size) up to the round-off of the distance
    assert deepest <= 1e-12
    summary = run(Simulation(model, dt=1e-4, t_end=0.008, v0=v0), tmp_path, frames=False,
                  checkpoint_every=0)  # fmt: skip
    assert summary["status"] == "completed" and summary["max_penetration"] <= 1e-12
    # the two segments at a node never both hold it (before: least-squares multipliers at
    # every step under the node) and a row changing segment at the node retakes no step
    assert summary["least_squares_multipliers"] == 0 and summary["step_halvings"] == 0


def test_a_row_left_out_at_a_convex_node_is_a_candidate():
    disk, circle, model = disk_at_peg(True, 0.0)
    pair = model.contacts.pairs[0]
    q = np.zeros(model.n)
    q[: disk.ndof] = model.translation(disk, (0.001, 0.0))[: disk.ndof]
    pole = np.argmax(disk.positions(q[: disk.ndof])[:, 0])
    at_pole = np.flatnonzero(np.any(pair.segments == pole, axis=1))
    # one segment at the pole reads no row, yet its distance (the node's, 0 to round-off)
    # makes it a candidate: a correction that dents the node makes it a row
    assert np.count_nonzero(np.isinf(pair.gaps(q)[at_pole])) == 1
    assert np.allclose(pair.reach(q)[at_pole], 0.0, atol=1e-15)
    cand = candidates(model.contacts, q, model.contacts.gaps(q), 1e-3)
    assert set(at_pole) <= set(cand)


@pytest.mark.parametrize("off", [0.0, 1e-9])
def test_a_node_dented_within_a_correction_is_held_by_both_segments(off, tmp_path):
    # 10 m/s, e_N 1: at 0.54 ms the predictor has the pole node convex under the peg (one
    # row) and the correction dents it, the peg then touching both segments inside them
    # (xi 0.026 and 0.974); before, the second segment was no candidate and the step was
    # retaken with the peg 6.6e-6 m into it
    disk, _, model = disk_at_peg(True, 0.3, restitution=1.0, off=off)
    v0 = model.translation(disk, (10.0, 0.0))
    sim = Simulation(model, dt=1.08e-4, t_end=0.0012, v0=v0)
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    assert summary["step_halvings"] == 0 and summary["penetration_retakes"] == 0
    assert summary["least_squares_multipliers"] == 0
    # the correction holds the gaps to its tolerance, 1e-12 of the model's size (measured
    # 2.7e-15 m)
    assert summary["max_penetration"] <= 1e-12


def test_rows_thrown_off_by_restitution_strike_again_at_their_instant(tmp_path):
    # the peg in the dent's V, 1e-9 m off the node, 10 m/s, e_N 1, mu 0.3, h/8 (13.5 us):
    # Newton's law throws the two segment rows off at about 11 m/s every ten steps; taken as
    # a lasting contact's re-closing at the step's end, the correction pushed the rows out of
    # the peg and its strain created 4.3e-3 of the run's scale (152 closings at the step's
    # end, 2 located)
    disk, _, model = disk_at_peg(True, 0.3, restitution=1.0, off=1e-9)
    v0 = model.translation(disk, (10.0, 0.0))
    sim = Simulation(model, dt=1.08e-4 / 8, t_end=0.0121, v0=v0, output_interval=0.0121)
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    # the rebounding rows' closings are located (34 impacts); 4 closings beside the rows'
    # own strikes are left to the step's end
    assert summary["localization_fallbacks"]["persistent"] <= 10
    assert summary["localized_impacts"] >= 20
    # located, what is left is the gain of Newton's law with Coulomb's at the strikes (the
    # tangential impulses' positive work as a strike reverses the slip): 9.0e-5 here, 1.2e-4
    # at h/32, the same before and after (on the node it is 1.9e-2 at h/32:
    # docs/validation/contact_pairs.md); 5e-4 leaves room for the strikes' instants to move
    # with round-off, the step-end closings' 4.3e-3 is 9x above it
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 5e-4 * ledger["scale"]


@pytest.mark.parametrize("div", [1, 4])
def test_poissons_law_restitutes_no_smooth_force_a_held_row_gives_up(div, tmp_path):
    # the peg 1e-9 m off the node, 10 m/s, e_N 1, mu 0.3, Poisson's law: one segment row is
    # held by its smooth force when the other strikes (h, t = 0.756 ms: approach
    # -0.096 m/s). The held row lets its force's impulse go (-0.43 N s of its own, total 0)
    # and through the rows' coupling the struck row's compression takes it (+0.44 N s);
    # restituted as percussion, both rows left at 10 m/s and the jump did +2.3 J: 5.8e-3
    # (h) and 5.1e-3 (h/4) of the scale created, now 0 and 1.4e-5
    disk, _, model = disk_at_peg(True, 0.3, restitution=1.0, off=1e-9)
    v0 = model.translation(disk, (10.0, 0.0))
    opts = IntegratorOptions(impact_law="poisson")
    sim = Simulation(model, dt=1.08e-4 / div, t_end=0.0121, v0=v0, output_interval=0.0121,
                     options=opts)  # fmt: skip
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    # Poisson's law on the node creates at most 7.8e-5 of the scale at any h
    # (docs/validation/contact_pairs.md); 1e-4 is 50x below the fault's 5e-3
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 1e-4 * ledger["scale"]
