r"""The Newton loop every stepper solves its step with, over the force terms of its run.

The loop evaluates the force terms f_k(q, v, t) of a run (:mod:`.terms`) at an iterate,
sums their forces and tangents, and iterates a residual to convergence. What it iterates is
its *form*, decided once per run in the :class:`NewtonPlan`: the unknown, the residual, the
update and the test.

- :class:`~fecontact.time.acceleration_form.AccelerationForm`, the generalized-α step (the
  NSGA's smooth step, penalty): the unknown q_{n+1}, with (v, v̇, a) following, updates from
  S_t = β′M + Σ_k (∂f_k/∂q + γ′ ∂f_k/∂v) (:mod:`.acceleration_form`).
- Moreau–Jean's velocity form (:class:`fecontact.time.moreau.VelocityForm`): the unknown
  v_{n+1}, with the impact law inside each update.

A form is a class the loop builds for each step as ``form(newton, st, c, t, P, law)`` (the
step from the state ``st`` with the coefficients ``c`` to the time ``t``, the persistent
contacts ``P``; ``law``: what the form needs of the step besides, None for the acceleration
form). It holds ``step``, the step's :class:`StepContext` at the predictor, and gives
``residual(it)``, whether the iterate has converged, leaving ``rnorm`` and its
reference ``ref``; ``update()``, whether the update ended the iteration; and, where the plan
halves updates, ``halves()``. The acceleration form is built once per run and begun again
at every step (``begin(st, c, t, P, law)``); another form is built for each step.

The loop is built once per run (:meth:`NewtonPlan.loop`), its terms sorted into their roles
once, and started at every step (:meth:`SmoothNewton.start`).
"""

from __future__ import annotations

import time
from typing import NamedTuple

from .acceleration_form import AccelerationForm
from .constraints import StepFailure
from .terms import ExternalLoad, ForceTerm, Gyroscopic, Joints

__all__ = ["AccelerationForm", "NewtonPlan", "SmoothNewton"]


class Roles(NamedTuple):
    """What the loop asks of each of a step's terms, sorted once: all ``terms`` (the elastic
    one first), those evaluated after the elastic one (``evaluated``), those that set the
    residual's scale (``scaled``), those with rows (``rowed``) and with a convergence test of
    their own (``checked``), and the ``joints``, ``load`` and ``gyroscopic`` terms (None:
    absent); ``forced`` and ``stiff``: those with a force and with a tangent; ``begun``: those
    a step begins (the others' ``begin`` is the term itself)."""

    terms: list
    evaluated: list
    scaled: list
    rowed: list
    checked: list
    joints: Joints | None
    load: ExternalLoad | None
    gyroscopic: Gyroscopic | None
    forced: list
    stiff: list
    begun: list


def roles(terms) -> Roles:
    """The :class:`Roles` of ``terms`` (a method a term does not override is not called)."""
    terms = list(terms)

    def having(name, among=terms):
        return [term for term in among if getattr(type(term), name) is not getattr(ForceTerm, name)]

    def first(kind):  # (the first term of that kind, None: absent)
        return next((term for term in terms if isinstance(term, kind)), None)

    return Roles(
        terms,
        having("evaluate", terms[1:]),
        having("reference"),
        [term for term in terms if term.rows],
        having("converged"),
        first(Joints),
        first(ExternalLoad),
        first(Gyroscopic),
        having("residual"),
        terms[:1] + having("tangent", terms[1:]),
        having("begin"),
    )


