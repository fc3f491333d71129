"""Elastic ball on a rigid plane against Hertz's theory: mesh, step and size convergence.

``cases/ball_drop.py`` without gravity: the ball (R = 0.05 m, E = 10 MPa, ν = 0.3,
ρ = 1000 kg/m³, linear elastic) touches the plane at t = 0 moving at v toward it. Hertz
(quasi-static, frictionless, rigid plane): with E* = E/(1 − ν²) and the ball's mass m,

    δ_max = (15 m v² / (16 E* √R))^{2/5},   F_max = 4/3 E* √R δ_max^{3/2},
    t_c = 2.87 (m² / (R E*² v))^{1/5},      v_out / v = 1,

and statically δ = (3F / (4E*√R))^{2/3}. m is the finite element mass. Hertz's δ is the
approach of points far from a contact patch small against the bodies: his theory is the limit
a/R → 0, and a/R = (3.93 ρv²/E*)^{1/5} grows with the impact speed (0.20 at 1 m/s, 0.032 at
0.01 m/s). A finite ball differs from it at first order in a/R; three series measure this:

- static: the discrete Signorini problem of a ball pressed on the plane by a uniform body
  force of total F (the inertia of a rigidly decelerating ball; ``static_contact``, solved
  exactly), at four loads 8× apart (a halves from one to the next), on meshes graded toward
  the pole to a fixed fraction of each load's contact radius. The error of the centre of
  mass's approach against Hertz, and C = (δ_Hertz − δ) E R / F: a bulk term linear in F.
- slow: impacts at 0.01 m/s on P1 balls graded to a_max and a_max/2 at the pole, P2 balls
  graded to 2 a_max and a_max, and the latter at twice the step and the P1 a_max/2 ball at
  2, 4, 8 and 16 times it.
- fast: impacts at 1 m/s, on uniform quadratic isoparametric tetrahedra (P2, the boundary
  curved onto the sphere; refinements 1–3, and each at h/2), uniform P1 (a polyhedral ball)
  of the same node counts, and graded P1 balls.

Measured per impact, with no other force than the plane's acting (total momentum p changes
only by the impulses Σ_j k Λ_j):

- t_c: the end of the last step with an active contact (the contact starts at t = 0);
- F_max: the peak of the mean force Δp/Δt over a window of t_c/20 (Hertz's t_c; whole
  steps). The mean of the Hertz pulse over such a window at its peak is 0.15 % below F_max.
  The per-step force Σ k Λ_j / h is also listed ("per step"): it is noisy, since a ring of
  nodes entering contact takes its momentum in one step;
- δ_max: the largest approach of the ball's centre of mass toward the plane;
- v_out / v: the rebound speed of the centre of mass over the impact speed;
- static δ error: the same mesh's static approach under Hertz's F_max (``static_contact``)
  against Hertz's: the quasi-static law the impact follows;
- how well the contact zone is resolved: Δx, the shortest distance between nodes, against
  Hertz's largest contact radius a_max, and the largest number of nodes in contact at once.

Graded balls (``graded_mesh``): scikit-fem's ``init_ball(3)`` (6.25 mm edges; ``init_ball(2)``,
12.5 mm, for the P2 impacts) with its tetrahedra bisected until each edge is below
Δx + 0.5 × the distance from the pole.

The step is the largest power of two (in s) below 0.15 of the dilatational transit time across
the shortest distance between nodes (the shortest edge, half of it for P2): every step then has
the same h to the last bit. The "h/2" and "2h", "4h" rows change it. The detection margin is
1 % of the model size.

    python benchmarks/hertz.py                    # all three series
    python benchmarks/hertz.py --series static    # one of them (static, slow, fast)
    python benchmarks/hertz.py --quick            # one coarse P1 ball at 1 m/s (seconds)
    python benchmarks/hertz.py --quick --series static,slow,steps   # the first row of each
    python benchmarks/hertz.py --from-csv         # rewrite the tables from the CSV files
    python benchmarks/hertz.py --workers 2        # the rows on a local Dask cluster
"""

from __future__ import annotations

import math
import sys
import time
from functools import partial

import numpy as np
from _common import (
    case,
    machine_note,
    map_runs,
    markdown_table,
    parser,
    read_csv,
    write_csv,
    write_markdown,
)
from scipy.integrate import quad
from scipy.optimize import brentq

