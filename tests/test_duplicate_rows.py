"""A node's row twice (two segments of a beam clipped to their shared node) is merged before
the multipliers' solve (fecontact/contact/kkt.py): no least squares, the merge counted, the
motion that of the row once and its multiplier shared equally."""

import numpy as np

from fecontact import Beam2D, Contact, Material, Model, Section, simulate
from fecontact.bodies.rigid import Disk, RigidBody2D
from fecontact.contact.laws import solve_position_correction, solve_velocity_jump
from fecontact.contact.stats import ContactStats
from fecontact.time.stats import StepStats

STEEL = Material(210e9, rho=7850.0)
M = np.array([2.0, 3.0, 5.0])  # a diagonal mass matrix (kg)
ROW = np.array([[0.6, -0.8, 0.0]])  # a unit normal over the first two dofs


def test_a_row_twice_gives_the_velocity_jump_of_the_row_once():
    c = np.array([-1.5])  # an approaching normal velocity (m/s)
    once = solve_velocity_jump(ROW, c, lambda b: b / M[:, None], 1.0, 1.0)
    merged = ContactStats(merge_duplicates=True)
    W, Lam, _ = solve_velocity_jump(
        np.vstack([ROW, ROW]), np.r_[c, c], lambda b: b / M[:, None], 1.0, 1.0, stats=merged
    )
    assert merged.least_squares == 0 and merged.duplicate_rows == 1
    # halves and their sum are exact in binary: the jump is the single row's to the bit,
    # and each row holds half the impulse
    np.testing.assert_array_equal(W, once[0])
    np.testing.assert_array_equal(Lam, [once[1][0] / 2, once[1][0] / 2])
    np.testing.assert_allclose(ROW @ W + c, 0.0, atol=1e-15)  # (the row closed: ġ = 0)
    unmerged = ContactStats()
    solve_velocity_jump(np.vstack([ROW, ROW]), np.r_[c, c], lambda b: b / M[:, None], 1.0,
                        1.0, stats=unmerged)  # fmt: skip
    assert unmerged.least_squares > 0  # (without the merge the Schur matrix is singular)


def test_a_row_twice_gives_the_position_correction_of_the_row_once():
    g0 = -2e-4  # m: a penetration the correction removes; the gap linear in U

    def answer(rows):
        G = np.repeat(ROW, rows, axis=0)
        stats = ContactStats(merge_duplicates=True)
        gaps = lambda U: (np.full(rows, g0) + G @ U, G)  # noqa: E731
        system = lambda U, s, A: ((lambda b: b / M.reshape(-1, *[1] * (b.ndim - 1))), None)  # noqa: E731
        U, nu, _ = solve_position_correction(gaps, system, 3, 1.0, 1.0, 1e-12, 1e-14,
                                             stats=stats)  # fmt: skip
        return U, nu, stats

    U1, nu1, _ = answer(1)
    U2, nu2, stats = answer(2)
    assert stats.least_squares == 0 and stats.duplicate_rows > 0
    np.testing.assert_array_equal(U2, U1)  # (exact halves, as above)
    np.testing.assert_array_equal(nu2, [nu1[0] / 2, nu1[0] / 2])
    assert abs(g0 + ROW @ U1)[0] < 1e-15  # (the gap closed: a linear gap, one Newton step)


def test_a_disk_on_a_strip_right_over_a_node_takes_no_least_squares():
    # a pinned strip of 20 elements: x = 0.5 m is node 10, where elements 9 and 10 both clip
    # their closest point, so the disk's row comes twice
    strip = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 20, STEEL, Section.rectangle(0.05, 0.01))
    strip.pin(0).pin(-1)
    disk = RigidBody2D.uniform(0.5, [0.5, 0.057], Disk(0.05))
    model = Model([strip, disk], [Contact(strip, disk, clearance=0.005)], gravity=(0.0, 0.0))
    v0 = model.translation(disk, (0.0, -30.0))
    stats = StepStats()
    states = list(simulate(model, 2e-5, 0.002, v0=v0, stats=stats))
    assert stats.contact.least_squares == 0 and stats.contact.duplicate_rows > 0
    # the two clipped rows (elements 9 and 10) share every impulse equally, and hold it:
    # the disk stays out of the strip's surface (its centre 0.055 m above the node, within
    # the position tolerance's round-off, 1e-9 m). Equal to 1e-7 of the peak impulse: once
    # the strip rings, round-off moves the node off the centre's foot and the rows are no
    # longer one row twice (each solved, measured 2.4e-9 of the peak 1.7 N s apart)
    impulses = np.array([st.impulse for st in states[1:]])
    peak = impulses[:, 9].max()
    assert peak > 0.0
    np.testing.assert_allclose(impulses[:, 9], impulses[:, 10], rtol=0, atol=1e-7 * peak)
    for st in states:
        x = strip.positions(st.q[model.body_slice(0)])
        c = disk.center(st.q[model.body_slice(1)])
        assert np.linalg.norm(c - x[10]) >= 0.055 - 1e-9
