r"""Second-order forward differentiation over a batch: values with their gradient and Hessian.

A :class:`Jet` holds a batch of scalars f (B,) that depend on n local variables z, with their
gradients ∂f/∂z (B, n) and, unless built without, their Hessians ∂²f/∂z² (B, n, n). The
arithmetic propagates them by the chain rule,

    (ab)'' = a'' b + a b'' + a' b'ᵀ + b' a'ᵀ,   φ(a)'' = φ'(a) a'' + φ''(a) a' a'ᵀ,

exactly (to round-off), so that a geometric quantity written once as a formula — a mortar
weighted gap with its projections and normals — comes with its exact derivatives. Without
Hessians (``hessian=False``) it costs about n times the plain evaluation; values alone
(``hessian=None``) carry no derivatives and cost one array operation per operation.

A jet affine in z (the variables, their sums and multiples: coordinate differences) has a
Hessian that is exactly zero; it is marked ``flat`` and its zero Hessian never enters a
product or a function, which leaves the result bit for bit the same (adding exact zeros)
and saves the array operations of the terms that vanish: the small batches of a mortar
interface cost per operation, not per number.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Jet"]


class Jet:
    """Values v (B,), gradients g (B, n) or None (values only) and Hessians h (B, n, n) or
    None (first order, or values only); ``flat``: h is exactly zero (an affine jet)."""

    __slots__ = ("flat", "g", "h", "v")

    def __init__(self, v, g, h, flat: bool = False):
        self.v, self.g, self.h, self.flat = v, g, h, flat

    @classmethod
    def variables(cls, z: np.ndarray, hessian: bool | None = True) -> list[Jet]:
        """The n columns of z (B, n) as independent variables (``hessian`` None: values
        only, False: gradients, True: gradients and Hessians)."""
        B, n = z.shape
        if hessian is None:
            return [cls(z[:, i], None, None) for i in range(n)]
        eye = np.eye(n)
        h = np.zeros((B, n, n)) if hessian else None  # shared: a zero Hessian is never written
        return [cls(z[:, i], np.broadcast_to(eye[i], (B, n)), h, True) for i in range(n)]

    def constant_like(self, c) -> Jet:
        """A value c (scalar or (B,)) with zero derivatives, on the same batch."""
        v = np.broadcast_to(np.asarray(c, dtype=float), self.v.shape).copy()
        if self.g is None:
            return Jet(v, None, None)
        h = None if self.h is None else np.zeros_like(self.h)
        return Jet(v, np.zeros_like(self.g), h, True)

    def _lift(self, other) -> Jet:
        return other if isinstance(other, Jet) else self.constant_like(other)

    def __add__(self, other) -> Jet:
        if not isinstance(other, Jet):
            return Jet(self.v + other, self.g, self.h, self.flat)
        if self.g is None:
            return Jet(self.v + other.v, None, None)
        h = None if self.h is None else _sum(self, other.h, other.flat)
        return Jet(self.v + other.v, self.g + other.g, h, self.flat and other.flat)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        if self.g is None:
            return Jet(-self.v, None, None)
        h = None if self.h is None else (self.h if self.flat else -self.h)
        return Jet(-self.v, -self.g, h, self.flat)

    def __sub__(self, other) -> Jet:
        if not isinstance(other, Jet):
            return Jet(self.v - other, self.g, self.h, self.flat)
        if self.g is None:
            return Jet(self.v - other.v, None, None)
        h = None
        if self.h is not None:
            h = _sum(self, other.h if other.flat else -other.h, other.flat)
        return Jet(self.v - other.v, self.g - other.g, h, self.flat and other.flat)

    def __rsub__(self, other) -> Jet:
        return (-self) + other

    def __mul__(self, other) -> Jet:
        if not isinstance(other, Jet):
            c = np.asarray(other, dtype=float)
            if self.g is None:
                return Jet(self.v * c, None, None)
            cg = c[..., None] if c.ndim else c
            h = self.h
            if h is not None and not self.flat:
                h = h * (cg[..., None] if c.ndim else c)
            return Jet(self.v * c, self.g * cg, h, self.flat)
        a, b = self, other
        if a.g is None:
            return Jet(a.v * b.v, None, None)
        av, bv = a.v[:, None], b.v[:, None]
        g = a.g * bv + b.g * av
        h = None
        if a.h is not None:
            outer = a.g[:, :, None] * b.g[:, None, :]
            h = outer + outer.transpose(0, 2, 1)
            if not a.flat:
                h += a.h * bv[:, :, None]
            if not b.flat:
                h += b.h * av[:, :, None]
        return Jet(a.v * b.v, g, h)

    __rmul__ = __mul__

    def _unary(self, f, df, d2f) -> Jet:
        if self.g is None:
            return Jet(f, None, None)
        g = self.g * df[:, None]
        h = None
        if self.h is not None:
            h = self.g[:, :, None] * (self.g * d2f[:, None])[:, None, :]
            if not self.flat:
                h += self.h * df[:, None, None]
        return Jet(f, g, h)

    def reciprocal(self) -> Jet:
        r = 1.0 / self.v
        if self.g is None:
            return Jet(r, None, None)
        return self._unary(r, -(r**2), 2.0 * r**3)

    def __truediv__(self, other) -> Jet:
        if not isinstance(other, Jet):
            return self * (1.0 / np.asarray(other, dtype=float))
        if self.g is None:
            return Jet(self.v / other.v, None, None)
        out = self * other.reciprocal()
        out.v = self.v / other.v  # the value as the values-only mode has it, to the last bit
        return out

    def __rtruediv__(self, other) -> Jet:
        return self.reciprocal() * other

    def sqrt(self) -> Jet:
        s = np.sqrt(self.v)
        if self.g is None:
            return Jet(s, None, None)
        return self._unary(s, 0.5 / s, -0.25 / (s * self.v))

    def where(self, mask: np.ndarray, other) -> Jet:
        """This jet where ``mask`` (B,), ``other`` elsewhere."""
        o = self._lift(other)
        v = np.where(mask, self.v, o.v)
        if self.g is None:
            return Jet(v, None, None)
        g = np.where(mask[:, None], self.g, o.g)
        flat = self.flat and o.flat
        h = self.h
        if h is not None and not flat:
            h = np.where(mask[:, None, None], self.h, o.h)
        return Jet(v, g, h, flat)

    def take(self, index) -> Jet:
        """The batch entries ``index``."""
        g = None if self.g is None else self.g[index]
        return Jet(self.v[index], g, None if self.h is None else self.h[index], self.flat)

    def repeat(self, r: int) -> Jet:
        """Each batch entry r times in a row (B r,)."""
        rep = np.repeat
        g = None if self.g is None else rep(self.g, r, axis=0)
        h = None if self.h is None else rep(self.h, r, axis=0)
        return Jet(rep(self.v, r), g, h, self.flat)


def _sum(a: Jet, h: np.ndarray, flat: bool) -> np.ndarray:
    """a.h + h, where ``flat`` says h is zero (a.h itself when both are: the shared zeros)."""
    if flat:
        return a.h
    return h if a.flat else a.h + h
