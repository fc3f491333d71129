"""Case files: importing one, and the cases bundled with fecontact.

A case is a Python file defining ``build(**params) -> Simulation``. The bundled cases are the
``cases/`` folder of a source checkout; a wheel carries the same files as the package data
``fecontact.cases``, so ``fecontact run flexible_pendulum`` works from any folder.
"""

from __future__ import annotations

import hashlib
import importlib.util
import inspect
from pathlib import Path

from ..errors import InputError, did_you_mean

__all__ = ["bundled_cases", "case_origin", "cases_folder", "find_case", "load_case"]

_PACKAGE = Path(__file__).resolve().parents[1]


def cases_folder() -> Path | None:
    """Where the bundled case files are: the package data of an installed wheel, else the
    ``cases/`` folder beside the package in a source checkout."""
    installed = _PACKAGE / "cases"
    if installed.is_dir():
        return installed
    checkout = _PACKAGE.parent
    if (checkout / "pyproject.toml").is_file() and (checkout / "cases").is_dir():
        return checkout / "cases"
    spec = importlib.util.find_spec("fecontact.cases")  # an editable install's mapping
    if spec is not None and spec.submodule_search_locations:
        return Path(next(iter(spec.submodule_search_locations)))
    return None


def bundled_cases() -> dict[str, Path]:
    """The bundled cases by name (the file's stem), sorted."""
    folder = cases_folder()
    if folder is None:
        return {}
    return {p.stem: p for p in sorted(folder.glob("*.py")) if not p.stem.startswith("_")}


def find_case(name_or_path) -> Path:
    """The case file given by its path, or by the name of a bundled case."""
    p = Path(name_or_path)
    if p.is_file():
        if p.suffix != ".py":
            raise InputError(f"case file must be a Python file ending in .py, got {p.name}")
        return p
    if p.suffix == "" and len(p.parts) == 1:
        known = bundled_cases()
        if p.name in known:
            return known[p.name]
        listed = ", ".join(known) or "none found"
        hint = did_you_mean(p.name, known)
        raise InputError(
            f"case not found: {name_or_path}{hint}: no such file, nor a bundled case ({listed})"
        )
    # "ball_drop.py" typed in another folder than cases/: the bundled case of that name
    hint = did_you_mean(p.stem, bundled_cases()) if p.suffix == ".py" else ""
    raise InputError(f"case file not found: {name_or_path}{hint}")


def load_case(path) -> object:
    """Import a case file (or a bundled case by name) and return its module (it must define
    ``build``)."""
    p = find_case(path)
    spec = importlib.util.spec_from_file_location(f"fecontact_case_{p.stem}", p)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as err:
        raise InputError(f"cannot import case file {path}: {err}") from err
    if not callable(getattr(module, "build", None)):
        raise InputError(f"case file {path} defines no build() function")
    return module


def case_origin(build) -> dict:
    """What identifies the case a run was built from: the path and SHA-256 of the file that
    defines ``build`` (empty for a ``build`` defined outside a file)."""
    try:
        path = Path(inspect.getfile(inspect.unwrap(build))).resolve()
        return {"file": str(path), "sha256": hashlib.sha256(path.read_bytes()).hexdigest()}
    except (TypeError, OSError):
        return {}
