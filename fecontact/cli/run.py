"""``fecontact run``: one case from its file to its output folder, and the same command line
for a case file run as a script (``python cases/NAME.py [run options]``)."""

from __future__ import annotations

import argparse
import dataclasses
import inspect
import json
import sys
import warnings
from pathlib import Path

from ..errors import InputError, SolverError, did_you_mean
from ..extras import need
from ..io.output import SUMMARY_FILE
from ..io.run_lock import hold_folder
from ..io.termination import Terminated
from ..params import assignment
from .cases import case_origin

__all__ = ["Parser", "add_run_options", "execute", "parse_value", "prepare", "run_cli"]

# the run options that may also be a case parameter or be swept: name -> flag
RUN_OPTIONS = {"dt": "--dt", "t_end": "--t-end", "output_interval": "--output-interval"}


class Parser(argparse.ArgumentParser):
    """An argument parser whose mistakes are ``InputError`` (one line, exit status 2)."""

    def error(self, message):
        raise InputError(message)

    def parse_args(self, args=None, namespace=None):
        argv = sys.argv[1:] if args is None else list(args)
        return super().parse_args(_joined_numbers(argv), namespace)


def _joined_numbers(argv: list[str]) -> list[str]:
    """``argv`` with a number that starts with "-" joined to the option before it ("--dt
    -1e-3" as "--dt=-1e-3"): argparse reads "-1e-3" or "-inf" as an option and said "--dt:
    expected one argument"; joined, the value reaches its range check."""
    out, i = [], 0
    while i < len(argv):
        value = argv[i + 1] if i + 1 < len(argv) else ""
        if argv[i].startswith("--") and "=" not in argv[i] and _negative_number(value):
            out.append(f"{argv[i]}={value}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def _negative_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return text.startswith("-")


def parse_value(text: str):
    """``--set`` value: int, else float, else the string itself."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def split_overrides(build, args) -> tuple[dict, dict]:
    """``--set`` items as (case parameters, integrator options)."""
    from ..time import IntegratorOptions

    params = inspect.signature(build).parameters
    option_names = {f.name for f in dataclasses.fields(IntegratorOptions)}
    case_kw, option_kw = {}, {}
    for item in args.set:
        name, text = assignment(item)
        if name in case_kw or name in option_kw:  # which would win is no user's guess
            raise InputError(f"--set {name} is given twice; give it once")
        if name in params:
            case_kw[name] = parse_value(text)
        elif name in option_names:
            option_kw[name] = parse_value(text)
        else:
            known = ", ".join(list(params) + sorted(option_names - set(params)))
            hint = did_you_mean(name, [*params, *option_names])
            raise InputError(f"--set: unknown parameter {name!r}{hint}; known: {known}")
        if getattr(args, name, None) is not None and name in RUN_OPTIONS:
            raise InputError(f"{RUN_OPTIONS[name]} and --set {name}: give one of them")
    if getattr(args, "rtol", None) is not None:
        if "rtol" in option_kw:
            raise InputError("--rtol and --set rtol: give one of them")
        option_kw["rtol"] = args.rtol
    return case_kw, option_kw


def add_run_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", help="output folder (default: out/<case file name>)")
    p.add_argument("--dt", type=float, help="time step h in s")
    p.add_argument("--t-end", type=float, help="end time in s")
    p.add_argument("--output-interval", type=float, help="simulated time between frames, s")
    p.add_argument(
        "--rtol",
        type=float,
        help="steps chosen by this tolerance on the local error, from dt (the largest) down",
    )
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


def _build(build, case_kw: dict, name: str, debug: bool):
    try:
        sim = build(**case_kw)
    except InputError:
        raise
    except Exception as err:
        if debug:
            raise
        where = f"{type(err).__name__}: {err}".splitlines()[0][:120]
        raise InputError(f"case {name}: build() failed: {where} (--debug shows where)") from None
    from ..simulation import Simulation

    if not isinstance(sim, Simulation):
        raise InputError(f"case {name}: build() must return a Simulation, got {type(sim).__name__}")
    return sim


def prepare(build, args, name: str):
    """The ``Simulation`` of ``build`` with the command line's parameters and run options."""
    case_kw, option_kw = split_overrides(build, args)
    sim = _build(build, case_kw, name, getattr(args, "debug", False))
    changes = {k: getattr(args, k) for k in RUN_OPTIONS if getattr(args, k, None) is not None}
    if changes.keys() & sim.parameters.keys():  # the records say what ran
        changes["parameters"] = sim.parameters | {
            k: v for k, v in changes.items() if k in sim.parameters
        }
    if option_kw:
        changes["options"] = dataclasses.replace(sim.options, **option_kw)
    if sim.name == "simulation":
        changes["name"] = name
    origin = case_origin(build)
    if origin:
        changes["origin"] = origin
    return sim.replace(**changes) if changes else sim


def _run(sim, out: Path, args) -> dict | int:
    """``fecontact.run`` with the command line's options; an exit status if it stopped."""
    from ..simulation import run

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # printed by the caller already
            return run(
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
    except KeyboardInterrupt as err:
        how = "terminated (SIGTERM)" if isinstance(err, Terminated) else "interrupted"
        print(f"fecontact: {how}; {_so_far(out)}", file=sys.stderr)
        return 143 if isinstance(err, Terminated) else 130  # (128 + the signal's number)
    except OSError as err:  # a full disk, a folder that cannot be written
        what = Path(err.filename).name if err.filename else "the output"
        why = err.strerror or type(err).__name__
        print(
            f"fecontact: error: cannot write {what}: {why} (what was written stays in --out)",
            file=sys.stderr,
        )
        return 2


def _so_far(out: Path) -> str:
    """Where an interrupted run's results are: ``out``, if the run wrote its summary there
    (status "interrupted"); a stop before its first step (building the model, checking it)
    wrote nothing."""
    try:
        status = json.loads((out / SUMMARY_FILE).read_text()).get("status")
    except (OSError, ValueError):
        status = None
    if status == "interrupted":
        return f"results so far are in {out}"
    return "stopped before the run wrote anything"


def _report(sim, summary: dict, out: Path, quiet: bool) -> None:
    said = sim.warnings()  # (printed before the run)
    # said even with --quiet: among them the halvings, a run that did not keep its step
    for text in summary.get("warnings", []):
        if text not in said:
            print(f"fecontact: warning: {text}", file=sys.stderr)
    if not quiet:
        print(
            f"{sim.name}: {summary['steps']} steps in {summary['wall_time_s']:.2f} s, "
            f"{len(summary['impacts'])} impacts, max penetration "
            f"{summary['max_penetration']:.2e} m -> {out}"
        )


def execute(build, args, name: str) -> int:
    """Run case ``name`` (its ``build``) as ``args`` say; return the exit status."""
    if args.checkpoint_every < 0:
        raise InputError(f"checkpoint-every must be >= 0, got {args.checkpoint_every}")
    if args.render:  # before the run, not after it
        need("pyvista", "render")
        need("matplotlib", "render")
    out = Path(args.out) if args.out else Path("out") / name
    with hold_folder(out, name):  # before build(): two runs into one folder never mix
        sim = prepare(build, args, name)
        for text in sim.warnings():
            print(f"fecontact: warning: {text}", file=sys.stderr)
        summary = _run(sim, out, args)
    if isinstance(summary, int):
        return summary
    _report(sim, summary, out, args.quiet)
    if args.render:
        from ..io.render import render_run

        for path in render_run(out):
            if not args.quiet:
                print(f"  wrote {path}")
    return 0


def run_cli(build, argv=None) -> None:
    """Run a case from its own file: ``python cases/NAME.py [run options]``."""
    name = Path(sys.modules[build.__module__].__file__ or "case").stem
    parser = Parser(prog=f"python {name}.py")
    add_run_options(parser)
    try:
        args = parser.parse_args(argv)
        status = execute(build, args, name)
    except InputError as err:
        print(f"fecontact: error: {err}", file=sys.stderr)
        status = 2
    sys.exit(status)
