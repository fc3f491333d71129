"""Dual multipliers of quadratic faces (the basis transformation of Popp, Wohlmuth, Gee & Wall
2012, ``fecontact.contact.mortar_p2``) and mortar contact on the quadratic faces of P2 solids:
the patch test, exact derivatives on curved faces, Newton's quadratic rate, p/k independence
and friction."""

import dataclasses

import numpy as np
import pytest
from conftest import load_case

from fecontact import simulate
from fecontact.bodies import Solid
from fecontact.contact import Contact
from fecontact.contact.mortar3d_p2 import MortarContact3DP2, quadratic_triangles
from fecontact.contact.mortar_p2 import (
    dual_coefficients,
    reference_rule,
    shape_functions,
    transformation,
)
from fecontact.contact.mortar_p2_segments import MortarContactP2, quadratic_segments
from fecontact.contact.mortar_p2_triangles import p2_triangle_integrals
from fecontact.errors import InputError
from fecontact.model import Model
from fecontact.scenes import solid_material, wave_step
from fecontact.statics import solve_static_contact
from fecontact.testing import (
    gap_derivatives_error,
    pressed_p2_blocks,
    pressed_p2_boxes,
)

KINDS = ("segment", "triangle")
# a face of varying measure density (a curved face): J ∝ 1 + 0.3 ξ, 1 + 0.3 λ₂ − 0.2 λ₃
CURVED = {
    "segment": lambda p: 1.0 + 0.3 * p,
    "triangle": lambda p: 1.0 + 0.3 * p[:, 0] - 0.2 * p[:, 1],
}


def integrals(kind, jac=None):
    """Φ (m, n), Ñ (m, n), N (m, n) at the rule's points and their weights (m,)."""
    points, w = reference_rule(kind)
    if jac is not None:
        jac = jac(points)
        w = w * jac
    A, T = dual_coefficients(kind, jacobian=jac)
    N = shape_functions(kind, points)
    Nt = N @ T.T
    return Nt @ A.T, Nt, N, w


def test_corner_functions_of_the_quadratic_triangle_integrate_to_zero():
    """Why the transformation: without it (α = 0) the triangle's corners carry no weight."""
    points, w = reference_rule("triangle")
    D = shape_functions("triangle", points).T @ w
    # the exact values: 0 at the corners, 1/3 of the area at the edge nodes (round-off)
    assert np.allclose(D, [0, 0, 0, 1 / 3, 1 / 3, 1 / 3], rtol=0, atol=1e-15)
    with pytest.raises(InputError, match="integrates to"):
        dual_coefficients("triangle", alpha=0.0)


