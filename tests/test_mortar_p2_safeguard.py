"""The pointwise rows of two P2 solids' quadratic mortar faces: a node's own gap to the other
solid's curved segment, and the fast P2 disks that these rows and the fade of pairs far in
front let pass their first contact (docs/explanation/mortar.md, *Quadratic faces*)."""

import numpy as np
import pytest

from fecontact import Contact, Model, Solid, run
from fecontact.bodies.materials import NeoHookean
from fecontact.contact.mortar_p2_safeguard import DeepNodeRowsP2, curved_gaps
from fecontact.contact.mortar_safeguard import shortest_edge
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation

RUBBER = NeoHookean(1e7, 0.3, 1000.0)


def test_a_node_on_a_dented_p2_face_touches_it():
    """A point on a dented quadratic segment (0.2 m long, the body above it, its mid node
    5 mm above the ends' chord, into the body) reads a zero gap, where the flat pieces'
    plane gap puts it behind them by their sagitta (1.25 mm at ξ = ±½): the rows hold nodes
    off the curve, not off the pieces. Off the curve along its normal the gap is that
    distance (round-off ~1e-17 m)."""
    a, b, m = np.array([-0.1, 0.0]), np.array([0.1, 0.0]), np.array([0.0, 0.005])
    xi = np.array([-0.7, -0.5, 0.0, 0.3, 0.5])
    point = (np.outer(xi * (xi - 1) / 2, a) + np.outer(xi * (xi + 1) / 2, b)
             + np.outer(1 - xi * xi, m))  # fmt: skip
    tangent = np.outer(xi - 0.5, a) + np.outer(xi + 0.5, b) + np.outer(-2 * xi, m)
    normal = np.stack([tangent[:, 1], -tangent[:, 0]], 1)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    for offset in (0.0, 0.002, -0.001):
        z = np.concatenate([point + offset * normal, np.tile(np.r_[a, b, m], (len(xi), 1))], 1)
        assert np.allclose(curved_gaps(z, None).v, offset, rtol=0.0, atol=1e-15)
    # the plane gap of the piece m → b at ξ = ½: 1.25 mm inside, measured across x
    piece = (b - m) / np.linalg.norm(b - m)
    plane = (point[4] - m) @ np.array([piece[1], -piece[0]])
    assert plane == pytest.approx(-0.00125 * piece[0], rel=1e-12)


def test_curved_gap_derivatives_are_exact():
    """Gradients and Hessians over the node's and the segment's 8 coordinates against central
    differences, feet inside the segments and beyond an end (clamped). Step 1e-7 m on
    segments of ~5 cm: measured 2e-11 (gradients) and 7e-11 of the largest entry (Hessians);
    the differences' error falls as the step squared (5e-9 at 1e-6 m, 5e-7 at 1e-5 m:
    truncation, the derivatives exact)."""
    rng = np.random.default_rng(3)
    a = np.array([-0.025, 0.0]) + rng.normal(0, 0.002, (6, 2))
    b = np.array([0.025, 0.0]) + rng.normal(0, 0.002, (6, 2))
    m = np.array([0.0, 0.004]) + rng.normal(0, 0.002, (6, 2))
    x = np.c_[np.linspace(-0.03, 0.03, 6), rng.normal(0.0, 0.003, 6)]
    z = np.concatenate([x, a, b, m], axis=1)
    jet, eps = curved_gaps(z, True), 1e-7
    for i in range(8):
        d = np.zeros_like(z)
        d[:, i] = eps
        up, down = curved_gaps(z + d, False), curved_gaps(z - d, False)
        assert np.abs((up.v - down.v) / (2 * eps) - jet.g[:, i]).max() < 1e-9
        fd = (up.g - down.g) / (2 * eps) - jet.h[:, :, i]
        assert np.abs(fd).max() < 1e-9 * max(1.0, np.abs(jet.h).max())


def test_p2_interfaces_take_curved_pointwise_rows():
    """Both passes of a P2 interface (the slave's nodes, the master's) read the curved
    segments, with the allowance of the flat rows (half a per cent of a piece)."""
    left = Solid.disk([-0.051, 0.0], 0.05, 1, RUBBER, element="P2")
    right = Solid.disk([0.051, 0.0], 0.05, 1, RUBBER, element="P2")
    pair = Contact(left, right)
    assert isinstance(pair.pointwise, DeepNodeRowsP2)
    assert isinstance(pair.master_rows, DeepNodeRowsP2)
    edge = shortest_edge(right, right.contact_facets())
    assert pair.pointwise.allowance == pytest.approx(0.005 * edge)


