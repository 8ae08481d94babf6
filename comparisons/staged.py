"""What the field-slope cases share (thesis chapters 5-7): one scene's stage list run as a sweep
member, its result as plain data, and the figures of a strength search.

A field case's run is a ``dem_core.workflow.scene.Scene`` with all its stages: gravity (and an in-situ
stress), a solve, excavations, and usually a search stage at the end (``strength_schedule``:
the flaws' tensile strength lowered until the slope fails; ``factor_of_safety``). ``stage_run``
runs it (``dem_core.workflow.stages.run_stages``), reports progress per stage and per level of a search
(``comparisons.progress.report``, shown by the sweep), and returns:

- ``label``, ``params`` (the member's, unchanged), ``blocks``, ``contacts``, ``runtime_s``,
  ``measure_steps`` (the steps the response-time measurements ran, ``Model.measure_response``),
  ``critical_dt_start`` (s: the built model's critical step, ``Model.critical_dt``, before any
  stage);
- ``stages``: per stage kind, verdict, steps, wall seconds, the model time at its end (s),
  each monitoring point's (ux, uy) (m) and the crack counts (tension, shear);
- ``point_history`` when the member asks for it (``member["point_history"]``): the model's
  histories of time (s) and each monitoring point's ux and uy (m), recorded every
  ``history_every`` steps over the whole run (e.g. to compare two runs at the same model time
  within a failing stage, where the stage's end is where its judge stopped);
- ``search``: the last search stage's levels, verdicts, steps and each point's ux and uy per
  level (m), its ``parameter``, ``last_stable`` and ``failure`` values (None when nothing
  failed), ``unstable`` and ``blowups`` (as ``limit.LimitRecord``); None without a search;
- ``searches``: every search stage's record in the same form, in stage order (a run with two
  schedules, e.g. the tensile strength and then the cohesion, keeps both);
- ``cracks``, ``crack_xy``, ``crack_mode`` (1 tension, 2 shear), ``crack_material``: the broken
  bonds of the materials whose names start with one of ``crack_materials`` (default the intact
  rock: flaws and region boundaries);
- ``picture``: ``dem_core.output.plot.block_picture`` of the final state (the failed state when the
  search failed), with those cracks and the joints.

``stop_on_failure`` (default: the scene's ``after_failure``, "stop" unless the scene says
"continue") ends the run after the first stage that leaves the model failed or undecided
(``dem_core.workflow.stages.stops``: a solve that did not come to equilibrium, or a search that
failed), so an "excavate until failure" sequence (Excavate, Solve, Excavate, Solve, ...) costs
only the stages up to its critical height; ``stages`` then lists only the stages that ran (the
index of each is its place in the scene's list).

A member is a plain dict (``label``, ``params`` and anything the case's member function reads);
inside a case run ``store`` keeps each finished member, so a stopped sweep loses only the
members still running (``comparisons.sweep``). The rupture surface is added by the case
(``comparisons.centrifuge.rupture``: it needs the case's face and joint dip).
"""
from __future__ import annotations

import dataclasses
import time

import numba
import numpy as np

from comparisons.progress import ramp_status, report
from dem_core.output.plot import block_picture
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import STOPS, check_stages, run_stages

__all__ = ["INTACT", "stage_run", "settled_stages", "judged_stages", "search_rows",
           "history_figure", "coincident_rims", "curve_styles", "value_at_failure",
           "judge_note"]

INTACT = ("flaw:", "boundary:")        # bonds through intact rock (not joints)
_SEARCH_KEYS = ("search", "ramp")
_PLANS = ("values", "f_levels", "g_levels")


