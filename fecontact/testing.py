"""What the tests and the benchmarks share: the shipped cases, runs traced step by step,
the exact solutions the cases are checked against, observed orders, and a finite-difference
check of gap derivatives.

Exact solutions: the bouncing ball (impact times t₁ = √(2h₀/g), t_{k+1} = t_k + 2eᵏt₁; the
gap between impacts; rest after the accumulation time t₁(1 + e)/(1 − e)) and the uniform
rigid bar swinging against a stop at the vertical (Jacobi's sn, with
1 − cos θ_{k+1} = e²(1 − cos θ_k) after each impact).
"""

from __future__ import annotations

import math
import time
from functools import cache

import numpy as np

from .cli.cases import bundled_cases, cases_folder, load_case
from .derivative_checks import (
    derivative_errors_near_contact,
    gap_derivatives_error,
    group_derivative_errors,
    group_gradient_error,
    moved_on_group,
    slip_derivative_errors,
    slip_step_errors,
)
from .energy import EnergyBalance
from .errors import SolverError
from .time import StepStats, simulate

__all__ = [
    "G",
    "ball_exact_gap",
    "ball_impact_times",
    "block_on_rigid_box",
    "case",
    "episode_starts",
    "derivative_errors_near_contact",
    "gap_derivatives_error",
    "group_derivative_errors",
    "group_gradient_error",
    "moved_on_group",
    "roll_up",
    "slip_derivative_errors",
    "slip_step_errors",
    "observed_order",
    "pendulum_exact",
    "pressed_blocks",
    "pressed_boxes",
    "pressed_p2_blocks",
    "pressed_p2_boxes",
    "trace",
]

G = 9.81
CASES = cases_folder()  # the bundled case files


@cache
def case(name: str):
    """The module of the bundled case ``NAME`` (``cases/NAME.py`` of a source checkout, the
    package data ``fecontact.cases`` of an installed wheel)."""
    known = bundled_cases()
    if name not in known:
        raise ValueError(f"no bundled case {name!r}; bundled: {', '.join(known)}")
    return load_case(known[name])


def trace(sim, dt=None, t_end=None, max_wall=None, abort=None):
    """Step ``sim`` with ``simulate`` and return one row per step (t = 0 included) as arrays.

    Keys: ``t``, ``h``, the probes, ``kinetic``, ``total`` (energy, J), ``min_gap`` (m, over
    every contact), ``active`` (a contact with ν > 0, Λ > 0 or a smooth force λ > 0),
    ``impulse`` (Σ kΛ, N·s),
    ``iterations`` (smooth + position + velocity), ``halvings``, ``vmax`` (max |v|); the
    run's ``energy_retakes`` and ``energy_retake_halves`` (counts, as ``summary.json``'s); and
    ``status`` ("completed", "failed" on ``SolverError``, "timeout" after ``max_wall`` s,
    "diverged" when ``abort(row)`` is true), ``message``, ``wall`` (s) and ``warnings``: the
    run's, as ``summary.json`` holds them, of its settings and of its energy check
    (:class:`fecontact.energy.EnergyBalance`).
    """
    model = sim.model
    names = ["t", "h", "kinetic", "total", "min_gap", "active", "impulse"]
    names += ["iterations", "halvings", "vmax", *sim.probes]
    rows = {k: [] for k in names}
    status, message = "completed", ""
    balance = EnergyBalance(model)  # the run's energy check, as fecontact.run's
    start = time.perf_counter()
    stats = StepStats()  # (the run's counts, read at its end)
    steps = simulate(
        model, dt or sim.dt, t_end or sim.t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats
    )
    try:
        for st in steps:
            ke, pe, se = (
                model.kinetic_energy(st.v),
                model.potential_energy(st.q),
                model.strain_energy(st.q),
            )
            total = ke + pe + se
            balance.add(st.t, st.q, ke, se, pe)
            row = {
                "t": st.t,
                "h": st.h,
                "kinetic": ke,
                "total": total,
                "min_gap": float(np.min(st.gaps, initial=np.inf)),
                "active": bool(st.pressed().any()),
                "impulse": float(np.sum(st.impulse)),
                "iterations": st.newton_iterations,
                "halvings": st.halvings,
                "vmax": float(np.max(np.abs(st.v))),
            }
            for name, probe in sim.probes.items():
                row[name] = probe.fn(model, st)
            for k, v in row.items():
                rows[k].append(v)
            stop = _stopped(row, abort, max_wall, time.perf_counter() - start)
            if stop is not None:
                status, message = stop
                break
    except SolverError as err:
        status, message = "failed", str(err)
    out = {k: np.array(v) for k, v in rows.items()}
    out.update(status=status, message=message, wall=time.perf_counter() - start)
    out.update(energy_retakes=stats.energy_retakes, energy_retake_halves=stats.energy_retake_halves)
    settings = sim.replace(dt=dt or sim.dt, t_end=t_end or sim.t_end).warnings()
    out["warnings"] = settings + ([balance.describe()] if balance.unstable() else [])
    return out


