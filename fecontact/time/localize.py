r"""Impacts at their own instant: a step in which a gap open at its start closes is split at
the instant t* it closes.

The NSGA step applies an impact at the end of the step in which the gap closed, which makes
the global error first order in h. Here, after the step's smooth step (the trial, from
(q_n, v_n) to (q̃, ṽ)), every contact open at t_n (g > tol) whose gap at q̃ is below −tol
is a crossing. Its instant is first read from the cubic Hermite interpolant of g on
s = (t − t_n)/h ∈ [0, 1] with the end values g_0, g_1 and slopes h ġ_0, h ġ_1, ġ = G v:

    g(s) = (2s³ − 3s² + 1) g_0 + (s³ − 2s² + s) h ġ_0 + (−2s³ + 3s²) g_1 + (s³ − s²) h ġ_1,

then refined by smooth steps from t_n to δ (regula falsi, Illinois variant, on the gap at
the end of each) until 0 ≤ g(t_n + δ) ≤ tol, aimed at tol/2 (the interpolant's root too): the
gap is closed within its tolerance on its open side, so no position correction (and no
factorization of its metric) is needed. The last of them is the smooth step of a step of
δ: its corrections apply the impact law with the gap closed (Newton's or Poisson's, the
NSGA's own phases), and the rest of the step starts from there, where a later closing may
be located in turn; its smooth step, the impact's elastic response, is solved by modified
Newton (S_t's factors kept while the residual falls: one factorization where full Newton
made about three on the Neo-Hookean disk). Of several crossings the earliest is taken, with
those that close within ``TOGETHER`` of the step after it (the correction closes them with
it).

The step is left to the end-of-step treatment, counted by reason in the run's statistics:
``accumulation`` (``MAX_IMPACTS`` impacts already located in the step, less than ``MIN_REST``
of it left, or, beside a pressed contact or after an impact, more instants to locate than
it may), ``persistent`` (a contact pressed at the start of the step is still closed at its
end: a lasting contact that other points join), ``grazing`` (the gap
closes slower than ``GRAZING`` gap tolerances per step), ``unrefined`` (no instant found
to the tolerance within ``MAX_REFINE`` smooth steps, or a gap unknown at the step's start)
and ``failed`` (a smooth step of the split did not converge: the step is taken whole).
Positions stay held at every sub-step, so no penetration follows from a split.

Undamped solids (:func:`undamped_solids`) locate the closings beside a pressed
contact too (the later rings of a contact patch): left to the step's end, a point that
entered by about −ġ(1 − τ)h is pushed out by the correction, whose strain is energy the
impact did not have (the ball at 10 m/s: 0.343 J of strain against 0.087 J of kinetic
energy taken by the jump, 1.06 % of the run's scale created in one step). With friction,
the contacts pressed within the last ``CHATTER_WINDOW`` steps (``lasting``, from
:class:`~.substeps.Releases`) re-close at the step's end (counted ``persistent``).

Flexible bodies' chattering contacts and the release read aside for solids take these
steps in sub-steps (:mod:`fecontact.time.substeps`).

Linear models factorize their iteration matrix once per step size: the split steps' sizes
are used once, so their solvers (and the correction's columns) are dropped after the step;
the full step's are kept. An undamped sparse one solves them from the factors it keeps on a
ladder of sizes, or from its eigendecomposition (:mod:`fecontact.linalg.ladder`), counted
in ``localization_cost`` with the factorizations made for them.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..contact.mortar_safeguard import pointwise_row, real_gaps
from ..errors import InputError
from ..ledger_records import JoinedRecord
from .constraints import StepFailure
from .crossings import closings
from .dips import may_dip, near_dips, with_dips
from .nsga import smooth_phases
from .settings import RunSettings
from .state import PhaseTimer, State, deferred_ledger, length_scale
from .terms import SmoothContact
from .window import instants, last_together

__all__ = [
    "FRICTIONAL_SOLIDS",
    "GRAZING",
    "MAX_IMPACTS",
    "MIN_REST",
    "TOGETHER",
    "joined",
    "undamped_solids",
    "localized_step",
    "cache_keys",
    "drop_caches",
]

FRICTIONAL_SOLIDS = True
"""Whether "auto" localizes undamped frictional solids (:func:`undamped_solids`). On: the
end-of-step closing created 5.4e-2 of the scale on the struck block on its frictional floor,
2.66e-2 for the rigid box corner first on a slab (μ = 0.3), 1.11e-3 for ``disk_drop`` with
μ = 0.3; located 0 to round-off. A tumbling block landing on corners in space departs from itself by
up to 1e-4 m under a 1e-14 change of its initial velocity (a located impact sets the phase of
its ringing): its twin on a fixed box is held to that (docs/validation/localization.md)."""

MAX_IMPACTS = 4
"""Impacts located in one step, at most (K): more is an accumulation (Zeno)."""

MIN_REST = 1e-3
"""Fraction of the step below which what is left of it after an impact takes a closing at
its end (an accumulation: the rebound is shorter than this)."""

TOGETHER = 1e-4
"""Fraction of the step within which later closings are taken with the earliest: the
correction closes them at its instant (a flat face landing flat closes all its corners at
once, up to round-off)."""

GRAZING = 1e3
"""A closing speed −ġ(t*) below this many gap tolerances per step is grazing."""

MAX_REFINE = 12
"""Smooth steps that refine an instant, at most (the Hermite guess is exact for a constant
acceleration and the regula falsi converges superlinearly: 1 to 3 are measured)."""

MASS_COLUMNS = ("mass",)
"""The column cache's key of the mass's columns M⁻¹G_jᵀ (no step size in it)."""

LAST = 1e-9
"""Fraction of the step: an impact that closes this near its end ends the step."""


def localizes(model, opts: RunSettings) -> bool:
    """Whether the run of ``model`` with ``opts`` locates impacts inside its steps: the
    option ``localize`` (``"auto"``: a model of rigid bodies and point masses with
    contacts on fixed obstacles or between them, frictionless or not, or of solids,
    :func:`undamped_solids`, frictional ones where ``FRICTIONAL_SOLIDS``, the default) for
    the NSGA generalized-α step (the options check it) on a model with contacts. Raises
    ``InputError`` for ``localize=True`` with moving obstacles."""
    value = opts.localize
    applies = opts.integrator == "nsga" and opts.scheme == "generalized-alpha"
    if value is True and model.contacts.moving:
        raise InputError("localize = true: moving obstacles are not supported (set localize=0)")
    if value == "auto":
        # (measured: docs/validation/localization.md, friction between rigid bodies included)
        rigid = not (model.continuum or model.slender)
        value = rigid and not model.contacts.moving
        solids = undamped_solids(model)
        value = value or (solids and (FRICTIONAL_SOLIDS or not model.contacts.frictional))
    return bool(value and applies and model.contacts.size)


def undamped_solids(model) -> bool:
    """Whether ``model`` has solids (rigid bodies beside them or not, no beams), undamped, its
    contacts on fixed obstacles or between its bodies, frictionless or not: the models whose
    impacts "auto" localizes in whole steps. A frictional one leaves the re-closing of a
    lasting contact's nodes to the step's end (:class:`~.substeps.Releases`; located too, the
    struck block on its floor took 34 impacts for 14 and 1.4 × the CPU, and created 0 either
    way). Not Rayleigh damping (a damped block's located landing rebounds faster than it
    hit)."""
    solids = model.continuum and not model.slender  # (a rigid box on a slab: 12.4 % → 0)
    contacts = model.contacts
    undamped = not any(model.damping)
    return bool(contacts.size) and solids and undamped and not contacts.moving


def localized_step(
    model, st: State, h: float, opts: RunSettings, timer: PhaseTimer, lasting=None
) -> State:
    """The NSGA step from ``st`` over ``h`` (s), split at the instants the gaps open at its
    start close (module docstring); a step without a closing is the NSGA step itself. The
    contacts ``lasting`` (a mask, or None) are not located: their closing is left to the
    step's end (counted ``persistent``)."""
    phases = smooth_phases(model, st, h, opts, timer)
    # (most steps end here: the gaps at q̃, which the correction takes as they are, all
    # above −tol_gap × the model size, a lower bound of the gap tolerance; the obstacles
    # are fixed, localizes(): no set_time; argmin, not min: a third of the time on a few
    # contacts, where this test is most of what localization adds to a step)
    g1 = phases.g_tilde = model.contacts.gaps(phases.q)
    least = g1[g1.argmin()] if g1.size else math.inf
    if least >= -opts.tol_gap * model.length:
        if not near_dips(model, st, g1, opts, least):  # (closes and opens again: dips.py)
            return phases.finish(time.perf_counter())
    return _split_step(model, st, h, opts, timer, phases, lasting)


