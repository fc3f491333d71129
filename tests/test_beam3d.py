"""The spatial Simo–Reissner beam: sections, invariance, consistent force and tangent with
respect to the right rotation increments, Beam2D as its planar case, inertia, contact."""

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

from fecontact import (
    Beam2D,
    Beam3D,
    Contact,
    InputError,
    Material,
    Model,
    Plane,
    Section,
    Sphere,
    rotations,
    simulate,
    testing,
)
from fecontact.bodies.beam import rectangle_torsion
from fecontact.bodies.beam3d_complex_step import complex_step_internal
from fecontact.bodies.beam3d_kernels import rotation_matrices
from fecontact.statics import solve_static
from fecontact.statics_rotations import plus, solve_static_rotations

ALU = Material(70e9, nu=0.33, rho=2700.0)


def in_space(P):
    return np.column_stack([P, np.zeros(len(P))])


def bent_beam():
    """A polyline out of every coordinate plane, with a rectangle (distinct I₂, I₃)."""
    X = np.array([[0.0, 0.0, 0.0], [0.1, 0.02, 0.01], [0.2, 0.05, 0.04], [0.28, 0.1, 0.1]])
    return Beam3D(X, ALU, Section.rectangle(0.02, 0.004), orientation=[0.0, 0.3, 1.0])


def random_state(beam, seed, size=0.05):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=beam.ndof) * size
    return q


def right_increment(q, d):
    triples = np.arange(len(q)).reshape(-1, 6)[:, 3:]
    return plus(q, d, triples)


# -- sections -------------------------------------------------------------------------------
def test_rectangle_torsion_constant_matches_timoshenko_goodier_table():
    # J = k a b³ with k(a/b) from Timoshenko & Goodier's table (3 digits): 1 → 0.141,
    # 2 → 0.229, 10 → 0.312, and k → 1/3 as a/b → ∞
    for ratio, k in ((1.0, 0.141), (2.0, 0.229), (10.0, 0.312)):
        assert rectangle_torsion(ratio, 1.0) / ratio == pytest.approx(k, abs=6e-4)
    assert rectangle_torsion(1e4, 1.0) / 1e4 == pytest.approx(1 / 3, rel=1e-4)
    s = Section.rectangle(0.02, 0.004)
    assert s.inertia == pytest.approx(0.02 * 0.004**3 / 12)
    assert s.inertia_2 == pytest.approx(0.004 * 0.02**3 / 12)


def test_circle_section_has_equal_axes_and_the_polar_torsion_constant():
    s = Section.circle(0.01)
    assert s.inertia_2 == s.inertia
    assert s.torsion == pytest.approx(np.pi * 0.01**4 / 2, rel=1e-15)


# -- invariance -----------------------------------------------------------------------------
def rigid_motion(beam, q, Q, c):
    """The state q moved rigidly: x → Q x + c, R → Q R (Q a rotation of the frames too)."""
    n = beam.n_nodes
    Qn = q.reshape(n, 6)
    x = beam.positions(q) @ Q.T + c
    R = Q @ rotations.exp(Qn[:, 3:])
    out = np.zeros((n, 6))
    out[:, :3], out[:, 3:] = x - beam.X, rotations.log(R)
    return out.ravel()


def test_a_rigid_motion_strains_nothing():
    beam = bent_beam()
    Q = rotations.exp(np.array([0.7, -1.2, 2.1]))
    q = rigid_motion(beam, np.zeros(beam.ndof), Q, np.array([0.3, -0.1, 2.0]))
    Gam, Kap = beam.strains(q)
    W, f, _ = beam.internal(q)
    # round-off of O(1) rotation vectors and positions of 0.3 m: 1e-15 relative
    assert np.abs(Gam).max() < 1e-14 and np.abs(Kap).max() < 1e-13
    # strains of round-off (< 1e-13): W = ½ ℓ Γ·CΓ below ½ EA L (1e-13)²
    assert abs(W) < 0.5 * ALU.E * beam.section.area * beam.length * 1e-26
    assert np.abs(f).max() < 1e-13 * ALU.E * beam.section.area