def _stopped(row: dict, abort, max_wall, wall: float) -> tuple[str, str] | None:
    """(status, message) where the trace stops after ``row``, else None."""
    if not math.isfinite(row["total"]):
        return "diverged", f"non-finite energy at t = {row['t']:.6g} s"
    if abort is not None and abort(row):
        return "diverged", f"stopped at t = {row['t']:.6g} s (energy blow-up)"
    if max_wall is not None and wall > max_wall:
        return "timeout", f"stopped at t = {row['t']:.6g} s after {max_wall} s"
    return None


def episode_starts(active) -> np.ndarray:
    """Indices of the steps where a contact closes after a step with none closed; ``active``
    holds one flag per step, or one row of flags per step (one per contact)."""
    on = np.asarray(active, dtype=bool).reshape(len(active), -1).any(axis=1)
    return np.flatnonzero(on & ~np.r_[False, on[:-1]])


def observed_order(h, err) -> float:
    """Least-squares slope of log(err) against log(h) (nan with fewer than two points)."""
    h, err = np.asarray(h, float), np.asarray(err, float)
    ok = (h > 0) & (err > 0) & np.isfinite(err)
    if ok.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)[0])


def ball_impact_times(n, h0=1.0, e=0.8, g=G) -> np.ndarray:
    """First ``n`` impact times of a ball dropped from ``h0``: t₁ = √(2h₀/g),
    t_{k+1} = t_k + 2eᵏt₁."""
    t1 = math.sqrt(2.0 * h0 / g)
    t = [t1]
    for k in range(1, n):
        t.append(t[-1] + 2.0 * e**k * t1)
    return np.array(t)


def ball_exact_gap(t, h0=1.0, e=0.8, g=G) -> np.ndarray:
    """Exact gap of the bouncing ball (m) at times ``t``; zero after the accumulation time."""
    t = np.asarray(t, float)
    t1 = math.sqrt(2.0 * h0 / g)
    v1 = g * t1
    out = np.where(t < t1, h0 - 0.5 * g * t**2, 0.0)
    t_zeno = t1 * (1.0 + e) / (1.0 - e) if e < 1.0 else math.inf
    k, tk = 1, t1
    while tk < min(t.max(initial=0.0), t_zeno) and k < 10_000:
        vk = e**k * v1
        t_next = tk + 2.0 * vk / g
        sel = (t >= tk) & (t < t_next)
        s = t[sel] - tk
        out[sel] = vk * s - 0.5 * g * s**2
        k, tk = k + 1, t_next
    return out


def pendulum_exact(t, e=0.5, length=1.0, g=G, n_impacts=60):
    """θ(t) of the uniform rigid bar released horizontal against a stop at the vertical
    (Jacobi's sn; after each impact 1 − cos θ_{k+1} = e²(1 − cos θ_k)), and the impact times.
    With ``e=None`` there is no stop: the free swing of amplitude π/2."""
    from scipy.special import ellipj, ellipk

    t = np.asarray(t, float)
    w0 = math.sqrt(1.5 * g / length)
    k0 = math.sin(math.pi / 4)
    K0 = ellipk(k0**2)
    if e is None:
        return 2.0 * np.arcsin(k0 * ellipj(K0 - w0 * t, k0**2)[0]), np.zeros(0)
    t_imp = [K0 / w0]
    amps, theta = [], math.pi / 2
    for _ in range(n_impacts):
        theta = math.acos(1.0 - e**2 * (1.0 - math.cos(theta)))
        amps.append(theta)
        if theta < 1e-12:
            break
        t_imp.append(t_imp[-1] + 2.0 * ellipk(math.sin(theta / 2) ** 2) / w0)
    out = np.zeros_like(t)
    first = t < t_imp[0]
    out[first] = 2.0 * np.arcsin(k0 * ellipj(K0 - w0 * t[first], k0**2)[0])
    for j in range(len(t_imp) - 1):
        k = math.sin(amps[j] / 2)
        sel = (t >= t_imp[j]) & (t < t_imp[j + 1])
        out[sel] = 2.0 * np.arcsin(k * ellipj(w0 * (t[sel] - t_imp[j]), k * k)[0])
    return out, np.array(t_imp)


