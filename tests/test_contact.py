"""Contact geometry (gaps and their derivatives) and the Alart–Curnier laws."""

import numpy as np
import pytest

from fecontact import Beam2D, Circle, Contact, InputError, Material, Model, Plane, Point, Section
from fecontact.contact import (
    alart_curnier_residual,
    contact_force_multiplier,
    solve_position_correction,
    solve_velocity_jump,
)
from fecontact.testing import gap_derivatives_error

MATERIAL = Material(E=70e9, nu=0.33, rho=2700.0)
SECTION = Section.rectangle(0.02, 0.002)


def fd_check(pair, q):
    """G and ∇²g of every contact of ``pair`` against central differences: O(eps²) truncation
    and O(1e-16/eps) round-off at eps = 1e-7 stay below these bounds."""
    err_g, err_h = gap_derivatives_error(pair, q)
    assert err_g < 1e-7 and err_h < 1e-6
    return pair.evaluate(q)[0]


def beam_model(obstacle, nodes=None, seed=0):
    beam = Beam2D.polyline([[0, 0], [0.3, 0.1], [0.5, -0.1]], [2, 2], MATERIAL, SECTION)
    pair = Contact(beam, obstacle, nodes=nodes)
    model = Model([beam], [pair])
    rng = np.random.default_rng(seed)
    q = 0.03 * rng.normal(size=model.n)
    return pair, q


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_plane_gap_gradient(seed):
    pair, q = beam_model(Plane([0.1, -0.5], [0.3, 1.0]), seed=seed)
    g = fd_check(pair, q)
    x = pair.body.positions(q)
    n = np.array([0.3, 1.0]) / np.hypot(0.3, 1.0)
    assert np.allclose(g, (x - [0.1, -0.5]) @ n)


@pytest.mark.parametrize("inside", [False, True])
@pytest.mark.parametrize("seed", [0, 1])
def test_circle_gap_gradient_and_curvature(inside, seed):
    center, radius = np.array([0.2, 0.9]), 0.5 if not inside else 1.5
    # the nodes named: from outside, a Circle otherwise acts on the segments
    pair, q = beam_model(Circle(center, radius, inside=inside), nodes=range(5), seed=seed)
    g = fd_check(pair, q)
    r = np.linalg.norm(pair.body.positions(q) - center, axis=1)
    assert np.allclose(g, (radius - r) if inside else (r - radius))


@pytest.mark.parametrize("position", [[0.22, 0.2], [0.41, 0.15], [0.35, -0.25]])
@pytest.mark.parametrize("seed", [0, 1])
def test_point_against_beam_segments(position, seed):
    """Interior projections: signed distance to the segment line and its exact Hessian."""
    pair, q = beam_model(Point(position, radius=0.01), seed=seed)
    g = fd_check(pair, q)
    x = pair.body.positions(q)
    P = np.asarray(position)

    def segment_distance(a, b):
        s = np.clip((P - a) @ (b - a) / ((b - a) @ (b - a)), 0, 1)
        return np.linalg.norm(P - a - s * (b - a))

    d = min(segment_distance(a, b) for a, b in zip(x[:-1], x[1:], strict=True))
    assert abs(g[0] + 0.01) == pytest.approx(d, abs=1e-12)


def test_point_beyond_the_beam_end_uses_the_end_node():
    pair, q = beam_model(Point([0.7, -0.2], radius=0.0), seed=3)
    g = fd_check(pair, q)
    tip = pair.body.positions(q)[-1]
    assert g[0] == pytest.approx(np.linalg.norm(tip - [0.7, -0.2]))


def test_contact_input_is_validated():
    beam = Beam2D.straight([0, 0], [1, 0], 2, MATERIAL, SECTION)
    with pytest.raises(InputError, match="restitution"):
        Contact(beam, Plane([0, -1], [0, 1]), restitution=1.5)
    with pytest.raises(InputError, match="restitution"):
        Contact(beam, Plane([0, -1], [0, 1]), restitution=-0.1)
    with pytest.raises(InputError, match="normal"):
        Plane([0, 0], [0, 0])
    with pytest.raises(InputError, match="radius"):
        Circle([0, 0], -1.0)
    with pytest.raises(InputError, match="node"):
        Contact(beam, Plane([0, -1], [0, 1]), nodes=[7])


