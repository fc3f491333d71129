"""Static benchmarks of the spatial beam (Beam3D): Simo's roll-up and Bathe & Bolourchi's 45°
curved cantilever, against their exact and published answers, with the mesh.

Roll-up (Simo, Comput. Methods Appl. Mech. Eng. 1985): a cantilever of length L = 1 m,
EI = EA/10⁴ (E = 10⁷ Pa, A = 1 m², I = 10⁻⁴ m⁴), clamped at x = 0, under an end moment
M = λ 2πEI/L about z. Exactly it bends into an arc of radius L/(2πλ): at λ = 1 a full circle,
the tip back on the root; at λ = ½ a half circle, the tip at (0, 2L/π). Measured: the tip's
distance to these, over L, and the load increments (10 and 5 asked; more where one was halved)
and Newton iterations.

45° bend (Bathe & Bolourchi, Int. J. Numer. Methods Eng. 1979): an arc of radius 100 m over 45°
in the x–y plane from the origin (tangent x), E = 10⁷ Pa, ν = 0, a unit square section
(A = 1 m², I₂ = I₃ = 1/12 m⁴, J = 1/6 m⁴ as in the classical data, shear area A), clamped at
the root, a tip force P = 600 N along z applied in 10 load steps. The reference tip is Simo &
Vu-Quoc's (Comput. Methods Appl. Mech. Eng. 1986) (47.23, 15.79, 53.37) m with 8 elements.
"""

from __future__ import annotations

import numpy as np
from _common import RESULTS, markdown_table, parser, write_csv, write_markdown

from fecontact import Beam3D, Material, Model, Section
from fecontact.statics_rotations import solve_static_rotations
from fecontact.testing import roll_up

REFERENCE_TIP = np.array([47.23, 15.79, 53.37])


def bend(n: int, steps: int = 10):
    """Tip position (m) and Newton iterations of the 45° bend with n elements."""
    material = Material(1e7, nu=0.0, rho=1.0)
    section = Section(area=1.0, inertia=1 / 12, inertia_2=1 / 12, torsion=1 / 6, shear_factor=1)
    t = np.linspace(0.0, np.pi / 4, n + 1)
    nodes = np.column_stack([100 * np.sin(t), 100 * (1 - np.cos(t)), np.zeros_like(t)])
    beam = Beam3D(nodes, material, section).clamp(0)
    model = Model([beam])
    load = np.zeros(model.n)
    load[-4] = 600.0
    sol = solve_static_rotations(model, load, steps=steps)
    return beam.positions(sol.q)[-1], sol


def roll_up_rows(counts):
    rows = []
    for n in counts:
        tip1, s1 = roll_up(n, 1.0, 10)
        tip2, s2 = roll_up(n, 0.5, 5)
        rows.append(
            {
                "elements": n,
                "full circle: |tip - root| / L": float(np.linalg.norm(tip1)),
                "half circle: |tip - exact| / L": float(
                    np.linalg.norm(tip2 - [0.0, 2.0 / np.pi, 0.0])
                ),
                "full: increments": len(s1.factors),
                "full: Newton iterations": int(s1.iterations.sum()),
                "half: increments": len(s2.factors),
            }
        )
    return rows


def bend_rows(counts):
    rows = []
    for n in counts:
        tip, sol = bend(n)
        err = np.abs(tip - REFERENCE_TIP) / np.abs(REFERENCE_TIP)
        rows.append(
            {"elements": n}
            | {k: f"{v:.3f}" for k, v in zip(("x", "y", "z"), tip, strict=True)}
            | {"largest relative difference": float(err.max())}
            | {"increments": len(sol.factors), "Newton iterations": int(sol.iterations.sum())}
        )
    return rows


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    rolls = roll_up_rows((5, 10) if args.quick else (4, 5, 10, 20, 40, 80))
    bends = bend_rows((8,) if args.quick else (4, 8, 16, 32, 64))
    t1 = markdown_table(rolls, list(rolls[0]))
    t2 = markdown_table(bends, list(bends[0]))
    print(t1, "\n\n", t2)
    out = args.out or RESULTS
    stem = "beam3d_statics_quick" if args.quick else "beam3d_statics"
    write_csv(f"{out}/{stem}_rollup.csv", rolls, list(rolls[0]))
    write_csv(f"{out}/{stem}_bend.csv", bends, list(bends[0]))
    text = (
        "# Beam3D statics\n\n## Roll-up (Simo 1985)\n\n"
        + t1
        + "\n\n## 45° bend (Bathe & Bolourchi 1979), P = 600 N; "
        + "Simo & Vu-Quoc (1986): (47.23, 15.79, 53.37) m\n\n"
        + t2
    )
    write_markdown(f"{out}/{stem}.md", text)


if __name__ == "__main__":
    main()
