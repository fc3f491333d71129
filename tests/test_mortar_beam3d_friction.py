"""Coulomb friction on the dual mortar pair of a 3D solid and a Beam3D's tube
(fecontact.contact.mortar_beam3d): the slip rows against central differences of the exact
slips, rows resolved on the solid's normal."""

import numpy as np
from test_mortar_beam3d import R, bent_rod_on_block

from fecontact.testing import moved_on_group


def test_slip_rows_are_the_derivatives_of_the_exact_slips():
    """G_T d against central differences of the exact slips from q to q moved by ±εd on the
    group (every dof: the block's nodes, the beam's translations and its rotations composed
    on the right): the difference is the central rule's O(ε²) (measured 3.4e-6, 3.4e-8,
    3.4e-10 at ε = 1e-5, 1e-6, 1e-7 against rows of 1.8), and the slip rows act on the
    beam's rotations (a turning section moves the material point under a node, by its arm
    of about r: measured 0.84 r)."""
    pair, model, q = bent_rod_on_block()
    pair.friction = 0.3
    dofs, W, T = pair.tangents(q)
    assert np.allclose(np.einsum("mti,msi->mts", T, T), np.eye(2), atol=1e-14)
    rotations = model.offset_of(pair.beam) + pair.beam.rotation_triples.ravel()
    turn = np.isin(dofs, rotations)[:, None, :].repeat(2, axis=1)
    assert np.abs(W[turn]).max() > 0.5 * R  # m/rad: the arm to the tube's surface, about r
    d = np.random.default_rng(2).normal(size=model.n)
    linear = np.einsum("mtk,mk->mt", W, d[dofs])
    errors = []
    for eps in (1e-5, 1e-6):
        plus = pair.slips(moved_on_group(model, q, eps * d), q, T)
        minus = pair.slips(moved_on_group(model, q, -eps * d), q, T)
        errors.append(np.abs((plus - minus) / (2 * eps) - linear).max())
    assert errors[1] <= 1e-7 * np.abs(linear).max()
    assert errors[1] <= 0.02 * errors[0]  # second order: 100× per decade
