"""The continuum column of a scene run (``run-scene FILE --method continuum|both``).

A scene with a "continuum" section (mesh size, each region's rock mass, flow rule;
docs/scenes.md) runs its stages in ``continuum_ref`` too (``continuum_ref.scene_run``), before
any compute checked (``check_continuum``: a stage the continuum cannot run is refused, naming
it). ``<out>/<scene name>/`` then also holds:

- ``continuum.json``: its stages (verdict, F or g, largest displacement, seconds);
- ``continuum_stage<i>_<kind>.png``: the continuum at each stage's end, excavated cells left
  out (``continuum_ref.plot.stage_figure``: displacement, yield, tau_max, the water table the
  stages have set);
- in report.md, a table of both methods' stages with their run times (``methods_table``) and
  the continuum's pictures; with ``continuum`` alone no DEM model is built and report.md holds
  the continuum column only.
"""
from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

from comparisons.results import _jsonable, software_versions
from comparisons.run_scene import verdict_line

__all__ = ["METHODS", "CONTINUUM_SUMMARY", "check_continuum", "run_continuum",
           "continuum_line", "methods_table", "continuum_picture", "water_at"]

METHODS = ("dem", "continuum", "both")
CONTINUUM_SUMMARY = "continuum.json"        # <out>/<scene name>/<this>, --method continuum|both


def check_continuum(scene) -> None:
    """What ``--method continuum|both`` needs before any compute: the scene's "continuum"
    section, its region materials (built, so their ranges are checked), boundaries on box
    sides (``continuum_ref.scene_run.check_boundaries``) and stages the
    continuum can run (``continuum_ref.scene_run.check_continuum_stages``). ValueError naming
    what is missing or refused."""
    from continuum_ref.scene_run import check_boundaries, check_continuum_stages, \
        region_materials

    if scene.continuum is None:
        raise ValueError(f"scene {scene.name!r} has no \"continuum\" section (mesh size h and "
                         f"each region's material, docs/scenes.md): the continuum cannot run it")
    _, fos = region_materials(scene, scene.continuum["materials"])
    check_boundaries(scene)
    check_continuum_stages(scene, fos)


def run_continuum(scene, folder, path, progress=None, dem=None):
    """Run the scene's stages in the continuum (``continuum_ref.scene_run.run_scene``) and
    write ``continuum.json`` (mesh size, flow, materials, each stage: kind, verdict, value,
    first_failed, max_displacement (m), points (m), seconds, note; runtime_s, error) and the
    report: with ``dem`` (the DEM's records and run time, its report.md already written) the
    DEM-and-continuum table is put into that report (the DEM's time is its summary's
    ``runtime_s``: build and stages, no outputs), else report.md holds the continuum
    column alone. Returns (records, error)."""
    from continuum_ref.scene_run import run_scene as run_continuum_scene

    say = progress or (lambda message: None)
    t0, records, error = time.perf_counter(), [], None
    try:
        records = run_continuum_scene(scene, progress=say,
                                      on_stage=lambda m, r: _draw(scene, folder, m, r))
    except Exception as e:          # kept in the outputs, as a DEM stage that raises
        error = e
    runtime = time.perf_counter() - t0
    section = scene.continuum
    summary = {"scene": scene.name, "file": str(Path(path).resolve()), "method": "continuum",
               "h": section["h"], "flow": section.get("flow", "native"),
               "materials": section["materials"],
               "stages": [dataclasses.asdict(r) for r in records], "runtime_s": runtime,
               "error": None if error is None else f"{type(error).__name__}: {error}",
               "versions": software_versions(), "written": time.strftime("%Y-%m-%d %H:%M:%S")}
    (Path(folder) / CONTINUUM_SUMMARY).write_text(json.dumps(_jsonable(summary), indent=2))
    table = methods_table(scene, records, runtime, error, dem) + _pictures(records, folder)
    report = Path(folder) / "report.md"
    if dem is not None and report.exists():
        text = report.read_text().replace("(scene file, DEM)", "(scene file, DEM and continuum)",
                                          1)
        head, sep, tail = text.partition("\n## Scene\n")
        report.write_text(head + "\n" + table + sep + tail if sep else text + "\n" + table)
    else:
        report.write_text(f"# {scene.name} (scene file, continuum)\n\nFile: "
                          f"`{summary['file']}`\n\n{table}\n## Software\n\n"
                          + "".join(f"- {k}: {v}\n" for k, v in summary["versions"].items()))
    return records, error


