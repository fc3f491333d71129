"""Every bundled case with contact, perturbed one parameter at a time from its defaults, the
way a user would provoke it: what must hold on every run, and which runs break it.

Per case (the table ``CASES``): the default row over a short end time (the first impact and a
few ms after it), then one row per change: the approach speed × 0.1, × 3 and × 10 where the
case has one (an initial speed, or a drop height scaled by the speed's square, the end time
moved by the change of the approach's duration); e_N 0, 0.5 and 1; μ 0, 0.3 and 1 where the
case has friction; an offset or obliquity where it has one; one coarser and one finer mesh;
the step × 2 and × ½; p × 1000 and k ÷ 100 (``penalty_scale``, ``multiplier_scale``); and
the impact localized (``localize`` on) and not (off).

Each run is a subprocess of this script (``--worker``) with a timeout; it builds the case
through its ``build()`` (so that a parameter value that crashes inside is seen as the crash
it is, not as the command line's one-line error), runs it without frames, and reports:
status, wall time, step halvings, least-squares multipliers, unconverged corrections,
``max_penetration`` and ``mortar_depth`` of summary.json, a depth measured here at every step
from the positions alone (every point of a body against a plane obstacle with the pair's
clearance; the nodes of one 2D solid inside the other's boundary polygon, by ray parity; a
rigid disk's centre against a strip's centreline; two bars' facing ends), the ledger's
``created``/``scale``, the warnings, and for the p and k rows the largest change of the final
positions (over the case's length) and velocities (over the largest initial speed) from the
default row.

A row is flagged when: it did not complete (``failed``, ``timeout``, ``input`` for an
``InputError``, ``crash`` for any other exception); ``created`` > 1e-2 of ``scale``; a
depth beyond the contact tolerance (``max_penetration`` or the independent depth over
``PEN_REL`` of the case's length, or a mortar node beyond ``BOUND`` of an edge); a p/k row's
final state beyond 1e-6 of the default row's; a warning in summary.json.

    python benchmarks/case_matrix.py                  # every case (long on a shared machine)
    python benchmarks/case_matrix.py --quick          # six cheap rows (``QUICK``), seconds
    python benchmarks/case_matrix.py --quick --case rod_drop  # its default row and one more
    python benchmarks/case_matrix.py --case two_disks # one case, every row
    python benchmarks/case_matrix.py --combinations 4 --seed 1  # two changes at once

``--combinations N`` replaces the rows by each case's default row and N rows that each join
two of its changes (drawn with ``--seed`` among pairs that change different things: the
offset with the speed × 10, μ = 1 with e_N = 1, the finer mesh with k ÷ 100, ...): the
failures no single change provokes.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import markdown_table, parser, read_csv, write_csv, write_markdown

G = 9.81
PEN_REL = 1e-6  # depth over the case's length beyond which a row is flagged
CREATED = 1e-2  # ledger's created over its scale beyond which a row is flagged
ROUND_OFF_J = 1e-12  # created energy (J) below which a row at rest is not flagged
PK_REL = 1e-6  # change of the final state under p × 1000 or k ÷ 100 beyond which it is flagged


@dataclasses.dataclass(frozen=True)
class Spec:
    """A case's matrix: ``t_end`` (s) of its rows, ``length`` (m) its size, ``speed`` the
    parameter of its approach (``height``: a drop height, scaled by the speed's square),
    ``approach`` (s) the default approach's duration, the parameters it has (``restitution``,
    ``friction``), ``oblique`` rows (label, {param: value}), ``mesh`` (coarser, finer) sets,
    ``quick`` the labels of the quick subset beside the default row."""

    t_end: float
    length: float
    speed: str = ""
    height: bool = False
    approach: float = 0.0
    restitution: bool = True
    friction: bool = False
    oblique: tuple = ()
    mesh: tuple = ()
    quick: tuple = ("e_N=0.5",)
    fields: dict = dataclasses.field(default_factory=dict)  # fixed changes of every row


CASES = {
    "two_disks": Spec(
        0.004,
        0.1,
        "velocity",
        approach=1e-3,
        friction=True,
        oblique=(
            ("offset 0.3R", {"offset": 0.015}),
            ("offset 0.7R", {"offset": 0.035}),
            ("node-to-surface", {"method": "node-to-surface"}),
        ),
        mesh=({"refinements": 2}, {"refinements": 4}),
        quick=("coarse", "speed x3"),
    ),
    "two_balls": Spec(
        0.0015,
        0.1,
        "velocity",
        approach=1e-4,
        oblique=(
            ("rotate 0", {"rotate": 0.0}),
            ("against plane", {"against": "plane"}),
            ("node-to-surface", {"method": "node-to-surface"}),
        ),
        mesh=({"base": 1}, {"spacing": 0.05}),
        quick=(),
    ),
    "ball_on_slab": Spec(
        0.004,
        0.1,
        "velocity",
        approach=2e-3,
        oblique=(("node-to-surface", {"method": "node-to-surface"}),),
        mesh=({"refinements": 1}, {"divisions": 16}),
        quick=(),
    ),
    "ball_drop": Spec(
        0.004,
        0.1,
        "velocity",
        approach=2e-3,
        oblique=(("P2", {"element": "P2"}),),
        mesh=({"refinements": 1}, {"refinements": 3}),
        quick=("coarse",),
    ),
    "disk_drop": Spec(
        0.004,
        0.1,
        "velocity",
        approach=2e-3,
        friction=True,
        oblique=(
            ("sliding 1 m/s mu 0.3", {"slide_velocity": 1.0, "friction": 0.3}),
            ("linear", {"material": "linear"}),
        ),
        mesh=({"refinements": 2}, {"refinements": 4}),
        quick=("coarse",),
    ),
    "disk_on_beam": Spec(
        0.15,
        1.0,
        "drop_height",
        height=True,
        approach=0.101,
        oblique=(("position 0.25", {"position": 0.25}),),
        mesh=({"n_elements": 10}, {"n_elements": 42}),
    ),
    "two_bars": Spec(
        2.5,
        1.0,
        "velocity",
        oblique=(("gap 0.01", {"gap": 0.01}),),
        mesh=({"n_elements": 50}, {"n_elements": 200}),
    ),
    "impacting_bar": Spec(
        2.5,
        1.0,
        "velocity",
        oblique=(("exact kinematics", {"kinematics": "exact"}),),
        mesh=({"n_elements": 50}, {"n_elements": 200}),
    ),
    "box_stack": Spec(0.3, 0.2, "knock", friction=True),
    "rocking_block": Spec(1.0, 0.4, friction=True, oblique=(("angle 0.4", {"angle": 0.4}),)),
    "sliding_block": Spec(
        1.0,
        0.2,
        restitution=False,
        friction=True,
        oblique=(
            ("velocity 1", {"velocity": 1.0}),
            ("velocity -1", {"velocity": -1.0}),
            ("incline 60", {"incline": 60.0}),
        ),
        quick=("mu=0.3",),
    ),
    "rolling_disk": Spec(
        1.0,
        0.1,
        "velocity",
        restitution=False,
        friction=True,
        oblique=(("backspin 60", {"spin": 60.0}),),
        quick=("mu=1",),
    ),
    "bouncing_ball": Spec(1.0, 0.1, "height", height=True, approach=0.4515),
    "rigid_pendulum": Spec(1.0, 1.0),
    "flexible_pendulum": Spec(
        0.6,
        0.3,
        friction=True,
        mesh=({"n_elements": 2}, {"n_elements": 8}),
    ),
    "spatial_pendulum": Spec(
        0.6,
        0.3,
        friction=True,
        oblique=(("out of plane 1 m/s", {"out_of_plane_velocity": 1.0}),),
        mesh=({"n_elements": 2}, {"n_elements": 8}),
    ),
    "rod_drop": Spec(
        0.02,
        0.5,
        "velocity",
        approach=2e-3,
        friction=True,
        oblique=(
            ("angle 0", {"angle": 0.0}),
            ("angle 80", {"angle": 80.0}),
            ("yaw 20 rad/s mu 0.3", {"yaw_rate": 20.0, "friction": 0.3}),
        ),
        mesh=({"n_elements": 5}, {"n_elements": 20}),
    ),
    "rod_on_post": Spec(
        0.13,
        0.5,
        "spin",
        approach=0.1,
        oblique=(("post at the tip", {"post_distance": 0.49}),),
        mesh=({"n_elements": 5}, {"n_elements": 20}),
    ),
    "tumbling_box": Spec(1.0, 0.2, "velocity", friction=True, oblique=(("spin 0", {"spin": 0}),)),
    "kane_chain": Spec(0.6, 1.0, friction=True, oblique=(("angle2 -100", {"angle2": -100.0}),)),
}


# --quick: the cheapest rows, a few seconds each on one core
QUICK = (
    ("ball_drop", "default"),
    ("disk_drop", "default"),
    ("disk_drop", "coarse"),
    ("two_disks", "coarse"),
    ("bouncing_ball", "default"),
    ("rolling_disk", "mu=1"),
)

# -- the rows -------------------------------------------------------------------------------------


@dataclasses.dataclass
class Row:
    """One run: ``case``, ``label``, case parameters ``params``, integrator ``options``,
    step factor ``dt_factor`` on the case's step, end time ``t_end`` (s)."""

    case: str
    label: str
    params: dict
    options: dict
    dt_factor: float
    t_end: float

    def command(self, dt: float | None = None) -> str:
        """The command line that reproduces the row (``dt``: the step it ran with, s)."""
        parts = [f"python -m fecontact run {self.case} --t-end {self.t_end:g}"]
        # (a switch as 1 or 0: the command line reads neither True nor False)
        values = {**self.params, **self.options}.items()
        parts += [f"--set {k}={int(v) if isinstance(v, bool) else v}" for k, v in values]
        if self.dt_factor != 1.0 and dt:
            parts.append(f"--dt {dt:.6g}")
        return " ".join(parts)