def pressed_blocks(n_lower: int, n_upper: int, p: float, method="mortar", small=True):
    """The contact patch test: two blocks [0, 1] × [0, 0.5] and [0, 1] × [0.5, 1] (m) with
    ``n_lower`` and ``n_upper`` cells along x (non-matching meshes; the finer one is the
    mortar slave), the upper one
    three times stiffer, pressed by a uniform pressure p (Pa) on its top; the lower one
    rests on rollers at y = 0, both on rollers at x = 0; ``method`` of the contact, ``small``
    displacements or not (:func:`fecontact.statics.solve_static_contact`). Returns (the
    pair, the displacements of each block, the contact forces λ (N), the exact linear
    displacements of each block)."""
    from .bodies import Solid
    from .contact import Contact
    from .model import Model
    from .scenes import solid_material
    from .statics import solve_static_contact

    E_LOW, E_UP, NU = 1e7, 3e7, 0.3
    lower = Solid.rectangle(
        [0, 0], [1, 0.5], (n_lower, 3), solid_material("linear", E_LOW, NU, 1e3)
    )
    upper = Solid.rectangle(
        [0, 0.5], [1, 1.0], (n_upper, 3), solid_material("linear", E_UP, NU, 1e3)
    )
    lower.fix(lower.nodes_where(lambda x: x[1] < 1e-9), "y")
    for b in (lower, upper):
        b.fix(b.nodes_where(lambda x: x[0] < 1e-9), "x")
    if method == "mortar":
        pair = Contact(upper, lower, method="mortar")
    else:  # the face's nodes but its corners (at a corner the closest facet is a tie)
        face = upper.nodes_where(
            lambda x: (abs(x[1] - 0.5) < 1e-9) & (x[0] > 1e-9) & (x[0] < 1 - 1e-9)
        )
        pair = Contact(upper, lower, nodes=face, method="node-to-surface")
    model = Model([lower, upper], [pair], gravity=(0.0, 0.0))
    load = np.zeros(model.n)
    top = upper.nodes_where(lambda x: x[1] > 1 - 1e-9)
    top = top[np.argsort(upper.X[top, 0])]
    o = model.offset_of(upper)
    for a, b in zip(top[:-1], top[1:], strict=True):  # consistent nodal forces
        load[o + 2 * np.array([a, b]) + 1] -= 0.5 * p * (upper.X[b, 0] - upper.X[a, 0])
    q, lam = solve_static_contact(model, load, small=small)
    # plane strain, σ_yy = −p, σ_xx = 0 in both blocks
    exx, eyy = (lambda E: NU * (1 + NU) * p / E), (lambda E: -(1 - NU**2) * p / E)
    XL, XU = lower.X, upper.X
    u_low = np.stack([exx(E_LOW) * XL[:, 0], eyy(E_LOW) * XL[:, 1]], axis=1)
    u_up = np.stack([exx(E_UP) * XU[:, 0], eyy(E_LOW) * 0.5 + eyy(E_UP) * (XU[:, 1] - 0.5)], axis=1)
    parts = (q[model.body_slice(0)], q[model.body_slice(1)])
    # (the interface's own rows come first; the safeguard rows of its nodes follow)
    return pair, parts, lam[: pair.size], (u_low.ravel(), u_up.ravel())


