"""Seeded fuzz test of the command line itself: random command lines built from paths (files,
folders, missing ones, files in the way), ``--set`` values, ``--resume`` on good, truncated,
empty and garbage checkpoints, and ``render`` targets (runs, junk files, broken indexes) end
either in exit 0 or in exit 2 with one line of at most 200 characters on stderr — never a
traceback, never a longer message.

Runs are two or three steps of the bouncing ball, so that a valid command finishes at once.
"""

import contextlib
import io
import shutil
from pathlib import Path

import numpy as np
import pytest

from fecontact.cli.commands import main
from fecontact.testing import CASES

SEED_RUNS = 80
CASE = str(CASES / "bouncing_ball.py")


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """A finished run, corrupted copies of its checkpoint and index, junk files and a file
    where a folder should be."""
    root = tmp_path_factory.mktemp("fuzz")
    run = root / "good"
    args = ["run", CASE, "--quiet", "--out", str(run), "--t-end", "0.002", "--dt", "1e-3"]
    assert main([*args, "--checkpoint-every", "1"]) == 0
    checkpoint = (run / "checkpoint.npz").read_bytes()
    for name, data in {
        "truncated": checkpoint[: len(checkpoint) // 2],
        "empty": b"",
        "garbage": bytes(np.random.default_rng(0).integers(0, 256, 999, dtype=np.uint8)),
    }.items():
        shutil.copytree(run, root / name)
        (root / name / "checkpoint.npz").write_bytes(data)
    (root / "junk.vtu").write_text("not a vtu")
    (root / "junk.pvd").write_text("<VTKFile>")
    (root / "empty.pvd").write_text("")
    (root / "a_file").write_text("in the way")
    (root / "junk_case.py").write_text("this is not python(")
    (root / "no_build.py").write_text("x = 1\n")
    (root / "bad.msh").write_text("$MeshFormat\ngarbage\n")
    return root


def paths(root: Path) -> list[str]:
    return [
        str(root / "good"),
        str(root / "good" / "bouncing_ball.pvd"),
        str(root / "good" / "history.csv"),
        str(root / "truncated"),
        str(root / "empty"),
        str(root / "garbage"),
        str(root / "junk.vtu"),
        str(root / "junk.pvd"),
        str(root / "empty.pvd"),
        str(root / "a_file"),
        str(root / "a_file" / "below"),
        str(root / "missing" / "deeper"),
        str(root / "new"),
    ]


SETS = [
    "restitution=0.5",
    "restitution=1.5",
    "restitution=nan",
    "restitution=abc",
    "height=inf",
    "height=-1",
    "height=1e300",
    "colour=red",
    "=3",
    "novalue",
    "rho_inf=2",
    "rho_inf=0.8",
    "max_iterations=0",
    "metric=wrong",
    "integrator=moreau",
    "tol_gap=-1",
]


def command(rng, root: Path) -> list[str]:
    kind = rng.choice(["run"] * 6 + ["render", "render", "info", "junk"])
    where = paths(root)
    if kind == "render":
        return ["render", str(rng.choice(where))]
    if kind == "info":
        return ["info", str(rng.choice([CASE, str(root / "junk_case.py"), str(root / "nope.py")]))]
    if kind == "junk":
        return [str(rng.choice(["fly", "--help-me", "run"]))]
    case = str(rng.choice([CASE] * 10 + [str(root / "junk_case.py"), str(root / "no_build.py")]))
    argv = ["run", case, "--quiet", "--out", str(rng.choice(where)), "--t-end", "0.003"]
    for item in rng.choice(SETS, size=rng.integers(0, 3), replace=False):
        argv += ["--set", str(item)]
    extra = [
        [],
        ["--dt", "1e-3"],
        ["--dt", str(rng.choice(["0", "-1", "nan", "x"]))],
        ["--resume"],
        ["--resume", "--t-end", "0.001"],
        ["--overwrite"],
        ["--checkpoint-every", str(rng.choice(["-1", "0", "1"]))],
        ["--output-interval", str(rng.choice(["0", "1e-3", "-2"]))],
    ]
    return argv + extra[rng.integers(len(extra))]


def test_random_command_lines_end_in_success_or_one_line(workspace):
    rng = np.random.default_rng(20261124)
    for _ in range(SEED_RUNS):
        argv = command(rng, workspace)
        err, out = io.StringIO(), io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            try:
                status = main(argv)
            except SystemExit as exit_:  # argparse's --help (not drawn) would exit 0
                status = exit_.code
        lines = [line for line in err.getvalue().splitlines() if line.strip()]
        if status == 0:
            continue
        assert status == 2, (argv, status, err.getvalue())
        assert len(lines) == 1, (argv, err.getvalue())
        assert lines[0].startswith("fecontact: error: ") and len(lines[0]) <= 200, (argv, lines)
        # a fresh run folder must not hold anything after an input error
        new = workspace / "new"
        if new.exists():
            assert not any(new.iterdir()) or (new / "summary.json").exists(), argv
