"""The run's own tolerances and margins decide, everywhere (issue: other silent paths)."""

import numpy as np
import pytest

from fecontact import InputError, Model
from fecontact.bodies import LinearElastic, PointMass, Solid
from fecontact.contact import Contact, Plane
from fecontact.contact.body_pairs import NodeSurfaceContact
from fecontact.time import IntegratorOptions, simulate


def point_below_plane(depth):
    mass = PointMass(1.0, [0.0, 1.0])
    return Model([mass], [Contact(mass, Plane([0.0, 1.0 + depth], [0.0, 1.0]))])


def test_the_initial_gap_is_checked_against_the_run_tolerance():
    # 1e-10 m into the plane: refused at the default tol_gap = 1e-12 (of the 1 m coordinates),
    # accepted when the run allows 1e-9
    model = point_below_plane(1e-10)
    with pytest.raises(InputError, match="penetrates"):
        next(simulate(model, 1e-3, 1e-2))
    first = next(simulate(model, 1e-3, 1e-2, IntegratorOptions(tol_gap=1e-9)))
    assert first.t == 0.0


def two_blocks(margin=None):
    material = LinearElastic(E=1e6, nu=0.3, rho=1000.0)
    low = Solid.rectangle([0.0, 0.0], [1.0, 0.2], (5, 1), material)
    high = Solid.rectangle([0.0, 0.3], [1.0, 0.5], (5, 1), material)
    pair = NodeSurfaceContact(high, low, margin=margin)
    return Model([low, high], [pair], gravity=(0.0, 0.0)), pair


@pytest.mark.parametrize("detection_margin", [0.05, 0.2])
def test_node_to_surface_pairs_search_as_far_as_the_integrator_looks(detection_margin):
    model, pair = two_blocks()
    options = IntegratorOptions(detection_margin=detection_margin)
    next(simulate(model, 1e-3, 1e-2, options))
    assert pair.margin == pytest.approx(detection_margin * model.length)
    # the lower face 0.1 m above the other block: found at the wide margin (finite gaps),
    # beyond the narrow one (no facet: +inf)
    gaps = model.contacts.gaps(np.zeros(model.n))
    assert np.any(np.isfinite(gaps)) == (detection_margin * model.length >= 0.1)


def test_a_pair_keeps_the_margin_it_was_given():
    model, pair = two_blocks(margin=0.5)
    next(simulate(model, 1e-3, 1e-2))
    assert pair.margin == 0.5
