"""3D body-to-body contact on configurations neither the cases nor ``stress_3d.py`` run.

Each row is one run, measured as ``benchmarks/stress_3d.py`` measures its rows (status, the
run's ``max_penetration``, the independent depth of a boundary node inside the partner's
discretized surface over the shortest and over its facet's longest edge, created energy over
the ledger's scale, momentum of free pairs, the lateral speed of head-on pairs, the fallbacks
summary.json counts), and again with p ×1000 and with k ÷100 (the largest change of the
bodies' centres over the run, over R: the converged answer does not depend on them).

Groups:

- ``balls``: two elastic balls (Neo-Hookean rubber, R = 5 cm, no gravity, graded P1 meshes),
  off-centre with Coulomb friction μ = 0.3 and 1 and e_N = 0, 0.5, 1; head-on with μ = 1;
  head-on with a graded ball against a uniform one (either one the mortar's slave side);
  a small stiff ball (E ×10) against the big rubber one, either one the slave side.
- ``slab``: the elastic ball of ``cases/ball_on_slab.py`` by the slab's corner, thrown
  obliquely with friction near its edge, and onto a thin slab (1 cm, one layer).
- ``box``: the elastic ball thrown obliquely with friction onto a fixed rigid box's edge and
  corner.

Rows marked ``localize 0`` are the row above them with ``localize=False`` (the default is
"auto").

    python benchmarks/explore_3d.py            # every row (about 30 min on one core)
    python benchmarks/explore_3d.py --quick    # two small rows (seconds)
    python benchmarks/explore_3d.py --row "mu 1"   # the rows whose label holds the text
"""

from __future__ import annotations

import dataclasses

import numpy as np
from _common import parser, publish_report
from stress_3d import (
    RUBBER,
    R,
    Spec,
    ball_and_box,
    centre_probes,
    depth_probes,
    hertz_time,
    lateral_probe,
    measured_rows,
    momentum_probes,
    report_tables,
    solid_depth,
)

from fecontact import Model
from fecontact.bodies import Solid
from fecontact.bodies.materials import NeoHookean
from fecontact.bodies.meshes import ball_mesh, graded_ball_mesh
from fecontact.contact import Contact
from fecontact.scenes import wave_step
from fecontact.simulation import Simulation

SOFT = NeoHookean(RUBBER.E, RUBBER.nu, RUBBER.rho)
STIFF = NeoHookean(10.0 * RUBBER.E, RUBBER.nu, RUBBER.rho)


