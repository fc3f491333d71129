"""Coulomb's law of a few planar contacts solved by its cases
(:mod:`fecontact.contact.friction_cases`): every answer holds the law, reads neither p nor
k, and is of no larger norm than any solution Newton reaches; the solid–Beam2D pair, whose
beam-node rows meet the solid's nodes, takes minimum-norm multipliers."""

import numpy as np
import pytest

from fecontact import Beam2D, Contact, Material, Model, Section
from fecontact.bodies import Solid
from fecontact.bodies.materials import LinearElastic
from fecontact.contact.coulomb_newton import NotConverged, newton
from fecontact.contact.friction import coulomb_residual
from fecontact.contact.friction_cases import planar_cases
from fecontact.contact.stats import CoulombStats

STEEL = Material(210e9, rho=7850.0)


def near_pairs(rng, m, tilt=0.2):
    """Rows (c, D) of m planar contacts in pairs holding nearly one motion: the second of
    a pair is the first's rows turned by ``tilt`` rad (a beam node's row on a solid's facet
    and the solid node's row on the beam), plus a little of the body's other dofs."""
    B = rng.normal(size=(2 * m, 2 * m + 1))
    turn = np.array([[np.cos(tilt), -np.sin(tilt)], [np.sin(tilt), np.cos(tilt)]])
    for j in range(1, m, 2):
        B[2 * j : 2 * j + 2] = turn @ B[2 * j - 2 : 2 * j] + 0.01 * B[2 * j : 2 * j + 2]
    c = rng.normal(size=2 * m)
    c[::2] = -np.abs(c[::2])  # (every contact pressed by the free motion)
    return c, B @ B.T


@pytest.mark.parametrize("seed", range(12))
def test_the_cases_hold_the_law_without_p_or_k_and_are_of_least_norm(seed):
    rng = np.random.default_rng(seed)
    m = 2 + seed % 3
    c, D = near_pairs(rng, m)
    mu = np.where(np.arange(m) == seed % m, 0.0, rng.uniform(0.2, 1.0, m))
    # (rates of order 1: an exact solution's error is round-off, 2e-15 at p = 1/D_ii and
    # weighed by p D_ii = 1000 up to 1.7e-12 at p × 1000, measured over these seeds)
    p, tol = 1.0 / np.diag(D), 1e-10
    x = planar_cases(c, D, p, 1.0, mu, tol)
    assert x is not None
    # the Alart–Curnier residual, zero where the law holds, at any p (a frictionless
    # contact slips freely: coulomb_violation reads its slip as one across its zero force)
    for scale_p in (1.0, 1e3):
        assert coulomb_residual(c + D @ x, x, scale_p * p, 1.0, mu, 1) <= tol
    # the same answer at p × 1000 and k ÷ 100 (k x is the force): the systems read
    # neither, and k's round-off, on Delassus matrices of condition up to 6e6 here, was
    # at most 2.5e-15 of |x| (seeds 3 and 10: Newton from zero does not converge)
    scale = np.linalg.norm(x)
    assert np.abs(planar_cases(c, D, 1e3 * p, 1.0, mu, tol) - x).max() < 1e-12 * scale
    assert np.abs(0.01 * planar_cases(c, D, p, 0.01, mu, tol) - x).max() < 1e-12 * scale
    # no solution Newton reaches from random starts is of lower norm (1e-9: round-off)
    for _ in range(8):
        try:
            y = newton(c, D, p, 1.0, mu, 1, rng.normal(size=2 * m), tol, 50, CoulombStats())[0]
        except NotConverged:
            continue
        assert np.linalg.norm(y) >= (1.0 - 1e-9) * scale


def test_more_contacts_than_the_cases_take_are_left_to_the_other_solves():
    c, D = near_pairs(np.random.default_rng(0), 5)
    assert planar_cases(c, D, 1.0 / np.diag(D), 1.0, np.full(5, 0.5), 1e-12) is None


def test_a_solid_on_a_strip_takes_minimum_norm_multipliers():
    # the beam-node rows (BeamNodeSurface) meet the solid's node rows where nodes meet
    strip = Beam2D.straight([-0.5, 0.0], [0.5, 0.0], 20, STEEL, Section.rectangle(0.02, 0.01))
    disk = Solid.disk([0.0, 0.0551], 0.05, 1, LinearElastic(1e7, 0.3, 1e3))
    pair = Contact(disk, strip, clearance=0.005, friction=1.0)
    model = Model([disk, strip], [pair], gravity=(0.0, 0.0))
    assert pair.companions[0].redundant_rows and model.contacts.redundant_rows
