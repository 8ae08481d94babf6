"""Searches for the load at which a model fails: one engine for every load parameter.

A load parameter (a g-level, a strength-reduction factor F, a tensile strength, a water depth)
is moved through ``levels``, each more severe than the one before (increasing or decreasing);
at each level the model is solved towards equilibrium and judged:

- ``Model.solve`` returns "failed" (displacement still growing without slowing down at the
  step limit, or a block moved more than ``failure_displacement`` during that level), or
- the largest block displacement during the level exceeds ``failure_displacement``, or
- the model blows up numerically (``ModelUnstable``) after the level's displacement record
  already passed one of these tests: the loose fragments of a failing slope move fast and can
  break the explicit scheme, but the slope failed first (``LimitRecord.blowups``). A blow-up
  before that ends the search with the verdict "unstable" and no failure level.

A level that ends "moving" (not in equilibrium but slowing down) or "settled" (stopped early
with ``settle``: no new crack and hardly any movement over two windows, ``monitor.settled``)
counts as stable; it is kept in the record so a reader can see how close the model came. The first failed level is
``failure_level``; the limit lies between it and ``last_stable_level``. With ``refine_to`` the
bracket is bisected from a snapshot of the last stable state (``Model.snapshot``) to that
width, then, if the failed level came from a larger step, the parameter is moved on from the
last stable state in steps of ``refine_to`` until a level fails: a change of load is applied
over a few hundred steps, much faster than a slender model's lowest period, so its dynamic
overshoot grows with the step, and the answer is that of a search in ``refine_to`` steps
(``gravity_ramp`` gives the measured case).

With ``judge="response"`` (``workflow.response``) a level is "equilibrium", "failing" (a failed
level) or "undecided": the search stops at an undecided level with no failure level
(``LimitRecord.undecided_level``; a bisection keeps the bracket it had), since nothing beyond it
can be judged from a state not known to stand. The model's response time N_r is measured before
the first level (if the model has none) and again after each level that stood, so each level is
judged over the response time of the structure the level before left.

``apply(model, level_from, level_to)`` moves the parameter (``gravity_ramp`` ramps g over a
few hundred steps; ``strength`` changes the strength table at once, which moves no stress).

Resuming: after a level with ``LimitRecord.resumable()`` true (every level so far stood, none
bisected), the model and the record are all the search depends on. Save both then (an
``on_level`` callback: ``Model.save`` and the record's fields); a search started from the loaded
model with ``record`` = the loaded record, ``start`` = its last level and the levels after it
gives the result of the search that was not stopped (``Model.load`` is exact).
"""
from __future__ import annotations

import json
import os
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..model import Model, ModelUnstable
from ..output.monitor import FAILED, SolveResult, verdict
from ..settings import SolveSettings

__all__ = ["LimitRecord", "search_failure", "check_levels", "save_resumable", "load_resumable",
           "remove_resumable"]


@dataclass
class LimitRecord:
    """What happened at each level of a search.

    parameter : name of the load parameter ("g", "F", a material property, ...);
    level : levels run; verdict : solve verdict per level; steps : steps per level;
    max_displacement : the largest displacement (m) in each level; point_ux, point_uy : name ->
    displacement (m) of each history point at the end of each level; cracks : total crack count
    after each level; failure_level : the first failed level (None if none failed);
    last_stable_level; seconds; unstable : None, or the ``ModelUnstable`` message when the model
    became numerically unstable while it was not failing (the level is recorded "unstable" and
    the search stops: a failure of the numerics, not of the rock, so no failure level);
    blowups : [level, message] of levels at which the model blew up *after* it had started to
    fail (recorded "failed"; the search goes on from the last stable state). Levels run by
    ``refine_to`` (bisection, then the closing steps) are appended in the order they were run;
    ``refined`` holds their number. undecided_level : the level judged "undecided"
    (``judge="response"``: neither at rest nor failing within the cap), at which the search
    stopped with no failure level; response_steps : the N_r each level was judged over
    (``judge="response"``; the measurements' steps: ``Model.measured_steps``).
    """

    parameter: str = "level"
    level: list = field(default_factory=list)
    verdict: list = field(default_factory=list)
    steps: list = field(default_factory=list)
    max_displacement: list = field(default_factory=list)
    point_ux: dict = field(default_factory=dict)
    point_uy: dict = field(default_factory=dict)
    cracks: list = field(default_factory=list)
    failure_level: float | None = None
    last_stable_level: float | None = None
    refined: int = 0
    seconds: float = 0.0
    unstable: str | None = None
    blowups: list = field(default_factory=list)
    undecided_level: float | None = None
    response_steps: list = field(default_factory=list)

    def resumable(self) -> bool:
        """True when a search can go on from the model as it is now with this record (module
        docstring): some level was run, all stood, none was bisected."""
        return (bool(self.level) and self.refined == 0 and self.unstable is None
                and not self.blowups and self.undecided_level is None
                and all(v not in ("failed", "failing", "unstable") for v in self.verdict))


