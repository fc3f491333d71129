"""What a step costs in space: spatial_pendulum (Beam3D) against flexible_pendulum (Beam2D),
the same strip, mass, elements, step and options, run side by side in one process.

Measured, alternating the two cases run after run so that both see the same load on a shared
machine: the compute time per step of each run through the driver (no frames; wall clock, and
the process CPU time, which a busy machine inflates less), and the ratio of each pair of runs;
then the time of one evaluation of each beam's internal force with and without its tangent,
alternating too, and of the spatial step's other per-iteration work on the group (the
gyroscopic force and tangent, q_n ⊕ D, T(D), K (T(D) − I)) and of the strain energy the
recorder asks for each step. Reported: medians and the spread
(min–max) of the ratios. The runs move in the x–y plane (out_of_plane_velocity = 0), where the
two give the same history. ``--kernels`` times the evaluations alone (no runs).
``--compare-kernels`` runs the spatial case with Beam3D's numpy kernel and with its compiled
(numba) kernel beside the planar one, the three alternated, and reports both ratios
(:func:`compare_kernels`).

Then the step's budget, piece by piece (:func:`budget`): per case, the Newton updates, the
force-and-tangent evaluations and the tangents formed but never factorized (a step that ends
on the residual test) per step, counted over a run; and the CPU time of each piece of the
smooth step's Newton loop per call, at a stored state of the swing (step 150), the two cases
alternated piece by piece, times its calls per step: the spatial step's cost beyond the planar
one, where it is spent. A whole step from stored states (``Stepper.step``, no recorder) is
timed the same way.
"""

from __future__ import annotations

import collections
import os
import statistics
import time

import numpy as np
from _common import RESULTS, case, markdown_table, parser, timed_run, write_csv, write_markdown

from fecontact.linalg.direct import factorize
from fecontact.time import simulate
from fecontact.time.generalized_alpha import coefficients
from fecontact.time.state import PhaseTimer
from fecontact.time.stepper import make_stepper

CASES = ("flexible_pendulum", "spatial_pendulum")


def step_times(sims, repeats: int) -> dict:
    """Per case: lists of wall and CPU ms per step over ``repeats`` alternating runs."""
    out = {name: {"wall": [], "cpu": [], "steps": 0, "status": ""} for name in sims}
    for _ in range(repeats):
        for name, sim in sims.items():
            cpu = time.process_time()
            run = timed_run(sim, repeats=1)
            cpu = time.process_time() - cpu
            rec = out[name]
            rec["wall"].append(1e3 * run["compute"] / run["steps"])
            rec["cpu"].append(1e3 * cpu / run["steps"])
            rec["steps"], rec["status"] = run["steps"], run["status"]
    return out


def kernel_times(beams, repeats: int, number: int = 200) -> dict:
    """Per case: lists of µs (process CPU time) per internal-force call with the tangent and
    without, alternating the cases."""
    out = {name: {True: [], False: []} for name in beams}
    for _ in range(repeats):
        for name, beam in beams.items():
            q = np.random.default_rng(0).normal(size=beam.ndof) * 1e-3
            for tangent in (True, False):
                t = time.process_time()
                for _ in range(number):
                    beam.internal(q, tangent)
                out[name][tangent].append(1e6 * (time.process_time() - t) / number)
    return out


def group_times(sim, repeats: int, number: int = 200) -> dict:
    """µs (process CPU time) per call of the spatial step's work besides the kernel, on the
    case's arrays at a random state: the gyroscopic force and tangent, q_n ⊕ D, T(D), and
    S_t's K (T(D) − I) with the T(D) − I it makes, as a Newton iteration asks for them; the
    strain energy, as the recorder asks for it once a step."""
    from fecontact.time.lie import LieGroup, LieStep

    model = sim.model
    rng = np.random.default_rng(1)
    q, v, D = (rng.normal(size=model.n) * s for s in (1e-2, 1.0, 1e-3))
    step = LieStep(LieGroup(model), q)
    step.configuration(D)
    K = rng.normal(size=(model.n_free, model.n_free))
    S = K.copy()
    beam = model.bodies[0]

    calls = {
        "gyroscopic (µs)": lambda: beam.inertial(q, v),
        "q_n ⊕ D (µs)": lambda: step.configuration(D),
        "T(D) (µs)": step.p.tangent,  # (the step's RightIncrements, uncached)
        "K (T(D) − I) (µs)": lambda: step.iteration_matrix(S, K),
        "strain energy (µs)": lambda: beam.energy(q[: beam.ndof]),
    }
    out = {name: [] for name in calls}
    for _ in range(repeats):
        for name, call in calls.items():
            t = time.process_time()
            for _ in range(number):
                call()
            out[name].append(1e6 * (time.process_time() - t) / number)
    return out


