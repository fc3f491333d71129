"""Optional dependencies: rendering, sweeps and the AMG solver come with extras of the
package, and a missing one is a one-line error naming the extra that installs it."""

from __future__ import annotations

import importlib

from .errors import InputError

__all__ = ["need"]


def need(module: str, extra: str):
    """Import ``module``; if it is not installed, raise ``InputError`` naming the extra."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as err:
        if err.name is None or err.name.split(".")[0] != module.split(".")[0]:
            raise  # a module missing inside an installed package is another problem
        raise InputError(
            f'{module} is not installed; it comes with: pip install "fecontact[{extra}]"'
        ) from None
