"""Run output: frames (``.vtu`` with a ``.pvd`` index, or transient ``.vtkhdf``),
``history.csv``, ``summary.json``.

Layout of an output folder written by a run of case ``<case>`` with VTU frames::

    <case>.pvd                     time index (VTK Collection XML), rewritten after every frame
    <case>_<part>_<index>.vtu      one file per moving part and frame (index: 00000, 00001, ...)
    <case>_<part>.vtu              a static part (obstacle), written once
    history.csv                    one row per time step, every cell numeric
    summary.json                   strict JSON (non-finite floats as "inf", "-inf", "nan")

With VTKHDF frames (:mod:`fecontact.io.vtkhdf`) ``<case>.frames.json`` lists the parts and
each part is one ``<case>_<part>.vtkhdf`` holding every frame.

Every ``DataSet`` entry of the ``.pvd`` carries ``timestep`` (s), ``part`` (a fixed index per
part), ``name`` (the part name: ParaView uses it as block name) and ``file`` (relative path).
Static parts are listed at every timestep because ParaView and ``pyvista.get_reader`` select the
datasets of a time by exact match of ``timestep``.

Frames, the ``.pvd`` and JSON files are written under a temporary name in the same folder and
moved into place with ``os.replace`` (:func:`atomic_write`), so a reader never sees a
half-written file and the ``.pvd`` only ever lists complete frames, even when the run is
interrupted. ``history.csv`` is appended in blocks of rows; a line cut by a killed process is
dropped when the file is read back.

Bodies are written in the reference configuration with a ``displacement`` point field (m), as
finite element tools expect: ParaView's *Warp By Vector* on ``displacement`` (or
:func:`deformed`) shows the deformed shape. Vectors have 3 components.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..extras import need
from .files import atomic_write, write_text
from .pvd import PVDWriter, read_pvd
from .vtkhdf import INDEX_SUFFIX, VTKHDFSeries, read_index, read_step, step_times
from .vtu import body_mesh, line_mesh

__all__ = [
    "body_mesh",
    "deformed",
    "frame_format",
    "frame_writer",
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
    "COLUMN_UNITS",
    "FRICTION_COLUMNS",
    "LEDGER_COLUMNS",
    "OBSTACLE_COLUMNS",
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
    "dt",
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
# ... and, in models with moving obstacles, the work they did on the bodies since t = 0 (J)
OBSTACLE_COLUMNS = ("obstacle_work",)
# the units of those columns ("": a count); a probe's is in summary.json
COLUMN_UNITS = {
    "t": "s",
    "kinetic_energy": "J",
    "strain_energy": "J",
    "potential_energy": "J",
    "total_energy": "J",
    "min_gap": "m",
    "n_active": "",
    "impulse": "N·s",
    "newton_iterations": "",
    "dt": "s",
    "tangential_impulse": "N·s",
    "friction_work": "J",
    **dict.fromkeys(LEDGER_COLUMNS + OBSTACLE_COLUMNS, "J"),
}


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


# the cells' usual exact types, formatted as _cell does without its dispatch
_FORMATS = {float: float.__repr__, np.float64: float.__repr__, int: int.__repr__}


class HistoryWriter:
    """Append one numeric CSV row per time step; the header fixes the column order.

    Rows are buffered and written every ``flush_every`` rows, or with the first row after
    ``flush_seconds`` of wall time since the last write, and on :meth:`flush`/:meth:`close`:
    a run killed hard (SIGKILL, a cluster's time limit) keeps its rows up to about that time
    before, as the ``.pvd`` index its frames (100 rows alone are minutes of a large 3D run).
    Booleans are written as 0/1, non-finite values as ``inf``, ``-inf``, ``nan``.
    """

    def __init__(
        self,
        path: str | Path,
        columns: list[str],
        flush_every: int = 100,
        keep_rows=None,
        flush_seconds: float = 1.0,
    ):
        self.path = Path(path)
        self.flush_seconds = float(flush_seconds)
        self._flushed_at = time.perf_counter()
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
        get = _FORMATS.get
        self._buffer.append(",".join([get(type(x), _cell)(x) for x in row]) + "\n")
        late = time.perf_counter() - self._flushed_at >= self.flush_seconds
        if len(self._buffer) >= self.flush_every or late:
            self.flush()

    def flush(self) -> None:
        if self._buffer:
            self._file.write("".join(self._buffer))
            self._buffer.clear()
        self._file.flush()
        self._flushed_at = time.perf_counter()

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


@dataclass
class RunResult:
    """A finished (or interrupted) run read back from its output folder.

    ``history`` holds every ``history.csv`` column as a float array, ``summary`` the contents of
    ``summary.json`` (empty if the run did not finish), ``times`` the frame times (s),
    ``pvd`` the frames' index: the ``.pvd``, or the ``.frames.json`` of VTKHDF frames (None
    for a run that wrote no frames, ``frames=False``: ``times`` is then empty).
    """

    out_dir: Path
    pvd: Path | None
    history: dict[str, np.ndarray]
    summary: dict
    times: np.ndarray
    parts: list[str]
    static_parts: list[str]
    files: list[dict[str, str]] = field(repr=False)

    def to_dataframe(self):
        """``history.csv`` as a pandas ``DataFrame`` indexed by the time ``t`` (s): one row per
        step, the standard columns and the probes; ``attrs["units"]`` maps each column to its
        unit (:data:`COLUMN_UNITS`; a probe's from ``summary.json``; "" for counts). Needs
        pandas: ``pip install "fecontact[pandas]"``."""
        pd = need("pandas", "pandas")
        if "t" not in self.history:
            raise InputError(f"{self.out_dir} has no history.csv to tabulate")
        columns = {k: v for k, v in self.history.items() if k != "t"}
        frame = pd.DataFrame(columns, index=pd.Index(self.history["t"], name="t"))
        probes = self.summary.get("probes", {})
        units = {k: p.get("unit", "") for k, p in probes.items()}
        frame.attrs["units"] = {k: COLUMN_UNITS.get(k, units.get(k, "")) for k in columns}
        return frame

    def __repr__(self) -> str:
        # (a notebook shows it: what the run is, not its arrays, which the fields hold)
        t = self.history.get("t", np.empty(0))
        rows = f"{t.size} history rows" + (f" to t = {t[-1]:g} s" if t.size else "")
        status = self.summary.get("status", "no summary.json")
        frames = f"{len(self.times)} frames of {', '.join(self.parts)}" if self.parts else ""
        return (
            f"RunResult({str(self.out_dir)!r}: {self.case}, {status}, {rows}, "
            f"{frames or 'no frames'})"
        )

    @property
    def case(self) -> str:
        """The case's name (case names hold no dots)."""
        if self.pvd is None:  # (a run without frames)
            return self.summary.get("case", self.out_dir.name)
        return self.pvd.name.split(".")[0]

    def reader(self):
        """``pyvista.get_reader`` on the ``.pvd`` (time-aware, all parts as blocks)."""
        pyvista = need("pyvista", "render")
        if self.pvd is None:
            raise FileNotFoundError(f"{str(self.out_dir)!r}: the run wrote no frames")
        return pyvista.get_reader(str(self.pvd))

    def frames(self, indices=None) -> list[tuple[float, dict]]:
        """``[(time, {part: pyvista.DataSet})]`` for all frames or the given frame indices.

        A static part's file is read once and the same object is shared by all frames.
        """
        pyvista = need("pyvista", "render")
        static: dict[str, object] = {}

        def read(part: str, file: str, i: int):
            path = self.out_dir / file
            if part not in self.static_parts:
                return read_step(path, i) if path.suffix == ".vtkhdf" else pyvista.read(path)
            if part not in static:
                static[part] = read_step(path) if path.suffix == ".vtkhdf" else pyvista.read(path)
            return static[part]

        indices = range(len(self.times)) if indices is None else indices
        indices = [range(len(self.times))[i] for i in indices]  # negative indices too
        return [
            (float(self.times[i]), {p: read(p, f, i) for p, f in self.files[i].items()})
            for i in indices
        ]

    def multiblock(self, index: int = -1):
        """Frame ``index`` as a ``pyvista.MultiBlock`` whose blocks carry the part names, in
        ``part`` order (``pyvista.get_reader`` on a ``.pvd`` numbers them ``Block-00``, ...)."""
        pyvista = need("pyvista", "render")

        parts = self.frames([index])[0][1]
        return pyvista.MultiBlock({p: parts[p] for p in self.parts if p in parts})


def deformed(mesh):
    """A copy of a frame's dataset (a ``pyvista`` mesh) in its deformed configuration: the
    points plus the ``displacement`` point data (a part without it, an obstacle, as it is)."""
    if "displacement" not in mesh.point_data:
        return mesh
    out = mesh.copy()
    out.points = np.asarray(mesh.points) + np.asarray(mesh.point_data["displacement"])
    return out


AUTO_VTKHDF_DOFS = 2000
"""3D models of at least this many dofs write VTKHDF frames by default (``"auto"``): on the
dropped ball VTKHDF writes a frame about 2x faster than VTU at 2 499 dofs and 9x at 18 051,
and is slower (7 against 1 to 4 ms a frame) at 387 (benchmarks/results/frames.md)."""


def frame_format(requested: str, model, index: Path | None = None) -> str:
    """The format a run writes its frames in: ``requested`` ("vtu", "vtkhdf" or "auto"), or
    for "auto" VTKHDF on 3D models of ``AUTO_VTKHDF_DOFS`` dofs or more when h5py is
    installed, else VTU. A run that continues another (``index``: the frame index it left, a
    ``.pvd`` or ``.frames.json``) keeps that run's format."""
    if requested not in ("auto", "vtu", "vtkhdf"):
        raise InputError(f"format must be 'auto', 'vtu' or 'vtkhdf', got {requested!r}")
    if index is not None:
        chosen = "vtu" if index.suffix == ".pvd" else "vtkhdf"
    elif requested == "auto":
        large = model.dim == 3 and model.n >= AUTO_VTKHDF_DOFS
        chosen = "vtkhdf" if large and _has_h5py() else "vtu"
    else:
        chosen = requested
    if chosen == "vtkhdf" and not _has_h5py():
        raise InputError("format vtkhdf needs h5py: pip install 'fecontact[vtkhdf]'")
    return chosen


def _has_h5py() -> bool:
    import importlib.util

    return importlib.util.find_spec("h5py") is not None


def frame_writer(fmt: str, out_dir, case_name: str, index_interval: float = 0.0):
    """The writer of a run's frames: ``"vtu"`` (a ``.vtu`` per part and frame, indexed by a
    ``.pvd``) or ``"vtkhdf"`` (a transient ``.vtkhdf`` per part, :mod:`fecontact.io.vtkhdf`)."""
    if fmt == "vtu":
        return PVDWriter(out_dir, case_name, index_interval)
    if fmt == "vtkhdf":
        return VTKHDFSeries(out_dir, case_name, index_interval)
    raise ValueError(f"format must be 'vtu' or 'vtkhdf', got {fmt!r}")


def _find_index(out_dir: Path) -> Path | None:
    """The ``.pvd`` or ``.frames.json`` of a run folder (or that file itself); None for the
    folder of a run that wrote no frames (``frames=False``: its history and summary only)."""
    if out_dir.is_file() and (out_dir.suffix == ".pvd" or out_dir.name.endswith(INDEX_SUFFIX)):
        return out_dir
    if not out_dir.is_dir():
        raise FileNotFoundError(f"no run output folder {str(out_dir)!r}")
    found = sorted([*out_dir.glob("*.pvd"), *out_dir.glob(f"*{INDEX_SUFFIX}")])
    if not found and any((out_dir / name).is_file() for name in (HISTORY_FILE, SUMMARY_FILE)):
        return None
    if not found:
        raise FileNotFoundError(f"no .pvd file in {str(out_dir)!r}: not a run output folder")
    if len(found) > 1:
        names = ", ".join(p.name for p in found)
        raise FileNotFoundError(
            f"{len(found)} .pvd files (frame indices) in {str(out_dir)!r} ({names}): pass the "
            "path of one"
        )
    return found[0]


def _read_series(index: Path):
    """Times, parts, static parts and per time ``{part: file}`` of a VTKHDF run."""
    parts, static = read_index(index)
    moving = [p for p in parts if p not in static]
    times = step_times(index.parent / parts[moving[0]]) if moving else np.zeros(0)
    return times, list(parts), static, [dict(parts) for _ in times]


def load_run(out_dir: str | Path) -> RunResult:
    """Read a run back from its output folder (or from the path of its ``.pvd``, or of its
    ``.frames.json`` for VTKHDF frames).

    ``history.csv`` and ``summary.json`` are optional (an interrupted run may lack the summary);
    ``"inf"``, ``"-inf"`` and ``"nan"`` strings in the summary become floats again.
    """
    index = _find_index(Path(out_dir))
    folder = Path(out_dir) if index is None else index.parent
    history_path, summary_path = folder / HISTORY_FILE, folder / SUMMARY_FILE
    history = read_history(history_path) if history_path.is_file() else {}
    summary = read_json(summary_path) if summary_path.is_file() else {}
    if index is None:  # (a run without frames: its history and summary)
        return RunResult(folder, None, history, summary, np.zeros(0), [], [], [])
    if index.suffix != ".pvd":
        return RunResult(folder, index, history, summary, *_read_series(index))
    times, files, parts = read_pvd(index)
    # a static part is written once as <case>_<part>.vtu, a moving one per frame
    static = [p for p in parts if all(f.get(p) == f"{index.stem}_{p}.vtu" for f in files)]
    return RunResult(folder, index, history, summary, times, parts, static, files)