from fecontact import (
    Contact,
    IntegratorOptions,
    LinearElastic,
    Model,
    Plane,
    Solid,
    simulate,
    statics,
)
from fecontact.bodies.meshes import graded_ball_mesh

RADIUS, E, NU, RHO, V = 0.05, 1e7, 0.3, 1000.0, 1.0
E_STAR = E / (1.0 - NU**2)
SPHERE_MASS = 4.0 / 3.0 * math.pi * RADIUS**3 * RHO
WINDOW = 1.0 / 20.0  # of Hertz's contact duration
FINITE_SIZE_C = 0.42  # C of the P2 rows at a/R = 0.20 and 0.10 (hertz_static.md)
GRADING = 0.5  # growth of the graded meshes' edge length with the distance from the pole


def hertz(mass: float, v: float = V) -> dict:
    """Hertz's contact duration (s), peak force (N) and approach (m) for the ball at ``v`` (m/s)."""
    delta = (15.0 * mass * v**2 / (16.0 * E_STAR * math.sqrt(RADIUS))) ** 0.4
    return {
        "t_c": 2.87 * (mass**2 / (RADIUS * E_STAR**2 * v)) ** 0.2,
        "F_max": 4.0 / 3.0 * E_STAR * math.sqrt(RADIUS) * delta**1.5,
        "delta": delta,
    }


def hertz_approach(force: float) -> float:
    """Hertz's static approach (m) of the ball pressed on the plane by ``force`` (N)."""
    return (3.0 * force / (4.0 * E_STAR * math.sqrt(RADIUS))) ** (2.0 / 3.0)


def contact_radius(v: float) -> float:
    """Hertz's largest contact radius a_max = √(R δ_max) (m) of the sphere's impact at ``v``."""
    return math.sqrt(RADIUS * hertz(SPHERE_MASS, v)["delta"])


def finite_ball(mass: float, v: float, c: float = FINITE_SIZE_C) -> dict:
    """Hertz's quasi-static impact with the finite ball's bulk term: contact duration (s),
    peak force (N) and approach (m) of a mass at ``v`` on the law δ(F) = δ_Hertz(F) − c F/(E R)
    (``hertz_static.md``). With c = 0 it is Hertz's impact (t_c to 0.1 % of the rounded 2.87)."""
    a, b = (3.0 / (4.0 * E_STAR * math.sqrt(RADIUS))) ** (2.0 / 3.0), c / (E * RADIUS)

    def work(f):  # ∫ F dδ from 0 to f
        return 0.4 * a * f ** (5.0 / 3.0) - 0.5 * b * f * f

    f_max = brentq(lambda f: work(f) - 0.5 * mass * v * v, 0.0, 4.0 * hertz(mass, v)["F_max"])

    def dt(theta):  # dδ/v with F = F_max sin²θ, which removes both ends' singularities
        f = f_max * math.sin(theta) ** 2
        speed = math.sqrt(max(v * v - 2.0 * work(f) / mass, 0.0))
        slope = 2.0 / 3.0 * a * f ** (-1.0 / 3.0) - b
        return slope * 2.0 * f_max * math.sin(theta) * math.cos(theta) / speed if f > 0 else 0.0

    t_c = 2.0 * quad(dt, 0.0, 0.5 * math.pi, limit=200)[0]
    return {"t_c": t_c, "F_max": f_max, "delta": a * f_max ** (2.0 / 3.0) - b * f_max}


def windowed_peak(p: np.ndarray, h: float, window: float) -> float:
    """max over t of (p(t + w) − p(t)) / w, w the whole number of steps nearest ``window``."""
    k = max(1, round(window / h))
    return float(np.max(p[k:] - p[:-k]) / (k * h))


def static_contact(ball, force: float) -> tuple[float, int]:
    """(approach of the centre of mass (m), nodes in contact) of ``ball`` (linear, lowest
    point on the plane z = 0) in equilibrium under a uniform body force of total ``force``
    (N) along −z, the inertia of a rigidly decelerating ball, and the plane's nodal
    reactions (``fecontact.statics.static_contact``: the discrete Signorini problem of the
    nodes within three Hertz approaches of the plane, solved exactly)."""
    M, ez = ball.mass_matrix(), ball.translation_field((0.0, 0.0, 1.0))
    load = -(force / ball.mass) * (M @ ez)
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    u, touching = statics.static_contact(ball, load, floor, 3.0 * hertz_approach(force))
    return -float((M @ ez) @ u) / ball.mass, touching.size


