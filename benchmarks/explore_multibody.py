"""Rigid multibody systems in space on configurations the cases do not run, against exact answers.

Every row is one configuration with an exact or invariant answer (``_multibody_exact.py``):
its status, steps, the fallbacks summary.json counts, the energy ledger's created energy over
its scale, the compared quantity (exact, measured, relative error; ``order`` where the row
runs several steps), and for contacts the largest change of the centres over the body's size
with p ×1000 and with k ÷100 (the converged answer does not depend on them).

Groups:

- ``free``: torque-free bodies (no gravity): the intermediate-axis flip's half period
  2K(k)/λ on either side of the separatrix, with the energy and the spatial angular momentum
  H = R J Ω; a symmetric disk's body rate Ω(t) (Euler's precession ν = (C − A)Ω₃/A) at three
  steps.
- ``top``: the heavy top of ``cases/heavy_top.py`` at other tilts and spins: steady
  precession (the slow root of A_O cos θ φ̇² − Cω₃φ̇ + mgℓ = 0) at two steps; a top released
  nearly upright above and below the sleeping threshold ω_c = 2√(A_O mgℓ)/C, its largest tilt
  against the root of the nutation cubic.
- ``joints``: three bars hanging on ball joints and on hinges of crossed axes, thrown into
  3D motion, no contact, 10 s: the joints' drift at position (m) and velocity (m/s) level and
  the energy; a 3D double pendulum on ball joints against a step of h/16.
- ``contact``: a box dropped on a plane on a corner, an edge and flat, for several e_N and μ
  (Newton's law at the first corner, horizontal momentum without friction, Coulomb's bound on
  each step's impulse); a ball launched sliding and spinning (v = v₀ − (2/7)s₀ from
  t* = 2|s₀|/(7μg)); a rigid rod falling flat onto a post 0.2 m off its centre (its angular
  momentum after the impact, −P d).

    python benchmarks/explore_multibody.py            # every row (some 10 min on one core)
    python benchmarks/explore_multibody.py --quick    # three short rows (seconds)
    python benchmarks/explore_multibody.py --row top  # the rows whose key holds the text
"""

from __future__ import annotations

import numpy as np
from _common import parser, publish_report
from _multibody_exact import (
    bar_impact,
    flip_half_period,
    rolling_ball,
    steady_precession,
    stuck_impact,
    symmetric_omega,
    top_nutation_bound,
)
from _multibody_rows import (
    NAN,
    centre_probes,
    compared,
    measured,
    order,
    spatial_omega,
    with_options,
    with_pk,
)

from fecontact import (
    Ball,
    BallJoint,
    Box,
    Capsule,
    Contact,
    Cylinder,
    HingeJoint,
    Model,
    Plane,
    Probe,
    RigidBody3D,
    Simulation,
)
from fecontact.rotations import exp, log
from fecontact.testing import G, case
from fecontact.time.localize import localizes

TOP = case("heavy_top")


# -- torque-free bodies -------------------------------------------------------------------------

BRICK = Box(0.3, 0.2, 0.1)  # J = m/12 (b² + c², a² + c², a² + b²): three distinct moments


def free_run(body, W0, h: float, t_end: float):
    model = Model([body], gravity=(0.0, 0.0, 0.0))
    probes = {
        f"w{i + 1}": Probe(lambda m, st, i=i: float(st.v[3 + i]), "rad/s", "body rate")
        for i in range(3)
    }
    for i, c in enumerate("xyz"):
        probes[f"H{c}"] = Probe(
            lambda m, st, i=i: float((body.rotation(st.q) @ (body.J @ st.v[3:]))[i]), "N m s", ""
        )
    return Simulation(model, dt=h, t_end=t_end, probes=probes, v0=np.r_[0.0, 0.0, 0.0, W0],
                      name="explore_free", output_interval=t_end)  # fmt: skip


