"""One run at a time in an output folder: a lock file held from before the case is built until
the run has written its summary.

The lock is a file created exclusively (``O_CREAT | O_EXCL``, atomic on local and network file
systems) holding the process, host, case and start time of its holder. A lock left by a
process of this host that no longer exists (killed) is stale and taken over. The process that
holds a folder may enter it again (the command line takes it before ``build()``, ``run`` again
around the run).
"""

from __future__ import annotations

import json
import os
import socket
import time
from contextlib import contextmanager
from pathlib import Path

from ..errors import InputError

__all__ = ["LOCK_FILE", "hold_folder"]

LOCK_FILE = ".fecontact.lock"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def _holder(path: Path) -> dict | None:
    """The record of the lock at ``path``, or None if there is none (or it was just freed)."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    except (OSError, ValueError):  # being written this instant: a holder all the same
        return {"pid": -1, "host": "?", "case": "?", "started": "?"}


def _create(path: Path, record: dict) -> bool:
    try:
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    except FileExistsError:
        return False
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        json.dump(record, f)
    return True


def _mine(holder: dict) -> bool:
    return holder.get("pid") == os.getpid() and holder.get("host") == socket.gethostname()


def _stale(holder: dict) -> bool:
    pid = holder.get("pid")
    same_host = holder.get("host") == socket.gethostname()
    return same_host and isinstance(pid, int) and pid > 0 and not _alive(pid)


def _take(path: Path, record: dict) -> bool:
    """Take the lock; False if this process holds it already. Raises if another does."""
    for _ in range(3):  # a stale lock removed, or freed, between two looks: look again
        if _create(path, record):
            return True
        holder = _holder(path)
        if holder is None:
            continue
        if _mine(holder):
            return False
        if not _stale(holder):
            raise InputError(
                f"out: {path.parent} is in use by a run of case {holder.get('case')} "
                f"(process {holder.get('pid')} on {holder.get('host')}, started "
                f"{holder.get('started')}); wait for it to end or choose another --out"
            )
        path.unlink(missing_ok=True)
    raise InputError(f"out: cannot take the lock {path}")


@contextmanager
def hold_folder(out, case: str):
    """Hold the output folder ``out`` for a run of ``case`` inside the ``with`` block.

    Creates the folder if needed (and removes it again if the block leaves it empty, so that
    a mistake found before the run writes nothing). Raises ``InputError`` naming the running
    case if another live process holds it.
    """
    out = Path(out)
    created = not out.exists()
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:  # a file in the way, a folder that cannot be written
        raise InputError(f"out: cannot create the output folder {out}: {err.strerror}") from None
    path = out / LOCK_FILE
    record = {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "case": case,
        "started": time.strftime("%Y-%m-%d %H:%M:%S"),
    }
    try:
        owner = _take(path, record)
    except InputError:
        if created:
            _remove_if_empty(out)
        raise
    try:
        yield
    finally:
        if owner:
            path.unlink(missing_ok=True)
            if created:
                _remove_if_empty(out)


def _remove_if_empty(out: Path) -> None:
    try:
        out.rmdir()
    except OSError:  # not empty: it holds the run's files
        pass
