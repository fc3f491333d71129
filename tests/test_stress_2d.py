"""Planar contact beyond the cases: regression tests of what the sweep
(``benchmarks/stress_2d.py``) found broken, each on a small mesh."""

import numpy as np

from fecontact import Beam2D, Contact, Material, Model, Section, simulate
from fecontact.bodies import Disk, RigidBody2D
from fecontact.testing import case

STEEL = Material(210e9, rho=7850.0)


def test_frictional_disks_whose_safeguard_row_lets_go_complete():
    # off-centre disks with friction and e_N = 0.5 (refinements 2): a node held by the
    # mortar interface's frictionless pointwise safeguard is released in a step; the slip
    # rows of that release hold no frictional contact, and the retake must still take its
    # force out (it stopped with a ValueError in the slip rows' shapes)
    sim = case("two_disks").build(refinements=2, offset=0.015, friction=0.3, restitution=0.5)
    states = list(simulate(sim.model, sim.dt, sim.t_end, sim.options, v0=sim.v0))
    assert states[-1].t == sim.t_end or np.isclose(states[-1].t, sim.t_end)
    vx = [float(np.mean(b.nodal(states[-1].v[sim.model.body_slice(i)])[:, 0]))
          for i, b in enumerate(sim.model.bodies)]  # fmt: skip
    assert vx[0] < 0.0 < vx[1]  # they have struck and part


def test_a_strip_thrown_end_first_at_a_rigid_disk_on_its_axis():
    # the disk's centre on the strip's axis beyond its end: no side of the centreline to
    # tell, none needed (the gap is the distance to the end node); it was refused as "the
    # disk centre lies on the beam centreline"
    section = Section.rectangle(0.05, 0.01)
    strip = Beam2D.straight([-0.51, 0.0], [-0.01, 0.0], 10, STEEL, section)
    disk = RigidBody2D.uniform(1.0, [0.05, 0.0], Disk(0.05))
    model = Model([strip, disk], [Contact(disk, strip, clearance=0.005)], gravity=(0.0, 0.0))
    v0 = model.translation(strip, (2.0, 0.0))
    s = model.body_slice(1)
    for st in simulate(model, 2e-5, 0.006, v0=v0):
        end = strip.positions(st.q[model.body_slice(0)])[-1]
        # measured without the solver's gaps: the end node stays r + c from the centre
        assert np.linalg.norm(disk.center(st.q[s]) - end) >= 0.055 - 1e-12
    assert st.v[s][0] > 1.0  # struck along the axis
    assert abs(st.v[s][1]) < 1e-12 and abs(st.v[s][2]) < 1e-12  # and nothing else
