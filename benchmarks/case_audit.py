"""The energy audit of the bundled cases: every case at its defaults and three variants, with
what summary.json says of its energy, fallbacks, warnings and penetration.

Rows per case (each its own subprocess, as in ``benchmarks/case_matrix.py``, whose worker
measures it):

- ``default``: the case as it ships (its ``dt`` and ``t_end``);
- ``off grid``: ``t_end`` moved so that the last step is cut to 0.56 of the step (where the
  default ``t_end`` is already off the grid of ``dt``: ``on grid``, ``t_end`` moved down to the
  last whole step, the run the default's cut step ends beside);
- ``e_N=1``: Newton's coefficient 1 where the case has one;
- ``h x2``: the step doubled.

``last_step``: the last step's fraction of ``dt`` (1: t_end on the grid).

Columns: the ledger's ``created`` (J) and over its ``scale`` (a creation above 1e-3 of the scale
is the ledger's warning), the warnings and fallbacks summary.json counts, step halvings,
``max_penetration`` (m) and the worker's own depth (m, where it has a measure for the case).
A row is flagged where it did not complete, warns, creates energy above the ledger's warning
level or counts a fallback.

    python benchmarks/case_audit.py                 # every case (about 40 min on one core)
    python benchmarks/case_audit.py --quick         # two cheap cases' rows (seconds)
    python benchmarks/case_audit.py --case disk_drop --case two_disks
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from _common import markdown_table, parser, read_csv, write_csv, write_markdown
from case_matrix import ROUND_OFF_J, Row, run_row, run_worker

WARN = 1e-3  # the ledger's warning level, created over scale (fecontact.ledger.CREATED)
CUT = 0.56  # the last step's fraction of dt in the "off grid" rows
QUICK = ("disk_drop", "impacting_bar")
VARIANTS = ("default", "off grid", "e_N=1", "h x2")
COLUMNS = [
    "case",
    "row",
    "status",
    "flags",
    "steps",
    "dt",
    "t_end",
    "last_step",
    "created",
    "created_rel",
    "warnings",
    "halvings",
    "fallbacks",
    "max_penetration",
    "depth",
    "wall",
    "warning",
    "message",
]
SHOWN = COLUMNS[: COLUMNS.index("wall")]


def audit_row(case: str, variant: str) -> dict:
    """Run ``variant`` of ``case`` in this process (see the module docstring)."""
    from fecontact.cli.cases import load_case
    from fecontact.params import declared_parameters

    build = load_case(case).build
    sim = build()
    dt, t_end, params, factor = sim.dt, sim.t_end, {}, 1.0
    label = variant
    if variant == "off grid":
        whole = math.floor(t_end / dt + 1e-9)
        if abs(t_end - whole * dt) <= 1e-9 * dt:
            t_end = (whole - 1 + CUT) * dt
        else:
            t_end, label = whole * dt, "on grid"
    elif variant == "e_N=1":
        if "restitution" not in declared_parameters(build):
            return {"row": variant, "status": "no e_N"}
        params = {"restitution": 1.0}
    elif variant == "h x2":
        factor = 2.0
    out = run_row(Row(case, label, params, {}, factor, t_end))
    out.update(row=label, t_end=t_end, last_step=t_end / out.get("dt", dt) % 1.0 or 1.0)
    return out


def flags(entry: dict) -> str:
    """What the audit flags on ``entry`` (module docstring)."""
    if entry["status"] != "completed":
        return "" if entry["status"] == "no e_N" else entry["status"]
    out = []
    # (a body at rest has a scale of round-off: below ROUND_OFF_J created is round-off too)
    if entry.get("created_rel", 0.0) > WARN and entry.get("created", 0.0) > ROUND_OFF_J:
        out.append("created")
    if entry.get("warnings"):
        out.append("warning")
    if entry.get("fallbacks") or entry.get("halvings"):
        out.append("fallback")
    return " ".join(out)


def run_audit(cases, variants, timeout: float, csv_path: Path) -> list[dict]:
    here = Path(__file__)
    table = []
    for case in cases:
        for variant in variants:
            payload = json.dumps({"case": case, "variant": variant})
            res = run_worker(here, payload, timeout)
            entry = {"case": case, "row": res.get("row", variant)}
            entry.update({k: v for k, v in res.items() if k not in ("q", "v", "row")})
            entry["flags"] = flags(entry)
            table.append(entry)
            write_csv(csv_path, table, COLUMNS)  # (a long audit stopped keeps its rows)
            print(f"{case:24s} {entry['row']:9s} {entry['status']:9s} {entry['flags']}", flush=True)
    return table


def main() -> None:
    p = parser(__doc__.splitlines()[0], from_csv=True)
    p.add_argument("--case", action="append", help="only this case (repeatable)")
    p.add_argument("--timeout", type=float, default=900.0, help="per run, s (default 900)")
    p.add_argument("--variant", action="append", help="only this row (repeatable)")
    p.add_argument("--worker", help=argparse_hidden())
    args = p.parse_args()
    if args.worker:
        w = json.loads(args.worker)
        print(json.dumps(audit_row(w["case"], w["variant"]), default=float))
        return
    from fecontact.testing import bundled_cases

    cases = args.case or (list(QUICK) if args.quick else sorted(bundled_cases()))
    stem = "case_audit" + ("_quick" if args.quick else "")
    if args.from_csv:  # the table of an earlier run, flagged again
        table = read_csv(args.from_csv)
        for r in table:
            r.update({k: str(r[k]) for k in ("case", "row", "status", "fallbacks", "warning")})
            r["flags"] = flags(r)
        write_csv(Path(args.out) / f"{stem}.csv", table, COLUMNS)
    else:
        table = run_audit(
            cases, args.variant or VARIANTS, args.timeout, Path(args.out) / f"{stem}.csv"
        )
    flagged = [r for r in table if r["flags"]]
    text = "\n".join(
        [
            "# Energy audit of the cases" + (" (quick)" if args.quick else ""),
            "",
            f"{len(table)} runs, {len(flagged)} flagged (not completed; created > {WARN:g} of "
            "the scale; a warning; a fallback or step halving). created: the ledger's (J), "
            "created_rel: over its scale.",
            "",
            markdown_table(table, SHOWN),
        ]
    )
    print(text)
    write_markdown(Path(args.out) / f"{stem}.md", text)


def argparse_hidden():
    import argparse

    return argparse.SUPPRESS


if __name__ == "__main__":
    main()
