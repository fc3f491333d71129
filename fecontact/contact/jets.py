r"""Second-order forward differentiation of small vectorised formulas: each quantity carries its
value, gradient and Hessian with respect to n local variables, for m independent instances at
once (a value of shape (m, *s), a gradient (m, *s, n), a Hessian (m, *s, n, n)).

Used where a gap is a composition of a dozen elementary steps (norms, quotients, projections,
clamps and smooth blends) whose hand-derived curvature would be longer than the formula and no
easier to check: the product, quotient and chain rules below are exact, so the derivatives are
those of the formula to round-off (checked against central differences by the tests of the pairs
that use it).
"""

from __future__ import annotations

import numpy as np

__all__ = ["Jet", "dot", "variables"]


class Jet:
    """A value (m, *s) with its gradient (m, *s, n) and Hessian (m, *s, n, n); s is () for a
    scalar, (3,) for a vector. Arithmetic broadcasts as numpy does over the value's axes."""

    def __init__(self, val, grad, hess):
        self.val, self.grad, self.hess = val, grad, hess

    def __add__(self, other):
        if not isinstance(other, Jet):
            return Jet(self.val + other, self.grad, self.hess)
        return Jet(self.val + other.val, self.grad + other.grad, self.hess + other.hess)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.val, -self.grad, -self.hess)

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, Jet):
            other = np.asarray(other, dtype=float)
            return Jet(self.val * other, self.grad * other[..., None],
                       self.hess * other[..., None, None])  # fmt: skip
        f, g = self, other
        outer = f.grad[..., :, None] * g.grad[..., None, :]
        return Jet(
            f.val * g.val,
            f.val[..., None] * g.grad + g.val[..., None] * f.grad,
            f.val[..., None, None] * g.hess + g.val[..., None, None] * f.hess
            + outer + np.swapaxes(outer, -1, -2),
        )  # fmt: skip

    __rmul__ = __mul__

    def __truediv__(self, other):
        if not isinstance(other, Jet):
            return self * (1.0 / np.asarray(other, dtype=float))
        return self * other.apply(1.0 / other.val, -1.0 / other.val**2, 2.0 / other.val**3)

    def apply(self, value, first, second):
        """φ(self) for a scalar function φ given its value, first and second derivative at
        self's value (arrays of the value's shape): the chain rule."""
        return Jet(
            value,
            first[..., None] * self.grad,
            first[..., None, None] * self.hess
            + second[..., None, None] * self.grad[..., :, None] * self.grad[..., None, :],
        )

    def sqrt(self):
        s = np.sqrt(self.val)
        return self.apply(s, 0.5 / s, -0.25 / s**3)

    def column(self, i: int):
        """Component i of a vector jet: a scalar jet (m,)."""
        return Jet(self.val[:, i], self.grad[:, i], self.hess[:, i])

    def scalar(self):
        """A scalar jet as a vector's factor: shapes (m, 1, ...) broadcasting over (m, 3)."""
        return Jet(self.val[:, None], self.grad[:, None], self.hess[:, None])


def dot(u: Jet, v: Jet) -> Jet:
    """u·v (m,) of two vector jets (m, 3)."""
    p = u * v
    return Jet(p.val.sum(axis=1), p.grad.sum(axis=1), p.hess.sum(axis=1))


def variables(values, n: int) -> list[Jet]:
    """The jets of independent vector variables ``values`` (each (m, 3)), numbered in order
    over n local variables."""
    out, start = [], 0
    m = len(values[0])
    for v in values:
        grad = np.zeros((m, 3, n))
        grad[:, np.arange(3), start + np.arange(3)] = 1.0
        out.append(Jet(np.asarray(v, dtype=float), grad, np.zeros((m, 3, n, n))))
        start += 3
    return out