def newton_counts(sims) -> dict:
    """Per case, per step of a run: Newton updates (factorized iteration matrices), force
    and tangent evaluations of the beam, those never factorized (evaluations − updates: the
    step ended on the residual test after it) and the strain energies the recorder asks."""
    out = {}
    for name, sim in sims.items():
        beam = sim.model.bodies[0]
        calls = {True: 0, False: 0, "energy": 0}
        internal, energy = beam.internal, beam.energy

        def counted_internal(q, tangent=True, _f=internal, _c=calls):
            _c[bool(tangent)] += 1
            return _f(q, tangent)

        def counted_energy(q, _f=energy, _c=calls):
            _c["energy"] += 1
            return _f(q)

        beam.internal, beam.energy = counted_internal, counted_energy
        try:
            run = timed_run(sim, repeats=1)
        finally:
            del beam.internal, beam.energy  # (the instance's own attributes: back to the class)
        n, updates = run["steps"], run["summary"]["newton_iterations_total"]
        out[name] = {
            "updates": updates / n,
            "evaluations": calls[True] / n,
            "unfactorized": (calls[True] - updates) / n,
            "energies": calls["energy"] / n,
        }
    return out


def _stored(sim, step: int):
    """(the model's stepper, the state after ``step`` steps, the step size)."""
    model = sim.model
    (st,) = collections.deque(
        simulate(model, sim.dt, step * sim.dt * (1 + 1e-9), sim.options, v0=sim.v0), maxlen=1
    )
    return make_stepper(model, sim.options), st, sim.dt


def _pieces(sim, step: int = 150) -> dict:
    """The Newton loop's pieces at the state after ``step`` steps of ``sim``, as calls:
    the step's begin (predictor; on the group q_n ⊕ D), a residual (the force terms with
    their tangents), of which the internal force and tangent and the gyroscopic term, S_t
    (on the group with K (T(D) − I)), its LU, q_n ⊕ D after an update (the begin makes one
    too), a whole step, the energies."""
    stepper, st, h = _stored(sim, step)
    opts, model = stepper.settings, sim.model
    c = coefficients(opts.rho_inf, h)
    loop = opts.plan.loop(model, opts, PhaseTimer()).start(st, st.t + h, c)
    form, timer = loop.form, PhaseTimer()
    form.residual(0)
    stp, lie = form.step, form.lie
    K = loop.elastic.K

    def matrix():
        S = loop.tangent()
        return S if lie is None else lie.iteration_matrix(S, K)

    S = matrix()
    pieces = {
        "begin (predictor)": lambda: loop.start(st, st.t + h, c),
        "residual": lambda: form.residual(0),
        "  internal force + tangent": lambda: model.internal(stp.q),
        "  gyroscopic": None
        if loop.gyroscopic is None
        else (lambda: loop.gyroscopic.evaluate(stp, 0)),
        "S_t": matrix,
        "LU of S_t": lambda: factorize(S),
        "q_n ⊕ D after an update": None if lie is None else (lambda: lie.configuration(stp.X[0])),
        "whole step (no recorder)": lambda: stepper.step(st, h, timer),
        "recorder's energies": lambda: model.kinetic_energy(st.v) + model.strain_energy(st.q),
    }
    return pieces


