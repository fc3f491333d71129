"""The work a 3D node-to-surface evaluation leaves out changes nothing: the pairs that cannot
hold a node's closest facet (``FacetSearch.closest_candidates``), and the planes of deep-node
rows that cannot be deeper than δ/2 (``DeepNodeRows3D``)."""

import numpy as np

from fecontact import Model
from fecontact.bodies import Solid
from fecontact.contact import Contact
from fecontact.contact.body_pairs import NodeSurfaceContact
from fecontact.contact.closest_facet import closest_among
from fecontact.contact.mortar_safeguard import DeepNodeRows3D
from fecontact.scenes import solid_material

RNG = np.random.default_rng(5)
MAT = solid_material("linear", 1e7, 0.3, 1e3)


def test_the_pairs_left_out_leave_each_nodes_facet_and_gap_bit_for_bit():
    # a ball's nodes 0.5 mm from another's surface, then moved step by step (both balls,
    # with noise) through the search's life and past re-rankings; a few nodes placed on the
    # master's vertices, where facets tie: the choice among the pairs kept is the choice
    # among all the search's pairs, facets, gaps and order to the bit
    master = Solid.ball([0.0, 0.0, 0.0], 0.05, 1, MAT)
    slave = Solid.ball([0.1005, 0.0, 0.0], 0.05, 1, MAT)
    pair = NodeSurfaceContact(slave, master, margin=0.01)
    xs0 = slave.positions(np.zeros(slave.ndof))[pair.nodes]
    xm0 = master.positions(np.zeros(master.ndof))
    near = np.flatnonzero(xs0[:, 0] < 0.06)
    vertices = np.flatnonzero(xm0[:, 0] > 0.045)[: len(near) // 3]
    xs0[near[: len(vertices)]] = 1.001 * xm0[vertices]
    left_out = 0
    for k in range(60):
        # (the balls close at 2e-5 m a step, 3e-5 m of noise: re-ranked every few steps)
        xs = xs0 - [2e-5 * k, 0.0, 0.0] + RNG.normal(0.0, 3e-5, xs0.shape)
        xm = xm0 + RNG.normal(0.0, 3e-5, xm0.shape)
        s, f, g = pair.closest_facets(xs, xm)
        every, facets, _ = pair.search.found(xs, xm, pair.margin)
        kept = pair.search.closest_candidates(xs, xm, pair.margin, pair.tie_tolerance)[0]
        left_out += len(every) - len(kept)
        full = closest_among(xs, xm, pair.facets, every, facets, pair.margin, pair.tie_tolerance)
        for a, b in zip((s, f, g), full, strict=True):
            assert a.dtype == b.dtype and np.array_equal(a, b)
    assert left_out > 0.5 * 60 * len(every)  # (most pairs are left out: the test bites)


def test_the_planes_left_out_leave_every_row_bit_for_bit(monkeypatch):
    # two balls overlapping by 3 mm, 4 mm off-centre, every node moved by noise: the rows'
    # gaps, dofs and gradients are those made with the planes of every node
    a = Solid.ball([0.0, 0.0, 0.0], 0.05, 2, MAT)
    b = Solid.ball([0.097, 0.004, 0.0], 0.05, 2, MAT)
    pair = Contact(a, b, method="mortar")
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    for rows in (pair, pair.pointwise, pair.master_rows):
        rows.detect_within(0.02)
    planes = DeepNodeRows3D._planes
    counted = []

    def counting(self, x, *args, **kwargs):
        counted.append(len(x))
        return planes(self, x, *args, **kwargs)

    monkeypatch.setattr(DeepNodeRows3D, "_planes", counting)
    # (and with δ set negative, −5 mm, as tests/test_mortar_safeguard.py does in 2D: every
    # node near is deep)
    for rows, allowance in [(r, d) for r in (pair.pointwise, pair.master_rows)
                            for d in (r.allowance, -0.005)]:  # fmt: skip
        rows.allowance = allowance
        for _ in range(5):
            q = RNG.normal(0.0, 2e-4, model.n)
            rows.reset()
            skipped = rows.evaluate(q)
            with monkeypatch.context() as every_plane:
                every_plane.setattr(
                    DeepNodeRows3D, "_may_be_deep", lambda self, x, t: x[:, 0] == x[:, 0]
                )
                rows.reset()
                every = rows.evaluate(q)
            for x, y in zip(skipped[:3], every[:3], strict=True):
                assert np.array_equal(x, y)
            # (some rows deep, and planes left out: the test bites)
            assert np.count_nonzero(every[0] < 0.5 * rows.allowance) > 0
            assert 0 < counted[-2] and (counted[-2] < counted[-1] or allowance < 0.0)