class NewtonPlan:
    """The Newton loop of a run, decided once: its ``terms`` (the elastic one first), its
    ``form`` (what it iterates: :class:`AccelerationForm` or another class with its
    methods), ``reuse``: S_t and its factors come from the linear model's cache,
    ``descent``: plain updates of a nonlinear model are globalized in energy
    (:mod:`.descent`), ``halving``: an update that does not lower the residual is halved (up
    to six times), ``bound``: the joints' remainder bound may end the iteration, and the
    ``name`` failures carry. ``group``: the positions live on a Lie group (rotation vectors
    in space, :mod:`.lie`; its :class:`~.lie.LieGroup`, else None): the iterate's first row
    is the increment D and q = q_n ⊕ D.
    ``roles``: the terms' :class:`Roles`, when every term acts in every step as itself (no
    ``per_step`` term), else None (sorted per step). ``exact``: every force is affine in q
    and every row's gap too (a linear model without joints or friction, its contacts nodes
    on fixed planes), so an update solves the step's equations to round-off, and ends the
    iteration where the rows' active set holds after it (:meth:`ForceTerm.solved`)."""

    __slots__ = (
        "terms reuse descent halving bound name group roles bare form last_loop exact sorts"
    ).split()

    def __init__(
        self,
        terms,
        reuse: bool,
        descent: bool,
        halving: bool,
        bound: bool,
        name: str,
        group=None,
        form: type | None = None,
    ):
        self.terms: tuple[ForceTerm, ...] = tuple(terms)
        self.reuse, self.descent, self.halving, self.bound = reuse, descent, halving, bound
        self.name, self.group = name, group
        self.form = AccelerationForm if form is None else form
        fixed = not any(term.per_step for term in self.terms)
        self.roles = roles(self.terms) if fixed else None
        # (the roles of a step in which every per-step term is absent, sorted once: most
        # steps of a run with smooth contact forces have no persistent contact)
        per_step = [term for term in self.terms if term.per_step]
        self.bare = None if fixed else (per_step, roles(t for t in self.terms if not t.per_step))
        self.last_loop: SmoothNewton | None = None
        self.exact = False  # (set by the plans whose updates are exact, alpha_plan)
        self.sorts: dict = {}  # (the places of each role, by the types of a step's terms)

    def sorted(self, terms) -> Roles:
        """The :class:`Roles` of a step's ``terms``: a term's roles are its type's, so they
        are sorted once per sequence of types and the step's terms put in their places (a
        third of the time of sorting them, at every step of a lasting contact)."""
        terms = list(terms)
        key = tuple(map(type, terms))
        places = self.sorts.get(key)
        if places is None:
            where = {id(term): i for i, term in enumerate(terms)}
            places = self.sorts[key] = [
                tuple(where[id(t)] for t in role) if isinstance(role, list) else where.get(id(role))
                for role in roles(terms)
            ]
        # (the lists by map over the places, one Python frame for all roles: this runs at
        # every step of a lasting contact and at the rest of a located impact's step)
        at = terms.__getitem__
        return Roles(
            *[
                list(map(at, p)) if type(p) is tuple else None if p is None else at(p)
                for p in places
            ]
        )

    def loop(self, model, opts, timer) -> SmoothNewton:
        """The run's loop over this plan for ``model`` with the run's settings ``opts`` and
        ``timer``: built on first use and kept (a plan belongs to one run), built anew where
        the model, settings or timer differ from the kept loop's."""
        loop = self.last_loop
        if (
            loop is None
            or loop.model is not model
            or loop.opts is not opts
            or loop.timer is not timer
        ):
            loop = self.last_loop = SmoothNewton(self, model, None, 0.0, None, opts, timer)
        return loop


