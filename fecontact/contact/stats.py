"""Counts of the contact solvers' work over one run, filled by the solvers that are given
them (the run owns them, so that runs never mix their counts)."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["ContactStats", "CoulombStats", "FinalResiduals"]


@dataclass
class CoulombStats:
    """Frictional contact solves (:func:`fecontact.contact.friction.solve_coulomb`) and
    their fallbacks, each counted where it happens."""

    solves: int = 0
    iterations: int = 0  # semi-smooth Newton iterations
    line_search_cuts: int = 0  # backtracking cuts of the merit |R|²
    # updates taken in full after the backtracking found no decrease (a kink of the residual)
    full_steps_forced: int = 0
    # Newton solves given up as soon as a step forced in full moved the multipliers by
    # round-off alone (a stationary point of |R|² that is not a solution): the fallbacks
    # then take over, as they did after the remaining iterations
    stalled_newtons: int = 0
    # solves where Newton alone did not converge and a nonsmooth Gauss–Seidel over the
    # contacts brought it near the solution first
    gauss_seidel_solves: int = 0
    # Newton steps taken as the minimum-norm solution on a singular Jacobian (more closed
    # rows than degrees of freedom: redundant contacts)
    minimum_norm_steps: int = 0
    # moves along a family of solutions to its least-norm member (redundant rows), and the
    # solves where that choice did not settle (the solution kept is the law's, not the least)
    least_norm_moves: int = 0
    least_norm_unsettled: int = 0
    # open contacts whose normal rate was nearly grazing (on the scale of the jump) and the
    # law was solved again with each held closed; tries dropped (a search that failed, or a
    # search from zero that reached another closed solution); solves whose closed solution
    # was of lower norm, and kept
    grazing_tries: int = 0
    grazing_unsettled: int = 0
    grazing_closed: int = 0
    # closed solutions kept whose law's error at the run's p exceeded the tolerance, finished
    # by Newton at that p
    grazing_finished: int = 0
    # solves (in runs with redundant rows) where Newton stalled with every contact closed
    # and the law was solved with one contact left out, which separates
    opened_contact_solves: int = 0
    # solves of at most four planar contacts where Newton did not converge and the law was
    # solved by its cases, each contact's four branches a linear system
    # (:mod:`fecontact.contact.friction_cases`)
    case_solves: int = 0
    # solves (in runs with redundant rows) where Newton stalled on a singular Delassus
    # matrix and the law was solved by the proximal point method (each step on D + εI), and
    # those proximal steps
    proximal_solves: int = 0
    proximal_steps: int = 0
    # solves (in runs with redundant rows) where the proximal iterations settled without
    # solving the law and the law was solved from there by Lemke's pivoting on the normal
    # multipliers, the tangential statuses held, then Newton; the pivots; and the settled
    # iterations where that did not solve it (then left for the cold start, one contact left
    # out, Gauss–Seidel)
    pivoted_solves: int = 0
    pivots: int = 0
    pivoted_failures: int = 0
    # solves (in runs with redundant rows) whose warm and cold starts reached solutions of
    # the law that move the bodies differently (beyond the tolerance): the law is not unique
    distinct_solutions: int = 0
    # solves (in runs with redundant rows) whose warm start failed and whose cold start
    # (from zero) converged
    cold_restarts: int = 0
    # position corrections and smooth-step friction updates (in runs with redundant rows)
    # that failed on their slips and converged without the part of them no multiplier
    # reaches (a face landing flat)
    unreachable_slip_solves: int = 0
    # velocity jumps (in runs with redundant rows) whose frictional law with the impact
    # law's restitution terms was not solved and that were solved as plastic ones (e = 0)
    plastic_jumps: int = 0
    # singular value decompositions (least-norm moves, minimum-norm Newton steps, slips no
    # multiplier reaches) where LAPACK's divide and conquer did not converge and the QR
    # iteration was taken (:mod:`fecontact.linalg.svd`)
    svd_fallbacks: int = 0


@dataclass
class FinalResiduals:
    """The largest Alart–Curnier residual a converged correction left at each level,
    relative to its tolerance (≤ 1)."""

    position: float = 0.0
    velocity: float = 0.0

    def record(self, level: str, ratio: float) -> None:
        if level == "position":
            self.position = max(self.position, ratio)
        else:
            self.velocity = max(self.velocity, ratio)


@dataclass
class ContactStats:
    """The contact solvers' counts: active sets whose constraints were redundant (a
    singular Schur matrix G_A Y, multipliers by least squares), the final residuals, and the
    frictional solves."""

    least_squares: int = 0
    # active rows merged into a duplicate of theirs (a node's row from two segments clipped
    # to it) before the multipliers' solve (:mod:`fecontact.contact.kkt`)
    duplicate_rows: int = 0
    # smooth-step Newton updates whose bordered matrix was singular because the touching
    # rows were redundant (four corners of a rigid face on a plane): taken on a maximal
    # independent subset of the rows, the others' multipliers kept
    redundant_row_updates: int = 0
    # position corrections whose active sets cycled, ended on the set of least residual
    # (:func:`fecontact.contact.laws.solve_position_correction`)
    frozen_active_sets: int = 0
    # position corrections whose active sets cycled, settled by complementarity updates on
    # every row at once (the linearised law solved by principal pivoting)
    complementary_corrections: int = 0
    # position corrections whose held rows (equalities by the smooth step's decision) froze
    # with the law unsettled, solved again with them unilateral (the law then held)
    released_corrections: int = 0
    # frictionless velocity jumps whose redundant rows left the law unsettled after the
    # active set repeated (the rows could not all close), solved again by the proximal
    # point method (:mod:`fecontact.contact.redundant_jump`), and its proximal steps
    redundant_jumps: int = 0
    redundant_jump_steps: int = 0
    # smooth-step Newton updates whose persistent rows, dependent or with an active set that
    # repeated, were solved whole as the linearised law (:mod:`fecontact.time.smooth_redundant`)
    complementary_smooth_updates: int = 0
    # decided once per run: the model has pairs whose rows can be redundant up to round-off
    # (:func:`fecontact.contact.kkt.kkt_multipliers` then reads the LU's pivots)
    minimum_norm: bool = False
    # decided once per run: the model has pairs whose rows can be one row twice
    # (:func:`fecontact.contact.kkt.schur_multipliers` then merges them)
    merge_duplicates: bool = False
    final_residuals: FinalResiduals = field(default_factory=FinalResiduals)
    coulomb: CoulombStats = field(default_factory=CoulombStats)