def dzhanibekov(W0, h: float = 2e-3, t_end: float = 15.0) -> dict:
    body = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], BRICK)
    J = np.diag(body.J)
    exact = flip_half_period(J, W0)
    L2, E2 = np.sum((J * W0) ** 2), W0 @ (J * W0)
    side = "major" if L2 > E2 * J[1] else "minor"
    spin = ", ".join(f"{w:g}" for w in W0)
    label = f"brick 0.3x0.2x0.1 spun near axis 2, W0 ({spin}), {side} side"
    row, hist = measured("free", label, free_run(body, np.asarray(W0, float), h, t_end))
    t, w = hist["t"], hist["w2"]
    i = np.flatnonzero(np.sign(w[:-1]) != np.sign(w[1:]))
    cross = t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])
    H = np.column_stack([hist[f"H{c}"] for c in "xyz"])
    dH = np.max(np.linalg.norm(H - H[0], axis=1)) / np.linalg.norm(H[0])
    E = hist["kinetic_energy"]
    also = f"{len(cross)} flips; |dH|/|H| {dH:.1e}; dE/E {np.max(np.abs(E - E[0])) / E[0]:.1e}"
    half = (cross[-1] - cross[0]) / (len(cross) - 1) if len(cross) > 1 else NAN
    return compared(row, "flip half period (s)", exact, half, also)


def euler_precession(steps=(4e-3, 2e-3, 1e-3), t_end: float = 2.0) -> dict:
    body = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Cylinder(0.1, 0.02))
    A, C = body.J[0, 0], body.J[2, 2]
    W0 = np.array([2.0, 0.0, 10.0])
    exact = symmetric_omega(A, C, W0, t_end)
    errors, rows = [], []
    for h in steps:
        row, hist = measured("free", "", free_run(body, W0, h, t_end))
        last = np.array([hist[f"w{i}"][-1] for i in (1, 2, 3)])
        errors.append(np.linalg.norm(last - exact) / np.linalg.norm(exact))
        rows.append(row)
    row = rows[-1] | {"run": f"disk r 0.1 m, W0 (2, 0, 10): nu = {(C - A) * 10 / A:.4g} rad/s, "
                             f"h {', '.join(f'{1e3 * h:g}' for h in steps)} ms"}  # fmt: skip
    row["status"] = ", ".join(sorted({r["status"] for r in rows}))
    compared(row, "|Omega(2 s)| error at each h", 0.0, errors[-1],
             ", ".join(f"{e:.2e}" for e in errors))  # fmt: skip
    row["order"] = order(errors)
    return row


# -- the heavy top ------------------------------------------------------------------------------


def top_moments(sim):
    body = sim.model.bodies[0]
    arm = sim.parameters["arm"]
    m = body.mass
    return body.J[0, 0] + m * arm**2, body.J[2, 2], m * sim.parameters["gravity"] * arm


def unwrapped_phi(hist) -> np.ndarray:
    return np.unwrap(hist["phi"])


def steady_top(tilt: float, w3: float, steps=(1e-3, 5e-4), t_end: float = 2.0) -> dict:
    """A top in steady precession at ``tilt`` with axial rate ``w3``: its mean precession
    rate and the spread of its tilt (0 exactly)."""
    A_O, C, mgl = top_moments(TOP.build())
    rate = steady_precession(A_O, C, mgl, tilt, w3)
    spin = w3 - rate * np.cos(tilt)
    errors, rows, spread = [], [], []
    for h in steps:
        sim = TOP.build(tilt=tilt, spin=spin, precession=rate, dt=h, t_end=t_end)
        row, hist = measured("top", "", sim.replace(output_interval=t_end))
        phi = unwrapped_phi(hist)
        errors.append(abs((phi[-1] - phi[0]) / t_end - rate) / abs(rate))
        spread.append(float(np.max(np.abs(hist["theta"] - tilt))))
        rows.append(row)
    hs = ", ".join(f"{1e3 * h:g}" for h in steps)
    row = rows[-1] | {"run": f"steady precession, tilt {tilt:g} rad, w3 {w3:g} rad/s "
                             f"(phi dot {rate:.4g} rad/s), h {hs} ms"}  # fmt: skip
    row["status"] = ", ".join(sorted({r["status"] for r in rows}))
    also = "precession rate errors " + ", ".join(f"{e:.1e}" for e in errors)
    also += "; |theta - tilt| max " + ", ".join(f"{s:.1e}" for s in spread) + " rad"
    compared(row, "mean precession rate (rad/s)", rate, rate * (1 + errors[-1]), also)
    row["order"] = order(errors)
    return row


