"""The flat module paths of earlier releases (``fecontact.integrator``, ``fecontact.rigid``, ...),
resolved on first import to the modules that now hold them, so that scripts importing them
still run. Nothing is imported until a script asks for an old path."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys

MOVED = {
    "beam": "bodies.beam",
    "solid": "bodies.solid",
    "rigid": "bodies.rigid",
    "materials": "bodies.materials",
    "obstacles": "contact.obstacles",
    "rigid_contact": "contact.rigid_pairs",
    "body_contact": "contact.body_pairs",
    "sparse_solvers": "linalg.sparse_solvers",
    "integrator": "time",
    "baselines": "time",
    "output": "io.output",
    "render": "io.render",
    "cli": "io.cli",
}


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds ``fecontact.<old>`` and loads it as the module at its new path."""

    def find_spec(self, fullname, path=None, target=None):
        package, _, old = fullname.rpartition(".")
        if package != "fecontact" or old not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec):
        module = importlib.import_module(f"fecontact.{MOVED[spec.name.rpartition('.')[2]]}")
        # the import machinery stamps the alias's spec on the module: keep the module's own
        self.own_spec = module.__spec__
        return module

    def exec_module(self, module):
        module.__spec__ = self.own_spec


def install() -> None:
    if not any(isinstance(finder, _Alias) for finder in sys.meta_path):
        sys.meta_path.append(_Alias())