def speed_rows(name: str, spec: Spec, default: dict) -> list[Row]:
    """The approach speed × 0.1, × 3, × 10, the end time moved by the approach's change."""
    rows = []
    for f in (0.1, 3.0, 10.0):
        value = default[spec.speed] * (f * f if spec.height else f)
        # a gap closed at f times the speed takes 1/f of the time; a fall from rest f² higher
        # (f times the speed at its end) takes f times as long
        approach = spec.approach * f if spec.height else spec.approach / f
        t_end = spec.t_end + approach - spec.approach
        rows.append(Row(name, f"speed x{f:g}", {spec.speed: value}, {}, 1.0, t_end))
    return rows


def case_rows(name: str, default: dict) -> list[Row]:
    """Every row of case ``name`` (its declared defaults ``default``)."""
    spec = CASES[name]

    def row(label, params=None, options=None, dt=1.0):
        return Row(name, label, params or {}, options or {}, dt, spec.t_end)

    rows = [row("default")]
    if spec.speed and default.get(spec.speed):
        rows += speed_rows(name, spec, default)
    if spec.restitution:
        rows += [row(f"e_N={e:g}", {"restitution": e}) for e in (0.0, 0.5, 1.0)]
    if spec.friction:
        rows += [row(f"mu={mu:g}", {"friction": mu}) for mu in (0.0, 0.3, 1.0)]
    rows += [row(label, params) for label, params in spec.oblique]
    if spec.mesh:
        rows += [row("coarse", spec.mesh[0]), row("fine", spec.mesh[1])]
    rows += [row("dt x2", dt=2.0), row("dt x0.5", dt=0.5)]
    rows += [row("p x1000", options={"penalty_scale": 1e3})]
    rows += [row("k /100", options={"multiplier_scale": 1e-2})]
    rows += [row("localize on", options={"localize": True})]
    rows += [row("localize off", options={"localize": False})]
    # a row equal to the default (e_N or μ at its default value) is run once
    seen, out = set(), []
    for r in rows:
        key = json.dumps(
            [
                {k: v for k, v in r.params.items() if default.get(k) != v},
                r.options,
                r.dt_factor,
                r.t_end,
            ],
            sort_keys=True,
        )
        if key not in seen or r.label == "default":
            seen.add(key)
            out.append(r)
    return out