def pressed_boxes(n_lower: int, n_upper: int, p: float, method="mortar", small=True):
    """The 3D contact patch test: boxes [0, 1]² × [0, 0.5] and [0, 1]² × [0.5, 1] (m) of
    tetrahedra, ``n_lower`` and ``n_upper`` cells along x and y (non-matching meshes), the
    upper (slave) one three times stiffer, pressed by a uniform pressure p (Pa) on its top;
    the lower one rests on rollers at z = 0, both on rollers at x = 0 and y = 0; ``method``
    of the contact (node-to-surface: the face's nodes off its edges). Returns (the pair, the
    displacements of each box, the contact forces λ (N), the exact linear displacements of
    each box)."""
    from .bodies import Solid
    from .contact import Contact
    from .model import Model
    from .scenes import solid_material
    from .statics import solve_static_contact

    E_LOW, E_UP, NU = 1e7, 3e7, 0.3
    lower = Solid.box([0, 0, 0], [1, 1, 0.5], (n_lower, n_lower, 2),
                      solid_material("linear", E_LOW, NU, 1e3))  # fmt: skip
    upper = Solid.box([0, 0, 0.5], [1, 1, 1.0], (n_upper, n_upper, 2),
                      solid_material("linear", E_UP, NU, 1e3))  # fmt: skip
    lower.fix(lower.nodes_where(lambda x: x[2] < 1e-9), "z")
    for b in (lower, upper):
        b.fix(b.nodes_where(lambda x: x[0] < 1e-9), "x")
        b.fix(b.nodes_where(lambda x: x[1] < 1e-9), "y")
    if method == "mortar":
        pair = Contact(upper, lower, method="mortar")
    else:  # the face's nodes off its edges (on an edge the closest facet is a tie)
        inner = upper.nodes_where(
            lambda x: (
                (abs(x[2] - 0.5) < 1e-9)
                & (np.min(np.abs(x[:2] - 0.5), axis=0) < 0.5 - 1e-9)
                & (np.max(np.abs(x[:2] - 0.5), axis=0) < 0.5 - 1e-9)
            )
        )
        pair = Contact(upper, lower, nodes=inner, method="node-to-surface")
    model = Model([lower, upper], [pair], gravity=(0.0, 0.0, 0.0))
    load = np.zeros(model.n)
    o = model.offset_of(upper)
    X = upper.X
    for tri in upper.boundary_facets():
        if np.all(X[tri, 2] > 1 - 1e-9):  # the top face: p A / 3 on each vertex
            area = 0.5 * np.linalg.norm(np.cross(X[tri[1]] - X[tri[0]], X[tri[2]] - X[tri[0]]))
            load[o + 3 * tri + 2] -= p * area / 3.0
    q, lam = solve_static_contact(model, load, small=small)
    # σ_zz = −p, the other stresses zero
    XL, XU = lower.X, upper.X
    u_low = np.stack([NU * p / E_LOW * XL[:, 0], NU * p / E_LOW * XL[:, 1],
                      -p / E_LOW * XL[:, 2]], axis=1)  # fmt: skip
    u_up = np.stack([NU * p / E_UP * XU[:, 0], NU * p / E_UP * XU[:, 1],
                     -p / E_LOW * 0.5 - p / E_UP * (XU[:, 2] - 0.5)], axis=1)  # fmt: skip
    parts = (q[model.body_slice(0)], q[model.body_slice(1)])
    # (the interface's own rows come first; the safeguard rows of its nodes follow)
    return pair, parts, lam[: pair.size], (u_low.ravel(), u_up.ravel())


def _p2_pair(upper, lower, method: str, face):
    """The contact of the P2 patch tests: "quadratic" (mortar on the curved faces), "split"
    (mortar on the faces split into linear pieces) or "node-to-surface" (the ``face`` nodes)."""
    from .contact import Contact
    from .contact.mortar import MortarContact
    from .contact.mortar3d import MortarContact3D
    from .contact.mortar3d_p2 import MortarContact3DP2
    from .contact.mortar_p2_segments import MortarContactP2

    if method == "node-to-surface":
        return Contact(upper, lower, nodes=upper.nodes_where(face), method=method)
    kinds = {"quadratic": (MortarContactP2, MortarContact3DP2),
             "split": (MortarContact, MortarContact3D)}  # fmt: skip
    return kinds[method][upper.dim - 2](upper, lower)


