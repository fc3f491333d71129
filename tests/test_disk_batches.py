"""Disk pairs evaluated together (``fecontact.contact.disk_batches``) give the numbers of the
pairs evaluated alone, and a small pile of disks in a box runs on them without penetration."""

import itertools

import numpy as np
import pytest

from fecontact import Model
from fecontact.bodies import Disk, RigidBody2D
from fecontact.contact import Circle, Contact, Plane
from fecontact.contact.disk_batches import DiskDiskBatch, DiskPlaneBatch
from fecontact.time import simulate


def disks_and_walls(seed: int, n: int = 5):
    """``n`` disks of different radii scattered in a box of three tilted walls and a circular
    obstacle, every disk against every wall and every other disk (friction on some)."""
    rng = np.random.default_rng(seed)
    disks = [
        RigidBody2D.uniform(1.0 + i, rng.uniform(-0.3, 0.3, 2), Disk(rng.uniform(0.02, 0.08)))
        for i in range(n)
    ]
    walls = [Plane(rng.normal(size=2) * 0.1, rng.normal(size=2)) for _ in range(3)]
    contacts = [Contact(d, w, restitution=0.5, friction=0.3) for d in disks for w in walls]
    contacts += [Contact(disks[0], Circle([0.0, 0.0], 1.0, inside=True))]
    contacts += [
        Contact(a, b, restitution=0.2, friction=0.3) for a, b in itertools.combinations(disks, 2)
    ]
    return Model(disks, contacts, (0.0, -9.81)), rng


def stacked(parts):
    """The per-pair tuples of arrays stacked row over row (None kept)."""
    return [None if p[0] is None else np.concatenate(p) for p in zip(*parts, strict=True)]


@pytest.mark.parametrize("seed", range(4))
def test_batches_give_the_pairs_own_numbers(seed):
    model, rng = disks_and_walls(seed)
    contacts = model.contacts
    kinds = [type(u) for u in contacts.units]
    # the planes' run, the circle alone, the disks' run: three units over 31 pairs
    assert kinds[0] is DiskPlaneBatch and kinds[2] is DiskDiskBatch and len(kinds) == 3
    for _ in range(5):
        q = rng.normal(size=len(contacts.free_index)) * 0.1
        for unit, pairs in (
            (contacts.units[0], contacts.pairs[:15]),
            (contacts.units[2], contacts.pairs[16:]),
        ):
            # the same products row by row: equal to the last bit, not within a tolerance
            g, dofs, G, H = unit.evaluate(q)
            ref = stacked([p.evaluate(q) for p in pairs])
            np.testing.assert_array_equal(g, ref[0])
            np.testing.assert_array_equal(dofs, ref[1])
            np.testing.assert_array_equal(G, ref[2])
            if H is None:
                assert ref[3] is None
            else:
                np.testing.assert_array_equal(H, ref[3])
            np.testing.assert_array_equal(unit.gaps(q), ref[0])
            for got, want in zip(
                unit.tangents(q), stacked([p.tangents(q) for p in pairs]), strict=True
            ):
                np.testing.assert_array_equal(got, want)


def test_contact_set_with_batches_matches_pair_assembly():
    model, rng = disks_and_walls(7)
    contacts = model.contacts
    q = rng.normal(size=len(contacts.free_index)) * 0.1
    select = np.flatnonzero(rng.random(contacts.size) < 0.6)
    w = rng.random(len(select))
    g, G, C = contacts.linearize(q, select, w)
    n = contacts.n_free
    G_ref, C_ref = np.zeros((contacts.size, n)), np.zeros((n, n))
    for j, (_, dofs, Gp, Hp) in enumerate(contacts.evaluate(q)):
        row = np.flatnonzero(contacts.owner == j)[0]
        fi = contacts.free_index[dofs[0]]
        G_ref[row, fi] = Gp[0]
        k = np.searchsorted(select, row)
        if Hp is not None and k < len(select) and select[k] == row:
            C_ref[np.ix_(fi, fi)] += w[k] * Hp[0]
    np.testing.assert_array_equal(g, contacts.gaps(q)[select])
    np.testing.assert_array_equal(G, G_ref[select])
    # (sums over pairs in one order: equal up to the round-off of a few terms of size ~1/d)
    np.testing.assert_allclose(C, C_ref, rtol=0, atol=1e-12 * np.abs(C_ref).max())


def test_small_pile_lands_without_penetration():
    """Four disks dropped 2 cm into a box (e_N 0.5, μ 0.3, h = 1 ms) for 0.1 s: every step's
    deepest overlap stays at the position correction's tolerance."""
    r, k = 0.05, 2
    rng = np.random.default_rng(0)
    disks = [
        RigidBody2D.uniform(
            1.0,
            ((i % k - 0.5) * 2.3 * r + rng.uniform(-0.005, 0.005), r + 0.02 + (i // k) * 2.3 * r),
            Disk(r),
        )
        for i in range(4)
    ]
    w = k * 1.3 * r + 0.02
    walls = [Plane([0, 0], [0, 1]), Plane([-w, 0], [1, 0]), Plane([w, 0], [-1, 0])]
    pairs = [(d, o) for d in disks for o in walls] + list(itertools.combinations(disks, 2))
    model = Model(
        disks, [Contact(a, b, restitution=0.5, friction=0.3) for a, b in pairs], (0, -9.81)
    )
    assert [type(u) for u in model.contacts.units] == [DiskPlaneBatch, DiskDiskBatch]
    depth, rise = 0.0, 0.0
    for st in simulate(model, 1e-3, 0.1):
        depth = max(depth, model.contacts.penetration(st.q))
        rise = max(rise, st.v[1], st.v[4])  # the lower disks' upward speed
    # the correction closes gaps to tol_gap = 1e-12 m: overlaps beyond it are penetration
    assert depth <= 1e-12
    # the lower disks fell 2 cm and left the floor at e_N √(2 g h₀) (Newton's law at the
    # impact located in its step), less the g h that gravity takes within the step
    v_up = 0.5 * np.sqrt(2 * 9.81 * 0.02)
    assert v_up - 9.81e-3 <= rise <= v_up