def graded_mesh(spacing: float, base: int = 3, grading: float = GRADING, element="P1"):
    """The ball of radius R centred at (0, 0, R), graded toward its pole (0, 0, 0)
    (``graded_ball_mesh``; P2: quadratic cells, curved boundary)."""
    centre = [0.0, 0.0, RADIUS]
    quadratic = element == "P2"
    return graded_ball_mesh(centre, RADIUS, spacing, [0.0] * 3, grading, base, quadratic)


def uniform_case(element: str, refinements: int, v: float = V):
    """``ball_drop`` without gravity, touching the plane at t = 0 at ``v``: (model, options, v0)."""
    sim = case("ball_drop").build(
        radius=RADIUS, refinements=refinements, element=element, E=E, nu=NU, rho=RHO,
        drop_height=0.0, velocity=v, gravity=0.0, t_end=1.0,
    )  # fmt: skip
    return sim.model, sim.options, sim.v0


def graded_case(spacing: float, element: str = "P1", v: float = V, base: int = 3):
    """``ball_drop``'s model (no gravity, e_N = 0, ρ∞ = 0.5) on ``graded_mesh``:
    (model, options, v0)."""
    mesh = graded_mesh(spacing, base, element=element)
    ball = Solid(mesh, LinearElastic(E=E, nu=NU, rho=RHO), element=element)
    floor = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=4.0 * RADIUS)
    model = Model([ball], [Contact(ball, floor, restitution=0.0)], gravity=(0.0, 0.0, 0.0))
    return model, IntegratorOptions(rho_inf=0.5), model.translation(ball, (0.0, 0.0, -v))


def node_spacing(ball) -> float:
    """The shortest distance between nodes (m): the shortest edge, half of it for P2."""
    return ball.min_edge_length / (2.0 if ball.element == "P2" else 1.0)


def base_step(ball) -> float:
    """The largest power of two (s) below 0.15 of the dilatational transit time across
    ``node_spacing``: every step of a run then has the same h to the last bit."""
    return 2.0 ** math.floor(math.log2(0.15 * node_spacing(ball) / ball.material.wave_speed))


def located_impact(element: str, refinements: int, steps, localize):
    """One impact of the uniform ball at 1 m/s closing 0.37 of a step into its third step,
    at h = t_c/``steps`` (None: ``base_step``) with ``localize``, run until 0.1 t_c after its
    last step with a contact force: (the ball, the last state, the run's statistics, the
    end of that last pressed step (s), h (s))."""
    from fecontact.time import StepStats

    model, options, v0 = uniform_case(element, refinements)
    ball = model.bodies[0]
    t_c = hertz(ball.mass)["t_c"]
    h = base_step(ball) if steps is None else t_c / steps
    q0 = model.translation(ball, (0.0, 0.0, 2.37 * h * V))
    options.detection_margin, options.localize = 0.01, localize
    stats, last, after = StepStats(), 0.0, 0
    for st in simulate(model, h, 3 * t_c, options, q0=q0, v0=v0, stats=stats):
        if st.step and st.pressed().any():
            last, after = st.t, 0
        elif last and (after := after + 1) * h > 0.1 * t_c:
            break
    return ball, st, stats, last, h


