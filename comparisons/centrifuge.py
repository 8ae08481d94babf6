"""What the centrifuge slope cases share: one g-ramp run of a scene as a sweep member, the
rupture surface from its crack log, and the figures (the failed slope's blocks and cracks,
displacement vs g, a run's g search with each level's verdict, the continuum's yield).

A scene module passed here provides ``scene(params, stages)`` (the ``dem_core.workflow.scene.Scene`` both
methods build from: geometry, materials, boundaries, points "A" and "B", solver), ``profile()``
and ``face()``; see comparisons/scenes/longtan.py. The g-ramp is the scene's one stage
(``dem_core.workflow.stages.RaiseGravity``), run with a checkpoint after each stable level so that a
killed run goes on from its last level (``ramp_run``).
"""
from __future__ import annotations

import textwrap
import time
from pathlib import Path

import numba
import numpy as np

from comparisons import store
from comparisons.progress import ramp_status, report
from dem_core.workflow.gravity_ramp import RampRecord
from dem_core.workflow.limit import load_resumable, remove_resumable, save_resumable
from dem_core.output.plot import block_picture, draw_picture, magnification
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import Gravity, RaiseGravity, check_stages
from dem_core.output.vtk import VtkSeries
from dem_core.output.rupture import angle_to_joint_normal, depth_from_face, find_rupture


# Quasi-static solver of the g-ramps: kinetic damping (dynamic relaxation, checked every 100
# steps) and no local damping. Toppling columns are slender: local damping turns their lowest
# bending mode (tens of thousands of steps) into a creep lasting many levels, so a level never
# settles and "still moving" says more about the step budget than about the slope; with kinetic
# damping a stable level settles within about 20,000 steps and a failing one runs away
# (benchmarks/centrifuge_resolution.py, docs/comparisons.md).
DAMPING = 0.0
KINETIC_DAMPING = 100


def tensile_label(tensile: float) -> str:
    """A run's label from its flaw tensile strength (Pa): "T=1.1" (MPa)."""
    return f"T={tensile / 1e6:g}"


def file_name(label: str) -> str:
    """A run's label as a file name: "T=1.1" -> "T1.1", "bedding c 5 kPa" -> "bedding_c_5_kPa"."""
    return label.replace("=", "").replace(" ", "_")


def ramp_members(v: dict, seed: int, **studies) -> list:
    """The sweep members of a centrifuge case's variant ``v`` (VARIANTS entry): the
    conventional run first if ``v["conventional"]`` (the longest: it does not fail early), then
    one run per flaw tensile strength in ``v["tensile"]`` (Pa; label ``tensile_label``), then one per value of each
    ``studies`` entry: label format -> (parameter name, values in the parameter's units, and
    optionally a divisor for the label), e.g. ``{"flaw friction {:g}": ("flaw_friction",
    [25.0])}`` or ``{"bedding c {:g} kPa": ("bedding_cohesion", [5e3], 1e3)}``. When the run
    writes VTK files (``store.vtk_folder``), each member gets ``vtk``: its file,
    ``<folder>/<label as file name>.vtu``; inside a case run each gets ``checkpoint``, where
    ``ramp_run`` keeps its progress (``store.checkpoint``). ``v["solver"]`` (optional): Model
    options over the scene's for every member, e.g. ``{"edge_elements": True}``; ``v["judge"]``
    (optional, default "response"): how each level is judged (``SolveSettings.judge``)."""
    base = dict(edge_length=v["edge_length"], relax_iterations=v["relax_iterations"], seed=seed)
    common = dict(g_levels=v["g_levels"], max_steps=v["max_steps"], threads=v.get("threads", 1),
                  refine_to=v.get("refine_to"), solver=dict(v.get("solver", {})),
                  judge=v.get("judge", "response"))
    members = []
    if v["conventional"]:
        members.append(dict(label="conventional", params=dict(base, conventional=True),
                            **common))
    members += [dict(label=tensile_label(t), params=dict(base, flaw_tensile_strength=t), **common)
                for t in v["tensile"]]
    for label, (name, values, *divisor) in studies.items():
        scale = divisor[0] if divisor else 1.0
        members += [dict(label=label.format(x / scale), params=dict(base, **{name: x}),
                         **common) for x in values]
    folder = store.vtk_folder()
    for m in members:
        if folder is not None:
            m["vtk"] = str(folder / f"{file_name(m['label'])}.vtu")
        if store.current() is not None:
            m["checkpoint"] = store.checkpoint(m)
    return members


