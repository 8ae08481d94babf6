"""The continuum column of case ``adhikary``: the same slope in ``continuum_ref``.

Mohr-Coulomb with a tension cut-off, the intact model material's strength smeared over the mass
(flaw c 1.6 MPa, friction 37, T 1.1 MPa; block E 2.6 GPa, nu 0.16): the bedding joints are not
represented, which is the point the thesis makes about continuum models of toppling (ch. 2.3.2,
4.2.2): a continuum cannot form the rupture surface through the columns. Non-associated flow
(dilation 0). Gravity is raised with step cutting until Newton fails to converge or a node moves
more than ``RUNAWAY`` (``continuum_ref.ssr.critical_g``); A and B are the DEM's points.
"""
from __future__ import annotations

import time

import numpy as np

from comparisons.scenes import adhikary as scene

RUNAWAY = 0.02   # m


def run_continuum(h: float, g_max: float, result) -> dict:
    """Critical g, displacement at A and B against g, and a yield-indicator figure."""
    import matplotlib.pyplot as plt

    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.mesh import mesh_from_geometry
    from continuum_ref.model import ContinuumModel
    from continuum_ref.plot import plot_yield
    from continuum_ref.ssr import critical_g

    t0 = time.perf_counter()
    p = scene.AdhikaryParams()
    mesh = mesh_from_geometry(scene.geometry(p), h, points=scene.monitoring_points())
    material = MohrCoulomb(E=p.block_E, nu=p.block_nu, cohesion=p.flaw_cohesion,
                           friction=p.flaw_friction, dilation=0.0,
                           tensile_strength=p.flaw_tensile)
    model = ContinuumModel(mesh, material, scene.DENSITY)
    tol = 1e-9
    model.fix(lambda x: x[1] < tol)
    model.fix(lambda x: (x[0] < tol) | (x[0] > scene.WIDTH - tol), components=(0,))
    model.solve_gravity(1.0)
    limit = critical_g(model, g_max=float(g_max), first_step=max(1.0, g_max / 10.0),
                       tol=1.0, runaway=RUNAWAY)
    hist = {name: np.array([(t, ux) for label, t, ux, _ in model.history[name]
                            if label == "g"]) for name in ("A", "B")}
    fig, ax = plt.subplots(figsize=(6, 5))
    plot_yield(model, ax=ax)
    ax.set_title(f"continuum yield indicator at {limit.value:.0f} g")
    result.figures["continuum_yield"] = fig
    g = hist["A"][:, 0] if len(hist["A"]) else np.zeros(0)
    return {
        "failure_g": limit.first_failed, "last_stable_g": limit.value,
        "g": g.tolist(), "ux_A": hist["A"][:, 1].tolist() if len(g) else [],
        "ux_B": hist["B"][:, 1].tolist() if len(g) else [],
        "newton_iterations": limit.newton_iterations, "cells": int(len(model.triangles()[1])),
        "material": "Mohr-Coulomb c 1.6 MPa, friction 37, T 1.1 MPa, dilation 0 (intact rock "
                    "smeared; no joints)",
        "runtime_s": time.perf_counter() - t0,
    }
