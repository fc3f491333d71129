r"""Contact phases taken in sub-steps: the chattering contacts of flexible bodies, and the
release of solids read aside.

On a flexible body (a beam or a solid) a closing starts a contact phase of its own dynamics:
the body's elastic spring-back lifts the point off and it strikes again, several times
within a few steps (a chattering contact). A step of h holds such a contact pressed for as
long as the smooth step still drives it in, which it does for several steps after the
converged release. So a step of a flexible model in which a contact closes, or that starts
with a contact pressed within ``CHATTER_WINDOW`` steps of the latest closing, or one whose
mean force falls to zero within ``RELEASE`` steps along the line of its last two, is taken
as ``CHATTER`` sub-steps, each localized (:func:`fecontact.time.localize.localized_step`):
the releases and re-strikes fall at the sub-steps' resolution and every re-strike is
located. A contact pressed for longer is a lasting one, left to the step. Such steps are
counted (``subdivided_steps``). They are taken with ``localize`` on; "auto" localizes the
solids it chooses (:func:`fecontact.time.localize.undamped_solids`) in whole steps (with
friction, a contact pressed within ``CHATTER_WINDOW`` steps is a lasting one whose
re-closing is left to the step's end, :meth:`Releases.__call__`, unless Newton's law threw
it off, :meth:`Releases._rebounding`): the
closing's energy is gone at the cost of a few smooth steps, where the sub-steps cost the
contact phase about eight steps per step. There the releasing step (the last test above) is
also taken aside in sub-steps, which read the contact's end at a sub-step's resolution and
leave the run as it is (:class:`Releases`); where the reading falls inside a step whose
total force is falling to zero, that step is split there
(:mod:`fecontact.time.release_split`).
"""

from __future__ import annotations

import copy

import numpy as np

from ..contact.mortar_safeguard import pointwise_pairs, real_starts
from ..errors import SolverError
from ..ledger_records import joined_record
from .aside import taken_aside
from .constraints import StepFailure
from .localize import GRAZING, cache_keys, drop_caches, joined, localized_step
from .release_split import EDGE, split_at_release
from .settings import RunSettings
from .state import PhaseTimer, State, length_scale

__all__ = ["CHATTER", "CHATTER_WINDOW", "Localizer", "Releases", "localized_stepper"]

CHATTER = 8
"""Sub-steps of a step of a flexible model in which a contact chatters (module docstring)."""

CHATTER_WINDOW = 16
"""Steps after the latest closing within which a pressed contact of a flexible model is
taken as chattering; longer, it is a lasting contact."""

RELEASE = 2.0
"""Steps within which a contact whose mean force falls reaches zero along the line of its
last two steps' forces: the step is taken in sub-steps (the release falls inside it)."""

LET_GO = 1.1
"""Steps within which the total mean force of a contact pair reaches zero along the line of
its last two steps': its release is read now and the step split there (:class:`Releases`;
Hertz's ball at t_c/20, its force 125.9 → 63.0 N, reaches zero 1.0006 steps ahead, and the
probe reads the release at 0.875 of that step). With 1.5 the readings and splits were the
same and the probes started a step earlier: `two_disks` 1.06 × the CPU of whole steps, 1.0
× now (docs/validation/localization.md)."""

READ_RELEASE = 1.0
"""The same for the solids "auto" localizes in whole steps, whose release is read from
sub-steps taken aside (:class:`Releases`): Hertz's balls read the same instants with 2.0
(docs/validation/localization.md) at the cost of up to a step more of sub-steps."""


def localized_stepper(model, opts: RunSettings):
    """The step function of a run of ``model`` with ``opts`` that localizes its impacts,
    decided once: a :class:`Localizer` (sub-steps while a contact chatters) where a body is
    flexible and ``localize`` is on, :class:`Releases` (whole steps, sub-steps where a
    contact releases, the releasing step split at the release they read where the run's
    acceleration restarts after an impact) where "auto" chose it for solids
    (:func:`undamped_solids`), and
    :func:`localized_step` itself (whole steps) where the bodies are rigid."""
    flexible = model.continuum or model.slender
    if flexible and opts.localize is True and CHATTER > 1:
        return Localizer(model)
    if flexible and CHATTER > 1:
        return Releases(model, split=opts.restarts)
    return localized_step


def _same(rows, other) -> bool:
    """Whether two sets of contacts (index arrays, or None for all) are the same."""
    if rows is None or other is None:
        return rows is other
    return rows.size == other.size and bool(np.all(rows == other))


