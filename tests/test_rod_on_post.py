"""A rod swung onto a post (cases/rod_on_post.py): the post strikes the rod between its nodes,
and the rod's tube stays out of the post, measured on the segments themselves."""

import numpy as np
from conftest import load_case

from fecontact import simulate
from fecontact.contact.geometry import closest_on_segments


def test_the_post_strikes_the_rod_between_its_nodes_and_stays_out_of_it():
    """Through the impact (0.097 s) and the rebound: the rod's centreline, sampled at 201
    points per element, never comes nearer the post's axis than the post's radius plus the
    rod's (bound 1e-9 m, the solver's tolerance); the contact's closest point lies inside an
    element, not at a node; the rod turns back (its tip's speed about the vertical reverses)."""
    sim = load_case("rod_on_post").build().replace(t_end=0.12)
    model = sim.model
    rod, post = model.bodies
    pair = model.contacts.pairs[0]
    p = sim.parameters
    axis = np.array([[0.0, 0.0, -0.5], [0.0, 0.0, 0.5]]) * (p["post_top"] - p["post_bottom"])
    s = np.linspace(0.0, 1.0, 201)[:, None]
    depth, inner, speeds = [], [], []
    for st in simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0):
        x = rod.positions(st.q[: rod.ndof])
        seg = rod.segments()
        pts = (x[seg[:, 0], None] * (1 - s) + x[seg[:, 1], None] * s).reshape(-1, 3)
        c = post.center(st.q[rod.ndof :])
        a, b = np.broadcast_to(c + axis[0], pts.shape), np.broadcast_to(c + axis[1], pts.shape)
        dist = closest_on_segments(pts, a, b)[1]
        depth.append(p["post_radius"] + p["radius"] - dist.min())
        if st.pressed().any():  # the closest segment's rows: ((1 − ξ) n, ξ n) on its ends
            g, _, G, _ = pair.evaluate(st.q)
            row = G[int(np.argmin(g))]
            a_share, b_share = np.linalg.norm(row[:3]), np.linalg.norm(row[3:6])
            inner.append(b_share / (a_share + b_share))
        speeds.append(sim.probes["tip_vt"].fn(model, st))
    assert max(depth) <= 1e-9
    assert inner and all(0.05 < xi < 0.95 for xi in inner)
    assert speeds[0] > 4.9 and min(speeds) < -2.0
