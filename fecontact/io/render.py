"""Off-screen pictures of a finished run: snapshots, an animation and ``history.png``.

Rendering reads only the output folder (see :mod:`fecontact.io.output`), so it works on runs
written earlier or by another process. It needs no display: without ``DISPLAY`` VTK is told to
open an EGL window (Mesa llvmpipe is enough).

One off-screen plotter is reused for every frame and the meshes are updated by assigning new
points and scalars (a new plotter per frame is ~3x slower). The camera and the colour range
are fixed over the rendered frames so that pictures of one run compare. Beams and other line
cells are drawn as tubes of radius ~1 % of the scene, coloured by the speed ``|velocity|``
(m/s); static parts (obstacles) are grey. A flat scene (one z for every point) is seen from +z
with y up in parallel projection.

Each frame is rendered once (~90 ms at 800x608 with llvmpipe; opening the first window costs
~3 s) and the same image feeds the snapshots and the animation. GIF frames are quantized with
Pillow's fast octree (~10 ms a frame, against ~65 ms for the median cut that
``Plotter.open_gif`` uses); MP4 goes through imageio-ffmpeg. Every file is written atomically.
"""

from __future__ import annotations

import os
from contextlib import ExitStack, contextmanager
from pathlib import Path

import numpy as np

from ..extras import need
from .history_plot import history_panels, plot_history
from .output import atomic_write, deformed, load_run

__all__ = ["render_run", "plot_history", "history_panels", "WINDOW_SIZE", "MAX_ANIMATION_FRAMES"]

WINDOW_SIZE = (800, 608)  # pixels; multiples of 16 suit video encoders
MAX_ANIMATION_FRAMES = 150

_STATIC_COLOR = "#9a9a9a"
_PLAIN_COLOR = "steelblue"
_SPEED = "speed"
_SPEED_TITLE = "speed (m/s)"
# fractions of the window height left free for the time (top) and the scalar bar (bottom)
_TOP, _BOTTOM = 0.08, 0.20


def _pyvista():
    """Import pyvista for off-screen use, choosing an EGL window when there is no display."""
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    pyvista = need("pyvista", "render")
    pyvista.OFF_SCREEN = True
    return pyvista


def _first_impact_time(history: dict) -> float | None:
    """Time (s) of the first step where more contacts are active than before, if history has
    ``n_active``; contacts that the run starts in (active from the first step) are not
    impacts."""
    n_active, t = history.get("n_active"), history.get("t")
    if n_active is None or t is None or len(n_active) < 3:
        return None
    new = np.flatnonzero(np.diff(n_active[1:]) > 0) + 2
    return float(t[new[0]]) if new.size else None


def _nearest(times: np.ndarray, t: float) -> int:
    return int(np.argmin(np.abs(times - t)))


def _snapshots(run, snapshot_times) -> dict[str, int]:
    """Snapshot file stem -> frame index."""
    times = run.times
    if snapshot_times is not None:
        return {f"snapshot_t{t:.4f}": _nearest(times, t) for t in snapshot_times}
    shots = {"snapshot_start": 0}
    t_impact = _first_impact_time(run.history)
    if t_impact is not None:
        shots["snapshot_impact"] = _nearest(times, t_impact)
    shots["snapshot_end"] = len(times) - 1
    return shots


def _speed(mesh) -> np.ndarray | None:
    if "velocity" not in mesh.point_data:
        return None
    v = np.asarray(mesh.point_data["velocity"], dtype=float)
    return np.linalg.norm(v.reshape(len(v), -1), axis=1)


def _scene(frames, static_parts) -> tuple[np.ndarray, float]:
    """Union of the bounds ``[x0, x1, y0, y1, z0, z1]`` (m) and the largest speed (m/s)."""
    lo, hi, vmax = np.full(3, np.inf), np.full(3, -np.inf), 0.0
    for _, parts in frames:
        for name, mesh in parts.items():
            if mesh.n_points == 0:
                continue
            points = np.asarray(mesh.points)
            lo, hi = np.minimum(lo, points.min(axis=0)), np.maximum(hi, points.max(axis=0))
            speed = _speed(mesh) if name not in static_parts else None
            if speed is not None and speed.size:
                vmax = max(vmax, float(np.nanmax(speed)))
    if not np.all(np.isfinite(lo)):
        lo, hi = np.zeros(3), np.ones(3)
    return np.column_stack([lo, hi]).ravel(), vmax


