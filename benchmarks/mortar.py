"""Mortar against node-to-surface contact: the patch test and the head-on disks.

1. Patch test: two blocks [0, 1] × [0, 0.5] and [0, 1] × [0.5, 1] m (E = 1e7 and 3e7 Pa,
   ν = 0.3, plane strain, non-matching meshes of n_lower and n_upper cells along x), the
   upper one pressed by p = 1e5 Pa, solved statically with small displacements
   (``fecontact.statics.solve_static_contact``). Per method: the largest displacement error
   against the linear solution (relative to the largest displacement) and the spread of the
   contact pressure, max |z_j/p − 1| over the contact nodes (node-to-surface: nodal force over
   the node's tributary length; its corner nodes are left out, where the closest facet is a
   tie between the face and the side of the lower block).
2. ``cases/two_disks.py`` head-on, both methods side by side in one process (two passes for
   node-to-surface, one interface for mortar), at each refinement: the largest sideways
   centre-of-mass speed |v_y| over the impact speed, the final energy over the initial one,
   the exit speed, steps, the wall time per step (ms, median of the repeats) and the share of
   the time loop spent in the contact phase and in the smooth step's assembly (which carries
   the smooth contact force, and with it the mortar integrals of persistent contacts).

    python benchmarks/mortar.py            # refinements 2–5, three repeats (several minutes)
    python benchmarks/mortar.py --quick    # refinements 2–3, one repeat
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from _common import case, parser, publish, report, timed_run

from fecontact.testing import pressed_blocks

PATCH_MESHES = ((7, 4), (4, 7), (5, 5), (13, 6))


def patch_rows():
    rows = []
    for n_low, n_up in PATCH_MESHES:
        for method in ("mortar", "node-to-surface"):
            p = 1e5
            pair, parts, lam, exact = pressed_blocks(n_low, n_up, p, method=method)
            scale = max(np.max(np.abs(u)) for u in exact)
            err = max(np.max(np.abs(u - ue)) for u, ue in zip(parts, exact, strict=True))
            active = lam > 0
            if method == "mortar":
                z = pair.nodal_pressure(lam)[1]
            else:
                x = pair.body.X[pair.nodes, 0]
                order = np.argsort(x)
                trib = np.zeros(len(x))
                trib[order[:-1]] += 0.5 * np.diff(x[order])
                trib[order[1:]] += 0.5 * np.diff(x[order])
                # the face's corners carry half a cell more (they are not slave nodes)
                trib[order[0]] += 0.5 * (x[order[0]] - 0.0)
                trib[order[-1]] += 0.5 * (1.0 - x[order[-1]])
                z = lam / trib
            rows.append(
                {
                    "cells lower/upper": f"{n_low}/{n_up}",
                    "method": method,
                    "active nodes": int(active.sum()),
                    "displacement error": err / scale,
                    "pressure spread": float(np.max(np.abs(z[active] / p - 1.0))),
                }
            )
    return rows


def disk_rows(refinements, repeats):
    rows = []
    for ref in refinements:
        for method in ("node-to-surface", "mortar"):
            sim = case("two_disks").build(refinements=ref, method=method)
            r = timed_run(sim, repeats=repeats)
            h, s = r["history"], r["summary"]
            v0 = 1.0
            ph = r["phases"]
            rows.append(
                {
                    "refinements": ref,
                    "method": method,
                    "status": r["status"],
                    "sideways |vy|/v0": float(
                        max(np.max(np.abs(h["vy_left"])), np.max(np.abs(h["vy_right"]))) / v0
                    ),
                    "E_end/E_0": s["energy_final"] / s["energy_initial"],
                    "exit speed (m/s)": float(h["v_right"][-1]),
                    "steps": r["steps"],
                    "ms per step": 1e3 * r["wall"] / r["steps"],
                    "contact share": ph.get("contact", 0.0) / r["wall"],
                    "assembly share": ph.get("assembly", 0.0) / r["wall"],
                }
            )
            print(rows[-1], flush=True)
    return rows


def main():
    args = parser(__doc__.splitlines()[0]).parse_args()
    refinements, repeats = ((2, 3), 1) if args.quick else ((2, 3, 4, 5), 3)
    patch = patch_rows()
    disks = disk_rows(refinements, repeats)
    text = report(
        "Mortar and node-to-surface contact" + (" (quick)" if args.quick else ""),
        ("Patch test, small displacements, p = 1e5 Pa (relative errors).", patch),
        ("Two elastic disks head-on (cases/two_disks.py), 1 m/s each, side by side.", disks),
    )
    print(text)
    stem = Path(args.out) / ("mortar_quick" if args.quick else "mortar")
    publish(stem, disks, list(disks[0]), text)


if __name__ == "__main__":
    main()
