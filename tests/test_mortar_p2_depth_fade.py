"""The depth cut of two P2 solids' quadratic segments: a pair deep behind leaves continuously.

A master segment whose mean gap over its overlap with a slave segment is below −margin lies
behind it (a far part of the master facing it) and was dropped whole: two P2 disks slid
rigidly across each other moved a row in one step by 14.6 × its slope at an overlap of
10 mm and 77.6 × at 14 mm (margin 7.1 mm). Its weight now falls as t²(3 − 2t) from 1 at a
mean gap of −margin to 0 at −2 margin (``mortar_p2_segments._depth_weights``).
"""

import numpy as np
import pytest

from fecontact import Contact, Model
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.contact.mortar_p2_segments import p2_segment_integrals
from fecontact.derivative_checks import gap_derivatives_error, gap_steps_along

RUBBER = NeoHookean(1e7, 0.3, 1000.0)


def _disks():
    a = Solid.disk([-0.05, 0.0], 0.05, 2, RUBBER, element="P2")
    b = Solid.disk([0.05, 0.0], 0.05, 2, RUBBER, element="P2")
    pair = Contact(a, b, method="mortar")
    model = Model([a, b], [pair], gravity=(0.0, 0.0))

    def shifted(overlap: float, y: float) -> np.ndarray:
        q = np.zeros(model.n)
        o = model.offset_of(b)
        q[o : o + b.ndof] = np.tile([-overlap, y], b.ndof // 2)
        return q

    return pair, shifted


@pytest.mark.parametrize("overlap", [0.010, 0.014])
def test_weighted_gaps_continuous_as_deep_p2_disks_slide(overlap):
    """The right disk, ``overlap`` into the left one (beyond the margin), slid rigidly by
    ±3 cm across it in 400 equal steps: no row's gap changes in a step by more than 1.5 ×
    the larger of |G Δq| at the step's two ends (measured ≤ 1.02; with the whole cut 14.6
    and 77.6)."""
    pair, shifted = _disks()
    assert pair.margin < overlap  # (the pairs at the deepest point are behind)
    change, slope = gap_steps_along(pair, shifted(overlap, -0.03), shifted(overlap, 0.03), 401)
    assert change.size > 400
    bound = 1.5 * slope + 1e-15  # (round-off of g ~ 1e-17 m)
    assert np.all(change <= bound), float(np.max(change / bound))


@pytest.mark.parametrize("overlap", [0.010, 0.014])
def test_derivatives_exact_while_a_deep_p2_pair_fades(overlap):
    """Head to head, 10 and 14 mm into each other: the pairs whose weight is falling (mean
    gap between −2 margin and −margin; 2 and 6 of them) have moments whose gradients and
    Hessians are those of central differences (step 1e-7 m, round-off ~1e-9 of the largest
    entry; measured ≤ 1.5e-9 and ≤ 8.9e-9), and every row its gradient (≤ 1.5e-9)."""
    pair, shifted = _disks()
    q = shifted(overlap, 0.0)
    z = pair._overlapping(q)[2]
    eps, d = 1e-7, pair.margin
    whole = p2_segment_integrals(z, None, np.inf)
    kept = p2_segment_integrals(z, None, d)
    fading = (kept[2] > 0.0) & (kept[2] < whole[2])
    assert fading.sum() >= 2
    z = z[fading]
    moments = p2_segment_integrals(z, True, d)[0]
    err_g = err_h = 0.0
    for i in range(z.shape[1]):
        dz = np.zeros_like(z)
        dz[:, i] = eps
        plus, minus = (p2_segment_integrals(z + s * dz, False, d)[0] for s in (1.0, -1.0))
        for m, p, n in zip(moments, plus, minus, strict=True):
            err_g = max(
                err_g, np.abs((p.v - n.v) / (2 * eps) - m.g[:, i]).max() / np.abs(m.g).max()
            )
            err_h = max(
                err_h, np.abs((p.g - n.g) / (2 * eps) - m.h[:, :, i]).max() / np.abs(m.h).max()
            )
    assert err_g < 2e-8 and err_h < 2e-8
    assert gap_derivatives_error(pair, q, eps)[0] < 2e-8