def _is_planar(bounds: np.ndarray) -> bool:
    return bounds[4] == bounds[5]


def _scene_size(bounds: np.ndarray) -> float:
    size = float(np.max(bounds[1::2] - bounds[::2]))
    return size if size > 0 else 1.0


def _fix_camera(plotter, bounds: np.ndarray, pad: float) -> None:
    """Place a fixed camera showing ``bounds`` (m) with margin ``pad`` (m)."""
    lo, hi = bounds[::2] - pad, bounds[1::2] + pad
    width, height = plotter.window_size
    free = 1.0 - _TOP - _BOTTOM
    if not _is_planar(bounds):
        _fix_camera_3d(plotter, lo, hi, free, width / height)
        return
    # planar: look down -z with y up; keep the top and bottom bands free for text and colours
    dx, dy = hi[0] - lo[0], hi[1] - lo[1]
    visible = max(dy / free, dx * height / (0.95 * width))
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, 0.0])
    # the centre of the drawing sits at height _BOTTOM + free/2 of the window
    centre[1] -= (_BOTTOM + free / 2 - 0.5) * visible
    distance = 10.0 * max(dx, dy)
    plotter.camera_position = [tuple(centre + [0.0, 0.0, distance]), tuple(centre), (0, 1, 0)]
    plotter.enable_parallel_projection()
    plotter.camera.parallel_scale = visible / 2
    plotter.camera.clipping_range = (distance / 100, distance * 100)


ELEVATION = 8.0
"""Degrees of the 3D camera above the horizontal: low enough that the lowest point of a body,
where it rests on a floor, lies on its silhouette instead of behind it."""


def _fix_camera_3d(plotter, lo, hi, free, aspect):
    """Perspective camera on the box ``lo``–``hi`` (m), z up, seen from the front right
    (azimuth −60° from +x) and ``ELEVATION`` above: every corner of the box lies inside the
    band of the window between the time (top) and the scalar bar (bottom), in every frame.

    The camera is placed explicitly: ``reset_camera`` does nothing before the first actor
    is added, which left 3D scenes outside the clipping range.
    """
    centre = 0.5 * (lo + hi)
    el, az = np.radians(ELEVATION), np.radians(-60.0)
    direction = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    up = np.array([0.0, 0.0, 1.0]) - np.sin(el) * direction
    up /= np.linalg.norm(up)
    right = np.cross(up, direction)
    tan = np.tan(0.5 * np.radians(plotter.camera.view_angle))  # vertical half angle
    corners = (
        np.stack(np.meshgrid(*zip(lo, hi, strict=True), indexing="ij"), -1).reshape(-1, 3) - centre
    )
    depth = corners @ direction  # toward the camera
    # a corner at depth z is seen within the band when |c·up| <= free (d − z) tan, and
    # within the width when |c·right| <= 0.95 aspect (d − z) tan
    distance = float(
        np.max(
            depth
            + np.maximum(
                np.abs(corners @ up) / (free * tan), np.abs(corners @ right) / (0.95 * aspect * tan)
            )
        )
    )
    radius = float(np.max(np.linalg.norm(corners, axis=1))) or 1.0
    distance = max(distance, 1.5 * radius)
    visible = 2.0 * distance * tan  # window height at the focal point, m
    # the middle of the free band lies (_BOTTOM + free/2 − 1/2) of the height above centre
    focal = centre - (_BOTTOM + free / 2 - 0.5) * visible * up
    plotter.camera_position = [tuple(focal + distance * direction), tuple(focal), tuple(up)]
    plotter.camera.clipping_range = (
        max(distance - 2.0 * radius, 1e-3 * distance),
        distance + 2.0 * radius,
    )


def _closed_planar_loop(surface) -> bool:
    """True for a polyline that closes on itself in a plane (a 3D ``Plane`` obstacle)."""
    p = np.asarray(surface.points)
    if surface.n_points < 4 or surface.n_cells != surface.n_lines:
        return False
    centred = p - p.mean(axis=0)
    size = np.linalg.norm(np.ptp(p, axis=0))
    return bool(np.linalg.svd(centred, compute_uv=False)[-1] <= 1e-9 * size * np.sqrt(len(p)))


