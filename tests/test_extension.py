"""A body type and its contact pair defined outside the package run through ``Contact``, the
model, the stepper and the output without a change to the package: the body subclasses
``BodyDefaults`` and provides the ``Body`` protocol, its pair registers with
``register_pair``."""

import math

import numpy as np
import pytest
import scipy.sparse as sp

import fecontact
from fecontact import (
    Circle,
    Contact,
    InputError,
    LinearElastic,
    Model,
    Plane,
    PointMass,
    Simulation,
    Solid,
)
from fecontact.bodies.base import Body, BodyDefaults
from fecontact.contact import NodeContact, register_pair
from fecontact.contact.base import PairDefaults
from fecontact.time import ForceTerm, IntegratorOptions, PhaseTimer, initial_state, make_stepper

G = 9.81


class Dumbbell(BodyDefaults):
    """Two balls of ``radius`` (m) and ``mass`` (kg) each, centred at ``a`` and ``b`` (m),
    joined by a linear spring of ``stiffness`` (N/m) acting on their relative displacement:
    W = k/2 |u_b − u_a|². Dofs: (u_a, u_b), 2 each."""

    dofs_per_node = 2
    n_nodes = 2
    components = ("x", "y")
    linear = True
    linear_kinematics = True
    element_dofs = np.array([[0, 1, 2, 3]])

    def __init__(self, a, b, mass: float, stiffness: float, radius: float):
        self.X = np.array([a, b], dtype=float)
        self.ball_mass, self.radius = mass, radius
        self.fixed: set[int] = set()
        I2 = np.eye(2)
        self._Ke = stiffness * np.block([[I2, -I2], [-I2, I2]])

    @property
    def mass(self) -> float:
        return 2.0 * self.ball_mass

    @property
    def characteristic_length(self) -> float:
        return float(np.linalg.norm(self.X[1] - self.X[0])) + 2.0 * self.radius

    def internal(self, q, tangent=True):
        f = self._Ke @ q
        return 0.5 * float(q @ f), f, (self._Ke[None] if tangent else None)

    def energy(self, q):
        return self.internal(q, False)[0]

    def mass_matrix(self):
        return sp.diags(np.full(4, self.ball_mass)).tocsr()

    def translation_field(self, vector):
        return np.tile(np.asarray(vector, dtype=float), 2)

    def node_index(self, node):
        if node not in (-2, -1, 0, 1):
            raise InputError(f"node must be in [-2, 1], got {node!r}")
        return node % 2

    def contact_nodes(self, nodes=None):
        return np.arange(2) if nodes is None else np.array([self.node_index(n) for n in nodes])

    def positions(self, q):
        return self.X + q.reshape(2, 2)

    def point_kinematics(self, q, nodes):
        dofs = 2 * nodes[:, None] + np.arange(2)
        return self.X[nodes] + q[dofs], dofs, np.repeat(np.eye(2)[None], len(nodes), 0), None

    def nodal(self, x, q=None):
        return np.asarray(x).reshape(2, 2)

    def point_data(self, q, v):
        return {"displacement": q.reshape(2, 2), "velocity": v.reshape(2, 2)}

    def cells(self):
        return [("line", np.array([[0, 1]]))]


class BallsOnPlane(PairDefaults):
    """Each ball of a dumbbell against a rigid plane: g = n·(x − p) − r, one contact a ball."""

    size = 2
    linear = True

    def __init__(self, body, plane, restitution):
        self.body, self.obstacle, self.restitution = body, plane, restitution
        self.offset = 0

    def bind(self, model):
        self.offset = model.offset_of(self.body)

    def evaluate(self, q):
        qb = q[self.offset : self.offset + self.body.ndof]
        x, dofs, _, _ = self.body.point_kinematics(qb, np.arange(2))
        g, n, _ = self.obstacle.gap(x)
        return g - self.body.radius, dofs + self.offset, n, None


