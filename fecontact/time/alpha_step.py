"""Step 1 of the NSGA step, the smooth generalized-α step: Newton on the equations of motion
with the joints (index 3) and the smooth forces of persistent contacts
(:mod:`.smooth_contact`), globalized in units of energy (:mod:`.descent`): the shared
:class:`~fecontact.time.newton.SmoothNewton` over the run's force terms
(:func:`alpha_plan`)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..contact.contact_set import rows_held
from .lie import LieGroup, on_group
from .newton import NewtonPlan
from .terms import (
    Damping,
    Elastic,
    ExternalLoad,
    ForceTerm,
    Gyroscopic,
    Joints,
    PersistentContacts,
    SmoothContact,
)

__all__ = ["SmoothStep", "alpha_plan", "alpha_smooth_step"]


class SmoothStep(NamedTuple):
    """The smooth step's result: positions, velocities, accelerations v̇ and a, joint
    multipliers λ (N), the iteration matrix with its solver for the correction metric (None
    with joints), the Newton iterations, and the joints' gradient at q (None when stale);
    ``fint``: the internal forces at q (N, all dofs; None where the last update moved q after
    they were evaluated)."""

    q: np.ndarray
    v: np.ndarray
    vd: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    S: tuple | None
    iterations: int
    Gb: np.ndarray | None
    force: np.ndarray | None  # λ of every contact (N), None without persistent contacts
    friction_force: np.ndarray | None  # λ_T (m, nt) (N), None without persistent friction
    friction_work: float  # the energy λ_T dissipated over the step's slip (J)
    fint: np.ndarray | None = None


def alpha_plan(model, smooth: bool, friction: bool, extra=()) -> NewtonPlan:
    """The smooth step's Newton loop for a run of ``model``: the force terms elastic, load,
    Rayleigh damping, joints, the persistent contacts (``smooth``: they carry a smooth force;
    ``friction``: with Coulomb's law) where the model has them, then the ``extra`` terms
    (:class:`~fecontact.time.terms.ForceTerm`). A linear model reuses S_t and its factors
    unless a term brings a tangent of its own."""
    extra = tuple(extra)
    # rotations in space (:mod:`.lie`): q = q_n ⊕ D, S_t through T(D), gyroscopic forces
    group = LieGroup(model) if on_group(model) else None
    if model.inertial_bodies:
        extra = (Gyroscopic(model), *extra)
    reuse = model.linear and not group and not any(term.own_tangent for term in extra)
    joints = model.joints
    # (a linear model on a group: K is assembled, once)
    elastic = Elastic(model, tangent=not reuse, constant=model.linear)
    terms: list[ForceTerm] = [elastic, ExternalLoad(model)]
    if any(model.damping):
        terms.append(Damping(model, elastic, constant=model.linear))
    if joints.size:
        terms.append(Joints(model, scaled=True, linearize_first=True))
    if smooth:
        terms.append(SmoothContact(model, friction))
    bound = _remainder_bound(model, reuse or (group is not None and model.linear))
    # (on a group, the line search alone: plain Newton took whole a 2 rad update of a
    # struck beam's rotation, S_t indefinite, that the planar twin's line search cut)
    descent = not model.linear
    plan = NewtonPlan((*terms, *extra), reuse, descent, False, bound, "smooth step", group)
    # (affine forces and gaps: an update through S_t's own factors is the solution)
    plan.exact = reuse and not (joints.size or friction or extra) and model.contacts.affine
    return plan


def _remainder_bound(model, affine: bool) -> bool:
    """Whether the joints' remainder bound may end Newton: every other force is ``affine``
    in q (on a group: but for the gyroscopic forces, whose remainder the loop adds) and every
    joint's curvature is known (its arms: pins, ball joints)."""
    joints = model.joints
    if not (affine and joints.size) or joints.linear:
        return False
    return all(joint.arms is not None for joint in joints.pairs)


def alpha_smooth_step(model, st, t, c, opts, timer, P=None) -> SmoothStep:
    """Step 1: Newton on M v̇ + C_t v + f_int(q) + G_bᵀλ_b − G_Pᵀλ = f_ext(t), g_b(q) = 0,
    0 ≤ g_P(q) ⊥ λ ≥ 0 on the persistent contacts ``P`` (:mod:`.smooth_contact`), and the
    force terms the run adds; ``opts`` are the run's settings
    (:class:`~fecontact.time.settings.RunSettings`, whose ``plan`` this step follows).

    Returns a :class:`SmoothStep`: S = (S_t, its solver) for the metric of the position
    correction (None with joints), G_b the joint gradient at the returned q (None when the
    last update moved q after it was evaluated)."""
    # (the persistent contacts' rows: those of q_n, held through the iterates)
    with rows_held(model.contacts, st.q, P is not None and P.size > 0):
        newton = opts.plan.loop(model, opts, timer).start(st, t, c, P)
        turns = opts.turns
        if turns is not None:  # (beams: a step that turns a node too far is halved, :mod:`.turns`)
            group = newton.form.lie is not None
            turns.start(newton.form, st.q, group, opts)
        it, stale = newton.run()
    step, joints = newton.step, newton.joints
    if turns is not None:
        turns.check(step.X[0], st.q, group, "the smooth step", opts.stats)
    Gb = None if stale or joints is None else joints.Gb
    q, (_, v, vd, a) = step.q, step.X  # (on a group the first row of X is the increment D)
    force, force_t, work = None, None, 0.0
    if newton.rowed:  # (the persistent contacts' forces, where they are a term)
        force, force_t, work = _contact_forces(newton.rowed, model.contacts.size)
    form = newton.form
    fint = None if stale else newton.elastic.fint
    return SmoothStep(q, v, vd, a, form.lam(), form.metric(), it, Gb, force, force_t, work, fint)


def _contact_forces(rowed, m: int):
    """(λ (m,), λ_T (m, nt), the work of λ_T (J)) of the persistent contacts among the
    terms with rows (None, None, 0 without them; λ_T None without friction)."""
    for term in rowed:
        if isinstance(term, PersistentContacts):
            return term.forces(m)
    return None, None, 0.0