def pressed_p2_blocks(n_lower: int, n_upper: int, p: float = 1e5, method: str = "quadratic"):
    """The patch test of :func:`pressed_blocks` on P2 triangles, the upper block loaded by its
    consistent P2 nodal forces p L (1/6, 2/3, 1/6) per top edge; ``method`` of the contact
    (:func:`_p2_pair`; node-to-surface: the face's nodes but its corners). Returns the pair,
    λ (N), the nodal pressures of the contact face over p (None for node-to-surface) and
    the largest displacement error of either block relative to the exact linear field."""
    from .bodies import Solid
    from .model import Model
    from .scenes import solid_material
    from .statics import solve_static_contact

    E_LOW, E_UP, NU = 1e7, 3e7, 0.3
    mats = [solid_material("linear", E, NU, 1e3) for E in (E_LOW, E_UP)]
    lower = Solid.rectangle([0, 0], [1, 0.5], (n_lower, 3), mats[0], element="P2")
    upper = Solid.rectangle([0, 0.5], [1, 1.0], (n_upper, 3), mats[1], element="P2")
    lower.fix(lower.nodes_where(lambda x: x[1] < 1e-9), "y")
    for b in (lower, upper):
        b.fix(b.nodes_where(lambda x: x[0] < 1e-9), "x")

    def face(x):  # node-to-surface: the face's nodes but its corners
        return (abs(x[1] - 0.5) < 1e-9) & (x[0] > 1e-9) & (x[0] < 1 - 1e-9)

    pair = _p2_pair(upper, lower, method, face)
    model = Model([lower, upper], [pair], gravity=(0.0, 0.0))
    load = np.zeros(model.n)
    top = upper.nodes_where(lambda x: x[1] > 1 - 1e-9)
    top = top[np.argsort(upper.X[top, 0])]  # corner, mid, corner, ... along the top
    o = model.offset_of(upper)
    for a, m, b in zip(top[:-2:2], top[1:-1:2], top[2::2], strict=True):
        length = upper.X[b, 0] - upper.X[a, 0]
        load[o + 2 * np.array([a, m, b]) + 1] -= p * length * np.array([1 / 6, 2 / 3, 1 / 6])
    q, lam = solve_static_contact(model, load, small=True)
    exact = []
    for body, E in ((lower, E_LOW), (upper, E_UP)):
        y = body.X[:, 1]
        uy = -(1 - NU**2) * p * (np.minimum(y, 0.5) / E_LOW + np.maximum(y - 0.5, 0.0) / E_UP)
        exact.append(np.stack([NU * (1 + NU) * p / E * body.X[:, 0], uy], axis=1).ravel())
    height = None if method == "node-to-surface" else upper.X[:, 1]
    return _p2_results(model, pair, q, lam, exact, height, 0.5, p)


def _p2_results(model, pair, q, lam, exact, height, face: float, p: float):
    """(pair, λ, the face's pressures over p or None, the largest relative displacement
    error) of a P2 patch test."""
    error = max(np.max(np.abs(q[model.body_slice(k)] - u)) / np.max(np.abs(u))
                for k, u in enumerate(exact))  # fmt: skip
    lam = lam[: pair.size]  # the pair's own rows come first (then any safeguard rows)
    if height is None:  # node-to-surface: no pressure field
        return pair, lam, None, error
    nodes, z = pair.nodal_pressure(lam)
    return pair, lam, z[np.abs(height[nodes] - face) < 1e-9] / p, error


def pressed_p2_boxes(n_lower: int, n_upper: int, p: float = 1e5, method: str = "quadratic"):
    """The patch test of :func:`pressed_boxes` on P2 tetrahedra, the upper box loaded by the
    consistent P2 nodal forces p ∫ N_k dA of its top faces (corners 0, edge nodes a third of
    the face); ``method`` of the contact (:func:`_p2_pair`; node-to-surface: the face's
    nodes off its edges). Returns as
    :func:`pressed_p2_blocks`."""
    from .bodies import Solid
    from .contact.mortar3d_p2 import quadratic_triangles
    from .contact.mortar_p2 import reference_rule, shape_functions
    from .model import Model
    from .scenes import solid_material
    from .statics import solve_static_contact

    E_LOW, E_UP, NU = 1e7, 3e7, 0.3
    mats = [solid_material("linear", E, NU, 1e3) for E in (E_LOW, E_UP)]
    lower = Solid.box([0, 0, 0], [1, 1, 0.5], (n_lower, n_lower, 2), mats[0], element="P2")
    upper = Solid.box([0, 0, 0.5], [1, 1, 1.0], (n_upper, n_upper, 2), mats[1], element="P2")
    lower.fix(lower.nodes_where(lambda x: x[2] < 1e-9), "z")
    for b in (lower, upper):
        b.fix(b.nodes_where(lambda x: x[0] < 1e-9), "x")
        b.fix(b.nodes_where(lambda x: x[1] < 1e-9), "y")

    def inner(x):  # node-to-surface: the face's nodes off its edges
        return (abs(x[2] - 0.5) < 1e-9) & (np.max(np.abs(x[:2] - 0.5), axis=0) < 0.5 - 1e-9)

    pair = _p2_pair(upper, lower, method, inner)
    model = Model([lower, upper], [pair], gravity=(0.0, 0.0, 0.0))
    load = np.zeros(model.n)
    o, X = model.offset_of(upper), upper.X
    points, w = reference_rule("triangle")
    share = shape_functions("triangle", points).T @ w  # ∫ N_k dA / A
    for tri in quadratic_triangles(upper):
        if np.all(X[tri, 2] > 1 - 1e-9):
            area = 0.5 * np.linalg.norm(np.cross(X[tri[1]] - X[tri[0]], X[tri[2]] - X[tri[0]]))
            load[o + 3 * tri + 2] -= p * area * share
    q, lam = solve_static_contact(model, load, small=True)
    exact = []
    for body, E in ((lower, E_LOW), (upper, E_UP)):
        Xb = body.X
        uz = -p * (np.minimum(Xb[:, 2], 0.5) / E_LOW + np.maximum(Xb[:, 2] - 0.5, 0.0) / E_UP)
        exact.append(np.stack([NU * p / E * Xb[:, 0], NU * p / E * Xb[:, 1], uz], 1).ravel())
    height = None if method == "node-to-surface" else upper.X[:, 2]
    return _p2_results(model, pair, q, lam, exact, height, 0.5, p)


