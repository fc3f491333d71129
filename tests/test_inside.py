"""The inside/outside test: signed distances of points to a solid's discretized boundary."""

import numpy as np
import pytest

from fecontact.bodies import Solid
from fecontact.bodies.materials import LinearElastic
from fecontact.contact import Contact
from fecontact.contact.inside import (
    Surface,
    face_depths,
    segment_depths,
    segment_neighbours,
    winding_numbers,
)
from fecontact.model import Model

MAT = LinearElastic(1e7, 0.3, 1000.0)
RNG = np.random.default_rng(7)


def test_the_box_distance_is_exact_inside_and_outside():
    # an axis-aligned box: the distance to its surface is known in closed form everywhere
    lo, hi = np.zeros(3), np.array([1.0, 2.0, 3.0])
    body = Solid.box(lo, hi, (3, 4, 5), MAT)
    x = body.positions(np.zeros(body.ndof))
    p = RNG.uniform(-0.5, [1.5, 2.5, 3.5], (4000, 3))  # within the pad of 1 m around the box
    s, _ = Surface(body.contact_facets()).signed_distance(x, p, pad=1.0)
    inside = np.all((p > lo) & (p < hi), axis=1)
    outside_gap = np.linalg.norm(np.maximum(0.0, np.maximum(lo - p, p - hi)), axis=1)
    inside_depth = np.min(np.minimum(p - lo, hi - p), axis=1)
    exact = np.where(inside, -inside_depth, outside_gap)
    np.testing.assert_allclose(s, exact, atol=1e-13)


@pytest.mark.parametrize("dim", [2, 3])
def test_points_far_inside_a_round_body_get_their_depth(dim):
    # deep points of a polygonal disk or ball: the sign everywhere, and the depth against the
    # distance to the inscribed and circumscribed spheres (the facets lie between them)
    c = np.array([0.1, 0.2, -0.3][:dim])
    body = (Solid.disk if dim == 2 else Solid.ball)(c, 0.05, 3 if dim == 2 else 2, MAT)
    x = body.positions(np.zeros(body.ndof))
    surface = Surface(body.contact_facets())
    p = c + RNG.uniform(-0.07, 0.07, (3000, dim))
    s, f = surface.signed_distance(x, p, pad=0.03)
    r = np.linalg.norm(p - c, axis=1)
    xf = x[surface.facets]
    # the inscribed radius: the smallest distance from the centre to a facet
    r_in = -surface.signed_distance(x, c[None])[0][0]
    assert 0.04 < r_in < 0.05
    assert np.all(s[r < r_in] < 0.0) and np.all(s[r > 0.05] > 0.0)
    deep = r < r_in
    assert np.all(-s[deep] >= r_in - r[deep] - 1e-12)
    assert np.all(-s[deep] <= 0.05 - r[deep] + 1e-12)
    # the closest facet is closest: no facet is nearer than |s| (all facets, brute force)
    for i in RNG.choice(len(p), 40, replace=False):
        d = surface._facet_distances(np.repeat(p[i][None], len(xf), 0), xf)
        assert abs(s[i]) == pytest.approx(d.min(), abs=1e-15)
        assert f[i] in np.flatnonzero(d <= d.min() + 1e-15)


def test_the_winding_number_counts_loops_and_holes():
    # a counter-clockwise square with a clockwise square hole
    outer = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    hole = np.array([[1, 1], [1, 3], [3, 3], [3, 1]], float)
    a = np.vstack([outer, hole])
    b = np.vstack([np.roll(outer, -1, 0), np.roll(hole, -1, 0)])
    w = winding_numbers(np.array([[0.5, 0.5], [2.0, 2.0], [5.0, 2.0]]), a, b)
    np.testing.assert_allclose(w, [1.0, 0.0, 0.0], atol=1e-12)


def test_points_beyond_the_box_are_outside_without_a_search():
    body = Solid.disk([0.0, 0.0], 1.0, 1, MAT)
    x = body.positions(np.zeros(body.ndof))
    s, f = Surface(body.contact_facets()).signed_distance(x, np.array([[5.0, 0.0]]), pad=0.1)
    assert s[0] == np.inf and f[0] == -1