def measure(setup, v: float = V, dt_factor: float = 1.0, static: bool = True) -> dict:
    """One impact at ``v`` of the ball of ``setup`` = (model, options, v0): duration, peak
    force, approach and rebound with Hertz's values, and (``static``) the same mesh's static
    approach under Hertz's peak force."""
    model, options, v0 = setup
    ball = model.bodies[0]
    ref = hertz(ball.mass, v)
    spacing = node_spacing(ball)
    dt = base_step(ball) * dt_factor
    options.detection_margin = 0.01
    w = ball.mass_matrix() @ ball.translation_field((0.0, 0.0, 1.0))  # z-momentum weights
    momentum, approach, per_step, touching = [], [], [], []
    t_last, after, steps = 0.0, 0, 0
    start = time.perf_counter()
    for st in simulate(model, dt, 3.0 * ref["t_c"], options, v0=v0):
        momentum.append(float(w @ st.v))
        approach.append(-float(w @ st.q) / ball.mass)
        if st.step == 0:
            continue
        steps += 1
        per_step.append(float(st.impulse.sum()) / st.h)
        touching.append(int(np.count_nonzero(st.pressed())))
        if st.pressed().any():
            t_last, after = st.t, 0
        else:
            after += 1
            if after * dt > 0.1 * ref["t_c"]:  # left the plane for good
                break
    wall = time.perf_counter() - start
    delta_static = static_contact(ball, ref["F_max"])[0] if static else math.nan
    p = np.array(momentum)
    f_window = windowed_peak(p, dt, WINDOW * ref["t_c"])
    delta = max(approach)

    def error(x, exact):
        return 100.0 * (x / exact - 1.0)

    return {
        "v": v,
        "a_per_R": math.sqrt(ref["delta"] / RADIUS),
        "dofs": model.n,
        "contact_nodes": model.contacts.size,
        "spacing_mm": 1e3 * spacing,
        "a_per_spacing": math.sqrt(RADIUS * ref["delta"]) / spacing,
        "touching_max": max(touching),
        "dt_us": 1e6 * dt,
        "dt_per_transit": dt * ball.material.wave_speed / spacing,
        "steps": steps,
        "t_c_ms": 1e3 * t_last,
        "t_c_hertz_ms": 1e3 * ref["t_c"],
        "t_c_error_pct": error(t_last, ref["t_c"]),
        "F_max_N": f_window,
        "F_max_hertz_N": ref["F_max"],
        "F_max_error_pct": error(f_window, ref["F_max"]),
        "F_step_error_pct": error(max(per_step), ref["F_max"]),
        "delta_mm": 1e3 * delta,
        "delta_hertz_mm": 1e3 * ref["delta"],
        "delta_error_pct": error(delta, ref["delta"]),
        "delta_static_error_pct": error(delta_static, hertz_approach(ref["F_max"])),
        "rebound": p[-1] / (ball.mass * v),
        "wall_s": wall,
    }


COLUMNS = [
    "element", "refinements", "v", "a_per_R", "dofs", "contact_nodes", "spacing_mm",
    "a_per_spacing", "touching_max", "dt_us", "steps", "t_c_ms",
    "t_c_hertz_ms", "t_c_error_pct", "F_max_N", "F_max_hertz_N", "F_max_error_pct",
    "F_step_error_pct", "delta_mm", "delta_hertz_mm", "delta_error_pct",
    "delta_static_error_pct", "rebound", "wall_s",
]  # fmt: skip
HEADERS = [
    "element", "mesh", "v (m/s)", "a_max / R", "dofs", "boundary nodes", "Δx (mm)",
    "a_max / Δx", "nodes in contact (max)", "h (µs)", "steps", "t_c (ms)",
    "Hertz t_c (ms)", "t_c error (%)", "F_max (N)", "Hertz F_max (N)", "F_max error (%)",
    "per-step F_max error (%)", "δ_max (mm)", "Hertz δ_max (mm)", "δ_max error (%)",
    "static δ error (%)", "v_out / v", "wall (s)",
]  # fmt: skip
STATIC_COLUMNS = [
    "element", "mesh", "force_N", "a_per_R", "dofs", "spacing_mm", "a_per_spacing",
    "touching", "delta_um", "delta_hertz_um", "delta_error_pct", "finite_size_C", "wall_s",
]  # fmt: skip
STATIC_HEADERS = [
    "element", "mesh", "F (N)", "a / R", "dofs", "Δx (mm)", "a / Δx", "nodes in contact",
    "δ (µm)", "Hertz δ (µm)", "δ error (%)", "C = (δ_H − δ) E R / F", "wall (s)",
]  # fmt: skip