def _unit(x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return x / np.linalg.norm(x)


def _rotation(axis, angle: float) -> np.ndarray:
    k = _unit(axis)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


def _ball(centre, radius, toward, spacing, base=2, quadratic=False):
    """A graded ball mesh (``spacing`` × radius at ``toward``), or uniform (spacing None)."""
    if spacing is None:
        return ball_mesh(centre, radius, base, quadratic)
    return graded_ball_mesh(centre, radius, spacing * radius, toward, 0.5, base, quadratic)


def balls(v=1.0, b=0.0, mu=0.0, e=0.0, r2=R, spacing=(0.16, 0.16), stiff=None, swap=False,
          element="P1", method="mortar", base=2):  # fmt: skip
    """Two balls at ``v`` (m/s) each along x, the right one (radius ``r2``) moved sideways by
    ``b`` R; ``spacing``: each ball's cell size at the contact over its radius (None:
    uniform); ``stiff``: "left" or "right" is of E ×10; ``swap``: the right ball is the
    mortar's slave side (the pair's first body); ``element`` P1 or P2, ``method`` mortar or
    node-to-surface (both ways)."""
    gap = 0.02 * R
    y = b * R
    dx = np.sqrt((R + r2 + gap) ** 2 - y**2)
    cl, cr = np.array([-0.5 * dx, 0.0, 0.0]), np.array([0.5 * dx, y, 0.0])
    n = _unit([np.sqrt((R + r2) ** 2 - y**2), y, 0.0])
    p2 = element == "P2"
    ml = _ball(cl, R, cl + R * n, spacing[0], base, p2)
    mr = _ball(cr, r2, cr - r2 * n, spacing[1], base, p2)
    turn = _rotation(n, np.radians(30.0))
    mr = dataclasses.replace(mr, doflocs=cr[:, None] + turn @ (mr.doflocs - cr[:, None]))
    mats = [STIFF if stiff == side else SOFT for side in ("left", "right")]
    left, right = Solid(ml, mats[0], element=element), Solid(mr, mats[1], element=element)
    first, second = (right, left) if swap else (left, right)
    pairs = [Contact(first, second, restitution=e, friction=mu, method=method)]
    if method == "node-to-surface":
        pairs.append(Contact(second, first, restitution=e, friction=mu, method=method))
    model = Model([left, right], pairs, gravity=(0.0, 0.0, 0.0))
    v0 = model.translation(left, (v, 0.0, 0.0)) + model.translation(right, (-v, 0.0, 0.0))
    sl, sr = model.body_slice(0), model.body_slice(1)
    probes = momentum_probes(model) | centre_probes(model, left, "l")
    probes |= centre_probes(model, right, "r")
    probes |= depth_probes(solid_depth(left, right, sl, sr), local=True)
    if b == 0.0:
        probes["lateral"] = lateral_probe(model, (left, right))
    edge = min(left.min_edge_length, right.min_edge_length)
    dt = min(wave_step(left, 1.0), wave_step(right, 1.0)) / (2.0 if p2 else 1.0)
    t_end = gap / (2.0 * v) + 1.4 * hertz_time(v, min(R, r2))
    sim = Simulation(model, dt=dt, t_end=t_end, probes=probes, v0=v0, name="explore_balls",
                     output_interval=t_end)  # fmt: skip
    parts = [f"{v:g} m/s", f"b {b:g}", f"mu {mu:g}", f"e_N {e:g}"]
    if r2 != R:
        parts.append(f"right R {100 * r2:g} cm")
    if spacing != (0.16, 0.16):
        parts.append("meshes " + "/".join("uniform" if s is None else f"{s:g}" for s in spacing))
    if stiff:
        parts.append(f"{stiff} E x10")
    if swap:
        parts.append("right ball slave")
    if p2 or method != "mortar" or base != 2:
        parts.append(f"{element} base {base} {method}")
    return Spec("balls", ", ".join(parts), sim, R, edge, v, free=True, pk=True, step="dx/c")


def _slab(width, thick, divisions, layers):
    half = 0.5 * width
    slab = Solid.box([-half, -half, -thick], [half, half, 0.0], (divisions, divisions, layers),
                     RUBBER)  # fmt: skip
    slab.fix(slab.nodes_where(lambda x: x[2] <= -thick * (1.0 - 1e-9)))
    return slab


def slab(v=(0.0, 0.0, -1.0), offset=(0.0, 0.0), mu=0.0, thick=0.04, layers=2, refinements=2):
    """The elastic ball of ``cases/ball_on_slab.py`` (R, rubber) thrown at ``v`` (m/s) with
    its pole over ``offset`` (m) of the slab (0.2 m, 10 cells, ``thick`` m in ``layers``)."""
    slab_ = _slab(0.2, thick, 10, layers)
    ball = Solid.ball([offset[0], offset[1], R + 0.001], R, refinements, RUBBER)
    model = Model([ball, slab_], [Contact(ball, slab_, friction=mu)], (0.0, 0.0, -9.81))
    probes = centre_probes(model, ball, "b")
    probes |= depth_probes(
        solid_depth(ball, slab_, model.body_slice(0), model.body_slice(1)), local=True
    )
    vz = -v[2]
    t_end = 0.001 / vz + 1.5 * hertz_time(vz, R)
    v0 = model.translation(ball, v)
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="explore_slab", output_interval=t_end)  # fmt: skip
    edge = min(ball.min_edge_length, slab_.min_edge_length)
    label = f"elastic ball ({', '.join(f'{c:g}' for c in v)}) m/s, pole over "
    label += f"({100 * offset[0]:g}, {100 * offset[1]:g}) cm, mu {mu:g}"
    if thick != 0.04:
        label += f", slab {100 * thick:g} cm in {layers} layer" + ("s" if layers > 1 else "")
    return Spec("slab", label, sim, R, edge, vz, pk=True, step="dx/c")


