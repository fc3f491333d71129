"""Every benchmark script runs in its ``--quick`` mode (a tiny problem, seconds) and writes its
report, so that none of them rots; and none reaches into the package's private names."""

import ast
import os
import subprocess
import sys

import pytest
from conftest import ROOT

BENCHMARKS = ROOT / "benchmarks"
SCRIPTS = sorted(p for p in BENCHMARKS.glob("*.py") if not p.name.startswith("_"))
# namedtuple methods: public API despite the underscore
PUBLIC_UNDERSCORED = {"_replace", "_asdict", "_fields", "_make"}


def private_uses(path):
    """(line, name) of every private name of the package a script imports or touches."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("fecontact"):
            for a in node.names:
                if a.name.startswith("_") and not a.name.endswith("__"):
                    yield node.lineno, a.name
        elif isinstance(node, ast.Attribute):
            name = node.attr
            if name.startswith("_") and not name.endswith("__") and name not in PUBLIC_UNDERSCORED:
                yield node.lineno, name


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_benchmark_uses_only_public_names(script):
    assert list(private_uses(script)) == []


@pytest.mark.slow
@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_benchmark_runs_in_its_quick_mode(script, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg", OPENBLAS_NUM_THREADS="1")
    done = subprocess.run(
        [sys.executable, str(script), "--quick", "--out", str(tmp_path)],
        cwd=BENCHMARKS,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    written = [p.name for p in tmp_path.iterdir()]
    assert any(name.endswith(".md") for name in written), written
