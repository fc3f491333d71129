"""Two-sided beams: a beam's surface is its centreline offset by ± the clearance, and the side
a point is on follows its motion over each step (fecontact/contact/beam_sides.py)."""

import numpy as np
import pytest

from fecontact import Beam2D, Contact, Material, Model, Section, simulate
from fecontact.bodies import Solid
from fecontact.bodies.materials import LinearElastic
from fecontact.bodies.rigid import Disk, RigidBody2D
from fecontact.contact.beam_sides import PointBeamContact, swept_sides
from fecontact.testing import gap_derivatives_error

STEEL = Material(210e9, rho=7850.0)


def cantilever(n=10):
    section = Section.rectangle(0.05, 0.01)
    return Beam2D.straight([0.0, 0.0], [1.0, 0.0], n, STEEL, section).clamp(0)


def test_the_side_is_the_one_the_path_came_from_only_when_it_crossed_the_element():
    # element from t = 0 to 1 along the line; (t, f) of a point at the start and now
    start = (np.array([0.5, 1.5, 0.5, 0.5]), np.array([0.1, 0.1, 0.1, -0.1]))
    t = np.array([0.5, 0.7, 1.8, 0.5])
    f = np.array([-0.1, -0.1, -0.1, -0.05])
    # through the element: kept; around its end (t* = 1.1 and 1.15): where it is now;
    # from below, still below
    np.testing.assert_array_equal(swept_sides(start, t, f), [1.0, -1.0, -1.0, -1.0])
    np.testing.assert_array_equal(swept_sides(None, t, f), [-1.0, -1.0, -1.0, -1.0])


@pytest.mark.parametrize("seed", range(4))
def test_point_beam_gap_derivatives(seed):
    # central differences of g and G; the closest point inside an element or at an end
    rng = np.random.default_rng(seed)
    beam = cantilever(4)
    disk = Solid.disk([0.4 + 0.5 * seed, 0.3], 0.1, 0, LinearElastic(1e7, 0.3, 1e3))
    pair = PointBeamContact(disk, beam, clearance=0.01)
    model = Model([disk, beam], [pair], gravity=(0.0, 0.0))
    q = 1e-3 * rng.normal(size=model.n)
    assert np.isfinite(pair.evaluate(q)[0]).any()  # (a node's second row is +inf outside valleys)
    err_g, err_h = gap_derivatives_error(pair, q, 1e-6)
    # O(eps²) truncation on lengths of order 0.1-1: 1e-6 relative leaves margin
    assert err_g < 1e-6 and err_h < 1e-4


@pytest.mark.parametrize("seed", range(3))
def test_beam_node_rows_on_a_solid_gap_derivatives(seed):
    # the strip's nodes against a block's boundary, the companion of Contact(block, strip):
    # central differences of g and G, nodes over the block's face and beyond its corner
    rng = np.random.default_rng(seed)
    block = Solid.rectangle([0.0, -0.1], [0.3, 0.0], (3, 1), LinearElastic(1e8, 0.3, 1e3))
    strip = Beam2D.straight(
        [-0.015, 0.006], [0.315, 0.006], 8, STEEL, Section.rectangle(0.02, 0.01)
    )
    pair = Contact(block, strip, clearance=0.005)
    model = Model([block, strip], [pair], gravity=(0.0, 0.0))
    rows = pair.companions[0]
    rows.detect_within(0.02)
    q = 1e-3 * rng.normal(size=model.n)
    g = rows.evaluate(q)[0]
    assert np.isfinite(g).sum() == strip.n_nodes  # (every node within the margin)
    err_g, err_h = gap_derivatives_error(rows, q, 1e-6)
    # O(eps²) truncation on lengths of order 0.1: 1e-6 relative leaves margin
    assert err_g < 1e-6 and err_h < 1e-4


def flight(partner, velocity, beam=True, t_end=0.1, dt=1e-3):
    """Displacements of a body thrown past the cantilever's free end, every step, with the
    total impulse of the contact (with ``beam``) or of none."""
    cant = cantilever()
    pairs = [Contact(partner, cant, clearance=0.005)] if beam else []
    model = Model([cant, partner], pairs, gravity=(0.0, 0.0))
    v0 = model.translation(partner, velocity)
    s = model.body_slice(1)
    path, impulse = [], 0.0
    for st in simulate(model, dt, t_end, v0=v0):
        path.append((st.t, st.q[s].copy()))
        impulse += float(np.sum(st.impulse))
    return path, impulse


START, VELOCITY = np.array([1.6, 0.2]), np.array([-10.0, -5.0])
# from above-right of the free end (1, 0), down and left: the path passes 8.9 cm from the end
# node, then 0.1-0.3 m under the beam; it never touches (radius 5 cm, clearance 5 mm)


