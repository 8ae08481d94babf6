"""Results at a glance for a scene run (``comparisons.run_scene``): the model at the end of a
stage, the failure search of a search stage, and the monitoring points' history.

- ``stage_figure(scene, model, record)``: the model as it is when stage ``record`` ended (drawn
  right then, by ``run_scene.run_prepared``): blocks moved by their displacement times a
  magnification and coloured by the true displacement, joints, the cracks through intact rock
  by mode, support, the water table the model has, the monitoring points; the title names the
  stage, its verdict, which state of a search is drawn (``search_state``) and the crack counts
  of ``stages.csv`` with what of them is drawn (``crack_counts_text``).
- ``search_figure(record)``: a search's levels (a ``limit.LimitRecord``: F, g or a strength)
  against the largest displacement in each level and each monitoring point's displacement
  since the start, each level's marker by its verdict, the last level that stood and the first
  that failed marked.
- ``history_figure(records, points, history)``: each monitoring point's displacement against
  the steps (the model's history, ``monitor.History``, every ``history_every`` steps) with the
  stage ends marked, or at the end of each stage when the model kept no history.

Displacements are drawn in mm, positions in m.
"""
from __future__ import annotations

import textwrap

import numpy as np

from comparisons.staged import INTACT
from dem_core.workflow.stages import STOPS

__all__ = ["stage_figure", "state_figure", "search_figure", "history_figure", "search_record",
           "search_state", "crack_counts_text", "draw_water_table", "VERDICT_STYLE",
           "PARAMETER_LABEL", "stage_picture", "search_picture", "HISTORY_PICTURE"]

HISTORY_PICTURE = "history.png"
SEARCH_KEYS = ("search", "ramp")            # a stage's LimitRecord in its detail

# a level's verdict -> (marker, face colour, legend words); edge colour black
VERDICT_STYLE = {"equilibrium": ("o", "tab:green", "stands (equilibrium)"),
                 "settled": ("s", "yellowgreen", "stands (settled)"),
                 "moving": ("^", "white", "stands (still moving, slowing)"),
                 "failed": ("X", "tab:red", "failed"),
                 "failing": ("X", "tab:red", "failing"),
                 "undecided": ("D", "orange", "undecided"),
                 "unstable": ("*", "black", "numerically unstable (no displacement)")}

PARAMETER_LABEL = {"F": "strength-reduction factor F", "g": "g-level (x 9.81 m/s²)",
                   "tensile_strength": "tensile strength (Pa)", "cohesion": "cohesion (Pa)",
                   "friction": "friction angle (deg)"}


def stage_picture(record) -> str:
    """The file of a stage's picture: ``stage<i>_<kind>.png``."""
    return f"stage{record.index}_{record.kind}.png"


def search_picture(record) -> str:
    """The file of a search stage's search plot: ``stage<i>_search.png``."""
    return f"stage{record.index}_search.png"


def _wrap(text, width=78) -> str:
    """Each line of ``text`` wrapped to ``width`` characters (a title as wide as its axes)."""
    return "\n".join(textwrap.fill(t, width) or t for t in text.split("\n"))


def _level(parameter, value) -> str:
    """A level as words: "F = 1.15", "60 g", "tensile_strength = 4e+05"."""
    return f"{value:g} g" if parameter == "g" else f"{parameter} = {value:.4g}"


def draw_water_table(ax, surface, xs, **style):
    """The water table ``surface`` (a level or [[x, y], ...], m; ``workflow.water``) over
    ``xs`` (m) as a blue line on ``ax``; ``style`` as ``ax.plot``'s. Returns the line."""
    from dem_core.workflow.water import surface_height

    xs = np.asarray(xs, float)
    line, = ax.plot(xs, surface_height(surface, xs), "-", **{"color": "tab:blue", "lw": 1.8,
                                                              **style})
    return line


