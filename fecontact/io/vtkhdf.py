"""Frames as transient VTKHDF files (format 2.0, read by VTK ≥ 9.3, ParaView ≥ 5.12): one
``<case>_<part>.vtkhdf`` per part, written with h5py.

A part's geometry (points, connectivity) is written once and every step points to it; it is
written again only when it changes (a moving obstacle's outline). Each step appends its point
and cell data and the offsets of the ``Steps`` group: ``Values`` (times, s), ``PartOffsets``,
``NumberOfParts``, ``PointOffsets``, ``CellOffsets``, ``ConnectivityIdOffsets``,
``PointDataOffsets/<name>``, ``CellDataOffsets/<name>``. A part that never moves (an obstacle)
is a plain, non-transient VTKHDF file. ``<case>.frames.json`` lists the parts and their files.

The files grow in place and are flushed after every frame: a run that is killed leaves every
flushed frame readable, unless the kill lands inside a write.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .files import atomic_write, write_text
from .vtu import VTK_TYPES

__all__ = ["INDEX_SUFFIX", "VTKHDFSeries", "read_index", "read_step", "step_times"]

INDEX_SUFFIX = ".frames.json"
VERSION = (2, 0)  # transient unstructured grids: the oldest version that has them
_COUNTS = ("NumberOfPoints", "NumberOfCells", "NumberOfConnectivityIds")
_STEPS = ("PartOffsets", "NumberOfParts", "PointOffsets", "CellOffsets", "ConnectivityIdOffsets")


def _h5py():
    try:
        import h5py
    except ImportError:  # pragma: no cover - depends on the install
        raise ImportError("--format vtkhdf needs h5py: pip install 'fecontact[vtkhdf]'") from None
    return h5py


def _arrays(mesh):
    """Points (n, 3), connectivity, offsets (n_cells + 1), VTK types, point and cell data of a
    ``meshio.Mesh`` (the same numbering as the VTU writer)."""
    blocks = [(b.type, np.asarray(b.data, dtype=np.int64)) for b in mesh.cells if len(b.data)]
    conn = [c.ravel() for _, c in blocks]
    sizes = np.concatenate([np.full(len(c), c.shape[1]) for _, c in blocks] or [np.zeros(0)])
    types = [np.full(len(c), VTK_TYPES[kind], dtype=np.uint8) for kind, c in blocks]
    cell_data = {}
    for name, per_block in mesh.cell_data.items():
        kept = [np.asarray(v) for v, b in zip(per_block, mesh.cells, strict=True) if len(b.data)]
        cell_data[name] = np.concatenate(kept) if kept else np.zeros(0)
    return (
        np.asarray(mesh.points, dtype=float),
        np.concatenate(conn) if conn else np.zeros(0, np.int64),
        np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64),
        np.concatenate(types) if types else np.zeros(0, np.uint8),
        {k: np.asarray(v, dtype=float) for k, v in mesh.point_data.items()},
        cell_data,
    )


def _append(group, name: str, values) -> int:
    """Append ``values`` (rows) to the resizable dataset ``name``; return its length before."""
    values = np.asarray(values)
    if name not in group:
        group.create_dataset(name, data=values, maxshape=(None, *values.shape[1:]), chunks=True)
        return 0
    data = group[name]
    start = data.shape[0]
    data.resize(start + values.shape[0], axis=0)
    data[start:] = values
    return start


def _truncate(group, name: str, length: int) -> None:
    if name in group:
        group[name].resize(length, axis=0)


def _header(f) -> object:
    root = f.create_group("VTKHDF")
    root.attrs["Version"] = np.array(VERSION, dtype=np.int64)
    root.attrs.create("Type", np.bytes_(b"UnstructuredGrid"))
    return root


def _write_geometry(root, points, conn, offsets, types) -> None:
    _append(root, "NumberOfPoints", [len(points)])
    _append(root, "NumberOfCells", [len(types)])
    _append(root, "NumberOfConnectivityIds", [len(conn)])
    _append(root, "Points", points)
    _append(root, "Offsets", offsets)
    _append(root, "Connectivity", conn)
    _append(root, "Types", types)


class _Partition(NamedTuple):
    """The geometry the steps point to: its arrays, index and offsets in the file."""

    points: np.ndarray
    conn: np.ndarray
    n_cells: int
    index: int
    point0: int
    cell0: int
    id0: int

    def next_offsets(self) -> list[int]:
        """Index and offsets of a partition written after this one."""
        return [self.index + 1, self.point0 + len(self.points), self.cell0 + self.n_cells,
                self.id0 + len(self.conn)]  # fmt: skip


class _TransientPart:
    """One part's transient file, open for appending."""

    def __init__(self, path: Path, resume_upto: float | None = None):
        h5py = _h5py()
        self.path = path
        if resume_upto is None:
            self.file = h5py.File(path, "w")
            root = _header(self.file)
            root.create_group("PointData"), root.create_group("CellData")
            root.create_group("Steps").attrs["NSteps"] = 0
            self.geometry = None
        else:
            self.file = h5py.File(path, "a")
            self._cut(resume_upto)

    def _cut(self, upto: float) -> None:
        """Keep the steps at times ≤ ``upto`` (s)."""
        root = self.file["VTKHDF"]
        steps = root["Steps"]
        n = int(np.searchsorted(steps["Values"][()], upto, side="right"))
        for data, offsets in (("PointData", "PointDataOffsets"), ("CellData", "CellDataOffsets")):
            for name in list(root[data]):
                end = int(steps[offsets][name][n]) if n < steps["Values"].shape[0] else None
                if end is not None:
                    _truncate(root[data], name, end)
                _truncate(steps[offsets], name, n)
        for name in ("Values", *_STEPS):
            _truncate(steps, name, n)
        steps.attrs["NSteps"] = n
        self.geometry = None if n == 0 else self._geometry(int(steps["PartOffsets"][n - 1]))
        # the geometry written after the kept steps goes too: the next partition follows it
        end = [0, 0, 0, 0] if self.geometry is None else self.geometry.next_offsets()
        for name in _COUNTS:
            _truncate(root, name, end[0])
        for name, length in zip(("Points", "Types", "Connectivity"), end[1:], strict=True):
            _truncate(root, name, length)
        _truncate(root, "Offsets", end[2] + end[0])  # n_cells + 1 offsets per partition
        self.file.flush()

    def _geometry(self, part: int) -> _Partition:
        """Partition ``part`` as written in the file."""
        root = self.file["VTKHDF"]
        counts = [root[k][: part + 1] for k in _COUNTS]
        p0, c0, i0 = (int(c[:-1].sum()) for c in counts)
        points = root["Points"][p0 : p0 + int(counts[0][-1])]
        conn = root["Connectivity"][i0 : i0 + int(counts[2][-1])]
        return _Partition(points, conn, int(counts[1][-1]), part, p0, c0, i0)

    def append(self, t: float, mesh) -> None:
        points, conn, offsets, types, point_data, cell_data = _arrays(mesh)
        root = self.file["VTKHDF"]
        steps = root["Steps"]
        g = self.geometry
        if g is None or not (np.array_equal(g.points, points) and np.array_equal(g.conn, conn)):
            # a new partition: the first frame, or geometry that moved
            where = [0, 0, 0, 0] if g is None else g.next_offsets()
            _write_geometry(root, points, conn, offsets, types)
            self.geometry = g = _Partition(points, conn, len(types), *where)
        _append(steps, "Values", [float(t)])
        for name, value in zip(_STEPS, [g.index, 1, g.point0, g.cell0, g.id0], strict=True):
            _append(steps, name, np.array([value], dtype=np.int64))
        self._append_data(root, "PointData", "PointDataOffsets", point_data)
        self._append_data(root, "CellData", "CellDataOffsets", cell_data)
        steps.attrs["NSteps"] = steps["Values"].shape[0]
        self.file.flush()

    @staticmethod
    def _append_data(root, data: str, offsets: str, fields: dict) -> None:
        group = root[data]
        known = set(group)
        if known and known != set(fields):
            raise ValueError(f"{data}: fields {sorted(fields)} differ from {sorted(known)}")
        offset_group = root["Steps"].require_group(offsets)
        for name, values in fields.items():
            start = _append(group, name, values)
            _append(offset_group, name, np.array([start], dtype=np.int64))

    def close(self) -> None:
        self.file.close()