def value_words(r) -> str:
    """" F = 1.23", " g = 45.6" or " value = 1.2e+06" (a strength schedule's property) of a
    continuum stage with a value, else ""."""
    name = {"factor_of_safety": "F", "raise_gravity": "g"}.get(r.kind, "value")
    return "" if r.value is None else f" {name} = {r.value:.4g}"


def continuum_line(r) -> str:
    """One line of a continuum stage: kind, verdict, its value, max |u| (mm), seconds."""
    value = value_words(r)
    return (f"stage {r.index} {r.kind}: {r.verdict}{value}, max |u| "
            f"{1e3 * r.max_displacement:.3g} mm, {r.seconds:.1f} s")


def methods_table(scene, records, runtime, error=None, dem=None) -> str:
    """The "DEM and continuum" section of a report: per stage the DEM's verdict line and wall
    seconds (``dem``: (records, runtime_s), or None for the continuum alone) and the
    continuum's verdict, F or g, largest displacement and wall seconds; the run times."""
    from dem_core.workflow.stages import stage_to_dict

    by_dem = {r.index: r for r in (dem[0] if dem else [])}
    by_fe = {r.index: r for r in records}
    section = scene.continuum
    lines = ["## DEM and continuum" if dem else "## Continuum", "",
             f"Continuum: mesh size h = {section['h']:g} m, flow "
             f"{section.get('flow', 'native')!r}, materials "
             + ", ".join(f"{k}: {v.get('kind') if isinstance(v, dict) else v}"
                         for k, v in section["materials"].items())
             + " (continuum_ref.scene_run).", ""]
    head = "| stage | kind |" + (" DEM | DEM s |" if dem else "") + \
        " continuum | F or g | max abs(u) (mm) | continuum s |"
    lines += [head, "|" + "---|" * (head.count("|") - 1)]
    for i, st in enumerate(scene.stages):
        kind, d, r = stage_to_dict(st)["kind"], by_dem.get(i), by_fe.get(i)
        row = f"| {i} | {kind} |"
        if dem:
            row += (f" {verdict_line(d).split(': ', 1)[-1]} | {d.seconds:.1f} |" if d
                    else " not run | |")
        if r:
            row += (f" {r.verdict} | {'' if r.value is None else f'{r.value:.4g}'} | "
                    f"{1e3 * r.max_displacement:.3g} | {r.seconds:.1f} |")
        else:
            row += " not run | | | |"
        lines.append(row)
    times = ([f"DEM {dem[1]:.1f} s"] if dem else []) + [f"continuum {runtime:.1f} s (with "
                                                        f"the mesh)"]
    lines += ["", "Run time: " + ", ".join(times) + "."]
    if error is not None:
        lines += ["", f"**The continuum run stopped with an error:** "
                      f"{type(error).__name__}: {error}"]
    return "\n".join(lines) + "\n"


def continuum_picture(r) -> str:
    """The file name of continuum stage record ``r``'s picture."""
    return f"continuum_stage{r.index}_{r.kind}.png"


def water_at(scene, index):
    """The water table's points [(x, y), ...] m the stages up to ``index`` have set (the last
    water stage's surface), or None (no water, or drained)."""
    from dem_core.workflow.stages import WaterTable

    surface = None
    for st in scene.stages[:index + 1]:
        if isinstance(st, WaterTable):
            surface = st.surface
    return None if surface is None else [tuple(map(float, p)) for p in surface]


def _draw(scene, folder, model, r) -> None:
    """``continuum_picture(r)`` in ``folder``: the continuum at stage ``r``'s end."""
    import matplotlib.pyplot as plt

    from continuum_ref.plot import stage_figure

    value = value_words(r)
    state = (" (state drawn: the last converged level)" if r.kind in
             ("factor_of_safety", "raise_gravity", "strength_schedule") else "")
    fig = stage_figure(model, f"{scene.name}, continuum: end of stage {r.index} of "
                              f"{len(scene.stages)} ({r.kind}): {r.verdict}{value}{state}",
                       water=water_at(scene, r.index))
    fig.savefig(Path(folder) / continuum_picture(r), dpi=100)
    plt.close(fig)


def _pictures(records, folder) -> str:
    """The report's lines for the continuum's pictures that are in ``folder``."""
    have = [r for r in records if (Path(folder) / continuum_picture(r)).exists()]
    if not have:
        return ""
    lines = ["", "### The continuum at each stage's end", ""]
    for r in have:
        lines += [f"![continuum stage {r.index} {r.kind}]({continuum_picture(r)})", ""]
    return "\n".join(lines)