def test_strains_are_objective():
    beam = bent_beam()
    q = random_state(beam, 1, 0.2)
    Q = rotations.exp(np.array([-2.0, 0.4, 1.1]))
    moved = rigid_motion(beam, q, Q, np.array([1.0, 2.0, 3.0]))
    for a, b in zip(beam.strains(q), beam.strains(moved), strict=True):
        np.testing.assert_allclose(b, a, atol=1e-13)


# -- force and tangent ----------------------------------------------------------------------
def test_force_is_the_derivative_of_the_energy_along_right_increments():
    beam = bent_beam()
    q = random_state(beam, 2, 0.1)
    _, f, _ = beam.internal(q, tangent=False)
    h = 1e-7  # central differences: error O(h²) plus round-off W·1e-16/h, both ~1e-7 of |f|
    fd = [
        (beam.energy(right_increment(q, h * e)) - beam.energy(right_increment(q, -h * e))) / (2 * h)
        for e in np.eye(beam.ndof)
    ]
    np.testing.assert_allclose(fd, f, rtol=0, atol=1e-6 * np.abs(f).max())


def test_tangent_is_the_derivative_of_the_force_along_right_increments():
    beam = bent_beam()
    q = random_state(beam, 3, 0.3)
    _, f, Ke = beam.internal(q)
    K = np.zeros((beam.ndof, beam.ndof))
    for dofs, k in zip(beam.element_dofs, Ke, strict=True):
        K[np.ix_(dofs, dofs)] += k
    h = 1e-6  # central differences of the force: O(h²) ~ 1e-12 relative, round-off |f|1e-16/h
    fd = np.column_stack(
        [
            (beam.internal(right_increment(q, h * e), False)[1]
             - beam.internal(right_increment(q, -h * e), False)[1]) / (2 * h)
            for e in np.eye(beam.ndof)
        ]
    )  # fmt: skip
    np.testing.assert_allclose(K, fd, rtol=0, atol=1e-7 * np.abs(K).max())


@pytest.mark.parametrize("size", [0.0, 1e-4, 0.05, 0.3, 1.0])
def test_analytic_tangent_is_the_complex_step_one(size):
    # states from straight to elements turned by about a radian, through the series and the
    # closed forms of the rotation coefficients and of their slopes
    beam = bent_beam()
    el = beam.elements
    q = random_state(beam, 3, size)
    f_cs, W_cs, K_cs = complex_step_internal(el, beam.X, q)
    W, f, K = beam.internal(q)
    # both exact to round-off: 1e-10 leaves room for the conditioning of log and T⁻¹ at θ ~ 1
    np.testing.assert_allclose(K, K_cs, rtol=0, atol=1e-10 * np.abs(K_cs).max())
    f_ref = np.bincount(el.dofs.ravel(), f_cs.ravel(), minlength=beam.ndof)
    # at rest both forces are round-off: strains of ~1e-16 times the rigidities
    round_off = 1e-15 * el.C.max()
    np.testing.assert_allclose(f, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max() + round_off)
    assert W == pytest.approx(W_cs.sum(), rel=1e-12, abs=1e-20)


def test_the_kernels_rotation_matrices_are_the_exponential():
    # angles from 0 through 1e-12 (series regime of rotations.exp) to 2.5 rad
    psi = np.random.default_rng(1).normal(size=(60, 3)) * np.logspace(-12, 0.4, 60)[:, None]
    psi[0] = 0.0
    # two formulas for entries ≤ 1, each with round-off of a few ulps at θ ~ 1
    np.testing.assert_allclose(rotation_matrices(psi), rotations.exp(psi), rtol=0, atol=5e-15)


# -- the plane ------------------------------------------------------------------------------
def planar_pair():
    P = np.array([[0.0, 0.0], [0.3, 0.0], [0.5, 0.2]])
    section = Section.rectangle(0.02, 0.002)
    b2 = Beam2D.polyline(P, [3, 2], ALU, section)
    return b2, Beam3D(in_space(b2.X), ALU, section)


IN_PLANE = [0, 1, 5]  # x, y and the rotation about z of a Beam3D node