def search_record(record):
    """The ``LimitRecord`` of a search stage's ``StageRecord`` (detail "search" or "ramp"), or
    None for any other stage."""
    return next((record.detail[k] for k in SEARCH_KEYS if k in record.detail), None)


def search_state(lr) -> str:
    """Which state a search (``LimitRecord`` ``lr``) leaves the model in (``limit``): the first
    failed level's failed state (a bisection restores it), else the level where it stopped
    undecided or blew up, else the last level, which stood."""
    p = lr.parameter
    if lr.failure_level is not None:
        return (f"state drawn: at {_level(p, lr.failure_level)}, the first failed level (the "
                f"search ends in that failed state)")
    if lr.unstable and lr.level:
        return (f"state drawn: as the model was left when it became numerically unstable at "
                f"{_level(p, lr.level[-1])} (blocks that blew up are not drawn)")
    if lr.undecided_level is not None:
        return (f"state drawn: at {_level(p, lr.undecided_level)}, judged undecided (the "
                f"search stopped there)")
    if lr.level:
        return f"state drawn: at {_level(p, lr.level[-1])}, the last level (it stood)"
    return "state drawn: no level ran"


def crack_counts_text(model, counts=None) -> str:
    """The bond failures so far (``counts``: {"tension", "shear"}, as stages.csv; default the
    model's) and which of them a picture draws: the intact rock's as red (tension) and blue
    (shear) edges, a joint's counted but not drawn."""
    counts = counts or model.crack_counts()
    log = model.crack_log()
    intact = np.array([str(m).startswith(INTACT) for m in log["material"]], bool)
    t, s = (int(np.sum(intact & (log["mode"] == mode))) for mode in (1, 2))
    text = (f"bond failures so far: {counts['tension']} tension, {counts['shear']} shear (as "
            f"stages.csv); drawn: the intact rock's {t} tension (red), {s} shear (blue); "
            f"{int(np.sum(~intact))} on joints not drawn")
    unlogged = counts["tension"] + counts["shear"] - len(log["mode"])
    return text + (f"; {unlogged} beyond the crack log's size not drawn" if unlogged > 0 else "")


def state_figure(scene, model, headline, extra=(), counts=None):
    """The model as it is now: blocks moved by their displacement x the magnification in the
    title (``dem_core.output.plot``), coloured by the true displacement (mm), joints, the
    cracks through intact rock (``INTACT``) by mode, support, the model's water table, the
    monitoring points (moved the same way). The title: ``headline``, the lines ``extra``, the
    magnification and ``crack_counts_text``, wrapped to the axes."""
    import matplotlib.pyplot as plt

    from dem_core.output.plot import block_picture, magnification, plot_model

    fig, ax = plt.subplots(figsize=(9, 6.5))
    pic = block_picture(model, cracks=(), joints=())
    k = magnification(pic)
    still = not np.any(np.asarray(pic["pos"]) != np.asarray(pic["pos0"]))
    plot_model(model, ax, displacement_scale=k, crack_lines=True, joints="joint:",
               crack_materials=INTACT, unit="mm", colour_limit=1.0 if still else None)
    for name in model.points:                       # where they are, as drawn
        x0, y0 = model.points[name][2]
        ux, uy = model.point_motion(name)[:2]
        ax.plot(x0 + k * ux, y0 + k * uy, "k^")
        ax.annotate(name, (x0 + k * ux, y0 + k * uy), xytext=(5, 5), textcoords="offset points",
                    fontsize=9, bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="0.5",
                                          alpha=0.8))
    table = getattr(model, "water", None)
    if table is not None and table.surface is not None:
        x = np.asarray(model.blocks.vertices)[:, 0]
        draw_water_table(ax, table.surface, np.linspace(x.min(), x.max(), 200),
                         label=f"water table (on {table.on})")
    lines = [headline, *extra, "no block has moved yet" if still else
             f"displacement drawn x {k:g} (colour: true displacement, mm)",
             crack_counts_text(model, counts)]
    ax.set_title(_wrap("\n".join(lines)), fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="lower left")
    return fig


