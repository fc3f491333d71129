"""Friction of a mortar interface at a block's edge: the slip rows of a node where the
boundary turns by 60° or more lie in the plane of the facets its row integrates over, so that
the friction of a sliding block stays in Coulomb's cone (docs/explanation/mortar.md,
*Friction at edges and corners*)."""

import numpy as np

from fecontact import Model, simulate
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.contact import Contact
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