def ramp_stage(member: dict, failure_displacement: float, creep: float) -> RaiseGravity:
    """A member's g-ramp (``ramp_run``): its g-levels, step budget, bisection and judge,
    watching A and B, failing beyond ``failure_displacement`` (m) or ``creep`` (m)."""
    return RaiseGravity(tuple(member["g_levels"]), ratio=1e-5, max_steps=member["max_steps"],
                        failure_displacement=failure_displacement, creep=creep,
                        watch=("A", "B"), refine_to=member.get("refine_to"),
                        settle=bool(member.get("settle", False)),
                        **{k: member[k] for k in ("judge", "windows") if k in member})


def check_members(scene, params_class, members, failure_displacement, creep) -> None:
    """Each member's parameters (``params_class(**params)``), scene (``scene.scene``) and
    g-ramp (``ramp_stage``) built and checked before the sweep starts, as ``Scene`` checks a
    scene file: a negative edge length, g-levels that do not increase, a step budget that is
    not a whole number > 0 are one ValueError naming the member, not a traceback from a
    worker after the sweep has started."""
    for m in members:
        try:
            ramp = ramp_stage(m, failure_displacement, creep)
            scene.scene(params_class(**m["params"]), stages=[ramp])
        except (ValueError, TypeError) as e:
            raise ValueError(f"member {m['label']!r}: {e}") from None


def ramp_run(scene, params, member: dict, failure_displacement: float, creep: float,
             rupture_materials=("flaw:",)) -> dict:
    """Raise gravity on one scene to failure (a ``RaiseGravity`` stage, watching A and B).

    ``member`` holds ``label``, ``params`` (the plain dict of ``params``), ``g_levels``,
    ``max_steps`` and optionally ``settle`` (stop a level early once settled,
    ``limit.search_failure``), ``judge`` and ``windows`` (``SolveSettings``), ``threads``, ``damping`` and ``kinetic_damping`` (the solver,
    default ``DAMPING`` and ``KINETIC_DAMPING``), ``solver`` (further ``Model`` options over
    the scene's, e.g. ``{"edge_elements": True}``), ``refine_to`` (g: bisect the failure bracket
    to this width, ``raise_gravity``), ``vtk`` (a .vtu path: the model's state at the end of
    the ramp is written there, ``Model.write_vtk``, and each level's state to a series
    ``<path without .vtu>/<name>.pvd``, time = g) and ``checkpoint`` (a file stem: the model
    is saved there after each stable level of the first pass, ``limit.save_resumable``; a run
    that finds it goes on from that level with the result of a run that had not stopped, and
    deletes it at the end). After each level the run reports its g, level, steps, elapsed
    time and an estimate of the time left (``comparisons.progress.report``, ``ramp_status``:
    the planned levels are known in advance); the result is a plain dict (a sweep
    member's output) with the histories of A and B, the cracks of the materials whose names
    start with one of ``rupture_materials``, ``picture`` (``dem_core.output.plot.block_picture`` of
    the end of the ramp: the failed state when it failed, with those cracks and the joints),
    ``level_steps`` (each level's steps, in the order of ``g``), ``unstable`` (None, or the
    message of a numerical blow-up of a slope that was not failing: ``raise_gravity`` stops
    there), ``blowups`` ([g, message] of levels that blew up after the slope had started to
    fail: counted as failed) and ``runtime_s``. The rupture is added by ``rupture``.
    """
    t0 = time.perf_counter()
    ramp = ramp_stage(member, failure_displacement, creep)
    sc = scene.scene(params, stages=[ramp])
    checkpoint = member.get("checkpoint")
    saved = load_resumable(checkpoint, RampRecord) if checkpoint else None
    if saved is None:
        threads = min(member.get("threads", 1), numba.config.NUMBA_NUM_THREADS)
        # the case's solver setting wins over the member's own damping (one keyword each)
        model = build_model(sc, **{"threads": threads,
                                   "damping": member.get("damping", DAMPING),
                                   "kinetic_damping": member.get("kinetic_damping",
                                                                 KINETIC_DAMPING),
                                   **member.get("solver", {})})
        check_stages(sc.stages, set(model.blocks.groups), model.materials)
    model, resume = saved if saved is not None else (model, None)
    earlier = 0.0 if resume is None else resume.seconds
    series = _level_series(member.get("vtk"), resume)

    def on_level(m, r):
        stage, left = ramp_status(r, ramp.g_levels, time.perf_counter() - t0 + earlier,
                                  ramp.refine_to)
        report(stage, int(np.sum(r.steps)), left, elapsed=time.perf_counter() - t0 + earlier)
        if series is not None:
            series.add(m, time=r.level[-1])
        if checkpoint:
            save_resumable(checkpoint, m, r)

    rec = ramp.run(model, on_level=on_level, resume=resume)[2]["ramp"]
    if member.get("vtk"):
        model.write_vtk(member["vtk"])
    blocks = model.blocks
    log = model.crack_log()
    keep = np.array([m.startswith(tuple(rupture_materials)) for m in log["material"]], bool)
    out = {
        "label": member["label"], "params": member["params"], "blocks": blocks.n_blocks,
        "contacts": int(model.contacts.n), "g": rec.g, "verdict": rec.verdict,
        "steps": int(np.sum(rec.steps)), "level_steps": [int(k) for k in rec.steps],
        "measure_steps": int(getattr(model, "measured_steps", 0)),
        "failure_g": rec.failure_g,
        "last_stable_g": rec.last_stable_g, "refined_levels": rec.refined,
        "ux_A": rec.point_ux.get("A", []),
        "ux_B": rec.point_ux.get("B", []), "cracks": int(keep.sum()),
        "crack_xy": np.column_stack([log["x"][keep], log["y"][keep]]).tolist(),
        "crack_mode": log["mode"][keep].tolist(),
        "crack_material": [str(m) for m in np.asarray(log["material"])[keep]],
        "unstable": rec.unstable, "blowups": rec.blowups,
        "picture": block_picture(model, cracks=rupture_materials, joints="joint:"),
        "runtime_s": time.perf_counter() - t0 + earlier,
    }
    if checkpoint:
        remove_resumable(checkpoint)
    return out