class SmoothNewton:
    """Newton's iteration of a run's steps over the terms of ``plan``, in the plan's form.
    Built for one step from ``st`` with the coefficients ``c`` to the time ``t`` (s), the
    persistent contacts ``P`` and the form's ``law`` (what the form needs of the step besides
    its state, None for the acceleration form), or, with ``st`` None, for a run whose steps
    each :meth:`start` it (:meth:`NewtonPlan.loop`). ``run()`` iterates; then ``step`` holds
    the iterate and ``form`` what the form found."""

    __slots__ = (
        "checked clock elastic evaluated form gyroscopic joints load model name opts plan rowed "
        "scaled step terms timer fixed kept keeps shift forced stiff begun frozen"
    ).split()

    def __init__(self, plan: NewtonPlan, model, st, t, c, opts, timer, P=None, law=None):
        self.model, self.opts, self.timer, self.name = model, opts, timer, plan.name
        self.plan = plan
        # (the acceleration form is kept from step to step, begun again at each; the terms'
        # roles, where fixed, are the plan's)
        self.fixed, self.kept = plan.roles is not None, None
        self.keeps = issubclass(plan.form, AccelerationForm)
        self.shift = (None, None)  # (the coefficients, β′M of them)
        # modified Newton: S_t's factors of a step's first update serve its later ones while
        # the residual contracts (the acceleration form; set by the steps that ask for it)
        self.frozen = False
        if self.fixed:
            self._sort(plan.roles)
        if st is not None:
            self.start(st, t, c, P, law)

    def _sort(self, sorted_: Roles) -> None:
        self.terms, self.evaluated, self.scaled, self.rowed, self.checked = sorted_[:5]
        self.joints, self.load, self.gyroscopic = sorted_.joints, sorted_.load, sorted_.gyroscopic
        self.elastic, self.forced, self.stiff = self.terms[0], sorted_.forced, sorted_.stiff
        self.begun = sorted_.begun

    def start(self, st, t, c, P=None, law=None) -> SmoothNewton:
        """Begin the step from ``st`` with the coefficients ``c`` to the time ``t`` (s) (the
        persistent contacts ``P``, the form's ``law``); returns the loop."""
        plan, form = self.plan, self.kept
        if form is None:
            form = plan.form(self, st, c, t, P, law)
            if self.keeps:
                self.kept = form
        else:
            form.begin(st, c, t, P, law)
        self.form = form
        self.step = step = form.step
        if self.fixed:
            for term in self.begun:
                term.begin(step)
        else:
            per_step, bare = plan.bare
            own = [term.begin(step) for term in per_step]
            if own.count(None) == len(own):  # (no per-step term acts in this step)
                for term in bare.begun:
                    term.begin(step)
                self._sort(bare)
            else:
                made = iter(own)
                begun = [next(made) if t.per_step else t.begin(step) for t in plan.terms]
                self._sort(plan.sorted(term for term in begun if term is not None))
        self.clock = time.perf_counter()
        return self

    def mass_shift(self, c):
        """β′M of the coefficients ``c`` (the shift of a direction that does not descend),
        made once for a run's steps of one size."""
        of, shift = self.shift
        if of is not c:
            shift = c.bp * self.model.M
            self.shift = (c, shift)
        return shift

    def run(self) -> tuple[int, bool]:
        """Iterate to convergence: (the iterations, whether the last update moved the
        iterate after the terms were evaluated). Raises StepFailure where it does not
        converge."""
        top, form = self.opts.max_iterations, self.form
        for it in range(top + 1):
            if form.residual(it):
                return it, False
            if it == top:
                raise StepFailure(self.name, form.rnorm / form.ref)
            if self.plan.halving and form.halves():
                continue
            if form.update():
                return it + 1, True
        raise AssertionError("unreachable")

    def evaluate(self, it: int, check=None) -> None:
        """Every term at the iterate (the elastic one first, then ``check(it)`` where given),
        each timed in its phase."""
        step, timer, elastic = self.step, self.timer, self.elastic
        elastic.evaluate(step, it)
        if check is not None:
            check(it)
        for term in self.evaluated:
            if term.phase == "assembly":
                term.evaluate(step, it)
                continue
            self.clock = timer.add("assembly", self.clock)
            term.evaluate(step, it)
            self.clock = timer.add(term.phase, self.clock)

    def forces(self, r):
        """r + Σ_k f_k, the terms' forces added in their order."""
        for term in self.forced:
            r = term.residual(r)
        return r

    def tangent(self):
        """Σ_k of the terms' tangents, opened by the elastic term with the inertia."""
        S = None
        for term in self.stiff:
            S = term.tangent(S)
        return S