class Localizer:
    """The localized step of one run of a flexible ``model`` (its step function):
    :func:`localized_step`, in ``CHATTER`` sub-steps while a contact chatters (module
    docstring). It remembers the instant of the run's latest closing (s) and whether a
    contact carried a force in its last (sub-)step (a joined step's state sums its
    sub-steps' impulses)."""

    def __init__(self, model):
        self.substeps = CHATTER
        self.lasting = None  # (Releases: the contacts whose re-closing is not located)
        self.closed = -np.inf
        self.pressed = None
        self.force = np.zeros(model.contacts.size)  # N: the mean forces of the last step

    def __call__(self, model, st: State, h: float, opts: RunSettings, timer: PhaseTimer) -> State:
        pressed, releasing = st.pressed().any(), self._releasing(st)
        if pressed and (releasing or st.t - self.closed <= CHATTER_WINDOW * h):
            return self._subdivided(model, st, h, opts, timer)
        out = localized_step(model, st, h, opts, timer)
        ends = out.pressed().any()
        if not ends and (pressed if self.pressed is None else self.pressed):
            opts.stats.localization.last_release = st.t  # (a release at the step's start)
        if pressed or not ends:
            self.pressed = ends
            return out
        self.closed = st.t  # a closing: the step again, in sub-steps
        return self._subdivided(model, st, h, opts, timer)

    def _resting(self) -> None:
        """Note the forces of a state that presses no contact as zeros: its mean forces
        λ + kΛ/h are ≤ 0, and the next :meth:`_releasing` finds a force falling only from a
        positive one, so zeros read as they would (without making them)."""
        self.force = np.zeros(self.force.size)

    def _releasing(self, st: State, within: float = RELEASE, settled=None) -> bool:
        """Whether a contact's mean force, falling from the step before ``st``'s to
        ``st``'s, reaches zero within ``within`` steps along that line (its release), of the
        contacts not ``settled`` (a mask, or None: all); notes the forces of ``st``."""
        force = st.mean_force() if st.impulse.size == self.force.size else self.force * 0
        before, self.force = self.force, force
        falling = (force > 0.0) & (force < before)
        if settled is not None:
            falling &= ~settled
        return bool(np.any(falling & (force <= within * (before - force))))

    def _subdivided(self, model, st, h, opts, timer) -> State:
        """The step from ``st`` over ``h`` as ``substeps`` localized steps, joined; a closing
        in one of them moves the latest closing there, a release the run's last one."""
        opts.stats.localization.subdivided += 1
        k = h / self.substeps
        before = st.pressed().any() if self.pressed is None else self.pressed
        parts, cur = [], st
        for _ in range(self.substeps):
            cur = localized_step(model, cur, k, opts, timer, self.lasting)
            after = cur.pressed().any()
            if after and not before:
                self.closed = parts[-1].t if parts else st.t
            elif before and not after:
                opts.stats.localization.last_release = parts[-1].t if parts else st.t
            parts.append(cur)
            before = after
        self.pressed = before
        out = parts[0]
        for part in parts[1:]:  # (after the sub-steps: each starts from its own state)
            part.ledger = joined_record(model, out, part)  # every sub-step's contact phases
            out = joined(out, part, h)
        return out