def sleeping_top(factor: float, tilt: float = 0.01, h: float = 5e-4, t_end: float = 2.0) -> dict:
    """A top released at ``tilt`` spinning at ``factor`` × ω_c: its largest tilt against the
    bottom of its nutation (a root of the cubic)."""
    A_O, C, mgl = top_moments(TOP.build())
    w_c = 2.0 * np.sqrt(A_O * mgl) / C
    spin = factor * w_c
    exact = top_nutation_bound(A_O, C, mgl, tilt, spin)
    sim = TOP.build(tilt=tilt, spin=spin, dt=h, t_end=t_end)
    label = f"released at tilt {tilt:g} rad, spin {factor:g} w_c = {spin:.4g} rad/s"
    row, hist = measured("top", label, sim.replace(output_interval=t_end))
    L = hist["L_vertical"]
    also = f"w_c {w_c:.4g} rad/s; L_z spread {np.ptp(L) / np.max(np.abs(L)):.1e}"
    return compared(row, "largest tilt (rad)", exact, float(np.max(hist["theta"])), also)


# -- joints -------------------------------------------------------------------------------------

LINK = 0.3  # m: the bars' length
BAR = Box(0.04, 0.04, LINK)


def chain(n: int, kind: str, rates, axes=None):
    """``n`` bars hanging from the origin along −z on ball joints (``kind`` "ball") or hinges
    about ``axes`` (one per joint, "hinge"), their angular velocities ``rates`` (spatial,
    rad/s; for hinges the rates about the axes); the model and v₀ of consistent velocities."""
    tops = [np.array([0.0, 0.0, -i * LINK]) for i in range(n + 1)]
    bars = [RigidBody3D.uniform(1.0, 0.5 * (tops[i] + tops[i + 1]), BAR) for i in range(n)]
    joints, omegas, w = [], [], np.zeros(3)
    for i, bar in enumerate(bars):
        other = bars[i - 1] if i else None
        if kind == "ball":
            joints.append(BallJoint(bar, tops[i], other))
            w = np.asarray(rates[i], dtype=float)
        else:
            joints.append(HingeJoint(bar, tops[i], axes[i], other))
            w = w + rates[i] * np.asarray(axes[i], float) / np.linalg.norm(axes[i])
        omegas.append(w)
    model = Model(bars, gravity=(0.0, 0.0, -G), joints=joints)
    v0, vj = np.zeros(model.n), np.zeros(3)
    for i, (bar, w) in enumerate(zip(bars, omegas, strict=True)):
        o = model.offset_of(bar)
        v0[o : o + 3] = vj + np.cross(w, bar.position - tops[i])
        v0[o + 3 : o + 6] = w  # body frame = world frame at q = 0
        vj = vj + np.cross(w, tops[i + 1] - tops[i])
    return model, v0, joints


def joint_probes(model, joints) -> dict:
    def position(m, st):
        return max(float(np.max(np.abs(j.gaps(st.q)))) for j in joints)

    def velocity(m, st):
        out = 0.0
        for j in joints:
            _, dofs, Gj, _ = j.evaluate(st.q)
            out = max(out, float(np.max(np.abs(np.einsum("ik,ik->i", Gj, st.v[dofs])))))
        return out

    return {"gap": Probe(position, "m", "largest joint gap"),
            "gap_rate": Probe(velocity, "m/s", "largest joint gap rate")}  # fmt: skip