def _penetrates(model, phases, opts) -> bool:
    """Whether a gap at the end of the smooth ``phases`` is below −tol_gap × the model size
    (a lower bound of the gap tolerance, :func:`length_scale`); sets the phases' gaps (fixed
    obstacles, :func:`localizes`: no ``set_time``)."""
    g1 = phases.g_tilde = model.contacts.gaps(phases.q)
    return bool(g1.size) and g1.min() < -opts.tol_gap * model.length


def _split_step(model, st, h, opts, timer, phases, lasting) -> State:
    """:func:`localized_step` from its first smooth step ``phases``, which penetrates."""
    stats = opts.stats.localization
    kept: list = []  # the caches' entries of the full step
    before = (stats.impacts, stats.first_closing)
    # the split's sizes are used once: solved from the ladder's factors (linalg.ladder)
    passing, model.passing = model.passing, True
    try:
        parts = _parts(model, st, h, opts, timer, phases, kept, lasting)
    except StepFailure:  # a smooth step of the split failed: the trial, whole (counted)
        stats.fallbacks["failed"] += 1
        stats.impacts, stats.first_closing = before
        model.contacts.look_ahead(st.q, st.v, h)
        parts = None
    finally:
        model.passing = passing
        if kept:
            drop_caches(model, kept, stats)
    if parts is None:  # (or no split: the trial is the step)
        return phases.finish(time.perf_counter())
    out = parts[0]
    for part in parts[1:]:
        # the step's contact phases, for the ledger (made when read)
        part.ledger = JoinedRecord(model, out, part, deferred_ledger(part))
        out = joined(out, part, h)
    out.h = h
    return out


