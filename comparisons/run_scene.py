"""Run a scene file from the command line: ``python -m comparisons run-scene FILE [--out DIR]
[--vtk] [--set KEY=VALUE ...] [--resume] [--restart]``, so a slope can be modelled without
writing Python.

The scene (``dem_core.workflow.scene.Scene.load``: checked before any compute) is built as a DEM model
(``build_model``) and its stages run (``dem_core.workflow.stages.run_stages``); ``<out>/<scene name>/``
then holds, like a case's folder:

- ``summary.json``: the scene's name, file and description, blocks and contacts, ``stages``
  (one object per stage: index, kind, verdict, steps, model time (s), each monitoring point's
  displacement ``[ux, uy]`` (m), the crack counts, wall seconds, and the stage's own numbers:
  a g-ramp's failure_g and last_stable_g, a factor of safety's factor_of_safety and
  first_failed, a strength schedule's last_stable_value and failure_value, a load's peak;
  a search's whole record under ``search``), ``results`` (those numbers of the last stage
  giving each), ``runtime_s``, ``error`` (None, or the message of the stage that raised; the
  stages before it are kept) and ``versions``;
- ``stages.csv`` (the stage table: kind, verdict, steps, times, crack counts, each point's ux
  and uy in m) and, for a stage with a curve (``load``), ``stage<i>_<kind>.csv``;
- ``stage<i>_<kind>.png``, drawn as each stage ends (``stage_outputs``,
  ``comparisons.scene_figures.stage_figure``): the model at that stage's end, blocks moved by
  their displacement times the magnification in the title, coloured by the true displacement
  (mm), joints, the cracks through intact rock (flaws, region boundaries) as the broken edges
  by mode, support, the water table the model has, the monitoring points; the title names the
  stage, its verdict, for a search which state is drawn (the first failed level's, or the last
  level's), and the crack counts of ``stages.csv`` with those drawn;
- ``stage<i>_search.png`` for a search stage (``search_figure``): each level (F, g or the
  strength) against the largest displacement in it and each monitoring point's displacement,
  markers by verdict, the last stable and first failed levels marked;
- ``history.png`` (``history_figure``): each monitoring point's displacement against the steps
  (the model's history) with the stage ends marked;
- ``blocks.png``: the final state, drawn as a stage's picture;
- ``report.md``: the results, the stage table (``stage_table``, mm), the history, each stage's
  pictures under its verdict (only the pictures there are: a stage kept by an earlier run that
  drew none has none), the final state;
- with ``--vtk``: ``<scene name>.vtu``, the final state for ParaView (``Model.write_vtk``);
  ``vtk/<scene name>.pvd``, the state at each stage's end (time: the stage's index), and
  ``vtk/stage<i>_search.pvd``, each level of a search stage in the order run (field data: the
  level); each file's field data names the integer codes (``dem_core.output.vtk``).

The run ends with one line per stage giving its verdict with its number (``verdict_lines``: a
factor of safety ``factor of safety 1.30 (1.35 fails)``, a strength schedule's last stable and
failed values, a g-ramp's failure g and last stable g, a solve's verdict and steps; a stage
that raised says it stopped the run, those after it that they did not run); ``report.md``
starts with the same lines under "## Verdicts".

Checking a scene (``--check``, ``check_scene``): the scene is loaded and checked, the model
built (blocks and contacts, no step) and its stages checked against it; ``<out>/<scene
name>/check.png`` draws it (``check_figure``: blocks coloured by region, joints, the groups
with boundaries hatched, the groups a stage excavates outlined, the monitoring points
labelled, each water table a stage sets, the cables a stage installs). Nothing is computed and
nothing a run kept is touched.

``--set KEY=VALUE`` (``apply_settings``) changes a top-level key of the scene file (VALUE as
JSON, else a string): ``solver`` is laid over the file's solver options (``--set
'solver={"damping": 0.5}'``), any other key (``density``, ``block_nu``, ``stages``, ...) is
replaced; the result is checked like the file.

Resuming (``--resume``): the run keeps, in ``<out>/<scene name>/members/``, the model after
each finished stage and the stages' records (``checkpoint-stages.npz`` and ``.json``, the
latter with the run's ``source``: a hash of the scene's canonical JSON and the ``--set``
items, ``scene_source``). A resumed run goes on after the last kept stage (a finished run's
outputs are written again, no stage run); a checkpoint of another source (the scene file or
``--set`` changed) is refused before any compute (``comparisons.store.check_kept``);
``--restart``, like a run without ``--resume``, deletes the kept results first.

The continuum (``--method continuum|both``): ``comparisons.scene_continuum``.
"""
from __future__ import annotations

import csv
import dataclasses
import importlib
import json
import os
import re
import time
from pathlib import Path

