"""Joints, welds and spinning impacts in space on configurations no case runs, against exact
answers or invariants.

Rows (``docs/validation/multibody.md``, "Beyond the cases"):

- a torque-free brick flipping about its intermediate axis for 30 s (15 000 steps): E and
  the spatial H = R J Ω, at two steps;
- a spherical pendulum (a bar on a ball joint, swung about the vertical): L_z about the
  pivot, which gravity and the joint's force never change, at three steps;
- a free chain of six bars on ball joints, no gravity: total P and L;
- a chain of ten bars hanging on hinges of random axes, thrown: the joints' drift;
- a double pendulum of two bars on hinges against the same bars on planar ``Pin`` joints,
  in the x–y plane and turned by a rotation Q (bodies, axes and gravity);
- two boxes welded by a ``FixedJoint``, tumbling free, against one body of their combined
  mass and inertia at h/20;
- a box on a ``PrismaticJoint`` along a tilted line: s = ½ g (e·ĝ) t²;
- a ball spinning at 100 rad/s dropped on a rough plane: it slides through the impact
  (v_x = μ P_N / m, ω_y − 5μP_N/(2mR)), and one at 10 rad/s that sticks (v_x = 2/7 R Ω);
- a ball launched sliding and spinning on a plane beside a pendulum on a ball joint that
  touches nothing: v = v₀ − (2/7)s₀ once it rolls;
- the flexible pendulum of ``spatial_pendulum`` turned by Q against the unturned one;
- a pendulum on a hinge striking a pinned steel rod (``Beam3D``): p × 1000 and k ÷ 100.

    python benchmarks/multibody_hunt.py            # every row (a few minutes on one core)
    python benchmarks/multibody_hunt.py --quick    # two short rows (seconds)
"""

from __future__ import annotations

import numpy as np
from _common import parser, publish_report
from _multibody_exact import rolling_ball
from _multibody_rows import compared, measured, order, spatial_omega, with_options

from fecontact import (
    Ball,
    BallJoint,
    Box,
    Capsule,
    Contact,
    HingeJoint,
    Model,
    Pin,
    Plane,
    Probe,
    RigidBody3D,
    Simulation,
    node_probe,
)
from fecontact.bodies import Beam3D, Material, Polygon, RigidBody2D, Section
from fecontact.joints3d import FixedJoint, PrismaticJoint
from fecontact.rotations import exp
from fecontact.testing import G

Q = exp(np.array([0.4, -1.1, 0.7]))  # a rotation with no special axis
FLOOR = Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], extent=5.0)


def vector_probes(name: str, f) -> dict:
    return {f"{name}{k}": Probe(lambda m, st, k=k: float(f(st)[k]), "", "") for k in range(3)}


def last(hist, name: str) -> np.ndarray:
    return np.array([hist[f"{name}{k}"][-1] for k in range(3)])


def long_flip(steps=(2e-3, 1e-3), t_end: float = 30.0) -> dict:
    drifts, energies = [], []
    for h in steps:
        body = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Box(0.3, 0.2, 0.1))
        probes = vector_probes("H", lambda st, b=body: b.rotation(st.q) @ (b.J @ st.v[3:]))
        model, v0 = Model([body], gravity=(0.0, 0.0, 0.0)), np.r_[0, 0, 0, 0, 6.0, 0.3]
        sim = Simulation(model, dt=h, t_end=t_end, probes=probes, v0=v0, name="hunt_flip")
        row, hist = measured("free", "", sim)
        H = np.column_stack([hist[f"H{k}"] for k in range(3)])
        E = hist["kinetic_energy"]
        drifts.append(float(np.linalg.norm(H[-1] - H[0]) / np.linalg.norm(H[0])))
        energies.append(float(np.abs(E - E[0]).max() / E[0]))
    row["run"] = "brick 0.3x0.2x0.1 spun at (0, 6, 0.3) rad/s, 30 s, rho_inf 0.5"
    compared(row, "|H(30 s) - H0| / |H0| at h 2, 1 ms", 0.0, drifts[-1],
             ", ".join(f"{d:.2e}" for d in drifts) + "; max |E - E0| / E0 "
             + ", ".join(f"{e:.1e}" for e in energies))  # fmt: skip
    row["order"] = order(drifts)
    return row


