"""Angular momentum of free rigid bodies in space through the position correction.

Every run twice in one process: as the integrator runs it (the correction's change of the
conserved angular momentum put back, ``fecontact.time.momentum_rigid``) and with that hold
switched off (the model's hold factory replaced by one that holds nothing: the correction
then moves the bodies at fixed velocities). Impacts at the steps' ends (``localize=False``,
and friction, which leaves the automatic localization off).

1. A rigid ball (1 kg, r = 5 cm) thrown at 2 m/s at a ball (1.5 kg, r = 6 cm) or a box
   (0.2 × 0.15 × 0.1 m) spinning at 10 rad/s in space, impact parameter 0.5, e_N = 0.5,
   μ = 0 and 0.5, at h = 0.2, 0.1, 0.05 ms: max |L(t) − L(0)| / (m v R) (m the total mass,
   R = 5 cm), max |P(t) − P(0)| / (m v), the ledger's created / scale, the kinetic energy at
   the end (J).
2. A box thrown spinning at 15 rad/s about the vertical, tilted, onto a frictionless plane
   (e_N = 0.5) with gravity, 0.4 s at h = 1, 0.5, 0.25 ms: max |L_z(t) − L_z(0)| / L_z(0).

    python benchmarks/rigid_momentum.py            # about a minute
    python benchmarks/rigid_momentum.py --quick    # seconds
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import numpy as np

try:
    from . import _common as common
except ImportError:
    import _common as common

import fecontact.time.correction as correction
from fecontact import Contact, IntegratorOptions, Model, Plane, simulate
from fecontact.bodies.rigid3d import RigidBody3D
from fecontact.bodies.shapes3d import Ball, Box
from fecontact.ledger import EnergyLedger
from fecontact.rotations import exp

HOLD = correction.rigid_momentum


def momentum(model, q, v):
    """(P, L about the origin) of the model's rigid bodies."""
    P, L = np.zeros(3), np.zeros(3)
    for i, body in enumerate(model.bodies):
        qa, va = q[model.body_slice(i)], v[model.body_slice(i)]
        P += body.mass * va[:3]
        L += np.cross(body.center(qa), body.mass * va[:3]) + body.rotation(qa) @ (body.J @ va[3:])
    return P, L


def measured(model, h, t_end, q0, v0, hold: bool):
    """(max |ΔP|, max |ΔL| (3,), created / scale, final kinetic energy) of one run."""
    correction.rigid_momentum = HOLD if hold else (lambda model: None)
    try:
        opts = IntegratorOptions(localize=False)
        ledger = EnergyLedger(model, opts)
        P0, L0 = momentum(model, q0, v0)
        dP, dL = 0.0, np.zeros(3)
        for st in simulate(model, h, t_end, options=opts, q0=q0, v0=v0):
            P, L = momentum(model, st.q, st.v)
            dP, dL = max(dP, np.linalg.norm(P - P0)), np.maximum(dL, np.abs(L - L0))
            kinetic, gravity = model.kinetic_energy(st.v), model.potential_energy(st.q)
            ledger.add(st, kinetic, 0.0, gravity, 0.0)  # (rigid: no strain; no load)
    finally:
        correction.rigid_momentum = HOLD
    return dP, dL, L0, ledger.created / ledger.scale, kinetic


def free_pair(kind, friction, h, hold, t_end=0.15):
    target_shape = Box(0.2, 0.15, 0.1) if kind == "box" else Ball(0.06)
    size = 0.075 if kind == "box" else 0.06
    target = RigidBody3D.uniform(1.5, [0.0, 0.0, 0.0], target_shape)
    ball = RigidBody3D.uniform(1.0, [-0.3, 0.5 * (0.05 + size), 0.01], Ball(0.05))
    pair = Contact(target, ball, friction=friction, restitution=0.5)
    model = Model([target, ball], [pair], gravity=(0.0, 0.0, 0.0))
    v0 = np.zeros(12)
    v0[3:6], v0[6:9] = [0.0, 0.0, 10.0], [2.0, 0.0, 0.0]
    dP, dL, _, created, kinetic = measured(model, h, t_end, np.zeros(12), v0, hold)
    ref = 2.5 * 2.0
    return {
        "target": kind, "mu": friction, "h (ms)": 1e3 * h, "hold": hold,
        "dL / (m v R)": float(np.linalg.norm(dL)) / (ref * 0.05), "dP / (m v)": dP / ref,
        "created / scale": created, "final kinetic (J)": kinetic,
    }  # fmt: skip


def box_on_plane(h, hold, t_end=0.4):
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.2], Box(0.2, 0.15, 0.1))
    floor = Contact(box, Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), restitution=0.5)
    model = Model([box], [floor], gravity=(0.0, 0.0, -9.81))
    q0, v0 = np.zeros(6), np.zeros(6)
    q0[3:] = [0.4, 0.3, 0.0]
    v0[:3] = [0.5, 0.0, -2.0]
    v0[3:] = exp(q0[3:]).T @ np.array([0.0, 0.0, 15.0])
    _, dL, L0, created, kinetic = measured(model, h, t_end, q0, v0, hold)
    return {
        "h (ms)": 1e3 * h, "hold": hold, "dL_z / L_z": float(dL[2] / abs(L0[2])),
        "created / scale": created, "final kinetic (J)": kinetic,
    }  # fmt: skip


def main() -> None:
    args = common.parser(__doc__.splitlines()[0]).parse_args()
    steps = (2e-4,) if args.quick else (2e-4, 1e-4, 5e-5)
    t_pair, t_box = (0.02, 0.05) if args.quick else (0.15, 0.4)
    pairs = [
        free_pair(kind, mu, h, hold, t_pair)
        for kind in ("ball", "box")
        for mu in (0.0, 0.5)
        for h in steps
        for hold in (False, True)
    ]
    boxes = [box_on_plane(5 * h, hold, t_box) for h in steps for hold in (False, True)]
    common.publish_report(
        args.out, "rigid_momentum", args.quick,
        "Angular momentum of free rigid bodies through the position correction", pairs,
        ("A ball thrown at a spinning ball or box in space, b = 0.5, e_N = 0.5", pairs),
        ("A box spinning about the vertical thrown onto a frictionless plane", boxes),
    )  # fmt: skip


if __name__ == "__main__":
    main()
