"""Rigid disks wedged in a box: rows that the arrangement makes redundant.

Disk–disk and disk–plane pairs each hold independent rows; four disks in a box close seven
of them at once, 14 frictional rows on 12 dofs of rank 9. The run decides from the graph of
its rigid bodies and pairs that its rows can be redundant (minimum-norm multipliers), and a
velocity jump whose frictional law with restitution has no solution there is solved as a
plastic one, counted (docs/validation/pile.md)."""

import dataclasses
import itertools

import numpy as np
import pytest

from fecontact import Model, Pin, Simulation, run
from fecontact.bodies import Disk, RigidBody2D
from fecontact.contact import Contact, Plane
from fecontact.contact.contact_loops import loops_of_contacts
from fecontact.time.simulate import simulate
from fecontact.time.state import State, length_scale
from fecontact.time.stats import StepStats

R = 0.05  # the disks' radius (m)


def _pile(n, friction=0.3, walls=True):
    """The pile of ``benchmarks/pile.py``: n disks of 1 kg in rows over a floor, between two
    walls (or on the floor alone), every disk against every obstacle and every other disk."""
    k = int(np.ceil(np.sqrt(n)))
    rng = np.random.default_rng(0)
    disks = []
    for i in range(n):
        x = (i % k - (k - 1) / 2) * 2.3 * R + rng.uniform(-0.005, 0.005)
        y = R + 0.02 + (i // k) * 2.3 * R
        disks.append(RigidBody2D.uniform(1.0, (x, y), Disk(R)))
    w = k * 1.3 * R + 0.02
    planes = [Plane([0, 0], [0, 1])]
    if walls:
        planes += [Plane([-w, 0], [1, 0]), Plane([w, 0], [-1, 0])]
    pairs = [(d, o) for d in disks for o in planes] + list(itertools.combinations(disks, 2))
    contacts = [Contact(a, b, restitution=0.5, friction=friction) for a, b in pairs]
    return Model(disks, contacts, (0.0, -9.81))


def test_loops_of_rigid_bodies_and_their_pairs():
    # one disk on a floor, a disk on a disk: trees, every row independent
    assert not loops_of_contacts(_pile(1, walls=False))
    stacked = [RigidBody2D.uniform(1.0, (0.0, y), Disk(R)) for y in (R, 3 * R)]
    floor = Contact(stacked[0], Plane([0, 0], [0, 1]), friction=0.3)
    tree = Model(stacked, [floor, Contact(*stacked, friction=0.3)], (0.0, -9.81))
    assert not loops_of_contacts(tree)
    # a disk against a floor and a wall (two pairs with the ground), two disks on a floor
    # touching each other (ground, disk, disk): loops
    assert loops_of_contacts(_pile(1))
    assert loops_of_contacts(_pile(2, walls=False))
    assert loops_of_contacts(_pile(4))
    # a pendulum pinned at its end (one free dof) against a stop with friction: two rows
    pinned = RigidBody2D.uniform(1.0, (0.0, 0.0), Disk(R)).fix("x", "y")
    stop = Contact(pinned, Plane([0, -R], [0, 1]), friction=0.3)
    assert loops_of_contacts(Model([pinned], [stop], (0.0, -9.81)))
    assert not loops_of_contacts(
        Model([pinned], [Contact(pinned, Plane([0, -R], [0, 1]))], (0.0, -9.81))
    )
    # joints tie the bodies they join: two disks pinned together, each on the floor, close
    # ground, disk, pin, disk; a disk pinned to the ground and on the floor closes a loop too
    pair = [RigidBody2D.uniform(1.0, (x, R), Disk(R)) for x in (0.0, 2 * R)]
    floor = Plane([0, 0], [0, 1])
    on_floor = [Contact(d, floor) for d in pair]
    assert not loops_of_contacts(Model(pair, on_floor, (0.0, -9.81)))
    assert loops_of_contacts(
        Model(pair, on_floor, (0.0, -9.81), joints=[Pin(pair[0], (R, R), pair[1])])
    )
    assert loops_of_contacts(
        Model(pair[:1], on_floor[:1], (0.0, -9.81), joints=[Pin(pair[0], (0, R))])
    )


# the 2 × 2 pile's state at t = 0.79 s (run from rest at 1 ms steps; q: displacements of
# (x, y, θ) per disk from where the pile is built), four steps before its wedged jump
Q790 = [
    0.056120950279344266, -0.01999999999999879, -1.1113093110832533,
    0.044802132862361295, -0.02, -0.8713677241905828,
    -0.03790973523936193, -0.13362650791443945, 3.623987921977534,
    -0.0026990878459579952, -0.04838338917964308, 1.8435053260343721,
]  # fmt: skip
V790 = [
    0.002147007971490965, -1.5612511283791264e-17, -0.04294015942981763,
    -8.471232974353407e-18, -2.6020852139652106e-17, -3.5099238330597394e-16,
    9.364689710013201e-17, -0.23049860761774205, 0.06238643900259799,
    -0.06048106466057414, 0.1289150307573983, 2.4163881910155016,
]  # fmt: skip


@pytest.mark.slow
def test_the_wedged_jump_is_solved_plastic_and_counted(tmp_path):
    model = _pile(4)
    sim = Simulation(model, dt=1e-3, t_end=0.01, q0=np.array(Q790), v0=np.array(V790))
    s = run(sim, tmp_path / "jam", progress=False, frames=False)
    assert s["status"] == "completed"
    # the wedged jump at 0.796 s, and one at 0.800 s: which member of the wedged jump's
    # family is kept (the law has several there) decides the next; with the stick branch
    # at a cone's edge (docs/explanation/friction.md) it was the one alone
    assert s["friction_solver"]["plastic_jumps"] == 2
    assert any("plastic" in w for w in s["warnings"])  # (not only counted: said)
    # the law's residuals converged at every solve kept, and nothing inside beyond the
    # run's gap tolerance (tol_gap 1e-12 of the coordinates' extent, 4.7e-13 m here)
    assert s["final_residuals"] == {"position": 0.0, "velocity": 0.0}
    assert s["max_penetration"] <= 1e-12 * length_scale(model, np.array(Q790))


# the 2 × 2 pile at k ÷ 100 at t = 0.899 s (run from rest at 1 ms steps): three disks at
# rest wedged, the fourth rolling on them; k ν of the last step on its contacts (1 to 18)
Q899 = [
    0.05613038312661326, -0.019999999999933772, -1.1061451595260714,
    0.04480213286245402, -0.02000000000003974, -0.8740742325491342,
    -0.03790973523936194, -0.135, 3.6236963373161997,
    -0.0026806347728402283, -0.04838859425067327, 1.8634747556375741,
]  # fmt: skip
V899 = [
    -6.188251466339745e-18, -1.5612511283791264e-17, -6.521444617022061e-17,
    1.5189862054281884e-18, 1.734723475976807e-18, -3.0379724108563777e-17,
    6.295217862564486e-18, 1.734723475976807e-18, 4.7949798594437055e-17,
    -0.018147634770369257, 0.039510626417353936, 0.7093433317321892,
]  # fmt: skip
NU899 = {
    0: 3.589224866687908e-05, 3: 4.904999960263286e-06, 6: 8.306943507793524e-06,
    7: 1.4144835854782505e-05, 13: 1.6636918907118648e-05, 14: 3.917989967622299e-05,
}  # fmt: skip
CANDIDATES899 = [0, 3, 5, 6, 7, 12, 13, 14, 16]


def test_least_norm_cycles_entered_anywhere_keep_one_member():
    # the position correction of the step after 0.899 s: least_norm's cycles go round three
    # members of the law's family (contacts sticking and slipping in turn); each
    # relinearization, warm-started from the last one's solution, entered the loop
    # elsewhere and stopped on another member, rates 1.1e-13 m apart, so that the update
    # (1.06e-12 m) never fell below 0.1 of the gap tolerance and the step failed after 6
    # halvings. Keeping the least-norm member visited makes the relinearizations settle.
    model = _pile(4)
    q, v = np.array(Q899), np.array(V899)
    nu = np.zeros(model.contacts.size)
    nu[list(NU899)] = list(NU899.values())
    gravity = np.tile([0.0, -9.81, 0.0], 4)
    start = State(
        0.0, q, v, gravity, gravity.copy(), h=1e-3, gaps=model.contacts.gaps(q),
        candidates=np.array(CANDIDATES899), nu=nu, impulse=np.zeros(model.contacts.size),
    )  # fmt: skip
    options = Simulation(model, dt=1e-3, t_end=0.003).options
    options = dataclasses.replace(options, multiplier_scale=0.01)
    stats = StepStats()
    states = list(simulate(model, 1e-3, 0.003, options, start=start, stats=stats))
    assert [s.step for s in states] == [1, 2, 3]
    assert all(s.halvings == 0 for s in states)
    coulomb = stats.contact.coulomb
    # the loop's members had contacts sticking and slipping in turn: read on their slip
    # branch at the cone's edge, the least-norm search settles, and the loop is not met
    assert coulomb.least_norm_unsettled == 0
    # nothing inside beyond the gap tolerance (1e-12 of the coordinates' extent)
    assert -min(s.gaps.min() for s in states) <= 1e-12 * length_scale(model, q)
