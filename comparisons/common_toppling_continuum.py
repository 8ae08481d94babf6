"""The continuum column of case ``common_toppling``: the case's scene (comparisons/scenes/
common_toppling.py, the one its DEM runs: the same section, regions and excavation lifts) in
``continuum_ref``, through ``continuum_ref.scene_run.run_scene``, then the strength-reduction
factor of safety at full height.

Material (``continuum_section``): equivalent rock mass (**assumption**; the thesis runs no
continuum for this case): the intact rock of table 5.2 everywhere, Mohr-Coulomb c 5 MPa, phi 30
degrees, tension cut-off 1 MPa, dilation 0, E 20 GPa, nu 0.25, density as the DEM's. An
isotropic continuum cannot hold the joint set (its c = 0 along one direction only), so this is
the rock mass without its joints: an upper bound that cannot topple. The other bound, the
joints' strength everywhere (c = 0, phi = 30 degrees), needs no run: a cohesionless slope stands
only up to its friction angle, F = tan 30 / tan 60 = 0.33 for the 60 degree face, so it fails
at the first lift.

Stages (``continuum_stages``): the DEM's ``height_stages`` without its strength changes and
solves (``change_material`` of the contact materials, which do not reach a rock mass given by
its own entry): gravity on the unexcavated ground, the 12 lifts removed one by one
(``ContinuumModel.excavate``, each with its own load stepping; the scene stops after a lift
that does not converge: the continuum's failure stage), then the factor of safety at full
height (``FactorOfSafety`` up to ``F_MAX``, resolution ``F_TOL``; c and tan(phi) divided by F).
Each lift's displacement is the change of the points' displacement over its stage.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from comparisons.scenes import common_toppling as scene
from dem_core.workflow.stages import Excavate, FactorOfSafety, Gravity

MASS = dict(cohesion=5e6, friction=30.0, tensile_strength=1e6, dilation=0.0)
F_MAX = 20.0
F_TOL = 0.05         # resolution of the factor of safety
F_STEP = 1.0         # the search's first and largest step in F (the section's search_step)


def continuum_section(p: scene.ToppleParams, h: float) -> dict:
    """The scene's "continuum" section: mesh size ``h`` (m) and the rock mass of the module
    docstring for every region, as a file entry (Pa, degrees)."""
    return {"h": float(h), "materials": {"*": {"kind": "mohr_coulomb", "E": p.block_E,
                                               "nu": p.block_nu, **MASS}},
            "search_step": {"F": F_STEP}}


def continuum_stages() -> list:
    """Gravity, the lifts one by one, F at full height (module docstring)."""
    lifts = [Excavate(scene.lift_name(k)) for k in range(1, scene.N_LIFTS + 1)]
    return [Gravity(1.0)] + lifts + [FactorOfSafety(("*",), f_levels=(1.0, F_MAX),
                                                    refine_to=F_TOL)]


def continuum_scene(h: float, p: scene.ToppleParams | None = None):
    """The case's scene with its continuum section and stages (module docstring)."""
    p = p or scene.ToppleParams()
    return replace(scene.scene(p), stages=continuum_stages(),
                   continuum=continuum_section(p, h))


def run_continuum(h: float, result) -> dict:
    """Staged excavation and F at full height of the equivalent mass (module docstring) on a
    mesh of size ``h`` (m); adds the yield figure to ``result``; returns plain data."""
    import matplotlib.pyplot as plt

    from continuum_ref.plot import plot_yield
    from continuum_ref.scene_run import run_scene

    t0 = time.perf_counter()
    end = {}
    records = run_scene(continuum_scene(h), on_stage=lambda model, rec: end.update(model=model))
    cm = end["model"]
    if records[0].verdict != "equilibrium":
        raise RuntimeError("continuum: gravity on the unexcavated ground did not converge")
    moved, failed_at, fos = {}, None, None
    for k, (before, rec) in enumerate(zip(records, records[1:]), start=1):
        if rec.kind == "factor_of_safety":
            fos = rec
        elif rec.verdict != "equilibrium":
            failed_at = scene.height_after(k)
        else:
            moved[scene.height_after(k)] = {
                n: [rec.points[n][0] - before.points[n][0], rec.points[n][1] - before.points[n][1]]
                for n in rec.points}
    fig, ax = plt.subplots(figsize=(7, 5))
    plot_yield(cm, ax=ax)
    ax.set_title(f"continuum, intact rock of table 5.2 (no joints): "
                 f"{'fails at H = %g m' % failed_at if failed_at else 'F = %.2f' % _last(fos)}"
                 f"\n{ax.get_title()}", fontsize=8)
    result.figures["continuum_yield"] = fig
    return {
        "material": "Mohr-Coulomb c 5 MPa, phi 30, T 1 MPa, dilation 0 (table 5.2 intact "
                    "rock, no joints)",
        "failure_height_m": failed_at,
        "factor_of_safety": None if fos is None else _last(fos),
        "fos_first_failed": None if fos is None else fos.first_failed,
        "mechanism": None if fos is None else fos.verdict == "limit",
        "excavation_displacement_m": moved,
        "joints_everywhere_fos": float(np.tan(np.radians(30.0)) /
                                       np.tan(np.radians(scene.FACE_DIP))),
        "cells": int(len(cm.triangles()[1])), "h_m": h,
        "runtime_s": time.perf_counter() - t0,
    }


def _last(fos) -> float:
    """The last stable F of a factor-of-safety record (its value when it found a limit)."""
    return float(fos.detail["last_converged"])
