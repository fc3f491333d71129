"""Rigid bodies on lasting contacts with the smooth contact force: a contact the smooth step
holds is an equality of the velocity jump only while the step's total impulse on it stays
a push (docs/explanation/energy_ledger.md, *Default cases that warn*)."""

import dataclasses

from fecontact.simulation import run
from fecontact.testing import case


def test_a_held_pivot_leaves_the_floor_when_the_other_corner_strikes(tmp_path):
    """The rocking block at e_N = 1, its pivot corner held by the smooth force when the
    other corner strikes: Newton's law on both corners lifts the pivot (its velocity after a
    lone strike at the other corner points up), so the block hops and lands on the pivot
    again (its contact 0 strikes at 0.131 s). Held as an equality, the pivot stayed down by
    a pull of 0.69 N s a strike and the run created 7.6e-4 of its scale by 0.3 s; let go,
    9.9e-8 (1e-6: ten times that, four decades below the ledger's warning)."""
    sim = case("rocking_block").build(restitution=1.0)
    options = dataclasses.replace(sim.options, smooth_contact="on")
    summary = run(sim.replace(t_end=0.3, options=options), tmp_path, frames=False)
    ledger = summary["energy_ledger"]
    assert ledger["created"] <= 1e-6 * ledger["scale"]
    struck = [i["contact"] for i in summary["impacts"] if i["time"] > 0.1]
    assert 0 in struck  # the pivot left the floor and struck it again
