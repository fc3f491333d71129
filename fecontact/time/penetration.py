"""The penetration a step leaves: measured at the end of every step, and a step that ends with
a point deeper than the constraints allow is taken again, smaller.

The depth is that of :meth:`fecontact.contact.ContactSet.penetration`: a solid's nodes
against the other solid's discretized boundary by an inside/outside test, the signed
distance of the other pairs. With positions held at the position level (Signorini, the NSGA
steppers) a node-to-surface or obstacle contact allows round-off only: the position
correction ends with every candidate's gap ≥ −tol_gap × the length scale. A deeper point is
one that no constraint saw — it crossed a facet that was not its closest, or it was not a
candidate — and the step is failed so that the time loop halves it. Velocity-level steppers
(Moreau–Jean) and the penalty law allow penetration by design: their depth is measured only.

A mortar interface holds its weighted gaps to round-off (they count with the gaps above); the
depth of its nodes, every boundary node of either solid against the other's boundary
(:mod:`fecontact.contact.watch`), is measured and reported in ``State.penetration``, and at the
predictor a node deeper than ``DEEPEST`` fails the step as for the other solids (two disks
closing faster than the search reaches: without it they passed through each other).
"""

from __future__ import annotations

import time

import numpy as np

from ..contact.watch import entering, entry_depth, held_nodes, watched_depth
from .constraints import StepFailure
from .state import IntegratorOptions, PhaseTimer, State, length_scale

__all__ = ["DEEPEST", "PenetrationFailure", "ROUND_OFF", "check_predictor", "hold_penetration"]

DEEPEST = 0.05
"""Deepest a node may enter another solid in the predictor of a step (−g, the gap from the
plane of the closest facet, which the correction undoes), over the size of that facet.
Deeper, the closest facet may no longer be the one it crossed (the correction would push the
node out on the far side), and the correction, which moves the nodes and not the bodies'
momentum, stores strain energy growing with the depth squared: two rubber disks at 5 m/s and
4 Δx/c gain 15 % of their energy with the bound at 1/4 facet, 2.6 % at 1/10 and none at 1/20
(docs/explanation/contact_search.md). The step is halved instead."""

ROUND_OFF = 4.0
"""Allowed depth in units of the gap tolerance tol_gap × length scale: the correction's own
tolerance, with room for the plane gap and the distance to the facet to differ in their last
bits."""


class PenetrationFailure(StepFailure):
    """A step ended with a point deeper inside another body than the constraints allow."""


def hold_penetration(model, st: State, opts: IntegratorOptions, timer: PhaseTimer) -> State:
    """Record the deepest penetration at the end of step ``st`` (``st.penetration``, m) and
    fail the step (``PenetrationFailure``) when a position-level stepper left it beyond the
    round-off the constraints allow. ``opts``: the run's settings
    (:class:`~fecontact.time.settings.RunSettings`). Where pairs test nodes inside another
    solid or mortar interfaces are watched, its time counts in the ``contact`` phase (else it
    is a minimum over the gaps, cheaper than its timer)."""
    if model.contacts.size == 0:
        return st
    nsga = opts.integrator == "nsga"
    if not opts.depth_check:  # signed distances only (decided once per run)
        # an NSGA step that made no correction and held no contact by a smooth force knows
        # every gap is ≥ 0 (``State.outside``)
        depth = 0.0 if nsga and st.outside else model.contacts.penetration(st.q, st.gaps)
        st.penetration, st.mortar_depth = depth, 0.0
    else:
        clock = time.perf_counter()
        depth = model.contacts.penetration(st.q, st.gaps)
        # the mortar interfaces' nodes: measured and reported, not held (contact.watch)
        watched = st.mortar_depth = 0.0
        if model.contacts.watches:
            watched, st.mortar_depth = watched_depth(model.contacts.watches, st.q)
            st.mortar_held = held_nodes(model.contacts.pairs, st.q)
        st.penetration = max(depth, watched)
        timer.add("contact", clock)
    # (the allowed depth is at least its value at the model size, which length_scale is at
    # least: below that, the coordinates' extent is not needed to decide)
    if not nsga or depth <= ROUND_OFF * opts.tol_gap * model.length:
        return st
    allowed = ROUND_OFF * opts.tol_gap * length_scale(model, st.q)
    if depth > allowed:
        raise PenetrationFailure(
            f"a contact point ends {depth:.3e} m on the wrong side (allowed {allowed:.1e} m)",
            depth,
        )
    return st


def check_predictor(model, q, gaps, q_start=None) -> None:
    """Fail the step (``PenetrationFailure``) when a node of a solid lies deeper inside another
    solid at the predictor q (−g, ``gaps`` every contact's g at q) than ``DEEPEST`` of the
    facet closest to it (per node, so that a graded surface's finest cells elsewhere do not
    set the step: the facet's longest edge for node-to-surface pairs, its shortest for the
    nodes of a mortar interface, :meth:`fecontact.contact.watch.SolidWatch.entry`). A mortar
    node is measured by what the step brings in, its depth at the predictor less its depth
    at ``q_start`` (the positions the step starts from): the weighted gaps do not hold a
    node's own depth, and a smaller step cannot take out what a node had at its start."""
    if not model.contacts.size:
        return
    ratio = own = model.contacts.relative_depth(q, gaps)
    watches = model.contacts.watches
    if watches:  # a mortar interface's nodes, which no own gap measures
        ratio = max(ratio, entry_depth(watches, q, q_start))
    if ratio > DEEPEST:
        what = entering(watches, q) if ratio > own else "a node"
        raise PenetrationFailure(
            f"{what} enters another body {ratio:.2f} facet lengths deep in one step", np.nan
        )