def _write_static(path: Path, mesh) -> None:
    points, conn, offsets, types, point_data, cell_data = _arrays(mesh)
    h5py = _h5py()
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        root = _header(f)
        _write_geometry(root, points, conn, offsets, types)
        for group, fields in (("PointData", point_data), ("CellData", cell_data)):
            g = root.create_group(group)
            for name, values in fields.items():
                g.create_dataset(name, data=values)


class VTKHDFSeries:
    """Frames as transient VTKHDF files, one per part, with the interface of
    :class:`~fecontact.io.output.PVDWriter` (``write_static``, ``write_frame``, ``flush``,
    ``resume``). Times (s) must increase strictly."""

    def __init__(self, out_dir: str | Path, case_name: str, index_interval: float = 0.0):
        self.out_dir = Path(out_dir)
        self.case_name = case_name
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.index = self.out_dir / f"{case_name}{INDEX_SUFFIX}"
        self.times: list[float] = []
        self._parts: dict[str, str] = {}  # part -> file, in order of appearance
        self._static: set[str] = set()
        self._open: dict[str, _TransientPart] = {}

    @property
    def n_frames(self) -> int:
        return len(self.times)

    def _file(self, part: str) -> Path:
        return self.out_dir / f"{self.case_name}_{part}.vtkhdf"

    def _write_index(self) -> None:
        text = {"format": "vtkhdf", "parts": self._parts, "static": sorted(self._static)}
        write_text(self.index, json.dumps(text, indent=1) + "\n")

    def resume(self, upto: float) -> None:
        """Take over the files of an earlier run, keeping its frames at times ≤ ``upto`` (s)."""
        parts, static = read_index(self.index)
        self._parts, self._static = dict(parts), set(static)
        for part, file in parts.items():
            if part not in static:
                self._open[part] = _TransientPart(self.out_dir / file, resume_upto=upto)
        moving = [p for p in parts if p not in static]
        if moving:
            self.times = step_times(self.out_dir / parts[moving[0]]).tolist()

    def flush(self) -> None:
        """Every frame is flushed when written: nothing to do."""

    def write_static(self, part: str, mesh) -> Path:
        """Write a part that never moves (an obstacle), again if called again."""
        if part in self._parts and part not in self._static:
            raise ValueError(f"part {part!r} was already written as a moving part")
        path = self._file(part)
        _write_static(path, mesh)
        self._static.add(part)
        if part not in self._parts:
            self._parts[part] = path.name
            self._write_index()
        return path

    def write_frame(self, t: float, parts: dict) -> list[Path]:
        """Append one frame at time ``t`` (s) to each part's file."""
        t = float(t)
        if not math.isfinite(t) or (self.times and t <= self.times[-1]):
            last = self.times[-1] if self.times else None
            raise ValueError(f"frame time must be finite and increase, got {t!r} after {last!r}")
        clash = self._static & parts.keys()
        if clash:
            raise ValueError(f"parts {sorted(clash)} were written as static parts")
        new = [p for p in parts if p not in self._parts]
        for part, mesh in parts.items():
            if part not in self._open:
                self._open[part] = _TransientPart(self._file(part))
                self._parts[part] = self._file(part).name
            self._open[part].append(t, mesh)
        if new:
            self._write_index()
        self.times.append(t)
        return [self._open[p].path for p in parts]

    def close(self) -> None:
        for part in self._open.values():
            part.close()
        self._open.clear()


def read_index(path: Path) -> tuple[dict[str, str], list[str]]:
    """{part: file} (in order of appearance) and the static parts of a ``.frames.json``."""
    data = json.loads(Path(path).read_text(encoding="utf-8"))
    if data.get("format") != "vtkhdf":
        raise ValueError(f"{path} is not a VTKHDF frame index")
    return dict(data["parts"]), list(data["static"])


def step_times(path: Path) -> np.ndarray:
    """The times (s) of a transient part file."""
    with _h5py().File(path, "r") as f:
        return np.asarray(f["VTKHDF/Steps/Values"][()], dtype=float)


def read_step(path: Path, step: int | None = None):
    """A part file as a ``pyvista.UnstructuredGrid``: step ``step`` of a transient file (VTK's
    own reader, ``vtkHDFReader``), or the static file."""
    import pyvista
    from vtkmodules.vtkIOHDF import vtkHDFReader

    reader = vtkHDFReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    if step is not None:
        reader.SetStep(int(step))
    reader.Update()
    return pyvista.wrap(reader.GetOutput())