def combined_rows(rows: list[Row], n: int, seed: int) -> list[Row]:
    """Per case, its default row and ``n`` rows that each join two of its changes, drawn at
    random (``seed``) among the pairs that change different things: parameters and options
    merged, the step factors multiplied, the later end time kept."""
    rng = random.Random(seed)
    out = []
    for name in dict.fromkeys(r.case for r in rows):
        own = [r for r in rows if r.case == name]
        out += [r for r in own if r.label == "default"]
        changes = [r for r in own if r.label != "default"]
        pairs = [(a, b) for a, b in itertools.combinations(changes, 2) if _apart(a, b)]
        for a, b in rng.sample(pairs, min(n, len(pairs))):
            params, options = {**a.params, **b.params}, {**a.options, **b.options}
            dt, t_end = a.dt_factor * b.dt_factor, max(a.t_end, b.t_end)
            out.append(Row(name, f"{a.label} + {b.label}", params, options, dt, t_end))
    return out


def _apart(a: Row, b: Row) -> bool:
    """Whether rows ``a`` and ``b`` change different things (parameters, options, step)."""
    steps = a.dt_factor != 1.0 and b.dt_factor != 1.0
    return not (steps or a.params.keys() & b.params.keys() or a.options.keys() & b.options.keys())


def quick_rows(rows: list[Row]) -> list[Row]:
    """The default row and the case's quick labels."""
    spec = CASES[rows[0].case]
    keep = {"default", *spec.quick}
    return [r for r in rows if r.label in keep]