def _surface(pyvista, mesh):
    """Polygonal surface of ``mesh`` with the original point ids, for updates by indexing."""
    try:
        surface = mesh.extract_surface(
            pass_pointid=True, pass_cellid=False, algorithm="dataset_surface"
        )
    except TypeError:  # pyvista < 0.47 has no choice of algorithm
        surface = mesh.extract_surface(pass_pointid=True, pass_cellid=False)
    if "vtkOriginalPointIds" in surface.point_data:
        ids = np.asarray(surface.point_data["vtkOriginalPointIds"]).copy()
    else:
        ids = np.arange(surface.n_points)
    return pyvista.PolyData(surface), ids


def _tubes(surface, radius: float):
    """A VTK pipeline turning line cells into tubes; it follows later edits of ``surface``."""
    from vtkmodules.vtkFiltersCore import vtkStripper, vtkTubeFilter

    # joining segments into polylines gives smooth tubes across nodes
    stripper = vtkStripper()
    stripper.SetInputData(surface)
    tube = vtkTubeFilter()
    tube.SetInputConnection(stripper.GetOutputPort())
    tube.SetRadius(radius)
    tube.SetNumberOfSides(20)
    tube.CappingOn()
    return tube


def _add_part(pyvista, plotter, mesh, static: bool, radius: float, clim, space: bool = False):
    """Add one part; return ``update(mesh)`` for a moving part, ``None`` for a static one.

    In a 3D scene (``space``) a closed planar outline (a ``Plane``) is also drawn filled and
    translucent, and surfaces show their element edges.
    """
    surface, ids = _surface(pyvista, mesh)
    speed = None if static else _speed(mesh)
    style = {"smooth_shading": True}
    if static:
        style["color"] = _STATIC_COLOR
    elif speed is None:
        style["color"] = _PLAIN_COLOR
    else:
        surface.point_data[_SPEED] = speed[ids]
        style |= {
            "scalars": _SPEED,
            "clim": clim,
            "cmap": "viridis",
            "scalar_bar_args": {"title": _SPEED_TITLE, "fmt": "%.3g", "n_labels": 5},
        }
    if space and static and _closed_planar_loop(surface):
        # a rigid plane in 3D: its outline, filled and translucent, shows where contact is
        loop = np.asarray(surface.points)
        plane = pyvista.PolyData(loop, faces=np.r_[len(loop), np.arange(len(loop))])
        plotter.add_mesh(plane, color=_STATIC_COLOR, opacity=0.35)
    if surface.n_lines and not surface.n_cells - surface.n_lines:
        actor = plotter.add_mesh(_tubes(surface, radius), **style)
    elif surface.n_cells:
        if space and surface.n_cells <= 20000:
            style |= {"show_edges": True, "edge_color": "#303030", "line_width": 0.5}
        actor = plotter.add_mesh(surface, **style)
    else:
        actor = plotter.add_mesh(surface, render_points_as_spheres=True, point_size=8, **style)
    if static:
        return None

    state = {"n_points": mesh.n_points, "ids": ids}

    def update(new):
        actor.visibility = new is not None
        if new is None:
            return
        if new.n_points != state["n_points"]:
            # the part was remeshed: rebuild its surface in place, the pipeline follows
            fresh, state["ids"] = _surface(pyvista, new)
            surface.copy_from(fresh)
            state["n_points"] = new.n_points
        ids = state["ids"]
        surface.points = np.asarray(new.points)[ids]
        if speed is not None:
            new_speed = _speed(new)
            surface.point_data[_SPEED] = new_speed[ids] if new_speed is not None else 0.0 * ids

    return update


def _chosen_frames(run, snapshot_times, max_frames: int) -> tuple[dict[str, int], set[int]]:
    """The frames of the snapshots ({file stem: frame}) and of the animation (at most
    ``max_frames``, evenly subsampled; none for 0)."""
    n = len(run.times)
    if n == 0:
        raise ValueError(f"{run.pvd} lists no frames")
    shots = _snapshots(run, snapshot_times)
    movie = set()
    if max_frames:
        movie = set(np.unique(np.linspace(0, n - 1, min(n, max_frames)).round().astype(int)))
    return shots, movie


def _show(updates: dict, parts: dict, add) -> None:
    """Draw a frame's ``parts``: a part seen first is added (``add(name, mesh)`` returns its
    update, None for a static part), the others updated, and those missing hidden."""
    for name, mesh in parts.items():
        if name not in updates:
            updates[name] = add(name, mesh)
        elif updates[name] is not None:
            updates[name](mesh)
    for name, update in updates.items():
        if update is not None and name not in parts:
            update(None)