def _parts(model, st, h, opts, timer, phases, kept: list, lasting) -> list[State] | None:
    """The parts of the step of ``h`` from ``st`` whose trial is ``phases``: each ends at a
    located impact, the last at the step's end; None where the trial is not split."""
    stats = opts.stats.localization
    parts: list[State] = []
    cur, left = st, h
    while True:
        if parts:
            phases = _rest_phases(model, cur, left, opts, timer)
        split = _split(model, cur, phases, left, h, len(parts), opts, timer, kept, lasting)
        if split is None:
            if not parts:
                return None
            parts.append(phases.finish(time.perf_counter()))
            return parts
        delta, phases = split
        parts.append(phases.finish(time.perf_counter()))
        stats.impacts += 1
        if stats.first_closing is None:
            stats.first_closing = parts[-1].t
        cur, left = parts[-1], left - delta
        if left <= LAST * h:
            return parts
        model.contacts.look_ahead(cur.q, cur.v, left)


def _rest_phases(model, st, left, opts, timer):
    """The smooth step of the rest of a step after a located impact, from ``st`` over
    ``left`` (s), by modified Newton (:data:`~.acceleration_form.CONTRACTION`): the impact's
    elastic response, about three updates from one factorization of S_t where each full
    Newton update factorized its own. The persistent contacts' multipliers start from the
    forces the restart at the impact carries in v̇ (:attr:`SmoothContact.carried`): the
    contacts it holds are rows from the first update, which on a linear model is then the
    solution (from zero, a free update first let them penetrate and a second held them)."""
    loop = opts.plan.loop(model, opts, timer)
    loop.frozen = True
    terms = [term for term in opts.plan.terms if isinstance(term, SmoothContact)]
    for term in terms:
        term.carried = True
    try:
        return smooth_phases(model, st, left, opts, timer)
    finally:
        loop.frozen = False
        for term in terms:
            term.carried = False