def spherical_pendulum(steps=(2e-3, 1e-3, 5e-4), t_end: float = 2.0) -> dict:
    spreads = []
    for h in steps:
        bar = RigidBody3D.uniform(1.0, [0.15, 0.0, 0.0], Box(0.3, 0.02, 0.02))
        model = Model([bar], gravity=(0.0, 0.0, -G), joints=[BallJoint(bar, [0, 0, 0])])
        w = np.array([0.0, 0.0, 4.0])

        def Lz(m, st, bar=bar):
            L = bar.rotation(st.q) @ (bar.J @ st.v[3:])
            return float(L[2] + bar.mass * np.cross(bar.center(st.q), st.v[:3])[2])

        sim = Simulation(model, dt=h, t_end=t_end, probes={"Lz": Probe(Lz, "", "")},
                         v0=np.r_[np.cross(w, bar.position), w], name="hunt_sph")  # fmt: skip
        row, hist = measured("joints", "", sim)
        spreads.append(float(np.ptp(hist["Lz"]) / abs(hist["Lz"][0])))
    row["run"] = "spherical pendulum, bar 0.3 m horizontal at 4 rad/s about z, 2 s"
    compared(row, "L_z spread / L_z at h 2, 1, 0.5 ms", 0.0, spreads[-1],
             ", ".join(f"{s:.2e}" for s in spreads))  # fmt: skip
    row["order"] = order(spreads)
    return row


def free_chain(h: float = 2e-3, t_end: float = 5.0) -> dict:
    n, L = 6, 0.3
    tops = [np.array([i * L, 0.0, 0.0]) for i in range(n + 1)]
    bars = [RigidBody3D.uniform(1.0 + 0.3 * i, 0.5 * (tops[i] + tops[i + 1]), Box(L, 0.03, 0.02))
            for i in range(n)]  # fmt: skip
    joints = [BallJoint(bars[i], tops[i], bars[i - 1]) for i in range(1, n)]
    model = Model(bars, gravity=(0.0, 0.0, 0.0), joints=joints)
    rng = np.random.default_rng(1)
    v0, vj = np.zeros(model.n), np.array([0.1, 0.2, -0.3])
    for i, b in enumerate(bars):
        o, w = model.offset_of(b), 3.0 * rng.normal(size=3)
        v0[o : o + 3], v0[o + 3 : o + 6] = vj + np.cross(w, b.position - tops[i]), w
        vj = vj + np.cross(w, tops[i + 1] - tops[i])

    def momenta(st):
        P, H = np.zeros(3), np.zeros(3)
        for b in bars:
            o = model.offset_of(b)
            q, v = st.q[o : o + 6], st.v[o : o + 6]
            P += b.mass * v[:3]
            H += b.rotation(q) @ (b.J @ v[3:]) + b.mass * np.cross(b.center(q), v[:3])
        return np.r_[P, H]

    probes = vector_probes("P", lambda st: momenta(st)[:3])
    probes |= vector_probes("L", lambda st: momenta(st)[3:])
    probes["gap"] = Probe(lambda m, st: max(float(np.abs(j.gaps(st.q)).max()) for j in joints),
                          "m", "")  # fmt: skip
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, v0=v0, name="hunt_chain")
    row, hist = measured("joints", "free chain of 6 bars on ball joints, no gravity, 5 s", sim)
    P = np.column_stack([hist[f"P{k}"] for k in range(3)])
    H = np.column_stack([hist[f"L{k}"] for k in range(3)])
    dH = np.abs(H - H[0]).max() / np.linalg.norm(H[0])
    also = f"|dP| / |P| {np.abs(P - P[0]).max() / np.linalg.norm(P[0]):.1e}; "
    also += f"joint gap {hist['gap'].max():.1e} m; "
    also += f"dE/E {np.ptp(hist['kinetic_energy']) / hist['kinetic_energy'][0]:.1e}"
    return compared(row, "|dL| / |L|", 0.0, dH, also)


