"""Friction of a mortar interface at a block's edge: the slip rows of a node where the
boundary turns by 60° or more lie in the plane of the facets its row integrates over, so that
the friction of a sliding block stays in Coulomb's cone (docs/explanation/mortar.md,
*Friction at edges and corners*)."""

import numpy as np

from fecontact import Model, simulate
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.contact import Contact, mortar3d
from fecontact.derivative_checks import gap_derivatives_error
from fecontact.scenes import wave_step
from fecontact.time.state import IntegratorOptions

RUBBER = NeoHookean(1e7, 0.3, 1000.0)
G = 9.81


def test_a_block_dragged_on_a_slab_keeps_its_friction_in_coulombs_cone():
    # a 4 x 2 cm block laid on a clamped slab, thrown along it at 1 m/s with mu = 1: every
    # pressed node slips, so the plane takes exactly mu times along it what it gives normal
    # to it. A tangent from the mean normal of a block corner (45°) pressed the block on
    # with its friction: 1.47 times mu from the first step, 2.4 times over 5 ms
    mu = 1.0
    slab = Solid.rectangle([-0.1, -0.02], [0.1, 0.0], (20, 2), RUBBER)
    slab.fix(slab.nodes_where(lambda x: x[1] <= -0.02 + 1e-9))
    block = Solid.rectangle([-0.08, 0.0], [-0.04, 0.02], (4, 2), RUBBER)
    model = Model([block, slab], [Contact(block, slab, friction=mu)], gravity=(0.0, -G))
    pair = model.contacts.pairs[0]  # (then the safeguard rows of deep nodes)
    assert pair.body is block
    x = block.X[pair.nodes]
    corners = np.isclose(x[:, 0] % 0.04, 0.0) & np.isclose(x[:, 1] % 0.02, 0.0)
    assert np.array_equal(pair.sharp, corners)  # the block's four corners, no other node
    dt = wave_step(block, 1.0)
    v0 = model.translation(block, (1.0, 0.0))
    s = model.body_slice(0)
    w = [block.mass_matrix() @ block.translation_field(a) for a in ((1.0, 0.0), (0.0, 1.0))]
    states = list(simulate(model, dt, 12 * dt, IntegratorOptions(), v0=v0))
    start, end = states[0], states[-1]
    tangential = float(w[0] @ (end.v[s] - start.v[s]))
    normal = float(w[1] @ (end.v[s] - start.v[s])) + block.mass * G * (end.t - start.t)
    assert tangential < 0.0 < normal
    # within the cone to the rows' Newton tolerance (1e-8 relative; the impulses are sums
    # of positive multiples of each row's forces), and on it: the block slips (0.99996)
    assert 0.999 <= abs(tangential) / (mu * normal) <= 1.0 + 1e-6


def test_a_box_laid_on_a_slab_rests_on_it_in_3d():
    # a 2 x 2 x 1 cm box laid on a clamped slab: its side faces stand at 90° to the slab's
    # top, where a cut on facing pairs took them in and out with the round-off of the
    # normals; the position correction's active set cycled and the run stopped at step 2.
    # Their weight now rises from 0 at 90° (mortar3d.TURNED)
    slab = Solid.box([-0.04, -0.03, -0.01], [0.04, 0.03, 0.0], (8, 6, 1), RUBBER)
    slab.fix(slab.nodes_where(lambda x: x[2] <= -0.01 + 1e-9))
    block = Solid.box([-0.01, -0.01, 0.0], [0.01, 0.01, 0.01], (2, 2, 1), RUBBER)
    model = Model([block, slab], [Contact(block, slab)], gravity=(0.0, 0.0, -G))
    dt = wave_step(block, 1.0)
    states = list(simulate(model, dt, 4 * dt, IntegratorOptions()))
    assert len(states) == 5 and states[-1].t > 3.5 * dt
    z = block.mass_matrix() @ block.translation_field((0.0, 0.0, 1.0))
    # held up: its centre sinks by a third of a free fall's g t²/2 = 5.8e-7 m over the 4
    # steps (1.9e-7 m: the two bodies' compression under the suddenly applied weight)
    assert -float(z @ states[-1].q[model.body_slice(0)]) / block.mass < 0.5 * G * (4 * dt) ** 2


def test_the_facing_weight_of_a_box_on_a_slab_has_exact_gradients():
    # a box pressed 0.5 mm into a slab with random displacements of 0.3 mm: 195 triangle
    # pairs between 90° and 104.5° (mortar3d.TURNED), whose weights scale their entries.
    # Central differences of 1e-7 m against the two rows' gradients: 1.9e-9 and 7.8e-10
    # relative measured (falling as the step squared: a truncation error); the weight's own
    # gradient left out reads 8.1e-3 and 9.2e-2. Bound 1e-6: 500 times the measurement and
    # 8000 times below the error it guards against
    slab = Solid.box([-0.03, -0.03, -0.01], [0.03, 0.03, 0.0], (3, 3, 1), RUBBER)
    block = Solid.box([-0.01, -0.01, -0.0005], [0.01, 0.01, 0.0095], (2, 2, 1), RUBBER)
    model = Model([block, slab], [Contact(block, slab)], gravity=(0.0, 0.0, 0.0))
    pair = model.contacts.pairs[0]
    pair.detect_within(0.005)
    q = np.random.default_rng(3).normal(0.0, 3e-4, model.n)
    xs, xm = pair.positions(q)
    ts, tm = xs[pair.facets], xm[pair.master_facets]
    n = np.cross(ts[:, 1] - ts[:, 0], ts[:, 2] - ts[:, 0])
    m = np.cross(tm[:, 1] - tm[:, 0], tm[:, 2] - tm[:, 0])
    c = -(n / np.linalg.norm(n, axis=1)[:, None]) @ (m / np.linalg.norm(m, axis=1)[:, None]).T
    assert np.any((c > 0.0) & (c < mortar3d.TURNED))  # (pairs in the band, some of them near)
    assert np.isfinite(pair.evaluate(q)[0]).sum() >= 4
    # the rows of two nodes of the box's bottom edges (a corner's and an edge's middle one),
    # whose side triangles stand in the band
    x0 = block.X[pair.nodes]
    rows = np.flatnonzero(np.isclose(x0[:, 2], -0.0005) & np.isclose(x0[:, 0], -0.01)
                          & np.isin(x0[:, 1], [-0.01, 0.0]))  # fmt: skip
    assert len(rows) == 2
    gradient_error, _ = gap_derivatives_error(pair, q, 1e-7, rows)
    assert gradient_error <= 1e-6
