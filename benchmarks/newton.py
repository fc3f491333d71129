"""Newton on the founding case: step halvings, iterations and the globalization's work.

The default flexible pendulum (1.5 s) at h ∈ {1e-3, 2e-3} s and e_N ∈ {0, 0.5, 1}. Per run:
the step halvings; the smooth Newton iterations per step (mean, max); all iterations per step
(smooth + position + velocity; mean, max); and, from the run's ``StepStats``
(``fecontact.time``), the line-search halvings of an update's length and the directions that
had to be mass-shifted because Newton's pointed uphill on the incremental potential
(``fecontact/time/descent.py``).

    python benchmarks/newton.py            # about 10 s
    python benchmarks/newton.py --quick    # h = 1e-3, e_N = 0.5, through the first impact
"""

from __future__ import annotations

from _common import RESULTS, case, markdown_table, parser, write_csv, write_markdown

from fecontact.time import StepStats, simulate

COLUMNS = [
    "h",
    "e_N",
    "halvings",
    "smooth_mean",
    "smooth_max",
    "total_mean",
    "total_max",
    "line_search_cuts",
    "shifted_directions",
]


def measure(h: float, e: float, t_end: float | None = None) -> dict:
    sim = case("flexible_pendulum").build(restitution=e)
    stats = StepStats()
    smooth, total, halvings = [], [], 0
    t_end = sim.t_end if t_end is None else t_end
    for st in simulate(sim.model, h, t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats):
        if st.step:
            smooth.append(st.iterations["smooth"])
            total.append(st.newton_iterations)
            halvings += st.halvings
    row = {"h": h, "e_N": e, "halvings": halvings}
    row |= {"smooth_mean": sum(smooth) / len(smooth), "smooth_max": max(smooth)}
    row |= {"total_mean": sum(total) / len(total), "total_max": max(total)}
    newton = stats.newton
    row |= {"line_search_cuts": newton.line_search_cuts}
    row |= {"shifted_directions": newton.shifted_directions}
    return row


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    if args.quick:
        rows = [measure(1e-3, 0.5, 0.35)]
    else:
        rows = [measure(h, e) for h in (1e-3, 2e-3) for e in (0.0, 0.5, 1.0)]
    table = markdown_table(rows, COLUMNS)
    print(table)
    out = args.out or RESULTS
    stem = "newton_quick" if args.quick else "newton"
    write_csv(f"{out}/{stem}.csv", rows, COLUMNS)
    write_markdown(f"{out}/{stem}.md", "# Newton on the founding case\n\n" + table)


if __name__ == "__main__":
    main()
