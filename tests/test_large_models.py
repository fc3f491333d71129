"""What keeps large models fast, each checked to give the exact answer.

A linear elastic solid has a constant iteration matrix S = β′M + K: a run of many steps must
factorize it once (and the mass once), however its time step rounds, and must not reassemble
it. Symmetric factorizations must solve as accurately as the general ones. The position
correction works on the penetrating candidates and adds those its correction pushes in.
"""

import numpy as np
import pytest
import scipy.sparse as sp

import fecontact.linalg.ladder as ladder_module
import fecontact.model as model_module
import fecontact.time.constraints as constraints_module
import fecontact.time.impacts as impacts_module
from fecontact import Contact, IntegratorOptions, LinearElastic, Model, Plane, Solid, simulate
from fecontact.bodies.rigid import Polygon, RigidBody2D, rotation
from fecontact.linalg import factorize
from fecontact.time.generalized_alpha import Coefficients


def counted(monkeypatch):
    """Count the calls of ``factorize`` from the model and the integrator."""
    calls = []

    def wrapper(A, symmetric=False, solver=None, **options):
        calls.append((A.shape[0], symmetric))
        return factorize(A, symmetric, solver, **options)

    monkeypatch.setattr(model_module, "factorize", wrapper)
    monkeypatch.setattr(constraints_module, "factorize", wrapper)
    monkeypatch.setattr(impacts_module, "factorize", wrapper)
    monkeypatch.setattr(ladder_module, "factorize", wrapper)
    return calls


def falling_ball(refinements=2, lift=0.0):
    mat = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
    ball = Solid.ball([0.0, 0.0, 0.05 + lift], 0.05, refinements, mat)
    model = Model([ball], [Contact(ball, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]))])
    return model, model.translation(ball, (0.0, 0.0, -1.0))


def test_linear_solid_in_contact_factorizes_once_per_run(monkeypatch):
    model, v0 = falling_ball()
    assert model.n_free > 120  # sparse factorizations
    calls = counted(monkeypatch)
    assembled = []
    assemble = model.pattern.assemble
    monkeypatch.setattr(model.pattern, "assemble", lambda v: assembled.append(1) or assemble(v))
    # n·dt − (n − 1)·dt is not dt to the last bit for this dt: the step must still be dt
    dt = 1e-5 / 3.0
    steps = list(simulate(model, dt, 60 * dt, v0=v0))
    assert len(steps) == 61
    assert sum(np.count_nonzero(st.impulse) for st in steps) > 0  # contact was resolved
    # the mass (initial acceleration, velocity jumps) and S, each once and symmetric
    assert calls == [(model.n_free, True)] * 2
    assert len(assembled) == 1
    assert len(model.iteration_cache) == 1


def test_column_cache_solves_only_for_new_contacts(monkeypatch):
    """H⁻¹G_jᵀ and S⁻¹G_jᵀ are kept per contact: the right-hand sides solved with the factors
    of S are one per smooth Newton update plus one per contact that enters the position
    correction, or carries a smooth contact force, for the first time. Only penetrating
    candidates (and those the correction pushes in) enter it: far fewer than the candidates
    within the detection margin. The ball lands inside the first step (half of it): released
    touching, it would take its impact at t = 0 and its contacts would all be held by the
    smooth force, without a correction."""
    model, v0 = falling_ball(lift=0.5e-5)
    columns = []
    factors = model_module.iteration_solver

    def counting(model, a, S, K):  # (a run makes its own factors: counted as it makes them)
        solve_S = factors(model, a, S, K)

        def solve(b):
            b = np.asarray(b)
            columns.append(1 if b.ndim == 1 else b.shape[1])
            return solve_S(b)

        return solve

    monkeypatch.setattr(model_module, "iteration_solver", counting)
    # the closing taken at the step's end ("auto" would locate it, in a step of its own size)
    states = list(simulate(model, 1e-5, 40e-5, IntegratorOptions(localize=False), v0=v0))
    seen = set()
    for st in states:
        seen.update(st.candidates.tolist())
    updates = sum(st.iterations["smooth"] for st in states)
    cached = model.column_cache[("stiffness", *_bp_gp(model, 1e-5))]
    smooth = model.column_cache.get(("smooth", *_bp_gp(model, 1e-5)), {})
    assert set(cached) <= seen and set(smooth) <= seen
    assert 0 < len(cached) < len(seen) / 2
    assert 0 < sum(columns) <= updates + len(cached) + len(smooth)


def _bp_gp(model, h):
    c = Coefficients(IntegratorOptions().rho_inf, h)
    return c.bp, c.gp