import numpy as np

from comparisons.results import _jsonable, software_versions
from dem_core.output.fingerprint import results_hash, state_hash
from comparisons import store
from comparisons.store import check_folder

__all__ = ["prepare", "run_scene", "run_prepared", "build_checked", "scene_folder",
           "RESULT_KEYS", "apply_settings", "scene_source", "load_stages", "STAGES_CHECKPOINT",
           "check_scene", "check_figure", "verdict_line", "verdict_lines", "CHECK_PICTURE",
           "stage_outputs", "VTK_FOLDER"]

CHECK_PICTURE = "check.png"                 # <out>/<scene name>/<this>, written by --check

STAGES_CHECKPOINT = "checkpoint-stages"     # <members>/<this>.npz and .json

# the numbers a stage gives that a reader looks for first (copied to summary["results"])
RESULT_KEYS = ("failure_g", "last_stable_g", "factor_of_safety", "first_failed",
               "last_stable_value", "failure_value", "peak", "displacement_at_peak")
_SEARCH_KEYS = ("ramp", "search")           # a stage's LimitRecord in its detail


def scene_folder(scene, out) -> Path:
    """``<out>/<scene name>`` (characters other than letters, digits, ".", "-", "_" as "_").
    A name that would leave ``out`` ("..", ".": ``Scene`` refuses them already) is a
    ValueError."""
    stem = re.sub(r"[^\w.\-]", "_", scene.name) or "scene"
    if not stem.strip("."):
        raise ValueError(f"scene name {scene.name!r} is not a plain file name: its results "
                         f"would not go into {str(out)!r}")
    return Path(out) / stem


def apply_settings(d: dict, settings) -> dict:
    """The scene file's dict ``d`` with each "KEY=VALUE" of ``settings`` applied (VALUE parsed
    as JSON, else taken as a string): ``solver`` laid over the file's solver options, any
    other top-level key replaced (``Scene.from_dict`` checks the result). ValueError naming an
    item that is not KEY=VALUE or a solver that is not an object."""
    d = dict(d)
    for item in settings:
        key, sep, text = item.partition("=")
        if not sep or not key:
            raise ValueError(f"--set takes KEY=VALUE, got {item!r}")
        try:
            value = json.loads(text)
        except json.JSONDecodeError:
            value = text
        if key == "solver":
            if not isinstance(value, dict):
                raise ValueError(f"--set solver: expected a JSON object like "
                                 f"{{\"damping\": 0.5}}, got {value!r}")
            value = {**(d.get("solver") or {}), **value}
        d[key] = value
    return d


def scene_source(scene, settings=()) -> str:
    """What a scene run comes from (``store.source_hash``): the scene's canonical JSON
    (``Scene.to_dict``, keys sorted) and the ``--set`` items."""
    return store.source_hash({"scene": scene.to_dict(), "set": list(settings)})


def prepare(path, out="results", settings=()):
    """The checks before any compute: (scene, folder) of the scene file ``path`` (with the
    ``--set`` items ``settings``, ``apply_settings``) and its results folder
    ``scene_folder(scene, out)``, created and writable. ValueError naming the file and what
    is wrong with it (missing, not JSON, not a valid scene: the item), or the folder that
    cannot be written."""
    from dem_core.workflow.scene import Scene, load_json

    try:
        with open(path) as fh:
            scene = Scene.from_dict(apply_settings(load_json(fh), settings))
    except OSError as e:
        raise ValueError(f"scene file {str(path)!r}: {e.strerror or e}") from None
    except json.JSONDecodeError as e:
        raise ValueError(f"scene file {str(path)!r} is not valid JSON: {e}") from None
    except (ValueError, TypeError, KeyError) as e:
        raise ValueError(f"scene file {str(path)!r}: {e}") from None
    return scene, check_folder(scene_folder(scene, out))


def run_scene(path, out="results", vtk: bool = False, progress=None, settings=(),
              resume: bool = False, restart: bool = False):
    """Load the scene file ``path`` (``prepare``, with the ``--set`` items ``settings``), run
    its stages on the DEM model and write the outputs (module docstring) to ``scene_folder``.
    ``resume``: go on from the stages kept in ``<folder>/members`` (refused, before any
    compute, when they came from another scene or settings); without it, or with
    ``restart``, they are deleted first. Returns (folder, records, error): the
    ``StageRecord``s of the stages that ran and None, or the exception a stage raised (the
    outputs of the stages before it are still written)."""
    scene, folder = prepare(path, out, settings)
    with store.case_output(folder, resume=resume, source=scene_source(scene, settings),
                           restart=restart) as keep:
        kept = build_checked(scene, load_stages(keep) if keep.resume else None)
        return (folder,) + run_prepared(scene, folder, path, vtk, progress, kept=kept)