@register_pair(Dumbbell, Plane)
def balls_on_plane(body, plane, nodes, restitution, clearance):
    if nodes is not None or clearance:
        raise InputError("nodes, clearance: a dumbbell touches a plane with its two balls")
    return BallsOnPlane(body, plane, restitution)


def dumbbell(height: float):
    r = 0.05
    return Dumbbell([0.0, r + height], [0.4, r + height], 0.5, 1e4, r)


def test_the_new_body_declares_the_protocol_and_contact_finds_its_pairs():
    body = dumbbell(0.1)
    assert isinstance(body, Body)
    assert isinstance(Contact(body, Plane([0, 0], [0, 1]), restitution=0.5), BallsOnPlane)
    # a partner it registered nothing for: the nodes of any body against a Circle
    assert isinstance(Contact(body, Circle([0.2, 1.0], 0.1)), NodeContact)
    solid = Solid.disk([2.0, 0.0], 0.1, 0, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    with pytest.raises(InputError, match="no contact between a Dumbbell and a Solid: .*Plane"):
        Contact(body, solid)


def test_the_new_body_bounces_by_newtons_law_through_the_stepper_and_the_output(tmp_path):
    """Dropped level from h = 0.1 m, both balls hit at t₁ = √(2h/g) with speed √(2gh) and
    leave with e√(2gh) (the spring stays unstretched: the motion is a translation); the apex
    after the bounce is e²h above the plane, at t₁ + e√(2h/g)."""
    h, e, dt = 0.1, 0.5, 1e-4
    body = dumbbell(h)
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([body], [Contact(body, floor, restitution=e)], gravity=(0.0, -G))
    t1 = np.sqrt(2 * h / G)
    summary = fecontact.run(
        Simulation(model, dt=dt, t_end=t1 * (1 + e) + 0.01, name="dumbbell"), tmp_path
    )
    assert summary["status"] == "completed"
    states = list(fecontact.simulate(model, dt, t1 * (1 + e) + 0.01))
    t = np.array([s.t for s in states])
    y = np.array([s.q[1] for s in states])  # the first ball's rise above its start
    vy = np.array([s.v[1] for s in states])
    gaps = np.array([s.gaps for s in states])
    # the balls never enter the plane beyond the position correction's tolerance (1e-9 m
    # scale here, far below the 1e-4 m the step moves a ball at impact)
    assert gaps.min() > -1e-8
    after = t > t1 + 2 * dt
    # Newton's law at the impact: exactly −e times the speed just before (to the step's
    # gravity increment g·dt ≈ 1e-3 m/s, where the impact lies inside a step)
    v_out = vy[after][0] + G * (t[after][0] - t1)
    assert v_out == pytest.approx(e * np.sqrt(2 * G * h), abs=2 * G * dt)
    apex = h + y[after].max()
    assert apex == pytest.approx(e**2 * h, abs=2 * np.sqrt(2 * G * h) * dt)
    # a translation: both balls move alike, the spring stays at rest
    q = np.array([s.q for s in states])
    np.testing.assert_allclose(q[:, 0:2], q[:, 2:4], atol=1e-12)


# -- a force term defined outside the package ---------------------------------------------------


class CubicSpring(ForceTerm):
    """A nonlinear spring to ground on every free dof: f = k u³ (N, the sign of an internal
    force), tangent ∂f/∂q = 3k u² (stiffness-like: it enters S_t with coefficient 1)."""

    own_tangent = True

    def __init__(self, model, k: float):
        self.k, self.F = k, model.free_slice

    def evaluate(self, step, it):
        self.u = step.q[self.F].copy()

    def residual(self, r):
        return r + self.k * self.u**3

    def tangent(self, S):
        return S + np.diag(3.0 * self.k * self.u**2)


class LinearDrag(ForceTerm):
    """A linear drag f = c v (N) on every free dof, tangent ∂f/∂v = c I (damping-like: it
    enters S_t with γ′)."""

    own_tangent = True

    def __init__(self, model, c: float):
        self.c, self.F = c, model.free_slice

    def begin(self, step):
        self.gp = step.c.gp
        return self

    def evaluate(self, step, it):
        self.v = step.v[self.F].copy()

    def residual(self, r):
        return r + self.c * self.v

    def tangent(self, S):
        return S + self.gp * self.c * np.eye(len(self.v))


def free_point(mass: float):
    point = PointMass(mass, [0.0, 0.0], size=1.0)
    return Model([point], [], gravity=(0.0, 0.0))


def stepped(model, terms, h: float, n: int, v0, f0, q0=None, rho_inf: float = 1.0):
    """The states of n steps of h (s) through the run's stepper with the extra ``terms``,
    from the acceleration v̇₀ = −M⁻¹f₀ of the terms' force f₀ at the start (``initial_state``
    knows the model's forces only; an inconsistent v̇₀ costs generalized-α an order)."""
    stepper = make_stepper(model, IntegratorOptions(rho_inf=rho_inf), terms=terms)
    st, timer = initial_state(model, q0=q0, v0=v0), PhaseTimer()
    st.vd = -model.solve_M(np.asarray(f0, dtype=float))
    st.a = st.vd.copy()
    states = [st]
    for _ in range(n):
        st = stepper.step(st, h, timer)
        states.append(st)
    return states, stepper


def test_a_nonlinear_spring_term_from_outside_oscillates_with_the_exact_period():
    """m ü + k u³ = 0 from u(0) = A at rest: the period is T = 4 K √(m/k)/A with
    K = ∫₀¹ √2 du/√(1 − u⁴) = √2 Γ(¼)²/(4√(2π)) (the complete elliptic integral of the pure
    cubic oscillator). Generalized-α is second order: at T/h = 2000 the phase error of the
    first quarter period is O((ωh)²) ~ 1e-6 relative, far below the 1e-4 asserted."""
    m, k, A = 2.0, 50.0, 0.1
    model = free_point(m)
    K = math.sqrt(2.0) * math.gamma(0.25) ** 2 / (4.0 * math.sqrt(2.0 * math.pi))
    T = 4.0 * K * math.sqrt(m / k) / A
    h = T / 2000
    f0 = [k * A**3, 0.0]
    states, _ = stepped(model, [CubicSpring(model, k)], h, 600, [0.0, 0.0], f0, [A, 0.0])
    u = np.array([s.q[0] for s in states])
    i = int(np.argmax(u < 0.0))  # the first crossing of u = 0, a quarter period in
    t_cross = (i - 1 + u[i - 1] / (u[i - 1] - u[i])) * h
    assert t_cross == pytest.approx(T / 4, rel=1e-4)


def test_a_drag_term_from_outside_decays_the_velocity_exponentially_at_second_order():
    """m v̇ + c v = 0: v(t) = v₀ exp(−ct/m). The error at t = 1 s falls by 4 when h halves
    (generalized-α's second order holds for a term that enters through γ′)."""
    m, c, v0 = 1.0, 2.0, 1.5
    errors = []
    for h in (1e-2, 5e-3):
        model = free_point(m)
        drag, f0 = [LinearDrag(model, c)], [c * v0, 0.0]
        states, _ = stepped(model, drag, h, round(1.0 / h), [v0, 0.0], f0, rho_inf=0.8)
        errors.append(abs(states[-1].v[0] - v0 * math.exp(-c / m)))
    # 1.4e-5 m/s at h = 1e-2 s: (ch/m)² v₀ e^(-2) ~ 1e-4 v₀ bounds it
    assert errors[0] < 1e-4 * v0
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.05)


def test_terms_are_refused_by_a_stepper_without_the_loop():
    model = free_point(1.0)
    with pytest.raises(InputError, match="terms: .*integrator='moreau'"):
        make_stepper(model, IntegratorOptions(integrator="moreau"), terms=[LinearDrag(model, 1.0)])