def _level_series(vtk, resume):
    """The VtkSeries of a ramp's levels next to its final-state file ``vtk`` (None: none);
    a resumed ramp goes on with the levels it had written up to its last stable one."""
    if not vtk:
        return None
    folder = Path(vtk).with_suffix("")
    until = float("-inf") if resume is None else resume.level[-1]
    return VtkSeries.reopen(folder, folder.name, until)


def unstable_notes(runs: list) -> list:
    """A note for each run whose model became numerically unstable: at rest (``raise_gravity``
    stops the ramp there and sets no failure g) or after the slope had started to fail (the
    level counts as failed): the level and the solver's message."""
    notes = [f"{r['label']}: the model became numerically unstable at {r['g'][-1]:g} g, so the "
             f"ramp stopped there (no failure g from it): {r['unstable']}"
             for r in runs if r.get("unstable")]
    for r in runs:
        for g, message in r.get("blowups") or []:
            notes.append(f"{r['label']}: at {g:g} g the failing slope blew the model up after "
                         f"the failure test had been met (the level counts as failed): {message}")
    return notes


def rupture(run: dict, link_distance: float, face_part, joint_dip: float,
            face, dip_direction: str = "left") -> dict | None:
    """The rupture surface of a run's cracks (``dem_core.output.rupture``) as plain data: polyline
    (m, from the face inwards), crack count, angle above the joint normal (deg), depth behind
    ``face`` (m) and length (m); None when no crack group reaches ``face_part``."""
    xy = np.asarray(run["crack_xy"], float).reshape(-1, 2)
    found = find_rupture(xy[:, 0], xy[:, 1], link_distance=link_distance, face=face_part)
    if found is None:
        return None
    return {"polyline": found.polyline.tolist(), "n_cracks": found.n_cracks,
            "angle_above_joint_normal_deg": angle_to_joint_normal(found.direction, joint_dip,
                                                                  dip_direction),
            "depth_m": depth_from_face(found.polyline, face), "length_m": found.length}


def lower_part_of_face(face, fraction: float):
    """The lowest ``fraction`` of a face ((x_toe, y_toe), (x_crest, y_crest))."""
    (tx, ty), (cx, cy) = face
    return (tx, ty), (tx + fraction * (cx - tx), ty + fraction * (cy - ty))


def displacement_rows(run: dict) -> np.ndarray:
    """(n, 3) rows g, ux_A (m), ux_B (m) of a run's levels, sorted by g."""
    if not run["g"]:
        return np.zeros((0, 3))
    rows = np.column_stack([run["g"], run["ux_A"], run["ux_B"]])
    return rows[np.argsort(rows[:, 0], kind="stable")]