def build_checked(scene, kept=None):
    """(model, records) ready to run: ``kept`` ((model, records) of the stages an earlier run
    finished, ``load_stages``) or the scene's new model (``build_model``, which refuses a
    geometry too large for the machine), after the checks before any compute: the stages
    against the model's groups and materials (``check_stages``) and the stages left to run
    against the model (``check_on_model``: watched points, excavated groups, cables, liners,
    loads the contacts cannot carry). ValueError naming the stage or item."""
    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import check_on_model, check_stages

    model, records = kept if kept is not None else (build_model(scene), [])
    check_stages(scene.stages, set(model.blocks.groups), model.materials)
    check_on_model(scene.stages[len(records):], model, first=len(records))
    return model, records


def check_scene(path, out="results", settings=()):
    """``run-scene FILE --check``: load and check the scene (``prepare``), build its model
    (``build_model``: blocks and contacts, no step), check its stages against the model
    (``build_checked``) and draw it to ``<folder>/check.png`` (``check_figure``). Nothing is
    computed and no kept result is touched. Returns (folder, line): the line gives the block
    and contact counts and the stages' kinds. ValueError for a scene that does not load or
    whose stages or points do not fit the model."""
    import matplotlib.pyplot as plt

    from dem_core.workflow.stages import stage_to_dict

    scene, folder = prepare(path, out, settings)
    try:
        model, _ = build_checked(scene)
    except ValueError as e:
        raise ValueError(f"scene file {str(path)!r}: {e}") from None
    fig = check_figure(scene, model)
    picture = folder / CHECK_PICTURE
    fig.savefig(picture, dpi=110, bbox_inches="tight")
    plt.close(fig)
    kinds = ", ".join(f"{i} {stage_to_dict(st)['kind']}" for i, st in enumerate(scene.stages))
    line = (f"{scene.name}: {model.n_blocks} blocks, {int(model.contacts.n)} contacts; "
            f"{len(scene.stages)} stage{'s' if len(scene.stages) != 1 else ''}: "
            f"{kinds or 'none'}; nothing run; picture {picture}")
    return folder, line