def _write_png(path: Path, image: np.ndarray) -> Path:
    from PIL import Image

    with atomic_write(path) as tmp:
        Image.fromarray(image).save(tmp, format="PNG")
    return path


@contextmanager
def _movie(path: Path, fps: float):
    """Yield ``add(image)`` collecting RGB frames into a GIF or MP4 written at ``path``.

    GIF frames get their own 256-colour palette by the fast octree quantizer (~10 ms a frame;
    the median cut behind ``Plotter.open_gif`` takes ~65 ms) and are saved at the end.
    """
    with atomic_write(path) as tmp:
        if path.suffix == ".gif":
            from PIL import Image

            frames = []
            yield lambda image: frames.append(
                Image.fromarray(image).quantize(256, method=Image.Quantize.FASTOCTREE)
            )
            frames[0].save(
                tmp, format="GIF", save_all=True, append_images=frames[1:],
                duration=round(1000 / fps), loop=0,
            )  # fmt: skip
        else:
            imageio = need("imageio.v2", "mp4")
            writer = imageio.get_writer(
                tmp, format="FFMPEG", fps=fps, quality=7, macro_block_size=16
            )
            try:
                yield writer.append_data
            finally:
                writer.close()


def render_run(
    out_dir,
    snapshot_times: list[float] | None = None,
    animation: bool = True,
    fmt: str = "gif",
    *,
    max_frames: int = MAX_ANIMATION_FRAMES,
    fps: float = 15,
    window_size: tuple[int, int] = WINDOW_SIZE,
) -> list[Path]:
    """Render snapshots (PNG), an animation (``animation.gif`` or ``.mp4``) and ``history.png``.

    Snapshots default to the first frame, the frame nearest the first impact (first step of
    ``history.csv`` with ``n_active > 0``) and the last frame; ``snapshot_times`` (s) picks the
    frames nearest those times instead. The animation uses at most ``max_frames`` frames,
    evenly subsampled. ``history.png`` is skipped when the folder has no ``history.csv``.
    Returns the paths written, in that order.
    """
    if fmt not in ("gif", "mp4"):
        raise ValueError(f"animation format must be 'gif' or 'mp4', got {fmt!r}")
    run = load_run(out_dir)
    if run.pvd is None:
        raise FileNotFoundError(f"{str(out_dir)!r}: the run wrote no frames to render")
    shots, movie = _chosen_frames(run, snapshot_times, max_frames if animation else 0)
    indices = sorted(movie | set(shots.values()))
    # bounds and colours over the frames drawn: what is not drawn needs no room
    frames = [(t, {k: deformed(m) for k, m in parts.items()}) for t, parts in run.frames(indices)]
    bounds, vmax = _scene(frames, run.static_parts)
    clim = (0.0, vmax if vmax > 0 else 1.0)
    radius = 0.01 * _scene_size(bounds)

    shot_at: dict[int, list[str]] = {}
    for stem, i in shots.items():
        shot_at.setdefault(i, []).append(stem)
    movie_path = run.out_dir / f"animation.{fmt}"
    written = []
    pyvista = _pyvista()
    with ExitStack() as stack:
        plotter = pyvista.Plotter(off_screen=True, window_size=list(window_size))
        stack.callback(plotter.close)
        add_to_movie = stack.enter_context(_movie(movie_path, fps)) if animation else None
        plotter.set_background("white")
        plotter.add_text(run.case, position="upper_right", font_size=10, color="black")
        clock = plotter.add_text("", position="upper_left", font_size=12, color="black")
        _fix_camera(plotter, bounds, pad=2 * radius)
        updates = {}

        def add(name, mesh):
            static = name in run.static_parts
            space = not _is_planar(bounds)
            return _add_part(pyvista, plotter, mesh, static, radius, clim, space)

        for i, (t, parts) in zip(indices, frames, strict=True):
            _show(updates, parts, add)
            clock.SetText(2, f"t = {t:.4f} s")
            # render() is a no-op before the first screenshot, which then renders itself
            plotter.render()
            image = plotter.screenshot(return_img=True)
            if i in movie:
                add_to_movie(image)
            for stem in shot_at.get(i, []):
                written.append(_write_png(run.out_dir / f"{stem}.png", image))
    if animation:
        written.append(movie_path)
    if "t" in run.history:
        written.append(plot_history(run.out_dir))
    return written