def stage_run(sc, member: dict, crack_materials=INTACT, stop_on_failure=None,
              poses=False, read=None, **model_options) -> dict:
    """Build the DEM model of scene ``sc`` and run its stages (module docstring). ``member``:
    the sweep member (``label``, ``params``; ``threads`` optional, capped at numba's;
    ``solver`` optional: Model options over the scene's, e.g. ``{"step_estimate": "eigen"}``,
    the case's ``solver`` setting; ``settle`` optional: True stops every solve and every level
    of a search that can settle early once settled, ``settled_stages``; ``judge`` and
    ``windows`` optional: every solve and search judged so, ``judged_stages``).
    ``stop_on_failure``: end after the first failed stage (module docstring; None: the
    scene's ``after_failure``).
    ``poses``: also return ``poses``, the blocks' (pos (nb, 2) m, theta (nb,) rad) after each
    stage that ran, as arrays (e.g. what moved during one stage).
    ``model_options`` override the scene's solver (``build_model``)."""
    t0 = time.perf_counter()
    threads = min(int(member.get("threads", 1)), numba.config.NUMBA_NUM_THREADS)
    model = build_model(sc, **{"threads": threads, **member.get("solver", {}), **model_options})
    critical_dt = float(model.critical_dt)     # of the built model, before any stage
    check_stages(sc.stages, set(model.blocks.groups), model.materials)
    n, finished, pose_log, reads = len(sc.stages), [], [], []

    def on_stage(message):          # after each stage
        finished.append(message)
        if poses:
            pose_log.append((model.state.pos.copy(), model.state.theta.copy()))
        if read is not None:
            reads.append(read(model))
        report(f"{message} ({len(finished)}/{n} stages)", 0, elapsed=time.perf_counter() - t0)

    def on_level(i, stage, m, rec):  # after each level of a search stage
        plan = next(getattr(stage, k) for k in _PLANS if hasattr(stage, k))
        text, left = ramp_status(rec, [float(v) for v in plan], time.perf_counter() - t0,
                                 stage.refine_to)
        report(f"stage {i} {text}", int(np.sum(rec.steps)), left,
               elapsed=time.perf_counter() - t0)

    stages = settled_stages(sc.stages) if member.get("settle") else sc.stages
    if "judge" in member:
        stages = judged_stages(stages, member["judge"], member.get("windows"))
    stop = sc.after_failure == "stop" if stop_on_failure is None else stop_on_failure
    out_records = run_stages(model, stages, progress=on_stage, on_level=on_level,
                             after_failure="stop" if stop else "continue")
    log = model.crack_log()
    keep = np.array([str(m).startswith(tuple(crack_materials)) for m in log["material"]],
                    bool)
    return {
        "label": member["label"], "params": member["params"],
        "blocks": int(model.blocks.n_blocks), "contacts": int(model.contacts.n),
        "critical_dt_start": critical_dt,
        "stages": [{"kind": r.kind, "verdict": r.verdict, "steps": int(r.steps),
                    "seconds": float(r.seconds), "time": float(r.time),
                    "points": {k: list(v) for k, v in r.points.items()},
                    "cracks": dict(r.cracks)} for r in out_records],
        "search": _search(out_records),
        "searches": [_search([r]) for r in out_records if _search([r]) is not None],
        "cracks": int(keep.sum()),
        "crack_xy": np.column_stack([log["x"][keep], log["y"][keep]]).tolist(),
        "crack_mode": np.asarray(log["mode"])[keep].tolist(),
        "crack_material": [str(m) for m in np.asarray(log["material"])[keep]],
        "picture": block_picture(model, cracks=tuple(crack_materials), joints="joint:"),
        "runtime_s": time.perf_counter() - t0,
        "measure_steps": int(getattr(model, "measured_steps", 0)),
        **({"poses": pose_log} if poses else {}),
        **({"reads": reads} if read is not None else {}),
        **({"point_history": point_history(model)} if member.get("point_history") else {}),
    }


def point_history(model) -> dict:
    """The model's recorded time (s) and each monitoring point's ux and uy (m), as lists."""
    h = model.history.as_arrays()
    keep = ["time"] + [f"{n}.{c}" for n in model.points for c in ("ux", "uy")]
    return {k: h[k].tolist() for k in keep if k in h}


def judge_note(judge, budget: str, failure_displacement=None, what="a block") -> str:
    """The report's sentence on what a failed solve or level means under ``judge``:
    "response" (``dem_core.workflow.response``) or "budget" (``budget``: the case's own
    sentence on its step budget, e.g. "no equilibrium within 40000 steps")."""
    past = (f"{what} moves more than {failure_displacement} m in it, or "
            if failure_displacement is not None else "")
    if judge == "budget":
        return f"Failure at a solve or level (budget judge): {past}{budget}."
    return ("Failure at a solve or level (response judge, docs/mechanics.md): " + past
            + "a mechanism seen twice over windows of the model's measured response time "
              "('failing'), or neither at rest nor a mechanism within the cap ('undecided'); "
              "neither counts as standing, and no step budget is in the answer.")


def judged_stages(stages, judge, windows=None) -> list:
    """The stages with ``judge`` (and ``windows``, if given) wherever a stage has that
    setting (solves, g-ramps, strength searches; ``dem_core.settings.SolveSettings``)."""
    changes = {"judge": judge, **({} if windows is None else {"windows": int(windows)})}
    return [dataclasses.replace(st, **changes)
            if dataclasses.is_dataclass(st) and
            any(f.name == "judge" for f in dataclasses.fields(st)) else st
            for st in stages]


def settled_stages(stages) -> list:
    """The stages with ``settle=True`` wherever a stage has that option (solves, g-ramps,
    strength searches): each ends a solve or level early as "settled" once its displacement
    has stopped growing and no bond broke (``dem_core.output.monitor.settled``)."""
    return [dataclasses.replace(st, settle=True)
            if dataclasses.is_dataclass(st) and
            any(f.name == "settle" for f in dataclasses.fields(st)) else st
            for st in stages]