@pytest.mark.parametrize("n", [50, 400])
def test_symmetric_factorization_solves_like_the_general_one(n):
    """Positive definite and indefinite symmetric matrices (a buckling tangent), dense and
    sparse: the symmetric mode returns the same solution to round-off."""
    rng = np.random.default_rng(3)
    A = sp.random(n, n, density=8.0 / n, random_state=rng)
    A = A + A.T + sp.diags(rng.uniform(-1.0, 1.0, n))
    B = rng.standard_normal((n, 3))
    for shift in (0.0, 20.0):  # indefinite, then positive definite
        As = (A + shift * sp.identity(n)).tocsc()
        x_general = factorize(As)(B)
        x_symmetric = factorize(As, symmetric=True)(B)
        assert np.allclose(As @ x_symmetric, B, atol=1e-9 * np.abs(B).max())
        assert np.allclose(x_symmetric, x_general, rtol=1e-8, atol=1e-10)


def test_correction_adds_the_candidates_it_pushes_into_the_plane():
    """A rigid bar (1 m, 1 kg) with its left end on the plane and its right end 0.1 mm above
    it, the left end moving down at 1 m/s and the right end at rest. The correction of the
    left end alone lifts it and rotates the bar, lowering the right end by half the lift
    (uniform bar: M⁻¹ on a lever of L/2 with J = mL²/12): below the plane. The right end
    must join the correction: both ends end on the plane with ν ≥ 0, the left one carrying
    more."""
    L, eps, v, h = 1.0, 1e-4, 1.0, 1e-3
    shape = Polygon.box(L, 0.01)
    angle = np.arcsin(eps / L)
    bar = RigidBody2D.uniform(1.0, -rotation(angle) @ shape.vertices[0], shape, angle=angle)
    model = Model([bar], [Contact(bar, Plane([0.0, 0.0], [0.0, 1.0]))], gravity=(0.0, 0.0))
    v0 = model.body_vector(bar, (0.0, -0.5 * v, v / L))
    for margin in (0.05, 1.0):  # the same answer with every vertex a candidate
        st = list(simulate(model, h, h, IntegratorOptions(detection_margin=margin), v0=v0))[-1]
        assert np.all(st.gaps >= -1e-12 * model.length)
        assert np.allclose(st.gaps[:2], 0.0, atol=1e-12)
        assert st.nu[0] > st.nu[1] > 0.0
        assert np.all(st.nu[2:] == 0.0)


def test_curvature_of_large_models_is_sparse_over_the_weighted_contacts():
    """Node-to-segment curvature of two disks (580 free dofs: the sparse path) equals the
    sum of the weighted gap Hessians, and holds only the dofs of contacts with a weight."""
    mat = LinearElastic(E=1e7, nu=0.3, rho=1000.0)
    left = Solid.disk([-0.0499, 0.0], 0.05, 3, mat)
    right = Solid.disk([0.0499, 0.0], 0.05, 3, mat)
    pair = Contact(left, right, method="node-to-surface")
    model = Model([left, right], [pair], gravity=(0.0, 0.0))
    assert model.n_free > 120
    q = np.zeros(model.n)
    g_all = model.contacts.gaps(q)
    select = np.flatnonzero(np.isfinite(g_all))
    assert select.size >= 3
    weights = np.linspace(1.0, 2.0, select.size)
    weights[1] = 0.0
    g, G, C = model.contacts.linearize(q, select, weights)
    assert sp.issparse(C)
    pair = model.contacts.pairs[0]
    dofs, H = pair.evaluate(q)[1], pair.hessians(q, select)
    expected = np.zeros((model.n_free, model.n_free))
    for w, j, Hj in zip(weights, select, H, strict=True):
        fi = model.free_index[dofs[j]]
        expected[np.ix_(fi, fi)] += w * Hj
    assert np.allclose(C.toarray(), expected, rtol=1e-13, atol=1e-13 * np.abs(expected).max())
    touched = np.unique(C.nonzero()[0])
    assert not np.isin(model.free_index[dofs[select[1], :2]], touched).any()


def test_gap_gradients_of_a_selection_are_the_selected_rows():
    """Nodes of a P1 ball on a tilted plane (258 contacts × 2499 dofs: not the small models'
    affine form). Gap rows of linear kinematics carry no Hessian; the gradient rows of any
    selection of contacts must still be the selected rows of the full gradient."""
    ball = Solid.ball([0.0, 0.0, 0.05], 0.05, 3, LinearElastic(E=1e7, nu=0.3, rho=1000.0))
    model = Model([ball], [Contact(ball, Plane([0.0, 0.0, 0.01], [0.2, 0.1, 1.0]))])
    assert not model.contacts.affine
    q = np.random.default_rng(3).normal(scale=1e-3, size=model.n)
    g_all, G_all, _ = model.contacts.linearize(q, model.contacts.all)
    for select in (np.array([5]), np.array([40, 7, 200]), np.arange(0, model.contacts.size, 3)):
        g, G, _ = model.contacts.linearize(q, select)
        assert np.array_equal(g, g_all[select])
        assert np.array_equal(G, G_all[select])