def chain_drift(kind: str, h: float = 2e-3, t_end: float = 10.0, rho_inf: float = 0.5) -> dict:
    if kind == "ball":
        model, v0, joints = chain(3, "ball", [(3.0, 1.0, 0.5), (-2.0, 4.0, 1.0), (1.0, -3.0, 2.0)])
        label = "3 bars on ball joints"
    else:
        axes = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 1.0, 0.0)]
        model, v0, joints = chain(3, "hinge", [4.0, -6.0, 8.0], axes)
        label = "3 bars on hinges about x, y, x + y"
    probes = joint_probes(model, joints)
    for i, bar in enumerate(model.bodies):
        probes |= centre_probes(bar, model.offset_of(bar), f"b{i}")
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, v0=v0, name="explore_chain",
                     output_interval=t_end)  # fmt: skip
    if rho_inf != 0.5:
        sim = with_options(sim, rho_inf=rho_inf)
        label += f", rho_inf {rho_inf:g}"
    row, hist = measured("joints", f"{label}, 3D swing, {t_end:g} s", sim)
    E = hist["total_energy"]
    scale = np.max(hist["kinetic_energy"])
    also = f"gap rate max {np.max(hist['gap_rate']):.1e} m/s; "
    also += f"energy max |E - E0| / T_max {np.max(np.abs(E - E[0])) / scale:.1e}, "
    also += f"end {(E[-1] - E[0]) / scale:.1e}"
    return compared(row, "largest joint gap (m)", 0.0, float(np.max(hist["gap"])), also)


def double_pendulum(steps=(4e-3, 2e-3, 1e-3), t_end: float = 1.0) -> dict:
    """Two bars on ball joints thrown into 3D motion: the lower bar's end at ``t_end``
    against the run at the finest step / 16."""
    rates = [(2.0, 1.0, 0.0), (-1.0, 3.0, 1.0)]

    def tip(h):
        model, v0, joints = chain(2, "ball", rates)
        bar = model.bodies[1]
        o = model.offset_of(bar)
        probes = {f"tip_{c}": Probe(lambda m, st, i=i: float(bar.point_positions_frame(
            st.q[o : o + 6], np.array([[0.0, 0.0, -0.5 * LINK]]))[0, i]), "m", "")
            for i, c in enumerate("xyz")}  # fmt: skip
        sim = Simulation(model, dt=h, t_end=t_end, probes=probes | joint_probes(model, joints),
                         v0=v0, name="explore_pendulum", output_interval=t_end)  # fmt: skip
        row, hist = measured("joints", "", sim)
        return row, np.array([hist[f"tip_{c}"][-1] for c in "xyz"]), hist

    _, ref, _ = tip(steps[-1] / 16)
    errors, rows = [], []
    for h in steps:
        row, x, hist = tip(h)
        errors.append(float(np.linalg.norm(x - ref)) / LINK)
        rows.append(row)
    row = rows[-1] | {"run": f"3D double pendulum on ball joints, 1 s, h "
                             f"{', '.join(f'{1e3 * h:g}' for h in steps)} ms vs h/16"}  # fmt: skip
    row["status"] = ", ".join(sorted({r["status"] for r in rows}))
    also = ", ".join(f"{e:.2e}" for e in errors) + f"; joint gap {np.max(hist['gap']):.1e} m"
    compared(row, "lower end at 1 s vs fine step / L", 0.0, errors[-1], also)
    row["order"] = order(errors)
    return row


# -- contact in space ---------------------------------------------------------------------------

SIDES = (0.2, 0.15, 0.1)  # m: the dropped box
FLOOR = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=2.0)


