"""A moving body striking a beam along its length, in the plane and in space, and the settling
rule (``settles`` and ``struck`` in fecontact/time/settings.py): a beam settles where a moving
body that is no beam strikes it, not where another beam meets it along its length.

- twins: a 0.1 kg ball thrown at a pinned 2 mm steel strip (``Beam3D``) in its bending plane
  against the disk on the ``Beam2D`` strip (tests/test_spatial_strike.py), mid-element and
  over a node, at 10 to 300 m/s: the largest distance of the two paths (strip nodes and the
  body's centre, m) with both settling (the rule) and with the plane settling alone (the rule
  before), and what each run created over its scale;
- heights: the drop height moved by 0, ¼, ½ and ¾ of a step, settling and not: two crossing
  rods (tests/test_beam3d_contact.py's scene, 10 elements each), a 10-element rod across a
  free capsule and flat on a free box, two planar strips crossing at 14° at 2 and 20 m/s
  (tests/test_two_sided_beams.py's scene); created / scale;
- steps: the strikes at 30, 100 and 300 m/s at h = 0.1 ms to h/8, plane and space: created /
  scale and the step halvings (those of a step that turned a beam node by more than a
  quarter turn among them, fecontact/time/turns.py).

    python benchmarks/beam_strike.py           # about 3 minutes on one core
    python benchmarks/beam_strike.py --quick   # one row of each table
"""

from __future__ import annotations

import numpy as np
from _common import parser, publish, report

from fecontact import Beam2D, Beam3D, Contact, Material, Model, Section, simulate
from fecontact.bodies import Disk, RigidBody2D, RigidBody3D
from fecontact.bodies.shapes3d import Ball, Box, Capsule
from fecontact.errors import SolverError
from fecontact.ledger import EnergyLedger
from fecontact.time import IntegratorOptions, settings

STEEL = Material(210e9, nu=0.3, rho=7850.0)
R_TUBE = 0.005