# -- Alart–Curnier ------------------------------------------------------------------------------

CASES = [  # (nu, g, satisfies 0 <= g ⊥ nu >= 0)
    (0.0, 0.3, True),  # open, no force
    (2.0, 0.0, True),  # closed with force
    (0.0, 0.0, True),  # touching, no force
    (1.0, 0.2, False),  # force at a distance
    (0.0, -0.1, False),  # penetration
    (-1.0, 0.0, False),  # adhesive force
]


@pytest.mark.parametrize("nu, g, ok", CASES)
@pytest.mark.parametrize("p, k", [(1.0, 1.0), (1e-3, 10.0), (1e4, 0.01)])
def test_alart_curnier_residual_is_zero_exactly_at_complementarity(nu, g, ok, p, k):
    r = alart_curnier_residual(nu, g, p, k)
    assert (r == 0.0) == ok
    if ok:
        assert contact_force_multiplier(nu, g, p, k) == pytest.approx(k * nu)


def test_position_correction_on_two_masses_against_a_wall():
    """Two unit masses on a line, coupled by a spring; the first penetrates a wall at x = 0
    by 0.1. With metric H = diag(1, 1) + spring the corrected state is known in closed form."""
    kspring = 3.0
    H = np.array([[1.0 + kspring, -kspring], [-kspring, 1.0 + kspring]])
    x_tilde = np.array([-0.1, 0.5])

    def gaps(U):
        return (x_tilde + U)[:1].copy(), np.array([[1.0, 0.0]])

    solve = lambda b: np.linalg.solve(H, b)  # noqa: E731
    for p, k in [(1.0, 1.0), (1e-6, 1.0), (1e6, 1e-3)]:
        U, nu, its = solve_position_correction(
            gaps, lambda U, s, A: (solve, None), 2, np.array([p]), k, 1e-14, 1e-14
        )
        assert U[0] == pytest.approx(0.1, abs=1e-15)
        # H U = Gᵀ (k ν): the second mass follows through the spring metric
        assert np.allclose(H @ U, [k * nu[0], 0.0], atol=1e-14)
        assert nu[0] > 0 and its <= 3


def test_position_correction_leaves_separated_contacts_alone():
    x_tilde = np.array([0.2])
    U, nu, _ = solve_position_correction(
        lambda U: ((x_tilde + U).copy(), np.eye(1)),
        lambda U, s, A: ((lambda b: b), None),
        1,
        np.ones(1),
        1.0,
        1e-14,
        1e-14,
    )
    assert U[0] == 0.0 and nu[0] == 0.0


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_velocity_jump_applies_newtons_impact_law(e):
    """A unit mass hits a wall at 2 m/s: after the jump v⁺ = −e v⁻, impulse (1 + e)·2."""
    v_minus = -2.0
    G = np.array([[1.0]])
    c = np.array([v_minus + e * v_minus])
    for p, k in [(1.0, 1.0), (1e-5, 1e3)]:
        W, Lam, its = solve_velocity_jump(G, c, lambda b: b, np.array([p]), k)
        assert v_minus + W[0] == pytest.approx(-e * v_minus, abs=1e-14)
        assert k * Lam[0] == pytest.approx((1 + e) * 2.0)


def test_velocity_jump_ignores_separating_contacts():
    W, Lam, _ = solve_velocity_jump(np.eye(1), np.array([0.5]), lambda b: b, np.ones(1), 1.0)
    assert W[0] == 0.0 and Lam[0] == 0.0


def _ledge(U):
    """Two rows over two dofs: one 1 mm inside along the second dof, and one 2 mm inside
    along the first that has no gap (+inf, zero gradient) once the first dof passes 1 mm, as
    a box edge's row whose common normal leaves the ridge's cone. The iterates met are kept
    in ``_ledge.met``."""
    _ledge.met.append(U.copy())
    defined = U[0] < 1e-3
    g = np.array([U[1] - 1e-3, U[0] - 2e-3 if defined else np.inf])
    return g, np.array([[0.0, 1.0], [1.0 if defined else 0.0, 0.0]])