@pytest.mark.parametrize("dim", [2, 3])
def test_inside_points_alone_get_the_same_distances(dim):
    body = (Solid.disk if dim == 2 else Solid.ball)(np.zeros(dim), 1.0, 2, MAT)
    x = body.positions(np.zeros(body.ndof))
    surface = Surface(body.contact_facets())
    p = RNG.uniform(-1.2, 1.2, (500, dim))
    s, f = surface.signed_distance(x, p)
    s_in, f_in = surface.signed_distance(x, p, outside=False)
    inside = s < 0.0
    np.testing.assert_array_equal(s_in[inside], s[inside])
    np.testing.assert_array_equal(f_in[inside], f[inside])
    if dim == 2:  # (3D finds the sign from the closest facet: it keeps both)
        assert np.all(np.isinf(s_in[~inside]))
    np.testing.assert_array_equal(surface.depths(x, p), np.maximum(0.0, -s))


@pytest.mark.parametrize("dim", [2, 3])
def test_a_point_whose_closest_point_is_on_a_face_gets_the_full_tests_depth(dim):
    # points around and inside a round body: where the closest facet (the full test's) has
    # the closest point inside its face, the depth behind its plane is the full test's; near
    # the surface, where the pair asks, this settles most of the points
    body = (Solid.disk if dim == 2 else Solid.ball)(np.zeros(dim), 1.0, 2, MAT)
    x = body.positions(np.zeros(body.ndof))
    surface = Surface(body.contact_facets())
    p = RNG.uniform(-1.2, 1.2, (2000, dim))
    s, f = surface.signed_distance(x, p, pad=1.0)
    face, depth = face_depths(p, x[surface.facets[f]])
    np.testing.assert_allclose(depth[face], np.maximum(0.0, -s[face]), rtol=1e-12, atol=1e-15)
    near = np.abs(s) < 0.02
    assert face[near].sum() >= 0.5 * near.sum()


def test_a_vertex_certifies_outside_only_points_the_full_test_finds_outside():
    # a star polygon (reflex and sharp convex vertices) with a square hole, points all around:
    # where segment_depths settles a point beyond a vertex its depth is the full test's 0, on
    # a face the full test's depth; and it settles most points whose closest point is a vertex
    k = np.arange(14)
    radius = np.where(k % 2 == 0, 1.0, 0.35)
    star = np.c_[radius * np.cos(k * np.pi / 7), radius * np.sin(k * np.pi / 7)]
    hole = 0.1 * np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]], float)  # clockwise
    x = np.vstack([star, hole])
    facets = np.r_[np.c_[k, np.roll(k, -1)], 14 + np.c_[np.arange(4), np.roll(np.arange(4), -1)]]
    surface = Surface(facets)
    p = RNG.uniform(-1.3, 1.3, (20000, 2))
    s, f = surface.signed_distance(x, p, pad=1.0)
    known, depth = segment_depths(p, x, facets, segment_neighbours(facets), f, 1e-12)
    full = np.maximum(0.0, -s)
    face = face_depths(p, x[facets[f]])[0]
    np.testing.assert_array_equal(depth[face], face_depths(p, x[facets[f]])[1][face])
    vertex = known & ~face
    assert np.all(full[vertex] == 0.0) and np.all(depth[vertex] == 0.0)
    assert vertex.sum() >= 0.95 * np.count_nonzero(~face & (s > 0.0))
    assert not known[~face & (s < 0.0)].any()
    # not a closed polygon (a node starts two segments): no neighbours
    assert segment_neighbours(np.array([[0, 1], [1, 2], [1, 0]])) is None


def test_a_few_points_are_settled_in_floats_exactly_as_by_numpy():
    # the plain-float path of a few points against segment_depths on the star polygon with a
    # hole of the test above: the same deepest depth and the same unsettled points, to the
    # bit, for batches of 1 to 8 points all around (faces, convex and reflex vertices)
    k = np.arange(14)
    radius = np.where(k % 2 == 0, 1.0, 0.35)
    star = np.c_[radius * np.cos(k * np.pi / 7), radius * np.sin(k * np.pi / 7)]
    hole = 0.1 * np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]], float)
    x = np.vstack([star, hole])
    facets = np.r_[np.c_[k, np.roll(k, -1)], 14 + np.c_[np.arange(4), np.roll(np.arange(4), -1)]]
    surface = Surface(facets)
    # points near the boundary, where the pairs ask (half of them within 1 % of a vertex)
    p = np.vstack([RNG.uniform(-1.3, 1.3, (3000, 2)), x[RNG.integers(0, 18, 3000)]])
    p[3000:] += RNG.normal(0.0, 0.01, (3000, 2))
    s, f = surface.signed_distance(x, p, pad=1.0)
    neighbours = segment_neighbours(facets)
    vertex = 0  # points settled beyond a vertex (the vertex certificate exercised)
    for start in range(0, len(p), 8):
        for n in (1, 3, 8):
            i = slice(start, start + n)
            known, depth = segment_depths(p[i], x, facets, neighbours, f[i], 1e-12)
            deepest, rest = surface.settled_depth(p[i], x, f[i], 1e-12)
            assert deepest == float(np.max(depth[known], initial=0.0))
            np.testing.assert_array_equal(rest, np.flatnonzero(~known))
            vertex += np.count_nonzero(known & ~face_depths(p[i], x[facets[f[i]]])[0])
    assert vertex > 1000
    # a NaN position is not settled: the full test gets it
    assert 0 in surface.settled_depth(np.r_[[[np.nan, 0.0]], p[1:2]], x, f[:2], 1e-12)[1]