def test_a_rigid_disk_passing_around_the_free_end_and_under_the_beam_flies_straight():
    path, impulse = flight(RigidBody2D.uniform(1.0, START, Disk(0.05)), VELOCITY)
    assert impulse == 0.0
    for t, q in path:
        np.testing.assert_allclose(q[:2] - VELOCITY * t, 0.0, atol=1e-12)
    assert path[-1][1][1] < -0.4  # under the beam at the end


def test_an_elastic_disk_passing_around_the_free_end_flies_as_if_no_beam_were_there():
    # its own flight deviates from the line by the elastic steps' Newton tolerance (3e-10 m
    # here); with the beam it is the same flight, to the last bit
    def disk():
        return Solid.disk(START, 0.05, 1, LinearElastic(1e9, 0.3, 1e3))

    path, impulse = flight(disk(), VELOCITY)
    free, _ = flight(disk(), VELOCITY, beam=False)
    assert impulse == 0.0
    for (_, q), (_, q_free) in zip(path, free, strict=True):
        np.testing.assert_array_equal(q, q_free)


@pytest.mark.parametrize("speed", [30.0, 300.0])
@pytest.mark.parametrize("x", [0.5, 0.525], ids=["over a node", "mid-element"])
def test_a_disk_thrown_at_a_thin_strip_does_not_tunnel(x, speed):
    # a 2 mm steel strip pinned at both ends; a 0.1 kg disk hits it at up to 300 m/s: in one
    # step of 0.1 ms it would travel up to 3 cm, 15 strip thicknesses
    section = Section.rectangle(0.05, 0.002)
    strip = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 20, STEEL, section).pin(0).pin(-1)
    disk = RigidBody2D.uniform(0.1, [x, 0.03], Disk(0.02))
    pair = Contact(disk, strip, clearance=0.001)
    model = Model([strip, disk], [pair], gravity=(0.0, 0.0))
    v0 = model.translation(disk, (0.0, -speed))
    s = model.body_slice(1)
    touched = False
    for st in simulate(model, 1e-4, 0.004, v0=v0):
        x = strip.positions(st.q[model.body_slice(0)])
        c = disk.center(st.q[s])
        # the strip's centreline height under the disk centre (independent of the gaps)
        y = np.interp(c[0], x[:, 0], x[:, 1])
        assert c[1] - y >= 0.021 - 1e-9
        touched |= bool(np.any(st.impulse > 0.0))
    assert touched


def test_two_strips_crossing_at_an_angle_touch_at_their_faces():
    # a free strip, tilted by 14°, thrown down onto a pinned one; each strip's nodes against
    # the other's two-sided surface, clearance = the sum of the half thicknesses (1 cm)
    section = Section.rectangle(0.05, 0.01)
    lower = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 10, STEEL, section).pin(0).pin(-1)
    upper = Beam2D.straight([0.3, 0.03], [0.7, 0.13], 8, STEEL, section)
    pairs = [Contact(upper, lower, clearance=0.01), Contact(lower, upper, clearance=0.01)]
    model = Model([lower, upper], pairs, gravity=(0.0, 0.0))
    v0 = model.translation(upper, (0.0, -2.0))
    touched = False
    for st in simulate(model, 5e-5, 0.02, v0=v0):
        xl = lower.positions(st.q[model.body_slice(0)])
        xu = upper.positions(st.q[model.body_slice(1)])
        # every node of the upper strip stays 1 cm above the lower one's centreline
        # (independent of the gaps: its height over the lower polyline, which stays nearly
        # flat, |slope| < 0.1, so the vertical distance is the normal one to 0.5 %)
        y = np.interp(xu[:, 0], xl[:, 0], xl[:, 1])
        assert np.min(xu[:, 1] - y) >= 0.01 * 0.995 - 1e-9
        touched |= bool(np.any(st.impulse > 0.0))
    assert touched


def test_an_elastic_disk_thrown_onto_a_beam_stays_on_its_face():
    # a Solid disk (its boundary nodes) at 3 m/s onto a pinned strip, clearance its half
    # thickness (5 mm), steps at the disk's wave step: it is stopped, and no boundary node
    # comes nearer the centreline than the clearance (measured on the polyline, which stays
    # nearly flat: its height under a node is its normal distance to 0.5 %)
    beam = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 20, STEEL, Section.rectangle(0.05, 0.01))
    beam.pin(0).pin(-1)
    disk = Solid.disk([0.52, 0.06], 0.05, 2, LinearElastic(1e8, 0.3, 1e3))
    model = Model([beam, disk], [Contact(disk, beam, clearance=0.005)], gravity=(0.0, 0.0))
    v0 = model.translation(disk, (0.0, -3.0))
    impulse, nodes = 0.0, disk.boundary_nodes()
    for st in simulate(model, 3.4e-5, 0.01, v0=v0):
        x = disk.positions(st.q[model.body_slice(1)])[nodes]
        xb = beam.positions(st.q[model.body_slice(0)])
        assert np.min(x[:, 1] - np.interp(x[:, 0], xb[:, 0], xb[:, 1])) >= 0.005 * 0.995
        impulse += float(np.sum(st.impulse))
    assert impulse > 0.0
    vy = disk.nodal(st.v[model.body_slice(1)]).mean(axis=0)[1]
    assert vy > -1.0  # stopped from 3 m/s: it moves with the deflecting beam