def hinge_chain(n: int = 10, h: float = 2e-3, t_end: float = 2.0) -> dict:
    L = 0.2
    tops = [np.array([0.0, 0.0, -i * L]) for i in range(n + 1)]
    bars = [RigidBody3D.uniform(0.5, 0.5 * (tops[i] + tops[i + 1]), Box(0.02, 0.02, L))
            for i in range(n)]  # fmt: skip
    axes = [a / np.linalg.norm(a) for a in np.random.default_rng(2).normal(size=(n, 3))]
    joints = [HingeJoint(b, tops[i], axes[i], bars[i - 1] if i else None)
              for i, b in enumerate(bars)]  # fmt: skip
    model = Model(bars, gravity=(0.0, 0.0, -G), joints=joints)
    v0, vj, w = np.zeros(model.n), np.zeros(3), np.zeros(3)
    for i, b in enumerate(bars):  # each hinge turning at 2 rad/s
        o, w = model.offset_of(b), w + 2.0 * axes[i]
        v0[o : o + 3], v0[o + 3 : o + 6] = vj + np.cross(w, b.position - tops[i]), w
        vj = vj + np.cross(w, tops[i + 1] - tops[i])
    probes = {"gap": Probe(lambda m, st: max(float(np.abs(j.gaps(st.q)).max()) for j in joints),
                           "m", "")}  # fmt: skip
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, v0=v0, name="hunt_hinges")
    row, hist = measured("joints", f"{n} bars on hinges of random axes, thrown, 2 s", sim)
    return compared(row, "largest joint gap (m)", 0.0, float(hist["gap"].max()))


def double_pendulum_planar(h: float = 1e-3, t_end: float = 1.0) -> dict:
    """Kane's chain without its floor: 3D hinges about Q e_z against planar pins."""
    a1, a2 = np.radians(10.0), np.radians(-135.0)
    O = np.array([0.0, 1.5])
    d1, d2 = (np.array([np.cos(a), np.sin(a)]) for a in (a1, a2))
    J = O + d1
    dia = Polygon([[-0.5, 0.0], [0.0, -0.01], [0.5, 0.0], [0.0, 0.01]])
    up = RigidBody2D(1.0, 1.0 / 12.0, O + 0.5 * d1, angle=a1, shape=dia)
    lo = RigidBody2D(1.0, 1.0 / 12.0, J + 0.5 * d2, angle=a2, shape=dia)
    model = Model([up, lo], gravity=(0.0, -G), joints=[Pin(up, O), Pin(up, J, lo)])

    def tip2(st):
        phi = a2 + st.q[5]
        return np.r_[lo.position + st.q[3:5] + 0.5 * np.array([np.cos(phi), np.sin(phi)]), 0.0]

    sim = Simulation(model, dt=h, t_end=t_end, probes=vector_probes("t", tip2), name="hunt_2d")
    _, hist = measured("joints", "", sim)
    ref = last(hist, "t")
    errors = []
    for R in (np.eye(3), Q):

        def bar(c, d, R=R):
            e = np.r_[d, 0.0]
            Jb = (np.eye(3) - np.outer(e, e)) / 12.0 + 1e-6 * np.outer(e, e)
            return RigidBody3D(1.0, R @ Jb @ R.T, R @ np.r_[c, 0.0], Ball(0.01))

        u3, l3 = bar(O + 0.5 * d1, d1), bar(J + 0.5 * d2, d2)
        axis = R @ np.array([0.0, 0.0, 1.0])
        joints = [
            HingeJoint(u3, R @ np.r_[O, 0.0], axis),
            HingeJoint(l3, R @ np.r_[J, 0.0], axis, u3),
        ]
        model = Model([u3, l3], gravity=tuple(R @ np.array([0.0, -G, 0.0])), joints=joints)
        r = R @ np.r_[0.5 * d2, 0.0]

        def tip3(st, l3=l3, r=r):
            return l3.center(st.q[6:]) + l3.rotation(st.q[6:]) @ r

        sim = Simulation(model, dt=h, t_end=t_end, probes=vector_probes("t", tip3), name="hunt_3d")
        row, hist = measured("joints", "", sim)
        errors.append(float(np.linalg.norm(R.T @ last(hist, "t") - ref)))
    row["run"] = "double pendulum on hinges vs planar pins, 1 s, h 1 ms (axes z, then Q e_z)"
    return compared(row, "|tip 3D - tip 2D| (m)", 0.0, max(errors),
                    ", ".join(f"{e:.1e}" for e in errors))  # fmt: skip