def static_row(element: str, force: float, per_radius: float, base: int = 3) -> dict:
    """The static law at ``force`` (N) on a ball graded to Δx = a / ``per_radius`` at the pole,
    a Hertz's contact radius at that force."""
    a = math.sqrt(RADIUS * hertz_approach(force))
    start = time.perf_counter()
    mesh = graded_mesh(a / per_radius, base, element=element)
    ball = Solid(mesh, LinearElastic(E=E, nu=NU, rho=RHO), element=element)
    spacing = ball.min_edge_length / (2.0 if element == "P2" else 1.0)
    delta, touching = static_contact(ball, force)
    exact = hertz_approach(force)
    return {
        "element": element,
        "mesh": f"base {base}, graded to a/{per_radius:g}",
        "force_N": force,
        "a_per_R": a / RADIUS,
        "dofs": ball.ndof,
        "spacing_mm": 1e3 * spacing,
        "a_per_spacing": a / spacing,
        "touching": touching,
        "delta_um": 1e6 * delta,
        "delta_hertz_um": 1e6 * exact,
        "delta_error_pct": 100.0 * (delta / exact - 1.0),
        "finite_size_C": (exact - delta) * E * RADIUS / force,
        "wall_s": time.perf_counter() - start,
    }


READING = """\
Reading (measured when this file was written). At 1 m/s the contact radius is a fifth of the
ball's (a_max/R = 0.20) and the finite ball's static law is 12.6 % short of Hertz's δ at the
peak force (``hertz_static.md``): the continuum's quasi-static impact is t_c −7.6 %,
F_max +11.3 %, δ_max −6.6 % from Hertz (``finite_ball``, C = 0.42). The meshes converge toward
that, not toward Hertz; the 0.01 m/s series (``hertz_slow.md``) is where Hertz is the limit.

- Resolution of the contact zone. At P2 refinement 1 (node spacing 12.5 mm against
  a_max ≈ 10 mm) only the pole node ever touches: a point load, soft (F_max −19 %, static law
  +13 %). At refinement 2 (6.25 mm) the pole touches alone until 0.22 t_c, then a ring of four
  nodes enters at once; with e_N = 0 at each node the ring is stopped within a step and the
  contact stiffness jumps from one node to five, so the force overshoots (+20 %) while the
  approach stays within 3 %. Refinement 3 (3.1 mm, up to 17 nodes in contact) covers the
  patch with several rings. P1 meshes with the same nodes show the same sequence.
- Time step. Halving h moves t_c, F_max and δ_max by at most 1.6 points at the coarse meshes
  and 0.3 at P2 refinement 3.
- Each impact follows the static law of its own mesh (last error column). A law s short of
  Hertz's in δ scales t_c and δ_max by (1 − s)^{3/5} and F_max by (1 − s)^{−3/5}: P2
  refinement 3 (static −11.5 %) predicts t_c −7.1 %, F_max +7.6 %, δ_max −7.1 % against
  −6.6 %, +7.1 %, −7.0 % measured; P1 refinement 4 (−12.1 %) predicts −7.4 %, +8.0 %, −7.4 %
  against −6.2 %, +8.8 %, −6.2 %. The rest, a point or so, is dynamics: t_c is only about
  three periods of the ball's lowest mode, and 0.2–1.3 % of the kinetic energy stays in
  vibration or is damped (v_out/v = 0.987–0.998).
- The finest P2 mesh's static law (−11.5 %) is within 1.1 points of the continuum's
  (−12.6 %), and its t_c within 1 point of the finite ball's. The graded P1 balls come from
  the stiff side: static −15.4, −15.4, −13.5 % and t_c −8.4, −8.4, −7.3 % at a_max/2.5, /5,
  /10 (the linear elements in the graded region)."""


SLOW_READING = """\
Reading (measured when this file was written). At 0.01 m/s the patch is small
(a_max/R = 0.032): the finite ball's quasi-static law (``hertz_static.md``, C = 0.42) puts
the continuum's impact at t_c −1.2 %, F_max +1.5 %, δ_max −1.0 % from Hertz (``finite_ball``).

- P2 balls converge on it. Graded to 2 a_max (9 nodes in contact at most) the ball is soft
  (static law −0.6 %; t_c +0.3 %, F_max +4.2 %, δ_max +2.0 %); graded to a_max (its static law
  −3.2 %, 1.2 points beyond the continuum's −2.0 %) it lands at t_c −1.8 %, F_max +1.9 %,
  δ_max −1.5 %: within 0.6 points of the finite ball and 1.9 % of Hertz. At twice the step it
  gives −1.3 %, +1.2 %, −0.9 %. The next refinement (a_max/2, 23,000 dofs) takes 71,000 steps
  (the step is tied to the contact zone's Δx, last point) and was not run.
- The impact follows the static law of its mesh. A law s short of Hertz's in δ scales t_c and
  δ_max by (1 − s)^{3/5} and F_max by (1 − s)^{−3/5}: the P1 balls' static −4.8 % (a_max) and
  −6.1 % (a_max/2) predict t_c −2.9 % and −3.7 %; measured −2.0 % and −4.2 %.
- P1 meshes do not reach the continuum's law by refining the pole alone: their static law
  stays 5.9–7.3 % short at a_max/4 and a_max/8 (``hertz_static.md``), the error of the
  linear elements in the graded region, where P2 settles at −1.9 %.
- The step. At a_max/2 (P1), t_c is −4.2, −3.7, −2.2, +2.7 and +14.6 % at h, 2h, 4h, 8h and
  16h (h = 0.15 Δx/c, so 0.15 to 2.4 Δx/c), δ_max −4.4 % to +19 %: a persistent contact
  passes its force only through the velocity jumps (the smooth step carries none), and once
  the step exceeds the transit time of the contact zone's elements the jumps take too little
  momentum per step and the patch yields. Contact between solids needs h ≲ 0.3 Δx/c where they
  touch; the solid cases step at Δx/8c to Δx/16c."""
