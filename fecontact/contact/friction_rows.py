"""The slip rows of a contact set: tangents, slips and the output of friction, gathered over
the pairs that have it (a base of :class:`fecontact.contact.ContactSet`)."""

from __future__ import annotations

import numpy as np

__all__ = ["FrictionRows"]


class FrictionRows:
    """Slip rows of the frictional pairs of a contact set; the set provides ``pairs``,
    ``owner`` and ``local`` (each contact's pair and its number there), the same of its
    evaluation ``units`` (``unit_owner``, ``unit_local``: pairs alone or several of one
    kind together), ``free_index``, ``n_free``, ``size`` and ``moving`` (whether an
    obstacle moves)."""

    def _frictional(self, select: np.ndarray, units: bool = True):
        """(unit or pair, rows of ``select``, its own numbers of them) of the units (or the
        pairs) with friction among the contacts ``select``."""
        if units:
            owner, local, parts = self.unit_owner[select], self.unit_local, self.units
        else:
            owner, local, parts = self.owner[select], self.local, self.pairs
        for i, pair in enumerate(parts):
            rows = np.flatnonzero(owner == i)
            if rows.size and pair.friction:
                yield pair, rows, local[select[rows]]

    def tangent_jacobian(self, q: np.ndarray, select: np.ndarray):
        """Slip rows of the contacts ``select``: GT (len(select), nt, n_free), zero for the
        frictionless pairs, and the unit tangents T (len(select), nt, d) of the contact
        planes (both zero for a frictionless pair; None where no pair of the set has friction).
        The slip rate of contact j is GT_j v minus T_j·ḋ of a moving obstacle."""
        GT = T = None
        for pair, rows, loc in self._frictional(select):
            dofs, Gv, Tv = pair.tangent_rows(q, loc)
            if GT is None:
                nt, d = Tv.shape[1:]
                GT, T = np.zeros((len(select), nt, self.n_free)), np.zeros((len(select), nt, d))
            fi = self.free_index[dofs]
            values = np.where(fi[:, None, :] >= 0, Gv, 0.0)
            r = np.broadcast_to(rows[:, None, None], values.shape)
            c = np.broadcast_to(np.maximum(fi, 0)[:, None, :], values.shape)
            np.add.at(GT, (r, np.arange(values.shape[1])[None, :, None], c), values)
            T[rows] = Tv
        if GT is None and self.frictional:
            # none of ``select`` has friction, but the set does: the callers' arrays still
            # need their shape (a frictionless pair's rows, released)
            _, Gv, Tv = next(p for p in self.pairs if p.friction).tangents(q)
            GT = np.zeros((len(select), Gv.shape[1], self.n_free))
            T = np.zeros((len(select), *Tv.shape[1:]))
        return GT, T

    def slips(self, q, q_n, select, GT, T):
        """Slip of the contacts ``select`` over a step from q_n to q (len(select), nt): the
        linear G_T(q)(q − q_n) (GT, T from :meth:`tangent_jacobian`), exact where the pairs
        give it (points of rotating bodies)."""
        slip = GT @ (q - q_n)[self.free_index >= 0]
        for pair, rows, loc in self._frictional(select):
            exact = pair.slip_rows(q, q_n, T[rows], loc)
            if exact is not None:
                slip[rows] = exact
        return slip

    def tangent_force(self, q, select, mult, status, n: int):
        """Σ_j G_T,jᵀ mult_j (n,) over ``select`` on all n dofs (``mult`` (len, nt), the
        tangential impulses), and per dof the largest ``status`` of the contacts acting on it
        (1 stick, 2 slip), for the output of nodal friction."""
        f, flag = np.zeros(n), np.zeros(n)
        # pair by pair: each pair's forces summed into f in the order of the pairs
        for pair, rows, loc in self._frictional(select, units=False):
            dofs, GT, _ = pair.tangents(q)
            dofs = np.broadcast_to(dofs, (pair.size, dofs.shape[1]))[loc]
            values = np.einsum("mt,mtk->mk", mult[rows], GT[loc])
            f += np.bincount(dofs.ravel(), values.ravel(), minlength=n)
            acts = np.abs(GT[loc]).sum(axis=1) > 0.0
            s = np.broadcast_to(status[rows, None], dofs.shape)
            np.maximum.at(flag, dofs[acts], s[acts])
        return f, flag

    def obstacle_motion(self, select: np.ndarray, velocity: bool):
        """Velocity ḋ (m/s, ``velocity``) or displacement d (m) of the obstacle of each
        contact ``select`` at its current time, (len(select), d), zero for bodies and fixed
        obstacles; None when no obstacle moves. A moving obstacle drags the slip, which counts
        relative to it."""
        if not self.moving:  # (decided with the set: no pair to ask)
            return None
        out, offset = None, 0
        for pair in self.pairs:
            o = pair.obstacle
            if o is not None and o.moving:
                d = o.speed() if velocity else np.asarray(o.shift(), dtype=float)
                if out is None:
                    out = np.zeros((self.size, len(d)))
                out[offset : offset + pair.size] = d
            offset += pair.size
        return None if out is None else out[select]
