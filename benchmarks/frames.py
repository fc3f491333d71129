"""Frame writing: VTU (a file per part and frame) against transient VTKHDF (a file per part,
geometry once), side by side on the dropped ball.

The states come from runs of ``cases/ball_drop.py`` at ``refinements`` 2, 3 and 4 (512 to
32 768 tetrahedra; ``--quick``: 2 only), a frame at every step of the drop. The fields of each frame
(``frame_parts``: displacement, velocity, contact forces and pressure, stress) are computed once
and shared; what is timed is the writer alone, ``write_frame`` per frame, in one process,
the formats alternating over ``--rounds`` rounds (the table gives the median frame of the
fastest round). Sizes are the bytes on disk after the run, per frame.

    python benchmarks/frames.py            # about a minute
    python benchmarks/frames.py --quick
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

from _common import machine_note, markdown_table, parser, write_csv, write_markdown

from fecontact.io.frames import frame_parts, static_parts
from fecontact.io.output import frame_writer
from fecontact.testing import case
from fecontact.time import simulate

FORMATS = ("vtu", "vtkhdf")


def states(refinements: int, frames: int):
    """(simulation, [(t, parts)]) of the first ``frames`` steps of the ball dropped onto the
    plane (no initial gap: it touches at once)."""
    sim = case("ball_drop").build(refinements=refinements, drop_height=0.0)
    out = []
    for st in simulate(sim.model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0):
        if st.step >= 1:
            out.append((st.t, frame_parts(sim.model, st)))
        if len(out) == frames:
            break
    return sim, out


def write_all(fmt: str, sim, frames, folder: Path) -> dict:
    writer = frame_writer(fmt, folder, sim.name)
    for part, mesh in static_parts(sim.model).items():
        writer.write_static(part, mesh)
    seconds = []
    for t, parts in frames:
        start = time.perf_counter()
        writer.write_frame(t, parts)
        seconds.append(time.perf_counter() - start)
    writer.close()
    moving = [p for p in folder.iterdir() if "obstacle" not in p.name and p.suffix != ".json"]
    size = sum(p.stat().st_size for p in moving)
    return {
        "format": fmt,
        "first_frame_ms": 1e3 * seconds[0],
        "frame_ms": 1e3 * statistics.median(seconds[1:]),
        "total_s": sum(seconds),
        "bytes_per_frame": size / len(frames),
    }


def measure(refinements: int, n: int, rounds: int) -> list[dict]:
    sim, frames = states(refinements, n)
    body = sim.model.bodies[0]
    best: dict[str, dict] = {}
    for r in range(rounds):
        for fmt in FORMATS if r % 2 == 0 else FORMATS[::-1]:
            with tempfile.TemporaryDirectory(prefix="fecontact_frames_") as tmp:
                row = write_all(fmt, sim, frames, Path(tmp))
            if fmt not in best or row["total_s"] < best[fmt]["total_s"]:
                best[fmt] = row
    size = {"refinements": refinements, "dofs": body.ndof, "cells": body.n_elements}
    rows = [size | best[f] for f in FORMATS]
    for row in rows:
        row["time_ratio"] = row["frame_ms"] / best["vtu"]["frame_ms"]
        row["size_ratio"] = row["bytes_per_frame"] / best["vtu"]["bytes_per_frame"]
    return rows


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=3)
    args = p.parse_args()
    sizes, n = ([2], 10) if args.quick else ([2, 3, 4], 20)
    rows = [row for refinements in sizes for row in measure(refinements, n, args.rounds)]
    columns = list(rows[0])
    stem = "frames_quick" if args.quick else "frames"
    write_csv(Path(args.out) / f"{stem}.csv", rows, columns)
    text = "\n".join([
        "# Frame writing: VTU against transient VTKHDF",
        "",
        machine_note() + ".",
        "",
        f"ball_drop at refinements {', '.join(map(str, sizes))} (8·8^n linear tetrahedra); "
        f"{n} frames each (a frame every step of the drop); best of {args.rounds} "
        "alternating rounds. Fields per frame: displacement, velocity, contact force, impulse "
        "and pressure (points), stress tensor, von Mises, pressure (cells). Writer time only "
        "(the fields are computed once and shared).",
        "",
        markdown_table(rows, columns),
        "",
        "`first_frame_ms`: the first frame, which writes the geometry in VTKHDF; `frame_ms`: "
        "the median of the others; `bytes_per_frame`: the body's files on disk over the "
        "frames; ratios against VTU of the same mesh.",
    ])  # fmt: skip
    write_markdown(Path(args.out) / f"{stem}.md", text)
    print(text)


if __name__ == "__main__":
    main()