def stage_figure(scene, model, record, verdict=None):
    """The model at the end of stage ``record`` (a ``StageRecord``; ``model`` as that stage
    left it): ``state_figure`` titled with the scene, the stage's index, kind and ``verdict``
    (words, default the record's verdict) and, for a search, which state is drawn
    (``search_state``)."""
    lr = search_record(record)
    head = (f"{scene.name}: end of stage {record.index} of {len(scene.stages)} "
            f"({record.kind}): {verdict or record.verdict}")
    return state_figure(scene, model, head, [search_state(lr)] if lr is not None else [],
                        record.cracks)


def _bracket(ax, lr, legend=True):
    """The last level that stood (green) and the first that failed (red), dashed, and the
    bracket between them shaded; in the legend when ``legend``."""
    lo, hi = lr.last_stable_level, lr.failure_level
    for v, colour, words in ((lo, "tab:green", "last stable"), (hi, "tab:red", "first failed")):
        if v is not None:
            ax.axvline(v, color=colour, ls="--", lw=1,
                       label=f"{words}: {_level(lr.parameter, v)}" if legend else None)
    if lo is not None and hi is not None:
        ax.axvspan(min(lo, hi), max(lo, hi), color="0.9", zorder=0)


def _by_verdict(ax, levels, values, verdicts, colour=None, legend=True):
    """One marker line per verdict (gid "verdict:<v>"): the levels' (x) values (y); the
    marker's face the verdict's colour, or ``colour`` (a point's) for a level that stood."""
    for v in dict.fromkeys(verdicts):
        marker, face, words = VERDICT_STYLE.get(v, ("s", "0.5", v))
        k = [i for i, w in enumerate(verdicts) if w == v]
        stood = v not in STOPS
        ax.plot(np.asarray(levels)[k], np.asarray(values, float)[k], marker, ls="",
                mfc=colour if colour is not None and stood else face, mec="k", ms=8, zorder=3,
                gid=f"verdict:{v}", label=words if legend else None)


def _decades(values) -> bool:
    """Whether the positive ``values`` span more than two decades (then a log axis)."""
    v = np.asarray([x for x in values if x is not None and np.isfinite(x) and x > 0])
    return bool(v.size > 1 and v.max() / v.min() > 100)


def _named(name, u, log) -> str:
    """A curve's legend name; on a log axis a curve with no positive value says why it is
    not seen."""
    u = np.asarray(u, float)
    return f"{name} (0 throughout: not on the log axis)" if log and not np.any(u > 0) else name


def search_figure(lr, title="", failure_displacement=None):
    """A search's levels (``LimitRecord`` ``lr``, levels in order of the parameter) against the
    largest displacement (mm) during each level (blocks, or the watched points) with
    ``failure_displacement`` (m) dotted, and each monitoring point's displacement (mm) since
    the start at the end of each level (|u|; |ux| when only ux is known); markers by verdict
    (``VERDICT_STYLE``), the last stable and first failed levels marked; a log axis when the
    displacements span decades. The parameter's axis reads left to right towards failure (a
    strength schedule lowers it). ``title``: first line of the title."""
    import matplotlib.pyplot as plt

    levels = np.asarray(lr.level, float)
    largest = np.array([np.nan if d is None else 1e3 * float(d) for d in lr.max_displacement])
    panels = [p for p, on in (("largest", bool(np.isfinite(largest).any())),
                              ("points", bool(lr.point_ux))) if on] or ["largest"]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=(8.5, 1.5 + 3.0 * len(panels)))
    order = np.argsort(levels, kind="stable")
    for j, (ax, panel) in enumerate(zip(axes[:, 0], panels)):
        _bracket(ax, lr, legend=j == 0)
        if panel == "largest":
            _largest_panel(ax, lr, levels, largest, order, failure_displacement)
        else:
            _points_panel(ax, lr, levels, order)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    lowered = levels.size > 1 and levels[1] < levels[0]
    axes[-1, 0].set_xlabel(PARAMETER_LABEL.get(lr.parameter, lr.parameter)
                           + (", lowered towards failure" if lowered else ""))
    if lowered:
        axes[-1, 0].invert_xaxis()
    refined = (f"; {lr.refined} of them refine the bracket, each run from the last stable "
               f"state" if lr.refined else "") + _larger_steps(lr, levels, lowered)
    axes[0, 0].set_title(_wrap(f"{title}\n{levels.size} levels of {lr.parameter} in the order "
                               f"of {lr.parameter}{refined}".strip(), 90), fontsize=9)
    fig.tight_layout()
    return fig