def budget(sims, repeats: int, number: int = 100) -> tuple[list[dict], str]:
    """The rows of the step's budget (module docstring): per piece, per case, µs per call
    (least over ``repeats`` alternated rounds of ``number`` calls) and calls per step, and the
    spatial step's µs beyond the planar one; and the counts per step, as a sentence."""
    counts = newton_counts(sims)
    pieces = {name: _pieces(sim) for name, sim in sims.items()}
    times = {name: {k: [] for k, f in p.items() if f is not None} for name, p in pieces.items()}
    for _ in range(repeats):
        for key in pieces[CASES[1]]:
            for name in CASES:
                call = pieces[name][key]
                if call is None:
                    continue
                t = time.process_time()
                for _ in range(number):
                    call()
                times[name][key].append(1e6 * (time.process_time() - t) / number)
    rows = []
    for key in pieces[CASES[1]]:
        row, extra = {"piece": key}, 0.0
        for name in CASES:
            n = counts[name]
            per_step = {"begin (predictor)": 1.0, "S_t": n["updates"], "LU of S_t": n["updates"],
                        "q_n ⊕ D after an update": n["updates"], "whole step (no recorder)": 1.0,
                        "recorder's energies": 1.0}.get(key, n["evaluations"])  # fmt: skip
            least = min(times[name][key]) if times[name].get(key) else 0.0
            short = name.split("_")[0]
            row[f"{short} µs/call"], row[f"{short} calls/step"] = least, per_step
            extra += (1.0 if name == CASES[1] else -1.0) * least * per_step
        row["spatial − flexible, µs/step"] = extra
        rows.append(row)
    note = "Per step of a run: " + "; ".join(
        f"{name} " + ", ".join(f"{k} {v:.3f}" for k, v in counts[name].items()) for name in CASES
    )
    return rows, note + "."


def spread(values) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}–{max(values):.2f})"


def kernels_only(sims, repeats: int, out: str, quick: bool) -> None:
    """The ``--kernels`` mode: each beam's force (and tangent), and the group's work."""
    space = CASES[1]
    kernels = kernel_times({n: s.model.bodies[0] for n, s in sims.items()}, repeats)
    times = {}
    for name, k in kernels.items():
        times[f"{name}: force + tangent"] = k[True]
        times[f"{name}: force"] = k[False]
    for name, values in group_times(sims[space], repeats).items():
        times[f"{space}: {name[:-5]}"] = values
    rows = [
        {"evaluation": name, "median (µs)": statistics.median(v), "least (µs)": min(v)}
        for name, v in times.items()
    ]
    columns = list(rows[0])
    table = markdown_table(rows, columns)
    print(table)
    stem = "beam3d_kernels_quick" if quick else "beam3d_kernels"
    write_csv(f"{out}/{stem}.csv", rows, columns)
    write_markdown(f"{out}/{stem}.md", f"# One evaluation in space and in the plane\n\n{table}")


def _spatial(kernel: str, t_end: float):
    """The spatial case with Beam3D's ``kernel`` ("numpy" or "jit"), chosen at its
    construction (the environment's choice, as the case builds its beam)."""
    os.environ["FECONTACT_BEAM3D_KERNEL"] = kernel
    try:
        sim = case(CASES[1]).build().replace(t_end=t_end)
    finally:
        del os.environ["FECONTACT_BEAM3D_KERNEL"]
    assert sim.model.bodies[0].kernel == kernel
    return sim