STEPS_READING = """\
Reading (measured when this file was written). Deviations are from the same mesh's finest
step with the smooth contact force (``smooth_contact="on"``, the default for solids).

- With the smooth contact force the impact does not depend on the step from 0.13 to 16 Δx/c:
  t_c, F_max and δ_max stay within 0.44 % of the finest step on both meshes (P1 graded to
  a_max, P2 graded to 2 a_max). At h = t_c/50 (41 and 42 Δx/c, 55 and 56 steps) F_max and
  δ_max are within 0.2 % and t_c within 0.47 % and 0.06 %: t_c is read at the end of a
  step, so its resolution there is one step, 2 % of t_c.
- Without it (``"off"``, the fully decoupled scheme) the P1 ball at 0.51, 2.05 and 8.2 Δx/c
  gives t_c +4.8, +34 and +201 % and δ_max +6.5, +41 and +124 % from the same finest run: the
  pressed nodes sink in every smooth step and the patch yields."""
READINGS = {"fast": READING, "slow": SLOW_READING, "steps": STEPS_READING}
TITLE = "Elastic ball on a rigid plane against Hertz"
STATIC_READING = """\
Reading (measured when this file was written).

- Hertz is the limit. The P2 balls, resolved to a/Δx = 13 at every load, approach the plane
  12.6, 6.4, 3.3 and 1.75 % less than Hertz's δ as a/R halves from 0.20 to 0.026: the error
  halves with a/R, first order, toward zero.
- The finite ball's bulk term. C = (δ_Hertz − δ) E R / F stays at 0.42–0.47 over a 512-fold
  load range: the ball's centre of mass approaches by Hertz's half-space value less a term
  C F/(E R) linear in the load, whose share of δ is ∝ F^{1/3} ∝ a/R. Its size is that of
  Boussinesq's point-load solution at the centre's depth: a half-space point at depth R
  below the load is pushed (3 − 2ν)(1 + ν)/(2π) F/(E R) = 0.50 F/(E R) along it (ν = 0.3),
  so it approaches the plane by that much less than the distant points of Hertz's δ. The
  term is 12.6 % of δ at the peak of the 1 m/s impact and about 2 % at 0.01 m/s.
- C rises a little (0.42 to 0.47) as the load falls: the mesh's own error, about −0.15 % of
  δ at a/Δx = 13, weighs more against a smaller bulk term.
- Mesh convergence at the 0.01 m/s peak load (1.25 N, a/R = 0.032): P2 balls graded to
  a, a/2, a/4, a/8 give −2.9, −2.4, −1.9 and −1.9 %, settling on the bulk term (C = 0.42
  predicts −2.0 %).
- Linear tetrahedra are stiffer. The P1 balls at the same a/Δx approach 13.5, 8.5, 5.8 and
  4.6 % less than Hertz: 1–3 points beyond the P2 values, an error of the grading (edges
  growing as half the distance from the pole) that refining the pole alone does not remove."""