def _aligning(a, b) -> np.ndarray:
    """The rotation vector turning unit ``a`` onto unit ``b`` (not antiparallel)."""
    a, b = np.asarray(a, float) / np.linalg.norm(a), np.asarray(b, float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    return axis / np.linalg.norm(axis) * np.arccos(np.clip(a @ b, -1.0, 1.0))


POSES = {  # rotation vectors: one corner lowest (off the centre's vertical), an edge, a face
    "corner": log(exp(np.array([0.15, 0.0, 0.0])) @ exp(_aligning(SIDES, (0.0, 0.0, -1.0)))),
    "edge": np.array([0.0, np.pi / 4 + 0.2, 0.0]),
    "flat": np.zeros(3),
}


def coulomb_ratio(hist, mass: float, mu: float, normal: str = "z", tangent="xy") -> float:
    """max over steps of |Δp_T| / (μ Δp_N), the impulses on the body from its momentum
    change less gravity's (≤ 1 when every contact keeps Coulomb's bound)."""
    if mu == 0.0:
        return NAN
    dt = np.diff(hist["t"])
    dN = mass * (np.diff(hist[f"P{normal}"]) / mass + G * dt)
    dT = mass * np.linalg.norm(np.column_stack([np.diff(hist[f"P{c}"]) for c in tangent]), axis=1)
    dT /= mass
    hit = dN > 1e-9 * mass
    return float(np.max(dT[hit] / (mu * dN[hit]), initial=0.0))


def momentum_probes(body) -> dict:
    return {f"P{c}": Probe(lambda m, st, i=i: body.mass * float(st.v[i]), "N s", "")
            for i, c in enumerate("xyz")}  # fmt: skip


def box_drop(pose: str, e: float, mu: float, vx: float = 0.5, h: float = 1e-3,
             t_end: float = 0.5) -> dict:  # fmt: skip
    """The box dropped with its lowest point 5 cm above the plane at 1 m/s down and ``vx``
    along x, without spin."""
    psi = POSES[pose]
    probe_box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(*SIDES))
    r = probe_box.point_positions(np.r_[0.0, 0.0, 0.0, psi], np.arange(8))
    k = int(np.argmin(r[:, 2]))
    z0 = 0.05 - r[k, 2]
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, z0], Box(*SIDES))
    model = Model([box], [Contact(box, FLOOR, restitution=e, friction=mu)], (0.0, 0.0, -G))
    rk = box.point_positions(np.zeros(6), [k])[0] - box.position  # the corner, body frame

    def corner_vz(m, st):
        return float(st.v[2] + (box.rotation(st.q) @ np.cross(st.v[3:], rk))[2])

    probes = centre_probes(box) | momentum_probes(box)
    probes["corner_vz"] = Probe(corner_vz, "m/s", "first corner's normal velocity")
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, q0=np.r_[0.0, 0.0, 0.0, psi],
                     v0=np.r_[vx, 0.0, -1.0, 0.0, 0.0, 0.0], name="explore_box",
                     output_interval=t_end)  # fmt: skip
    row, hist = measured("contact", f"box {pose} down, e_N {e:g}, mu {mu:g}, vx {vx:g} m/s", sim)
    t, w = hist["t"], hist["corner_vz"]
    t_hit = (1.0 - np.sqrt(1.0 + 2 * G * 0.05)) / -G  # free flight to the plane
    i = int(np.searchsorted(t, t_hit))  # the step holding the impact
    before = -1.0 - G * t_hit
    after = w[i]  # an impact not located is taken at the end of the step holding it
    if localizes(model, sim.options):  # located: its rebound flew from t_hit
        after -= (w[i + 1] - w[i]) / (t[i + 1] - t[i]) * (t[i] - t_hit)  # back to t_hit
    P = np.column_stack([hist[f"P{c}"] for c in "xy"])
    parts = [f"v_N+ {after:.5g} m/s"]
    if mu == 0.0:
        parts.append(f"|dP_xy| / (m v) {np.max(np.abs(P - P[0])) / abs(before):.1e}")
    else:
        parts.append(f"|dp_T| / (mu dp_N) max {coulomb_ratio(hist, box.mass, mu):.6f}")
    E = hist["total_energy"]
    if e == 1.0 and mu == 0.0:
        parts.append(f"energy spread / E {np.ptp(E) / abs(E[0]):.1e}")
    compared(row, "Newton: v_N+ / v_N- at the first corner", -e, after / before, "; ".join(parts))
    return with_pk(row, sim, hist, max(SIDES))