def check_levels(levels, name="levels", positive=True) -> np.ndarray:
    """``levels`` as a float array; ValueError unless finite, (> 0 when ``positive``) and
    strictly monotone (a search moves one way)."""
    lv = np.asarray(list(levels), dtype=float)
    if lv.size == 0 or not np.all(np.isfinite(lv)) or (positive and np.any(lv <= 0)):
        raise ValueError(f"{name} must be finite{' and > 0' if positive else ''}, got "
                         f"{lv.tolist()}")
    d = np.diff(lv)
    if not (np.all(d > 0) or np.all(d < 0)):
        raise ValueError(f"{name} must increase or decrease strictly, got {lv.tolist()}")
    return lv


def search_failure(model, levels, apply, settings=None, *, record=None, progress=None,
                   refine_to=None, start=None, on_level=None, **changes) -> LimitRecord:
    """Move the load parameter through ``levels`` and judge each (module docstring).

    Parameters
    ----------
    model : dem_core.model.Model, with its boundary conditions set.
    levels : strictly monotone sequence, each level more severe than the one before.
    apply : callable(model, level_from, level_to) moving the parameter.
    settings : ``SolveSettings`` of each level (and/or its fields as keywords: ``ratio``,
        ``max_steps`` per level, ``failure_displacement`` (m; a block or watched point moving
        more than this in a level fails), ``creep``, ``watch``, ``settle``; ``Model.solve``).
    record : a LimitRecord (or subclass) to fill; default a new one.
    progress : callable(str), optional.
    refine_to : bracket width (in the parameter's units), optional.

    The search stops at the first failed level (the model is then in its failed state), or
    refines the bracket from there.
    start : the parameter's value before the first level (what ``apply`` moves from).
    on_level : callable(model, record), optional: called after each level is judged and
        recorded, before the search books it as its last stable or failed level (e.g. to save
        a resumable state, module docstring, or to write VTK files).
    """
    st = (settings or SolveSettings()).replace(**changes).validated("search")
    levels = check_levels(levels, "levels", positive=False)
    if refine_to is not None:
        if not (np.isfinite(refine_to) and refine_to > 0):
            raise ValueError(f"refine_to must be finite and > 0, got {refine_to}")
    missing = [n for n in st.watch if n not in model.points]
    if missing:          # before any step (the response time's measurement cycles the model)
        raise ValueError(f"no history point(s) {missing}; add them with add_history_point")
    remeasure = st.judge == "response" and st.response_steps is None
    if remeasure and model.response_steps is None:
        model.measure_response(st.watch)
    rec = record if record is not None else LimitRecord()
    t0 = time.perf_counter()
    now = float(levels[0] if start is None else start)
    stable_state = model.snapshot() if refine_to is not None else None
    running = [now, 0]                  # the level being run and its first step (unstable)

    def level(frm, to):
        """Run and record one level; True if it failed, None if undecided, else False."""
        running[:] = [to, model.step]
        apply(model, frm, to)
        failed, res = _judge(model, rec, to, st, progress)
        _record(rec, model, to, res, failed, progress)
        if res.response_steps is not None:
            rec.response_steps.append(res.response_steps)
        if res.verdict == "undecided":
            rec.undecided_level = float(to)
        elif remeasure and not failed:      # the next level from here: this structure's N_r
            model.measure_response(st.watch)
        if on_level is not None:
            on_level(model, rec)
        return None if res.verdict == "undecided" else failed

    try:
        _levels(rec, model, level, levels, now, refine_to, stable_state, start)
    except ModelUnstable as error:
        _record_unstable(rec, model, running[0], model.step - running[1], str(error), progress)
    rec.seconds += time.perf_counter() - t0         # a resumed search adds its part
    return rec


