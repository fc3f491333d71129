"""Whether the arrangement of a model's rigid bodies can make its contact rows redundant.

A pair of one kind declares whether its own rows can hold one motion twice
(``redundant_rows``: a box face on a plane, two segments clipped to one node). Pairs that
each hold independent rows can still do so together: four disks wedged in a box close
seven contacts, 14 frictional rows on the 12 dofs of the disks, of rank 9. The rows of a
set of pairs are independent where every pair's rows are independent on each rigid body
it moves and the pairs form no loop: a body at a leaf of a tree of contacts takes its one
pair's rows on its own dofs, and the rest of the tree is independent of it, leaf by leaf.
So rows can be redundant only where

- the graph whose vertices are the rigid bodies (every fixed obstacle, and every rigid body
  whose dofs are all held, one vertex: the ground) and whose edges are the pairs has a
  cycle, two pairs between the same two vertices included (a disk on a floor and a wall,
  friction on both: four rows on three dofs); or
- a pair carries more rows (a normal and, with friction, ``dim − 1`` tangents per contact)
  than the free dofs of a rigid body it moves (a pendulum pinned at its end, one free dof,
  against a stop with friction).

Deformable bodies are no vertices: their contacts hold nodes, each a dof of its own, and
close no loop of rigid motions (pairs whose rows meet on one node declare it themselves).
Joints between rigid bodies (or one and the ground) are edges too: they tie the motions of
the bodies they join, so that two of their contacts can hold one motion twice. A chain of
bars pinned end to end on a floor closes a loop ground–bar–pin–bar–ground, and where the
pin strikes, the two bars' vertices at it give two rows of one normal rate. The joints
among themselves are independent (:class:`fecontact.model.Model` checks it): a loop of
joints alone is no redundancy of contact rows, and only a pair that closes a loop counts.
The rule is a sufficient condition for independence, not a
measure: a loop that never closes at once (a disk that cannot touch both walls of a wide
box) is counted all the same; it costs those runs the minimum-norm path.
"""

from __future__ import annotations

import numpy as np

from ..bodies.base import RigidDefaults

__all__ = ["loops_of_contacts"]


def loops_of_contacts(model) -> bool:
    """Whether the rigid bodies of ``model`` and its contact pairs between them or with
    fixed obstacles form a cycle, or some pair has more rows than a rigid body it moves
    has free dofs (see the module's docstring)."""
    free = model.free_index >= 0
    counts = {id(b): int(np.count_nonzero(free[model.body_slice(i)])) for i, b in
              enumerate(model.bodies) if isinstance(b, RigidDefaults)}  # fmt: skip
    roots: dict[int, int] = {}  # union-find over the vertices; 0 is the ground
    for joint in model.joints.pairs:
        ends = _free_ends(joint, counts, (joint.body, joint.other))
        if ends:
            _joined(roots, ends[0], ends[1] if len(ends) > 1 else 0)
    for pair in model.contacts.pairs:
        ends = _free_ends(pair, counts)
        if ends is None or not ends:  # (moves a deformable body, or nothing)
            continue
        rows = pair.size * (model.dim if pair.friction > 0.0 else 1)
        if rows > min(counts[v] for v in ends):
            return True
        if _joined(roots, ends[0], ends[1] if len(ends) > 1 else 0):
            return True
    return False


def _free_ends(pair, counts: dict, moved=None):
    """The rigid bodies with free dofs that ``pair`` moves (their ids; ``moved``: a joint's
    two sides, None the ground), or None where it moves a deformable body: its nodes take
    rows of their own and close no loop."""
    moved = [b for b in (moved or pair.bodies or (pair.body,)) if b is not None]
    if any(id(b) not in counts for b in moved):
        return None
    return [id(b) for b in moved if counts[id(b)] > 0]


def _joined(roots: dict, a: int, b: int) -> bool:
    """Whether the vertices a and b are already joined; joins them if not."""
    a, b = _root(roots, a), _root(roots, b)
    roots[a] = b
    return a == b


def _root(roots: dict, v: int) -> int:
    while roots.get(v, v) != v:
        v = roots[v]
    return v