def _split(model, st, phases, left, h, done, opts, timer, kept: list, lasting=None):
    """(δ, the NSGA phases of a step of δ whose smooth step ends where the earliest gap that
    crosses in the trial ``phases`` closes), or None to finish the trial as it is; the first
    split of a step notes in ``kept`` the caches' entries its trial made."""
    crossing = _crossing(model, st, phases, left, opts, lasting)
    if crossing is None:
        return None
    if not kept:
        kept.extend(cache_keys(model, opts.stats.localization))
    tol, rows, tau, rate, g0, jumps, ends = crossing
    reason = None
    # a contact pressed throughout (one pressed was a candidate: none in flight, most impacts)
    beside = st.candidates.size and (st.pressed() & (phases.g_tilde <= tol)).any()
    if done >= MAX_IMPACTS or (done and left < MIN_REST * h):
        reason = "accumulation"
    elif beside and not _locates_beside(model, lasting):
        reason = "persistent"
    elif rows.size == 0:
        reason = "unrefined"
    elif _rings(tau, done, beside, h, left):
        reason = "accumulation"  # (a patch whose rings the step could not all locate)
    else:
        k = last_together(tau, TOGETHER * h / left)
        if -rate[k] * left <= GRAZING * tol:
            reason = "grazing"
    if reason is None:
        guess = (tau[k], g0[k], jumps[k], ends[0][k], ends[1][k])
        found = _refine(model, st, phases, left, rows[k], guess, tol, opts, timer)
        if found is not None:  # (the jump closes the rows taken together: nsga._closed)
            found[1].together = _together(rows, tau, rate, TOGETHER * h / left, h)
            return found
        reason = "unrefined"
    opts.stats.localization.fall_back(reason, phases.g_tilde)
    return None


def _together(rows, tau, rate, window: float, h: float):
    """(rows, reach (m)) of the crossing ``rows`` (instants ``tau``, fractions of the rest of
    the step ``h`` (s), closing speeds ``rate``, m/s) within ``window`` of the earliest, which
    the jump closes with it: each closes by −ġ ``TOGETHER`` h within the window."""
    if rows.size == 1 and tau[0] <= tau[0] + window:  # (one crossing, finite: most impacts)
        return rows, -rate * TOGETHER * h
    t = tau <= tau.min() + window
    return rows[t], -rate[t] * TOGETHER * h


def _locates_beside(model, lasting) -> bool:
    """Whether closings beside a pressed contact are located: undamped solids', a frictional
    one's only where its lasting contacts are known (``lasting``, :class:`~.substeps.Releases`;
    ``localize=1``'s sub-steps leave them to the step's end)."""
    return undamped_solids(model) and (lasting is not None or not model.contacts.frictional)


def _rings(tau: np.ndarray, done: int, beside, h: float, left: float) -> bool:
    """Whether the closings at ``tau`` (fractions of the rest ``left`` of the step ``h``, s),
    beside a pressed contact or after one of the step's ``done`` impacts, close at more
    instants than the step may still locate (a patch's rings: left to its end at once)."""
    return bool((beside or done) and done + instants(tau, TOGETHER * h / left) > MAX_IMPACTS)