def rolling(v0=(1.0, 0.5, 0.0), w0=(3.0, -2.0, 5.0), mu: float = 0.3, h: float = 1e-3,
            t_end: float = 0.3) -> dict:  # fmt: skip
    R = 0.1
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, R], Ball(R))
    model = Model([ball], [Contact(ball, FLOOR, friction=mu)], gravity=(0.0, 0.0, -G))

    def slip(m, st):
        s = st.v[:3] + np.cross(spatial_omega(ball, st), [0.0, 0.0, -R])
        return float(np.linalg.norm(s[:2]))

    probes = centre_probes(ball) | momentum_probes(ball)
    probes["slip"] = Probe(slip, "m/s", "contact point's speed")
    v0_ = np.r_[v0, w0]  # body frame = space at q = 0
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, v0=v0_, name="explore_rolling",
                     output_interval=t_end)  # fmt: skip
    t_star, v_end = rolling_ball(v0, w0, R, mu, G)
    label = f"ball R 0.1 m launched at v0 ({', '.join(f'{c:g}' for c in v0)}), w0 "
    label += f"({', '.join(f'{c:g}' for c in w0)}), mu {mu:g}"
    row, hist = measured("contact", label, sim)
    v = np.array([hist[f"P{c}"][-1] for c in "xy"]) / ball.mass
    rolls = hist["t"][np.flatnonzero(hist["slip"] < 1e-10)]
    t_roll = float(rolls[0]) if rolls.size else NAN
    also = f"rolls from {t_roll:.4g} s (t* {t_star:.4g} s); "
    also += f"slip at end {hist['slip'][-1]:.1e} m/s; "
    also += f"|z - R| max {np.max(np.abs(hist['zc'] - R)):.1e} m; "
    also += f"|dp_T| / (mu dp_N) max {coulomb_ratio(hist, ball.mass, mu):.6f}"
    err = float(np.linalg.norm(v - v_end[:2]))
    compared(row, "|v_end - (v0 - 2/7 s0)| / |v_end|", 0.0, err / np.linalg.norm(v_end), also)
    return with_pk(row, sim, hist, 2 * R)


def rod_on_post(e: float, mu: float = 0.0, vy: float = 0.0, d: float = 0.2, h: float = 1e-3,
                t_end: float = 0.04, smooth: str = "auto") -> dict:  # fmt: skip
    """A capsule rod (0.5 m, r 1 cm, 1 kg) falling flat along x at 1 m/s onto a held
    vertical capsule post (r 2 cm) under the point ``d`` from its centre (``smooth``: the
    option ``smooth_contact``; "on" restarts the acceleration after the impact)."""
    z0 = 0.02 + 0.01 + 0.001
    rod = RigidBody3D.uniform(1.0, [0.0, 0.0, z0], Capsule(0.01, 0.5))
    post = RigidBody3D.uniform(10.0, [d, 0.0, -0.15], Capsule(0.02, 0.3)).fix()
    contact = Contact(rod, post, restitution=e, friction=mu)
    model = Model([rod, post], [contact], gravity=(0.0, 0.0, -G))
    probes = centre_probes(rod) | momentum_probes(rod)
    probes["Hy"] = Probe(lambda m, st: float((rod.rotation(st.q) @ (rod.J @ st.v[3:6]))[1]),
                         "N m s", "angular momentum about the centre, y")  # fmt: skip
    q0 = np.zeros(model.n)
    q0[3:6] = (0.0, np.pi / 2, 0.0)  # the axis along x
    v0 = np.zeros(model.n)
    v0[:3] = (0.0, vy, -1.0)
    v = np.sqrt(1.0 + 2 * G * 0.001)
    q0[1] = -vy * (v - 1.0) / G  # over the post's apex at the touch: a normal along z
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, q0=q0, v0=v0, name="explore_rod",
                     output_interval=t_end)  # fmt: skip
    sim = with_options(sim, smooth_contact=smooth)
    inertia = rod.J[0, 0]
    P, vc, w = bar_impact(rod.mass, inertia, d, v, e)
    exact = -w * inertia
    if mu:  # stuck in the impact (|P_T| < μ P_N): friction along x, 1 cm below the axis, turns it
        R = rod.rotation(q0[:6])
        arm = (d, 0.0, -0.01)
        impulse = stuck_impact(rod.mass, R @ rod.J @ R.T, arm, (0.0, vy, -v), e)
        exact = float(np.cross(arm, impulse)[1])
    label = f"rod 0.5 m falling flat onto a post {d:g} m off its centre, e_N {e:g}, mu {mu:g}"
    if vy:
        label += f", vy {vy:g} m/s"
    if smooth != "auto":
        label += f", smooth_contact {smooth}"
    row, hist = measured("contact", label, sim)
    also = f"impulse exact {P:.4g} N s"
    if mu:
        also += f"; |dp_T| / (mu dp_N) max {coulomb_ratio(hist, rod.mass, mu, tangent='xy'):.6f}"
    # H about the centre is kept in flight
    also += f"; turn rate exact {w:.4g} rad/s"
    if mu:
        ratio = np.hypot(*impulse[:2]) / (mu * impulse[2])
        struck = hist["Hy"][np.flatnonzero(hist["Hy"])[0]]  # at the end of the impact's step
        also += f"; stuck ratio exact {ratio:.6f}; H_y at the impact's step {struck:.7g} N m s"
    compared(row, "H_y after impact (N m s)", exact, float(hist["Hy"][-1]), also)
    return with_pk(row, sim, hist, 0.5)