@pytest.mark.parametrize("kind", KINDS)
def test_transformed_basis_integrates_positively_and_sums_to_one(kind):
    points, w = reference_rule(kind)
    Nt = shape_functions(kind, points) @ transformation(kind).T
    assert np.allclose(Nt.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    expected = {"segment": [1 / 6, 1 / 6, 2 / 3], "triangle": [2 / 15] * 3 + [1 / 5] * 3}
    assert np.allclose(Nt.T @ w, expected[kind], rtol=0, atol=1e-15)
    T = transformation(kind, 0.2)
    # invertible: the same space, only the nodal unknowns change
    assert np.linalg.cond(T) < 10.0


@pytest.mark.parametrize("curved", [False, True])
@pytest.mark.parametrize("kind", KINDS)
def test_dual_functions_are_biorthogonal_and_reproduce_a_uniform_pressure(kind, curved):
    Phi, Nt, N, w = integrals(kind, CURVED[kind] if curved else None)
    D = Nt.T @ w
    # ∫ Φ_j Ñ_k = δ_jk ∫ Ñ_k: exact rule, so to round-off (1e-13 of weights of order 0.1)
    assert np.allclose((Phi * w[:, None]).T @ Nt, np.diag(D), rtol=0, atol=1e-13)
    assert np.allclose(Phi.sum(axis=1), 1.0, rtol=0, atol=1e-12)  # Σ Φ_j = 1
    # a uniform pressure z_j = p puts on each node k of the original basis its consistent
    # load p ∫ N_k (corners of the triangle 0, edge nodes 1/3 of the area)
    p = 1e5
    forces = p * (Phi.sum(axis=1) * w) @ N  # Σ_j z_j ∫ Φ_j N_k
    assert np.allclose(forces, p * (N.T @ w), rtol=1e-13, atol=1e-9)


@pytest.mark.parametrize("kind", KINDS)
def test_weighted_gaps_read_the_transformed_nodal_values(kind):
    """A quadratic gap field g = Σ N_k g_k: its weighted gaps over ∫Ñ_j are the nodal values
    in the transformed basis, (T⁻ᵀ g)_j; a uniform gap reads itself at every node."""
    Phi, Nt, N, w = integrals(kind, CURVED[kind])
    rng = np.random.default_rng(3)
    g = rng.normal(size=N.shape[1])
    read = (Phi * w[:, None]).T @ (N @ g) / (Nt.T @ w)
    T = transformation(kind)
    assert np.allclose(read, np.linalg.solve(T.T, g), rtol=0, atol=1e-12)
    uniform = (Phi * w[:, None]).T @ np.full(len(w), 0.25) / (Nt.T @ w)
    assert np.allclose(uniform, 0.25, rtol=0, atol=1e-14)


def test_bad_input():
    with pytest.raises(InputError, match="kind"):
        transformation("quad")
    with pytest.raises(InputError, match="alpha"):
        transformation("triangle", 0.5)
    with pytest.raises(InputError, match="jacobian"):
        dual_coefficients("segment", jacobian=np.ones(2))


@pytest.mark.parametrize("meshes", [(7, 5), (5, 7), (4, 4), (13, 6)])
def test_p2_patch_test_uniform_pressure(meshes):
    """Acceptance 1 on P2 blocks: every node of the quadratic face, ends and mid nodes, carries
    a row; the pressure is uniform and the displacements exact to round-off (measured
    1e-13 and 3e-14; the faces split into linear facets gave 0.86-1.19 p and 1.9 %)."""
    pair, lam, pressure, error = pressed_p2_blocks(*meshes)
    assert isinstance(pair, MortarContactP2)
    assert len(pressure) == 2 * meshes[1] + 1  # the face's ends and mid nodes
    assert np.count_nonzero(lam > 0) == len(pressure)  # every one of them pressed
    # the solve is direct and its tolerance 1e-12 of the model size: 1e-8 is round-off's bound
    assert np.max(np.abs(pressure - 1.0)) <= 1e-8
    assert error <= 1e-8


@pytest.mark.parametrize("method", ["split", "node-to-surface"])
def test_p2_patch_test_is_not_exact_without_the_quadratic_faces(method):
    """The same P2 blocks with the boundary split into linear segments, or node-to-surface
    (the table of docs/explanation/mortar.md): their nodal forces are not the P2 load of a
    uniform pressure."""
    _, _, _, error = pressed_p2_blocks(7, 5, method=method)
    assert error > 1e-3


MAT = solid_material("linear", 1e7, 0.3, 1e3)


def p2_disks(refinements=2, offset=0.0, friction=0.0, gap=0.002):
    """Two P2 disks of radius 0.1 m, ``gap`` apart, the right one ``offset`` higher, meeting at
    1 m/s each: the model, v0 and the step (the wave's transit over half the shortest edge)."""
    a = Solid.disk([-0.1 - gap / 2, -offset / 2], 0.1, refinements, MAT, element="P2")
    b = Solid.disk([0.1 + gap / 2, offset / 2], 0.1, refinements, MAT, element="P2")
    model = Model([a, b], [Contact(a, b, friction=friction)], gravity=(0.0, 0.0))
    v0 = model.translation(a, (1.0, 0.0)) + model.translation(b, (-1.0, 0.0))
    return model, v0, wave_step(a, 1.0, a.min_edge_length / 2.0)


def test_weighted_gap_derivatives_are_exact_on_curved_p2_faces():
    """Gradients and Hessians through the projections onto curved slave and master segments
    (the boundaries perturbed by 1 mm): exact against central differences, on the rows of
    the slave segments the master covers fully. (Two segments three off the contact meet
    master segments turned by 110°, in the facing fade's band, and are covered by 3 % and
    9 %: their rows take the covered part's dual functions, whose Hessians are those at
    fixed coefficients; test below and tests/test_mortar_p2_facing_fade.py.) The search
    reaches 4 cm: the rows 14 mm off the contact read +14 mm over pairs whose mean gap is
    beyond 2 cm, which fade out from the search distance on (far in front); searched to
    2 cm, those rows read +9 to +10 mm and one segment stays covered fully, not three."""
    model, _, _ = p2_disks(gap=0.002, offset=0.003)
    pair = model.contacts.pairs[0]
    assert isinstance(pair, MortarContactP2)
    pair.detect_within(0.04)
    q = np.random.default_rng(1).normal(0.0, 1e-3, model.n)
    _, e, _, _, (_, coverage, _) = pair._overlapping(q)
    fraction = np.bincount(e, coverage, len(pair.facets))
    partly = pair.element_rows[(fraction > 0.0) & (fraction < 1.0 - 1e-9)]
    full = np.setdiff1d(pair.element_rows[fraction >= 1.0 - 1e-9], partly)
    finite = np.isfinite(pair.gaps(q))
    assert finite[full].sum() >= 3 and finite[partly].any()
    err_g, err_h = gap_derivatives_error(pair, q, 1e-7, full)
    # central differences with step 1e-7 m: truncation ~1e-14 relative, round-off ~1e-9
    assert err_g < 1e-8 and err_h < 1e-6


def test_weighted_gap_gradients_are_exact_on_partly_covered_p2_segments():
    """The octagon-like P2 disks (refinements 1) 2 mm apart: each slave segment near the
    contact is covered in part and takes the dual functions of its covered part; the
    gradients through them are exact (measured 2e-10), and so are the rows' Hessians, with
    the terms coupling two pairs of one segment (measured 1.9e-9; 1.6 with those left out,
    2.2 at fixed dual coefficients). Searched to
    4 cm (as above: the pairs far in front fade out from the search distance on; at 2 cm
    only the contact's row takes part, the rows at +31 and +32 mm left out)."""
    from fecontact.contact.mortar_p2_segments import DUALS

    model, _, _ = p2_disks(refinements=1, gap=0.002, offset=0.003)
    pair = model.contacts.pairs[0]
    pair.detect_within(0.04)
    q = np.random.default_rng(1).normal(0.0, 1e-4, model.n)
    g = pair.evaluate(q)[0]
    A = pair._last[1]["quad"][3]
    assert np.count_nonzero(~np.all(np.isclose(A, DUALS), axis=(1, 2))) >= 2
    assert np.isfinite(g).sum() >= 3
    err_g, err_h = gap_derivatives_error(pair, q, 1e-7)
    # step 1e-7 m: truncation ~1e-14 relative, round-off ~1e-9 (as above)
    assert err_g < 1e-8 and err_h < 1e-6


def test_partly_covered_p2_segments_have_exact_pair_hessians():
    """On the segments covered in part (the disks of the test above), each pair's Hessian of
    the weighted gaps over its own 12 coordinates, the segment's other pairs held, is exact
    against central differences of the gradients: the dual coefficients of the covered part
    differentiated twice (at fixed coefficients the curvature along a Newton update of two
    fast P2 disks was 50 times the true one)."""
    model, _, _ = p2_disks(refinements=1, gap=0.002, offset=0.003)
    pair = model.contacts.pairs[0]
    pair.detect_within(0.02)
    q = np.random.default_rng(1).normal(0.0, 1e-4, model.n)
    _, e, z, _, (_, coverage, _) = pair._overlapping(q)
    fraction = np.bincount(e, coverage, len(pair.facets))[e]
    partly = np.flatnonzero(fraction < 1.0 - 1e-9)
    assert partly.size >= 2
    jets = pair._integrate(e, z, True)[0]
    rng, eps = np.random.default_rng(0), 1e-7
    for k in partly:
        dz = np.zeros_like(z)
        dz[k] = rng.normal(0.0, 1e-3, z.shape[1])
        up, down = (pair._integrate(e, z + s * eps * dz, False)[0] for s in (1.0, -1.0))
        for j, jet in enumerate(jets):
            fd = (up[j].g[k] - down[j].g[k]) / (2.0 * eps)
            # step 1e-7 m: truncation ~1e-14 relative, round-off ~1e-8 (measured 1e-7 at most)
            assert np.linalg.norm(fd - jet.h[k] @ dz[k]) < 1e-6 * np.linalg.norm(fd)


def test_newton_keeps_its_quadratic_rate_on_p2_faces():
    """A P2 disk pressed into a P2 block, geometry updated (gaps where the bodies are): once
    the active set has settled the errors fall quadratically (measured 3.0e-7, 9.8e-13,
    1.3e-16 m: e_{k+1}/e_k² ≈ 11 /m)."""
    disk = Solid.disk([0.0, 0.0], 0.1, 2, MAT, element="P2")
    block = Solid.rectangle([-0.15, -0.2], [0.15, -0.1], (7, 3), MAT, element="P2")
    base = block.nodes_where(lambda x: x[1] < -0.2 + 1e-9)
    block.fix(base, "x")
    block.fix(base, "y")
    disk.fix(disk.nodes_where(lambda x: abs(x[0]) < 1e-9), "x")
    model = Model([block, disk], [Contact(disk, block)], gravity=(0.0, 0.0))
    load = np.zeros(model.n)
    top = disk.nodes_where(lambda x: x[1] > 0.1 - 1e-9)
    load[model.offset_of(disk) + 2 * top + 1] = -4e4
    iterates = []
    internal = model.internal

    def recorded(q):
        iterates.append(q.copy())
        return internal(q)

    model.internal = recorded
    q, lam = solve_static_contact(model, load)
    assert np.count_nonzero(lam > 0.0) >= 3
    e = np.array([np.max(np.abs(x - q)) for x in iterates])
    # the last two errors above round-off (1e-15 m) against the one before: quadratic, with
    # the constant of this problem (~10 /m); a rate of 1.5 would leave e_{k+1}/e_k² ~1e3 /m
    big = np.flatnonzero(e > 1e-14)
    k = big[-1]
    assert e[k] <= 100.0 * e[k - 1] ** 2
    assert e[k - 1] <= 1e-4


def p2_trajectory(options, **params):
    model, v0, dt = p2_disks(**params)
    return np.array([st.q for st in simulate(model, dt, 0.003, options, v0=v0)])


OPTIONS = load_case("two_disks").build(refinements=1).options


@pytest.mark.parametrize("change", [{"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}])
def test_p2_mortar_trajectory_independent_of_p_and_k(change):
    base = p2_trajectory(OPTIONS)
    other = p2_trajectory(dataclasses.replace(OPTIONS, **change))
    assert np.max(np.abs(other - base)) <= 1e-8 * 0.05  # of the radius


def test_p2_disks_head_on_keep_on_the_axis_and_friction_keeps_momentum():
    """Head-on, the P2 disks keep on the axis through the impact and the parting (12 ms, step
    Δx/c): the vertices on the axis meet vertex to vertex and their pointwise rows hold them
    on the vertices' ties (lateral 2.1e-15 m/s measured; with one segment's gap 8.7 % of the
    impact speed; node-to-surface both ways 19 %); an oblique impact with Coulomb friction
    keeps the total momentum (equal and opposite forces on the quadratic faces)."""
    model, v0, dt = p2_disks()
    A, mortar = model.bodies[0], model.contacts.pairs[0].size
    wy = A.mass_matrix() @ A.translation_field((0.0, 1.0))
    lateral, held = [], 0
    for st in simulate(model, 2.0 * dt, 0.012, OPTIONS, v0=v0):
        lateral.append(float(wy @ st.v[model.body_slice(0)]) / A.mass)
        held += int(np.any(st.force[mortar:] > 0))  # (the pointwise rows)
    assert held > 0  # the rows hold the vertices in this run
    assert np.max(np.abs(lateral)) <= 1e-10
    model, v0, dt = p2_disks(offset=0.02, friction=0.3)
    states = list(simulate(model, dt, 0.004, OPTIONS, v0=v0))
    for axis in ((1.0, 0.0), (0.0, 1.0)):
        w = A.mass_matrix() @ A.translation_field(axis)
        total = float(w @ states[-1].v[model.body_slice(0)] + w @ states[-1].v[model.body_slice(1)])
        assert abs(total) <= 1e-9 * A.mass
    assert any(np.any(s.force > 0) or np.any(s.impulse > 0) for s in states)


@pytest.mark.parametrize("meshes", [(3, 2), (4, 3), (3, 4), (5, 2)])
def test_p2_patch_test_3d_uniform_pressure(meshes):
    """Acceptance 1 on P2 boxes, on the curved-face interface: every corner and edge node of
    the face carries a row with the transformed basis' dual functions; pressure uniform and
    displacements exact to round-off (measured 1e-13 and 7e-14; the faces split into flat
    triangles gave 0.57-1.23 p and 5.9 %)."""
    pair, lam, pressure, error = pressed_p2_boxes(*meshes)
    assert len(pressure) == (2 * meshes[1] + 1) ** 2  # the face's corners and edge nodes
    assert np.count_nonzero(lam > 0) == len(pressure)
    assert np.max(np.abs(pressure - 1.0)) <= 1e-8  # a direct solve: round-off
    assert error <= 1e-8


def test_p2_faces_split_into_flat_triangles_fail_the_3d_patch_test():
    """The default 3D mortar of P2 solids (faces split into flat triangles) is not exact on
    the same boxes: the table of docs/explanation/mortar.md."""
    _, _, pressure, error = pressed_p2_boxes(4, 3, method="split")
    assert np.max(np.abs(pressure - 1.0)) > 0.1 and error > 1e-2


def curved_pairs():
    """Two P2 balls (curved faces) 0.5 mm apart, displaced at random by 0.1 mm: the interface
    and the state."""
    a = Solid.ball([0.0, 0.0, -0.1005], 0.1, 2, MAT, element="P2")
    b = Solid.ball([0.003, 0.002, 0.1], 0.1, 2, MAT, element="P2")
    pair = MortarContact3DP2(a, b)
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.004)
    rng = np.random.default_rng(1)
    return pair, model, rng.normal(0.0, 1e-4, model.n), rng.normal(0.0, 1.0, model.n)


def test_curved_face_integrals_have_exact_derivatives():
    """The pair integrals m_k = ∫ Ñ_k g_N dA and M_kl = ∫ Ñ_k Ñ_l dA on curved faces, with
    the projections onto the curved master and the overlap's moving vertices: gradients and
    Hessians against central differences along a random direction (measured 1e-9)."""
    pair, _, q, _ = curved_pairs()
    pair.evaluate(q)
    z = pair._last[1]["z"][:12]
    dz = np.random.default_rng(2).normal(size=z.shape)
    eps = 1e-7  # central differences: truncation 1e-14, round-off 1e-9 of the values
    every = np.ones(len(z), bool)
    moments, mass_of, _, _, _ = p2_triangle_integrals(z, True)
    plus, minus = (p2_triangle_integrals(z + s * eps * dz, False) for s in (1.0, -1.0))
    mass, mp, mm = mass_of(every)[0], plus[1](every)[0], minus[1](every)[0]
    for jets, jp, jm in ((moments, plus[0], minus[0]), (mass, mp, mm)):
        for j, a, b in zip(jets, jp, jm, strict=True):
            slope = np.einsum("pi,pi->p", j.g, dz)
            assert np.max(np.abs((a.v - b.v) / (2 * eps) - slope)) <= 1e-7 * np.max(np.abs(slope))
            curve = np.einsum("pij,pj->pi", j.h, dz)
            assert np.max(np.abs((a.g - b.g) / (2 * eps) - curve)) <= 1e-7 * np.max(np.abs(curve))


def test_curved_face_rows_have_exact_gradients():
    """The rows of the curved-face interface, partly covered faces included (their dual
    functions those of the covered part, differentiated through it): the gradient against
    central differences along a random direction (measured 6e-9)."""
    pair, _, q, d = curved_pairs()
    g, dofs, G, _ = pair.evaluate(q)
    rows = np.flatnonzero(np.isfinite(g))
    assert len(rows) >= 10
    eps = 1e-7
    gp, gm = pair.evaluate(q + eps * d)[0], pair.evaluate(q - eps * d)[0]
    slope = np.einsum("jk,jk->j", G, d[dofs])[rows]
    assert np.max(np.abs((gp[rows] - gm[rows]) / (2 * eps) - slope)) <= 1e-7 * np.max(np.abs(slope))


def test_quadratic_faces_need_p2_tetrahedra():
    box = Solid.box([0, 0, 0], [1, 1, 1], 1, MAT)
    with pytest.raises(InputError, match="P2 solid of tetrahedra"):
        quadratic_triangles(box)
    with pytest.raises(InputError, match="2D P2 solid"):
        quadratic_segments(Solid.disk([0, 0], 0.1, 1, MAT))


@pytest.mark.parametrize("test", [pressed_p2_blocks, pressed_p2_boxes])
def test_slip_rows_of_quadratic_faces_read_a_sliding_translation(test):
    """Friction's slip rows on the quadratic faces: the slave sliding by a uniform velocity u
    over the resting master reads T_j·u at every pressed node inside the face (∫ Φ_j dA = L_j,
    Σ_i N_i = 1; a node on the face's border also carries the side faces' weight in L_j); the
    master sliding instead reads −T_j·u."""
    pair, lam, _, _ = test(4, 3)
    slave, master = pair.bodies
    n = slave.ndof + master.ndof
    q = np.zeros(n)
    dofs, rows, T = pair.tangents(q)
    u = np.eye(slave.dim)[0]
    X = slave.X[pair.nodes][:, :-1]  # the face's tangential coordinates
    pressed = (lam > 0) & np.all((X > 1e-9) & (X < 1 - 1e-9), axis=1)
    assert pressed.sum() >= 5
    for body, sign in ((slave, 1.0), (master, -1.0)):
        v = np.zeros(n)
        o = pair.offsets[pair.bodies.index(body)]
        v[o : o + body.ndof] = body.translation_field(u)
        slip = np.einsum("jtk,jk->jt", rows, v[dofs])
        expected = sign * T @ u
        # sums of products of weights of order 1: round-off
        assert np.max(np.abs(slip[pressed] - expected[pressed])) <= 1e-12


def test_p2_disks_out_of_reach_have_open_rows():
    """Two P2 disks farther apart than the search reaches (the fast approach's start): no
    candidate pair, every row open (+inf), its gradient and slip rows empty of weight
    (an empty batch of pairs once failed to reshape)."""
    model, _, _ = p2_disks(gap=0.1, friction=0.3)
    pair = model.contacts.pairs[0]
    q = np.zeros(model.n)
    g, _, G, _ = pair.evaluate(q)
    assert np.all(np.isposinf(g)) and not np.any(G)
    assert not np.any(pair.tangents(q)[1])