def _crossing(model, st, phases, left, opts, lasting=None):
    """(tol, rows, τ, ġ(τ), g_0, jumps, ends) of the contacts open at the start of the trial
    ``phases`` whose gap at its end is below −tol, or (``opts.dips``) dips below it inside
    the step (rows: a gap known at both ends, one per node, τ their Hermite crossing as a
    fraction of ``left``, ġ(τ) their closing speed in m/s, g_0 their gaps at the start,
    jumps: g_0 a placeholder, ends: the fractions and gaps less the aim that close their
    brackets), or None where none crosses; sets g at q̃."""
    contacts = model.contacts
    if phases.g_tilde is None and not _penetrates(model, phases, opts) and not opts.dips:
        return None
    g1 = phases.g_tilde
    g0 = st.gaps if st.gaps.size == contacts.size else contacts.gaps(st.q)
    low = opts.tol_gap * model.length  # a lower bound of tol: decides most steps at no cost
    reach = opts.detection_margin * model.length
    if not ((g1 < -low) & (g0 > low)).any() and not near_dips(model, st, g1, opts):
        return None
    tol = opts.tol_gap * length_scale(model, phases.q)
    closing = (g1 < -tol) & (g0 > tol)
    if lasting is not None and (closing & lasting).any():
        closing &= ~lasting  # (a lasting contact's row re-closing: left to the step's end)
        if not closing.any():
            opts.stats.localization.fall_back("persistent", g1)
            return None
    aim = closing_aim(model, tol)  # (inside the tolerance, on the open side: no correction)
    F = model.free_slice  # (a view where the free dofs are contiguous: no copies)
    found = None
    if closing.any():
        g0, found = closings(contacts, st, phases, left, closing, g0, aim, F)
    if opts.dips:
        near = may_dip(g0, g1, tol, reach) & ~closing
        if lasting is not None:
            near &= ~lasting
        found = with_dips(contacts, st, phases, left, F, near, g0, aim, tol, found)
    if found is None:
        return None
    rows, tau, slope, sloped, ends = found
    return tol, rows, tau, slope / left, g0[rows], ~sloped, ends


def closing_aim(model, tol: float) -> float:
    """The gap (m) a located closing aims at, and half the band [0, 2 aim] it accepts: half
    the gap tolerance ``tol`` (m), inside it on the open side; with friction, scaled from the
    model's size to its smallest body's. A frictional closing's instant is then that of its
    own bodies, not of the model's largest: a block landing on a fixed 1 m box aimed
    4.5e-13 m higher than on the plane of the box's face, and accepted an iterate 1e-12 m
    open that the plane refined further, and the two runs (μ = 0.3) parted by 7e-6 m in the
    plane; scaled, 7.4e-11 m. Frictionless runs keep tol/2 (their references, as measured)."""
    half = 0.5 * tol
    bodies = model.bodies
    if len(bodies) == 1 or not model.contacts.frictional:
        return half
    return half * (min(body.characteristic_length for body in bodies) / model.length)


def _refine(model, st, phases, left, j, guess, tol, opts, timer):
    """(δ, the phases of the smooth step of δ from ``st`` that ends with 0 ≤ g_j ≤ 2 aim, aim
    the :func:`closing_aim` of ``tol``, at most ``tol``):
    regula falsi (Illinois) on g_j − aim over δ ∈ (0, left) from the Hermite ``guess`` (τ,
    g_j at the start, whether g_j jumps from a placeholder), δ = τ·left first; None when
    ``MAX_REFINE`` smooth steps do not find it; a trial reading a placeholder bisects (it
    is no gap), and a row that jumps keeps its closed end (``stress_3d.md``, 63 Δx/c balls)."""
    stats, below = opts.stats.localization, None  # (below: δ and trial on the closed side)
    (tau, g0, jumps, end, g_end), aim = guess, closing_aim(model, tol)  # (0 ≤ g ≤ 2 aim)
    (a, ga), (b, gb) = (0.0, float(g0) - aim), (left * float(end), float(g_end))
    own = np.array([j]) if pointwise_row(model.contacts, j) else None
    read = not jumps  # (whether ga is a gap, not a placeholder's two margins)
    delta, side = float(tau) * left, 0  # (a float: the split's times and sizes are floats)
    for _ in range(MAX_REFINE):
        trial = smooth_phases(model, st, delta, opts, timer)
        stats.smooth_steps += 1
        stats.smooth_iterations += trial.iters["smooth"]
        trial.g_tilde = model.contacts.gaps(trial.q)
        g, real = _trial_gap(model, trial, j, own, aim)
        if abs(g) <= aim:
            return delta, trial
        if not math.isfinite(g):
            return None
        if g > 0.0:
            a, ga, gb = delta, g, (0.5 * gb if side > 0 else gb)
            side, read = 1, real
        else:
            b, gb, ga = delta, g, (0.5 * ga if side < 0 else ga)
            side, below = -1, (delta, trial)
        # a placeholder tells the side, not how far: bisect until the open end reads a gap
        delta = (a * gb - b * ga) / (gb - ga) if read else 0.5 * (a + b)
        if not a < delta < b:
            delta = 0.5 * (a + b)
    return below if jumps else None


