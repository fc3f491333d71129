"""Coulomb friction at a beam's closing: the frictional smooth step's law where its
Delassus block is not positive, and the spatial pendulum with friction through its first
impact episode."""

import numpy as np
import pytest
from conftest import load_case

from fecontact.contact.friction import solve_coulomb
from fecontact.testing import trace


def test_a_lone_contact_whose_law_has_no_answer_fails_after_one_sweep():
    # the rows of the spatial pendulum's tip at a diverging smooth iterate (t = 0.321 s,
    # μ = 1): S_t there is indefinite and so is D = A S_t⁻¹Aᵀ (D_NN < 0). Newton fails and
    # so does the one contact's exact law; a Gauss–Seidel sweep over that one contact only
    # repeats it (2000 sweeps of it stalled the run), so the solve gives up after one and
    # the step is halved
    c = np.array([-0.05679398, 0.01671032, 0.0])
    D = np.array(
        [
            [-3.93968126e-05, 1.22271944e-05, 0.0],
            [1.22271944e-05, -3.41993770e-06, 0.0],
            [0.0, 0.0, 2.01222366e-06],
        ]
    )
    p = 1.0 / np.abs(np.diag(D))
    with pytest.raises(RuntimeError, match=r"after 1 Gauss-Seidel sweeps"):
        solve_coulomb(c, D, p, 1.0, np.array([1.0]), 2, None, 3e-14)


def test_the_spatial_pendulum_with_friction_passes_its_first_impact_episode():
    # strike at 0.3186 s, the frictional smooth step's halvings at 0.321-0.322 s; the
    # planar twin's tip to 1e-6 m, the bound asked of the twin (measured 6e-10 m over 1.5 s)
    flat = trace(load_case("flexible_pendulum").build(friction=1.0), t_end=0.33)
    space = trace(load_case("spatial_pendulum").build(friction=1.0), t_end=0.33)
    assert space["status"] == flat["status"] == "completed"
    assert space["impulse"].max() > 0.0
    for q in ("tip_x", "tip_y"):
        np.testing.assert_allclose(space[q], flat[q], rtol=0, atol=1e-6)
    # the slip disk's two tangent rows are solved together: z moves by round-off only
    # (measured 4e-20 m here, 2e-18 m over 1.5 s)
    assert np.abs(space["tip_z"]).max() <= 1e-15
