"""The output folder of a run: checkpoints that a resumed run continues from, and the clean
start that keeps two runs from mixing their files."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..time import State, record_arrays, records_from_arrays
from ..version import __version__
from .files import atomic_write

__all__ = ["CHECKPOINT", "clear_earlier_run", "jsonable", "load_checkpoint", "save_checkpoint"]


def jsonable(params: dict) -> dict:
    out = {}
    for k, v in params.items():
        try:
            json.dumps(v)
            out[k] = v
        except TypeError:
            out[k] = repr(v)
    return out


CHECKPOINT = "checkpoint.npz"


def fingerprint(sim) -> str:
    """What must match for a checkpoint to continue this simulation: the case file it was built
    from (its SHA-256) and everything but the end time, which a resumed run may extend (also
    when the case takes it as a parameter)."""
    parameters = {k: v for k, v in sim.parameters.items() if k != "t_end"}
    return json.dumps(
        [
            sim.name,
            sim.origin.get("sha256"),
            __version__,
            jsonable(parameters),
            dataclasses.asdict(sim.options),
            sim.dt,
            sim.output_interval,
            sim.model.n,
        ],
        sort_keys=True,
        default=repr,
    )


def save_checkpoint(path: Path, sim, st: State, rec, next_frame: float) -> None:
    """Write ``st`` and the recorder ``rec``'s statistics to ``path`` (atomically)."""
    rec.history.flush()
    arrays = {
        k: getattr(st, k)
        for k in ("q", "v", "vd", "a", "gaps", "candidates", "nu", "impulse", "lam")
    }
    arrays |= {f"memory_{k}": v for k, v in record_arrays(st).items()}
    meta = {
        "t": st.t,
        "step": st.step,
        "h": st.h,
        "h_next": st.h_next,  # the step rtol's control takes next
        "energy_scale": st.energy_scale,  # the energy guard's (fecontact.time.energy_guard)
        "next_frame": next_frame,
        "fingerprint": fingerprint(sim),
        "stats": rec.stats(),
    }
    with atomic_write(path) as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, meta=json.dumps(meta, default=float), **arrays)


def load_checkpoint(path: Path, sim):
    if not path.is_file():
        raise InputError(f"resume: no checkpoint in {path.parent}")
    try:
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            arrays = {k: data[k] for k in data.files if k != "meta"}
        meta["fingerprint"], meta["t"], meta["step"]  # noqa: B018  (present, or unreadable)
    except Exception as err:  # a truncated, empty or foreign file: zip, pickle, JSON errors
        why = f"{type(err).__name__}: {err}".splitlines()[0][:80]
        raise InputError(f"resume: {path.name} is not a readable checkpoint ({why})") from None
    memory = {k[len("memory_") :]: arrays.pop(k) for k in list(arrays) if k.startswith("memory_")}
    records = records_from_arrays(memory)
    if meta["fingerprint"] != fingerprint(sim):
        raise InputError(f"resume: {_what_differs(meta['fingerprint'], sim)}")
    _check_history(path.parent / "history.csv", meta["step"])
    _check_frames(path.parent, sim.name, meta["t"])
    st = State(meta["t"], step=meta["step"], h=meta["h"], **records, **arrays)
    st.h_next = meta.get("h_next", 0.0)
    st.energy_scale = meta.get("energy_scale", 0.0)
    return st, meta


def _what_differs(stored: str, sim) -> str:
    """Why a checkpoint does not continue ``sim``: another case file, or other settings."""
    try:
        name, sha = json.loads(stored)[:2]
    except (ValueError, TypeError):
        name, sha = None, None
    if name != sim.name or (sha and sim.origin.get("sha256") and sha != sim.origin["sha256"]):
        return (
            f"the checkpoint was written by another case file (case {name}); start the run "
            "again without --resume, or choose another --out"
        )
    return "the checkpoint was written with other parameters or options"


def _check_history(path: Path, step: int) -> None:
    """The history a checkpoint at ``step`` continues holds its rows (t = 0 to that step)."""
    try:
        with open(path, encoding="utf-8") as f:
            rows = sum(1 for _ in f) - 1  # less the header
    except OSError:
        rows = -1
    if rows < step + 1:
        held = "is missing" if rows < 0 else f"holds {rows} rows"
        raise InputError(
            f"resume: {path.name} {held}; the checkpoint at step {step} needs {step + 1}; "
            "start the run again without --resume"
        )


def _check_frames(out: Path, name: str, t: float) -> None:
    """Every frame the run's index (``.pvd``, or ``.frames.json`` of VTKHDF frames) lists up
    to the checkpoint's time ``t`` (s) exists."""
    indexes = [out / f"{name}{ext}" for ext in (".pvd", ".frames.json")]
    pvd = next((path for path in indexes if path.is_file()), None)
    if pvd is None:
        return  # a run without frames
    from .output import load_run

    try:
        run = load_run(pvd)
    except (OSError, ValueError, SyntaxError) as err:  # XML parse errors are SyntaxErrors
        raise InputError(f"resume: {pvd.name} is unreadable ({str(err)[:80]})") from None
    for when, files in zip(run.times, run.files, strict=True):
        missing = [f for f in files.values() if not (pvd.parent / f).is_file()]
        if when <= t and missing:
            raise InputError(
                f"resume: {missing[0]}, listed in {pvd.name}, is missing; start the run again "
                "without --resume"
            )


RUN_FILES = ("history.csv", "summary.json", CHECKPOINT, "history.png", "animation.gif")


def clear_earlier_run(out: Path, name: str, overwrite: bool) -> None:
    """Remove the files of an earlier run of case ``name`` in ``out``; another case's run
    there is an error unless ``overwrite`` (then its files go too)."""
    if not out.is_dir():
        return
    cases = {p.stem for p in out.glob("*.pvd")}
    cases |= {p.name[: -len(".frames.json")] for p in out.glob("*.frames.json")}
    others = sorted(cases - {name})
    if others and not overwrite:
        raise InputError(
            f"out: {out} holds the output of case {others[0]}; choose another --out, or "
            "--overwrite to replace it"
        )
    stale = [out / f for f in RUN_FILES] + list(out.glob("snapshot_*.png"))
    for case in cases | {name}:
        stale += [out / f"{case}.pvd", *out.glob(f"{case}_*.vtu")]
        stale += [out / f"{case}.frames.json", *out.glob(f"{case}_*.vtkhdf")]
    for path in stale:
        try:
            path.unlink(missing_ok=True)
        except OSError as err:
            why = f"cannot remove {path.name} of an earlier run: {err.strerror}"
            raise InputError(f"out: {why}") from None