def _trial_gap(model, trial, j: int, own, aim: float):
    """(g_j − aim at the ``trial``, whether it is a gap): a pointwise row (``own``: [j]) reads
    its node's real gap (:func:`real_gaps`) where that is known; elsewhere its placeholder,
    two margins whatever the node's depth above half its allowance (not a gap)."""
    g = float(trial.g_tilde[j]) - aim
    if own is None:
        return g, True
    real = float(real_gaps(model.contacts, trial.q, own)[0][0]) - aim
    return (real, True) if math.isfinite(real) else (g, False)


def joined(first: State, second: State, h: float) -> State:
    """``second`` as the end of one step of ``h`` (s) made of ``first`` and ``second``: the
    step's impulses, normal and tangential, iterations, halvings and retakes are the sums of
    theirs, its penetration the deeper, its shortest halved sub-step (``h_least``) the shorter."""
    second.impulse = second.impulse + first.impulse
    if second.friction is not None:  # the step's tangential impulse, as the normal
        second.friction.impulse = first.friction.impulse + second.friction.impulse
    second.iterations = {k: first.iterations[k] + second.iterations[k] for k in first.iterations}
    second.halvings = first.halvings + second.halvings
    second.retakes = first.retakes + second.retakes
    second.turn_halvings = first.turn_halvings + second.turn_halvings
    second.penetration = max(first.penetration, second.penetration)
    halved = [part.h_least for part in (first, second) if part.h_least is not None]
    second.h_least = min(halved) if halved else None
    second.h = h
    return second


def cache_keys(model, stats) -> tuple:
    """The step sizes' entries of a linear model's caches (factorizations, columns), the work
    of its ladder (:meth:`fecontact.linalg.ladder.Ladder.work`) so far and the localization
    ``stats``' counts of it."""
    work = {} if model.ladder is None else model.ladder.work()
    return set(model.iteration_cache), set(model.column_cache), work, _reported(stats)


def _reported(stats) -> dict:
    """The localization ``stats``' counts of the ladder's work, by the ladder's names."""
    return {**stats.ladder, "factorizations": stats.factorizations}


def drop_caches(model, kept, stats) -> None:
    """Drop the caches' entries made since ``kept`` (the split steps' sizes, used once; not
    the mass's columns, which every size shares); count
    in the localization ``stats`` the factorizations made for them and the ladder's solves
    without one (the ladder keeps its factors)."""
    added = [k for k in model.iteration_cache if k not in kept[0]]
    for key in added:
        del model.iteration_cache[key]
    # (the mass's columns M⁻¹G_jᵀ hold at every step size: kept for the run's later jumps)
    for key in [k for k in model.column_cache if k not in kept[1] and k != MASS_COLUMNS]:
        del model.column_cache[key]
    if model.ladder is None:
        stats.factorizations += len(added)
        return
    # the counts as at ``kept`` plus the work since: what the calls nested in this one
    # counted (localized steps in a split at a release, in sub-steps, taken aside) is part
    # of it, so each factorization and solve is counted once
    work, reported = kept[2], kept[3]
    counts = {k: reported[k] + v - work.get(k, 0) for k, v in model.ladder.work().items()}
    stats.factorizations = counts.pop("factorizations")
    stats.ladder.update(counts)