def report(rows, out, stem, reading, title=TITLE, columns=COLUMNS, headers=HEADERS) -> str:
    """Write ``stem``.csv and ``stem``.md into ``out``; return the Markdown table."""
    table = markdown_table(rows, columns, headers)
    write_csv(f"{out}/{stem}.csv", rows, columns)
    intro = __doc__.split("\n\n", 1)[1].split("    python")[0].strip()
    note = f"\n\nMachine: {machine_note()}\n"
    write_markdown(f"{out}/{stem}.md", f"# {title}\n\n{intro}\n\n{table}\n\n{reading}{note}")
    return table


# impacts at v = 1 m/s: (label, element, uniform refinements or graded spacing / a_max, h factor)
FAST = [
    ("uniform", "P2", 1, 1.0), ("uniform", "P2", 1, 0.5), ("uniform", "P2", 2, 1.0),
    ("uniform", "P2", 2, 0.5), ("uniform", "P2", 3, 1.0), ("uniform", "P2", 3, 0.5),
    ("uniform", "P1", 2, 1.0), ("uniform", "P1", 3, 1.0), ("uniform", "P1", 4, 1.0),
    ("graded", "P1", 2.5, 1.0), ("graded", "P1", 5, 1.0), ("graded", "P1", 10, 1.0),
]  # fmt: skip
SLOW_V = 0.01  # m/s: a_max/R = 0.032, where Hertz's half-space is the ball's limit
# the step sweep at 0.01 m/s: (element, graded spacing / a_max, h factors (0: t_c/50),
# scheme); each mesh's first row is its finest step with the smooth contact force
STEP_SWEEP = [
    ("P1", 1, (1.0, 4.0, 16.0, 64.0, 128.0, 0.0), "on"),
    ("P1", 1, (4.0, 16.0, 64.0), "off"),
    ("P2", 0.5, (4.0, 16.0, 64.0, 128.0, 0.0), "on"),
]
STEP_COLUMNS = [
    "element", "refinements", "scheme", "dofs", "dt_us", "dt_per_transit", "steps", "t_c_ms",
    "t_c_dev_pct", "F_max_N", "F_dev_pct", "delta_mm", "delta_dev_pct", "t_c_error_pct",
    "F_max_error_pct", "delta_error_pct", "rebound", "wall_s",
]  # fmt: skip
STEP_HEADERS = [
    "element", "mesh", "smooth contact", "dofs", "h (µs)", "h / (Δx/c)", "steps", "t_c (ms)",
    "t_c vs finest (%)", "F_max (N)", "F_max vs finest (%)", "δ_max (mm)",
    "δ_max vs finest (%)", "t_c vs Hertz (%)", "F_max vs Hertz (%)", "δ_max vs Hertz (%)",
    "v_out / v", "wall (s)",
]  # fmt: skip


def step_sweep(quick: bool, each=map_runs) -> list[dict]:
    """The 0.01 m/s impact of graded P1 and P2 balls from a fine step to t_c/50, with and
    without the smooth contact force; deviations from each mesh's finest smooth run.
    ``each(fn, items)`` runs the rows (one after another, or ``map_runs`` on workers)."""
    runs = [
        (element, size, factor, scheme)
        for element, size, factors, scheme in STEP_SWEEP
        for factor in (factors[:1] if quick else factors)
    ]
    rows = each(lambda r: impact_row("graded", r[0], r[1], r[2], SLOW_V, r[3]), runs)
    finest = {}
    for (element, size, _, _), row in zip(runs, rows, strict=True):
        ref = finest.setdefault((element, size), row)
        for key, name in (("t_c_ms", "t_c"), ("F_max_N", "F"), ("delta_mm", "delta")):
            row[f"{name}_dev_pct"] = 100.0 * (row[key] / ref[key] - 1.0)
    return rows


SLOW = [("graded", "P1", n, 1.0) for n in (1, 2)] + [("graded", "P2", n, 1.0) for n in (0.5, 1)]
SLOW += [("graded", "P2", 1, 2.0)] + [("graded", "P1", 2, f) for f in (2.0, 4.0, 8.0, 16.0)]
# static law: (element, a / Δx, Hertz's F_max at 1 m/s over this): the loads 8x apart (a
# halves with each) on meshes graded to a fixed fraction of each load's contact radius; then
# the peak load at 0.01 m/s (F_max at 1 m/s over 251) on four refinements
STATIC = [("P2", 4.0, 8.0**k) for k in range(4)] + [("P1", 8.0, 8.0**k) for k in range(4)]
STATIC += [(el, n, (1.0 / SLOW_V) ** 1.2) for el in ("P2", "P1") for n in (1.0, 2.0, 4.0, 8.0)]