def _levels(rec, model, level, levels, now, refine_to, stable_state, start):
    """Run the levels, then refine the bracket (``_bisect``, ``_march``)."""
    frm_failed = now
    for v in levels:
        failed = level(now, float(v))
        frm_failed, now = now, float(v)
        if failed is None:                      # undecided: no answer beyond this level
            return
        if failed:
            rec.failure_level = float(v)
            break
        elif rec.failure_level is None:
            rec.last_stable_level = float(v)
            if refine_to is not None:
                stable_state = model.snapshot()
    if refine_to is not None and rec.failure_level is not None:
        low = rec.last_stable_level if rec.last_stable_level is not None else (
            float(levels[0]) if start is None else float(start))
        jump = _bisect(rec, model, level, stable_state, refine_to, low,
                       abs(rec.failure_level - frm_failed))
        if jump > refine_to * (1 + 1e-9):
            _march(rec, model, level, refine_to, low, float(levels[-1]))


def _judge(model, rec, value, settings, progress):
    """Solve one level; (failed, SolveResult). A blow-up of a level already failing is failure
    (recorded in ``rec.blowups``); any other blow-up propagates."""
    trace = ([0], [0.0])            # the solve's checks: steps, displacement (m)
    fd = settings.failure_displacement
    try:
        res = model.solve(settings, trace=trace)
    except ModelUnstable as error:
        res = _failing_before_blow_up(trace, fd, settings.creep)
        if res is None:
            raise
        rec.blowups.append([float(value), str(error)])
        if progress:
            progress(f"{rec.parameter} = {value:.4g}: the failing model blew up: {error}")
    failed = res.verdict in FAILED or (fd is not None and res.max_displacement > fd)
    return failed, res


def _bisect(rec, model, level, stable_state, refine_to, low, jump):
    """Narrow [last stable ``low``, failed] to ``refine_to`` from the stable state. Returns
    the step by which the failed level was reached (``jump`` for the level the bisection starts
    from) and leaves the model in the failed state, or in the last stable state when that step
    was larger than ``refine_to`` (``_march`` goes on)."""
    failed_state = model.snapshot()
    while abs(rec.failure_level - low) > refine_to * (1 + 1e-9):
        mid = 0.5 * (low + rec.failure_level)
        model.restore(stable_state)
        rec.refined += 1
        failed = level(low, mid)
        if failed is None:              # undecided: the bracket stays as it is
            break
        if failed:
            rec.failure_level, jump = mid, abs(mid - low)
            failed_state = model.snapshot()
        else:
            low = rec.last_stable_level = mid
            stable_state = model.snapshot()
    if rec.undecided_level is not None:
        model.restore(failed_state)
        return 0.0
    model.restore(stable_state if jump > refine_to * (1 + 1e-9) else failed_state)
    return jump


def _march(rec, model, level, step, low, end):
    """From the last stable state (the model's), move the parameter by ``step`` per level
    towards ``end`` until a level fails or ``end`` stands (then no failure level)."""
    low = rec.last_stable_level if rec.last_stable_level is not None else low
    sign = 1.0 if end > low else -1.0
    rec.failure_level = None
    while sign * (end - low) > 1e-12 * max(1.0, abs(end)):
        v = low + sign * min(step, abs(end - low))
        rec.refined += 1
        failed = level(low, v)
        if failed is None:
            return
        if failed:
            rec.failure_level = v
            return
        low = rec.last_stable_level = v


