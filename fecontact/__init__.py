"""fecontact: finite element impact dynamics with exact unilateral contact.

Bodies (geometrically exact beams), rigid obstacles and contact pairs make a ``Model``; a
``Simulation`` adds the time step, end time and probes; ``run`` integrates it with the
nonsmooth generalized-α method (contact enforced exactly at position and velocity level with
Alart–Curnier multipliers) and writes VTU frames, ``history.csv`` and ``summary.json``.
SI units throughout.
"""

import os

# The dense systems here have tens of unknowns: OpenBLAS threads only add synchronisation
# (measured 4-9x slower steps on a loaded 2-core machine). Takes effect when fecontact is
# imported before numpy (the command line, case scripts); an explicit setting wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

__version__ = "0.1.0"

from .beam import Beam2D, Material, Section
from .contact import Contact
from .errors import InputError, SolverError, check_count, check_positive, check_range
from .integrator import IntegratorOptions, State, simulate
from .joints import Pin
from .materials import LinearElastic, NeoHookean, StVenantKirchhoff
from .model import Model, NodalLoad
from .obstacles import Circle, Plane, Point, Sphere
from .simulation import Probe, Simulation, node_probe, run
from .solid import Solid

__all__ = [
    "Beam2D",
    "Circle",
    "Contact",
    "InputError",
    "IntegratorOptions",
    "LinearElastic",
    "Material",
    "Model",
    "NeoHookean",
    "NodalLoad",
    "Pin",
    "Plane",
    "Point",
    "Probe",
    "Section",
    "Simulation",
    "Solid",
    "SolverError",
    "Sphere",
    "State",
    "StVenantKirchhoff",
    "check_count",
    "check_positive",
    "check_range",
    "load_run",
    "node_probe",
    "run",
    "run_cli",
    "simulate",
]


def load_run(out_dir):
    """Load a finished run (history arrays, summary, frames): see ``fecontact.output``."""
    from .output import load_run as _load

    return _load(out_dir)


def run_cli(build, argv=None):
    """Command line of a case file: ``python cases/NAME.py [--dt ...] [--set ...]``."""
    from .cli import run_cli as _run_cli

    _run_cli(build, argv)
