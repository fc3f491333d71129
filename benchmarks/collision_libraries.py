"""GJK/EPA of coal and python-fcl on the same convex pairs: distance against closed forms,
what each reports (normal, witness points), time per query.

Two unit cubes as convex hulls of their corners (the form every polyhedron takes in
``fecontact.contact.convex_pairs``): face over face, offset sideways, at signed distances from
+0.3 m to −0.1 m (exact: the offset along z less 1 m), and one turned corner down, exact
z − 1/2 − √3/2. Per library the largest error against the closed form, whether it returns the
normal, and the least time per query over ``repeats`` batches (``time.perf_counter``; both
libraries alternate in this process so a change of load hits both). A library that is not
installed is reported so.

    python benchmarks/collision_libraries.py [--quick] [--repeats N] [--out DIR]
"""

from __future__ import annotations

import importlib
import time

import numpy as np
from _common import RESULTS, markdown_table, parser, write_markdown

from fecontact import Box
from fecontact.contact.convex_pairs import hull_faces
from fecontact.rotations import exp

CUBE = Box(1.0, 1.0, 1.0).vertices
_D = np.array([-1.0, -1.0, -1.0]) / np.sqrt(3.0)
_AXIS = np.cross(_D, [0.0, 0.0, -1.0])
CORNER_DOWN = exp(_AXIS / np.linalg.norm(_AXIS) * np.arccos(-_D[2]))
GAPS = (0.3, 1e-3, 1e-6, 0.0, -1e-3, -0.1)


def cases():
    """(exact signed distance, rotation and position of the second cube)."""
    out = [(g, np.eye(3), np.array([0.2, 0.1, 1.0 + g])) for g in GAPS]
    z0 = 0.5 + np.sqrt(3.0) / 2.0
    return out + [(g, CORNER_DOWN, np.array([0.0, 0.0, z0 + g])) for g in GAPS]


def coal_query(lib):
    points = lib.StdVec_Vec3s()
    for p in CUBE:
        points.append(p)
    a, b = lib.Convex.convexHull(points, False, ""), lib.Convex.convexHull(points, False, "")
    req = lib.DistanceRequest()
    req.gjk_tolerance = req.epa_tolerance = 1e-10
    origin = lib.Transform3s(np.eye(3), np.zeros(3))

    def query(R, x):
        res = lib.DistanceResult()
        d = lib.distance(a, origin, b, lib.Transform3s(R, x), req, res)
        return d, np.array(res.normal)

    return query


def fcl_query(lib):
    tris = np.array([np.r_[3, t] for t in _triangles()], dtype=np.int32).ravel()
    a = lib.CollisionObject(lib.Convex(CUBE, len(tris) // 4, tris))
    b = lib.CollisionObject(lib.Convex(CUBE, len(tris) // 4, tris))
    req = lib.DistanceRequest(enable_nearest_points=True, enable_signed_distance=True)

    def query(R, x):
        b.setTransform(lib.Transform(R, x))
        res = lib.DistanceResult()
        return lib.distance(a, b, req, res), None  # witness points only, no normal

    return query


def _triangles():
    faces, _, _ = hull_faces(CUBE)
    return [t for f in faces for t in ((f[0], f[1], f[2]), (f[0], f[2], f[3]))]


LIBRARIES = {"coal": ("coal", coal_query), "python-fcl": ("fcl", fcl_query)}


def measure(query, n: int) -> tuple[float, float]:
    """(largest |d − exact| in m, s per query over n queries of every case)."""
    err = max(abs(query(R, x)[0] - g) for g, R, x in cases())
    start = time.perf_counter()
    for _ in range(n):
        for _, R, x in cases():
            query(R, x)
    return err, (time.perf_counter() - start) / (n * len(cases()))


def main() -> None:
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    n, repeats = (20, 1) if args.quick else (500, args.repeats)
    queries = {}
    for name, (module, build) in LIBRARIES.items():
        try:
            queries[name] = build(importlib.import_module(module))
        except ImportError:
            queries[name] = None
    best = {name: (np.inf, np.inf) for name in queries}
    for _ in range(repeats):
        for name, query in queries.items():
            if query is not None:
                err, cost = measure(query, n)
                best[name] = (err, min(best[name][1], cost))
    rows = []
    for name, query in queries.items():
        if query is None:
            rows.append(
                {"library": name, "max_error_m": "not installed", "normal": "", "us_per_query": ""}
            )
            continue
        normal = query(np.eye(3), np.array([0.2, 0.1, 1.0]))[1]
        rows.append(
            {
                "library": name,
                "max_error_m": f"{best[name][0]:.1e}",
                "normal": "yes" if normal is not None else "no (witness points)",
                "us_per_query": f"{1e6 * best[name][1]:.1f}",
            }
        )
    text = (
        "# GJK/EPA of coal and python-fcl on two unit cubes\n\n"
        f"{len(cases())} pairs (face over face and corner first, signed distances "
        f"{', '.join(f'{g:g}' for g in GAPS)} m); least time per query over {repeats} "
        f"batches of {n} rounds.\n\n" + markdown_table(rows, list(rows[0])) + "\n"
    )
    print(text)
    stem = "collision_libraries_quick" if args.quick else "collision_libraries"
    write_markdown(f"{args.out or RESULTS}/{stem}.md", text)


if __name__ == "__main__":
    main()