def welded_pair(steps=(2e-3, 1e-3), t_end: float = 2.0) -> dict:
    A = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Box(0.3, 0.2, 0.1))
    B = RigidBody3D.uniform(1.0, [0.25, 0.1, 0.05], Box(0.2, 0.1, 0.1))
    m = A.mass + B.mass
    c = (A.mass * A.position + B.mass * B.position) / m
    arms = [b.position - c for b in (A, B)]  # the parallel axes' shifts
    Jc = sum(
        b.J + b.mass * (r @ r * np.eye(3) - np.outer(r, r))
        for b, r in zip((A, B), arms, strict=True)
    )
    W, V, mark = np.array([0.5, 6.0, 1.0]), np.array([0.2, -0.1, 0.3]), np.array([0.3, 0.1, 0.1])

    def composite(h):
        body = RigidBody3D(m, Jc, c, Ball(0.1))
        model = Model([body], gravity=(0.0, 0.0, 0.0))
        p = vector_probes("x", lambda st: body.point_positions_frame(st.q, (mark - c)[None])[0])
        sim = Simulation(model, dt=h, t_end=t_end, probes=p, v0=np.r_[V, W], name="hunt_one")
        return last(measured("joints", "", sim)[1], "x")

    ref, errors = composite(steps[-1] / 20), []
    for h in steps:
        model = Model(
            [A, B], gravity=(0.0, 0.0, 0.0), joints=[FixedJoint(B, [0.15, 0.05, 0.05], A)]
        )
        v0 = np.zeros(12)
        for i, b in enumerate((A, B)):
            v0[6 * i : 6 * i + 3], v0[6 * i + 3 : 6 * i + 6] = V + np.cross(W, b.position - c), W
        p = vector_probes(
            "x", lambda st: B.point_positions_frame(st.q[6:], (mark - B.position)[None])[0]
        )
        sim = Simulation(model, dt=h, t_end=t_end, probes=p, v0=v0, name="hunt_weld")
        row, hist = measured("joints", "", sim)
        errors.append(float(np.linalg.norm(last(hist, "x") - ref)))
    row["run"] = "two boxes on a FixedJoint tumbling free vs one body of their inertia, 2 s"
    compared(row, "a corner at 2 s vs the composite at h/20 (m), h 2, 1 ms", 0.0, errors[-1],
             ", ".join(f"{e:.1e}" for e in errors))  # fmt: skip
    row["order"] = order(errors)
    return row


def prismatic(h: float = 1e-3, t_end: float = 1.0) -> dict:
    e = np.array([1.0, 0.5, -0.8]) / np.linalg.norm([1.0, 0.5, -0.8])
    b = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(0.1, 0.05, 0.05))
    model = Model([b], gravity=(0.0, 0.0, -G), joints=[PrismaticJoint(b, [0, 0, 0], e)])
    probes = vector_probes("x", lambda st: st.q[:3]) | vector_probes("r", lambda st: st.q[3:])
    sim = Simulation(model, dt=h, t_end=t_end, probes=probes, name="hunt_slide")
    row, hist = measured(
        "joints", f"box on a PrismaticJoint along (1, 0.5, -0.8), {t_end:g} s", sim
    )
    exact = 0.5 * G * -e[2] * t_end**2 * e
    err = np.linalg.norm(last(hist, "x") - exact) / np.linalg.norm(exact)
    return compared(row, "|x - 1/2 g (e.g) t^2 e| / |x|", 0.0, float(err),
                    f"largest rotation {np.abs(last(hist, 'r')).max():.1e} rad")  # fmt: skip