# -- the worker: one run in its own process -------------------------------------------------------


def plane_depth(pair, x: np.ndarray) -> float:
    """Deepest of the points ``x`` (n, d) inside the pair's plane obstacle, less its clearance
    (m, 0 outside), within the plane's extent."""
    plane = pair.obstacle
    d = x - plane.point
    h = d @ plane.normal
    if plane.extent is not None:  # a finite wall: only points over it
        lateral = np.linalg.norm(d - h[:, None] * plane.normal, axis=1)
        h = h[lateral <= plane.extent]
    clearance = getattr(pair, "clearance", 0.0) or 0.0
    return float(max(0.0, np.max(clearance - h, initial=-np.inf)))


def polygon_depth(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Deepest of ``points`` inside the polygon with edges a→b (ray parity; m, 0 outside)."""
    x, y = points[:, None, 0], points[:, None, 1]
    crosses = (a[None, :, 1] > y) != (b[None, :, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (y - a[None, :, 1]) / (b[None, :, 1] - a[None, :, 1])
    inside = np.sum(crosses & (a[None, :, 0] + s * (b[None, :, 0] - a[None, :, 0]) > x), 1) % 2
    dist = segment_distance(points, a, b)
    return float(np.max(np.where(inside == 1, dist, 0.0), initial=0.0))


def segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance (m) of each point to the nearest of the segments a→b."""
    d = b - a
    w = points[:, None, :] - a[None]
    t = np.clip(np.einsum("pei,ei->pe", w, d) / np.sum(d * d, axis=1), 0.0, 1.0)
    return np.min(np.linalg.norm(w - t[:, :, None] * d[None], axis=2), axis=1)


def depth_measure(model):
    """``measure(q)``: the deepest point (m) of one body inside another, from the positions
    alone, over the pairs this script knows how to measure; None if it knows none."""
    bodies = list(model.bodies)
    slices = [model.body_slice(i) for i in range(len(bodies))]
    parts = plane_parts(model, bodies, slices) + body_parts(model, bodies, slices)
    if not parts:
        return None
    return lambda q: max(f(q) for f in parts)


def plane_parts(model, bodies, slices) -> list:
    """Depth measures of the bodies against their plane obstacles."""
    from fecontact.contact import Plane

    parts = []
    for pair in model.contacts.pairs:
        if isinstance(getattr(pair, "obstacle", None), Plane):
            i = bodies.index(pair.body)
            parts.append(lambda q, p=pair, i=i: plane_depth(p, bodies[i].positions(q[slices[i]])))
    return parts


def body_parts(model, bodies, slices) -> list:
    """Depth measures between bodies: two 2D solids, a rigid disk on a strip, two bars."""
    from fecontact.bodies import Beam2D, RigidBody2D, Solid

    parts = []
    solids = [i for i, b in enumerate(bodies) if isinstance(b, Solid) and b.dim == 2]
    if len(solids) == 2:
        for i, j in (solids, solids[::-1]):
            parts.append(lambda q, i=i, j=j: solid_in_solid(bodies, slices, q, i, j))
    beams = [i for i, b in enumerate(bodies) if isinstance(b, Beam2D)]
    disks = [i for i, b in enumerate(bodies) if isinstance(b, RigidBody2D)]
    if len(beams) == 1 and len(disks) == 1 and model.contacts.pairs:
        reach = bodies[disks[0]].shape.radius + model.contacts.pairs[0].clearance
        parts.append(lambda q: disk_on_strip(bodies, slices, q, beams[0], disks[0], reach))
    if len(beams) == 2:  # two bars on one axis: the striker's end past the target's
        parts.append(lambda q: bars_overlap(bodies, slices, q))
    return parts


def bars_overlap(bodies, slices, q) -> float:
    """How far the striker (body 0, on the left) reaches past the target's first node (m)."""
    striker = bodies[0].positions(q[slices[0]])[:, 0]
    target = bodies[1].positions(q[slices[1]])[:, 0]
    return max(0.0, float(np.max(striker) - np.min(target)))


def solid_in_solid(bodies, slices, q, i: int, j: int) -> float:
    """Deepest boundary node of 2D solid i inside solid j's boundary polygon (m)."""
    xi = bodies[i].positions(q[slices[i]])[bodies[i].boundary_nodes()]
    xj = bodies[j].positions(q[slices[j]])
    f = bodies[j].boundary_facets()
    return polygon_depth(xi, xj[f[:, 0]], xj[f[:, 1]])


def disk_on_strip(bodies, slices, q, beam: int, disk: int, reach: float) -> float:
    """How far a rigid disk's centre lies within ``reach`` (radius + clearance) of a strip's
    centreline (m, 0 outside)."""
    x = bodies[beam].positions(q[slices[beam]])
    c = bodies[disk].positions(q[slices[disk]]).mean(0)[None]  # the rim's points: its centre
    return max(0.0, reach - float(segment_distance(c, x[:-1], x[1:])[0]))


def mortar_pairs(model) -> bool:
    """Whether a pair of the model is a mortar interface (its nodes may lie inside the other
    body by a fraction of an edge, ``BOUND``)."""
    return any("Mortar" in type(pair).__name__ for pair in model.contacts.pairs)


def shortest_edge(model) -> float:
    """The shortest boundary edge (m) of the model's solids at the start (nan: none)."""
    from fecontact.bodies import Solid

    lengths = [math.nan]
    for i, body in enumerate(model.bodies):
        if isinstance(body, Solid):
            x = body.positions(np.zeros(model.body_slice(i).stop - model.body_slice(i).start))
            f = body.boundary_facets()
            ends = np.roll(f, -1, axis=1)  # every edge of every facet (2D: both ways)
            lengths.append(float(np.min(np.linalg.norm(x[f] - x[ends], axis=-1))))
    return float(np.nanmin(lengths)) if len(lengths) > 1 else math.nan


def run_row(row: Row) -> dict:
    """Run ``row`` in this process: the measurements (see the module docstring)."""
    from fecontact import InputError
    from fecontact.cli.cases import load_case

    out = {"status": "crash", "message": "", "wall": math.nan}
    clock = time.perf_counter()
    last = {}
    try:
        sim = load_case(row.case).build(**row.params)
        options = dataclasses.replace(sim.options, **row.options)
        sim = sim.replace(dt=sim.dt * row.dt_factor, t_end=row.t_end, options=options)
        out["dt"] = sim.dt
        measure = depth_measure(sim.model)
        out.update(mortar=mortar_pairs(sim.model), edge=shortest_edge(sim.model))
        summary = run_measured(sim, measure, out, last, "matrix_depth")
        out.update(measurements(summary, last, measure is not None))
    except InputError as err:
        out.update(status="input", message=str(err)[:300])
    except Exception as err:  # what the matrix looks for: a crash deep inside
        out.update(message=f"{type(err).__name__}: {str(err)[:250]}")
    out["wall"] = time.perf_counter() - clock
    return out


def run_measured(sim, measure, out: dict, last: dict, name: str) -> dict:
    """Run ``sim`` without frames, probed as ``name``: ``last`` keeps its last state, its
    largest speed and the deepest ``measure`` (m; None: not measured) read at its steps;
    ``out`` its status (``failed`` with the message of a ``SolverError``). The run's summary."""
    from fecontact import Probe, SolverError, run
    from fecontact.io.output import read_json

    def probe(model, st):
        last.update(q=st.q.copy(), v=st.v.copy())
        last["vmax"] = max(last.get("vmax", 0.0), float(np.max(np.abs(st.v), initial=0.0)))
        depth = measure(st.q) if measure is not None else math.nan
        last["depth"] = max(last.get("depth", 0.0), depth)
        return depth

    sim = sim.replace(probes={**sim.probes, name: Probe(probe, "m")})
    with tempfile.TemporaryDirectory(prefix=f"{name}_") as tmp:
        try:
            summary = run(sim, tmp, frames=False, checkpoint_every=0)
            out["status"] = "completed"
        except SolverError as err:
            summary = read_json(Path(tmp) / "summary.json")
            out.update(status="failed", message=str(err)[:300])
    return summary


def measurements(summary: dict, last: dict, measured: bool) -> dict:
    """The row's numbers from its ``summary`` and the worker's record ``last``."""
    ledger = summary.get("energy_ledger", {})
    scale = ledger.get("scale") or math.nan
    return {
        "steps": summary.get("steps"),
        "t": summary.get("t_end") if summary.get("status") == "completed" else math.nan,
        "halvings": summary.get("step_halvings", 0),
        "least_squares": summary.get("least_squares_multipliers", 0),
        "final_residual": max(summary.get("final_residuals", {}).values(), default=math.nan),
        "fallbacks": fallbacks(summary),
        "max_penetration": summary.get("max_penetration", math.nan),
        "mortar_depth": summary.get("mortar_depth", 0.0),
        "depth": last.get("depth", math.nan) if measured else math.nan,
        "created": ledger.get("created", math.nan),
        "created_rel": ledger.get("created", math.nan) / scale,
        "warnings": len(summary.get("warnings", [])),
        "warning": "; ".join(summary.get("warnings", []))[:300],
        "q": last["q"].tolist() if "q" in last else None,
        "v": last["v"].tolist() if "v" in last else None,
        "vmax": last.get("vmax", math.nan),
        "impacts": summary.get("localized_impacts", 0),
        "subdivided": summary.get("localization_cost", {}).get("subdivided_steps", 0),
    }


def fallbacks(summary: dict) -> str:
    """The other fallbacks ``summary`` counts, those not zero, as "name count; ..."."""
    counts = {
        "retakes": summary.get("penetration_retakes", 0),
        "line search cuts": summary.get("smooth_newton", {}).get("line_search_cuts", 0),
        "shortened follow-ups": summary.get("velocity_follow_ups", {}).get("shortened", 0),
        "localization fallbacks": sum(summary.get("localization_fallbacks", {}).values()),
        "rejected steps": summary.get("steps_rejected", 0),
    }
    return "; ".join(f"{name} {n}" for name, n in counts.items() if n)


def run_isolated(row: Row, timeout: float) -> dict:
    """``run_row`` in a subprocess of this script, at most ``timeout`` s."""
    return run_worker(Path(__file__), json.dumps(dataclasses.asdict(row)), timeout)


def run_worker(script: Path, payload: str, timeout: float) -> dict:
    """The last JSON line ``script --worker payload`` prints, run in a subprocess for at most
    ``timeout`` s; a timeout or a crash as a row of that status with its message and wall time."""
    here = Path(script).resolve()
    clock = time.perf_counter()
    try:
        done = subprocess.run(
            [sys.executable, str(here), "--worker", payload],
            capture_output=True,
            text=True,
            timeout=timeout,
            cwd=here.parent,
        )
    except subprocess.TimeoutExpired:
        return {
            "status": "timeout",
            "message": f"no answer within {timeout:g} s",
            "wall": time.perf_counter() - clock,
        }
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("{")]
    if done.returncode or not lines:
        tail = done.stderr.strip().splitlines()[-1:] or ["no output"]
        return {"status": "crash", "message": tail[0][:300], "wall": time.perf_counter() - clock}
    return json.loads(lines[-1])


