"""GetFEM's side of ``getfem_ball.py``: the ball impact on a rigid plane, run by GetFEM.

Run by the system Python that has Debian's ``python3-getfem`` (not fecontact's); it reads the
mesh file the benchmark wrote and a JSON of the parameters, and prints one JSON line: the wall
and CPU time of the set-up and of the time loop, and per step the z-momentum, the approach of
the centre of mass and whether a node touches.

The model is what a GetFEM user writes for this impact: P1 displacement on the same
tetrahedra, ``add_isotropic_linearized_elasticity_brick``, Newmark's average acceleration
(β = 1/4, γ = 1/2, written into the model as a mass term and a source term, so the step solves
ρ/(βh²) M u + K u + contact = ρ/(βh²) M u_pred), and the nodal Alart–Curnier contact with the
rigid obstacle z ≥ 0 (``add_nodal_contact_with_rigid_obstacle_brick``, augmentation r = E) on
the boundary faces of the lower hemisphere, solved by GetFEM's Newton solver with MUMPS.

    /usr/bin/python3 benchmarks/_getfem_ball_driver.py MESH.msh PARAMS.json
"""

import json
import sys
import time

import getfem as gf
import numpy as np

BETA, GAMMA = 0.25, 0.5
CONTACT = 1  # the region of the faces that may touch


def cpu_seconds() -> float:
    return time.process_time()


def build(mesh_path: str, p: dict):
    """The model, its displacement FEM and integration method, and the mass weights of u_z."""
    gf.util_trace_level(0)  # no assembly traces on stderr
    gf.util_warning_level(0)
    mesh = gf.Mesh("import", "gmsh", mesh_path)
    mfu = gf.MeshFem(mesh, 3)
    mfu.set_classical_fem(1)
    mfd = gf.MeshFem(mesh, 1)
    mfd.set_classical_fem(1)
    mim = gf.MeshIm(mesh, gf.Integ("IM_TETRAHEDRON(2)"))  # exact for the P1 mass
    faces = mesh.outer_faces()
    down = mesh.normal_of_faces(faces)[2] < 0.0  # the lower hemisphere faces the plane
    mesh.set_region(CONTACT, faces[:, down])

    E, nu, rho, h = p["E"], p["nu"], p["rho"], p["h"]
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_initialized_data("lambda", [E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))])
    md.add_initialized_data("mu", [E / (2.0 * (1.0 + nu))])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
    md.add_initialized_data("c", [rho / (BETA * h * h)])
    md.add_mass_brick(mim, "u", "c")
    md.add_initialized_fem_data("Upred", mfu, np.zeros(mfu.nbdof()))
    md.add_source_term_brick(mim, "u", "c*Upred")
    n_contact = mfd.dof_on_region(CONTACT).size
    md.add_variable("lambda_n", n_contact)
    md.add_initialized_data("r", [E])
    md.add_nodal_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "r", CONTACT, "z", 1)

    ez = np.zeros(mfu.nbdof())
    ez[2::3] = 1.0  # mfu's dofs interleave x, y, z per node
    M = gf.asm_mass_matrix(mim, mfu)
    w = rho * np.asarray(M.mult(ez)).ravel()  # z-momentum weights: p_z = w · v
    return md, mfu, w, n_contact


def run(mesh_path: str, p: dict) -> dict:
    wall, cpu = time.perf_counter(), cpu_seconds()
    md, mfu, w, n_contact = build(mesh_path, p)
    setup_wall, setup_cpu = time.perf_counter() - wall, cpu_seconds() - cpu
    mass = float(w.sum())  # w is zero on the x and y dofs
    h, steps = p["h"], p["steps"]
    u = np.zeros(mfu.nbdof())
    v = np.zeros(mfu.nbdof())
    v[2::3] = -p["speed"]
    a = np.zeros(mfu.nbdof())  # no force at t = 0: the ball just touches the plane
    momentum, approach, touching, newton = [float(w @ v)], [0.0], [], []
    wall, cpu = time.perf_counter(), cpu_seconds()
    for _ in range(steps):
        u_pred = u + h * v + h * h * (0.5 - BETA) * a
        md.set_variable("Upred", u_pred)
        its = md.solve("max_res", p["tol"], "max_iter", 50, "lsolver", p["lsolver"])
        u_new = md.variable("u")
        a_new = (u_new - u_pred) / (BETA * h * h)
        v = v + h * ((1.0 - GAMMA) * a + GAMMA * a_new)
        u, a = u_new, a_new
        lam = md.variable("lambda_n")
        momentum.append(float(w @ v))
        approach.append(-float(w @ u) / mass)
        touching.append(int(np.count_nonzero(np.abs(lam) > p["tol"])))  # beyond Newton's noise
        newton.append(int(its[0]) if np.ndim(its) else int(its))
    loop_wall, loop_cpu = time.perf_counter() - wall, cpu_seconds() - cpu
    return {
        "dofs": int(mfu.nbdof()),
        "contact_nodes": int(n_contact),
        "setup_wall_s": setup_wall,
        "setup_cpu_s": setup_cpu,
        "loop_wall_s": loop_wall,
        "loop_cpu_s": loop_cpu,
        "momentum": momentum,
        "approach": approach,
        "touching": touching,
        "newton": newton,
        "mass": mass,
    }


if __name__ == "__main__":
    params = json.loads(open(sys.argv[2]).read())
    print(json.dumps(run(sys.argv[1], params)))
