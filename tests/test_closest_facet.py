"""The facet each slave node takes among its candidate pairs: a few 2D pairs in plain floats
choose exactly as the arrays do."""

import numpy as np
import pytest

from fecontact.contact import closest_facet
from fecontact.contact.closest_facet import FEW, closest_among
from fecontact.contact.geometry import closest_facet_distance

RNG = np.random.default_rng(11)


def _star():
    """A star polygon's nodes and counter-clockwise segments (convex and reflex vertices)."""
    k = np.arange(14)
    radius = np.where(k % 2 == 0, 1.0, 0.35)
    x = np.c_[radius * np.cos(k * np.pi / 7), radius * np.sin(k * np.pi / 7)]
    return x, np.c_[k, np.roll(k, -1)]


@pytest.mark.parametrize("n_pairs", [1, 5, FEW])
def test_a_few_pairs_choose_in_floats_as_the_arrays_do(monkeypatch, n_pairs):
    # slave nodes near the star's boundary (a third on its vertices, where facets tie), each
    # with random candidate segments, some nodes with several: the floats' choice (facets,
    # gaps to the bit, node order) is the arrays'
    x, facets = _star()
    for trial in range(300):
        xs = np.vstack([RNG.uniform(-1.1, 1.1, (6, 2)), x[RNG.integers(0, 14, 3)]])
        xs[6:] += RNG.normal(0.0, 0.02, (3, 2)) * (trial % 2)  # (exact vertices every other)
        s = np.sort(RNG.integers(0, len(xs), n_pairs))
        f = RNG.integers(0, len(facets), n_pairs)
        margin, tie = (0.3, 1e-12) if trial % 3 else (np.inf, 0.05)
        few = closest_among(xs, x, facets, s, f, margin, tie)
        monkeypatch.setattr(closest_facet, "FEW", -1)  # the arrays' path
        arrays = closest_among(xs, x, facets, s, f, margin, tie)
        monkeypatch.undo()
        for a, b in zip(few, arrays, strict=True):
            assert a.dtype == b.dtype
            np.testing.assert_array_equal(a, b)


def test_a_node_on_a_convex_vertex_takes_the_larger_plane_gap():
    # a node outside the star's tip (vertex 0 at (1, 0)), off its axis, equally close to
    # both of its segments (the vertex is the closest point of each): it takes the one whose
    # plane it is farther from
    x, facets = _star()
    xs = np.array([[1.2, 0.02]])
    s, f = np.array([0, 0]), np.array([13, 0])  # the segments ending and starting at vertex 0
    dist, gaps = closest_facet_distance(xs[s], x[facets[f]])
    assert dist[0] == pytest.approx(dist[1], rel=1e-14) and abs(gaps[1]) > 2.0 * abs(gaps[0])
    node, facet, g = closest_among(xs, x, facets, s, f, 1.0, 1e-12)
    assert node.tolist() == [0] and facet.tolist() == [0] and g[0] == gaps[1]
