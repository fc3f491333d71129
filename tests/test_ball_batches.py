"""Ball pairs in space evaluated together (``fecontact.contact.ball_batches``) give the numbers
of the pairs evaluated alone, through the contact set too, and a column of balls runs on them
step for step as on the pairs alone."""

import itertools

import numpy as np
import pytest

from fecontact import Model
from fecontact.bodies import Ball, Capsule, RigidBody3D
from fecontact.contact import Contact, Plane
from fecontact.contact.ball_batches import BallBallBatch, BallPlaneBatch
from fecontact.contact.contact_set import ContactSet
from fecontact.time import simulate


def balls_and_planes(seed: int, n: int = 5):
    """``n`` balls of different radii scattered over three tilted planes, every ball against
    every plane and every other ball (friction on all), and a capsule on the first plane
    between them (evaluated alone)."""
    rng = np.random.default_rng(seed)
    balls = [
        RigidBody3D.uniform(1.0 + i, rng.uniform(-0.3, 0.3, 3), Ball(rng.uniform(0.02, 0.08)))
        for i in range(n)
    ]
    capsule = RigidBody3D.uniform(1.0, (0.0, 0.0, 0.5), Capsule(0.03, 0.1))
    planes = [Plane(rng.normal(size=3) * 0.1, rng.normal(size=3)) for _ in range(3)]
    contacts = [Contact(b, p, restitution=0.5, friction=0.3) for b in balls for p in planes]
    contacts += [Contact(capsule, planes[0], friction=0.3)]
    contacts += [
        Contact(a, b, restitution=0.2, friction=0.3) for a, b in itertools.combinations(balls, 2)
    ]
    return Model([*balls, capsule], contacts, (0.0, 0.0, -9.81)), rng


def stacked(parts):
    """The per-pair tuples of arrays stacked row over row (None kept)."""
    return [None if p[0] is None else np.concatenate(p) for p in zip(*parts, strict=True)]


def pairs_alone(model):
    """The model's pairs in a contact set of their own, each pair its own unit."""
    pairs = model.contacts.pairs
    keys = [type(p).batch_key for p in pairs]
    for p in pairs:
        p.batch_key = lambda: None
    try:
        return ContactSet(pairs, model.contacts.free_index, model.contacts.n_free)
    finally:
        for p, key in zip(pairs, keys, strict=True):
            del p.batch_key
            assert type(p).batch_key is key


@pytest.mark.parametrize("seed", range(4))
def test_batches_give_the_pairs_own_numbers(seed):
    model, rng = balls_and_planes(seed)
    contacts = model.contacts
    kinds = [type(u) for u in contacts.units]
    # the planes' run, the capsule alone, the balls' run: three units over 26 pairs
    assert kinds[0] is BallPlaneBatch and kinds[2] is BallBallBatch and len(kinds) == 3
    for _ in range(5):
        q = rng.normal(size=len(contacts.free_index)) * 0.1
        q_n = q + rng.normal(size=len(q)) * 0.01
        for unit, pairs in (
            (contacts.units[0], contacts.pairs[:15]),
            (contacts.units[2], contacts.pairs[16:]),
        ):
            # the same operations row by row: equal to the last bit, not within a tolerance
            g, dofs, G, H = unit.evaluate(q)
            ref = stacked([p.evaluate(q) for p in pairs])
            np.testing.assert_array_equal(g, ref[0])
            np.testing.assert_array_equal(dofs, ref[1])
            np.testing.assert_array_equal(G, ref[2])
            if H is None:  # a ball's centre is its body's: the pairs' curvature is zero
                assert not ref[3].any()
            else:
                np.testing.assert_array_equal(H, ref[3])
            np.testing.assert_array_equal(unit.gaps(q), ref[0])
            rows = np.flatnonzero(rng.random(unit.size) < 0.5)
            want = stacked([p.tangents(q) for p in pairs])
            for got, w in zip(unit.tangent_rows(q, rows), want, strict=True):
                np.testing.assert_array_equal(got, w[rows])
            for got, w in zip(unit.tangents(q), want, strict=True):
                np.testing.assert_array_equal(got, w)
            slips = np.concatenate(
                [p.slips(q, q_n, T[None]) for p, T in zip(pairs, want[2], strict=True)]
            )
            np.testing.assert_array_equal(unit.slip_rows(q, q_n, want[2][rows], rows), slips[rows])


def test_contact_set_rows_match_the_pairs_alone():
    """Gaps, gradients, slip rows and slips of a selection through the units are those of a
    contact set of the pairs alone; the curvature sums the same terms (its sum over pairs is
    in one order in both)."""
    model, rng = balls_and_planes(7)
    batched, alone = model.contacts, pairs_alone(model)
    assert len(alone.units) == len(alone.pairs) and len(batched.units) == 3
    q = rng.normal(size=len(batched.free_index)) * 0.1
    q_n = q + rng.normal(size=len(q)) * 0.01
    select = np.flatnonzero(rng.random(batched.size) < 0.6)
    w = rng.random(len(select))
    g, G, C = batched.linearize(q, select, w)
    g0, G0, C0 = alone.linearize(q, select, w)
    np.testing.assert_array_equal(g, g0)
    np.testing.assert_array_equal(G, G0)
    np.testing.assert_array_equal(C, C0)
    GT, T = batched.tangent_jacobian(q, select)
    GT0, T0 = alone.tangent_jacobian(q, select)
    np.testing.assert_array_equal(GT, GT0)
    np.testing.assert_array_equal(T, T0)
    np.testing.assert_array_equal(
        batched.slips(q, q_n, select, GT, T), alone.slips(q, q_n, select, GT0, T0)
    )


def column(n: int):
    """``n`` balls of 5 cm nearly on one vertical, 1 cm apart, over a floor (e_N 0.5,
    μ 0.3)."""
    rng = np.random.default_rng(0)
    balls = [
        RigidBody3D.uniform(1.0, (*rng.uniform(-1e-3, 1e-3, 2), 0.06 + 0.11 * k), Ball(0.05))
        for k in range(n)
    ]
    floor = Plane([0, 0, 0], [0, 0, 1])
    pairs = [(b, floor) for b in balls] + list(itertools.combinations(balls, 2))
    contacts = [Contact(a, b, restitution=0.5, friction=0.3) for a, b in pairs]
    return Model(balls, contacts, (0.0, 0.0, -9.81))


def test_column_steps_as_the_pairs_alone():
    """Four balls dropped onto each other and the floor for 0.1 s: the batched run's positions
    are those of the pairs alone at every step, to the last bit."""
    runs = []
    for alone in (False, True):
        model = column(4)
        if alone:
            model.contacts = pairs_alone(model)
        else:
            assert [type(u) for u in model.contacts.units] == [BallPlaneBatch, BallBallBatch]
        runs.append(np.array([st.q for st in simulate(model, 1e-3, 0.1)]))
    assert runs[0].shape == runs[1].shape
    np.testing.assert_array_equal(runs[0], runs[1])
    # every contact of the column closed at some step (the floor's and the three between
    # neighbours: pairs 0, 4, 7 and 9), within the correction's tolerance of 1e-12 m
    closed = (np.array([model.contacts.gaps(q) for q in runs[0]]) <= 1e-12).any(axis=0)
    assert closed[[0, 4, 7, 9]].all()
