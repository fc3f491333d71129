"""The facing test of two P2 solids' quadratic segments: a pair enters and leaves the weighted
gaps continuously.

A master segment whose chord makes less than 120° with the slave segment's was cut off whole:
as one P2 disk turned against another, such a pair crossed the cut with a finite overlap, and
the row of its slave segment's nodes moved by up to 5.4 mm in one step of an eighth of a turn
over 400 (1176 × the rows' own slope over the step). Between 120° and 104.5° the pair's overlap
now shrinks to 0 as t²(3 − 2t) toward the contact zone's side, as on linear segments
(``mortar_segments.TURNED``, tests/test_mortar_facing_fade.py).
"""

import numpy as np
import pytest

from fecontact import Contact, Model
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.contact.mortar_p2_segments import MortarContactP2, p2_segment_integrals
from fecontact.derivative_checks import gap_derivatives_error, rigidly_placed, turn_gap_steps

RUBBER = NeoHookean(1e7, 0.3, 1000.0)


def _disks():
    a = Solid.disk([-0.05, 0.0], 0.05, 2, RUBBER, element="P2")
    b = Solid.disk([0.05, 0.0], 0.05, 2, RUBBER, element="P2")
    pair = Contact(a, b, method="mortar")
    assert isinstance(pair, MortarContactP2)
    return b, pair, Model([a, b], [pair], gravity=(0.0, 0.0))


def _turns(z: np.ndarray) -> np.ndarray:
    """n_s·n_m of the pairs' chords (the normals are the chords turned alike)."""
    s, m = z[:, 2:4] - z[:, 0:2], z[:, 8:10] - z[:, 6:8]
    return np.einsum("pi,pi->p", s, m) / np.linalg.norm(s, axis=1) / np.linalg.norm(m, axis=1)


@pytest.mark.parametrize("dy", [0.0, 0.005, 0.015])
def test_weighted_gaps_continuous_as_a_p2_disk_turns(dy):
    """Two P2 disks of 16 quadratic segments 1.5 mm into each other, one turned by an eighth
    of a turn over 400 equal steps (node positions linear in the step): no row's gap changes
    in a step by more than 1.5 × the larger of |G Δq| at the step's two ends (1.5 covers the
    curvature over 1/400 of the path; measured ≤ 1.009). With the hard cut: 2.6–5.4 mm in
    one step, 101–1176 × |G Δq|."""
    body, pair, model = _disks()
    change, slope = turn_gap_steps(pair, model, body, np.pi / 8, (-0.0015, dy))
    assert change.size > 400  # the turn keeps rows in contact
    bound = 1.5 * slope + 1e-15  # (round-off of g ~ 1e-17 m)
    assert np.all(change <= bound), float(np.max(change / bound))


@pytest.mark.parametrize("angle", [0.0, 0.0687, 0.3043])
def test_derivatives_exact_while_a_p2_pair_fades(angle):
    """Where pairs lie in the band (0 < φ < 1): the fading pairs' moments ∫ N_k g_N ds have
    the gradients and Hessians of central differences, and every row its gradient (≤ 7e-9:
    the segments of the fading pairs are covered in part, and their dual coefficients
    amplify the round-off; the rows' Hessians there are at fixed coefficients,
    tests/test_mortar_p2.py). The differences are extrapolated from the steps 2e-7 and
    1e-7 m (Richardson): at 0.0687 the fading pair also lies far in front (its weight ψ
    small, coverage 1e-6), whose third derivatives left a plain central difference 1.3e-6
    off at 1e-7 m, 1.3e-4 at 1e-6 m, 1.3e-8 at 1e-8 m (the step's square: truncation);
    extrapolated, 7e-11 at most (measured), round-off ~1e-9 of the largest entry."""
    body, pair, model = _disks()
    q = rigidly_placed(model, body, angle, (-0.0015, 0.005))
    z = pair._overlapping(q)[2]
    c = _turns(z)
    z = z[(c > -0.5) & (c < -0.25)]
    assert len(z) >= 1
    eps, moments = 1e-7, p2_segment_integrals(z, True, pair.margin)[0]

    def central(i, h):  # the moments' values and gradients, central differences along z_i
        d = np.zeros_like(z)
        d[:, i] = h
        plus = p2_segment_integrals(z + d, False, pair.margin)[0]
        minus = p2_segment_integrals(z - d, False, pair.margin)[0]
        pairs = zip(plus, minus, strict=True)
        return [((p.v - n.v) / (2.0 * h), (p.g - n.g) / (2.0 * h)) for p, n in pairs]

    err_g = err_h = 0.0
    for i in range(z.shape[1]):
        wide, near = central(i, 2.0 * eps), central(i, eps)
        for m, (wv, wg), (nv, ng) in zip(moments, wide, near, strict=True):
            fd = (4.0 * nv - wv) / 3.0 - m.g[:, i]
            err_g = max(err_g, np.abs(fd).max() / np.abs(m.g).max())
            fd = (4.0 * ng - wg) / 3.0 - m.h[:, :, i]
            err_h = max(err_h, np.abs(fd).max() / np.abs(m.h).max())
    assert err_g < 2e-8 and err_h < 2e-8
    # the rows at steps 1e-7 and 1e-8 m, the better kept: at 0.0687 a segment is covered by
    # 9.7e-7 of its length, within a step of 1e-7 m of the sliver cut (mortar_p2.SMALLEST,
    # 1e-6), across which its rows jump by design (0.067 off; 2.5e-10 at 1e-8 m); a wrong
    # derivative is off at both steps
    assert min(gap_derivatives_error(pair, q, step)[0] for step in (eps, 0.1 * eps)) < 2e-8