def spinning_drop(spin: float, mu: float, e: float = 0.5, h: float = 1e-3) -> dict:
    R, v = 0.1, 1.0
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, R + 0.01], Ball(R))
    model = Model([ball], [Contact(ball, FLOOR, restitution=e, friction=mu)], (0.0, 0.0, -G))
    probes = vector_probes("v", lambda st: st.v[:3])
    probes |= vector_probes("w", lambda st: spatial_omega(ball, st))
    sim = Simulation(model, dt=h, t_end=0.08, probes=probes, v0=np.r_[0, 0, -v, 0, spin, 0],
                     name="hunt_spin")  # fmt: skip
    row, hist = measured("contact", f"ball R 0.1 m spinning at {spin:g} rad/s about y dropped "
                                    f"at 1 m/s, mu {mu:g}, e_N {e:g}", sim)  # fmt: skip
    PN = (1.0 + e) * np.sqrt(v * v + 2 * G * 0.01)  # the impulse over m at the touch
    F = min(mu * PN, 2.0 / 7.0 * R * spin)  # sliding through, or stuck at 2/7 of R Ω
    exact = np.array([F, spin - 2.5 * F / R])
    got = np.array([last(hist, "v")[0], last(hist, "w")[1]])
    side = "slides" if mu * PN < 2.0 / 7.0 * R * spin else "sticks"
    return compared(row, "|(v_x, w_y) after the bounce - exact| / |exact|", 0.0,
                    float(np.linalg.norm(got - exact) / np.linalg.norm(exact)),
                    f"{side}: v_x {got[0]:.6g} m/s, w_y {got[1]:.6g} rad/s")  # fmt: skip


def rolling_beside_pendulum(h: float = 1e-3, t_end: float = 0.3) -> dict:
    w0, R, mu = np.array([10.0, 0.0, 20.0]), 0.1, 0.5
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, R], Ball(R))
    bar = RigidBody3D.uniform(1.0, [3.15, 0.0, 1.0], Box(0.3, 0.02, 0.02))
    model = Model([ball, bar], [Contact(ball, FLOOR, friction=mu)], (0.0, 0.0, -G),
                  joints=[BallJoint(bar, [3.0, 0.0, 1.0])])  # fmt: skip
    v0 = np.zeros(12)
    v0[3:6] = w0
    sim = Simulation(model, dt=h, t_end=t_end, probes=vector_probes("v", lambda st: st.v[:3]),
                     v0=v0, name="hunt_roll")  # fmt: skip
    row, hist = measured("contact", "ball rolling (w0 (10, 0, 20), mu 0.5) beside a pendulum "
                                    "on a ball joint", sim)  # fmt: skip
    exact = rolling_ball(np.zeros(3), w0, R, mu, G)[1]
    err = np.linalg.norm(last(hist, "v") - exact) / np.linalg.norm(exact)
    return compared(row, "|v_end - (v0 - 2/7 s0)| / |v_end|", 0.0, float(err))


def turned_pendulum(t_end: float = 0.6, tip_speed: float = 1.0) -> dict:
    tips = []
    for R in (np.eye(3), Q):
        strip = Material(70e9, nu=0.33, rho=2700.0), Section.rectangle(0.02, 0.002)
        beam = Beam3D.straight([0, 0, 0], R @ [0.3, 0, 0], 4, *strip, orientation=R @ [0, 1.0, 0])
        beam.pin(0).add_mass(-1, 0.14)
        wall = Plane(R @ [0, -0.3, 0], R @ [1.0, 0, 0], extent=0.08)
        stop = Contact(beam, wall, nodes=[-1], restitution=0.8, friction=0.3)
        model = Model([beam], [stop], gravity=tuple(R @ [0, -G, 0]))
        probes = {f"t{k}": node_probe(model, beam, -1, c) for k, c in enumerate("xyz")}
        v0 = np.zeros((beam.n_nodes, 6))
        omega = R @ np.array([0.0, -tip_speed / 0.3, 0.0])
        v0[:, :3], v0[:, 3:] = np.cross(omega, beam.X), omega
        sim = Simulation(
            model, dt=1e-3, t_end=t_end, probes=probes, v0=v0.ravel(), name="hunt_turned"
        )
        row, hist = measured("beam", "", sim)
        tips.append(np.column_stack([hist[f"t{k}"] for k in range(3)]) @ R)
    row["run"] = (
        f"spatial_pendulum turned by Q (tip thrown at {tip_speed:g} m/s along z) vs unturned"
    )
    span = np.ptp(tips[0], axis=0).max()
    return compared(row, "tip history, largest difference (m)", 0.0,
                    float(np.abs(tips[0] - tips[1]).max()), f"tip span {span:.3g} m")  # fmt: skip