def compare_kernels(repeats: int, t_end: float, out: str, quick: bool) -> None:
    """The ``--compare-kernels`` mode: flexible_pendulum, spatial_pendulum with the numpy
    kernel and with the jit kernel, run after run alternated; per step wall and CPU, the
    ratios spatial/flexible of each pair, and the force + tangent of each beam alone."""
    sims = {
        "flexible_pendulum": case(CASES[0]).build().replace(t_end=t_end),
        "spatial_pendulum numpy": _spatial("numpy", t_end),
        "spatial_pendulum jit": _spatial("jit", t_end),
    }
    for sim in sims.values():  # (compiled, or loaded from the cache, outside the timing)
        timed_run(sim.replace(t_end=2 * sim.dt), repeats=1)
    steps = step_times(sims, repeats)
    kernels = kernel_times({n: s.model.bodies[0] for n, s in sims.items()}, repeats)
    base = "flexible_pendulum"
    rows = []
    for name in sims:
        s, k = steps[name], kernels[name]
        row = {"case": name, "steps": s["steps"], "status": s["status"]}
        for key in ("wall", "cpu"):
            r = [a / b for a, b in zip(s[key], steps[base][key], strict=True)]
            row[f"{key} per step (ms)"] = statistics.median(s[key])
            row[f"{key} ratio"] = spread(r)
        k_ratio = [a / b for a, b in zip(k[True], kernels[base][True], strict=True)]
        row["force + tangent (µs)"] = statistics.median(k[True])
        row["force + tangent ratio"] = spread(k_ratio)
        rows.append(row)
    columns = list(rows[0])
    table = markdown_table(rows, columns)
    print(table)
    stem = "beam3d_jit_quick" if quick else "beam3d_jit"
    write_csv(f"{out}/{stem}.csv", rows, columns)
    write_markdown(
        f"{out}/{stem}.md",
        "# A step in space with Beam3D's numpy and compiled kernels\n\n"
        f"Ratios to flexible_pendulum: median (min–max) of {repeats} alternated "
        f"triples.\n\n{table}",
    )


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--kernels", action="store_true", help="time the evaluations alone")
    p.add_argument(
        "--compare-kernels", action="store_true", help="the spatial case with both kernels"
    )
    args = p.parse_args()
    t_end, repeats = (0.05, 2) if args.quick else (0.5, 9)
    if args.compare_kernels:
        compare_kernels(repeats, t_end, args.out or RESULTS, args.quick)
        return
    sims = {name: case(name).build().replace(t_end=t_end) for name in CASES}
    if args.kernels:
        kernels_only(sims, repeats, args.out or RESULTS, args.quick)
        return
    steps = step_times(sims, repeats)
    kernels = kernel_times({n: s.model.bodies[0] for n, s in sims.items()}, repeats)
    group = group_times(sims[CASES[1]], repeats)
    base, space = CASES
    ratio = {
        key: [a / b for a, b in zip(steps[space][key], steps[base][key], strict=True)]
        for key in ("wall", "cpu")
    }
    k_ratio = [a / b for a, b in zip(kernels[space][True], kernels[base][True], strict=True)]
    rows = []
    for name in CASES:
        s, k = steps[name], kernels[name]
        rows.append(
            {
                "case": name,
                "steps": s["steps"],
                "status": s["status"],
                "wall per step (ms)": statistics.median(s["wall"]),
                "CPU per step (ms)": statistics.median(s["cpu"]),
                "force + tangent (µs)": statistics.median(k[True]),
                "force (µs)": statistics.median(k[False]),
            }
        )
    columns = list(rows[0])
    table = markdown_table(rows, columns)
    note = (
        f"Ratios spatial/flexible, median (min–max) of {repeats} alternating pairs: step wall "
        f"{spread(ratio['wall'])}, step CPU {spread(ratio['cpu'])}, force + tangent "
        f"{spread(k_ratio)}. Spatial, per call (µs, median): "
        + ", ".join(f"{name[:-5]} {statistics.median(v):.1f}" for name, v in group.items())
        + "."
    )
    parts, counts = budget(sims, repeats)
    part_columns = list(parts[0])
    part_table = markdown_table(parts, part_columns)
    print(table)
    print(note)
    print(part_table)
    print(counts)
    out = args.out or RESULTS
    stem = "beam3d_cost_quick" if args.quick else "beam3d_cost"
    write_csv(f"{out}/{stem}.csv", rows, columns)
    write_csv(f"{out}/{stem}_budget.csv", parts, part_columns)
    write_markdown(
        f"{out}/{stem}.md",
        f"# The cost of a step in space\n\n{table}\n\n{note}\n\n## Where a step goes\n\n"
        f"Per call at a stored state of the swing, least of {repeats} alternated rounds, "
        f"times the calls per step counted over a run.\n\n{part_table}\n\n{counts}",
    )


if __name__ == "__main__":
    main()
