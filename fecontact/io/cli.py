"""The ``fecontact`` command: run a case, describe its parameters, render a finished run.

    fecontact run CASE.py [--out DIR] [--dt H] [--t-end T] [--output-interval S]
                          [--set NAME=VALUE]... [--render] [--quiet]
    fecontact sweep CASE.py --set NAME=V1,V2,... [--workers N] [--scheduler ADDRESS]
                            [run options]
    fecontact info CASE.py
    fecontact render OUT_DIR_OR_PVD

A case is a Python file with ``build(**params) -> Simulation`` whose parameters are ``Param``
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
import importlib.util
import inspect
import io
import os
import sys
import warnings
from pathlib import Path

from ..errors import InputError, SolverError
from ..params import assignment, declared_parameters

__all__ = ["main", "run_cli", "run_one", "load_case", "parse_value"]


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise InputError(message)


def parse_value(text: str):
    """``--set`` value: int, else float, else the string itself."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def load_case(path) -> object:
    """Import a case file and return its module (it must define ``build``)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"case file not found: {path}")
    spec = importlib.util.spec_from_file_location(f"fecontact_case_{p.stem}", p)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as err:
        raise InputError(f"cannot import case file {path}: {err}") from err
    if not callable(getattr(module, "build", None)):
        raise InputError(f"case file {path} defines no build() function")
    return module


def _split_overrides(build, pairs: list[str]):
    from ..time import IntegratorOptions

    params = inspect.signature(build).parameters
    option_names = {f.name for f in dataclasses.fields(IntegratorOptions)}
    case_kw, option_kw = {}, {}
    for item in pairs:
        name, text = assignment(item)
        if name in params:
            case_kw[name] = parse_value(text)
        elif name in option_names:
            option_kw[name] = parse_value(text)
        else:
            known = ", ".join(list(params) + sorted(option_names - set(params)))
            raise InputError(f"--set: unknown parameter {name!r}; known: {known}")
    return case_kw, option_kw


def _add_run_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", help="output folder (default: out/<case>)")
    p.add_argument("--dt", type=float, help="time step h in s")
    p.add_argument("--t-end", type=float, help="end time in s")
    p.add_argument("--output-interval", type=float, help="simulated time between frames, s")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="override a case parameter or an integrator option",
    )
    p.add_argument("--render", action="store_true", help="render snapshots and an animation")
    p.add_argument("--quiet", action="store_true", help="no progress display")
    p.add_argument("--debug", action="store_true", help="show the traceback of a failing build()")
    p.add_argument(
        "--checkpoint-every",
        type=int,
        default=500,
        metavar="N",
        help="save a checkpoint every N steps (0: never)",
    )
    p.add_argument(
        "--resume", action="store_true", help="continue the run in --out from its last checkpoint"
    )
    p.add_argument(
        "--overwrite", action="store_true", help="replace another case's output in --out"
    )
    p.add_argument(
        "--format",
        choices=("auto", "vtu", "vtkhdf"),
        default="auto",
        help="frames: a .vtu per part and frame (.pvd index), a transient .vtkhdf per part, "
        "or auto: vtkhdf for 3D models of 2000 dofs or more (default)",
    )


def _prepare(build, args, name: str):
    case_kw, option_kw = _split_overrides(build, args.set)
    try:
        sim = build(**case_kw)
    except InputError:
        raise
    except Exception as err:
        if getattr(args, "debug", False):
            raise
        where = f"{type(err).__name__}: {err}".splitlines()[0][:120]
        raise InputError(f"case {name}: build() failed: {where} (--debug shows where)") from None
    from ..simulation import Simulation

    if not isinstance(sim, Simulation):
        raise InputError(f"case {name}: build() must return a Simulation, got {type(sim).__name__}")
    changes = {}
    if args.dt is not None:
        changes["dt"] = args.dt
    if args.t_end is not None:
        changes["t_end"] = args.t_end
    if args.output_interval is not None:
        changes["output_interval"] = args.output_interval
    if option_kw:
        changes["options"] = dataclasses.replace(sim.options, **option_kw)
    if sim.name == "simulation":
        changes["name"] = name
    return sim.replace(**changes) if changes else sim


def _execute(build, args, name: str) -> int:
    from ..simulation import run

    sim = _prepare(build, args, name)
    out = Path(args.out) if args.out else Path("out") / sim.name
    for text in sim.warnings():
        print(f"fecontact: warning: {text}", file=sys.stderr)
    try:
        if args.checkpoint_every < 0:
            raise InputError(f"checkpoint-every must be >= 0, got {args.checkpoint_every}")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # printed above already
            summary = run(
                sim,
                out,
                progress=not args.quiet,
                checkpoint_every=args.checkpoint_every,
                resume=args.resume,
                overwrite=args.overwrite,
                frame_format=args.format,
            )
    except SolverError as err:
        print(f"fecontact: run failed: {err}; results so far are in {out}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"fecontact: interrupted; results so far are in {out}", file=sys.stderr)
        return 130
    except OSError as err:  # a full disk, a folder that cannot be written
        name = Path(err.filename).name if err.filename else "the output"
        why = err.strerror or type(err).__name__
        print(
            f"fecontact: error: cannot write {name}: {why} (what was written stays in --out)",
            file=sys.stderr,
        )
        return 2
    if summary.get("step_halvings"):
        # said even with --quiet: the run did not keep the step it was asked for
        print(
            f"fecontact: warning: {summary['step_halvings']} step(s) of dt = {sim.dt:g} s "
            "were halved to converge (summary.json: step_halvings)",
            file=sys.stderr,
        )
    for text in summary.get("warnings", []):  # said even with --quiet, as the halvings
        print(f"fecontact: warning: {text}", file=sys.stderr)
    if not args.quiet:
        print(
            f"{sim.name}: {summary['steps']} steps in {summary['wall_time_s']:.2f} s, "
            f"{len(summary['impacts'])} impacts, max penetration "
            f"{summary['max_penetration']:.2e} m -> {out}"
        )
    if args.render:
        from .render import render_run

        for path in render_run(out):
            if not args.quiet:
                print(f"  wrote {path}")
    return 0


def _sweep(build, args, case: Path) -> int:
    from .sweep import RUN_OPTIONS, run_sweep, sweep_axes

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
    for name, flag in RUN_OPTIONS.items():
        if getattr(args, name) is not None:
            options += [flag, repr(getattr(args, name))]
    options += [f for f in ("--render", "--overwrite") if getattr(args, f[2:])]
    options += ["--format", args.format]

    def check(values: dict[str, str]) -> None:
        one = argparse.Namespace(**vars(args))
        one.set = [f"{k}={v}" for k, v in values.items() if k not in RUN_OPTIONS]
        for name in RUN_OPTIONS:
            if name in values:
                setattr(one, name, _number(name, values[name]))
        _prepare(build, one, case.stem).warnings()

    out = Path(args.out) if args.out else Path("out") / f"{case.stem}-sweep"
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


def _info(module) -> int:
    build = module.build
    doc = inspect.getdoc(module) or ""
    print(doc.splitlines()[0] if doc else f"case {Path(module.__file__).stem}")
    declared = declared_parameters(build)
    rows = []
    for name, par in inspect.signature(build).parameters.items():
        p = declared.get(name)
        if p is not None:
            rows.append((name, repr(p.default), p.unit, p.allowed, p.text))
            continue
        default = "" if par.default is inspect.Parameter.empty else repr(par.default)
        rows.append((name, default, "-", "", ""))
    head = ("parameter", "default", "unit", "allowed")
    width = [max(len(r[i]) for r in [*rows, head]) for i in range(4)]
    print("  ".join(f"{h:<{w}}" for h, w in zip(head, width, strict=True)) + "  meaning")
    for r in rows:
        print("  ".join(f"{c:<{w}}" for c, w in zip(r[:4], width, strict=True)) + f"  {r[4]}")
    from ..time import IntegratorOptions

    names = [f.name for f in dataclasses.fields(IntegratorOptions)]
    print("integrator options (also --set NAME=VALUE): " + ", ".join(names))
    return 0


def _render(target: str) -> int:
    from .render import render_run

    for p in render_run(render_target(Path(target))):
        print(f"wrote {p}")
    return 0


def render_target(path: Path) -> Path:
    """The ``.pvd`` of a finished run given by its folder or its path, checked to list
    frames that exist and are VTU files."""
    from .output import load_run

    if not path.exists():
        raise InputError(f"render: no such run: {path}")
    if path.is_file() and path.suffix != ".pvd":
        raise InputError(f"render: give a run folder or its .pvd file, got {path.name}")
    try:
        run = load_run(path)
    except (OSError, ValueError, SyntaxError) as err:  # XML parse errors are SyntaxErrors
        raise InputError(f"render: {str(err).splitlines()[0][:150]}") from None
    if len(run.times) == 0:
        raise InputError(f"render: {run.pvd.name} lists no frames")
    for files in (run.files[0], run.files[-1]):
        for name in files.values():
            vtu = run.pvd.parent / name
            head = vtu.read_bytes()[:200] if vtu.is_file() else b""
            if b"<VTKFile" not in head and not head.startswith(b"\x89HDF"):
                why = "is missing" if not vtu.is_file() else "is not a VTU or VTKHDF file"
                raise InputError(f"render: {name}, listed in {run.pvd.name}, {why}")
    return run.pvd


def main(argv=None) -> int:
    """Entry point of the ``fecontact`` command; returns the exit status."""
    parser = _Parser(prog="fecontact", description="Finite element impact dynamics.")
    sub = parser.add_subparsers(dest="command", required=True)
    p_run = sub.add_parser("run", help="run a case")
    p_run.add_argument("case", help="case file (Python, defines build())")
    _add_run_options(p_run)
    p_sweep = sub.add_parser("sweep", help="run every combination of parameter values on Dask")
    p_sweep.add_argument("case", help="case file (Python, defines build())")
    _add_run_options(p_sweep)
    p_sweep.add_argument("--workers", type=int, default=None, help="local worker processes")
    p_sweep.add_argument("--scheduler", help="address of a running dask.distributed scheduler")
    p_info = sub.add_parser("info", help="list a case's parameters")
    p_info.add_argument("case")
    p_render = sub.add_parser("render", help="render a finished run")
    p_render.add_argument("target", help="run folder or its .pvd file")
    try:
        args = parser.parse_args(argv)
        if args.command == "render":
            return _render(args.target)
        module = load_case(args.case)
        if args.command == "info":
            return _info(module)
        if args.command == "sweep":
            return _sweep(module.build, args, Path(args.case))
        return _execute(module.build, args, Path(args.case).stem)
    except InputError as err:
        print(f"fecontact: error: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # the reader of our output closed it (``fecontact info CASE | head``): nothing is
        # wrong; point stdout at devnull so that the interpreter's final flush is silent
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def run_cli(build, argv=None) -> None:
    """Run a case from its own file: ``python cases/NAME.py [run options]``."""
    name = Path(sys.modules[build.__module__].__file__ or "case").stem
    parser = _Parser(prog=f"python {name}.py")
    _add_run_options(parser)
    try:
        args = parser.parse_args(argv)
        status = _execute(build, args, name)
    except InputError as err:
        print(f"fecontact: error: {err}", file=sys.stderr)
        status = 2
    sys.exit(status)