# -- the table ----------------------------------------------------------------------------------

QUICK = [
    ("free", lambda: dzhanibekov((0.0, 6.0, 0.3), t_end=6.0)),
    ("top", lambda: sleeping_top(1.5, t_end=0.3)),
    ("contact", lambda: box_drop("corner", 0.5, 0.0, t_end=0.25)),
]

FULL = [
    ("free flip major", lambda: dzhanibekov((0.0, 6.0, 0.3))),
    ("free flip minor", lambda: dzhanibekov((0.3, 6.0, 0.0))),
    ("free flip both", lambda: dzhanibekov((0.2, 6.0, 0.2), h=1e-3)),
    ("free euler", euler_precession),
    *((f"top steady {t:g}", lambda t=t, w=w: steady_top(t, w))
      for t, w in ((1.0, 100.0), (2.0, 60.0), (0.3, 150.0))),
    *((f"top sleeping {f:g}", lambda f=f: sleeping_top(f)) for f in (1.5, 1.05, 0.8)),
    ("joints ball", lambda: chain_drift("ball")),
    ("joints ball rho 1", lambda: chain_drift("ball", rho_inf=1.0)),
    ("joints hinge", lambda: chain_drift("hinge")),
    ("joints double pendulum", double_pendulum),
    *((f"contact box {p} e {e:g} mu {m:g}", lambda p=p, e=e, m=m: box_drop(p, e, m))
      for p, e, m in (("corner", 0.5, 0.0), ("corner", 1.0, 0.0), ("corner", 0.0, 0.3),
                      ("corner", 0.5, 0.5), ("edge", 0.5, 0.0), ("edge", 1.0, 0.5),
                      ("flat", 0.5, 0.0), ("flat", 1.0, 0.3))),
    ("contact ball rolling", rolling),
    ("contact ball spinning", lambda: rolling((0.0, 0.0, 0.0), (10.0, 0.0, 20.0), mu=0.5)),
    ("contact rod e 0.5", lambda: rod_on_post(0.5)),
    ("contact rod e 1", lambda: rod_on_post(1.0)),
    ("contact rod friction", lambda: rod_on_post(0.5, mu=0.3, vy=0.5)),
    ("contact rod friction h/2", lambda: rod_on_post(0.5, mu=0.3, vy=0.5, h=5e-4)),
    ("contact rod friction restarted", lambda: rod_on_post(0.5, mu=0.3, vy=0.5, smooth="on")),
]  # fmt: skip

COLUMNS = ("group", "run", "h (s)", "status", "steps", "fallbacks", "created / scale",
           "compared", "exact", "measured", "error", "order", "p x1000: d centre / size",
           "k /100: d centre / size", "also", "CPU (s)")  # fmt: skip


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--row", default="", help="run only the rows whose label contains this text")
    args = p.parse_args()
    rows = []
    for key, build in QUICK if args.quick else FULL:
        if args.row in key:
            rows.append(build())
            print({k: rows[-1][k] for k in COLUMNS if k in rows[-1]}, flush=True)
    summary = [{k: r.get(k, "") for k in COLUMNS} for r in rows]
    failed = [{"run": r["run"], "status": r["status"], "message": r["message"]}
              for r in rows if r.get("message")]  # fmt: skip
    sections = [("Every configuration against its exact answer", summary)]
    if failed:
        sections.append(("Runs that stopped, and why", failed))
    publish_report(args.out, "explore_multibody", args.quick,
                   "Rigid multibody in space beyond the cases, against exact answers",
                   [{k: r.get(k, "") for k in COLUMNS + ("message",)} for r in rows],
                   *sections)  # fmt: skip


if __name__ == "__main__":
    main()
