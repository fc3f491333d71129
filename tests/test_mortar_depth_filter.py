"""The 3D mortar pairs' depth filter: a pair enters and leaves the weighted gaps continuously.

A master triangle whose vertices lie on average more than twice the detection margin ahead of
a slave triangle was cut off whole: as the balls slide, such a pair crossed the cut with a
finite overlap and the rows of the slave triangle's nodes jumped (on the oblique balls of
``benchmarks/probe_pairs.py`` by 4.9e-5 m under a held row's force, 1.9 mJ created;
``docs/validation/stress_3d.md``). Beyond twice the margin the pair's weight now falls to 0 at
three times (``mortar3d._faded``).
"""

import numpy as np

from fecontact import Model
from fecontact.bodies import Solid
from fecontact.contact import Contact
from fecontact.derivative_checks import gap_steps_along
from fecontact.scenes import solid_material


def test_weighted_gaps_continuous_as_the_balls_slide():
    """Two coarse balls 1.5 mm into each other, one slid rigidly by (4, 1) cm over 800 equal
    steps: no row's gap changes in a step by more than its gradient says, 1.5 × the larger of
    |G Δq| at the step's two ends (a kink of g within the step, where a pair's overlap gains
    or loses a vertex or a weight starts to fall, keeps the change between the two ends'
    slopes; the margin 1.5 covers the curvature over a step, 1/800 of the path). Measured:
    the cut made one step change a row by 3.9e-4 m, 40 × the median step (9e-6 m)."""
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    a = Solid.ball([0.0, 0.0, -0.101], 0.1, 1, mat)
    b = Solid.ball([0.003, 0.002, 0.1], 0.1, 1, mat)
    pair = Contact(a, b, method="mortar")
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.03)
    q0 = model.translation(b, (0.0, 0.0, -0.0015))
    change, slope = gap_steps_along(pair, q0, q0 + model.translation(b, (0.04, 0.01, 0.0)), 801)
    assert change.size > 100  # the slide keeps rows in contact
    bound = 1.5 * slope + 1e-15  # (round-off of g ~ 1e-17 m)
    assert np.all(change <= bound), float(np.max(change / bound))
