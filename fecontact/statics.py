"""Static equilibrium by Newton's method with load stepping: f_int(q) = λ f, λ: 0 → 1."""

from __future__ import annotations

import numpy as np

from .errors import SolverError
from .linalg import factorize

__all__ = ["solve_static"]


def solve_static(
    model, load: np.ndarray, steps: int = 10, tol: float = 1e-10, max_iterations: int = 30
) -> np.ndarray:
    """Displacements (full dof vector) in equilibrium with the nodal ``load`` (N, N·m).

    The load is applied in ``steps`` equal increments, each solved by Newton's method to a
    relative residual ``tol``; contacts and gravity are ignored. Raises ``SolverError`` if an
    increment does not converge.
    """
    F = model.free
    q = np.zeros(model.n)
    scale = max(np.linalg.norm(load[F]), 1e-300)
    for lam in np.linspace(0.0, 1.0, steps + 1)[1:]:
        for it in range(max_iterations + 1):
            _, f, K = model.internal(q)
            r = f[F] - lam * load[F]
            if np.linalg.norm(r) <= tol * scale:
                break
            if it == max_iterations:
                raise SolverError(
                    f"static Newton did not converge at load factor {lam:.3g}",
                    residual=float(np.linalg.norm(r) / scale),
                )
            q[F] -= factorize(K, symmetric=True)(r)
    return q
