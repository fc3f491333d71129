import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(scope="session")
def cases_dir() -> Path:
    return ROOT / "cases"


def load_case(name: str):
    """Import a case module from cases/ by name."""
    from fecontact.testing import case

    return case(name)


sys.path.insert(0, str(Path(__file__).parent))