def _larger_steps(lr, levels, lowered) -> str:
    """A note when a level less severe than the first failed one failed too: it was reached by
    a larger step, and the search's closing steps of ``refine_to`` decide (``limit``)."""
    if lr.failure_level is None:
        return ""
    sign = -1.0 if lowered else 1.0
    below = [v for v, w in zip(levels, lr.verdict)
             if w in ("failed", "failing") and sign * (v - lr.failure_level) < 0]
    return (f"; {_level(lr.parameter, min(below, key=lambda v: sign * v))} failed too, reached "
            f"by a larger step: the closing steps decide" if below else "")


def _largest_panel(ax, lr, levels, y, order, failure_displacement):
    """The largest displacement in each level (mm, ``y``), markers by verdict."""
    log = _decades(y)
    ax.plot(levels[order], y[order], "-", color="0.4", lw=1, gid="max_displacement",
            label=_named("largest displacement in the level", y, log))
    _by_verdict(ax, levels, y, list(lr.verdict))
    if failure_displacement is not None:
        ax.axhline(1e3 * failure_displacement, color="tab:red", ls=":", lw=1,
                   label=f"failure displacement {1e3 * failure_displacement:g} mm")
    _unstable_marks(ax, levels, y, lr.verdict)
    if log:
        ax.set_yscale("log")
    ax.set_ylabel("largest displacement\nin the level (mm)")


def _points_panel(ax, lr, levels, order):
    """Each monitoring point's |u| (|ux| without uy) at the end of each level (mm), one colour
    per point, the marker's shape by verdict."""
    both = set(lr.point_ux) == set(lr.point_uy)
    curves = {}
    for name in lr.point_ux:
        ux = np.asarray(lr.point_ux[name], float)
        curves[name] = 1e3 * (np.hypot(ux, np.asarray(lr.point_uy[name], float)) if both
                              else np.abs(ux))
    log = _decades(np.concatenate(list(curves.values())))
    for c, (name, u) in zip(_colours(len(curves)), curves.items()):
        ax.plot(levels[order], u[order], "-", color=c, lw=1.2, gid=f"point:{name}",
                label=_named(name, u, log))
        _by_verdict(ax, levels, u, list(lr.verdict), colour=c, legend=False)
    for v in dict.fromkeys(lr.verdict):             # the markers' shapes, once
        marker, face, words = VERDICT_STYLE.get(v, ("s", "0.5", v))
        stood = v not in STOPS
        ax.plot([], [], marker, ls="", mfc="0.85" if stood else face, mec="k", label=words)
    if log:
        ax.set_yscale("log")
    ax.set_ylabel("monitoring points:\n" + ("|u|" if both else "|ux|")
                  + " since the start (mm)")


def _colours(n):
    """``n`` distinct colours (tab10, tab20 beyond ten)."""
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("tab10" if n <= 10 else "tab20")
    return [cmap(i % cmap.N) for i in range(n)]


def _unstable_marks(ax, levels, y, verdicts):
    """A level with no displacement (it blew up) as a star at the bottom of the axes."""
    k = [i for i, v in enumerate(verdicts) if v == "unstable" or not np.isfinite(y[i])]
    if k:
        ax.plot(levels[k], np.zeros(len(k)), "*", color="k", ms=10, clip_on=False,
                transform=ax.get_xaxis_transform(), gid="unstable")