def _search(records) -> dict | None:
    """The last search stage's record as plain data (module docstring)."""
    for r in reversed(records):
        rec = next((r.detail[k] for k in _SEARCH_KEYS if k in r.detail), None)
        if rec is None:
            continue
        return {"stage": r.index, "kind": r.kind, "parameter": rec.parameter,
                "level": [float(v) for v in rec.level], "verdict": list(rec.verdict),
                "steps": [int(v) for v in rec.steps],
                "point_ux": {k: [float(v) for v in vals] for k, vals in rec.point_ux.items()},
                "point_uy": {k: [float(v) for v in vals] for k, vals in rec.point_uy.items()},
                "cracks": [int(v) for v in rec.cracks],
                "last_stable": rec.last_stable_level, "failure": rec.failure_level,
                "unstable": rec.unstable, "blowups": list(rec.blowups)}
    return None


def stopped_before_search(run: dict) -> dict | None:
    """The stage that ended a run before its search (strength schedule, ramp) could run,
    as {"stage", "kind", "verdict"} (its verdict one of ``stages.STOPS``), or None when the
    search ran or no stage stopped. Such a run failed at the strengths it had then; it never
    stood."""
    if run.get("search") is not None:
        return None
    hit = next(((i, st) for i, st in enumerate(run["stages"]) if st["verdict"] in STOPS), None)
    return None if hit is None else {"stage": hit[0], "kind": hit[1]["kind"],
                                     "verdict": hit[1]["verdict"]}


def value_at_failure(run: dict):
    """(last stable value, first failed value) of a run's search (None, None without one)."""
    s = run.get("search")
    return (None, None) if s is None else (s["last_stable"], s["failure"])


def search_rows(run: dict, point: str, component: str = "ux") -> np.ndarray:
    """(n, 2) rows (level, displacement of ``point`` in m) of a run's search levels, in the
    order the levels were run."""
    s = run.get("search")
    if not s or point not in s["point_" + component]:
        return np.zeros((0, 2))
    return np.column_stack([s["level"], s["point_" + component][point]])


def history_figure(runs: list, points: tuple, scale: float = 1e-6, unit: str = "MPa",
                   component: str = "ux", xlabel: str | None = None):
    """Each run's watched points' displacement (mm) against its search parameter (divided by
    ``scale`` for the axis, in ``unit``), with the parameter's axis reversed when the search
    lowers it (a strength schedule reads left to right as the rock weakens); the failed level
    of each run is marked with a cross. A curve that coincides with a later run's (the same
    levels, displacements within 1 % of the largest: the same answer) is drawn wider underneath
    it, one rim per later run, so no run disappears behind another."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5))
    colours = plt.get_cmap("tab10" if len(runs) <= 10 else "tab20")
    searched = [(n, r) for n, r in enumerate(runs) if r.get("search")]   # n: the colour
    lowering = any(r["search"]["kind"] == "strength_schedule" for _, r in searched)
    for p, style in zip(points, ("-o", ":s", "--^", "-.v")):
        curves = [search_rows(r, p, component) for _, r in searched]
        curves = [c[np.argsort(c[:, 0])] for c in curves]
        for (n, r), rows, line in zip(searched, curves, curve_styles(curves)):
            if not len(rows):
                continue
            s, colour = r["search"], colours(n)
            ax.plot(rows[:, 0] / scale, 1e3 * rows[:, 1], style, color=colour,
                    label=f"{p}, {r['label']}", **line)
            if s["failure"] is not None:
                k = np.flatnonzero(np.asarray(s["level"]) == s["failure"])
                if k.size:              # the cross as wide as its curve's rims
                    ax.plot(s["failure"] / scale, 1e3 * s["point_" + component][p][k[0]],
                            "x", ms=9 + 1.6 * (line["ms"] - 3), mew=1.5 + 0.8 * (line["lw"] - 1.5),
                            color=colour, zorder=line["zorder"])
    if lowering:
        ax.invert_xaxis()
    ax.set_xlabel(xlabel or f"search parameter ({unit}); x: first failed level")
    ax.set_ylabel(f"{'horizontal' if component == 'ux' else 'vertical'} displacement (mm)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return fig


def coincident_rims(curves: list) -> list:
    """For each (n, 2) curve (x, y rows), how many later curves have the same x and y within
    1 % of the largest |y|: a figure draws a curve that wide underneath the later ones it
    coincides with, so every run stays visible (``history_figure``)."""
    top = max([float(np.abs(c[:, 1]).max()) for c in curves if len(c)] + [0.0])
    return [sum(1 for d in curves[i + 1:] if len(c) and d.shape == c.shape
                and np.array_equal(d[:, 0], c[:, 0])
                and np.allclose(d[:, 1], c[:, 1], rtol=0.0, atol=0.01 * top))
            for i, c in enumerate(curves)]


def curve_styles(curves: list) -> list:
    """matplotlib line options (marker size, line width, z-order) for each run's curve, in
    drawing order: one rim wider per later curve it coincides with (``coincident_rims``)."""
    return [dict(ms=3 + 2.5 * rim, lw=1.5 + 2.5 * rim, zorder=2 + i)
            for i, rim in enumerate(coincident_rims(curves))]
