"""Off-screen rendering of a small synthetic run: snapshots, animation and history plot."""

import subprocess

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
import pytest

from fecontact.io.output import STANDARD_COLUMNS, HistoryWriter, PVDWriter, line_mesh, write_json
from fecontact.io.render import WINDOW_SIZE, plot_history, render_run

N_FRAMES = 10
T_END = 0.45
T_IMPACT = 0.3
LENGTH = 0.3
PROBES = {
    "tip_x": {"unit": "m", "description": "tip position x"},
    "tip_y": {"unit": "m", "description": "tip position y"},
    "tip_vx": {"unit": "m/s", "description": "tip velocity x"},
    "tip_vy": {"unit": "m/s", "description": "tip velocity y"},
}


def angle(t):
    return -1.2 * t / T_END


def write_run(folder, probes=PROBES):
    """A straight line of 6 points swinging about the origin past a fixed stop."""
    s = np.linspace(0.0, LENGTH, 6)
    omega = -1.2 / T_END
    writer = PVDWriter(folder, "swing")
    writer.write_static("stop", line_mesh([[0.0, -0.25], [0.0, -0.4]], [[0, 1]]))
    for t in np.linspace(0.0, T_END, N_FRAMES):
        c, d = np.cos(angle(t)), np.sin(angle(t))
        x = np.column_stack([s * c, s * d])
        v = omega * np.column_stack([-s * d, s * c])
        data = {"displacement": x - np.column_stack([s, 0 * s]), "velocity": v}
        writer.write_frame(
            t, {"beam": line_mesh(x, np.column_stack([range(5), range(1, 6)]), data)}
        )
    with HistoryWriter(folder / "history.csv", [*STANDARD_COLUMNS, *probes]) as history:
        for t in np.linspace(0.0, T_END, 91):
            c, d = np.cos(angle(t)), np.sin(angle(t))
            in_contact = t >= T_IMPACT
            energy = 0.1 - 0.01 * t
            history.write(
                [t, 0.05, 0.0, energy - 0.05, energy, 0.0 if in_contact else np.inf,
                 in_contact, 0.01 * in_contact, 2, T_END / 90,
                 LENGTH * c, LENGTH * d, 0.8 * d, -0.8 * c][: len(STANDARD_COLUMNS) + len(probes)]
            )  # fmt: skip
    impacts = [{"time": T_IMPACT, "contact": "stop", "impulse": 0.01}]
    write_json(folder / "summary.json", {"probes": probes, "impacts": impacts})
    return folder


def assert_picture(image, shape):
    assert image.shape[:2] == shape
    rgb = image[..., :3].astype(np.int64)
    assert rgb.std() > 0
    colours = np.unique((rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2])
    assert colours.size > 10  # a drawing, not a flat fill


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    folder = write_run(tmp_path_factory.mktemp("swing"))
    return folder, render_run(folder)


def test_render_run_writes_snapshots_animation_and_history(rendered):
    folder, paths = rendered
    names = [p.name for p in paths]
    assert names == [
        "snapshot_start.png",
        "snapshot_impact.png",
        "snapshot_end.png",
        "animation.gif",
        "history.png",
    ]
    assert all(p.parent == folder and p.stat().st_size > 0 for p in paths)
    height_width = WINDOW_SIZE[::-1]
    snapshots = {p.stem: iio.imread(p) for p in paths if p.suffix == ".png"}
    for stem in ("snapshot_start", "snapshot_impact", "snapshot_end"):
        assert_picture(snapshots[stem], height_width)
    # the line moves between snapshots while the camera stays put
    start, impact, end = (
        snapshots[s].astype(int) for s in ("snapshot_start", "snapshot_impact", "snapshot_end")
    )
    assert np.abs(start - end).sum() > 0 and np.abs(start - impact).sum() > 0

    movie = iio.imread(folder / "animation.gif", index=None)
    assert movie.shape[0] == N_FRAMES
    assert movie.shape[1:3] == height_width
    assert_picture(movie[N_FRAMES // 2], height_width)
    assert np.abs(movie[0].astype(int) - movie[-1].astype(int)).sum() > 0


def test_planar_view_keeps_moving_and_static_parts_in_frame(rendered):
    folder, _ = rendered
    white = np.array([255, 255, 255])
    for stem in ("snapshot_start", "snapshot_end"):
        image = iio.imread(folder / f"{stem}.png")[..., :3]
        drawn = np.any(image != white, axis=-1)
        # nothing drawn touches the left, right or bottom edge: the fixed camera fits the scene
        assert not drawn[:, :2].any() and not drawn[:, -2:].any() and not drawn[-2:].any()
        # static stop is grey: equal channels, neither white nor black
        grey = (np.ptp(image, axis=-1) < 4) & (image[..., 0] > 60) & (image[..., 0] < 220)
        assert grey.sum() > 200


def test_history_plot_has_one_panel_per_unit_and_energy(rendered):
    folder, _ = rendered
    image = iio.imread(folder / "history.png")
    # 7.0 in wide at 150 dpi; 2.0 in per unit panel (m, m/s), 1.2 in energy, 0.8 in margins
    assert_picture(image, (round((2 * 2.0 + 1.2 + 0.8) * 150), round(7.0 * 150)))


def test_history_plot_without_units_has_one_panel_per_probe(tmp_path):
    folder = write_run(tmp_path / "run", probes={"tip_x": {}, "tip_y": {"unit": ""}})
    (folder / "swing.pvd").unlink()  # the plot needs only history.csv and summary.json
    path = plot_history(folder, path=tmp_path / "plot.png")
    assert path == tmp_path / "plot.png"
    assert_picture(iio.imread(path), (round((2 * 2.0 + 1.2 + 0.8) * 150), 1050))


def test_render_mp4_at_requested_times_without_history(tmp_path):
    folder = write_run(tmp_path / "run")
    (folder / "history.csv").unlink()
    paths = render_run(folder, snapshot_times=[0.1, 0.4], fmt="mp4", max_frames=4)
    assert [p.name for p in paths] == [
        "snapshot_t0.1000.png",
        "snapshot_t0.4000.png",
        "animation.mp4",
    ]
    assert_picture(iio.imread(paths[0]), WINDOW_SIZE[::-1])
    n_frames, _ = imageio_ffmpeg.count_frames_and_secs(str(folder / "animation.mp4"))
    assert n_frames == 4
    # decode the last frame with ffmpeg itself (imageio's ffmpeg reader leaves pipes open)
    last = tmp_path / "last.png"
    subprocess.run(
        [imageio_ffmpeg.get_ffmpeg_exe(), "-v", "error", "-i", str(folder / "animation.mp4"),
         "-vf", "select=eq(n\\,3)", "-frames:v", "1", str(last)],
        check=True,
    )  # fmt: skip
    assert_picture(iio.imread(last), WINDOW_SIZE[::-1])


def test_history_panels_name_what_the_probes_measure():
    from fecontact.io.render import history_panels

    probes = {
        "y_center": {"unit": "m", "description": "centre of mass position"},
        "vy_center": {"unit": "m/s", "description": "centre of mass velocity"},
        "gap": {"unit": "m", "description": "lowest point height"},
        "tip_x": {"unit": "m", "description": "tip position"},
        "omega": {"unit": "rad/s", "description": "angular velocity of the disk"},
    }
    panels = dict((tuple(names), label) for label, names in history_panels(list(probes), probes))
    assert panels[("y_center", "gap", "tip_x")] == "length (m)"  # positions: no displacement
    assert panels[("vy_center",)] == "centre of mass velocity (m/s)"
    assert panels[("omega",)] == "angular velocity of the disk (rad/s)"