def ball_box(v=(0.0, 0.0, -1.0), where="edge", mu=0.3):
    """The elastic ball thrown at ``v`` (m/s) onto a fixed rigid box 0.3 × 0.3 × 0.05 m,
    its pole 5 mm inside an edge ("edge") or over a corner ("corner"), friction ``mu``."""
    ball, model, probes = ball_and_box(where, 2, friction=mu)
    vz = -v[2]
    t_end = 0.001 / vz + 1.5 * hertz_time(vz, R)
    v0 = model.translation(ball, v)
    sim = Simulation(model, dt=wave_step(ball, 1.0), t_end=t_end, probes=probes, v0=v0,
                     name="explore_box", output_interval=t_end)  # fmt: skip
    label = f"elastic ball ({', '.join(f'{c:g}' for c in v)}) m/s on a rigid box's {where}"
    label += f", mu {mu:g}"
    return Spec("box", label, sim, R, ball.min_edge_length, vz, pk=True, step="dx/c")


def unlocalized(spec: Spec) -> Spec:
    """``spec`` with ``localize=False``."""
    options = dataclasses.replace(spec.sim.options, localize=False)
    return dataclasses.replace(
        spec, sim=spec.sim.replace(options=options), label=spec.label + ", localize 0"
    )


QUICK = [
    lambda: balls(b=0.3, mu=1.0, spacing=(None, None), base=1),
    # (the p and k runs once, on the balls above)
    lambda: dataclasses.replace(
        slab((1.0, 0.0, -1.0), (0.08, 0.0), mu=0.3, refinements=1), pk=False
    ),
]

FULL = [
    lambda: balls(b=0.0, mu=1.0),
    *(lambda b=b, m=m, e=e: balls(b=b, mu=m, e=e)
      for b, m, e in ((0.3, 0.3, 0.0), (0.3, 1.0, 0.0), (0.7, 0.3, 0.5), (0.7, 1.0, 1.0))),
    lambda: unlocalized(balls(b=0.3, mu=0.3)),
    lambda: balls(spacing=(0.16, None)),
    lambda: balls(spacing=(0.16, None), swap=True),
    lambda: balls(b=0.3, mu=0.3, spacing=(0.16, None), swap=True),
    lambda: balls(r2=0.025, stiff="right"),
    lambda: balls(r2=0.025, stiff="right", swap=True),
    lambda: balls(b=0.3, mu=0.3, r2=0.025, stiff="right", swap=True),
    lambda: slab(offset=(0.09, 0.09)),
    lambda: slab((1.0, 0.0, -1.0), (0.08, 0.0), mu=0.3),
    lambda: slab((2.0, 1.0, -1.0), mu=1.0),
    lambda: slab((1.0, 0.0, -1.0), mu=0.3, thick=0.01, layers=1),
    lambda: unlocalized(slab((1.0, 0.0, -1.0), mu=0.3, thick=0.01, layers=1)),
    lambda: ball_box((1.0, 0.0, -1.0), "edge", 0.3),
    lambda: ball_box((1.0, 1.0, -1.0), "corner", 1.0),
]  # fmt: skip

COLUMNS = ("group", "run", "step", "status", "max_penetration (m)", "depth / edge",
           "depth / local edge", "created / scale", "dP / (m v)", "dL / (m v R)", "lateral / v",
           "fallbacks", "p x1000: d centre / R", "k /100: d centre / R", "CPU (s)")  # fmt: skip


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--row", default="", help="run only the rows whose label contains this text")
    args = p.parse_args()
    rows = measured_rows(QUICK if args.quick else FULL, args.row)
    table, summary, failed = report_tables(rows, COLUMNS)
    sections = [("Every run: status, depth, energy, momentum, fallbacks, p and k", summary)]
    if failed:
        sections.append(("Runs that stopped, and why", failed))
    publish_report(args.out, "explore_3d", args.quick,
                   "3D body-to-body contact on configurations no case runs", table,
                   *sections)  # fmt: skip


if __name__ == "__main__":
    main()
