"""Files written whole or not at all: a temporary name in the same folder, then a rename."""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_write", "write_text"]


@contextmanager
def atomic_write(path: str | Path):
    """Yield a temporary path next to ``path``; on success move it onto ``path``.

    The rename is atomic on one file system, so readers see the old file or the complete new
    one, never a part; on an exception the temporary file is removed. The temporary name keeps
    the suffix, for writers that pick the format from it.
    """
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_text(path: Path, text: str) -> None:
    with atomic_write(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