@pytest.mark.slow
def test_fast_off_centre_p2_disks_pass_their_first_contact(tmp_path):
    """Two P2 disks at 14.5 m/s each, 0.3 R off centre, 8 Δx/c (a step moves each by one
    boundary cell): they stopped in the smooth step of their first contact (step 3). Run
    through the contact's first steps (to 4.5 ms: the first contact is at step 3 of
    0.86 ms, held nodes at steps 3-5): it completes, no node deeper than 1 % of the shortest
    edge (the run's own watch; held nodes end at the allowance, measured 0.50 %), no energy
    created (measured 2.8e-16 of the scale; 1e-6 leaves room for round-off of the ledger's
    sums, far below the 0.1 % a failed correction creates). About 40 CPU s (16 halvings)."""
    disk = Solid.disk([0.0, 0.0], 0.05, 2, RUBBER)
    h = wave_step(disk, 8.0)
    speed = disk.min_edge_length / h  # one boundary cell a step
    h = min(wave_step(Solid.disk([0, 0], 0.05, 2, RUBBER, element="P2"), 8.0), h)
    gap = max(0.002, 5.0 * speed * h)
    left = Solid.disk([-0.05 - 0.5 * gap, -0.0075], 0.05, 2, RUBBER, element="P2")
    right = Solid.disk([0.05 + 0.5 * gap, 0.0075], 0.05, 2, RUBBER, element="P2")
    model = Model([left, right], [Contact(left, right)], gravity=(0.0, 0.0))
    v0 = model.translation(left, (speed, 0.0)) + model.translation(right, (-speed, 0.0))
    sim = Simulation(model, dt=h, t_end=0.0045, v0=v0, name="p2_fast")
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["status"] == "completed"
    edge = shortest_edge(right, right.contact_facets())
    assert summary["max_penetration"] <= 0.01 * edge
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 1e-6 * ledger["scale"]


def test_the_sweeps_depth_measure_reads_a_p2_boundary_on_its_curve():
    """``benchmarks/stress_2d.py`` measures a node's depth by ray parity on the other solid's
    boundary; a P2 boundary is its curved segments cut into fine chords, not its flat pieces.
    One segment of a P2 disk dented by 1 mm at its mid node (the fast P2 disks' deepest dent
    is 0.36 mm): points 0.05 mm behind the curve at ξ = ±½ read 0.05 mm, where the pieces read
    them behind by their sagitta too (¼ of the dent, 0.25 mm, at ξ = ±½); a point on the curve
    reads 0. Margin: a chord stands off the parabola by at most the dent over N², 1e-6 m at
    N = 32 chords (measured 2e-18 m: ξ = ±½ are ends of chords; the pieces read 0.2997 mm)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from stress_2d import CURVE_CHORDS, boundary_polygon, polygon_depths

    from fecontact.contact.mortar_p2_curves import quadratic_segments

    disk = Solid.disk([0.0, 0.0], 0.05, 1, RUBBER, element="P2")
    x = disk.positions(np.zeros(disk.ndof))
    a, b, m = quadratic_segments(disk)[0]
    chord = x[b] - x[a]
    inward = np.array([-chord[1], chord[0]]) / np.linalg.norm(chord)  # (counter-clockwise)
    dent = 1e-3
    x[m] = 0.5 * (x[a] + x[b]) + dent * inward  # (the reference mid node is on the chord)
    xi = np.array([-0.5, 0.5])
    curve = np.outer(xi * (xi - 1) / 2, x[a]) + np.outer(xi * (xi + 1) / 2, x[b])
    curve += np.outer(1 - xi * xi, x[m])
    tangent = np.outer(xi - 0.5, x[a]) + np.outer(xi + 0.5, x[b]) + np.outer(-2 * xi, x[m])
    normal_in = np.stack([-tangent[:, 1], tangent[:, 0]], 1)
    normal_in /= np.linalg.norm(normal_in, axis=1)[:, None]
    depth = 5e-5
    points = np.concatenate([curve + depth * normal_in, curve])
    bound = dent / CURVE_CHORDS**2
    d, _ = polygon_depths(points, *boundary_polygon(disk, x))
    assert np.allclose(d, [depth, depth, 0.0, 0.0], rtol=0.0, atol=bound)
    f = disk.contact_facets()
    pieces, _ = polygon_depths(points, x[f[:, 0]], x[f[:, 1]])
    # behind the pieces by the depth and the sagitta, ¼ of the dent at ξ = ±½, less the
    # pieces' tilt (cos of their angle to the curve, under 3 % at a 1 mm dent on 38 mm)
    assert np.all(pieces[:2] >= depth + 0.97 * 0.25 * dent)


def pressed_vertex_to_vertex(depth):
    """Two P2 disks (refinements 2, 5 cm) whose vertices on the x axis overlap by ``depth``
    (m): the model and the left disk's pointwise rows, at q = 0."""
    left = Solid.disk([-0.05 + 0.5 * depth, 0.0], 0.05, 2, RUBBER, element="P2")
    right = Solid.disk([0.05 - 0.5 * depth, 0.0], 0.05, 2, RUBBER, element="P2")
    model = Model([left, right], [Contact(left, right)], gravity=(0.0, 0.0))
    return model, model.contacts.pairs[0].pointwise


