"""Run output: ``.vtu`` frames with a ``.pvd`` index, ``history.csv``, ``summary.json``.

Layout of an output folder written by a run of case ``<case>``::

    <case>.pvd                     time index (VTK Collection XML), rewritten after every frame
    <case>_<part>_<index>.vtu      one file per moving part and frame (index: 00000, 00001, ...)
    <case>_<part>.vtu              a static part (obstacle), written once
    history.csv                    one row per time step, every cell numeric
    summary.json                   strict JSON (non-finite floats as "inf", "-inf", "nan")

Every ``DataSet`` entry of the ``.pvd`` carries ``timestep`` (s), ``part`` (a fixed index per
part), ``name`` (the part name: ParaView uses it as block name) and ``file`` (relative path).
Static parts are listed at every timestep because ParaView and ``pyvista.get_reader`` select the
datasets of a time by exact match of ``timestep``.

Frames, the ``.pvd`` and JSON files are written under a temporary name in the same folder and
moved into place with ``os.replace`` (:func:`atomic_write`), so a reader never sees a
half-written file and the ``.pvd`` only ever lists complete frames, even when the run is
interrupted. ``history.csv`` is appended in blocks of rows; a line cut by a killed process is
dropped when the file is read back.

Geometry is written in the current configuration (points = reference + displacement); the
``displacement`` point data must not be used to warp again. Vectors have 3 components.
"""

from __future__ import annotations

import json
import math
import re
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from .files import atomic_write, write_text
from .vtu import body_mesh, line_mesh, write_vtu

__all__ = [
    "body_mesh",
    "PVDWriter",
    "HistoryWriter",
    "RunResult",
    "write_json",
    "load_run",
    "read_history",
    "read_json",
    "line_mesh",
    "atomic_write",
    "HISTORY_FILE",
    "SUMMARY_FILE",
    "STANDARD_COLUMNS",
    "FRICTION_COLUMNS",
    "LEDGER_COLUMNS",
]

HISTORY_FILE = "history.csv"
SUMMARY_FILE = "summary.json"
# the first columns of history.csv; a case's probes follow them
STANDARD_COLUMNS = (
    "t",
    "kinetic_energy",
    "strain_energy",
    "potential_energy",
    "total_energy",
    "min_gap",
    "n_active",
    "impulse",
    "newton_iterations",
)
# ... and, in models with friction, these after them: Σ_j |k Λ_T,j| of the step (N·s) and
# the work dissipated by friction since t = 0 (J)
FRICTION_COLUMNS = ("tangential_impulse", "friction_work")
# ... then the energy ledger's terms since t = 0 (J, :mod:`fecontact.ledger`)
LEDGER_COLUMNS = (
    "load_work",
    "damping_dissipation",
    "friction_dissipation",
    "impact_dissipation",
    "numerical_dissipation",
)

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


def _cell(x, _repr=float.__repr__) -> str:
    # repr of a float is the shortest string that reads back exactly, and gives inf/nan;
    # dispatch on exact types first: this runs for every cell of every step
    if isinstance(x, float):  # also numpy.float64
        return _repr(x)
    if isinstance(x, (bool, np.bool_)):
        return "1" if x else "0"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return _repr(float(x))