def lift(q2, n):
    q3 = np.zeros((n, 6))
    q3[:, IN_PLANE] = q2.reshape(n, 3)
    return q3.ravel()


def test_in_plane_the_beam_is_beam2d():
    b2, b3 = planar_pair()
    q2 = random_state(b2, 4, 0.05)
    q3 = lift(q2, b3.n_nodes)
    W2, f2, K2 = b2.internal(q2)
    W3, f3, K3 = b3.internal(q3)
    # the same formulas evaluated in another order: round-off
    assert W3 == pytest.approx(W2, rel=1e-13)
    F3 = f3.reshape(-1, 6)
    np.testing.assert_allclose(F3[:, IN_PLANE].ravel(), f2, atol=1e-13 * np.abs(f2).max())
    assert np.abs(F3[:, 2:5]).max() == 0.0
    idx = [0, 1, 5, 6, 7, 11]
    np.testing.assert_allclose(K3[:, idx][:, :, idx], K2, atol=1e-13 * np.abs(K2).max())
    ii = (6 * np.arange(b3.n_nodes)[:, None] + np.array(IN_PLANE)).ravel()
    M2, M3 = b2.mass_matrix().toarray(), b3.mass_matrix().toarray()
    np.testing.assert_allclose(M3[np.ix_(ii, ii)], M2, atol=1e-14 * np.abs(M2).max())


def test_in_plane_static_tip_deflection_is_beam2d():
    section = Section.rectangle(0.02, 0.002)
    b2 = Beam2D.straight([0, 0], [0.3, 0], 6, ALU, section).clamp(0)
    b3 = Beam3D.straight([0, 0, 0], [0.3, 0, 0], 6, ALU, section).clamp(0)
    m2, m3 = Model([b2]), Model([b3])
    load2, load3 = np.zeros(m2.n), np.zeros(m3.n)
    load2[-2], load3[-5] = -20.0, -20.0  # a tip force along −y: large deflection
    q2 = solve_static(m2, load2, steps=5)
    q3 = solve_static_rotations(m3, load3, steps=5).q
    tip2, tip3 = b2.positions(q2)[-1], b3.positions(q3)[-1]
    assert tip2[1] < -0.05  # far from linear
    np.testing.assert_allclose(tip3[:2], tip2, rtol=0, atol=1e-10)
    assert tip3[2] == 0.0


# -- inertia --------------------------------------------------------------------------------
def test_mass_matrix_carries_mass_and_rotary_inertia():
    beam = bent_beam().add_mass(-1, 0.1, inertia=2e-5)
    M = beam.mass_matrix()
    for e in np.eye(3):
        t = beam.translation_field(e)
        assert t @ (M @ t) == pytest.approx(beam.mass, rel=1e-14)
    # about the tangent of a straight beam: ρ(I₂ + I₃) L, polar moment of the section
    s = Section.rectangle(0.02, 0.004)
    straight = Beam3D.straight([0, 0, 0], [0.0, 0.0, 0.5], 4, ALU, s)
    r = np.zeros((straight.n_nodes, 6))
    r[:, 5] = 1.0
    spin = r.ravel()
    expected = ALU.rho * (s.inertia + s.inertia_2) * 0.5
    assert spin @ (straight.mass_matrix() @ spin) == pytest.approx(expected, rel=1e-14)


def test_a_given_rotary_inertia_replaces_the_sections():
    beam = Beam3D.straight([0, 0, 0], [2.0, 0, 0], 4, ALU, Section.circle(0.01),
                           rotary_inertia=(20.0, 10.0, 10.0))  # fmt: skip
    spin = np.zeros((beam.n_nodes, 6))
    spin[:, 3] = 1.0  # about the axis: J₁ L
    assert spin.ravel() @ (beam.mass_matrix() @ spin.ravel()) == pytest.approx(40.0, rel=1e-14)