def displacement_figure(runs: list, continuum: dict | None = None):
    """Horizontal displacement of points A and B against g for each run (and the continuum);
    levels are drawn in order of g (a bisected ramp runs them out of order). A run whose curve
    coincides with a later run's is drawn wider underneath it (``staged.curve_styles``)."""
    import matplotlib.pyplot as plt

    from comparisons.staged import curve_styles

    fig, ax = plt.subplots(figsize=(8, 4.5))
    # one colour per run (A solid, B dotted): the default cycle repeats after ten runs
    colours = plt.get_cmap("tab10" if len(runs) <= 10 else "tab20")
    rows = [displacement_rows(r) for r in runs]
    for col, point, style in ((1, "A", "-o"), (2, "B", ":s")):
        lines = curve_styles([d[:, [0, col]] for d in rows])
        for i, (r, d, line) in enumerate(zip(runs, rows, lines)):
            ax.plot(d[:, 0], 1e3 * d[:, col], style, color=colours(i),
                    label=f"{point}, {r['label']}", **line)
    if continuum is not None and len(continuum.get("g", [])):
        ax.plot(continuum["g"], 1e3 * np.asarray(continuum["ux_A"]), "k--",
                label="A, continuum")
    ax.set_xlabel("g-level")
    ax.set_ylabel("horizontal displacement (mm, + out of slope)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return fig


def ramp_record(run: dict) -> RampRecord:
    """A ``ramp_run`` result's levels as the ``RampRecord`` it came from (g, verdicts, ux of A
    and B; no largest displacement per level: a run does not keep it)."""
    return RampRecord(level=list(run["g"]), verdict=list(run["verdict"]),
                      steps=list(run.get("level_steps", [])),
                      point_ux={p: list(run[f"ux_{p}"]) for p in ("A", "B")},
                      failure_level=run["failure_g"], last_stable_level=run["last_stable_g"],
                      refined=int(run.get("refined_levels") or 0), unstable=run.get("unstable"))


def ramp_words(run: dict) -> str:
    """A ramp's verdict in words: where it failed and the last g that stood, or that it stood."""
    stood = run["last_stable_g"]
    if run["failure_g"] is not None:
        return (f"fails at {run['failure_g']:g} g (last stable "
                f"{'none' if stood is None else f'{stood:g} g'})")
    if run.get("unstable"):
        return f"numerically unstable at {run['g'][-1]:g} g, no failure g"
    return f"no failure: stands at {run['g'][-1]:g} g, the last level" if run["g"] else "no level"


def search_plot(run: dict):
    """A run's g search (``comparisons.scene_figures.search_figure``): the horizontal
    displacement of A and B at the end of each level against g, each level's marker by its
    verdict, the last stable and first failed g marked."""
    from comparisons.scene_figures import search_figure

    return search_figure(ramp_record(run), f"g search, {run['label']}: {ramp_words(run)}")


def cracks_figure(scene, run: dict, rupture_line=None, title: str = "", references=()):
    """The failed slope: the run's blocks at the end of its run (displacement magnified, the
    factor in the title, coloured by the true displacement in mm), the joints, the cracks
    (tension red, shear blue, along the broken bonds), its rupture surface and points A and B;
    ``references``: (label, (n, 2) m polylines) pairs, each drawn dashed (e.g. an experiment's
    fracture paths, ``experiment_paths``). A run without a
    ``picture`` (``ramp_run``) is drawn as its cracks' points on the section."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5))
    pic = run.get("picture")
    if pic is not None:
        k = magnification(pic)
        draw_picture(pic, ax, k, rupture=rupture_line, unit="mm")
        title += (f"\nblocks at the end of the run, displacement drawn x {k:g} "
                  f"(colour: true displacement)")
    else:
        _crack_points(ax, scene, run, rupture_line)
    for (label, lines), style in zip(references, ("k--", "m:", "c-.")):
        for i, line in enumerate(lines):
            line = np.asarray(line, float)
            ax.plot(line[:, 0], line[:, 1], style, lw=1.5, label=None if i else label)
    for name, (x, y) in scene.monitoring_points().items():
        ax.plot(x, y, "k^")
        ax.annotate(name, (x, y), xytext=(4, 4), textcoords="offset points")
    ax.set_aspect("equal")
    # each line wrapped to the axes' width: a title wider than the axes ran under the colour bar
    ax.set_title("\n".join(textwrap.fill(t, 80) for t in title.split("\n")), fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="lower left")
    return fig


def _crack_points(ax, scene, run, rupture_line):
    """The section's outline with the run's cracks as points and the rupture polyline."""
    ring = scene.profile()
    ax.fill(*np.array(ring + [ring[0]]).T, color="0.9")
    xy = np.asarray(run["crack_xy"], float).reshape(-1, 2)
    mode = np.asarray(run["crack_mode"])
    for m, colour, label in ((1, "red", "tension"), (2, "blue", "shear")):
        k = mode == m
        if k.any():
            ax.plot(xy[k, 0], xy[k, 1], ".", ms=3, color=colour, label=f"cracks ({label})")
    if rupture_line is not None:
        line = np.asarray(rupture_line)
        ax.plot(line[:, 0], line[:, 1], "k-", lw=2, label="rupture surface")


CONTINUUM_G_TOL = 1.0    # g: resolution of the continuum's critical g


def continuum_search_step(g_max: float) -> dict:
    """The continuum section's ``search_step`` of a centrifuge case: the critical-g search's
    first and largest step, a tenth of ``g_max`` and at least 1 g (the step the hand-built
    columns used before they came from the scenes)."""
    return {"g": max(1.0, float(g_max) / 10.0)}


def continuum_stages(g_max: float, runaway: float) -> list:
    """The continuum's stage list of a centrifuge case (``continuum_critical_g``): gravity at
    1 g, then raised towards ``g_max`` until a limit (``continuum_ref.ssr.critical_g``,
    resolution ``CONTINUUM_G_TOL``; a node moving more than ``runaway`` m counts as failed).
    Not the DEM's ramp: that starts at its first level and judges the displacement within
    each level; the continuum starts from equilibrium at 1 g and judges the total."""
    return [Gravity(1.0), RaiseGravity((1.0, float(g_max)), failure_displacement=runaway,
                                       refine_to=CONTINUUM_G_TOL)]


def continuum_critical_g(sc, result, label: str) -> dict:
    """The continuum column of a centrifuge case: the scene ``sc`` (the DEM's, with a
    "continuum" section and ``continuum_stages``: its boundaries, points A and B and density)
    run by ``continuum_ref.scene_run.run_scene``. Adds the yield-indicator figure at the end
    of the search to ``result`` and returns failure g (the first failed g, None: none up to
    g_max), last stable g, ux of A and B against g (m), Newton iterations of the search,
    cells, ``label`` (the material in words) and runtime_s (s, meshing included)."""
    import matplotlib.pyplot as plt

    from continuum_ref.plot import plot_yield
    from continuum_ref.scene_run import run_scene

    t0 = time.perf_counter()
    end = {}
    records = run_scene(sc, on_stage=lambda model, rec: end.update(model=model))
    model, ramp = end["model"], records[-1]
    if ramp.kind != "raise_gravity":
        raise RuntimeError(f"continuum: stage {ramp.index} ({ramp.kind}) {ramp.verdict}: "
                           f"{ramp.note}")
    stood = ramp.detail["last_converged"]
    hist = {name: np.array([(t, ux) for kind, t, ux, _ in model.history[name]
                            if kind == "g"]) for name in ("A", "B")}
    fig, ax = plt.subplots(figsize=(6, 5))
    plot_yield(model, ax=ax)
    when = (f"no failure up to {stood:.0f} g" if ramp.first_failed is None else
            f"fails at {ramp.first_failed:.0f} g; shown at {stood:.0f} g")
    ax.set_title(f"continuum ({label.split(',')[0]}): {when}\n{ax.get_title()}", fontsize=9)
    result.figures["continuum_yield"] = fig
    if store.vtk_folder() is not None:
        from continuum_ref.vtk import write_xdmf

        write_xdmf(model, store.vtk_folder() / "continuum.xdmf", time=float(stood))
    g = hist["A"][:, 0] if len(hist["A"]) else np.zeros(0)
    return {
        "failure_g": ramp.first_failed, "last_stable_g": stood,
        "g": g.tolist(), "ux_A": hist["A"][:, 1].tolist() if len(g) else [],
        "ux_B": hist["B"][:, 1].tolist() if len(g) else [],
        "newton_iterations": ramp.detail["newton_iterations"],
        "cells": int(len(model.triangles()[1])), "material": label,
        "runtime_s": time.perf_counter() - t0,
    }
