"""Stress tests of numerical stability: a matrix of runs and what each one did.

Per run: whether it completed ("completed, unstable" where the solver's own energy check,
``summary.json``'s warning, calls it unstable; ``SolverError`` caught: "failed"; non-finite
or runaway energy: "diverged"; over the time budget: "timeout"), the time reached, the max
penetration (m), the energy drift, Newton iterations per step (smooth + position +
velocity; mean and max), the step halvings, and the wall time. Energy drift, with E the
total energy (kinetic + strain + gravity) and K the kinetic energy:

- ``growth %``: max_t (E(t) − E(0)) over the peak kinetic energy max_t K(t), in %;
- ``impact step %``: the largest E_n − E_{n−1} over the steps n where a contact closes, over
  the kinetic energy K_{n−1} before it, in % (negative: every impact dissipates).

Groups (flexible pendulum = ``cases/flexible_pendulum.py``, founding case, 1.5 s unless noted):

1. ``matrix``: ρ∞ ∈ {0, 0.5, 0.8, 0.9, 1} × h ∈ {1e-2, 1e-3, 1e-4} × e_N ∈ {0, 0.5, 1} ×
   metric ∈ {stiffness, mass}; and h = 1e-5 at the default ρ∞ and metric (0.5 s);
2. ``stiffness``: E × {1e-2 … 1e4} with e_N ∈ {0, 1};
3. ``long``: 100 s with e_N = 1 (ρ∞ ∈ {0.5, 0.8, 0.9, 1}) and 60 s with e_N = 0
   (ρ∞ ∈ {0.5, 0.9, 1}), h = 1e-3; ``growth 20 s %`` is the growth over the first 20 s;
4. ``rest``: the ball past its accumulation time; a ball, a box, a beam and a stack of three
   disks at rest on a plane for 10 s (check: gap ≥ −1e-10 m, max |v| < 1e-10, no impact after
   the start, Newton iterations per step not growing);
5. ``many contacts``: a Beam2D with 200 elements falling flat on a plane;
6. ``augmentation``: penalty_scale and multiplier_scale over 1e-8 … 1e8, separately and
   together; ``deviation`` is the max difference of the probes from the run with both at 1,
   over the model size;
7. ``high speed``, ``grazing`` and ``start in contact`` runs;
8. ``solids``: the disk and ball drops and the two disks on small meshes (a disk at 443 m/s,
   four times its wave speed, stops: its elements would invert).

Runs stop early ("diverged") once E − E(0) exceeds 100 times the energy scale of the model
(its weight times its size), and after ``--max-wall`` s ("timeout").

    nohup python benchmarks/stability.py > /tmp/stab.log &     # full matrix, ~30 min
    python benchmarks/stability.py --quick                     # seconds: a check it runs
    python benchmarks/stability.py --workers 2                 # the runs on 2 processes

With ``--workers N`` the runs go to a local Dask cluster of N processes
(``_common.map_runs``, as ``fecontact sweep`` does); the rows are the same, and
``ms_per_step`` is then measured on a machine shared by N runs.
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import math
import os
import time
from dataclasses import dataclass, field, replace

import numpy as np

try:
    from . import _common as common
except ImportError:
    import _common as common

from fecontact import Beam2D, Contact, Material, Model, Plane, Probe, Section, Simulation
from fecontact.bodies.rigid import Disk, Polygon, RigidBody2D

COLUMNS = [
    "group",
    "run",
    "status",
    "t_end",
    "t_reached",
    "h",
    "steps",
    "max_penetration",
    "growth_J",
    "growth_pct",
    "growth_20s_pct",
    "impact_step_pct",
    "newton_mean",
    "newton_max",
    "halvings",
    "retakes",
    "retake_halves",
    "wall_s",
    "ms_per_step",
    "deviation",
    "check",
    "message",
]
TABLE = [
    "run",
    "status",
    "t_reached",
    "max_penetration",
    "growth_J",
    "growth_pct",
    "impact_step_pct",
    "newton_mean",
    "newton_max",
    "halvings",
    "retakes",
    "ms_per_step",
]
HEADERS = {
    "max_penetration": "max pen. (m)",
    "growth_J": "growth (J)",
    "growth_pct": "growth %",
    "growth_20s_pct": "growth 20 s %",
    "impact_step_pct": "impact step %",
    "newton_mean": "Newton mean",
    "newton_max": "Newton max",
    "ms_per_step": "ms/step",
    "t_reached": "t reached (s)",
}


@dataclass
class Spec:
    group: str
    run: str
    make: object  # () -> Simulation
    dt: float | None = None
    t_end: float | None = None
    check: object = None  # (trace, sim) -> str
    reference: str | None = None  # run name of the same group to compare the probes with
    keep: bool = False  # keep the energy history (plots)
    extra: dict = field(default_factory=dict)


# -- models ------------------------------------------------------------------------------------


def pendulum(rho_inf=None, **kw):
    """The founding case with case parameters ``kw``, and ρ∞ as an integrator option."""
    sim = common.case("flexible_pendulum").build(**kw)
    return sim if rho_inf is None else common.with_options(sim, rho_inf=rho_inf)


def with_opts(sim, **opts):
    return common.with_options(sim, **opts) if opts else sim


def ball(**kw):
    return common.case("bouncing_ball").build(**kw)


def box_at_rest(width=0.2, height=0.4, mass=1.0):
    box = RigidBody2D.uniform(mass, [0.0, 0.5 * height], Polygon.box(width, height))
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([box], [Contact(box, floor)], (0.0, -common.G))
    return Simulation(model, dt=1e-3, t_end=10.0, name="box_at_rest")


def beam_on_plane(n=20, height=0.0, restitution=0.0, length=1.0):
    """A free steel strip (20 mm × 5 mm) lying flat ``height`` above the plane y = 0, every
    node a contact."""
    section = Section.rectangle(0.02, 0.005)
    beam = Beam2D.straight(
        [0.0, height], [length, height], n, Material(E=210e9, nu=0.3, rho=7850.0), section
    )
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([beam], [Contact(beam, floor, restitution=restitution)], (0.0, -common.G))
    mid = 3 * (n // 2) + 1
    probes = {"mid_y": Probe(lambda m, st: height + st.q[mid], "m", "mid-node height")}
    return Simulation(model, dt=1e-3, t_end=10.0, probes=probes, name="beam_on_plane")


def disk_stack(n=3, radius=0.1, mass=1.0):
    """``n`` rigid disks stacked on the plane y = 0, touching, at rest."""
    disks = [RigidBody2D.uniform(mass, [0.0, radius * (1 + 2 * k)], Disk(radius)) for k in range(n)]
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    pairs = [Contact(disks[0], floor)]
    pairs += [Contact(disks[k + 1], disks[k]) for k in range(n - 1)]
    model = Model(disks, pairs, (0.0, -common.G))
    return Simulation(model, dt=1e-3, t_end=10.0, name="disk_stack")


def ceiling_graze(offset=0.0, restitution=0.5, height=0.5, radius=0.1):
    """A ball thrown up at √(2 g H) toward a ceiling H + ``offset`` above its top: its apex
    grazes the ceiling (offset 0) with zero normal velocity; the exact impulse is 0."""
    ball_ = RigidBody2D.uniform(1.0, [0.0, 0.0], Disk(radius))
    ceiling = Plane([0.0, radius + height + offset], [0.0, -1.0])
    model = Model([ball_], [Contact(ball_, ceiling, restitution=restitution)], (0.0, -common.G))
    v0 = model.body_vector(ball_, (0.0, math.sqrt(2.0 * common.G * height), 0.0))
    probes = {"y": Probe(lambda m, st: st.q[1], "m", "centre height")}
    t_apex = math.sqrt(2.0 * height / common.G)
    return Simulation(model, dt=1e-3, t_end=2.0 * t_apex, probes=probes, v0=v0, name="graze")


def disk_sliding(speed=1.0):
    """A disk resting on the plane and sliding along it at ``speed`` (frictionless)."""
    disk = RigidBody2D.uniform(1.0, [0.0, 0.1], Disk(0.1))
    floor = Plane([0.0, 0.0], [0.0, 1.0])
    model = Model([disk], [Contact(disk, floor)], (0.0, -common.G))
    v0 = model.body_vector(disk, (speed, 0.0, 0.0))
    probes = {
        "vx": Probe(lambda m, st: st.v[0], "m/s", "horizontal velocity"),
        "y": Probe(lambda m, st: st.q[1], "m", "vertical displacement"),
    }
    return Simulation(model, dt=1e-3, t_end=2.0, probes=probes, v0=v0, name="sliding")


def disk_on_beam_fast(speed):
    """``cases/disk_on_beam.py`` with the disk 1 mm above the beam, moving down at ``speed``."""
    sim = common.case("disk_on_beam").build(drop_height=1e-3)
    disk = sim.model.bodies[1]
    return sim.replace(v0=sim.model.body_vector(disk, (0.0, -speed, 0.0)))


# -- checks ------------------------------------------------------------------------------------


def rest_check(t_from=0.0, gap_probe=None):
    """Resting contact from ``t_from`` on: gap, velocity, chatter and iteration trend."""

    def check(tr, sim):
        late = tr["t"] >= t_from
        if late.sum() < 10:
            return "too short"
        gap = tr[gap_probe][late] if gap_probe else tr["min_gap"][late]
        gmin = float(np.min(gap))
        vmax = float(tr["vmax"][late].max())
        starts = common.episode_starts(tr["active"])
        chatter = int(np.sum(tr["t"][starts] > max(t_from, tr["t"][1]) + 1e-12))
        it = tr["iterations"][late]
        it = it[1:] if not t_from else it  # the first step closes the contact
        # not growing: the second half's tenths stay at the level the first half reached (a
        # run started exactly at equilibrium needs one tenth or so to reach round-off noise)
        tenths = [c.mean() for c in np.array_split(it, 10)] if len(it) >= 10 else [it.mean()]
        level = max(tenths[: max(len(tenths) // 2, 1)])
        ok = gmin >= -1e-10 and vmax < 1e-10 and chatter == 0 and max(tenths) <= level + 0.05
        return (
            f"{'PASS' if ok else 'FAIL'}: min gap {gmin:.2e} m, max abs v {vmax:.2e}, "
            f"impacts after start {chatter}, iterations per tenth of the run "
            + "/".join(f"{x:.2f}" for x in tenths)
        )

    return check


def ball_zeno_check(e, h0=1.0):
    t_zeno = math.sqrt(2 * h0 / common.G) * (1 + e) / (1 - e)
    inner = rest_check(t_zeno + 0.05, gap_probe="gap")

    def check(tr, sim):
        return f"after t_zeno + 0.05 = {t_zeno + 0.05:.3f} s: " + inner(tr, sim)

    return check


def graze_check(offset, restitution=0.5):
    """Total impulse against the exact one: 0 for offset ≥ 0, else (1 + e) m √(2 g |offset|)."""
    exact = (1 + restitution) * math.sqrt(2 * common.G * max(0.0, -offset))

    def check(tr, sim):
        imp = float(tr["impulse"].sum())
        return (
            f"total impulse {imp:.2e} N·s (exact {exact:.2e}), min gap {tr['min_gap'].min():.2e} m"
        )

    return check


def sliding_check(tr, sim):
    dv = float(np.abs(tr["vx"] - tr["vx"][0]).max())
    dy = float(np.abs(tr["y"]).max())
    return f"max abs(vx - vx0) {dv:.2e} m/s, max abs(y) {dy:.2e} m"


def bar_check(tr, sim):
    on = np.flatnonzero(tr["active"])
    dur = tr["t"][on[-1]] if on.size else math.nan
    v0 = sim.parameters["velocity"]
    c = math.sqrt(sim.parameters["E"] / sim.parameters["rho"])
    exact = 2 * sim.parameters["length"] / c
    return (
        f"contact {dur:.4g} s (2L/c = {exact:.4g}), rebound {tr['v_mean'][-1] / v0:.4f} v0, "
        f"E_end/E_0 {tr['total'][-1] / tr['total'][0]:.4f}"
    )


def ball_speed_check(h0, e):
    def check(tr, sim):
        starts = common.episode_starts(tr["active"])
        v_in = math.sqrt(2 * common.G * h0)
        if not starts.size:
            return "no impact"
        n = starts[0]
        after = tr["vy"][n:][: max(3, len(tr["vy"]) // 100)].max()
        return f"impact at {v_in:.3g} m/s, rebound {after / v_in:.4f} v (e = {e})"

    return check


# -- the matrix --------------------------------------------------------------------------------


def quick_specs(spec_list, t_end: float = 0.05) -> list:
    """The first run of each group, over at most ``t_end`` (s): the --quick check that every
    kind of run, measure and check still works (not a measurement)."""
    first = {}
    for spec in spec_list:
        first.setdefault(spec.group, spec)
    short = [min(s.t_end, t_end) if s.t_end else t_end for s in first.values()]
    return [replace(s, t_end=t) for s, t in zip(first.values(), short, strict=True)]


def specs(quick: bool):
    out = []
    T = 0.6 if quick else 1.5
    # 1. ρ∞ × h × e × metric on the flexible pendulum
    rhos = [0.0, 0.5, 1.0] if quick else [0.0, 0.5, 0.8, 0.9, 1.0]
    hs = [1e-2, 1e-3] if quick else [1e-2, 1e-3, 1e-4]
    es = [0.0, 1.0] if quick else [0.0, 0.5, 1.0]
    for metric in ("stiffness", "mass"):
        for rho in rhos:
            for h in hs:
                for e in es:
                    out.append(
                        Spec(
                            "matrix",
                            f"rho_inf={rho:g} h={h:g} e={e:g} metric={metric}",
                            lambda rho=rho, e=e, metric=metric: with_opts(
                                pendulum(restitution=e, rho_inf=rho), metric=metric
                            ),
                            dt=h,
                            t_end=T,
                            extra={"rho_inf": rho, "e": e, "metric": metric},
                        )
                    )
    if not quick:
        for e in (0.0, 1.0):
            out.append(
                Spec(
                    "matrix",
                    f"rho_inf=0.5 h=1e-05 e={e:g} metric=stiffness (0.5 s)",
                    lambda e=e: pendulum(restitution=e),
                    dt=1e-5,
                    t_end=0.5,
                    extra={"rho_inf": 0.5, "e": e, "metric": "stiffness"},
                )
            )
    # 2. stiffness ratios
    for scale in [1e-2, 1.0, 1e4] if quick else [1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4]:
        for e in (0.0, 1.0):
            out.append(
                Spec(
                    "stiffness",
                    f"E=70GPa x {scale:g} e={e:g}",
                    lambda s=scale, e=e: pendulum(E=70e9 * s, restitution=e),
                    dt=1e-3,
                    t_end=T,
                )
            )
    # 3. long runs
    long_e1 = 5.0 if quick else 100.0
    long_e0 = 3.0 if quick else 60.0
    for rho in [0.5, 0.8, 0.9, 1.0]:
        out.append(
            Spec(
                "long",
                f"e=1 rho_inf={rho:g} {long_e1:g} s",
                lambda rho=rho: pendulum(restitution=1.0, rho_inf=rho),
                dt=1e-3,
                t_end=long_e1,
                keep=True,
            )
        )
    for rho in [0.5, 0.9, 1.0]:
        out.append(
            Spec(
                "long",
                f"e=0 rho_inf={rho:g} {long_e0:g} s",
                lambda rho=rho: pendulum(restitution=0.0, rho_inf=rho),
                dt=1e-3,
                t_end=long_e0,
                keep=True,
            )
        )
    # 4. resting contact
    rest_T = 1.0 if quick else 10.0
    e = 0.8
    t_zeno = math.sqrt(2 / common.G) * (1 + e) / (1 - e)
    for h in [1e-3] if quick else [1e-3, 1e-4]:
        out.append(
            Spec(
                "rest",
                f"ball e=0.8 h0=1 past t_zeno (h={h:g})",
                lambda: ball(height=1.0, restitution=e),
                dt=h,
                t_end=t_zeno + (0.5 if quick else 2.0),
                check=ball_zeno_check(e),
            )
        )
    out += [
        Spec(
            "rest",
            f"ball at rest (height=0) {rest_T:g} s",
            lambda: ball(height=0.0),
            dt=1e-3,
            t_end=rest_T,
            check=rest_check(gap_probe="gap"),
        ),
        Spec("rest", f"box at rest {rest_T:g} s", box_at_rest, 1e-3, rest_T, rest_check()),
        Spec(
            "rest",
            f"beam (20 el.) lying on a plane {rest_T:g} s",
            lambda: beam_on_plane(20),
            1e-3,
            rest_T,
            rest_check(),
        ),
        Spec("rest", f"stack of 3 disks {rest_T:g} s", disk_stack, 1e-3, rest_T, rest_check()),
    ]
    # 5. many simultaneous contacts
    for h, es_, t_end in [(1e-3, (0.0, 0.5), 0.2 if quick else 0.5)] + (
        [] if quick else [(1e-4, (0.0,), 0.06)]
    ):
        for e in es_:
            out.append(
                Spec(
                    "many contacts",
                    f"beam 200 el. falls flat from 10 mm, e={e:g}, h={h:g}",
                    lambda e=e: beam_on_plane(200, height=0.01, restitution=e),
                    dt=h,
                    t_end=t_end,
                )
            )
    # 6. augmentation parameters
    scales = [1e-8, 1.0, 1e8] if quick else [1e-8, 1e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6, 1e8]
    for name, make, t_end in (
        ("flexible pendulum e=0.5", lambda: pendulum(restitution=0.5), T),
        ("rigid pendulum e=0.5", lambda: common.case("rigid_pendulum").build(), 1.5),
        ("ball e=0.8", lambda: ball(), 2.7),
    ):
        ref = f"{name}: p x 1, k x 1"
        out.append(Spec("augmentation", ref, make, None, t_end))
        for s in scales if name.startswith("flex") else scales[:: 2 if not quick else 1]:
            for which in ("p", "k", "p,k"):
                if s == 1.0:
                    continue
                opts = {}
                if "p" in which:
                    opts["penalty_scale"] = s
                if "k" in which:
                    opts["multiplier_scale"] = s
                out.append(
                    Spec(
                        "augmentation",
                        f"{name}: {which} x {s:g}",
                        lambda make=make, opts=opts: with_opts(make(), **opts),
                        None,
                        t_end,
                        reference=ref,
                    )
                )
    # 7. high speeds, grazing, starting in contact
    for h0 in [1.0, 100.0] if quick else [1.0, 100.0, 1e4]:
        t1 = math.sqrt(2 * h0 / common.G)
        out.append(
            Spec(
                "high speed",
                f"ball from {h0:g} m ({math.sqrt(2 * common.G * h0):.3g} m/s), h=1e-3",
                lambda h0=h0: ball(height=h0, restitution=0.8),
                1e-3,
                t1 + 0.2 * t1 + 0.01,
                ball_speed_check(h0, 0.8),
            )
        )
    for g in [9.81, 981.0] if quick else [9.81, 981.0, 98100.0]:
        f = math.sqrt(g / 9.81)
        for h in (1e-3, 1e-3 / f) if g != 9.81 else (1e-3,):
            out.append(
                Spec(
                    "high speed",
                    f"flexible pendulum g={g:g} (impact {2.47 * f:.3g} m/s) e=0.5 h={h:.2g}",
                    lambda g=g: pendulum(gravity=g, restitution=0.5),
                    h,
                    1.5 / f,
                )
            )
    for v in [1.0, 10.0] if quick else [1.0, 10.0, 100.0]:
        out.append(
            Spec(
                "high speed",
                f"disk on beam at {v:g} m/s",
                lambda v=v: disk_on_beam_fast(v),
                None,
                0.02 if quick else 0.05,
            )
        )
    for v in [0.01, 0.1] if quick else [0.01, 0.1, 0.5]:
        out.append(
            Spec(
                "high speed",
                f"impacting bar v0={v:g} (strain {v:g})",
                lambda v=v: common.case("impacting_bar").build(velocity=v),
                None,
                2.5,
                bar_check,
            )
        )
    for off in [0.0, 1e-6, -1e-6, 1e-3]:
        out.append(
            Spec(
                "grazing",
                f"ball apex at the ceiling {off:+g} m",
                lambda off=off: ceiling_graze(off),
                None,
                None,
                graze_check(off),
            )
        )
    out.append(
        Spec("grazing", "disk sliding on a plane at 1 m/s", disk_sliding, None, None, sliding_check)
    )
    out += [
        Spec(
            "start in contact",
            "bouncing_ball --set height=0, 1 s",
            lambda: ball(height=0.0),
            1e-3,
            1.0,
            rest_check(gap_probe="gap"),
        ),
        Spec(
            "start in contact",
            "impacting_bar gap=0 (default)",
            lambda: common.case("impacting_bar").build(),
            None,
            2.5,
            bar_check,
        ),
        Spec(
            "start in contact",
            "disk_on_beam drop_height=0",
            lambda: common.case("disk_on_beam").build(drop_height=0.0),
            None,
            0.1,
        ),
        Spec(
            "start in contact",
            "rocking_block (on one corner)",
            lambda: common.case("rocking_block").build(),
            None,
            None,
        ),
        Spec(
            "start in contact",
            "beam (200 el.) lying on a plane, 0.2 s",
            lambda: beam_on_plane(200),
            1e-3,
            0.2,
            rest_check(),
        ),
    ]
    # 8. elastic solids on small meshes (the cases' own steps and end times)
    for name, kw in [
        ("disk_drop", {"refinements": 2}),
        ("disk_drop", {"refinements": 2, "restitution": 1.0}),
        ("disk_drop", {"refinements": 2, "velocity": 443.0}),
        ("two_disks", {"refinements": 2}),
        ("ball_drop", {"refinements": 1}),
    ]:
        out.append(
            Spec(
                "solids",
                f"{name} " + " ".join(f"{k}={v:g}" for k, v in kw.items()),
                lambda name=name, kw=kw: common.case(name).build(**kw),
                None,
                None,
            )
        )
    return out


# -- running -----------------------------------------------------------------------------------


def measure(spec: Spec, sim, tr) -> dict:
    E, K, t = tr["total"], tr["kinetic"], tr["t"]
    n = len(t)
    peak = float(K.max()) if n else math.nan
    scale = abs(sim.model.f_gravity).sum() * sim.model.length  # weight × size, J
    moving = n and peak > 1e-9 * max(scale, 1e-300)
    growth = 100.0 * (E.max() - E[0]) / peak if moving else math.nan
    early = t <= 20.0 + 1e-9
    growth20 = math.nan
    if moving and t[-1] > 20.0:
        growth20 = 100.0 * (E[early].max() - E[0]) / K[early].max()
    starts = common.episode_starts(tr["active"])
    starts = starts[starts > 0]
    ratios = [(E[i] - E[i - 1]) / K[i - 1] for i in starts if K[i - 1] > 1e-12 * peak]
    its = tr["iterations"][1:]
    steps = max(n - 1, 0)
    row = {
        "group": spec.group,
        "run": spec.run,
        "status": _status(tr),
        "t_end": spec.t_end or sim.t_end,
        "t_reached": float(t[-1]) if n else 0.0,
        "h": spec.dt or sim.dt,
        "steps": steps,
        "max_penetration": max(0.0, -float(tr["min_gap"].min())) if n else math.nan,
        "growth_J": float(E.max() - E[0]) if n else math.nan,
        "growth_pct": growth,
        "growth_20s_pct": growth20,
        "impact_step_pct": 100.0 * max(ratios) if ratios else math.nan,
        "newton_mean": float(its.mean()) if its.size else math.nan,
        "newton_max": int(its.max()) if its.size else 0,
        "halvings": int(tr["halvings"].sum()),
        # beam steps that created energy, taken again at rho_inf = 0 (a fallback: counted)
        "retakes": tr["energy_retakes"],
        "retake_halves": tr["energy_retake_halves"],
        "wall_s": tr["wall"],
        "ms_per_step": 1e3 * tr["wall"] / max(steps, 1),
        "deviation": math.nan,
        "check": "",
        "message": "; ".join(filter(None, [tr["message"], *_unstable(tr)]))[:300],
    }
    if spec.check is not None and n > 1:
        row["check"] = spec.check(tr, sim)
    return row


def _unstable(tr) -> list[str]:
    """The verdict of the run's own energy check (``summary.json``'s warning), if any."""
    return [w for w in tr.get("warnings", []) if "integration is unstable" in w]


def _status(tr) -> str:
    """The run's status, "completed" qualified where its own energy check calls it unstable."""
    done = tr["status"] == "completed"
    return "completed, unstable" if done and _unstable(tr) else tr["status"]


