"""Write the small meshes shipped in ``meshes/`` (gmsh 2.2 ASCII, coordinates in m).

Run ``python meshes/make_meshes.py`` to regenerate them; the output is deterministic.

=============  =========================================================  =======  ========
file           geometry                                                   nodes    cells
=============  =========================================================  =======  ========
disk.msh       unit disk centred at the origin (scikit-fem                545      1024
               ``MeshTri.init_circle(4)``), triangles
ball.msh       unit ball centred at the origin (``MeshTet.init_ball(2)``),  129      512
               tetrahedra
bar.msh        bar [0, 1] × [0, 0.05], 100 × 2 quadrilaterals             303      200
=============  =========================================================  =======  ========

Scale and place them when loading: ``Solid.from_file("meshes/disk.msh", material,
scale=0.05, offset=(0.0, 0.1))``. Finer versions come from the same generators through
``Solid.disk``, ``Solid.ball`` and ``Solid.rectangle``.
"""

from pathlib import Path

import meshio
import numpy as np
import skfem
from skfem.io.meshio import to_meshio

HERE = Path(__file__).resolve().parent


def meshes() -> dict:
    """The scikit-fem meshes, by file name."""
    return {
        "disk.msh": skfem.MeshTri.init_circle(4),
        "ball.msh": skfem.MeshTet.init_ball(2),
        "bar.msh": skfem.MeshQuad.init_tensor(
            np.linspace(0.0, 1.0, 101), np.linspace(0.0, 0.05, 3)
        ),
    }


def write(mesh, path: Path) -> None:
    """Write ``mesh`` as gmsh 2.2 ASCII with every cell tagged 1 (physical and geometrical)."""
    m = to_meshio(mesh, encode_cell_data=False)
    points = np.zeros((len(m.points), 3))
    points[:, : m.points.shape[1]] = m.points
    cells = [(block.type, block.data) for block in m.cells]
    tags = {
        k: [np.ones(len(b.data), dtype=int) for b in m.cells] for k in ("physical", "geometrical")
    }
    out = meshio.Mesh(points, cells, cell_data={f"gmsh:{k}": v for k, v in tags.items()})
    meshio.write(path, out, file_format="gmsh22", binary=False)


if __name__ == "__main__":
    for name, mesh in meshes().items():
        write(mesh, HERE / name)
        print(f"{name}: {mesh.p.shape[1]} nodes, {mesh.t.shape[1]} cells")
