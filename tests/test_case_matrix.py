"""The case matrix (``benchmarks/case_matrix.py``): its cheapest quick rows hold what every
row must, and what it found broken stays fixed."""

import sys
from pathlib import Path

import pytest

from fecontact import InputError
from fecontact.contact.watch import BOUND
from fecontact.testing import case

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import case_matrix  # noqa: E402

CHEAP = case_matrix.QUICK  # the quick subset: the cheapest rows, a few seconds each


def quick_row(name: str, label: str) -> case_matrix.Row:
    return next(r for r in case_matrix.all_rows([name]) if r.label == label)


@pytest.mark.parametrize(("name", "label"), CHEAP, ids=lambda x: str(x))
def test_quick_row_completes_outside_the_other_body_without_creating_energy(name, label):
    row = quick_row(name, label)
    res = case_matrix.run_row(row)
    assert res["status"] == "completed", res["message"]
    # depth: the solver's record and the positions' own measure, against the pair's bound: a
    # node-based constraint holds its gap to round-off (1e-6 of the case's length is far
    # above it); a mortar interface holds weighted gaps, its nodes within BOUND of an edge
    if res["mortar"]:
        tolerance = BOUND * res["edge"]
    else:
        tolerance = case_matrix.PEN_REL * case_matrix.CASES[name].length
    assert res["max_penetration"] <= tolerance
    assert res["depth"] <= tolerance
    # energy: the closing step's position correction and jump create O(h²) energy on a
    # flexible body (docs/explanation/energy_ledger.md), measured at most 5e-3 of the scale
    # on these rows; rigid bodies create round-off
    assert res["created_rel"] <= case_matrix.CREATED or res["created"] <= case_matrix.ROUND_OFF_J


def test_a_tumbling_box_started_with_a_corner_under_the_plane_is_refused_naming_height():
    with pytest.raises(InputError, match="height: the lowest corner starts at z = -0.003"):
        case("tumbling_box").build(height=0.1)
    with pytest.raises(InputError, match="give a height above 4.16"):
        case("tumbling_box").build(a=20.0)


def test_a_post_started_inside_the_rod_is_refused_naming_its_parameters():
    # the post's axis 17 mm from the rod's with 20 + 5 mm of radii: it used to reach the run's
    # initial check as "contact 0 penetrates", naming no parameter
    with pytest.raises(InputError, match="post_distance, post_azimuth, post_radius"):
        case("rod_on_post").build(post_distance=0.02)
    with pytest.raises(InputError, match="within post_radius \\+ rod radius = 0.505 m"):
        case("rod_on_post").build(post_radius=0.5)
    case("rod_on_post").build(post_bottom=0.01, post_distance=0.2, post_radius=0.005)  # clear


def test_two_balls_started_inside_their_mortar_stand_off_are_refused_naming_gap():
    refused = "gap: 0 radii start the balls' mortar contact at -7.06e-06 m"
    with pytest.raises(InputError, match=refused):
        case("two_balls").build(gap=0.0, base=1)
    # node-to-surface reads the poles' distance to round-off: gap = 0 is admitted
    case("two_balls").build(gap=0.0, base=1, method="node-to-surface")


def test_a_bar_struck_at_a_strain_its_nodes_cannot_hold_is_refused_naming_velocity():
    # the strain at the wall is v/c and the discrete front overshoots it; only the end node
    # holds the wall: the matrix's row at 10 x the default speed (v = c = 1 m/s) left the
    # second node 8.95 mm inside the wall, and 0.7 c 0.39 mm; 0.6 c none
    with pytest.raises(InputError, match="velocity must be at most 0.6 of the bar's wave"):
        case("impacting_bar").build(velocity=0.7)
    with pytest.raises(InputError, match="velocity must be at most 1.2 times the bars' wave"):
        case("two_bars").build(velocity=1.4)
    row = case_matrix.Row("impacting_bar", "0.6 c", {"velocity": 0.6}, {}, 1.0, 0.3)
    res = case_matrix.run_row(row)
    assert res["status"] == "completed", res["message"]
    assert res["depth"] <= 1e-15  # every node on its side of the wall (the end: round-off)
