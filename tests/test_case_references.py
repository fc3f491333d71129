"""Every shipped case reproduces its reference history: the same rows, to round-off, for the
same parameters and options. A change that alters the physics regenerates the references
(``python tests/test_case_references.py``) and says why in its commit."""

import sys
from pathlib import Path

import numpy as np
import pytest

from fecontact.cli.commands import main
from fecontact.io.output import LEDGER_COLUMNS, read_history

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = Path(__file__).resolve().parent / "reference"

# short runs through the first contact events, fast enough for the suite
RUNS = {
    "ball_drop": ["--set", "refinements=1", "--t-end", "0.004"],
    "bouncing_ball": ["--t-end", "0.6", "--set", "restitution=0.5"],
    "disk_drop": ["--set", "refinements=2", "--t-end", "0.004"],
    "disk_on_beam": ["--t-end", "0.15"],
    "elastic_block": ["--t-end", "0.03", "--set", "incline=30", "--set", "velocity=0.5"],
    "flexible_pendulum": ["--t-end", "0.4", "--set", "restitution=0.5"],
    "impacting_bar": ["--set", "n_elements=20"],
    "rigid_pendulum": ["--t-end", "0.6"],
    "rocking_block": ["--t-end", "0.3"],
    "rod_on_post": ["--t-end", "0.11"],
    "two_bars": ["--set", "n_elements=20"],
    "two_disks": ["--set", "refinements=2", "--t-end", "0.004"],
}

# columns whose reference is zero up to round-off (a conserved total) are compared on the scale
# of their parts: the two disks' total momentum against one disk's, m v = 7.65 kg·m/s per m
PART_SCALE = {
    ("two_disks", "momentum"): 7.65,
    # the disk dropped straight down: no motion along the plane (1 m/s), no spin (20 rad/s)
    ("disk_drop", "vx_center"): 1.0,
    ("disk_drop", "omega"): 20.0,
    # the block's strain energy (1e-4 J) is what the contact leaves of its kinetic energy
    # (0.068 J): its round-off is on that scale (1.1e-13 J apart with two BLAS threads)
    ("elastic_block", "strain_energy"): 0.068,
    # the disks' sideways speeds, against their impact speed (1 m/s)
    ("two_disks", "vy_left"): 1.0,
    ("two_disks", "vy_right"): 1.0,
}


def run(case: str, out: Path) -> dict:
    args = ["run", str(ROOT / "cases" / f"{case}.py"), "--quiet", "--out", str(out)]
    assert main([*args, "--checkpoint-every", "0", *RUNS[case]]) == 0
    return read_history(out / "history.csv")


@pytest.mark.parametrize("case", sorted(RUNS))
def test_case_reproduces_its_reference_history(case, tmp_path):
    new = run(case, tmp_path)
    ref = read_history(REFERENCE / f"{case}.csv")
    assert list(new) == list(ref)
    assert set(LEDGER_COLUMNS) <= set(ref)
    # the energy ledger's terms are sums of differences of the energies: their round-off is
    # on the scale of the energies summed, not of the term (a damping of zero, a numerical
    # dissipation of 1e-6 J beside energies of 1 J)
    energies = sum(np.abs(ref[k]) for k in ("kinetic_energy", "strain_energy", "potential_energy"))
    for name in ref:
        a, b = new[name], ref[name]
        assert a.shape == b.shape, name
        finite = np.isfinite(b)
        assert np.array_equal(finite, np.isfinite(a)), name
        # a reordered sum changes the last bits; 1e-9 of the column's scale is far above
        # round-off and far below any change of the physics
        part = PART_SCALE.get((case, name), 1e-300)
        if name in LEDGER_COLUMNS:
            part = float(np.max(energies))
        scale = max(np.max(np.abs(b[finite]), initial=0.0), part)
        atol = 1e-9 * scale
        if name == "newton_iterations":
            # a step whose last residual lands at the tolerance takes one iteration more or
            # less on another BLAS or NumPy (seen on NumPy 1.23 / SciPy 1.9: 7 of 751 steps)
            atol = 1.0
        np.testing.assert_allclose(a[finite], b[finite], rtol=0, atol=atol, err_msg=name)


def add_columns(case: str, new: dict, text: list[list[str]]) -> list[list[str]]:
    """The reference ``text`` (header, rows) of ``case`` with the columns of the run ``new``
    that it lacks, in the run's order: its own cells stay as they are, byte for byte."""
    header, rows = text[0], text[1:]
    assert len(rows) == len(next(iter(new.values()))), case
    cells = {k: [row[i] for row in rows] for i, k in enumerate(header)}
    for k in new:
        cells.setdefault(k, [repr(float(x)) for x in new[k]])
    return [list(new)] + [[cells[k][i] for k in new] for i in range(len(rows))]


if __name__ == "__main__":
    # python tests/test_case_references.py [--add-columns] [CASE ...]: a change of the physics
    # rewrites the references; --add-columns only adds the columns a run gained (the
    # existing ones must pass this test first)
    import csv
    import shutil
    import tempfile

    add = "--add-columns" in sys.argv
    for case in [a for a in sys.argv[1:] if a != "--add-columns"] or sorted(RUNS):
        path = REFERENCE / f"{case}.csv"
        with tempfile.TemporaryDirectory() as tmp:
            new = run(case, Path(tmp))
            if add:
                with path.open(newline="") as f:
                    text = add_columns(case, new, list(csv.reader(f)))
                with path.open("w", newline="") as f:
                    csv.writer(f, lineterminator="\n").writerows(text)
            else:
                shutil.copy(Path(tmp) / "history.csv", path)
            print(f"wrote {path}")