@pytest.mark.parametrize("n", [3, 24])  # a dense tangent (18 dofs), a sparse one (150)
def test_gyroscopic_force_and_its_tangent(n):
    X = np.column_stack([np.linspace(0, 0.3, n + 1), 0.1 * np.sin(np.linspace(0, 2, n + 1)),
                         np.linspace(0, 0.1, n + 1) ** 2])  # fmt: skip
    beam = Beam3D(X, ALU, Section.rectangle(0.02, 0.004), orientation=[0.0, 0.3, 1.0])
    beam.add_mass(-1, 0.1, inertia=np.diag([1e-5, 2e-5, 4e-5]))
    v = random_state(beam, 5, 10.0)
    f, C = beam.inertial(np.zeros(beam.ndof), v)
    C = C.toarray() if sp.issparse(C) else C
    # the gyroscopic force of the consistent mass: Ω_a × (M Ω)_a, M's rotation rows alone
    spin = v.copy()
    spin.reshape(-1, 6)[:, :3] = 0.0
    Om, pi = spin.reshape(-1, 6)[:, 3:], (beam.mass_matrix() @ spin).reshape(-1, 6)[:, 3:]
    np.testing.assert_allclose(f.reshape(-1, 6)[:, 3:], np.cross(Om, pi), rtol=1e-13, atol=0)
    assert np.abs(f.reshape(-1, 6)[:, :3]).max() == 0.0
    # it does no work: Ω_a · (Ω_a × π_a) = 0 but for the round-off of the products
    assert abs(f @ v) <= 1e-14 * Om.size * np.abs(Om).max() ** 2 * np.abs(pi).max()
    h = 1e-6  # f is quadratic in v: central differences exact but for round-off
    fd = np.column_stack(
        [
            (beam.inertial(0, v + h * e)[0] - beam.inertial(0, v - h * e)[0]) / (2 * h)
            for e in np.eye(beam.ndof)
        ]
    )
    np.testing.assert_allclose(C, fd, atol=1e-8 * np.abs(fd).max())


def free_flight_momentum_drift(h: float) -> float:
    """Largest relative change of the angular momentum Σ x × p + Σ R π (about the origin, of
    the mass matrix) of a free, flexible Beam3D tumbling and twisting unevenly over 20 ms
    at the step ``h`` (s). Its rotary inertia is made large (ρA L²/25 per length) so that
    the nodes' angular velocities, which differ, carry much of the momentum."""
    material, section = Material(2e9, nu=0.3, rho=1000.0), Section.rectangle(0.02, 0.01)
    J = (2e-3, 1e-3, 1e-3)  # kg·m
    beam = Beam3D.straight([0, 0, 0], [0.5, 0, 0], 6, material, section, rotary_inertia=J)
    model = Model([beam], [], gravity=(0.0, 0.0, 0.0))
    s = np.linspace(-1.0, 1.0, beam.n_nodes)
    omega = np.array([3.0, 40.0, 25.0])
    v0 = np.zeros((beam.n_nodes, 6))
    v0[:, :3] = np.cross(omega, beam.X - beam.X.mean(axis=0)) + np.outer(2.0 * s**2, [0, 0, 1])
    v0[:, 3:] = omega + np.outer(200.0 * s**2, [1, 0, 0])  # twist rates that differ
    M = model.M_full

    def momentum(st):
        p = (M @ st.v).reshape(-1, 6)
        R = rotations.exp(st.q.reshape(-1, 6)[:, 3:])
        spin = np.einsum("nij,nj->ni", R, p[:, 3:])
        return (np.cross(beam.positions(st.q), p[:, :3]) + spin).sum(axis=0)

    L = np.array([momentum(st) for st in simulate(model, h, 0.02, v0=v0.ravel())])
    return float(np.abs(L - L[0]).max() / np.linalg.norm(L[0]))


def test_a_free_spinning_beam_keeps_its_angular_momentum_to_second_order():
    # the gyroscopic force of the consistent rotary mass: the semi-discrete equations keep
    # the momentum exactly, the step loses it at order 2 (measured 4.3e-4, 1.1e-4, 2.8e-5;
    # the lumped gyroscopic term with the same mass kept 4.8e-3 at every step)
    drift = [free_flight_momentum_drift(h) for h in (4e-4, 2e-4, 1e-4)]
    orders = np.log2(np.array(drift[:-1]) / drift[1:])
    assert np.all(orders > 1.8), (drift, orders)
    assert drift[-1] < 5e-5


