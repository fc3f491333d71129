"""Mortar rows held through a Newton loop (:mod:`fecontact.contact.mortar_hold`): two P1
cubes thrown at each other with their edges crossed, whose node at the crossing holds a
share of its covered weight at the taking-part threshold ¼."""

import numpy as np

from fecontact import Contact, Model, simulate
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.scenes import wave_step
from fecontact.time.state import IntegratorOptions


def turned(axis: int, degrees: float) -> np.ndarray:
    """The rotation matrix of ``degrees`` about the coordinate ``axis`` (right-handed)."""
    a = np.radians(degrees)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    R = np.eye(3)
    R[i, i] = R[j, j] = np.cos(a)
    R[j, i], R[i, j] = np.sin(a), -np.sin(a)
    return R


def crossed_cubes(speed: float):
    """Two free rubber cubes of 2 cm (2 × 2 × 2 cells of six P1 tetrahedra), one turned 45°
    about y, the other 45° about z, their leading edges 1 mm apart along x and crossing at
    90°, thrown at each other at ``speed`` (m/s) each: the model, q0, v0 and the pair."""
    rubber = NeoHookean(1e7, 0.3, 1000.0)
    a, b = (Solid.box([-0.01] * 3, [0.01] * 3, (2, 2, 2), rubber) for _ in range(2))
    xa, xb = a.X @ turned(1, 45.0).T, b.X @ turned(2, 45.0).T
    xa[:, 0] -= xa[:, 0].max() + 0.0005
    xb[:, 0] -= xb[:, 0].min() - 0.0005
    pair = Contact(a, b)
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    q0 = np.concatenate([(xa - a.X).ravel(), (xb - b.X).ravel()])
    v0 = model.translation(a, (speed, 0.0, 0.0)) + model.translation(b, (-speed, 0.0, 0.0))
    return model, q0, v0, pair


def test_cubes_meeting_edge_on_edge_pass_the_crossing():
    """At 3 m/s the run stopped at step 6: the row of the node at the crossing read a weighted
    gap of −22 µm at a share of 0.250, the correction pushed it out to a share just below
    ¼, where it read +inf, and the active set cycled between none and that row. Held
    through the loop, the step closes it and the cubes keep their momentum."""
    model, q0, v0, _ = crossed_cubes(3.0)
    a = model.bodies[0]
    dt = wave_step(a, 1.0)
    steps = list(simulate(model, dt, 8 * dt, IntegratorOptions(rho_inf=0.5), q0=q0, v0=v0))
    assert len(steps) == 9  # the start and 8 steps: past step 6
    assert steps[-1].t > 6 * dt
    M = model.M_full
    mass = float(model.translation(a, (1.0, 0.0, 0.0)) @ M @ model.translation(a, (1.0, 0.0, 0.0)))
    both = [model.translation(a, e) + model.translation(model.bodies[1], e) for e in np.eye(3)]
    drift = [abs(w @ M @ (steps[-1].v - steps[0].v)) for w in both]
    # the contact forces are equal and opposite: round-off of sums of ~10 forces of the
    # order of the momentum, far below 1e-12 of it on any machine
    assert max(drift) < 1e-12 * 2.0 * mass * 3.0
    # the cubes met: cube a slowed (the contact acted)
    va = model.translation(a, (1.0, 0.0, 0.0)) @ M @ steps[-1].v / mass
    assert va < 3.0 - 0.1


def test_a_held_row_reads_on_continuously_where_its_share_falls_below_a_quarter():
    """Cube b, 0.8 mm into cube a, slid along y: the crossing leaves a's node, whose share
    falls below ¼ between 0.59 and 0.58 mm (+inf there). Held from 0.8 mm, its row reads on,
    the same to the bit where it took part, continuous beyond; released, +inf again. Unheld,
    it read +1.5 mm at 0.59 mm (its triangles counted covered by less than
    ``mortar_cover.SMALLEST`` in whether they keep their covered part's dual functions)."""
    model, q0, _, pair = crossed_cubes(0.0)
    a, b = model.bodies

    def slid(dy):
        return q0 + model.translation(a, (8e-4, 0.0, 0.0)) + model.translation(b, (-8e-4, dy, 0.0))

    path = np.linspace(8e-4, 2e-4, 61)
    free = np.array([pair.gaps(slid(dy)) for dy in path])
    (row,) = np.flatnonzero(np.isfinite(free[0]))
    taking = np.isfinite(free[:, row])
    assert taking[0] and not taking[-1]
    pair.hold_rows(slid(path[0]))
    held = np.array([pair.gaps(slid(dy))[row] for dy in path])
    pair.release_rows()
    assert np.all(held[taking] == free[taking, row])
    # the row's slope along the path is 0.07 (−133 to −172 µm over 0.6 mm): a step of 10 µm
    # moves it by 0.7 µm, a jump (the +1.5 mm) by far more than 1 µm
    assert np.abs(np.diff(held)).max() < 1e-6
    assert np.isinf(pair.gaps(slid(path[-1]))[row])