class Releases(Localizer):
    """The localized step of one run of solids that "auto" localizes: whole steps, the
    closings located in them. Where a step starts pressed and a contact's mean force reaches
    zero within ``READ_RELEASE`` steps along the line of its last two steps'
    (:meth:`Localizer._releasing`), the run is also taken aside from that state in
    ``CHATTER`` sub-steps a step, for at most ``READ_RELEASE`` + 1 steps, only to read where
    the contact lets go (the end of the last sub-step with a force). When the run's own
    steps release within a step after it, the run's last release is that reading, not the
    end of the whole step (Hertz's t_c in docs/validation/localization.md). The sub-steps
    change nothing of the run, and their work is counted (``release_probes``). The sub-steps
    are taken when their reading is first needed (the run's release, the next falling force
    within their span, or a step whose total force falls to zero within ``LET_GO`` steps):
    a force that falls and rises again, or a run that ends pressed, costs none; nor does a
    frictional contact lasting for over ``CHATTER_WINDOW`` steps (``settled``: a floor
    under a ringing block, whose forces fall again and again; ``elastic_block`` 26 → 2
    probes, the run the same to the bit). With ``split`` (solids whose acceleration
    restarts, decided once by :func:`localized_stepper`), a step whose total force falls so
    and in which the reading falls is split there (:meth:`_falling`). A whole step that
    leaves a closing unrefined is retaken in sub-steps (:meth:`_retaken`)."""

    def __init__(self, model, split: bool = False):
        super().__init__(model)
        self.read = (None, -np.inf)  # (s, s): the release a probe read, the probe's end
        self.pending = None  # (state, step size): a probe not yet taken, from that state
        self.split = split  # (the run's choice: releasing steps split at the release read)
        self.watched = None  # the contacts whose release the pending probe reads (None: all)
        self.read_rows = None  # those of the latest reading
        self.flying = (None, None)  # (a state it returned that presses nothing, its impulses)
        # (frictional: when each contact last carried a force, s)
        self.touched = np.full(model.contacts.size, -np.inf) if model.contacts.frictional else None
        self.pressed_once = False  # (before: no lasting contact, no mask to make)
        # (frictional: since when each contact has been lasting, s; inf: it is not)
        self.since = np.full(model.contacts.size, np.inf)
        self.settled = None  # lasting for over CHATTER_WINDOW steps: no release read
        # (decided once: the mortar safeguard's pointwise rows, whose falling force reads no
        # release; two_balls at 10 m/s: every probe was theirs, none read a release)
        rows = pointwise_pairs(model.contacts.pairs)[model.contacts.owner]
        self.pointwise = rows if rows.any() else None
        self.ends = (None, None, False)  # (the last state, its impulses, whether it presses)
        # (frictional, decided once: the contacts with restitution, which an impulse can throw
        # off; None where none has it)
        elastic = model.contacts.restitution > 0.0
        self.elastic = elastic if model.contacts.frictional and elastic.any() else None

    def __call__(self, model, st: State, h: float, opts: RunSettings, timer: PhaseTimer) -> State:
        if self.touched is None:
            return self._step(model, st, h, opts, timer)
        # a frictional contact pressed within CHATTER_WINDOW steps is a lasting one: its nodes
        # that lift and re-close are left to the step's end (located, the struck block on its
        # floor cost 4.6x the CPU and created 0 either way: docs/validation/localization.md);
        # one that an impulse threw off is in flight (_rebounding)
        touched = self.touched
        self.lasting = st.t - touched <= CHATTER_WINDOW * h if self.pressed_once else None
        if self.lasting is not None:  # (a floor under a ringing block: its forces ring)
            self.since = np.where(self.lasting, np.minimum(self.since, st.t), np.inf)
            self.settled = st.t - self.since > CHATTER_WINDOW * h
        out = self._step(model, st, h, opts, timer)
        if out is not self.flying[0]:  # (a state noted in flight presses nothing)
            pressed = out.pressed()
            touched[pressed] = out.t
            if self.elastic is not None:  # (thrown off by its impulse: in flight, not lasting)
                touched[self._rebounding(model, out, pressed, opts)] = -np.inf
            self.ends = (out, out.impulse, pressed.any())  # (read by the next step)
            self.pressed_once = self.pressed_once or self.ends[2]
        return out

    def _step(self, model, st: State, h: float, opts: RunSettings, timer: PhaseTimer) -> State:
        """The step from ``st`` over ``h`` (s) (class docstring)."""
        # (in flight the step before proved st presses nothing, and noted the forces as zeros
        # then: no test of its arrays; a state joined since has other impulses)
        free, impulse = self.flying
        known = st is free and st.impulse is impulse
        pressed = not known and self._presses(st)
        if not (pressed or known):  # (no force to fall: most steps)
            self._resting()
        elif pressed and (out := self._falling(model, st, h, opts, timer)) is not None:
            return out
        stats = opts.stats.localization
        before = (stats.fallbacks["unrefined"], stats.impacts, stats.first_closing)
        stats.unrefined_depth = 0.0
        out = localized_step(model, st, h, opts, timer, self.lasting)
        if stats.fallbacks["unrefined"] > before[0]:  # an instant the whole step did not find
            out = self._retaken(model, st, out, h, opts, timer, before[1:])
        elif not pressed:
            self._note_flight(out, stats.impacts == before[1])
        if pressed and not out.pressed().any():  # (the run's release, at the step's start)
            self._drop_spent(st.t)
            release, until = self._reading(model, opts, timer)
            located = release is not None and st.t <= until
            opts.stats.localization.last_release = release if located else st.t
        return out

    def _rebounding(self, model, st: State, pressed, opts: RunSettings) -> np.ndarray:
        """The contacts of ``pressed`` (mask) that ``st`` leaves separating after an
        impulse of Newton's law with e_j > 0, carried by no smooth force: their normal
        velocity G_j(q) v at the step's end opens them by more than ``GRAZING`` gap
        tolerances within a step (the grazing speed of :mod:`.localize`). Such a contact
        rebounded: its next closing is an impact, to locate, not a lasting contact's node
        re-closing. Left to the step's end, the two segment rows of a soft disk on a peg
        (e_N = 1, μ = 0.3) rebounding at 11 m/s every four steps were pushed out of the peg
        by the correction, whose strain created up to 4.3e-3 of the run's scale
        (docs/validation/contact_pairs.md)."""
        rows = np.flatnonzero(pressed & self.elastic & (st.impulse > 0.0) & (st.force <= 0.0))
        out = np.zeros(pressed.size, bool)
        if rows.size:
            rate = _node_rates(model, st, rows)
            tol = opts.tol_gap * length_scale(model, st.q)
            out[rows] = rate * st.h > GRAZING * tol
        return out

    def _presses(self, st: State) -> bool:
        """Whether ``st`` presses a contact: as the step that returned it noted (:meth:`__call__`,
        frictional runs), else read."""
        end, impulse, pressed = self.ends
        if st is end and st.impulse is impulse:
            return bool(pressed)
        return bool(st.pressed().any())

    def _note_flight(self, out: State, unsplit: bool) -> None:
        """Note ``out``, the end of a step from a state that pressed nothing, as pressing
        nothing where it has no candidate, no smooth force and no impact was located in its
        step: its correction then gave ν to none, its jump Λ to none (nothing closed at its
        end), and no part of the step left Λ (:meth:`State.pressed`)."""
        flying = unsplit and out.candidates.size == 0 and out.smooth is None
        self.flying = (out, out.impulse) if flying else (None, None)

    def _falling(self, model, st, h, opts, timer) -> State | None:
        """The step from the pressed ``st`` split at the release the probe reads inside it,
        where ``split`` is on and the total mean force of the contacts reaches zero within
        ``LET_GO`` steps (:func:`~.release_split.split_at_release`); None for the step as
        it is. A probe starts from ``st`` where a contact's force (:meth:`_releasing`), or
        that total, is falling to zero and no reading covers ``st``; a pending probe of
        other contacts is replaced untaken (its reading would go unread)."""
        before = self.force  # (the step before's mean forces; st's after _releasing)
        falling = self._releasing(st, READ_RELEASE, self._aside())
        rows = self._letting_go(model, before) if self.split else None
        if not falling and rows is None:
            return None
        self._drop_spent(st.t)
        if self.pending is not None and not _same(rows, self.watched):
            self.pending, self.watched = (st, h), rows
        elif st.t > self._reading(model, opts, timer)[1] or not _same(rows, self.read_rows):
            self.pending, self.watched = (st, h), rows
        if rows is None:
            return None
        release = self._reading(model, opts, timer)[0]  # (taken now: the split needs it)
        if release is None or not st.t + EDGE * h < release < st.t + (1.0 - EDGE) * h:
            return None
        out = split_at_release(model, st, h, release - st.t, rows, opts, timer)
        pressed = st.pressed()
        pressed[rows] = False
        if out is not None and not pressed.any():  # (every contact let go: the run's release)
            opts.stats.localization.last_release = release
        return out

    def _aside(self) -> np.ndarray | None:
        """The contacts whose falling force reads no release: the settled ones (frictional
        runs) and the mortar safeguard's pointwise rows; None where there is none."""
        pointwise, settled = self.pointwise, self.settled
        if pointwise is None or settled is None:
            return settled if pointwise is None else pointwise
        return settled | pointwise

    def _letting_go(self, model, before: np.ndarray) -> np.ndarray | None:
        """The contacts of the pairs whose total mean force, from ``before`` to the step's
        (N), reaches zero within ``LET_GO`` steps along that line; None where none does (a
        ball leaving a box that stays pressed on its floor: the ball's pair)."""
        owner, n = model.contacts.owner, len(model.contacts.pairs)
        now = np.bincount(owner, weights=self.force, minlength=n)
        fell = np.bincount(owner, weights=before, minlength=n) - now
        pairs = (now > 0.0) & (now <= LET_GO * fell)
        return np.flatnonzero(pairs[owner]) if pairs.any() else None

    def _retaken(self, model, st, whole, h, opts, timer, counts) -> State:
        """The step from ``st`` over ``h`` retaken in ``substeps`` localized sub-steps, where
        the ``whole`` step left a closing to its end (counted ``unrefined``): a box corner's row
        on an elastic ball reads the plane of another triangle at the trial's end, −3.6e-4 m
        where it is +9e-8 m at its Hermite instant, and the regula falsi does not reach it;
        the correction at the step's end created 2.2 % of the run's scale, the sub-steps 7e-5
        (docs/validation/localization.md). The whole step's impacts (``counts``: the
        impacts and first closing before it) are not counted. The sub-steps' size is met
        once, as a split step's: its factorization and columns are dropped after it.

        The retake is there to leave less depth to a correction at a step's end: where a
        sub-step leaves a deeper gap unrefined than the ``whole`` step did
        (``unrefined_depth``), the ``whole`` step is kept, with the run's contact set, counts
        and chatter record as it left them (counted ``retakes_kept_whole``). A gap that
        jumps has no instant to find at any step size: a mortar row of two disks at 14.5 m/s
        jumped from +4.8e-5 to −1.2e-3 m inside a sub-step of h/8, deeper than the 9.6e-4 m
        the whole step left, and its correction made +48 J of strain where the whole step
        lost 2.8 J (docs/validation/stress_2d.md)."""
        stats = opts.stats.localization
        depth, stats.unrefined_depth = stats.unrefined_depth, 0.0  # (the whole step's)
        left = (stats.impacts, stats.first_closing, stats.last_release, stats.subdivided)
        fallbacks, chatter = dict(stats.fallbacks), (self.closed, self.pressed, self.force)
        contacts = copy.deepcopy(model.contacts, {id(body): body for body in model.bodies})
        stats.impacts, stats.first_closing = counts
        model.contacts.look_ahead(st.q, st.v, h)
        kept = cache_keys(model, stats)
        try:
            out = self._subdivided(model, st, h, opts, timer)
        finally:
            drop_caches(model, kept, stats)
        if stats.unrefined_depth <= depth:  # (0 where every closing was located)
            return out
        model.contacts = contacts
        stats.impacts, stats.first_closing, stats.last_release, stats.subdivided = left
        stats.fallbacks.update(fallbacks)
        self.closed, self.pressed, self.force = chatter
        stats.retakes_kept_whole += 1
        return whole

    def _drop_spent(self, t: float) -> None:
        """Forget a probe not yet taken whose reading ends before ``t`` (s) whatever it reads:
        its span, with the step after a release it reads, is below (READ_RELEASE + 2) steps."""
        if self.pending is not None:
            start, h = self.pending
            if t > start.t + (READ_RELEASE + 2.0) * h:
                self.pending = None

    def _reading(self, model, opts, timer) -> tuple:
        """(the release read, the end of its reading) (s) of the latest probe, taken now
        where it is pending (:meth:`_probe`)."""
        if self.pending is not None:
            start, h = self.pending
            self.pending = None
            self.read = self._probe(model, start, h, opts, timer)
            self.read_rows = self.watched
        return self.read

    def _probe(self, model, st, h, opts, timer) -> tuple:
        """(the release read and a step after it, or None and the end of the span probed)
        (s) of sub-steps of ``h``/``substeps`` from ``st`` (localized), at most
        ``READ_RELEASE`` + 1 steps' worth, until one carries no force on the contacts
        ``watched`` (None: on any; a sub-step that fails reads nothing, counted
        ``unrefined``), taken aside (:func:`taken_aside`): the run goes on as without them."""
        stats = opts.stats.localization
        stats.release_probes += 1
        cur, k = st, h / self.substeps
        with taken_aside(model, st, h, stats):
            try:
                for _ in range(int(READ_RELEASE + 1) * self.substeps):
                    nxt = localized_step(model, cur, k, opts, timer)
                    watched = slice(None) if self.watched is None else self.watched
                    if not nxt.pressed()[watched].any():  # (they let go within a step)
                        return cur.t, cur.t + h * (1.0 + 1e-9)
                    cur = nxt
            except (StepFailure, SolverError):  # (the run's step decides; read at its end)
                stats.fallbacks["unrefined"] += 1
        return None, cur.t


def _node_rates(model, st: State, rows: np.ndarray) -> np.ndarray:
    """G_j(q) v (m/s) of the contacts ``rows`` at ``st``. A mortar interface's pointwise row
    thrown back above half its allowance reads a placeholder without a gradient, and is read
    by its node's real gap (:func:`~fecontact.contact.mortar_safeguard.real_starts`): with
    the placeholder's zero rate an elastic disk's vertex rebounding at e_N = 1 (10 m/s,
    μ = 0.3) counted as a lasting contact, its re-closing was left to the step's end, and
    the correction pushed it out at three steps' ends (0.97 % of the scale created)."""
    G = model.contacts.linearize(st.q, rows)[1]
    return real_starts(model.contacts, st.q, rows, st.gaps, G)[1] @ st.v[model.free]
