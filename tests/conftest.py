import importlib.util
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
os.environ.setdefault("MPLBACKEND", "Agg")

# the tests step small models outside ``run`` too (``simulate``, ``trace``): one BLAS thread
# for them all, as inside a run, unless the environment says otherwise
from fecontact.threads import USER_SETTINGS  # noqa: E402

if not any(os.environ.get(name) for name in USER_SETTINGS):
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")


# convex–convex contact needs the 'collision' extra (coal)
needs_coal = pytest.mark.skipif(
    importlib.util.find_spec("coal") is None, reason="the 'collision' extra (coal) is missing"
)


@pytest.fixture(scope="session")
def cases_dir() -> Path:
    return ROOT / "cases"


def load_case(name: str):
    """Import a case module from cases/ by name."""
    from fecontact.testing import case

    return case(name)


sys.path.insert(0, str(Path(__file__).parent))