def test_a_strip_struck_end_first_through_a_pair_declared_one_way_is_reported(tmp_path):
    # a striker falls end-first at 1 m/s onto a pinned strip, 1 mm above its face. Declared
    # as Contact(strip, striker), the rows hold the strip's nodes (5 cm either side of the
    # striker) and not the striker's end node, which goes on through: after 4 ms its centre
    # is 7 mm from the strip's centreline, 3 mm inside the 1 cm clearance (free flight:
    # nothing touches it). The run reports that depth and warns; with the reversed pair
    # declared too, the end node is held and nothing is reported.
    from fecontact import Simulation, run

    section = Section.rectangle(0.02, 0.01)

    def strike(pairs_of):
        strip = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 10, STEEL, section).pin(0).pin(-1)
        striker = Beam2D.straight([0.45, 0.2], [0.45, 0.011], 4, STEEL, section)
        pairs = [Contact(a, b, clearance=0.01) for a, b in pairs_of(strip, striker)]
        model = Model([strip, striker], pairs, gravity=(0.0, 0.0))
        v0 = model.translation(striker, (0.0, -1.0))
        out = tmp_path / str(len(pairs))
        sim = Simulation(model, 2e-5, 0.004, v0=v0, name="strike")
        return run(sim, out, progress=False, frames=False)

    with pytest.warns(UserWarning, match="a strip's node that only the reversed strip pair"):
        one_way = strike(lambda strip, striker: [(strip, striker)])
    # the end node's path is free flight: its depth is exact to the steps' round-off
    assert one_way["max_penetration"] == pytest.approx(0.003, abs=1e-12)
    both = strike(lambda strip, striker: [(strip, striker), (striker, strip)])
    # held by its own rows to the position correction's round-off
    assert both["max_penetration"] < 1e-12
    assert not any(w.startswith("penetration") for w in both["warnings"])


def test_a_strip_falling_end_first_onto_a_coarse_block_is_held(tmp_path):
    # Contact(block, strip) holds the block's boundary nodes, 20 cm apart on its top face,
    # out of the strip, and the strip's nodes out of the block (beam_on_solid): the strip's
    # end, falling at 1 m/s onto the face between two block nodes 0.1 mm above its
    # clearance, stops on the face (it went 3.9 mm into the clearance before the strip's
    # nodes had rows of their own)
    from fecontact import Simulation, run

    block = Solid.rectangle([0.0, -0.1], [0.4, 0.0], (2, 1), LinearElastic(1e8, 0.3, 1e3))
    block.fix(block.nodes_where(lambda x: x[1] < -0.1 + 1e-9))
    strip = Beam2D.straight([0.1, 0.2], [0.1, 0.0051], 4, STEEL, Section.rectangle(0.02, 0.01))
    model = Model([block, strip], [Contact(block, strip, clearance=0.005)], gravity=(0, 0))
    v0 = model.translation(strip, (0.0, -1.0))
    top = block.nodes_where(lambda x: x[1] > -1e-9)
    top = top[np.argsort(block.X[top, 0])]  # (at x = 0, 0.2, 0.4)
    heights = []
    for st in simulate(model, 2e-5, 0.004, v0=v0):
        face = block.positions(st.q[model.body_slice(0)])[top]
        end = strip.positions(st.q[model.body_slice(1)])[-1]
        heights.append(end[1] - np.interp(end[0], face[:, 0], face[:, 1]))
    # the end's centre never nearer the (moving) face than the clearance, to the
    # correction's round-off (1e-12 m on lengths of 0.1 m), and it reaches the face
    assert min(heights) > 0.005 - 1e-12
    assert min(heights) < 0.005 + 1e-9
    sim = Simulation(model, 2e-5, 0.004, v0=v0, name="end_first")
    summary = run(sim, tmp_path, progress=False, frames=False)
    assert summary["max_penetration"] < 1e-12
    assert not summary["warnings"]


def test_a_solid_and_a_beam_take_the_energy_retakes():
    # decided once per run: a strip's node closing on a solid's face, corrected at the
    # step's end, strains it as a closing on a floor does (docs/validation/stress_2d.md)
    from fecontact.time import IntegratorOptions, make_stepper

    block = Solid.rectangle([0.0, -0.1], [0.4, 0.0], (2, 1), LinearElastic(1e8, 0.3, 1e3))
    strip = Beam2D.straight([0.1, 0.2], [0.1, 0.0051], 4, STEEL, Section.rectangle(0.02, 0.01))
    model = Model([block, strip], [Contact(block, strip, clearance=0.005)], gravity=(0, 0))
    assert make_stepper(model, IntegratorOptions()).guard is not None
    assert make_stepper(model, IntegratorOptions(energy_retakes=False)).guard is None