# -- flags and tables ----------------------------------------------------------------------------


def flags(entry: dict, reference: dict | None) -> list[str]:
    """What is wrong with a table row ``entry`` (``reference``: its case's default row)."""
    from fecontact.contact.watch import BOUND

    if entry["status"] != "completed":
        return [entry["status"]]
    out = []
    if entry["created_rel"] > CREATED and entry["created"] > ROUND_OFF_J:
        out.append("created")
    # a mortar interface holds weighted gaps: its nodes may lie inside by BOUND of an edge
    mortar = bool(entry.get("mortar"))
    tol = BOUND * entry["edge"] if mortar else PEN_REL * CASES[entry["case"]].length
    entry["tolerance"] = tol
    deep = max(entry["max_penetration"], np.nan_to_num(entry["depth"]))
    if deep > tol or entry["mortar_depth"] > BOUND:
        out.append("penetration")
    if entry.get("final_residual", 0.0) > 1.0:  # a correction accepted beyond its tolerance
        out.append("residual")
    pk = entry.get("pk_diff", math.nan)  # nan: not a p/k row
    if pk > PK_REL:
        out.append("p/k")
    if new_warnings(entry, reference):
        out.append("warning")
    return out


def new_warnings(res: dict, reference: dict | None) -> bool:
    """Whether the row warns of something (energy, penetration, ...) its default row does not
    (the default row itself: whether it warns at all)."""
    kinds = {w.split(":")[0] for w in res.get("warning", "").split("; ") if w}
    if reference is None or reference is res:
        return bool(kinds)
    return bool(kinds - {w.split(":")[0] for w in reference.get("warning", "").split("; ") if w})


