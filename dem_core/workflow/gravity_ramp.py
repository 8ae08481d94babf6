"""Centrifuge loading: raise the g-level step by step until the model fails.

At each g-level the model is solved towards equilibrium (``Model.solve``); the first level
judged failed is the failure g-level. The search and its failure test are
``limit.search_failure`` (shared with the strength searches) with g as its parameter: a level
fails when the solve ends "failed" or a block (or watched point) moved more than
``failure_displacement``, or when the model blew up after its displacement record had passed
that test; a level that ends "moving" counts as stable. The thesis raised gravity 1 g at a time
and called the model failed when it did not come to equilibrium with displacements growing
(ch. 3, 4). ``failure_g`` is the first failed level; the failure load lies between it and the
last stable level before it.

The size of the step to a level matters: g moves over ``ramp_steps`` steps, far fewer than the
lowest period of a slender model (tens of thousands of steps for a column of small blocks), so
each step is a sudden load whose dynamic overshoot grows with the step. A level that stands is
stable for any smaller step; a level that fails may stand when reached in smaller steps
(measured on the adhikary centrifuge slope at 6 mm blocks: T = 1.1 MPa fails at 100 g reached
from 90 g, stands to 109 g in 1 g steps and fails at 110 g). ``refine_to`` therefore ends with
steps of its own size: the failure g of a ramp in ``refine_to`` steps, the thesis's 1 g steps
when ``refine_to`` is 1.
"""
from __future__ import annotations

from dataclasses import dataclass

from .limit import LimitRecord, check_levels, search_failure

__all__ = ["RampRecord", "raise_gravity"]


@dataclass
class RampRecord(LimitRecord):
    """A ``limit.LimitRecord`` whose parameter is the g-level; ``g``, ``failure_g`` and
    ``last_stable_g`` read its ``level``, ``failure_level`` and ``last_stable_level``."""

    parameter: str = "g"

    @property
    def g(self) -> list:
        return self.level

    @property
    def failure_g(self):
        return self.failure_level

    @property
    def last_stable_g(self):
        return self.last_stable_level


def raise_gravity(model, g_levels, settings=None, *, ramp_steps=400, refine_to=None,
                  record=None, start=0.0, on_level=None, progress=None, **changes) -> RampRecord:
    """Solve the model at each g-level in turn (module docstring); return the record.

    Parameters
    ----------
    model : dem_core.model.Model, with its boundary conditions set.
    g_levels : increasing sequence of g-levels (multiples of ``units.STANDARD_GRAVITY``).
    settings : ``SolveSettings`` of each level (and/or its fields as keywords): ``ratio``,
        ``max_steps`` per level, ``failure_displacement`` (m; a block moving more than this
        during one level is failure), ``creep`` (m; slender models creep towards equilibrium
        slowly, and a small creep calls that failure), ``watch`` (history points judged
        instead of every block, e.g. the crest and the face, so that a loose block at a
        model boundary does not count as the failure of the slope), ``settle``.
    ramp_steps : steps over which g moves from one level to the next in 10 equal increments,
        so that a level is not applied as a sudden load (whose dynamic overshoot would break
        bonds a quasi-static load does not). 0 applies each level at once.
    refine_to : g, optional. After the first failure, bisect between the last stable and the
        failed level until they are at most this far apart; then, if the failed level was
        reached by a larger step than ``refine_to``, raise g from the last stable state in steps
        of ``refine_to`` until a level fails (or the last of ``g_levels`` stands). The failure g
        is then that of a ramp in ``refine_to`` steps (module docstring).
    record, start : to resume a ramp (``limit``, "Resuming"): its RampRecord and its last g;
        ``g_levels`` are then the levels after that. Default: a new record, from 0 g.
    on_level : callable(model, record), optional, called after each level
        (``limit.search_failure``).
    progress : callable(str), optional.

    The ramp stops at the first failed level (the model is then in its failed state), or
    refines from there (``refine_to``).
    """
    check_levels(g_levels, "g_levels")
    if any(b <= a for a, b in zip(g_levels, list(g_levels)[1:])):
        raise ValueError("g_levels must increase")
    return search_failure(model, g_levels, lambda m, a, b: _ramp(m, a, b, ramp_steps),
                          settings, record=RampRecord() if record is None else record,
                          progress=progress, refine_to=refine_to, start=float(start), on_level=on_level, **changes)


def _ramp(model, g_from, g_to, steps, increments=10):
    """Move gravity from ``g_from`` to ``g_to`` in equal increments over ``steps`` steps."""
    if steps > 0:
        for i in range(1, increments):
            model.set_gravity(g_from + (g_to - g_from) * i / increments)
            model.cycle(max(1, steps // increments))
    model.set_gravity(g_to)
