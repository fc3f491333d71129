"""The ``fecontact`` command: run a case, sweep its parameters, describe it, render a run.

    fecontact run CASE [--out DIR] [--dt H] [--t-end T] [--output-interval S]
                       [--set NAME=VALUE]... [--render] [--quiet]
    fecontact sweep CASE --set NAME=V1,V2,... [--workers N] [--scheduler ADDRESS]
                         [run options]
    fecontact info CASE
    fecontact cases
    fecontact render OUT_DIR_OR_PVD
    fecontact --version

CASE is a case file, or the name of a bundled case (``fecontact cases`` lists them). A case
is a Python file with ``build(**params) -> Simulation`` whose parameters are ``Param``
defaults (:mod:`fecontact.params`). ``--set`` values are read as an int, else a float
(``nan`` and ``inf`` parse, then fail validation), else a string; names of
``IntegratorOptions`` fields (``rho_inf``, ``metric``, ...) set the integrator unless the case
takes them itself. Every input error prints one line and exits with status 2; a run that
fails mid-way exits with status 1 and keeps what it wrote.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import inspect
import io
import os
import sys
from pathlib import Path

from ..errors import InputError
from ..extras import need
from ..params import declared_parameters
from ..version import __version__
from .cases import bundled_cases, find_case, load_case
from .run import RUN_OPTIONS, Parser, add_run_options, execute, prepare

__all__ = ["main", "render_target", "run_one"]


def _sweep(build, args, case: Path) -> int:
    from .sweep import run_sweep, sweep_axes

    need("distributed", "sweep")
    if args.resume:
        raise InputError("--resume: a sweep resumes by itself; run the same sweep again")
    axes = sweep_axes(args.set)
    for name, flag in RUN_OPTIONS.items():
        if getattr(args, name) is not None and name in dict(axes):
            raise InputError(f"{flag} and --set {name}: give one of them")
    workers = args.workers if args.workers is not None else os.cpu_count() or 1
    if workers < 1:
        raise InputError(f"--workers must be >= 1, got {workers}")
    options = ["--checkpoint-every", str(args.checkpoint_every)]
    options += [
        item
        for name, flag in RUN_OPTIONS.items()
        if getattr(args, name) is not None
        for item in (flag, repr(getattr(args, name)))
    ]
    options += [f for f in ("--render", "--overwrite") if getattr(args, f[2:])]
    options += ["--format", args.format]

    def check(values: dict[str, str]) -> None:
        one = argparse.Namespace(**vars(args))
        one.set = [f"{k}={v}" for k, v in values.items() if k not in RUN_OPTIONS]
        for name in RUN_OPTIONS.keys() & values.keys():
            setattr(one, name, _number(name, values[name]))
        prepare(build, one, case.stem).warnings()

    # absolute paths: the workers of an external scheduler run in folders of their own
    out = (Path(args.out) if args.out else Path("out") / f"{case.stem}-sweep").resolve()
    return run_sweep(
        case.resolve(), axes, out, options, workers, args.scheduler, args.quiet, check, run_one
    )


def run_one(argv: list[str]) -> dict:
    """Run one ``fecontact run`` command line in this process (a sweep's task on a worker):
    its exit status and the last line it wrote to stderr."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv)
        except Exception as exc:  # a run must never take the sweep down with it
            status = 1
            print(f"{type(exc).__name__}: {exc}", file=err)
    lines = [line for line in err.getvalue().splitlines() if line.strip()]
    return {"exit": status, "message": lines[-1] if lines else ""}


def _number(name: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise InputError(f"--set {name}: expected a number in s, got {text!r}") from None


def _parameter_rows(build) -> list[tuple[str, str, str, str, str]]:
    """(name, default, unit, allowed, meaning) of each parameter of ``build``."""
    declared = declared_parameters(build)
    rows = []
    for name, par in inspect.signature(build).parameters.items():
        p = declared.get(name)
        if p is not None:
            rows.append((name, repr(p.default), p.unit, p.allowed, p.text))
        else:
            default = "" if par.default is inspect.Parameter.empty else repr(par.default)
            rows.append((name, default, "-", "", ""))
    return rows


def _info(module) -> int:
    doc = inspect.getdoc(module) or ""
    print(doc.splitlines()[0] if doc else f"case {Path(module.__file__).stem}")
    rows = _parameter_rows(module.build)
    head = ("parameter", "default", "unit", "allowed")
    width = [max(len(r[i]) for r in [*rows, head]) for i in range(4)]
    print("  ".join(f"{h:<{w}}" for h, w in zip(head, width, strict=True)) + "  meaning")
    for r in rows:
        print("  ".join(f"{c:<{w}}" for c, w in zip(r[:4], width, strict=True)) + f"  {r[4]}")
    from ..time import IntegratorOptions
    from ..time.state import READERS

    names = [f.name for f in dataclasses.fields(IntegratorOptions)]
    every = [n for n in names if n not in READERS]
    some = [f"{n} ({', '.join(READERS[n])})" for n in names if n in READERS]
    print("integrator options (also --set NAME=VALUE): " + ", ".join(every))
    print("  read by some integrators only (others refuse them): " + ", ".join(some))
    return 0


def _cases() -> int:
    """List the bundled cases with the first line of their docstring."""
    import ast

    known = bundled_cases()
    if not known:
        raise InputError("cases: no bundled cases found in this installation")
    width = max(len(n) for n in known)
    for name, path in known.items():
        doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
        print(f"{name:<{width}}  {doc.splitlines()[0] if doc else ''}")
    return 0


def _render(target: str) -> int:
    need("pyvista", "render")
    from ..io.render import render_run

    for p in render_run(render_target(Path(target))):
        print(f"wrote {p}")
    return 0


def render_target(path: Path) -> Path:
    """The ``.pvd`` of a finished run given by its folder or its path, checked to list
    frames that exist and are VTU or VTKHDF files."""
    from ..io.output import load_run

    if not path.exists():
        raise InputError(f"render: no such run: {path}")
    if path.is_file() and path.suffix != ".pvd":
        raise InputError(f"render: give a run folder or its .pvd file, got {path.name}")
    try:
        run = load_run(path)
    except (OSError, ValueError, SyntaxError) as err:  # XML parse errors are SyntaxErrors
        raise InputError(f"render: {str(err).splitlines()[0][:150]}") from None
    if run.pvd is None:
        raise InputError(f"render: {str(path)!r} holds no frames (a run with frames=False)")
    if len(run.times) == 0:
        raise InputError(f"render: {run.pvd.name} lists no frames")
    listed = dict.fromkeys(name for files in run.files for name in files.values())
    for name in listed:  # every frame file, once (a VTKHDF file holds every frame)
        _check_frame_file(run.pvd.parent / name, run.pvd.name)
    return run.pvd


def _check_frame_file(path: Path, index: str) -> None:
    """A frame file listed in ``index`` exists and is VTU (XML) or VTKHDF (HDF5)."""
    try:
        with open(path, "rb") as f:
            head = f.read(200)
    except OSError:
        raise InputError(f"render: {path.name}, listed in {index}, is missing") from None
    if b"<VTKFile" not in head and not head.startswith(b"\x89HDF"):
        raise InputError(f"render: {path.name}, listed in {index}, is not a VTU or VTKHDF file")


def _parser() -> Parser:
    parser = Parser(prog="fecontact", description="Finite element impact dynamics.")
    parser.add_argument("--version", action="version", version=f"fecontact {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    case_help = "case file (Python, defines build()) or the name of a bundled case"
    p_run = sub.add_parser("run", help="run a case")
    p_run.add_argument("case", help=case_help)
    add_run_options(p_run)
    p_sweep = sub.add_parser("sweep", help="run every combination of parameter values on Dask")
    p_sweep.add_argument("case", help=case_help)
    add_run_options(p_sweep)
    p_sweep.add_argument("--workers", type=int, default=None, help="local worker processes")
    p_sweep.add_argument("--scheduler", help="address of a running dask.distributed scheduler")
    p_info = sub.add_parser("info", help="list a case's parameters")
    p_info.add_argument("case", help=case_help)
    sub.add_parser("cases", help="list the bundled cases")
    p_render = sub.add_parser("render", help="render a finished run")
    p_render.add_argument("target", help="run folder or its .pvd file")
    return parser


def _dispatch(args) -> int:
    if args.command == "render":
        return _render(args.target)
    if args.command == "cases":
        return _cases()
    module = load_case(args.case)
    if args.command == "info":
        return _info(module)
    if args.command == "sweep":
        return _sweep(module.build, args, find_case(args.case))
    return execute(module.build, args, find_case(args.case).stem)


def main(argv=None) -> int:
    """Entry point of the ``fecontact`` command; returns the exit status."""
    try:
        return _dispatch(_parser().parse_args(argv))
    except InputError as err:
        print(f"fecontact: error: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # the reader of our output closed it (``fecontact info CASE | head``): nothing is
        # wrong; point stdout at devnull so that the interpreter's final flush is silent
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
