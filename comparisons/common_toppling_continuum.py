"""The continuum column of case ``common_toppling``: the same section and excavation lifts in
``continuum_ref``, then the strength-reduction factor of safety at full height.

Equivalent rock mass (**assumption**; the thesis runs no continuum for this case): the intact
rock of table 5.2 everywhere, Mohr-Coulomb c 5 MPa, phi 30 degrees, tension cut-off 1 MPa,
dilation 0, E 20 GPa, nu 0.25, density as the DEM's. An isotropic continuum cannot hold the
joint set (its c = 0 along one direction only), so this is the rock mass without its joints:
an upper bound that cannot topple. The other bound, the joints' strength everywhere (c = 0,
phi = 30 degrees), needs no run: a cohesionless slope stands only up to its friction angle,
F = tan 30 / tan 60 = 0.33 for the 60 degree face, so it fails at the first lift.

Stages as the DEM's (``scene.height_stages`` without the strength change): gravity on the
unexcavated ground (``solve_gravity``), displacements zeroed, the 12 lifts removed one by
one (``ContinuumModel.excavate``, each with its own load stepping); a lift that does not
converge is the continuum's failure stage; otherwise the factor of safety at full height
(``continuum_ref.ssr.factor_of_safety``: c and tan(phi) divided by F).
"""
from __future__ import annotations

import time

import numpy as np

from comparisons.scenes import common_toppling as scene
from dem_core.geometry import GeometrySpec

MASS = dict(cohesion=5e6, friction=30.0, tensile_strength=1e6, dilation=0.0)


def run_continuum(h: float, result) -> dict:
    """Staged excavation and F at full height of the equivalent mass (module docstring) on a
    mesh of size ``h`` (m); adds the yield figure to ``result``; returns plain data."""
    import matplotlib.pyplot as plt

    from continuum_ref import ssr
    from continuum_ref.from_scene import apply_boundaries, mesh_from_scene, scene_bounds
    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.model import ContinuumModel
    from continuum_ref.plot import plot_yield

    t0 = time.perf_counter()
    p = scene.ToppleParams()
    sc = scene.scene(p)
    plain = GeometrySpec(sc.geometry.regions)           # the regions, no joints, no flaws
    rock = MohrCoulomb(E=p.block_E, nu=p.block_nu, **MASS)
    cm = ContinuumModel(mesh_from_scene(sc, h, geometry=plain), rock, sc.density)
    apply_boundaries(cm, sc, scene_bounds(sc))
    if not cm.solve_gravity(1.0).converged:
        raise RuntimeError("continuum: gravity on the unexcavated ground did not converge")
    cm.reset_displacement()
    moved, failed_at = {}, None
    for k in range(1, scene.N_LIFTS + 1):
        r = cm.excavate(scene.lift_name(k))
        if not r.converged:
            failed_at = scene.height_after(k)
            break
        moved[scene.height_after(k)] = {n: [float(x) for x in u]
                                        for n, u in r.displacement.items()}
    fos = None
    if failed_at is None:
        fos = ssr.factor_of_safety(cm, [rock], f_max=20.0, f_start=1.0, first_step=1.0,
                                   tol=0.05)
    fig, ax = plt.subplots(figsize=(7, 5))
    plot_yield(cm, ax=ax)
    ax.set_title(f"continuum, intact rock of table 5.2 (no joints): "
                 f"{'fails at H = %g m' % failed_at if failed_at else 'F = %.2f' % fos.value}"
                 f"\n{ax.get_title()}", fontsize=8)
    result.figures["continuum_yield"] = fig
    return {
        "material": "Mohr-Coulomb c 5 MPa, phi 30, T 1 MPa, dilation 0 (table 5.2 intact "
                    "rock, no joints)",
        "failure_height_m": failed_at,
        "factor_of_safety": None if fos is None else float(fos.value),
        "fos_first_failed": None if fos is None else fos.first_failed,
        "mechanism": None if fos is None else bool(fos.mechanism),
        "excavation_displacement_m": moved,
        "joints_everywhere_fos": float(np.tan(np.radians(30.0)) /
                                       np.tan(np.radians(scene.FACE_DIP))),
        "cells": int(len(cm.triangles()[1])), "h_m": h,
        "runtime_s": time.perf_counter() - t0,
    }
