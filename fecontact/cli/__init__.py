"""The command line and parameter sweeps: the layer above the driver (``fecontact.run``).

``fecontact`` (the console script) and ``python -m fecontact`` call :func:`main`; a case file
run as a script calls :func:`run_cli`. Nothing below this layer imports it.
"""

from .cases import bundled_cases, find_case, load_case
from .commands import main, run_one
from .run import parse_value, run_cli

__all__ = ["bundled_cases", "find_case", "load_case", "main", "parse_value", "run_cli", "run_one"]