def _record_points_and_cracks(rec, model):
    """Append the history points' displacements and the total crack count."""
    for name in model.points:
        ux, uy, _, _ = model.point_motion(name)
        rec.point_ux.setdefault(name, []).append(ux)
        rec.point_uy.setdefault(name, []).append(uy)
    counts = model.crack_counts()
    rec.cracks.append(counts["tension"] + counts["shear"])


def _record(rec, model, value, res, failed, progress):
    rec.level.append(float(value))
    rec.verdict.append(res.verdict if res.verdict in FAILED else
                       "failed" if failed else res.verdict)
    rec.steps.append(res.steps)
    rec.max_displacement.append(res.max_displacement)
    _record_points_and_cracks(rec, model)
    if progress:
        progress(f"{rec.parameter} = {value:.4g}: {rec.verdict[-1]} after {res.steps} steps, "
                 f"ratio {res.ratio:.2e}, cracks {rec.cracks[-1]}")


def _record_unstable(rec, model, value, steps, message, progress):
    """The level at which the model became unstable: verdict "unstable", the steps run in it,
    no largest displacement (None: a blown-up block's is meaningless), the points as left."""
    rec.unstable = message
    rec.level.append(float(value))
    rec.verdict.append("unstable")
    rec.steps.append(int(steps))
    rec.max_displacement.append(None)
    _record_points_and_cracks(rec, model)
    if progress:
        progress(f"{rec.parameter} = {value:.4g}: numerically unstable, the search stops: "
                 f"{message}")


def _failing_before_blow_up(trace, failure_displacement, creep):
    """A "failed" SolveResult if the displacement record ``trace`` (steps, m) of a level
    that blew up already shows the slope failing, else None. Failing: beyond
    ``failure_displacement``, or still growing without slowing down (``monitor.verdict``, the
    test a level gets at its step limit). Judged on the checks before the blow-up only."""
    steps, disp = trace
    if len(steps) < 2:
        return None
    d = max(disp)
    if failure_displacement is not None and d > failure_displacement:
        return SolveResult("failed", steps[-1], float("nan"), d, "past the failure "
                           "displacement before the model blew up")
    v, why = verdict(steps, disp, 0.0 if creep is None else creep)
    if v != "failed":
        return None
    return SolveResult("failed", steps[-1], float("nan"), d, why + " (then the model blew up)")


def save_resumable(path, model, rec) -> bool:
    """Save a search that can go on from here (``rec.resumable()``): the model to
    ``<path>.npz`` (``Model.save``) and the record to ``<path>.json``, each written whole
    before it replaces the last; returns whether it saved. Use as an ``on_level`` callback:
    ``on_level=lambda m, r: save_resumable(path, m, r)``."""
    if not rec.resumable():
        return False
    state = asdict(rec)
    state["last_stable_level"] = rec.level[-1]      # as the search books it next
    stem = Path(path)
    part = stem.with_name(stem.name + ".part.npz")
    model.save(part)
    os.replace(part, stem.with_name(stem.name + ".npz"))
    text = json.dumps({"record": state, "step": int(model.step)},
                      default=lambda v: v.item())         # numpy scalars
    stem.with_name(stem.name + ".part.json").write_text(text)
    os.replace(stem.with_name(stem.name + ".part.json"), stem.with_name(stem.name + ".json"))
    return True


def load_resumable(path, record_type=LimitRecord):
    """(model, record) saved by ``save_resumable`` at ``path``, or None when there is none (or
    the two files are not of the same level: the run was killed between them)."""
    stem = Path(path)
    npz, js = stem.with_name(stem.name + ".npz"), stem.with_name(stem.name + ".json")
    if not (npz.exists() and js.exists()):
        return None
    saved = json.loads(js.read_text())
    model = Model.load(npz)
    if int(model.step) != saved["step"]:
        return None
    return model, record_type(**saved["record"])


def remove_resumable(path) -> None:
    """Delete the files of ``save_resumable`` at ``path`` (the search has finished)."""
    stem = Path(path)
    for suffix in (".npz", ".json", ".part.npz", ".part.json"):
        stem.with_name(stem.name + suffix).unlink(missing_ok=True)
