"""The 2D mortar pairs' facing cut: a pair enters and leaves the weighted gaps continuously.

A master segment whose normal makes less than 120° with the slave segment's was cut off whole:
as the disks turn, such a pair crossed the cut with a finite overlap, the covered part of the
slave segment (and with it the dual functions of its other pairs) lost that overlap at once,
and the row of the segment's node jumped (on the mortar disks of ``benchmarks/stress_2d.py`` at
14.5 m/s, 8 Δx/c, by 1.26 mm within 3 µm of motion, +4.8e-5 → −1.2e-3 m;
``docs/validation/localization.md``). Between 120° and 104.5° the pair's overlap now shrinks
to 0 as t²(3 − 2t) toward the contact zone's side (``mortar_segments.TURNED``).
"""

import numpy as np
import pytest

from fecontact import Contact, Model
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.derivative_checks import gap_derivatives_error, rigidly_placed, turn_gap_steps

RUBBER = NeoHookean(1e7, 0.3, 1000.0)


def _disks():
    a = Solid.disk([-0.05, 0.0], 0.05, 2, RUBBER)
    b = Solid.disk([0.05, 0.0], 0.05, 2, RUBBER)
    pair = Contact(a, b, method="mortar")
    return b, pair, Model([a, b], [pair], gravity=(0.0, 0.0))


@pytest.mark.parametrize("dy", [0.0, 0.005, 0.015])
def test_weighted_gaps_continuous_as_a_disk_turns(dy):
    """Two 16-segment disks 1.5 mm into each other, one turned by an eighth of a turn about
    its centre over 400 equal steps (node positions linear in the step, so that G Δq is the
    slope of the path): no row's gap changes in a step by more than 1.5 × the larger of
    |G Δq| at the step's two ends (a kink where a pair's overlap gains or loses a node keeps
    the change between the two ends' slopes; 1.5 covers the curvature over 1/400 of the
    path). Measured with the hard cut: 1.2–1.8 mm in one step (670–2800 × the bound)."""
    body, pair, model = _disks()
    change, slope = turn_gap_steps(pair, model, body, np.pi / 8, (-0.0015, dy))
    assert change.size > 400  # the turn keeps rows in contact
    bound = 1.5 * slope + 1e-15  # (round-off of g ~ 1e-17 m)
    assert np.all(change <= bound), float(np.max(change / bound))


@pytest.mark.parametrize(("angle", "columns"), [(0.0, 22), (0.0687, 14), (0.3043, 22)])
def test_derivatives_exact_while_a_pair_fades(angle, columns):
    """Where a pair lies in the band (0 < φ < 1), with its overlap bounding the covered part
    of another pair's segment (angles 0 and 0.3043 rad: that pair carries the fading pair's
    master segment) or not (0.0687), the gradient and Hessian of every row match central
    differences: the bounds of the existing test of the derivatives (step 1e-7 m: round-off
    of the differences ~1e-9, measured here ≤ 4e-10 and ≤ 2e-8)."""
    body, pair, model = _disks()
    q = rigidly_placed(model, body, angle, (-0.0015, 0.005))
    fading = pair._overlapping(q)[-1][4][6]
    assert 0 < fading.sum() < len(fading)
    assert pair._local(q)[1].shape[1] == columns  # (12 + 8 foreign + 2 kinds; 12 + 2)
    err_g, err_h = gap_derivatives_error(pair, q, 1e-7)
    assert err_g < 1e-8 and err_h < 1e-6
