"""Two energy-controlling smooth steps tried against the pendulum's blow-up at ρ∞ = 0.8.

The flexible pendulum with e_N = 1 at h = 1e-3 s and ρ∞ = 0.8 completes at its nominal
parameters but diverges when the strip changes by about 1 % (``axial_pumping.py``). Two known
remedies, each as a replacement of the smooth generalized-α step of the NSGA (the position
correction and the velocity jump unchanged), prototyped here on the dense 15-dof model:

- GEMM, the generalized energy–momentum method (Kuhl & Crisfield 1999), in the variables of
  Arnold & Brüls: M[(1 − α_f) v̇_{n+1} + α_f v̇_n] + f_alg(q_n, q_{n+1}) = f_ext at the α-point,
  with f_alg = Σ_e ℓ_e B̄_eᵀ C [(1 − α_f) ε_{n+1} + α_f ε_n] and B̄ the discrete derivative of the
  strains of the one-point Simo–Reissner element, B̄ (q_{n+1} − q_n) = ε_{n+1} − ε_n exactly
  (products split at their means, Δcos φ = −sin φ̄ sinc(Δφ/2) Δφ). With ρ∞ = 1 it is the
  energy–momentum midpoint rule: the strain energy changes by exactly f_alg·Δq.
- An energy bound (after Hughes, Caughey & Liu 1978 and Kuhl & Ramm 1996): when the smooth
  step ends with more energy than it started with, it is solved again with the constraint
  E(q_{n+1}, v_{n+1}) = E_n and a multiplier μ on dE/dq_{n+1} = γ′Mv + f_int − f_ext.

Neither is kept. The step that is, ``scheme="energy-decaying"``, makes the midpoint rule
dissipative by second differences of the strains and of the velocities instead, so that a
modified energy provably decays (``fecontact/time/energy_step.py``; measured against
generalized-α in ``energy_decaying.py``).

Runs (``--quick``: 0.05 s each and the nominal strip only, a check that the script runs):

1. free flight before the first impact (0.3 s), ρ∞ = 1 and 0.8: energy drift;
2. the 7 strips of ``axial_pumping.PERTURBED`` at ρ∞ = 0.8, 3 s: completed or diverged;
3. the nominal strip at ρ∞ = 0.8 over 1.5 s: energy lost, against the generalized-α run at h/8
   (the impacts and the scheme's own dissipation), and the tip's largest distance from it.

    python benchmarks/energy_schemes.py --workers 2   # about 2 minutes
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp
from _common import map_runs, parser, report, trace, write_markdown
from axial_pumping import PERTURBED, runaway

import fecontact.time.nsga as nsga
from fecontact.bodies.beam_kernels import beam_strains
from fecontact.testing import case
from fecontact.time.generalized_alpha import predict


def _dense(A):
    return A.toarray() if sp.issparse(A) else np.asarray(A)


def _energy(model, q, v) -> float:
    return model.kinetic_energy(v) + model.potential_energy(q) + model.strain_energy(q)


def discrete_gradient_force(el, q0, q1, af: float, ndof: int) -> np.ndarray:
    """f_alg of one Beam2D: Σ ℓ B̄ᵀ C [(1 − α_f) ε(q1) + α_f ε(q0)], B̄Δq = ε(q1) − ε(q0)."""
    G0, g0, k0, c0, s0 = beam_strains(el, q0)
    G1, g1, k1, c1, s1 = beam_strains(el, q1)
    U0, U1 = q0.reshape(-1, 3), q1.reshape(-1, 3)

    def stretch(U):  # x′ of the element's axis, ((x_b − x_a)/ℓ, (y_b − y_a)/ℓ)
        d = el.chord + U[el.n1, :2] - U[el.n0, :2]
        return d / el.ell[:, None]

    a = 0.5 * (stretch(U0) + stretch(U1))
    phi0 = el.phi0 + 0.5 * (U0[el.n0, 2] + U0[el.n1, 2])
    phi1 = el.phi0 + 0.5 * (U1[el.n0, 2] + U1[el.n1, 2])
    mid, sinc = 0.5 * (phi0 + phi1), np.sinc((phi1 - phi0) / (2 * np.pi))
    cm, sm = 0.5 * (c0 + c1), 0.5 * (s0 + s1)
    dG_dphi = sinc * (a[:, 1] * np.cos(mid) - a[:, 0] * np.sin(mid))
    dg_dphi = -sinc * (a[:, 0] * np.cos(mid) + a[:, 1] * np.sin(mid))
    EA, GA, EI = el.C
    N = EA * ((1 - af) * G1 + af * G0)
    V = GA * ((1 - af) * g1 + af * g0)
    M = EI * ((1 - af) * k1 + af * k0)
    coef = np.stack([N * cm - V * sm, N * sm + V * cm, N * dG_dphi + V * dg_dphi, M], axis=1)
    f_e = np.einsum("ek,eki->ei", el.ell[:, None] * coef, el.e)
    return np.bincount(el.dofs.ravel(), f_e.ravel(), minlength=ndof)


def gemm_step(model, st, t, c, opts, timer, P=None):
    """The smooth step of GEMM (module docstring), Newton with a difference tangent."""
    F, free = model.free_slice, model.free
    X = predict(st, c)
    q, v, vd, a = X
    af = c.af
    fe = (1 - af) * model.external(t)[F] + af * model.external(st.t)[F]
    M = _dense(model.M)
    beam = model.bodies[0]

    def f_alg(q1):
        return discrete_gradient_force(beam.elements, st.q, q1, af, model.n)[F]

    rest = af * (M @ st.vd[F]) - fe
    for it in range(opts.max_iterations + 1):  # noqa: B007 (the count is returned)
        fa = f_alg(q)
        r = (1 - af) * (M @ vd[F]) + fa + rest
        if np.linalg.norm(r) <= opts.tol_residual * np.sqrt(max(fe @ fe, fa @ fa, 1e-300)):
            break
        J = np.empty((free.size, free.size))
        for i, dof in enumerate(free):
            qp = q.copy()
            qp[dof] += 1e-7
            J[:, i] = (f_alg(qp) - fa) / 1e-7
        X[:, F] += np.multiply.outer(c.w, -np.linalg.solve((1 - af) * c.bp * M + J, r))
    else:
        raise nsga.StepFailure("GEMM smooth step", float(np.linalg.norm(r)))
    return nsga.SmoothStep(q, v, vd, a, st.lam, None, it, None, None, None, 0.0)


def bounded_step(model, st, t, c, opts, timer, P=None, _step=nsga.alpha_smooth_step):
    """The generalized-α smooth step, solved again on E(q, v) = E_n when it gained energy."""
    s = _step(model, st, t, c, opts, timer, P)
    E0 = _energy(model, st.q, st.v)
    scale = model.kinetic_energy(st.v) + model.strain_energy(st.q) + 1e-300
    X = np.array([s.q, s.v, s.vd, s.a])
    q, v, vd = X[0], X[1], X[2]
    if _energy(model, q, v) - E0 <= 1e-9 * scale:
        return s
    F, M = model.free_slice, _dense(model.M)
    fext = model.external(t)[F]
    mu = 0.0
    for _ in range(30):
        _, fint, K = model.internal(q)
        K = _dense(K)
        r = M @ vd[F] + fint[F] - fext
        d = c.gp * M @ v[F] + fint[F] - fext  # dE/dq_{n+1}
        R = np.concatenate([r + mu * d, [_energy(model, q, v) - E0]])
        ref = np.sqrt(max(fext @ fext, fint[F] @ fint[F], 1e-300))
        if np.linalg.norm(R[:-1]) <= opts.tol_residual * ref and abs(R[-1]) < 1e-10 * scale:
            break
        S = c.bp * M + K + mu * (c.gp**2 * M + K)
        J = np.block([[S, d[:, None]], [d[None, :], np.zeros((1, 1))]])
        x = -np.linalg.solve(J, R)
        X[:, F] += np.multiply.outer(c.w, x[:-1])
        mu += x[-1]
    else:
        raise nsga.StepFailure("energy bound", float(np.linalg.norm(R)))
    return s._replace(q=X[0], v=X[1], vd=X[2], a=X[3], S=None, Gb=None)


SCHEMES = {"generalized-α": None, "GEMM": gemm_step, "energy bound": bounded_step}


def pendulum(rho_inf, **params):
    sim = case("flexible_pendulum").build(restitution=1.0, **params)
    return sim.replace(options=dataclasses.replace(sim.options, rho_inf=rho_inf))


def run(item):
    """(kind, scheme, ρ∞, strip changes, t_end, h) → the trace, with the scheme's smooth
    step (put back afterwards: the worker processes run the items one after another)."""
    _, scheme, rho_inf, params, t_end, h = item
    original = nsga.alpha_smooth_step
    if SCHEMES[scheme] is not None:
        nsga.alpha_smooth_step = SCHEMES[scheme]
    try:
        r = trace(pendulum(rho_inf, **params), dt=h, t_end=t_end, abort=runaway())
    finally:
        nsga.alpha_smooth_step = original
    return {k: r[k] for k in ("t", "total", "kinetic", "tip_x", "tip_y", "status")}


def rows(items, done):
    """The three tables' rows from the runs (module docstring)."""
    flight, strips, loss = [], [], []
    ref = next(r for (kind, *_), r in zip(items, done, strict=True) if kind == "reference")
    for (kind, scheme, rho, params, _, _), r in zip(items, done, strict=True):
        E, K = r["total"], r["kinetic"]
        change = 100 * (E[-1] - E[0]) / K.max()
        if kind == "flight":
            flight.append({"scheme": scheme, "ρ∞": rho, "energy change (% of peak KE)": change})
        elif kind == "strip":
            end = "completed" if r["status"] == "completed" else f"diverged at {r['t'][-1]:.3g} s"
            name = ", ".join(f"{k} = {v:g}" for k, v in params.items()) or "nominal"
            strips.append({"scheme": scheme, "strip": name, "result": end})
        else:
            tip = np.hypot(
                np.interp(ref["t"], r["t"], r["tip_x"]) - ref["tip_x"],
                np.interp(ref["t"], r["t"], r["tip_y"]) - ref["tip_y"],
            )
            name = scheme if kind == "loss" else f"{scheme} at h/8"
            loss.append(
                {
                    "scheme": name,
                    "status": r["status"],
                    "energy at 1.5 s (% of peak KE)": change,
                    "tip off the h/8 run (mm)": 1e3 * tip.max(),
                }
            )
    return flight, strips, loss


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--workers", type=int, default=1, help="local worker processes (Dask)")
    args = p.parse_args()
    t_long = 0.05 if args.quick else 3.0
    t_flight, t_loss = (0.05, 0.05) if args.quick else (0.3, 1.5)
    strips = PERTURBED[:1] if args.quick else PERTURBED
    items = [("flight", s, rho, {}, t_flight, 1e-3) for s in SCHEMES for rho in (1.0, 0.8)]
    items += [("strip", s, 0.8, params, t_long, 1e-3) for s in SCHEMES for params in strips]
    items += [("loss", s, 0.8, {}, t_loss, 1e-3) for s in SCHEMES]
    items += [("reference", "generalized-α", 0.8, {}, t_loss, 1.25e-4)]
    done = map_runs(run, items, args.workers, label=lambda x: " ".join(map(str, x[:5])))
    flight, strip_rows, loss_rows = rows(items, done)
    text = report(
        "Energy-controlling smooth steps on the flexible pendulum (e_N = 1, h = 1e-3 s)",
        (f"Free flight to {t_flight:g} s (the first impact is at 0.33 s):", flight),
        (
            f"ρ∞ = 0.8, {t_long:g} s, the strip changed by about 1 % ('diverged': the energy "
            "passed half the peak kinetic energy):",
            strip_rows,
        ),
        (f"ρ∞ = 0.8, nominal strip, {t_loss:g} s (1.5 s: three impacts):", loss_rows),
    )
    name = "energy_schemes_quick.md" if args.quick else "energy_schemes.md"
    print(write_markdown(f"{args.out}/{name}", text))


if __name__ == "__main__":
    main()