def impact_row(
    kind: str, element: str, size: float, factor: float, v: float, scheme: str = "auto"
) -> dict:
    """One row of an impact series (``measure`` with the mesh's label). Graded P2 balls start
    from ``init_ball(2)``: their quadratic cells hold the bulk's share (C, ``hertz_static.md``)
    as the finer P1 base does. ``scheme`` is the ``smooth_contact`` option; a ``factor`` of
    0 means the step t_c/50 (Hertz's t_c)."""
    if kind == "uniform":
        setup, label = uniform_case(element, int(size), v), f"uniform {int(size)}"
    else:
        base = 2 if element == "P2" else 3
        setup = graded_case(contact_radius(v) / size, element, v, base)
        label = f"base {base}, graded to a_max/{size:g}"
    setup[1].smooth_contact = scheme
    step = {1.0: "", 0.5: " (h/2)", 0.0: " (t_c/50)"}.get(factor, f" ({factor:g}h)")
    if factor == 0.0:
        factor = hertz(setup[0].bodies[0].mass, v)["t_c"] / 50.0 / base_step(setup[0].bodies[0])
    row = measure(setup, v, factor, static=factor == 1.0)
    row["scheme"] = scheme
    row["element"], row["refinements"] = element, label + step
    print(
        f"{element} {row['refinements']} v {v}: t_c {row['t_c_error_pct']:+.2f} %, F_max "
        f"{row['F_max_error_pct']:+.2f} %, delta {row['delta_error_pct']:+.2f} %, static "
        f"{row['delta_static_error_pct']:+.2f} %, {row['wall_s']:.0f} s",
        file=sys.stderr,
        flush=True,
    )
    return row


def main(argv=None) -> int:
    p = parser(__doc__.splitlines()[0])
    p.add_argument(
        "--series",
        default="static,slow,fast",
        help="comma-separated: static (the meshes' static law), slow (impacts at 0.01 m/s), "
        "fast (impacts at 1 m/s), steps (the step sweep at 0.01 m/s, not in the default); "
        "each writes its own table",
    )
    p.add_argument(
        "--from-csv",
        action="store_true",
        help="rewrite the Markdown tables from the CSV files of an earlier run, running nothing",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=1,
        help="run the rows on a local Dask cluster of this many processes (the wall-time "
        "column is then measured on a machine the rows share)",
    )
    args = p.parse_args(argv)
    each = partial(map_runs, workers=args.workers)
    series = args.series.split(",")
    fast = FAST
    if args.quick:  # a tiny run of each series asked for, the fast one by default
        series = ["fast"] if args.series == p.get_default("series") else series
        fast = [("uniform", "P1", 1, 1.0)]
    if "static" in series:
        f1 = hertz(SPHERE_MASS)["F_max"]
        runs = STATIC[:1] if args.quick else STATIC
        stem = "hertz_static" + ("_quick" if args.quick else "")
        if args.from_csv:
            rows = read_csv(f"{args.out}/{stem}.csv")
        else:
            rows = each(lambda run: static_row(run[0], f1 / run[2], run[1]), runs)
        title = "The meshed ball's static force–approach law against Hertz"
        print(report(rows, args.out, stem, STATIC_READING, title, STATIC_COLUMNS, STATIC_HEADERS))
    for name, runs, v in (("slow", SLOW, SLOW_V), ("fast", fast, V)):
        if name not in series:
            continue
        runs = runs[:1] if args.quick else runs
        stem = ("hertz" if name == "fast" else "hertz_slow") + ("_quick" if args.quick else "")
        if args.from_csv:
            rows = read_csv(f"{args.out}/{stem}.csv")
        else:
            rows = each(lambda run, v=v: impact_row(*run, v), runs)
        print(report(rows, args.out, stem, READINGS[name]))
    if "steps" in series:
        stem = "hertz_steps" + ("_quick" if args.quick else "")
        if args.from_csv:
            rows = read_csv(f"{args.out}/{stem}.csv")
        else:
            rows = step_sweep(args.quick, each)
        title = "Hertz impact at 0.01 m/s: the step, with and without the smooth contact force"
        print(report(rows, args.out, stem, STEPS_READING, title, STEP_COLUMNS, STEP_HEADERS))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