def test_a_held_row_whose_gap_becomes_undefined_holds_nothing():
    """The second row held (an equality: pressed by the smooth step's force): its update
    takes the first dof to 2 mm, where the row has no gap. It then leaves the equalities
    (it held them, and its +inf made the multipliers, the update and the next iterates
    NaN); without it the first dof returns to 0, where the row holds again: the set
    cycles, and the correction fails, as a step's failure to be halved, with every iterate
    finite."""
    import warnings

    _ledge.met = []
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(RuntimeError, match="did not settle"):
            solve_position_correction(
                _ledge, lambda U, s, A: ((lambda B: B), None), 2, np.ones(2), 1.0, 1e-9,
                1e-10, bilateral=np.array([False, True]),
            )  # fmt: skip
    assert np.all(np.isfinite(_ledge.met))


def test_a_gap_that_is_not_a_number_fails_the_correction():
    """A NaN gap is no iterate to go on from: the correction raises (the step fails, and
    is halved and counted) instead of carrying it into the multipliers."""

    def gaps(U):
        return np.array([np.nan]), np.ones((1, 1))

    with pytest.raises(RuntimeError, match="non-finite"):
        solve_position_correction(
            gaps, lambda U, s, A: ((lambda B: B), None), 1, 1.0, 1.0, 1e-9, 1e-10
        )


@pytest.mark.parametrize(
    "g, G",
    [
        ([-np.inf, 1.0], [[1.0, 0.0], [0.0, 1.0]]),
        ([-1e-3, np.nan], [[1.0, 0.0], [0.0, 1.0]]),
        ([-1e-3, 1.0], [[1.0, 0.0], [0.0, np.nan]]),
        ([-1e-3, 1.0], [[1.0, np.inf], [0.0, 1.0]]),
    ],
)
def test_a_gap_or_gradient_not_finite_anywhere_fails_the_correction(g, G):
    """Any NaN or −inf among the gaps, or any non-finite entry of the gradient, in any row
    (each array is checked by one reduction: a NaN or inf poisons its sum or its least
    value), fails the correction."""
    with pytest.raises(RuntimeError, match="non-finite gap or gradient"):
        solve_position_correction(
            lambda U: (np.array(g), np.array(G)),
            lambda U, s, A: ((lambda B: B), None), 2, np.ones(2), 1.0, 1e-9, 1e-10,
        )  # fmt: skip


def test_a_non_finite_update_fails_the_correction():
    """An update that is not a number (a solve gone NaN) is no iterate to go on from: the
    correction raises before the gaps are evaluated there. Rows without a gap (+inf, zero
    gradient) are no failure."""
    met = []

    def gaps(U):
        met.append(U.copy())
        return np.array([-1e-3, np.inf]), np.array([[1.0, 0.0], [0.0, 0.0]])

    with pytest.raises(RuntimeError, match="non-finite update"):
        solve_position_correction(
            gaps, lambda U, s, A: ((lambda B: np.full(B.shape, np.nan)), None), 2, np.ones(2),
            1.0, 1e-9, 1e-10,
        )  # fmt: skip
    assert len(met) == 1 and np.all(met[0] == 0.0)  # (the first iterate only)


def test_a_jump_that_did_not_settle_says_its_law_residual():
    """Both rows taken active first: Λ = (G Gᵀ)⁻¹(−c) = (23.5, −22.5) N·s, so the second
    row pulls, |kΛ₂ − [kΛ₂ − p ġ₂]_+| = 22.5 N·s, and one iteration cannot mend it."""
    G, c = np.array([[1.0, 0.0], [1.0, 0.2]]), np.array([-1.0, -0.1])
    with pytest.raises(RuntimeError, match=r"in 1 iterations \(law residual 2\.250e\+01 N·s\)"):
        solve_velocity_jump(G, c, lambda b: b, 1.0, 1.0, max_iter=1)
    W, Lam, _ = solve_velocity_jump(G, c, lambda b: b, 1.0, 1.0, max_iter=3)
    # row 1 alone: Λ₁ = −c₁ / (G₁ G₁ᵀ) = 1 / 1, exact in floating point on any machine
    np.testing.assert_allclose(Lam, [1.0, 0.0], atol=1e-15)