def roll_up(n: int, fraction: float, steps: int = 10):
    """Simo's roll-up: a cantilever (``Beam3D``, L = 1 m, EI = 10³ N·m², EA = 10⁷ N, n
    elements) under the end moment fraction × 2πEI/L, solved statically in ``steps`` load
    increments: (the tip's position in m, the static solution)."""
    from .bodies import Beam3D, Material, Section
    from .model import Model
    from .statics_rotations import solve_static_rotations

    material = Material(1e7, nu=0.0, rho=1.0)
    section = Section(area=1.0, inertia=1e-4, inertia_2=1e-4, torsion=2e-4)
    beam = Beam3D.straight([0, 0, 0], [1.0, 0, 0], n, material, section).clamp(0)
    model = Model([beam])
    load = np.zeros(model.n)
    load[-1] = fraction * 2.0 * np.pi * material.E * section.inertia
    sol = solve_static_rotations(model, load, steps=steps)
    return beam.positions(sol.q)[-1], sol


def block_on_rigid_box(method=None, p: float = 1e3):
    """A block 0.08 × 0.08 × 0.04 m (3 × 4 × 2 cells, E = 1 MPa) resting on a fixed rigid box,
    its top face loaded by a uniform pressure p (Pa, consistent nodal loads, no gravity),
    brought to rest by ρ∞ = 0 at steps far beyond its periods (100 steps of 5 ms); ``method``
    of the contact. Returns the contact force of each bottom node over the reference area it
    carries on the bottom face (Pa: p for the linear solution, which P1 holds exactly) and the
    largest speed left (m/s)."""
    from .bodies import RigidBody3D, Solid
    from .bodies.shapes3d import Box
    from .contact import Contact
    from .model import Model, NodalLoad
    from .scenes import solid_material
    from .time.settings import IntegratorOptions

    mat = solid_material("linear", 1e6, 0.3, 1e3)
    block = Solid.box([-0.04, -0.03, 0.0], [0.04, 0.05, 0.04], (3, 4, 2), mat)
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.05], Box(0.2, 0.2, 0.1)).fix()
    pair = Contact(block, box, method=method)
    f, X = block.contact_facets(), block.X
    area = 0.5 * np.linalg.norm(np.cross(X[f[:, 1]] - X[f[:, 0]], X[f[:, 2]] - X[f[:, 0]]), axis=1)

    def share(z):  # the area each node carries on the face at height z (m²)
        face = np.all(np.abs(X[f][..., 2] - z) < 1e-12, axis=1)
        return np.bincount(f[face].ravel(), np.repeat(area[face] / 3, 3), block.n_nodes)

    top, bottom = share(0.04), share(0.0)
    loads = [NodalLoad(block, j, [0.0, 0.0, -p * top[j]]) for j in np.flatnonzero(top)]
    model = Model([block, box], [pair], (0.0, 0.0, 0.0), loads=loads)
    st = list(simulate(model, 5e-3, 0.5, IntegratorOptions(rho_inf=0.0)))[-1]
    on = bottom[pair.nodes] > 0.0
    # (the pair's rows first: a box's corner rows follow them)
    return st.mean_force()[: pair.size][on] / bottom[pair.nodes][on], float(np.abs(st.v).max())