def test_rigid_modes_are_free_of_strain_to_first_order():
    beam = bent_beam()
    _, _, Ke = beam.internal(np.zeros(beam.ndof))
    K = np.zeros((beam.ndof, beam.ndof))
    for dofs, k in zip(beam.element_dofs, Ke, strict=True):
        K[np.ix_(dofs, dofs)] += k
    modes = beam.rigid_modes()
    assert modes.shape == (beam.ndof, 6)
    assert np.abs(K @ modes).max() < 1e-9 * np.abs(K).max()


# -- supports, contact, output, input -------------------------------------------------------
def test_supports_and_rotation_dofs():
    beam = Beam3D.straight([0, 0, 0], [1, 0, 0], 2, ALU, Section.circle(0.01))
    beam.clamp(0).pin(-1).fix(1, "rz")
    assert beam.fixed == {0, 1, 2, 3, 4, 5, 12, 13, 14, 11}
    np.testing.assert_array_equal(beam.rotation_triples, [[3, 4, 5], [9, 10, 11], [15, 16, 17]])
    with pytest.raises(InputError, match="components"):
        beam.fix(0, "theta")


def test_nodes_touch_a_plane_and_a_sphere_in_space_with_the_section_radius():
    beam = Beam3D.straight([0, 0, 0.1], [1, 0, 0.2], 4, ALU, Section.circle(0.01))
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    ball = Sphere([0.5, 0.0, 0.5], 0.3)
    pairs = [Contact(beam, floor, clearance=0.01), Contact(beam, ball, nodes=[2], clearance=0.01)]
    model = Model([beam], pairs, gravity=(0.0, 0.0, -9.81))
    g = model.contacts.gaps(np.zeros(model.n))
    np.testing.assert_allclose(g[:5], beam.X[:, 2] - 0.01, atol=1e-15)
    assert g[5] == pytest.approx(np.linalg.norm(beam.X[2] - ball.center) - 0.3 - 0.01)


def test_output_gives_the_section_frames():
    beam = Beam3D.straight([0, 0, 0], [1, 0, 0], 2, ALU, Section.rectangle(0.02, 0.004))
    q = np.zeros(beam.ndof)
    q[-3:] = [np.pi / 2, 0.0, 0.0]  # the tip section turned a quarter about the axis
    data = beam.point_data(q, np.zeros(beam.ndof))
    np.testing.assert_allclose(data["axis_2"][0], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(data["axis_2"][-1], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(data["axis_3"][-1], [0, -1, 0], atol=1e-15)
    assert beam.cells()[0][0] == "line"


def test_the_additive_static_solve_refuses_rotations_in_space():
    beam = Beam3D.straight([0, 0, 0], [1, 0, 0], 2, ALU, Section.circle(0.01)).clamp(0)
    model = Model([beam])
    with pytest.raises(InputError, match="solve_static_rotations"):
        solve_static(model, np.ones(model.n))


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: Beam3D([[0, 0], [1, 0]], ALU, Section.circle(0.01)), "nodes"),
        (lambda: Beam3D([[0, 0, 0], [0, 0, 0]], ALU, Section.circle(0.01)), "zero length"),
        (
            lambda: Beam3D.straight([0, 0, 0], [1, 0, 0], 2, ALU, Section.circle(0.01), [2, 0, 0]),
            "orientation",
        ),
        (
            lambda: Beam3D.straight([0, 0, 0], [1, 0, 0], 2, ALU, Section.circle(0.01)).add_mass(
                0, 1.0, inertia=-1.0
            ),
            "inertia",
        ),
        (lambda: Section(1.0, 1.0, inertia_2=-1.0), "inertia_2"),
        (
            lambda: Beam3D(
                [[0, 0, 0], [1, 0, 0]], ALU, Section.circle(0.01), rotary_inertia=(1.0, -1.0, 1.0)
            ),
            "rotary_inertia",
        ),
    ],
)
def test_bad_input_is_named(build, match):
    with pytest.raises(InputError, match=match):
        build()


