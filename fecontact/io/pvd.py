"""The ``.pvd`` index of VTU frames (a VTK Collection): written during a run, read back."""

from __future__ import annotations

import math
import re
import time
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from .files import write_text
from .vtu import write_vtu

__all__ = ["PVDWriter", "read_pvd"]

_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.\-]*")


def _check_name(kind: str, name: str) -> str:
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ValueError(
            f"{kind} {name!r} must be a non-empty file-name-safe string "
            "(letters, digits, '_', '-', '.')"
        )
    return name


class PVDWriter:
    """Write a time series of meshes as ``.vtu`` files indexed by ``<case>.pvd``.

    Parts are named by the caller (one per body, e.g. ``"beam"``, ``"stop"``); each gets a fixed
    ``part`` index in the order it first appears. Times (s) must increase strictly.

    The ``.pvd`` is rewritten after a frame when ``index_interval`` seconds of wall time have
    passed since it was last written (0: after every frame), and by :meth:`flush`. Replacing a
    file costs far more than creating one (ext4 writes the new data out before the rename
    completes: milliseconds, growing with the index), so a run rewrites it at most about once
    a second and flushes it when it stops.
    """

    def __init__(self, out_dir: str | Path, case_name: str, index_interval: float = 0.0):
        self.out_dir = Path(out_dir)
        self.case_name = _check_name("case name", case_name)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.pvd = self.out_dir / f"{case_name}.pvd"
        self.times: list[float] = []
        self._part_index: dict[str, int] = {}
        self._static: dict[str, str] = {}  # part -> file
        self._moving: list[list[tuple[int, str]]] = []  # per frame: (part index, XML line)
        self._blocks: list[str] = []  # per frame: its .pvd lines, so a rewrite is one join
        self.index_interval = float(index_interval)
        self._indexed = 0  # frames listed in the .pvd on disk
        self._indexed_at = -math.inf  # time.perf_counter() of that write

    @property
    def n_frames(self) -> int:
        return len(self.times)

    def resume(self, upto: float) -> None:
        """Take over the ``.pvd`` of an earlier run, keeping its frames at times <= ``upto``
        (s) and deleting the files of later ones."""
        root = ET.parse(self.pvd).getroot()
        frames: dict[float, list] = {}
        for ds in root.find("Collection").iter("DataSet"):
            name, file, index = ds.get("name"), ds.get("file"), int(ds.get("part", 0))
            self._part_index.setdefault(name, index)
            if file == f"{self.case_name}_{name}.vtu":
                self._static[name] = file
            else:
                frames.setdefault(float(ds.get("timestep")), []).append((index, name, file))
        for t in sorted(frames):
            if t > upto:
                for _, _, file in frames[t]:
                    (self.out_dir / file).unlink(missing_ok=True)
                continue
            ts = repr(t)
            moving = [(i, self._entry(ts, i, name, file)) for i, name, file in frames[t]]
            self.times.append(t)
            self._moving.append(moving)
            self._blocks.append(self._block(ts, moving))
        self._write_pvd()

    def _index(self, part: str) -> int:
        _check_name("part name", part)
        return self._part_index.setdefault(part, len(self._part_index))

    @staticmethod
    def _entry(timestep: str, index: int, name: str, file: str) -> str:
        return (
            f'    <DataSet timestep="{timestep}" group="" part="{index}" '
            f"name={quoteattr(name)} file={quoteattr(file)}/>\n"
        )

    def _block(self, timestep: str, moving: list[tuple[int, str]]) -> str:
        """The ``.pvd`` lines of one frame: its moving parts and every static part."""
        static = [
            (self._part_index[part], self._entry(timestep, self._part_index[part], part, file))
            for part, file in self._static.items()
        ]
        return "".join(line for _, line in sorted(moving + static))

    def _write_pvd(self) -> None:
        text = (
            '<?xml version="1.0"?>\n'
            '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            "  <Collection>\n" + "".join(self._blocks) + "  </Collection>\n</VTKFile>\n"
        )
        write_text(self.pvd, text)
        self._indexed, self._indexed_at = len(self._blocks), time.perf_counter()

    def flush(self) -> None:
        """Rewrite the ``.pvd`` if it does not list every frame written so far."""
        if self._indexed < len(self._blocks):
            self._write_pvd()

    def close(self) -> None:
        """The end of the run: the index lists every frame."""
        self.flush()

    def write_static(self, part: str, mesh) -> Path:
        """Write a part that never moves (an obstacle) once; it is listed at every timestep."""
        if part in self._part_index and part not in self._static:
            raise ValueError(f"part {part!r} was already written as a moving part")
        self._index(part)
        path = self.out_dir / f"{self.case_name}_{part}.vtu"
        write_vtu(path, mesh)
        self._static[part] = path.name
        if self.times:
            self._blocks = [
                self._block(repr(t), moving)
                for t, moving in zip(self.times, self._moving, strict=True)
            ]
            self._write_pvd()
        return path

    def write_frame(self, t: float, parts: dict) -> list[Path]:
        """Write one frame at time ``t`` (s): a ``.vtu`` per part, then the updated ``.pvd``.

        ``parts`` maps part names to ``meshio.Mesh`` objects (see :func:`line_mesh`).
        """
        t = float(t)
        if not math.isfinite(t) or (self.times and t <= self.times[-1]):
            last = self.times[-1] if self.times else None
            raise ValueError(f"frame time must be finite and increase, got {t!r} after {last!r}")
        clash = self._static.keys() & parts.keys()
        if clash:
            raise ValueError(f"parts {sorted(clash)} were written as static parts")
        frame = len(self.times)
        timestep = repr(t)
        paths, moving = [], []
        for part, mesh in parts.items():
            index = self._index(part)
            path = self.out_dir / f"{self.case_name}_{part}_{frame:05d}.vtu"
            write_vtu(path, mesh)
            paths.append(path)
            moving.append((index, self._entry(timestep, index, part, path.name)))
        self.times.append(t)
        self._moving.append(moving)
        self._blocks.append(self._block(timestep, moving))
        if time.perf_counter() - self._indexed_at < self.index_interval:
            return paths
        try:
            self._write_pvd()
        except BaseException:
            # keep the in-memory index equal to what the .pvd on disk lists
            del self.times[-1], self._moving[-1], self._blocks[-1]
            raise
        return paths


def read_pvd(pvd: Path) -> tuple[np.ndarray, list[dict[str, str]], list[str]]:
    """Times (s), per time ``{part: file}``, part names in ``part`` order."""
    root = ET.parse(pvd).getroot()
    collection = root.find("Collection")
    if root.get("type") != "Collection" or collection is None:
        raise ValueError(f"{pvd} is not a VTK Collection (.pvd) file")
    by_time: dict[float, dict[str, str]] = {}
    order: dict[str, int] = {}
    for ds in collection.iter("DataSet"):
        index = int(ds.get("part", 0))
        name = ds.get("name") or f"part{index}"
        order.setdefault(name, index)
        by_time.setdefault(float(ds.get("timestep", 0)), {})[name] = ds.get("file")
    times = np.array(sorted(by_time))
    return times, [by_time[t] for t in times], sorted(order, key=order.get)