def check_figure(scene, model):
    """The model as built, before any step: blocks coloured by region
    (``dem_core.geometry.plot.plot_block_system``: flaws thin, joints bold crimson), the groups
    with boundaries hatched, the groups a stage excavates outlined (dashed), the cables a stage
    installs, each water table a stage sets, the monitoring points labelled; the title (the
    scene's name, counts and stages) inside the figure."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from dem_core.geometry.plot import plot_block_system
    from dem_core.workflow.scene import group_sides
    from dem_core.workflow.stages import Cable, Excavate, WaterTable, stage_to_dict
    from comparisons.scene_figures import draw_water_table

    bs = model.blocks
    fig, ax = plt.subplots(figsize=(9, 7))
    cmap = plt.get_cmap("tab20")
    colours = [cmap(i % 20) for i in range(len(bs.region_names))]
    plot_block_system(bs, ax, region_colors=colours)
    handles = [Patch(facecolor=colours[i], alpha=0.6, label=f"region {name}")
               for i, name in enumerate(bs.region_names) if np.any(bs.region_id == i)][:12]
    joint = np.array([n.startswith("joint:") for n in bs.material_names], bool)
    if bs.n_edges and joint[bs.edge_material].any():
        handles.append(Line2D([], [], color="crimson", lw=1.2, label="joints"))

    def polys(group):
        return [bs.block_vertices(b) for b in model.group(group)]

    v = np.asarray(bs.vertices)
    (x0, y0), (x1, y1) = v.min(axis=0), v.max(axis=0)
    box = {"left": ([x0, x0], [y0, y1]), "right": ([x1, x1], [y0, y1]),
           "bottom": ([x0, x1], [y0, y0]), "top": ([x0, x1], [y1, y1])}
    styles = [("0.15", "//"), ("saddlebrown", "\\\\"), ("darkgreen", "||"), ("navy", "--")]
    for j, b in enumerate(scene.boundaries):
        colour, hatch = styles[j % len(styles)]
        fixed = ", ".join(k for k, on in (("x", b.x), ("y", b.y), ("rotation", b.rotation))
                          if on) or "nothing"
        sides = group_sides(scene, b.group) or []
        ax.add_collection(PolyCollection(polys(b.group), facecolors="none", edgecolors=colour,
                                         hatch=hatch, linewidths=0.6))
        for side in sides:                          # where it is held, drawn thick
            ax.plot(*_held_stretch(polys(b.group), side, box[side]), "-", color=colour, lw=4,
                    solid_capstyle="butt")
        handles.append(Patch(facecolor="none", edgecolor=colour, hatch=hatch,
                             label=f"boundary: {b.group} (fixed {fixed}"
                                   + (f"; on the {' and '.join(sides)}" if sides else "")
                                   + ")"))
    xs = np.linspace(x0, x1, 200)
    dug = [f"{st.group} (stage {i})" for i, st in enumerate(scene.stages)
           if isinstance(st, Excavate)]
    if dug:
        handles.append(Line2D([], [], color="magenta", ls="--", lw=1.6,
                              label=_wrap("excavated: " + ", ".join(dug), 45)))
    for i, st in enumerate(scene.stages):
        if isinstance(st, Excavate):
            ax.add_collection(PolyCollection(polys(st.group), facecolors="none",
                                             edgecolors="magenta", linestyles="--",
                                             linewidths=1.6))
        elif isinstance(st, WaterTable) and st.surface is not None:
            line = draw_water_table(ax, st.surface, xs, label=f"water table (stage {i})")
            handles.append(line)
        elif isinstance(st, Cable):
            (ca, cb), (ea, eb) = st.collar, st.end
            line, = ax.plot([ca, ea], [cb, eb], "-", color="purple", lw=1.5,
                            label=f"cable (stage {i})")
            handles.append(line)
    for name, (px, py) in scene.points.items():
        ax.plot(px, py, "k^", ms=7)
        ax.annotate(name, (px, py), xytext=(5, 5), textcoords="offset points", fontsize=9,
                    bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="0.5", alpha=0.8))
    if scene.points:
        handles.append(Line2D([], [], color="k", marker="^", ls="", label="monitoring points"))
    ax.autoscale_view()
    kinds = ", ".join(f"{i} {stage_to_dict(st)['kind']}" for i, st in enumerate(scene.stages))
    ax.set_title(_wrap(f"{scene.name}: {model.n_blocks} blocks, {int(model.contacts.n)} "
                       f"contacts, as built (no step run)") + "\n"
                 + _wrap(f"stages: {kinds or 'none'}"), fontsize=10)
    if handles:
        ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                  borderaxespad=0.0)
    fig.tight_layout()
    return fig


def _wrap(text, width=90) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width)) or text


def verdict_line(r) -> str:
    """A stage's verdict with its number, for a reader at a glance (``StageRecord`` ``r``):
    a factor of safety's last F that stood and first that failed, a strength schedule's last
    stable and failed values, a g-ramp's failure g and last stable g, a solve's verdict and
    steps, any other stage's verdict (and steps, if it took any)."""
    d, head = r.detail, f"stage {r.index} {r.kind}: "
    if r.kind == "factor_of_safety":
        text = _search_text(d.get("factor_of_safety"), d.get("first_failed"), d.get("F"), r,
                            lambda v: f"{v:.2f}", "factor of safety", "F = ", "level")
    elif r.kind == "strength_schedule":
        prop = getattr(d.get("search"), "parameter", None) or "value"
        text = _search_text(d.get("last_stable_value"), d.get("failure_value"),
                            d.get("values"), r, lambda v: f"{v:.4g}", prop, f"{prop} ",
                            "value")
    elif r.kind == "raise_gravity":
        text = _search_text(d.get("last_stable_g"), d.get("failure_g"), d.get("g"), r,
                            lambda v: f"{v:g} g", "failure g", "", "level")
    else:
        text = r.verdict + (f", {r.steps} steps" if r.steps or r.kind in ("solve", "cycle")
                            else "")
    return head + text


def _search_text(stood, failed, levels, r, fmt, what, prefix, unit) -> str:
    """A search's verdict: the limit lies between the last level that stood and the first that
    failed (``fmt`` writes a level, ``what`` names the result, ``unit`` a level)."""
    levels = list(levels or [])
    steps = f"; {r.steps} steps"
    if r.verdict == "undecided":
        rec = r.detail.get("search") or r.detail.get("ramp")
        last = "no level stood" if stood is None else f"the last that stood {prefix}{fmt(stood)}"
        return (f"undecided at {prefix}{fmt(rec.undecided_level)}: neither at rest nor failing "
                f"within the cap, no {what} ({last}){steps}")
    if r.verdict == "unstable":
        last = "no level stood" if stood is None else f"the last that stood {prefix}{fmt(stood)}"
        return f"the model became numerically unstable, no failure level ({last}){steps}"
    if what == "factor of safety":
        if failed is not None and stood is not None:
            return f"factor of safety {fmt(stood)} ({fmt(failed)} fails){steps}"
        if failed is not None:
            return (f"factor of safety below {fmt(failed)} (the first level, F = "
                    f"{fmt(failed)}, fails){steps}")
        top = stood if stood is not None else (max(levels) if levels else float("nan"))
        return f"factor of safety above {fmt(top)} (the last level stands){steps}"
    if what == "failure g":
        if failed is not None and stood is not None:
            return f"fails at {fmt(failed)} (last stable {fmt(stood)}){steps}"
        if failed is not None:
            return f"fails at {fmt(failed)}, the first level{steps}"
        return f"no failure: stands at {fmt(stood) if stood is not None else '?'}, the last " \
               f"level{steps}"
    if failed is not None and stood is not None:
        return f"{what} {fmt(stood)} stands, {fmt(failed)} fails{steps}"
    if failed is not None:
        return f"{what} fails at {fmt(failed)}, the first {unit}{steps}"
    return f"no failure: {what} {fmt(stood) if stood is not None else '?'} (the last {unit}) " \
           f"stands{steps}"