# -- statics: classical benchmarks ----------------------------------------------------------
def roll_up(n, fraction):
    """Simo's roll-up (:func:`fecontact.testing.roll_up`), solved without a halved increment."""
    tip, sol = testing.roll_up(n, fraction)
    assert sol.cuts == 0
    return tip


def test_roll_up_closes_the_circle():
    # equal chords turning by 2π in all close the polygon: the tip is back at the root
    for n in (10, 20):
        assert np.linalg.norm(roll_up(n, 1.0)) < 1e-6


def test_roll_up_half_circle_converges_at_order_two():
    errors = [np.linalg.norm(roll_up(n, 0.5) - [0.0, 2.0 / np.pi, 0.0]) for n in (10, 20)]
    # the chord of an arc of angle φ is shorter by φ²/24: the error falls 4× per halving
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.01)
    assert errors[1] < 1e-3


def test_bathe_bolourchi_bend_tip_within_one_percent_of_simo_vu_quoc():
    material = Material(1e7, nu=0.0, rho=1.0)
    section = Section(area=1.0, inertia=1 / 12, inertia_2=1 / 12, torsion=1 / 6, shear_factor=1)
    t = np.linspace(0.0, np.pi / 4, 9)
    nodes = np.column_stack([100 * np.sin(t), 100 * (1 - np.cos(t)), np.zeros_like(t)])
    beam = Beam3D(nodes, material, section).clamp(0)
    model = Model([beam])
    load = np.zeros(model.n)
    load[-4] = 600.0
    sol = solve_static_rotations(model, load, steps=10)
    tip = beam.positions(sol.q)[-1]
    np.testing.assert_allclose(tip, [47.23, 15.79, 53.37], rtol=0.01)


# -- small vibrations: stiffness and mass together ------------------------------------------
def test_cantilever_frequencies_in_bending_about_both_axes_and_in_torsion():
    section = Section.rectangle(0.02, 0.004)
    L, n = 0.5, 40
    beam = Beam3D.straight([0, 0, 0], [L, 0, 0], n, ALU, section).clamp(0)
    F = Model([beam]).free
    _, _, Ke = beam.internal(np.zeros(beam.ndof))
    K = np.zeros((beam.ndof, beam.ndof))
    for dofs, k in zip(beam.element_dofs, Ke, strict=True):
        K[np.ix_(dofs, dofs)] += k
    M = beam.mass_matrix().toarray()
    lam, V = scipy.linalg.eigh(K[np.ix_(F, F)], M[np.ix_(F, F)])
    omega = np.sqrt(lam)
    modes = np.zeros((beam.ndof, len(F)))
    modes[F] = V

    def share(component):  # the part of each mode's kinetic energy in one dof kind
        d = slice(component, None, 6)
        return np.einsum("im,ij,jm->m", modes[d], M[d, d], modes[d])

    rhoA = ALU.rho * section.area
    first = 1.8751040687**2 / L**2  # Euler–Bernoulli cantilever: ω = β₁² √(EI/ρA)
    in_plane = omega[np.argmax(share(1) > 0.5)]
    out_of_plane = omega[np.argmax(share(2) > 0.5)]
    torsion = omega[np.argmax(share(3) > 0.5)]
    # in-plane (thickness 4 mm): shear and rotary inertia (t/L)² ~ 1e-4, the mesh (h/L)² ~ 1e-4
    assert in_plane == pytest.approx(first * np.sqrt(ALU.E * section.inertia / rhoA), rel=3e-4)
    # about axis 2 (width 20 mm): Timoshenko's correction ~ (width/L)² ~ 2e-3
    assert out_of_plane == pytest.approx(
        first * np.sqrt(ALU.E * section.inertia_2 / rhoA), rel=3e-3
    )
    # torsion (no warping): ω = (π/2L) √(GJ/ρI_p), I_p = I₂ + I₃
    Ip = section.inertia + section.inertia_2
    expected = np.pi / (2 * L) * np.sqrt(ALU.G * section.torsion / (ALU.rho * Ip))
    assert torsion == pytest.approx(expected, rel=1e-3)