def strike(dim, x, speed, dz=0.0):
    """The body of 2 cm over the point ``x`` (m) of the strip, thrown at ``speed`` (m/s)."""
    section = Section.rectangle(0.05, 0.002)
    if dim == 2:
        strip = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 20, STEEL, section)
        body = RigidBody2D.uniform(0.1, [x, 0.03 + dz], Disk(0.02))
    else:
        strip = Beam3D.straight([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 20, STEEL, section)
        body = RigidBody3D.uniform(0.1, [x, 0.03 + dz, 0.0], Ball(0.02))
    strip.pin(0).pin(-1)
    model = Model([strip, body], [Contact(body, strip, clearance=0.001)], (0.0,) * dim)
    direction = np.zeros(dim)
    direction[1] = -speed
    return model, model.translation(body, direction)


def rod(a, b, n=10):
    return Beam3D.straight(a, b, n, STEEL, Section.circle(R_TUBE))


def crossing_rods(dz):
    d = np.array([np.cos(np.pi / 3), np.sin(np.pi / 3), 0.0])
    a = rod([-0.15, 0.0, 2 * R_TUBE + 0.001 + dz], [0.15, 0.0, 2 * R_TUBE + 0.001 + dz])
    b = rod(-0.15 * d, 0.15 * d)
    model = Model([a, b], [Contact(a, b, clearance=2 * R_TUBE)], (0.0, 0.0, 0.0))
    return model, model.translation(a, (0.0, 0.0, -1.0))


def rod_on_capsule(dx):
    m = STEEL.rho * np.pi * R_TUBE**2 * 0.3
    d = np.array([0.0, np.cos(np.radians(50.0)), np.sin(np.radians(50.0))])
    x0 = np.array([0.02 + R_TUBE + 0.001 + dx, 0.0, 0.0])
    bar = rod(x0 - 0.15 * d, x0 + 0.15 * d)
    capsule = RigidBody3D.uniform(2 * m, [0.0, 0.0, 0.0], Capsule(0.02, 0.3))
    model = Model([bar, capsule], [Contact(bar, capsule, clearance=R_TUBE)], (0.0, 0.0, 0.0))
    return model, model.translation(bar, (-1.0, 0.0, 0.0))


def rod_on_box(dz):
    z0 = R_TUBE + 0.001 + dz
    bar = rod([-0.08, -0.05, z0], [0.08, 0.07, z0])
    box = RigidBody3D.uniform(1.0, [0.0, 0.0, -0.05], Box(0.2, 0.2, 0.1))
    model = Model([bar, box], [Contact(bar, box, clearance=R_TUBE)], (0.0, 0.0, 0.0))
    return model, model.translation(bar, (0.0, 0.0, -1.0))


def strips(dy, speed=2.0):
    section = Section.rectangle(0.05, 0.01)
    lower = Beam2D.straight([0.0, 0.0], [1.0, 0.0], 10, STEEL, section).pin(0).pin(-1)
    upper = Beam2D.straight([0.3, 0.03 + dy], [0.7, 0.13 + dy], 8, STEEL, section)
    pairs = [Contact(upper, lower, clearance=0.01), Contact(lower, upper, clearance=0.01)]
    model = Model([lower, upper], pairs, gravity=(0.0, 0.0))
    return model, model.translation(upper, (0.0, -speed))


def run(model, v0, h, t_end, settle=None, options=None):
    """(positions of every step (m), status, created / scale, halvings); ``settle`` True or
    False forces the rule's answer for the run, None keeps it."""
    kept = settings.settles
    if settle is not None:
        settings.settles = lambda m, smooth: smooth and settle
    opts = options or IntegratorOptions()
    ledger, path, status, halvings = EnergyLedger(model, opts), [], "completed", 0
    try:
        for st in simulate(model, h, t_end, opts, v0=v0):
            ledger.add(st, model.kinetic_energy(st.v), model.strain_energy(st.q), 0.0, 0.0)
            path.append(st.q.copy())
            halvings += st.halvings
    except SolverError as err:
        status = str(err).split(":")[0]
    finally:
        settings.settles = kept
    return path, status, ledger.created / max(ledger.scale, 1e-300), halvings


def planar_view(model, q):
    """The strip's nodes and the body's centre, x and y (m)."""
    strip, body = model.bodies
    nodes = strip.positions(q[model.body_slice(0)])[:, :2]
    return np.vstack([nodes, body.center(q[model.body_slice(1)])[None, :2]])


def twin_row(x, speed, settle_space):
    (m2, v2), (m3, v3) = strike(2, x, speed), strike(3, x, speed)
    p2, s2, c2, _ = run(m2, v2, 1e-4, 0.004)
    p3, s3, c3, _ = run(m3, v3, 1e-4, 0.004, settle=settle_space)
    n = min(len(p2), len(p3))
    d = max(
        np.abs(planar_view(m2, a) - planar_view(m3, b)).max()
        for a, b in zip(p2[:n], p3[:n], strict=True)
    )
    rule = "both settle" if settle_space else "plane alone (before)"
    return {"x (m)": x, "speed (m/s)": speed, "settling": rule, "distance (m)": d,
            "plane": s2, "space": s3, "created plane": c2, "created space": c3}  # fmt: skip


SCENES = {  # name: (build(offset), step (s), end (s), one step's travel (m))
    "crossing rods": (crossing_rods, 1e-4, 0.004, 1e-4),
    "rod across a free capsule": (rod_on_capsule, 1e-4, 0.004, 1e-4),
    "rod flat on a free box": (rod_on_box, 1e-4, 0.004, 1e-4),
    "planar strips crossing": (strips, 5e-5, 0.02, 1e-4),
    "planar strips crossing, 20 m/s": (lambda dy: strips(dy, 20.0), 5e-5, 0.02, 1e-3),
}


def height_row(name, fraction):
    build, h, t_end, travel = SCENES[name]
    row = {"scene": name, "offset (steps)": fraction}
    for settle in (True, False):
        _, status, created, halvings = run(*build(fraction * travel), h, t_end, settle=settle)
        key = "settling" if settle else "not"
        row[f"{key}: created"], row[f"{key}: halvings"] = created, halvings
        row[f"{key}: status"] = status
    return row


def step_row(x, speed, divisor, dim):
    _, status, created, halvings = run(*strike(dim, x, speed), 1e-4 / divisor, 0.004)
    return {"x (m)": x, "speed (m/s)": speed, "h (s)": 1e-4 / divisor, "dim": dim,
            "status": status, "created": created, "halvings": halvings}  # fmt: skip


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    speeds = (30.0,) if args.quick else (10.0, 30.0, 100.0, 300.0)
    twins = [twin_row(x, v, s) for x in (0.525, 0.5) for v in speeds for s in (True, False)]
    fractions = (0.0,) if args.quick else (0.0, 0.25, 0.5, 0.75)
    names = ("crossing rods",) if args.quick else tuple(SCENES)
    heights = [height_row(n, f) for n in names for f in fractions]
    divisors = (2,) if args.quick else (1, 2, 4, 8)
    fast = (300.0,) if args.quick else (30.0, 100.0, 300.0)
    steps = [
        step_row(x, v, k, d) for x in (0.525, 0.5) for v in fast for k in divisors for d in (2, 3)
    ]
    sections = (
        ("Twins: the ball on the spatial strip against the disk on the planar one.", twins),
        ("Drop heights a fraction of a step apart, settling and not (created / scale).",
         heights),
        ("The strikes at 30, 100 and 300 m/s against the step.", steps),
    )  # fmt: skip
    title = "A moving body striking a beam along its length" + (" (quick)" if args.quick else "")
    text = report(title, *sections)
    print(text)
    rows = [
        {"table": caption.split(":")[0].split(",")[0], **r} for caption, t in sections for r in t
    ]
    columns = list(dict.fromkeys(k for r in rows for k in r))
    publish(f"{args.out}/beam_strike{'_quick' if args.quick else ''}", rows, columns, text)


if __name__ == "__main__":
    main()