def pendulum_on_rod(mu: float = 0.3, e: float = 0.5, h: float = 2e-4, t_end: float = 0.05) -> dict:
    rod = Beam3D.straight([-0.25, 0, 0], [0.25, 0, 0], 10, Material(210e9, nu=0.3, rho=7850.0),
                          Section.circle(0.005))  # fmt: skip
    rod.pin(0).pin(-1)
    P = np.array([0.05, -0.4, 0.017])  # the hinge: the cap 2 mm over the rod when horizontal
    bar = RigidBody3D.uniform(0.5, P - [0, 0, 0.2], Capsule(0.01, 0.4))
    model = Model([rod, bar], [Contact(bar, rod, restitution=e, friction=mu)], (0.0, 0.0, -G),
                  joints=[HingeJoint(bar, P, [1.0, 0.0, 0.0])])  # fmt: skip
    o = model.offset_of(bar)
    R0, c, w = exp(np.array([np.pi / 2, 0, 0])), bar.position, np.array([-2.5, 0.0, 0.0])
    q0, v0 = np.zeros(model.n), np.zeros(model.n)
    q0[o : o + 6] = np.r_[R0 @ (c - P) + P - c, np.pi / 2, 0.0, 0.0]  # horizontal, along +y
    v0[o : o + 6] = np.r_[np.cross(w, R0 @ (c - P)), w]
    probe = Probe(lambda m, st: float((bar.rotation(st.q[o : o + 6]) @ st.v[o + 3 : o + 6])[0]),
                  "rad/s", "")  # fmt: skip
    sim = Simulation(model, dt=h, t_end=t_end, probes={"wx": probe}, q0=q0, v0=v0, name="hunt_rod")
    row, hist = measured("beam", f"capsule pendulum on a hinge striking a pinned steel rod, "
                                 f"mu {mu:g}, e_N {e:g}, h {1e3 * h:g} ms", sim)  # fmt: skip
    moved = []
    for option in ({"penalty_scale": 1e3}, {"multiplier_scale": 1e-2}):
        other = measured("beam", "", with_options(sim, **option))[1]
        moved.append(abs(other["wx"][-1] - hist["wx"][-1]))
    return compared(row, "pendulum's w_x at 50 ms: p x1000, k /100 change (rad/s)", 0.0,
                    max(moved), f"w_x {hist['wx'][-1]:.4f} rad/s; "
                    f"changes {moved[0]:.1e}, {moved[1]:.1e}")  # fmt: skip


FULL = [long_flip, spherical_pendulum, free_chain, hinge_chain, double_pendulum_planar,
        welded_pair, prismatic,
        lambda: spinning_drop(100.0, 0.3), lambda: spinning_drop(10.0, 1.0),
        rolling_beside_pendulum, turned_pendulum, pendulum_on_rod]  # fmt: skip
QUICK = [lambda: prismatic(t_end=0.1), lambda: spinning_drop(100.0, 0.3)]
COLUMNS = ("group", "run", "h (s)", "status", "steps", "fallbacks", "created / scale",
           "compared", "measured", "order", "also", "CPU (s)")  # fmt: skip


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    rows = []
    for build in QUICK if args.quick else FULL:
        rows.append(build())
        print({k: rows[-1][k] for k in COLUMNS if k in rows[-1]}, flush=True)
    table = [{k: r.get(k, "") for k in COLUMNS} for r in rows]
    publish_report(args.out, "multibody_hunt", args.quick,
                   "Joints, welds and spinning impacts in space, against exact answers",
                   table, ("Every configuration against its exact answer", table))  # fmt: skip


if __name__ == "__main__":
    main()
