"""Steps taken aside from a run, only to read something (the instant a contact releases,
:class:`fecontact.time.substeps.Releases`), that leave the run as it would be without them.

A step leaves state behind for the next one, and a run that goes on from another state takes
other steps (other candidates, other round-off, amplified by the contacts):

- the contact pairs' spatial searches, kept while the nodes move little
  (:mod:`fecontact.contact.facet_search`, the mortar interfaces' element pairs), their last
  evaluations, and the margin each step looks ahead with (a located impact looks ahead over
  the rest of its step only);
- the factorizations of the step sizes (the model's caches), the ladder's factors and its
  count of factorizations, which decides when it turns to the eigendecomposition
  (:mod:`fecontact.linalg.ladder`).

So the steps taken aside work on a copy of the contact set (the bodies shared: their
positions are functions of q), which looks ahead from the state they start from as the
run's step from it did; afterwards the run's contact set, caches and ladder are put back as
they were, and the factorizations the steps made are counted in the localization statistics
(once: the ladder's work is not put back with the counts that decide).
"""

from __future__ import annotations

import copy
from contextlib import contextmanager

from .localize import cache_keys, drop_caches

__all__ = ["taken_aside"]


@contextmanager
def taken_aside(model, st, h: float, stats):
    """Steps of ``model`` from the state ``st`` that read something for a run whose step from
    ``st`` is of ``h`` (s): inside, ``model.contacts`` is a copy looking ahead over ``h`` from
    ``st`` and the step sizes are solved as met once (``model.passing``); on leaving, the run's
    contacts, caches and ladder are as they were (module docstring), the work counted in the
    localization ``stats``."""
    contacts, passing, ladder = model.contacts, model.passing, model.ladder
    kept = cache_keys(model, stats)
    rungs = None if ladder is None else (dict(ladder.rungs), ladder.modes, dict(ladder.counts))
    model.contacts = copy.deepcopy(contacts, {id(body): body for body in model.bodies})
    model.contacts.look_ahead(st.q, st.v, h)
    model.passing = True  # (sizes met once: the ladder's rungs, not the model's caches)
    try:
        yield model.contacts
    finally:
        model.contacts, model.passing = contacts, passing
        drop_caches(model, kept, stats)
        if rungs is not None:
            ladder.put_back(*rungs)
        model.ladder = ladder