def verdict_lines(records, error=None, stages=()) -> list:
    """``verdict_line`` of each stage that ran; with ``error`` (what the next of the scene's
    ``stages`` raised) a line saying that stage failed and stopped the run, and one for the
    stages after it, not run."""
    from dem_core.workflow.stages import stage_to_dict

    lines = [verdict_line(r) for r in records]
    if records and "stopped" in records[-1].detail:
        lines.append(records[-1].detail["stopped"])
    if error is not None:
        i = records[-1].index + 1 if records else 0
        kind = f" {stage_to_dict(stages[i])['kind']}" if i < len(stages) else ""
        lines.append(f"stage {i}{kind}: FAILED, it stopped the run: {type(error).__name__}: "
                     f"{error}")
        if len(stages) > i + 1:
            lines.append(f"stages {i + 1}..{len(stages) - 1}: not run" if len(stages) > i + 2
                         else f"stage {i + 1}: not run")
    return lines


def _checkpoint_stem(keep) -> Path:
    return keep.members / STAGES_CHECKPOINT


def load_stages(keep):
    """(model, records) kept by the scene run in the folder of ``keep`` (a
    ``store.CaseOutput``) after its last finished stage, or None when there are none (or the
    two files are not of the same stage: the run was killed between them). ValueError naming
    the file that does not read; ``store.StaleResult`` when they came from another source."""
    from dem_core.model import Model

    stem = _checkpoint_stem(keep)
    npz, js = stem.with_name(stem.name + ".npz"), stem.with_name(stem.name + ".json")
    if not js.exists():
        return None
    try:
        saved = json.loads(js.read_text(), object_hook=_decode_record)
        source, step, records = saved["source"], saved["step"], saved["records"]
    except (ValueError, KeyError, TypeError, ImportError, AttributeError) as e:
        raise ValueError(f"checkpoint {str(js)!r} does not read ({type(e).__name__}: "
                         f"{e}); run again with --restart to start over") from None
    if not isinstance(source, dict) or source.get("run") != keep.source:
        raise store.StaleResult(store.stale_message(js))
    if not npz.exists():
        return None
    try:
        model = Model.load(npz)
    except Exception as e:
        raise ValueError(f"checkpoint {str(npz)!r} does not read ({type(e).__name__}: "
                         f"{e}); run again with --restart to start over") from None
    if int(model.step) != int(step):
        return None
    for r in records:
        r.points = {k: tuple(v) for k, v in r.points.items()}
    return model, records


def _save_stages(keep, model, records) -> None:
    """Keep the model after the stages ``records`` and their records (each file written whole
    before it replaces the last)."""
    stem = _checkpoint_stem(keep)
    part = stem.with_name(stem.name + ".part.npz")
    model.save(part)
    os.replace(part, stem.with_name(stem.name + ".npz"))
    text = json.dumps({"source": {"run": keep.source}, "step": int(model.step),
                       "records": records}, default=_encode_record)
    part = stem.with_name(stem.name + ".part.json")
    part.write_text(text)
    os.replace(part, stem.with_name(stem.name + ".json"))