def test_a_node_pressed_onto_a_vertex_is_pushed_along_its_bisector():
    """The left disk's vertex on the axis, 2δ inside the right disk, is as deep behind both
    of the right disk's segments that meet at its vertex there: its row is their mean, and
    pushes it along the axis (sideways component of its gradient 0 to round-off), where one
    segment's normal pushed it 11.25° off the axis (0.2 of the axial component; the disks
    left their axis at 9 % of the impact speed). It reads the node's depth behind the two
    segments' ends (2δ cos 11.25°, the axial component of either normal) less τ/2 (to
    round-off: 1e-12 of δ). Its gradient and Hessian over the 12 coordinates (node, segment,
    the neighbour's two other nodes) are exact against central differences along a random
    direction of 1e-9 m, within the tie (τ = 4.9e-8 m): measured 2e-10 against a derivative of
    1.9, and 1.5e-9 of the largest entry (the differences' round-off, ~1e-18 m of the gaps
    and 1e-16 of the gradients over 2e-9 m)."""
    _, rows = pressed_vertex_to_vertex(0.0)
    model, rows = pressed_vertex_to_vertex(2.0 * rows.allowance)
    q = np.zeros(model.n)
    g, dofs, G, _ = rows.evaluate(q)
    node = int(np.argmax(rows.body.positions(np.zeros(rows.body.ndof))[rows.nodes, 0]))
    assert g[node] < 0.5 * rows.allowance and rows.end[node] >= 0  # deep, on the tie
    gx, gy = G[node, :2]
    assert abs(gy) <= 1e-12 * abs(gx)
    assert abs(gx) == pytest.approx(np.cos(np.pi / 16), rel=1e-12)  # (16 segments)
    depth = 2.0 * rows.allowance * abs(gx)
    expected = -depth + 0.5 * rows.tie + rows.allowance
    assert g[node] == pytest.approx(expected, rel=0.0, abs=1e-12 * rows.allowance)
    assert len(np.unique(dofs[node])) == rows.width  # (the vertex's five nodes and the node)
    H = rows.hessians(q, np.array([node]))[0]
    dq = np.random.default_rng(4).normal(0.0, 1.0, model.n)
    h, local = 1e-9, dq[dofs[node]]
    up, down = (rows.evaluate(q + s * h * dq) for s in (1.0, -1.0))
    assert rows.end[node] >= 0  # (still on the tie)
    assert abs((up[0][node] - down[0][node]) / (2 * h) - G[node] @ local) < 1e-7

    def spread(d, values):  # a row's columns gathered on the model's dofs
        return np.bincount(d, values, minlength=model.n)

    # (the closest piece, and so the columns' order, may differ between the two sides)
    dG = spread(up[1][node], up[2][node]) - spread(down[1][node], down[2][node])
    error = dG / (2 * h) - spread(dofs[node], H @ local)
    assert np.abs(error).max() < 1e-6 * max(1.0, np.abs(H).max())