def state_difference(res: dict, ref: dict, length: float) -> float:
    """Largest change of the final positions (over ``length``) and velocities (over the
    largest velocity component of the default run, at least √(g L)/1000) from the default
    row's."""
    q, q0 = np.array(res["q"]), np.array(ref["q"])
    v, v0 = np.array(res["v"]), np.array(ref["v"])
    if q.shape != q0.shape:
        return math.inf
    # a case at rest throughout has a largest velocity of round-off: √(g L)/1000 is the floor
    speed = max(ref.get("vmax") or 0.0, 1e-3 * math.sqrt(G * length))
    return float(max(np.max(np.abs(q - q0)) / length, np.max(np.abs(v - v0)) / speed))


COLUMNS = [
    "case",
    "row",
    "status",
    "flags",
    "wall",
    "steps",
    "halvings",
    "least_squares",
    "fallbacks",
    "final_residual",
    "max_penetration",
    "mortar_depth",
    "depth",
    "tolerance",
    "created_rel",
    "pk_diff",
    "message",
    "command",
    "created",
    "mortar",
    "edge",
    "warning",
]
SHOWN = COLUMNS[: COLUMNS.index("message")]  # the Markdown table's columns


def run_matrix(rows: list[Row], timeout: float, csv_path=None) -> list[dict]:
    """Run ``rows`` one after the other, each in its own process; the table's rows, also
    written to ``csv_path`` after each row (a long matrix stopped keeps what it ran)."""
    table, defaults = [], {}
    for row in rows:
        res = run_isolated(row, timeout)
        entry = {
            "case": row.case,
            "row": row.label,
            "command": row.command(res.get("dt")),
            **{k: v for k, v in res.items() if k not in ("q", "v")},
        }
        if row.label == "default":
            defaults[row.case] = res
        reference = defaults.get(row.case)
        pk = row.label in ("p x1000", "k /100") and res.get("q") is not None
        if pk and reference and reference.get("q") is not None:
            entry["pk_diff"] = state_difference(res, reference, CASES[row.case].length)
        # (a default row is its own reference: flagged where it warns at all, as combine() does)
        entry["flags"] = " ".join(flags(entry, entry if row.label == "default" else reference))
        entry["message"] = res.get("message") or res.get("warning", "")
        table.append(entry)
        if csv_path is not None:
            write_csv(csv_path, table, COLUMNS)
        print(
            f"{row.case:18s} {row.label:22s} {res['status']:9s} {res.get('wall', 0):6.1f} s "
            f"{entry['flags']}",
            flush=True,
        )
    return table


