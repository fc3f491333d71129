"""Order of the rolling time of a disk thrown along a plane with friction.

``cases/rolling_disk.py`` (R = 0.1 m, μ = 0.3) thrown at v₀ with spin ω₀: it slips until
t* = (v₀ + ω₀R)/(3μg) and then rolls at (2v₀ − ω₀R)/3. The scheme sticks at the first step end
past t*, so the measured rolling time (the first step whose contact point does not slip) is
late by less than one step. Over twelve throws (v₀ from 1 to 3 m/s, with and without
backspin, so that t* falls at every place inside a step), per step size h = 1e-3/2^k: the
largest and the mean error of the rolling time, the largest error of the rolling speed, and
the orders fitted over h.

    python benchmarks/rolling_order.py        # about a minute
"""

from __future__ import annotations

import numpy as np
from _common import RESULTS, G, case, markdown_table, observed_order, parser, trace, write_markdown

MU, R = 0.3, 0.1
THROWS = [(v0, spin) for v0 in np.linspace(1.0, 3.0, 6) for spin in (0.0, 7.3)]
STEPS = [1e-3 / 2**k for k in range(6)]


def rolling_errors(h: float, throws=THROWS) -> tuple[np.ndarray, np.ndarray]:
    """(t_roll − t*, v_roll − v*) over the ``throws`` (v0, spin) at step h."""
    dt, dv = [], []
    for v0, spin in throws:
        t_star = (v0 + spin * R) / (3 * MU * G)
        sim = case("rolling_disk").build(velocity=v0, spin=spin, friction=MU, radius=R)
        r = trace(sim, dt=h, t_end=t_star + 0.05)
        rolling = np.abs(r["slip"]) <= 1e-10 * v0
        i = int(np.argmax(rolling))
        dt.append(r["t"][i] - t_star)
        dv.append(r["vx"][i] - (2 * v0 - spin * R) / 3)
    return np.array(dt), np.array(dv)


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    rows = []
    for h in STEPS[:2] if args.quick else STEPS:
        dt, dv = rolling_errors(h, THROWS[:2] if args.quick else THROWS)
        rows.append(
            {
                "h": h,
                "max_time_error": np.abs(dt).max(),
                "mean_time_error": np.abs(dt).mean(),
                "max_error_over_h": np.abs(dt).max() / h,
                "min_lateness_over_h": dt.min() / h,
                "max_speed_error": np.abs(dv).max(),
            }
        )
    hs = [r["h"] for r in rows]
    orders = {
        "max": observed_order(hs, [r["max_time_error"] for r in rows]),
        "mean": observed_order(hs, [r["mean_time_error"] for r in rows]),
    }
    columns = list(rows[0])
    table = markdown_table(rows, columns)
    note = (
        f"\n\nFitted order of the rolling time's error: {orders['max']:.2f} (largest), "
        f"{orders['mean']:.2f} (mean over the throws)."
    )
    print(table + note)
    title = "# Rolling time of a disk thrown with friction: error against the step\n\n"
    stem = "rolling_order_quick" if args.quick else "rolling_order"
    write_markdown(f"{args.out or RESULTS}/{stem}.md", title + table + note)


if __name__ == "__main__":
    main()
