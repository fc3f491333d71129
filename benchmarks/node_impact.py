"""Energy across a disk's impact on a flexible cantilever with e_N = 0.

A steel cantilever (``Beam2D``, 20 elements over 1 m, E = 210 GPa, ρ = 7850 kg/m³, section
0.05 × 0.01 m) clamped at x = 0, and a rigid 1 kg disk of radius 0.05 m above x = position, its
centre 0.005 + 0.01 + 0.05 m above the beam's axis (a 0.01 m gap to the top face), released from
rest under gravity: it strikes the beam, sagging under its own weight, at about 0.52 m/s,
0.053 s later. ``Contact(disk, beam, restitution=0, clearance=0.005)``, ρ∞ = 0.5.

E = kinetic + strain + gravity. The gain is max(E) over the impact and after it minus E in the
step before the first contact, in % of the kinetic energy (disk and beam) in that step;
negative when even the largest energy after the impact is below the one before. With e_N = 0
an impact only dissipates: the gain must not be positive. x = 0.5 and 0.45 are nodes, 0.55 too
(elements of 0.05 m); 0.475 and 0.525 are mid-element. ``--phases N`` also starts the disk
higher by k/N (k < N) of its travel in one step, which moves the impact within its step, and
reports the worst.

    python benchmarks/node_impact.py            # about 10 s
    python benchmarks/node_impact.py --phases 8
    python benchmarks/node_impact.py --quick     # x = 0.5 at h = 4e-4 only
"""

from __future__ import annotations

# isort: off
import fecontact  # noqa: F401  (before numpy: single-threaded OpenBLAS)

# isort: on
import numpy as np
from _common import RESULTS, markdown_table, parser, write_markdown

from fecontact import IntegratorOptions, Model, simulate
from fecontact.bodies import Beam2D, Disk, Material, RigidBody2D, Section
from fecontact.contact import Contact

POSITIONS = (0.5, 0.45, 0.55, 0.475, 0.525)
STEPS = (4e-4, 2e-4, 1e-4)
SPEED = 0.52  # m/s, the disk's speed at the impact (for --phases)


def build(position: float, lift: float = 0.0, n_elements: int = 20):
    beam = Beam2D.straight(
        [0.0, 0.0],
        [1.0, 0.0],
        n_elements,
        Material(210e9, rho=7850.0),
        Section.rectangle(0.05, 0.01),
    )
    beam.clamp(0)
    disk = RigidBody2D.uniform(1.0, [position, 0.005 + 0.01 + 0.05 + lift], Disk(0.05))
    return Model([beam, disk], [Contact(disk, beam, restitution=0.0, clearance=0.005)])


def gain(position: float, h: float, lift: float = 0.0, t_end: float = 0.1) -> float:
    """max(E) after the first contact minus E before it, in % of the kinetic energy then."""
    model = build(position, lift)
    energy, kinetic, active = [], [], []
    for st in simulate(model, h, t_end, IntegratorOptions()):
        ke = model.kinetic_energy(st.v)
        energy.append(ke + model.strain_energy(st.q) + model.potential_energy(st.q))
        kinetic.append(ke)
        active.append(bool(st.pressed().any()))
    first = int(np.argmax(active))
    return 100.0 * (max(energy[first:]) - energy[first - 1]) / kinetic[first - 1]


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--phases", type=int, default=1)
    args = p.parse_args()
    steps, positions = ((4e-4,), (0.5,)) if args.quick else (STEPS, POSITIONS)
    rows = []
    for h in steps:
        row = {"h": h}
        for x in positions:
            lifts = [SPEED * h * k / args.phases for k in range(args.phases)]
            row[f"x={x}"] = max(gain(x, h, lift) for lift in lifts)
        rows.append(row)
        print(row, flush=True)
    columns = ["h", *(f"x={x}" for x in positions)]
    text = markdown_table(rows, columns)
    print(text)
    stem = "node_impact" if args.phases == 1 else f"node_impact_phases{args.phases}"
    stem += "_quick" if args.quick else ""
    write_markdown(f"{args.out or RESULTS}/{stem}.md", text)


if __name__ == "__main__":
    main()