def all_rows(names) -> list[Row]:
    from fecontact.cli.cases import load_case
    from fecontact.params import declared_parameters

    rows = []
    for name in names:
        default = {k: p.default for k, p in declared_parameters(load_case(name).build).items()}
        rows += case_rows(name, default)
    return rows


def main() -> None:
    args = options().parse_args()
    if args.worker:
        print(json.dumps(run_row(Row(**json.loads(args.worker))), default=float))
    elif args.combine:
        combine(args.combine, args.out, args.name or "case_matrix", args.quick)
    else:
        rows = selected_rows(args)
        stem = args.name or "case_matrix" + ("_" + "_".join(args.case) if args.case else "")
        stem += f"_combinations{args.seed}" if args.combinations and not args.name else ""
        stem += "_quick" if args.quick else ""
        table = run_matrix(rows, args.timeout, Path(args.out) / f"{stem}.csv")
        publish_table(table, args.out, stem, args.quick)


def options():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--case", action="append", help="only this case (repeatable)")
    p.add_argument("--timeout", type=float, default=300.0, help="per run, s (default 300)")
    p.add_argument("--row", action="append", help="only the rows of this label (repeatable)")
    p.add_argument("--name", help="stem of the result files (default: case_matrix)")
    p.add_argument("--combine", nargs="+", help="tables of earlier runs (CSV) to write as one")
    p.add_argument(
        "--combinations",
        type=int,
        default=0,
        help="per case, N rows each joining two of its changes drawn at random (default 0)",
    )
    p.add_argument("--seed", type=int, default=0, help="of --combinations' draw (default 0)")
    p.add_argument("--worker", help=argparse_hidden())
    return p