def _encode_record(value):
    """A dataclass (a StageRecord, a search's record) by its class and fields, else
    ``store``'s encoding (arrays, numpy scalars)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {"__record__": f"{type(value).__module__}:{type(value).__qualname__}",
                "fields": {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}}
    return store._encode(value)


def _decode_record(obj):
    if "__record__" in obj:
        module, _, name = obj["__record__"].partition(":")
        if not module.startswith(("dem_core.", "comparisons.")):
            raise ValueError(f"unexpected record type {obj['__record__']!r}")
        return getattr(importlib.import_module(module), name)(**obj["fields"])
    return store._decode(obj)


def run_prepared(scene, folder, path, vtk=False, progress=None, kept=None):
    """``run_scene`` after ``prepare``: (records, error). ``kept``: (model, records) to run
    from, checked (``build_checked``: a new model, or the stages finished by an earlier run,
    after which the others run); None builds and checks it here. Inside a
    ``store.case_output`` the model and records are kept after each stage."""
    from dem_core.workflow.stages import check_stages, run_stages, stop_after

    say = progress or (lambda message: None)
    keep = store.current()
    t0 = time.perf_counter()
    model, records = kept if kept is not None else build_checked(scene)
    records = list(records)
    say(f"{scene.name}: {model.n_blocks} blocks, {int(model.contacts.n)} contacts, "
        f"{len(scene.stages)} stages" + (f", {len(records)} kept from an earlier run (not run "
                                         f"again)" if records else ""))
    stage_start = [time.perf_counter()]
    series = _stage_series(folder, len(records)) if vtk else None
    levels = {}                                     # stage -> VtkSeries of its search levels

    def level_done(i, stage, m, rec):
        say(level_line(i, stage, rec, time.perf_counter() - stage_start[0]))
        if vtk:
            _add_level(folder, levels, i, m, rec)

    error = None
    try:
        check_stages(scene.stages, set(model.blocks.groups), model.materials)
        for i in range(len(records), len(scene.stages)):
            stage_start[0], before = time.perf_counter(), model.state.pos.copy()
            rec = run_stages(model, [scene.stages[i]], after_failure="continue",
                             on_level=lambda j, st, m, r, i=i: level_done(i, st, m, r))[0]
            rec = dataclasses.replace(rec, index=i)
            records.append(rec)
            say(f"{verdict_line(rec)}, {rec.seconds:.1f} s")      # a search's F or g, not "failed"
            if keep is not None:
                _save_stages(keep, model, records)
            stage_outputs(folder, scene, model, rec, series)
            if stop_after(rec, scene.stages, model, before, scene.after_failure):
                say(rec.detail["stopped"])
                break
    except Exception as e:          # kept in the outputs with the stages before it
        error = e
    write_outputs(folder, scene, path, model, records, error, time.perf_counter() - t0, vtk)
    return records, error


def level_line(i, stage, rec, elapsed) -> str:
    """A progress line after a level of search stage ``i``: the parameter, the level among the
    planned ones, its verdict, the stage's steps and elapsed time, an estimate of what is left
    (``comparisons.progress.ramp_status``)."""
    from comparisons.progress import duration, ramp_status

    plan = next(getattr(stage, k) for k in ("g_levels", "f_levels", "values")
                if hasattr(stage, k))
    text, left = ramp_status(rec, [float(v) for v in plan], elapsed, stage.refine_to)
    return (f"stage {i} {text}: {rec.verdict[-1]}, {int(sum(rec.steps))} steps, elapsed "
            f"{duration(elapsed)}, " + ("left unknown" if left is None else
                                        f"left ~{duration(left)}"))


VTK_FOLDER = "vtk"                  # <out>/<scene name>/<this>: the series of --vtk


def stage_outputs(folder: Path, scene, model, rec, series=None) -> list:
    """What a stage leaves, written while the model is at its end: ``stage<i>_<kind>.png``
    (``scene_figures.stage_figure``), a search's ``stage<i>_search.png``
    (``search_figure``) and, with ``series`` (a ``VtkSeries``), the state as its next member
    (time: the stage's index). Returns the pictures' names."""
    import matplotlib.pyplot as plt

    from comparisons.scene_figures import (search_figure, search_picture, search_record,
                                           stage_figure, stage_picture)

    words = verdict_line(rec).split(": ", 1)[-1]
    figures = {stage_picture(rec): stage_figure(scene, model, rec, words)}
    lr = search_record(rec)
    if lr is not None:
        fd = getattr(scene.stages[rec.index], "failure_displacement", None)
        figures[search_picture(rec)] = search_figure(lr, f"{scene.name}: stage {rec.index} "
                                                         f"({rec.kind}): {words}", fd)
    for name, fig in figures.items():
        fig.savefig(folder / name, dpi=110, bbox_inches="tight")
        plt.close(fig)
    if series is not None:
        series.add(model, time=rec.index, field_data={"stage": rec.index})
    return list(figures)


def _stage_series(folder, kept):
    """The VtkSeries of the stage ends, ``<folder>/vtk/<scene name>.pvd``, going on after the
    ``kept`` stages an earlier run wrote (a new run starts it afresh)."""
    from dem_core.output.vtk import VtkSeries

    return VtkSeries.reopen(Path(folder) / VTK_FOLDER, Path(folder).name, until=kept - 1)


def _add_level(folder, levels, i, model, rec):
    """Add the state after the last level of search stage ``i`` (``rec``: its LimitRecord so
    far) to ``<folder>/vtk/stage<i>_search.pvd`` (time: the level's place in the order run;
    field data: the level, under the parameter's name)."""
    from dem_core.output.vtk import VtkSeries

    if i not in levels:
        levels[i] = VtkSeries(Path(folder) / VTK_FOLDER, f"stage{i}_search")
    levels[i].add(model, time=len(rec.level) - 1, field_data={rec.parameter: rec.level[-1]})


def write_outputs(folder: Path, scene, path, model, records, error, runtime_s, vtk) -> None:
    """summary.json, stages.csv, the curves, blocks.png, history.png, report.md (and the
    .vtu); the stages' pictures (``stage_outputs``) were written as each stage ended."""
    stages = [_stage_summary(r) for r in records]
    curves = {}
    for r in records:
        name = _write_curve(folder, r)
        if name:
            curves[r.index] = name
            stages[r.index]["curve"] = name
    results = {k: s[k] for s in stages for k in RESULT_KEYS if s.get(k) is not None}
    summary = {"scene": scene.name, "file": str(Path(path).resolve()),
               "description": scene.description, "method": "dem",
               "blocks": int(model.n_blocks), "contacts": int(model.contacts.n),
               "stages": stages, "results": results,
               # the same input gives the same bits (docs/output.md): two runs compare here
               "results_hash": results_hash({"stages": stages, "results": results}),
               "state_hash": state_hash(model), "runtime_s": runtime_s,
               "error": None if error is None else f"{type(error).__name__}: {error}",
               "versions": software_versions(), "written": time.strftime("%Y-%m-%d %H:%M:%S")}
    (folder / "summary.json").write_text(json.dumps(_jsonable(summary), indent=2))
    _write_stage_csv(folder / "stages.csv", records, list(model.points))
    import matplotlib.pyplot as plt

    from comparisons.scene_figures import HISTORY_PICTURE, history_figure

    for name, fig in (("blocks.png", block_figure(scene, model, records)),
                      (HISTORY_PICTURE, history_figure(records, list(model.points),
                                                       model.history.as_arrays(),
                                                       scene.name))):
        fig.savefig(folder / name, dpi=110, bbox_inches="tight")
        plt.close(fig)
    if vtk:
        model.write_vtk(folder / f"{folder.name}.vtu")
    (folder / "report.md").write_text(_report(summary, records, curves, vtk, folder.name,
                                              verdict_lines(records, error, scene.stages),
                                              folder))


def _stage_summary(r) -> dict:
    """A StageRecord as plain data: its fields, its detail's numbers and lists (arrays go to
    CSV), a search's record as ``search``."""
    out = {"index": r.index, "kind": r.kind, "verdict": r.verdict, "steps": r.steps,
           "time": r.time, "points": {k: list(v) for k, v in r.points.items()},
           "cracks": dict(r.cracks), "seconds": r.seconds}
    for key, value in r.detail.items():
        if key in _SEARCH_KEYS and dataclasses.is_dataclass(value):
            out["search"] = dataclasses.asdict(value)
        elif not isinstance(value, np.ndarray):
            out[key] = value
    return out


def _write_curve(folder, r) -> str | None:
    """A stage's equal-length 1-D arrays (a load's time, displacement, reaction, ...) as
    ``stage<i>_<kind>.csv``; its name, or None when it has none."""
    cols = {k: v for k, v in r.detail.items() if isinstance(v, np.ndarray) and v.ndim == 1}
    if not cols or len({v.size for v in cols.values()}) != 1:
        return None
    name = f"stage{r.index}_{r.kind}.csv"
    np.savetxt(folder / name, np.column_stack(list(cols.values())), delimiter=",",
               header=",".join(cols), comments="", fmt="%.8g")
    return name


def _write_stage_csv(path, records, points) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["stage", "kind", "verdict", "steps", "time_s", "seconds", "tension_cracks",
                    "shear_cracks"] + [f"{p}_{c}_m" for p in points for c in ("ux", "uy")])
        for r in records:
            w.writerow([r.index, r.kind, r.verdict, r.steps, f"{r.time:.8g}",
                        f"{r.seconds:.3f}", r.cracks["tension"], r.cracks["shear"]]
                       + [f"{r.points[p][i]:.8g}" for p in points for i in (0, 1)])


def block_figure(scene, model, records):
    """The final state (``scene_figures.state_figure``): blocks moved by their displacement x
    the magnification in the title, coloured by the true displacement (mm), joints, the cracks
    through intact rock (flaws and region boundaries, ``comparisons.staged.INTACT``; a joint's
    breaks would hide the picture, they are counted in the title) as broken edges (red
    tension, blue shear), support, the water table, the monitoring points (moved the same
    way)."""
    from comparisons.scene_figures import search_record, search_state, state_figure

    last = records[-1] if records else None
    head = (f"{scene.name}: final state, after stage {last.index} ({last.kind}: "
            f"{verdict_line(last).split(': ', 1)[-1]})" if last else
            f"{scene.name}: before any stage")
    lr = search_record(last) if last else None
    return state_figure(scene, model, head, [search_state(lr)] if lr is not None else [],
                        last.cracks if last else None)


def _report(summary, records, curves, vtk, name, verdicts=(), folder=None) -> str:
    """report.md: the verdicts, the scene, the results, the stage table, the history and each
    stage's pictures (``_stage_pictures``: only the files in ``folder``), the final state,
    the data files."""
    from dem_core.workflow.stages import stage_table

    from comparisons.scene_figures import HISTORY_PICTURE

    folder = Path(folder) if folder is not None else None
    lines = [f"# {summary['scene']} (scene file, DEM)", "", "## Verdicts", ""]
    lines += [f"- {v}" for v in verdicts] or ["(no stage ran)"]
    lines += ["", "## Scene", "", f"File: `{summary['file']}`"]
    if summary["description"]:
        lines += ["", summary["description"]]
    lines += ["", f"{summary['blocks']} blocks, {summary['contacts']} contacts; "
              f"{len(records)} stages in {summary['runtime_s']:.1f} s."]
    lines += ["", f"Results hash: `{summary['results_hash']}`, final state: "
                  f"`{summary['state_hash']}` (docs/output.md, \"Same input, same bits\")."]
    if summary["error"]:
        lines += ["", f"**The run stopped with an error:** {summary['error']}"]
    if summary["results"]:
        lines += ["", "## Results", "", "| quantity | value |", "|---|---|"]
        lines += [f"| {k} | {v:.6g} |" for k, v in summary["results"].items()]
    lines += ["", "## Stages", "", "Monitoring points' displacement at the end of each stage "
              "(`stages.csv` has them in m, with times and crack counts):", ""]
    lines += [stage_table(records)] if records else ["(no stage ran)"]
    if folder is not None and (folder / HISTORY_PICTURE).exists():
        lines += ["", f"![monitoring points' history]({HISTORY_PICTURE})"]
    for r in records:
        lines += ["", f"### {verdict_line(r)}", ""] + _stage_pictures(r, folder)
    lines += ["", "## Final state", "", "![blocks](blocks.png)"]
    if curves or vtk:
        lines += ["", "## Data", ""]
        lines += [f"- `{c}`: stage {i}'s curve" for i, c in curves.items()]
        if vtk:
            lines += _vtk_lines(records, name, folder)
    lines += ["", "## Software", ""] + [f"- {k}: {v}" for k, v in summary["versions"].items()]
    return "\n".join(lines) + "\n"


def _stage_pictures(r, folder) -> list:
    """The report's lines for stage ``r``'s pictures: the state at its end and a search's
    plot, each only if its file is in ``folder`` (a stage kept from an earlier run that drew
    none has none: it says so)."""
    from comparisons.scene_figures import search_picture, search_record, stage_picture

    names = [stage_picture(r)] + ([search_picture(r)] if search_record(r) is not None else [])
    have = [n for n in names if folder is not None and (folder / n).exists()]
    if not have:
        return ["(no picture: the stage was kept from an earlier run that drew none)"]
    return [f"![stage {r.index} {'search' if n.endswith('_search.png') else r.kind}]({n})"
            for n in have]


def _vtk_lines(records, name, folder) -> list:
    """The report's lines for the ParaView files of ``--vtk`` that are in ``folder``."""
    lines = [f"- `{name}.vtu`: the final state for ParaView (docs/output.md)"]
    vtk = Path(folder or ".") / VTK_FOLDER
    if (vtk / f"{name}.pvd").exists():
        lines.append(f"- `{VTK_FOLDER}/{name}.pvd`: the state at each stage's end (time: the "
                     f"stage's index; `{name}_legend.json` and each file's field data name "
                     f"the integer codes)")
    for r in records:
        if (vtk / f"stage{r.index}_search.pvd").exists():
            lines.append(f"- `{VTK_FOLDER}/stage{r.index}_search.pvd`: stage {r.index}'s "
                         f"levels in the order run (field data: the level)")
    return lines


def _held_stretch(polygons, side, line):
    """The part of the box side ``line`` ((xs, ys), two points) that the group's polygons
    touch: the extent of their vertices on that side (the whole side if none lies on it)."""
    (xa, xb), (ya, yb) = line
    pts = np.concatenate(polygons) if polygons else np.zeros((0, 2))
    tol = 1e-9 * max(abs(xb - xa), abs(yb - ya), 1.0)
    if side in ("left", "right"):
        on = pts[np.abs(pts[:, 0] - xa) <= tol]
        return ([xa, xa], [on[:, 1].min(), on[:, 1].max()]) if on.size else line
    on = pts[np.abs(pts[:, 1] - ya) <= tol]
    return ([on[:, 0].min(), on[:, 0].max()], [ya, ya]) if on.size else line
