"""Centrifuge loading: raise the g-level step by step until the model fails.

At each g-level the model is solved towards equilibrium (``Model.solve``); the first level at
which it does not come to equilibrium *and* is judged failed is the failure g-level:

- ``Model.solve`` returns "failed" (displacement still growing without slowing down at the
  step limit, or a block moved more than ``failure_displacement`` during that level), or
- the largest block displacement during the level exceeds ``failure_displacement``, or
- the model blows up numerically (``ModelUnstable``) after the level's displacement record
  already passed one of these tests: the loose fragments of a failing slope move fast and can
  break the explicit scheme, but the slope failed first (``RampRecord.blowups``). A blow-up
  before that ends the ramp with the verdict "unstable" and no failure g.

A level that ends "moving" (not in equilibrium but slowing down) counts as stable; it is kept in
the record so a reader can see how close the model came. The thesis raised gravity 1 g at a time
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

import time
from dataclasses import dataclass, field

import numpy as np

from .model import ModelUnstable
from .monitor import SolveResult, verdict

__all__ = ["RampRecord", "raise_gravity"]


@dataclass
class RampRecord:
    """What happened at each g-level.

    g : g-levels run; verdict : solve verdict per level; steps : steps per level;
    point_ux, point_uy : name -> horizontal / vertical displacement (m) of each history point at
    the end of each level; cracks : total crack count after each level;
    failure_g : the first failed g-level (None if none failed); last_stable_g; seconds;
    unstable : None, or the ``ModelUnstable`` message when the model became numerically
    unstable while the slope was not failing (the level is recorded with verdict "unstable"
    and the ramp stops there; that is a failure of the numerics, not of the slope, so it sets
    no failure_g).
    blowups : [g, message] of levels at which the model blew up *after* the slope had started
    to fail: the displacement record of the level up to the blow-up already passes the
    failure test (``failure_displacement``, or ``monitor.verdict``: still growing without
    slowing down), so the level is recorded "failed" and the ramp goes on as after any failure
    (bisection restarts from the last stable state). Loose fragments of a failing slope move
    fast and can blow up the explicit scheme (docs/mechanics.md); the slope's failure came
    first.
    Levels run by ``refine_to`` (bisection, then the closing steps) are appended in the order
    they were run, so ``g`` is then no longer increasing; ``refined`` holds their number.
    """

    g: list = field(default_factory=list)
    verdict: list = field(default_factory=list)
    steps: list = field(default_factory=list)
    max_displacement: list = field(default_factory=list)
    point_ux: dict = field(default_factory=dict)
    point_uy: dict = field(default_factory=dict)
    cracks: list = field(default_factory=list)
    failure_g: float | None = None
    last_stable_g: float | None = None
    refined: int = 0
    seconds: float = 0.0
    unstable: str | None = None
    blowups: list = field(default_factory=list)


def raise_gravity(model, g_levels, ratio=1e-4, max_steps=20_000, failure_displacement=None,
                  progress=None, stop_at_failure=True, ramp_steps=400, creep=None,
                  watch=None, refine_to=None) -> RampRecord:
    """Solve the model at each g-level in turn (module docstring); return the record.

    Parameters
    ----------
    model : dem_core.model.Model, with its boundary conditions set.
    g_levels : increasing sequence of g-levels (multiples of 9.81 m/s^2).
    ratio : unbalanced-force ratio that counts as equilibrium.
    max_steps : step limit per level.
    failure_displacement : m. A block moving more than this during one level is failure.
    progress : callable(str), optional.
    stop_at_failure : stop at the first failed level (the model is then in its failed state).
    creep : m, passed to ``Model.solve``: a displacement increment below this over the last
        fifth of a level's steps is not "still moving" (slender models creep towards
        equilibrium slowly; a small creep value calls that failure).
    watch : sequence of history-point names, optional. Judge failure by the motion of these
        points (e.g. the crest and the face of a slope) instead of the largest displacement of
        any block, so that a loose block at a model boundary does not count as the failure of
        the slope. ``failure_displacement`` and ``creep`` then apply to the points.
    ramp_steps : steps over which g moves from one level to the next in 10 equal increments,
        so that a level is not applied as a sudden load (whose dynamic overshoot would break
        bonds a quasi-static load does not). 0 applies each level at once.
    refine_to : g, optional. After the first failure, bisect between the last stable and the
        failed level until they are at most this far apart; then, if the failed level was
        reached by a larger step than ``refine_to``, raise g from the last stable state in steps
        of ``refine_to`` until a level fails (or the last of ``g_levels`` stands). The failure g
        is then that of a ramp in ``refine_to`` steps (module docstring). Needs
        ``stop_at_failure``.
    """
    levels = np.asarray(list(g_levels), dtype=float)
    if levels.size == 0 or not np.all(np.isfinite(levels)) or np.any(levels <= 0):
        raise ValueError(f"g_levels must be finite and > 0, got {levels.tolist()}")
    if np.any(np.diff(levels) <= 0):
        raise ValueError("g_levels must increase")
    if refine_to is not None:
        if not (np.isfinite(refine_to) and refine_to > 0):
            raise ValueError(f"refine_to must be finite and > 0 (g), got {refine_to}")
        if not stop_at_failure:
            raise ValueError("refine_to needs stop_at_failure=True")
    rec = RampRecord()
    t0 = time.perf_counter()
    g_now = 0.0
    stable_state = model.snapshot() if refine_to is not None else None

    def level(g_from, g):
        running[:] = [g, model.step]
        trace = ([0], [0.0])            # the solve's checks: steps, displacement (m)
        _ramp(model, g_from, g, ramp_steps)
        try:
            if watch:
                res = _solve_watching(model, list(watch), ratio, max_steps,
                                      failure_displacement, creep, trace=trace)
            else:
                res = model.solve(ratio=ratio, max_steps=max_steps,
                                  failure_displacement=failure_displacement, creep=creep,
                                  trace=trace)
        except ModelUnstable as error:
            res = _failing_before_blow_up(trace, failure_displacement, creep)
            if res is None:
                raise
            rec.blowups.append([float(g), str(error)])
            if progress:
                progress(f"g = {g:5.1f}: the failing slope blew the model up: {error}")
        failed = res.verdict == "failed" or (
            failure_displacement is not None and res.max_displacement > failure_displacement)
        _record(rec, model, g, res, failed, progress)
        return failed

    running = [0.0, 0]                  # the level being run and its first step (unstable)
    try:
        g_from_failure = 0.0
        for g in levels:
            failed = level(g_now, float(g))
            g_from_failure, g_now = g_now, float(g)
            if failed:
                rec.failure_g = float(g)
                # a blown-up model cannot be loaded further (bisection restarts from a copy)
                if stop_at_failure or (rec.blowups and rec.blowups[-1][0] == g):
                    break
            elif rec.failure_g is None:
                rec.last_stable_g = float(g)
                if refine_to is not None:
                    stable_state = model.snapshot()
        if refine_to is not None and rec.failure_g is not None:
            step_to_failure = _bisect(rec, model, level, stable_state, refine_to,
                                      rec.failure_g - g_from_failure)
            if step_to_failure > refine_to * (1 + 1e-9):
                _march(rec, model, level, refine_to, float(levels[-1]))
    except ModelUnstable as error:
        _record_unstable(rec, model, running[0], model.step - running[1], str(error),
                         progress)
    rec.seconds = time.perf_counter() - t0
    return rec


def _bisect(rec, model, level, stable_state, refine_to, step_to_failure):
    """Narrow [last stable, failed] to ``refine_to`` g from the stable state (docstring).
    Returns the step (g) by which the failed level was reached (``step_to_failure``: that of
    the level the bisection starts from) and leaves the model in the failed state, or in the
    last stable state when that step was larger than ``refine_to`` (``_march`` goes on)."""
    failed_state = model.snapshot()
    low = rec.last_stable_g or 0.0
    while rec.failure_g - low > refine_to * (1 + 1e-9):
        mid = 0.5 * (low + rec.failure_g)
        model.restore(stable_state)
        rec.refined += 1
        if level(low, mid):
            rec.failure_g, step_to_failure = mid, mid - low
            failed_state = model.snapshot()
        else:
            low = rec.last_stable_g = mid
            stable_state = model.snapshot()
    model.restore(stable_state if step_to_failure > refine_to * (1 + 1e-9) else failed_state)
    return step_to_failure


def _march(rec, model, level, step, top):
    """From the last stable state (the model's), raise g by ``step`` per level until one fails
    or ``top`` stands: the failure g of a ramp in ``step`` increments (module docstring). No
    failure up to ``top`` leaves ``failure_g`` None."""
    low = rec.last_stable_g or 0.0
    rec.failure_g = None
    while low < top * (1 - 1e-12):
        g = min(low + step, top)
        rec.refined += 1
        if level(low, g):
            rec.failure_g = g
            return
        low = rec.last_stable_g = g


def _record_points_and_cracks(rec, model):
    """Append the history points' displacements and the total crack count."""
    for name in model.points:
        ux, uy, _, _ = model.point_motion(name)
        rec.point_ux.setdefault(name, []).append(ux)
        rec.point_uy.setdefault(name, []).append(uy)
    counts = model.crack_counts()
    rec.cracks.append(counts["tension"] + counts["shear"])


def _record(rec, model, g, res, failed, progress):
    rec.g.append(float(g))
    rec.verdict.append("failed" if failed else res.verdict)
    rec.steps.append(res.steps)
    rec.max_displacement.append(res.max_displacement)
    _record_points_and_cracks(rec, model)
    if progress:
        progress(f"g = {g:5.1f}: {rec.verdict[-1]} after {res.steps} steps, "
                 f"ratio {res.ratio:.2e}, cracks {rec.cracks[-1]}")


def _record_unstable(rec, model, g, steps, message, progress):
    """The level at which the model became unstable: verdict "unstable", the steps run in it,
    no largest displacement (None: a blown-up block's is meaningless), the points as left."""
    rec.unstable = message
    rec.g.append(float(g))
    rec.verdict.append("unstable")
    rec.steps.append(int(steps))
    rec.max_displacement.append(None)
    _record_points_and_cracks(rec, model)
    if progress:
        progress(f"g = {g:5.1f}: numerically unstable, the ramp stops: {message}")


def _ramp(model, g_from, g_to, steps, increments=10):
    """Move gravity from ``g_from`` to ``g_to`` in equal increments over ``steps`` steps."""
    if steps > 0:
        for i in range(1, increments):
            model.set_gravity(g_from + (g_to - g_from) * i / increments)
            model.cycle(max(1, steps // increments))
    model.set_gravity(g_to)


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


def _solve_watching(model, names, ratio, max_steps, failure_displacement, creep, chunk=None,
                    trace=None):
    """``Model.solve`` with the displacement test on history points ``names`` (see
    ``raise_gravity``): equilibrium at ``ratio``, failed when a point moved more than
    ``failure_displacement`` in this level or, at the step limit, by ``monitor.verdict`` on the
    points' displacement. ``trace``: optional (steps, displacements) lists the checks are
    appended to (read after a ``ModelUnstable``)."""
    missing = [n for n in names if n not in model.points]
    if missing:
        raise ValueError(f"no history point(s) {missing}; add them with add_history_point")
    chunk = int(chunk or max(model.history.every, 100))
    start = np.array([model.point_motion(n)[:2] for n in names])
    steps, disp = trace if trace is not None else ([0], [0.0])
    done, r = 0, float("inf")
    creep = 0.0 if creep is None else creep
    while done < max_steps:
        k = min(chunk, max_steps - done)
        model.cycle(k)
        done += k
        r = model.unbalanced_ratio()
        now = np.array([model.point_motion(n)[:2] for n in names])
        d = float(np.hypot(*(now - start).T).max())
        steps.append(done)
        disp.append(d)
        if r <= ratio:
            return SolveResult("equilibrium", done, r, max(disp), f"ratio {r:.3g} <= {ratio:.3g}")
        if failure_displacement is not None and d > failure_displacement:
            return SolveResult("failed", done, r, d, f"a watched point moved {d:.3g} m > "
                               f"{failure_displacement} m")
    v, why = verdict(steps, disp, creep)
    return SolveResult(v, done, r, max(disp), why)