def history_figure(records, points, history=None, title=""):
    """Each monitoring point's displacement |u| (mm) since the start: against the steps from
    the model's ``history`` (``monitor.History.as_arrays()``: "step", "time", "<point>.ux",
    "<point>.uy"; the path to the model's present state: levels a search undid are not in
    it) with each stage's end marked (its step found from its model time) and the points'
    values there (the stage table's), or, when the history lacks them, at the end of each
    stage against the stage (``records``: ``StageRecord``s)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5))
    points = list(points)
    ends = np.array([[1e3 * np.hypot(*r.points[p]) for p in points] for r in records])
    ends = ends.reshape(len(records), len(points))
    steps = _stage_steps(records, points, history)
    curves = ({p: 1e3 * np.hypot(history[f"{p}.ux"], history[f"{p}.uy"]) for p in points}
              if steps is not None else {p: ends[:, j] for j, p in enumerate(points)})
    log = _decades(np.concatenate([ends.ravel()] + list(curves.values())))
    for j, (c, p) in enumerate(zip(_colours(len(points)), points)):
        if steps is not None:
            ax.plot(history["step"], curves[p], "-", color=c, lw=1.2, gid=f"history:{p}",
                    label=_named(p, curves[p], log))
            ax.plot(steps, ends[:, j], "o", color=c, mec="k", ms=5, gid=f"stage ends:{p}")
        else:
            ax.plot([r.index for r in records], ends[:, j], "-o", color=c, ms=5,
                    gid=f"stage ends:{p}", label=_named(p, ends[:, j], log))
    if steps is not None:
        kinds = _stage_marks(ax, steps, records)
        ax.set_xlabel("step (the model's clock: a search's undone levels are not in it)")
        every = int(np.diff(np.asarray(history["step"])).min())
        what = (f"every {every} steps (the model's history); dots: the stage ends (stage "
                f"table)\nstages: {kinds}")
    else:
        ax.set_xticks([r.index for r in records], [f"{r.index} {r.kind}" for r in records],
                      rotation=45, ha="right", fontsize=8)
        ax.set_xlabel("stage")
        what = "at the end of each stage (the model kept no finer history)"
    if log:
        ax.set_yscale("log")
    ax.set_ylabel("displacement |u| since the start (mm)")
    ax.grid(alpha=0.3)
    if points:
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(_wrap(f"{title}\nmonitoring points' displacement {what}".strip(), 100),
                 fontsize=9)
    fig.tight_layout()
    return fig


def _stage_steps(records, points, history):
    """The step at each stage's end (from its model time on the history's time-step pairs),
    or None when the history has too few rows or lacks a point's columns."""
    h = history or {}
    cols = ["step", "time"] + [f"{p}.{c}" for p in points for c in ("ux", "uy")]
    if not records or any(len(h.get(c, ())) != len(h.get("step", ())) for c in cols) \
            or len(h.get("step", ())) < 2:
        return None
    t, s = np.asarray(h["time"], float), np.asarray(h["step"], float)
    return np.interp([r.time for r in records], t, s, left=0.0)


def _stage_marks(ax, steps, records) -> str:
    """A dotted vertical line at each stage's end, its index (those of the stages ending at
    the same step together) on a top axis; returns the stages' kinds as words for the
    title."""
    groups = {}
    for s, r in zip(steps, records):
        groups.setdefault(round(float(s)), []).append(str(r.index))
    for s in groups:
        ax.axvline(s, color="0.6", ls=":", lw=0.8)
    top = ax.secondary_xaxis("top")
    top.set_xticks(list(groups), [",".join(i) for i in groups.values()], rotation=90,
                   fontsize=7)
    top.set_xlabel("stage ends", fontsize=8)
    return ", ".join(f"{r.index} {r.kind}" for r in records)
