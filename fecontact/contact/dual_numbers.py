r"""Second-order forward differentiation over a batch: values with their gradient and Hessian.

A :class:`Jet` holds a batch of scalars f (B,) that depend on n local variables z, with their
gradients ∂f/∂z (B, n) and, unless built without, their Hessians ∂²f/∂z² (B, n, n). The
arithmetic propagates them by the chain rule,

    (ab)'' = a'' b + a b'' + a' b'ᵀ + b' a'ᵀ,   φ(a)'' = φ'(a) a'' + φ''(a) a' a'ᵀ,

exactly (to round-off), so that a geometric quantity written once as a formula — a mortar
weighted gap with its projections and normals — comes with its exact derivatives. Without
Hessians (``hessian=False``) it costs about n times the plain evaluation.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Jet"]


class Jet:
    """Values v (B,), gradients g (B, n) and Hessians h (B, n, n) or None (first order)."""

    __slots__ = ("g", "h", "v")

    def __init__(self, v, g, h):
        self.v, self.g, self.h = v, g, h

    @classmethod
    def variables(cls, z: np.ndarray, hessian: bool = True) -> list[Jet]:
        """The n columns of z (B, n) as independent variables."""
        B, n = z.shape
        eye = np.eye(n)
        h = np.zeros((B, n, n)) if hessian else None
        return [cls(z[:, i], np.broadcast_to(eye[i], (B, n)), h) for i in range(n)]

    def constant_like(self, c) -> Jet:
        """A value c (scalar or (B,)) with zero derivatives, on the same batch."""
        v = np.broadcast_to(np.asarray(c, dtype=float), self.v.shape).copy()
        return Jet(v, np.zeros_like(self.g), None if self.h is None else np.zeros_like(self.h))

    def _lift(self, other) -> Jet:
        return other if isinstance(other, Jet) else self.constant_like(other)

    def __add__(self, other) -> Jet:
        if not isinstance(other, Jet):
            return Jet(self.v + other, self.g, self.h)
        h = None if self.h is None else self.h + other.h
        return Jet(self.v + other.v, self.g + other.g, h)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet(-self.v, -self.g, None if self.h is None else -self.h)

    def __sub__(self, other) -> Jet:
        return self + (-other)

    def __rsub__(self, other) -> Jet:
        return (-self) + other

    def __mul__(self, other) -> Jet:
        if not isinstance(other, Jet):
            c = np.asarray(other, dtype=float)
            cg = c[..., None] if c.ndim else c
            h = None if self.h is None else self.h * (cg[..., None] if c.ndim else c)
            return Jet(self.v * c, self.g * cg, h)
        a, b = self, other
        g = a.g * b.v[:, None] + b.g * a.v[:, None]
        h = None
        if a.h is not None:
            ab = a.g[:, :, None] * b.g[:, None, :]
            h = a.h * b.v[:, None, None] + b.h * a.v[:, None, None] + ab + ab.transpose(0, 2, 1)
        return Jet(a.v * b.v, g, h)

    __rmul__ = __mul__

    def _unary(self, f, df, d2f) -> Jet:
        g = self.g * df[:, None]
        h = None
        if self.h is not None:
            h = self.h * df[:, None, None] + d2f[:, None, None] * (
                self.g[:, :, None] * self.g[:, None, :]
            )
        return Jet(f, g, h)

    def reciprocal(self) -> Jet:
        r = 1.0 / self.v
        return self._unary(r, -(r**2), 2.0 * r**3)

    def __truediv__(self, other) -> Jet:
        if not isinstance(other, Jet):
            return self * (1.0 / np.asarray(other, dtype=float))
        return self * other.reciprocal()

    def __rtruediv__(self, other) -> Jet:
        return self.reciprocal() * other

    def sqrt(self) -> Jet:
        s = np.sqrt(self.v)
        return self._unary(s, 0.5 / s, -0.25 / (s * self.v))

    def where(self, mask: np.ndarray, other) -> Jet:
        """This jet where ``mask`` (B,), ``other`` elsewhere."""
        o = self._lift(other)
        g = np.where(mask[:, None], self.g, o.g)
        h = None if self.h is None else np.where(mask[:, None, None], self.h, o.h)
        return Jet(np.where(mask, self.v, o.v), g, h)

    def take(self, index) -> Jet:
        """The batch entries ``index``."""
        return Jet(self.v[index], self.g[index], None if self.h is None else self.h[index])

    def repeat(self, r: int) -> Jet:
        """Each batch entry r times in a row (B r,)."""
        rep = np.repeat
        h = None if self.h is None else rep(self.h, r, axis=0)
        return Jet(rep(self.v, r), rep(self.g, r, axis=0), h)