def deviation(tr, ref, length):
    """Max difference of the probes (or of the energy, without probes) over the model size."""
    n = min(len(tr["t"]), len(ref["t"]))
    keys = [k for k in ref if k.startswith(("tip_", "theta", "gap", "vy", "omega"))]
    keys = keys or ["total"]
    return max(float(np.abs(tr[k][:n] - ref[k][:n]).max()) for k in keys) / length


def run_spec(spec, max_wall, compared: bool):
    """One run of the matrix: its row, its trace if ``compared`` (a reference or compared to
    one; else None, as when the builder refused) and its energy history if ``spec.keep``."""
    try:
        sim = spec.make()
    except Exception as err:  # a builder rejecting its input is a result too
        row = {"group": spec.group, "run": spec.run, "status": "input error"}
        return row | {"message": f"{type(err).__name__}: {err}"[:300]}, None, None
    scale = abs(sim.model.f_gravity).sum() * sim.model.length

    def abort(row, E0=[None], scale=scale):  # noqa: B006
        if E0[0] is None:
            E0[0] = row["total"]
        return scale > 0 and row["total"] - E0[0] > 100.0 * scale

    start = time.perf_counter()
    tr = common.trace(sim, spec.dt, spec.t_end, max_wall=max_wall, abort=abort)
    row = measure(spec, sim, tr)
    row["_length"], row["_seconds"] = sim.model.length, time.perf_counter() - start
    history = None
    if spec.keep:
        stride = max(1, len(tr["t"]) // 4000)
        history = (tr["t"][::stride], tr["total"][::stride] - tr["total"][0], tr["kinetic"].max())
    return row, tr if compared else None, history


def execute(spec_list, max_wall, workers=1):
    """Every spec's row (with ``deviation`` from its reference run) and the energy histories
    of the runs to plot; the runs go to ``workers`` processes (``common.map_runs``)."""
    refs = {s.reference for s in spec_list}
    results = common.map_runs(
        lambda spec: run_spec(spec, max_wall, spec.run in refs or spec.reference is not None),
        spec_list,
        workers,
        lambda s: s.run,
    )
    traces = {s.run: r[1] for s, r in zip(spec_list, results, strict=True) if r[1] is not None}
    rows, histories = [], {}
    for i, (spec, (row, tr, history)) in enumerate(zip(spec_list, results, strict=True)):
        length, seconds = row.pop("_length", None), row.pop("_seconds", 0.0)
        if tr is not None and spec.reference in traces:
            row["deviation"] = deviation(tr, traces[spec.reference], length)
        if history is not None:
            histories[spec.run] = history
        rows.append(row)
        _report(i, len(spec_list), spec, row, seconds)
    return rows, histories


def _report(i, n, spec, row, seconds):
    if row["status"] == "input error":
        print(f"[{i + 1}/{n}] {spec.run}: input error {row['message']}", flush=True)
        return
    print(
        f"[{i + 1}/{n}] {spec.group}: {spec.run}: {row['status']} "
        f"t={row['t_reached']:.4g} pen={row['max_penetration']:.2e} "
        f"growth={row['growth_pct']:.3g}% impact={row['impact_step_pct']:.3g}% "
        f"newton={row['newton_mean']:.2f}/{row['newton_max']} halv={row['halvings']} "
        f"retakes={row['retakes']}/{row['retake_halves']} "
        f"dev={row['deviation']:.2e} {seconds:.1f}s {row['check']} "
        f"{row['message'][:120]}",
        flush=True,
    )


def tables(rows) -> str:
    parts = []
    for group in dict.fromkeys(r["group"] for r in rows):
        sel = [r for r in rows if r["group"] == group]
        cols = list(TABLE)
        if group == "long":
            cols.insert(6, "growth_20s_pct")
        if group == "augmentation":
            cols.insert(2, "deviation")
        if any(r.get("check") for r in sel):
            cols.append("check")
        if any(r.get("message") for r in sel):
            cols.append("message")
        heads = [HEADERS.get(c, c) for c in cols]
        parts.append(f"### {group}\n\n" + common.markdown_table(sel, cols, heads))
    return "\n\n".join(parts)


def plot(rows, histories, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    ax = axes[0]
    for name, (t, dE, peak) in histories.items():
        ax.plot(t, 100.0 * dE / peak, label=name, lw=0.8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("(E − E0) / peak kinetic energy (%)")
    ax.set_title("flexible pendulum, long runs (h = 1e-3)", fontsize=9)
    ax.set_yscale("symlog", linthresh=1.0)
    ax.legend(fontsize=7)
    ax.grid(True, lw=0.3)
    for ax, metric in zip(axes[1:], ("stiffness", "mass"), strict=True):
        sel = [r for r in rows if r["group"] == "matrix" and r["run"].endswith(metric)]
        rhos = sorted({float(r["run"].split()[0].split("=")[1]) for r in sel})
        cols = sorted({" ".join(r["run"].split()[1:3]) for r in sel})
        grid = np.full((len(rhos), len(cols)), np.nan)
        label = np.full(grid.shape, "", dtype=object)
        for r in sel:
            i = rhos.index(float(r["run"].split()[0].split("=")[1]))
            j = cols.index(" ".join(r["run"].split()[1:3]))
            done = r["status"].startswith("completed")
            grid[i, j] = r["growth_pct"] if done else 1e3
            short = {"diverged": "div", "failed": "fail", "timeout": "time"}
            label[i, j] = f"{r['growth_pct']:.2g}" if done else short.get(r["status"], "?")
        im = ax.imshow(
            np.log10(np.clip(grid, 1e-3, 1e3)), cmap="viridis", aspect="auto", vmin=-3, vmax=3
        )
        ax.set_xticks(range(len(cols)), cols, rotation=60, fontsize=7)
        ax.set_yticks(range(len(rhos)), [f"ρ∞={r:g}" for r in rhos], fontsize=7)
        ax.set_title(f"energy growth % of peak KE, metric={metric} (1.5 s)", fontsize=9)
        for i in range(len(rhos)):
            for j in range(len(cols)):
                color = "k" if grid[i, j] > 10 else "w"
                ax.text(j, i, label[i, j], ha="center", va="center", fontsize=6, color=color)
        fig.colorbar(im, ax=ax, label="log10 growth % (fail/diverged: 3)")
    fig.tight_layout()
    fig.savefig(path, dpi=85)
    plt.close(fig)


def main(argv=None):
    p = common.parser(__doc__.splitlines()[0])
    p.add_argument("--max-wall", type=float, default=1800.0, help="time budget per run (s)")
    p.add_argument("--group", action="append", help="run only these groups (repeatable)")
    p.add_argument(
        "--workers", type=int, default=1, help="local worker processes (Dask) for the runs"
    )
    p.add_argument(
        "--update",
        action="store_true",
        help="with --group: replace those groups' rows in the existing CSV and Markdown",
    )
    args = p.parse_args(argv)
    out = common.Path(args.out)
    note = common.machine_note()
    t0 = time.perf_counter()
    spec_list = quick_specs(specs(True)) if args.quick else specs(False)
    if args.group:
        spec_list = [s for s in spec_list if s.group in args.group]
    rows, histories = execute(spec_list, args.max_wall, args.workers)
    suffix = "_quick" if args.quick else ""
    if args.group and args.update:
        old = common.read_csv(out / f"stability{suffix}.csv")
        fresh = {g: [r for r in rows if r["group"] == g] for g in args.group}
        merged, done = [], set()
        for r in old:
            if r["group"] in fresh:
                if r["group"] not in done:
                    merged += fresh[r["group"]]
                    done.add(r["group"])
            else:
                merged.append(r)
        rows = merged + [r for g, rs in fresh.items() if g not in done for r in rs]
        old = (out / f"stability{suffix}.md").read_text().splitlines()
        note = (old[2] if len(old) > 2 else "").rstrip(".") + (
            f"; then groups {', '.join(args.group)} re-run with `--update` "
            f"({time.perf_counter() - t0:.0f} s, load {os.getloadavg()[0]:.2f})."
        )
    else:
        if args.group:
            suffix += "_" + "_".join(g.replace(" ", "-") for g in args.group)
        note += f"; {time.perf_counter() - t0:.0f} s in total."
    md = tables(rows)
    text = (
        f"# Stability matrix\n\n{note}\n\n"
        "growth %: max (E − E0) over the peak kinetic energy; impact step %: max energy change "
        "over a step where a contact closes, over the kinetic energy before it; Newton: "
        "iterations per step (smooth + position + velocity); ms/step: wall time of "
        "`simulate` with the energy bookkeeping.\n\n" + md
    )
    common.write_csv(out / f"stability{suffix}.csv", rows, COLUMNS)
    common.write_markdown(out / f"stability{suffix}.md", text)
    if histories or not args.update:
        plot(rows, histories, out / f"stability{suffix}.png")
    print(md)
    return rows


if __name__ == "__main__":
    main()
