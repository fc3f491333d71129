"""The output folder of a run: checkpoints that a resumed run continues from, and the clean
start that keeps two runs from mixing their files."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import InputError
from ..time import State, record_arrays, records_from_arrays
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
    """What must match for a checkpoint to continue this simulation."""
    return json.dumps(
        [
            sim.name,
            __version__,
            jsonable(sim.parameters),
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
        raise InputError("resume: the checkpoint was written with other parameters or options")
    st = State(meta["t"], step=meta["step"], h=meta["h"], **records, **arrays)
    return st, meta


RUN_FILES = ("history.csv", "summary.json", CHECKPOINT, "history.png", "animation.gif")


def clear_earlier_run(out: Path, name: str, overwrite: bool) -> None:
    """Remove the files of an earlier run of case ``name`` in ``out``; another case's run
    there is an error unless ``overwrite`` (then its files go too)."""
    if not out.is_dir():
        return
    cases = {p.stem for p in out.glob("*.pvd")}
    others = sorted(cases - {name})
    if others and not overwrite:
        raise InputError(
            f"out: {out} holds the output of case {others[0]}; choose another --out, or "
            "--overwrite to replace it"
        )
    stale = [out / f for f in RUN_FILES] + list(out.glob("snapshot_*.png"))
    for case in cases | {name}:
        stale += [out / f"{case}.pvd", *out.glob(f"{case}_*.vtu")]
    for path in stale:
        try:
            path.unlink(missing_ok=True)
        except OSError as err:
            why = f"cannot remove {path.name} of an earlier run: {err.strerror}"
            raise InputError(f"out: {why}") from None