def _round_pair(dim: int, distance: float):
    """The node-to-surface pair of two round bodies of radius 1 whose centres are
    ``distance`` apart, and its model."""
    make = Solid.disk if dim == 2 else Solid.ball
    a = make(np.zeros(dim), 1.0, 3 if dim == 2 else 2, MAT)
    b = make(np.r_[distance, np.zeros(dim - 1)], 1.0, 3 if dim == 2 else 2, MAT)
    model = Model([a, b], [Contact(a, b, method="node-to-surface")])
    pair = model.contacts.pairs[0]
    pair.detect_within(0.2)
    return pair, model


@pytest.mark.parametrize("dim", [2, 3])
def test_the_pairs_penetration_is_the_full_inside_test(dim):
    # two round bodies pushed into each other, their nodes jittered: the node-to-surface
    # pair's depth (the closest facet's face first, the full test for the rest) equals the
    # full test over every slave node
    pair, model = _round_pair(dim, 1.9)
    for seed in range(5):
        q = np.random.default_rng(seed).normal(0.0, 0.01, model.n)
        xs, xm = pair.positions(q)
        full = float(np.max(pair.surface.depths(xm, xs), initial=0.0))
        pair.evaluate(q)
        assert full > 0.05
        # (the depth behind a face's plane and the distance to its closest point differ in
        # their last bits)
        assert pair.penetration(q) == pytest.approx(full, rel=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_pairs_penetration_after_its_evaluation_is_the_full_inside_test(dim):
    # two round bodies just touching, their nodes jittered, a few nodes on either side of
    # the other's boundary: the depth reusing the evaluation at q (its search, its full
    # test of the nodes without a facet near, a few points settled in floats) is the full
    # test's, and the same as measured before any evaluation
    pair, model = _round_pair(dim, 2.0)
    inside = 0
    for seed in range(20):
        q = np.random.default_rng(seed).normal(0.0, 0.01, model.n)
        xs, xm = pair.positions(q)
        depths = pair.surface.depths(xm, xs)
        inside += np.count_nonzero(depths)
        pair.reset()
        before = pair.penetration(q)  # (its own search, then an evaluation at q)
        pair.evaluate(q)
        after = pair.penetration(q)
        assert after == before
        assert after == pytest.approx(float(np.max(depths, initial=0.0)), rel=1e-12)
    assert inside >= 5  # (nodes found inside over the 20 states: the depths are not all 0)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_mortar_watch_measures_every_node_both_ways(dim):
    # two round bodies of a mortar interface pushed into each other, jittered: the watch's
    # depth is the full inside/outside test of every boundary node of each body against the
    # other (the weighted gaps alone do not see a node)
    make = Solid.disk if dim == 2 else Solid.ball
    a = make(np.zeros(dim), 1.0, 3 if dim == 2 else 2, MAT)
    b = make(np.r_[1.7, np.zeros(dim - 1)], 0.8, 3 if dim == 2 else 2, MAT)
    model = Model([a, b], [Contact(a, b, method="mortar")])
    (watch,) = model.contacts.watches
    watch.pair.detect_within(0.2)
    for seed in range(5):
        q = np.random.default_rng(seed).normal(0.0, 0.01, model.n)
        x = [body.positions(q[model.body_slice(i)]) for i, body in enumerate((a, b))]
        full = max(
            float(np.max(Surface(other.contact_facets()).depths(x[1 - i], x[i]), initial=0.0))
            for i, other in enumerate((b, a))
        )
        assert full > 0.05
        depth, relative = watch.depth(q)
        assert depth == full
        # over the shortest boundary edge of the body entered: at most the depth over the
        # shortest edge of both bodies, at least over the longer one's
        shortest = min(watch.edges)
        assert full / max(watch.edges) <= relative <= full / shortest
