"""fecontact: finite element impact dynamics with exact unilateral contact.

Bodies (geometrically exact beams, 2D and 3D elastic solids, planar rigid bodies), rigid
obstacles, contact pairs and joints make a ``Model``; a ``Simulation`` adds the time step, end
time and probes; ``run`` integrates it with the nonsmooth generalized-α method (contact
enforced exactly at position and velocity level with Alart–Curnier multipliers) and writes VTU
frames, ``history.csv`` and ``summary.json``. SI units throughout.

The package is laid out by concept: ``bodies`` (beam, solid, rigid, materials, meshes),
``contact`` (obstacles, pair kinematics, the Alart–Curnier laws), ``time`` (the steppers and
the time loop), ``linalg`` (the factorization seam), ``io`` (output and rendering) and, above
the driver, ``cli`` (the command line and sweeps). Every public name is importable from
``fecontact`` itself.
"""

from .bodies import (
    Ball,
    Beam2D,
    Beam3D,
    Box,
    Capsule,
    ConvexMesh,
    Cylinder,
    Disk,
    LinearElastic,
    Material,
    NeoHookean,
    PointMass,
    Polygon,
    RigidBody2D,
    RigidBody3D,
    Section,
    Solid,
    StVenantKirchhoff,
)
from .contact import Circle, Contact, Plane, Point, Sphere
from .errors import InputError, SolverError, check_count, check_positive, check_range
from .joints import Pin
from .joints3d import BallJoint, FixedJoint, HingeJoint, PrismaticJoint, UniversalJoint
from .model import Model, NodalLoad
from .params import Param, case
from .simulation import Probe, Simulation, node_probe, run
from .time import IntegratorOptions, State, simulate
from .version import __version__ as __version__

__all__ = [
    "Ball",
    "BallJoint",
    "Beam2D",
    "Beam3D",
    "Box",
    "Capsule",
    "case",
    "check_count",
    "check_positive",
    "check_range",
    "Circle",
    "Contact",
    "ConvexMesh",
    "Cylinder",
    "Disk",
    "FixedJoint",
    "HingeJoint",
    "InputError",
    "IntegratorOptions",
    "LinearElastic",
    "load_run",
    "Material",
    "Model",
    "NeoHookean",
    "NodalLoad",
    "node_probe",
    "Param",
    "Pin",
    "Plane",
    "Point",
    "PointMass",
    "Polygon",
    "PrismaticJoint",
    "Probe",
    "RigidBody2D",
    "RigidBody3D",
    "run",
    "run_cli",
    "Section",
    "simulate",
    "Simulation",
    "Solid",
    "SolverError",
    "Sphere",
    "State",
    "StVenantKirchhoff",
    "UniversalJoint",
]


def load_run(out_dir):
    """Load a finished run (history arrays, summary, frames): see ``fecontact.io.output``."""
    from .io.output import load_run as _load

    return _load(out_dir)


def run_cli(build, argv=None):
    """Command line of a case file: ``python cases/NAME.py [--dt ...] [--set ...]``."""
    from .cli.run import run_cli as _run_cli

    _run_cli(build, argv)