class HistoryWriter:
    """Append one numeric CSV row per time step; the header fixes the column order.

    Rows are buffered and written every ``flush_every`` rows and on :meth:`flush`/:meth:`close`.
    Booleans are written as 0/1, non-finite values as ``inf``, ``-inf``, ``nan``.
    """

    def __init__(
        self, path: str | Path, columns: list[str], flush_every: int = 100, keep_rows=None
    ):
        self.path = Path(path)
        self.columns = list(columns)
        if len(set(self.columns)) != len(self.columns) or not all(
            isinstance(c, str) and c and "," not in c for c in self.columns
        ):
            raise ValueError(f"history columns must be distinct names without ',': {columns!r}")
        self.flush_every = max(1, int(flush_every))
        self._buffer: list[str] = []
        header = ",".join(self.columns) + "\n"
        if keep_rows is not None:
            # resuming: keep the header and the first ``keep_rows`` rows, append after them
            with open(self.path, encoding="utf-8") as f:
                lines = f.readlines()
            if not lines or lines[0] != header or len(lines) < keep_rows + 1:
                raise ValueError(f"{self.path} does not hold the {keep_rows} rows to resume from")
            with atomic_write(self.path) as tmp:
                tmp.write_text("".join(lines[: keep_rows + 1]), encoding="utf-8")
            self._file = open(self.path, "a", encoding="utf-8", newline="")
            return
        self._file = open(self.path, "w", encoding="utf-8", newline="")
        self._file.write(header)
        self._file.flush()

    def write(self, row) -> None:
        """Append a row: a dict keyed by column names or a sequence in column order."""
        if isinstance(row, dict):
            try:
                values = [row[c] for c in self.columns]
            except KeyError:
                values = None
            if values is None or len(row) != len(self.columns):
                extra = sorted(set(row) - set(self.columns))
                missing = [c for c in self.columns if c not in row]
                raise ValueError(f"history row: unknown columns {extra}, missing {missing}")
            row = values
        elif len(row) != len(self.columns):
            raise ValueError(f"history row has {len(row)} values, expected {len(self.columns)}")
        self._buffer.append(",".join(map(_cell, row)) + "\n")
        if len(self._buffer) >= self.flush_every:
            self.flush()

    def flush(self) -> None:
        if self._buffer:
            self._file.write("".join(self._buffer))
            self._buffer.clear()
        self._file.flush()

    def close(self) -> None:
        if not self._file.closed:
            self.flush()
            self._file.close()

    def __enter__(self) -> HistoryWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _to_json(value):
    """Python types for ``json``, with non-finite floats as strings (strict JSON)."""
    if isinstance(value, dict):
        return {str(k): _to_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_to_json(v) for v in value]
    if isinstance(value, np.ndarray):
        return _to_json(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def _from_json(value):
    if isinstance(value, dict):
        return {k: _from_json(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_from_json(v) for v in value]
    if value in ("inf", "-inf", "nan"):
        return float(value)
    return value


def read_json(path: str | Path) -> dict:
    """Read a file written by :func:`write_json`; "inf", "-inf", "nan" strings become floats."""
    return _from_json(json.loads(Path(path).read_text(encoding="utf-8")))


def write_json(path: str | Path, data: dict) -> Path:
    """Write ``data`` as indented strict JSON, atomically; numpy values become Python values."""
    path = Path(path)
    text = json.dumps(_to_json(data), indent=2, allow_nan=False) + "\n"
    write_text(path, text)
    return path


def read_history(path: str | Path) -> dict[str, np.ndarray]:
    """Every column of a ``history.csv`` as a float array; a line cut by a kill is dropped."""
    text = Path(path).read_text(encoding="utf-8")
    lines = text.splitlines()
    if not lines:
        return {}
    columns = lines[0].split(",")
    rows = lines[1:]
    if rows and not text.endswith("\n"):
        rows = rows[:-1]  # a line cut by an interrupted run
    if not rows:
        return {c: np.empty(0) for c in columns}
    data = np.loadtxt(rows, delimiter=",", dtype=float, ndmin=2)
    return {c: data[:, j].copy() for j, c in enumerate(columns)}


def _read_pvd(pvd: Path) -> tuple[np.ndarray, list[dict[str, str]], list[str]]:
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


@dataclass
class RunResult:
    """A finished (or interrupted) run read back from its output folder.

    ``history`` holds every ``history.csv`` column as a float array, ``summary`` the contents of
    ``summary.json`` (empty if the run did not finish), ``times`` the frame times (s).
    """

    out_dir: Path
    pvd: Path
    history: dict[str, np.ndarray]
    summary: dict
    times: np.ndarray
    parts: list[str]
    static_parts: list[str]
    files: list[dict[str, str]] = field(repr=False)

    def reader(self):
        """``pyvista.get_reader`` on the ``.pvd`` (time-aware, all parts as blocks)."""
        import pyvista

        return pyvista.get_reader(str(self.pvd))

    def frames(self, indices=None) -> list[tuple[float, dict]]:
        """``[(time, {part: pyvista.DataSet})]`` for all frames or the given frame indices.

        A static part's file is read once and the same object is shared by all frames.
        """
        import pyvista

        static: dict[str, object] = {}

        def read(part: str, file: str):
            if part not in self.static_parts:
                return pyvista.read(str(self.out_dir / file))
            if part not in static:
                static[part] = pyvista.read(str(self.out_dir / file))
            return static[part]

        indices = range(len(self.times)) if indices is None else indices
        return [
            (float(self.times[i]), {p: read(p, f) for p, f in self.files[i].items()})
            for i in indices
        ]


def _find_pvd(out_dir: Path) -> Path:
    if out_dir.suffix == ".pvd" and out_dir.is_file():
        return out_dir
    if not out_dir.is_dir():
        raise FileNotFoundError(f"no run output folder {str(out_dir)!r}")
    found = sorted(out_dir.glob("*.pvd"))
    if not found:
        raise FileNotFoundError(f"no .pvd file in {str(out_dir)!r}: not a run output folder")
    if len(found) > 1:
        names = ", ".join(p.name for p in found)
        raise FileNotFoundError(
            f"{len(found)} .pvd files in {str(out_dir)!r} ({names}): pass the .pvd path"
        )
    return found[0]


def load_run(out_dir: str | Path) -> RunResult:
    """Read a run back from its output folder (or from the path of its ``.pvd``).

    ``history.csv`` and ``summary.json`` are optional (an interrupted run may lack the summary);
    ``"inf"``, ``"-inf"`` and ``"nan"`` strings in the summary become floats again.
    """
    pvd = _find_pvd(Path(out_dir))
    folder = pvd.parent
    history_path, summary_path = folder / HISTORY_FILE, folder / SUMMARY_FILE
    history = read_history(history_path) if history_path.is_file() else {}
    summary = read_json(summary_path) if summary_path.is_file() else {}
    times, files, parts = _read_pvd(pvd)
    # a static part is written once as <case>_<part>.vtu, a moving one per frame
    static = [p for p in parts if all(f.get(p) == f"{pvd.stem}_{p}.vtu" for f in files)]
    return RunResult(folder, pvd, history, summary, times, parts, static, files)
