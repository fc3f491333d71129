"""The elastic ball's impact answers against a fine step: energy, contact duration, peak
force and rebound speed.

The linear ball of ``large_solids.py`` (0.1 m/s onto the plane z = 0, ρ∞ = 0.5, e_N = 0),
over one Hertz contact duration t_c at h = t_c/k for each k of ``--steps``, and at the fine
step t_c/``--fine`` on the same mesh. Per row: the final energy (kinetic + strain) over the
initial (kinetic) minus one, and the largest energy gain of one step (% of the initial
energy, with its step); the contact duration (the end of the last step in which a contact
carried a force), the peak force (the largest change of the ball's z-momentum over a window
of t_c/20, in whole steps) and the rebound speed (z-momentum over mass at the end), each
with its difference from the fine step's (%); the wall time of the time loop. A release
step that puts energy in, or a closing inside a step whose correction does, shows in the
largest gain.

    python benchmarks/ball_release.py [--quick] [--sizes 10,18,27] [--steps 10,20,50]
        [--fine 160] [--name ball_release]
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import time
import warnings
from pathlib import Path

import numpy as np

try:
    from . import _common as common
    from .large_solids import SPEED, ball
except ImportError:
    import _common as common
    from large_solids import SPEED, ball

from fecontact import IntegratorOptions
from fecontact.time import simulate

COLUMNS = [
    "dofs",
    "step",
    "final_vs_initial_pct",
    "largest_gain_pct",
    "gain_step",
    "t_c_ms",
    "t_c_vs_fine_pct",
    "F_max_N",
    "F_max_vs_fine_pct",
    "v_out",
    "v_out_vs_fine_pct",
    "wall_s",
]


def answers(size: int, per_tc: int) -> dict:
    """The answers of the linear ball of ``size`` divisions at h = t_c/``per_tc``."""
    model, v0, t_c = ball(size, "linear")
    h = t_c / per_tc
    ez = -v0 / SPEED
    w = model.M_full @ ez  # z-momentum weights
    mass = float(ez @ w)
    energy0 = 0.5 * float(v0 @ (model.M_full @ v0))
    momentum, energy, last = [], [], 0.0
    start = time.perf_counter()
    with warnings.catch_warnings():  # (the ledger's warnings are measured here, as gains)
        warnings.simplefilter("ignore", UserWarning)
        for st in simulate(
            model, h, per_tc * h * (1.0 + 1e-9), IntegratorOptions(rho_inf=0.5), v0=v0
        ):
            momentum.append(float(w @ st.v))
            energy.append(model.kinetic_energy(st.v) + model.strain_energy(st.q))
            if st.step and st.pressed().any():
                last = st.t
    wall = time.perf_counter() - start
    p, gains = np.array(momentum), np.diff(energy)
    gains[gains <= 1e-9 * energy0] = 0.0  # (round-off of the energies' sums)
    k = max(1, round(t_c / 20 / h))
    return {
        "dofs": model.n,
        "step": f"t_c/{per_tc}",
        "final_vs_initial_pct": 100.0 * (energy[-1] / energy0 - 1.0),
        "largest_gain_pct": 100.0 * gains.max() / energy0,
        "gain_step": int(gains.argmax()) + 1 if gains.max() > 0.0 else "",
        "t_c_ms": 1e3 * last,
        "F_max_N": float(np.max(p[k:] - p[:-k]) / (k * h)),
        "v_out": p[-1] / mass,
        "wall_s": wall,
    }


def main():
    parser = common.parser(__doc__)
    parser.add_argument("--sizes", default="10,18,27", help="ball divisions n (n³ × 6 tets)")
    parser.add_argument("--steps", default="10,20,50", help="steps per t_c, comma-separated")
    parser.add_argument("--fine", type=int, default=160, help="steps per t_c of the reference")
    parser.add_argument("--name", default=None, help="results stem (default ball_release)")
    args = parser.parse_args()
    if args.quick:
        sizes, steps, fine = [4], [10], 40
    else:
        sizes = [int(s) for s in args.sizes.split(",")]
        steps, fine = [int(k) for k in args.steps.split(",")], args.fine
    rows = []
    for size in sizes:
        ref = answers(size, fine)
        group = [answers(size, k) for k in steps] + [ref]
        for r in group:
            for key, unit in (("t_c", "_ms"), ("F_max", "_N"), ("v_out", "")):
                r[f"{key}_vs_fine_pct"] = 100.0 * (r[key + unit] / ref[key + unit] - 1.0)
        print(common.markdown_table(group, COLUMNS), flush=True)
        rows += group
    name = args.name or ("ball_release_quick" if args.quick else "ball_release")
    common.write_csv(Path(args.out) / f"{name}.csv", rows, COLUMNS)
    text = common.markdown_table(rows, COLUMNS)
    body = f"# The ball's impact against a fine step\n\n{common.machine_note()}\n\n{text}\n"
    common.write_markdown(Path(args.out) / f"{name}.md", body)


if __name__ == "__main__":
    main()