def selected_rows(args) -> list[Row]:
    """The rows the command line asks for."""
    names = args.case or list(CASES)
    unknown = sorted(set(names) - set(CASES))
    if unknown:
        raise SystemExit(f"--case: unknown {unknown[0]!r}; known: {', '.join(CASES)}")
    rows = all_rows(names)
    if args.combinations:
        rows = combined_rows(rows, args.combinations, args.seed)
    if args.row:  # the default row too: the p/k rows' reference
        rows = [r for r in rows if r.label in {"default", *args.row}]
    if args.quick and args.case:
        return [r for name in names for r in quick_rows([x for x in rows if x.case == name])]
    if args.quick:  # the cheapest rows, seconds each (the tests run them)
        return [r for r in rows if (r.case, r.label) in QUICK]
    return rows


def combine(paths, out: str, stem: str, quick: bool) -> None:
    """One table of the CSVs ``paths`` (a row run again in a later one replaces the earlier),
    flagged again, published as ``out``/``stem``."""
    runs = {(r["case"], r["row"]): r for path in paths for r in read_csv(path)}
    table = list(runs.values())
    defaults = {r["case"]: r for r in table if r["row"] == "default"}
    text = ("case", "row", "status", "flags", "message", "command", "warning", "fallbacks")
    for r in table:  # an empty cell is a number not measured
        r.update({k: math.nan for k, v in r.items() if v == "" and k not in text})
        r.update({k: str(r[k]) for k in text})
        r["flags"] = " ".join(flags(r, defaults.get(r["case"])))
    publish_table(table, out, stem, quick)


def publish_table(table: list[dict], out: str, stem: str, quick: bool) -> None:
    """Print the table of runs and write it as ``out``/``stem``.{csv,md}."""
    write_csv(Path(out) / f"{stem}.csv", table, COLUMNS)
    flagged = [r for r in table if r["flags"]]
    text = "\n".join(
        [
            "# Case matrix" + (" (quick)" if quick else ""),
            "",
            f"{len(table)} runs, {len(flagged)} flagged. Flags: not completed (failed, timeout, "
            f"input, crash); created > {CREATED:g} of the scale; penetration beyond "
            f"{PEN_REL:g} of the case's length or a mortar node beyond 1 % of an edge; p/k: the "
            f"final state moved by more than {PK_REL:g}; residual: a converged correction left "
            "its residual above its tolerance; warning: summary.json warns.",
            "",
            markdown_table(table, SHOWN),
            "",
            "## Flagged rows: command lines",
            "",
            *[
                f"- {r['case']} / {r['row']}: `{r['command']}` — {r['message'][:200]}"
                for r in flagged
            ],
        ]
    )
    print(text)
    write_markdown(Path(out) / f"{stem}.md", text)


def argparse_hidden():
    import argparse

    return argparse.SUPPRESS


if __name__ == "__main__":
    main()
