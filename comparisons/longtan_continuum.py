"""The continuum column of case ``longtan``: the same slope in ``continuum_ref``.

An equivalent Mohr-Coulomb rock mass (**assumption**: the thesis gives no continuum run for
Longtan): the cross joints' rock bridges smeared over the mass as in the conventional model
(Jennings' rule with the other columns' k = 0.7): c = (1 - k) c_intact + k c_joint = 0.474
MPa, tan(phi) = (1 - k) tan(phi_intact) + k tan(phi_joint) = 0 (both 0, see the scene),
T = (1 - k) 4.81 MPa = 1.44 MPa; E 2.0 GPa, nu 0.25; non-associated (dilation 0). Isotropic:
the continuous joints are not represented (their c = 0 along one direction cannot be in an
isotropic criterion), so the continuum is weak in every direction, not only along the bases.
Gravity is raised with step cutting until Newton fails or a node runs away
(``continuum_ref.ssr.critical_g``); A and B are the DEM's points.
"""
from __future__ import annotations

import time

import numpy as np

from comparisons.scenes import longtan as scene
from dem_core.geometry import GeometrySpec

RUNAWAY = 0.02   # m


def equivalent_rock_mass(p: scene.LongtanParams) -> dict:
    """Jennings' smeared strength of the jointed mass (module docstring), SI units."""
    k = p.persistence
    tan_phi = (1 - k) * np.tan(np.radians(p.flaw_friction)) + k * np.tan(
        np.radians(p.base_friction))
    return {"cohesion": (1 - k) * p.flaw_cohesion, "friction": float(np.degrees(
        np.arctan(tan_phi))), "tensile_strength": (1 - k) * p.flaw_tensile}


def run_continuum(h: float, g_max: float, result) -> dict:
    """Critical g, displacement at A and B against g, and a yield-indicator figure."""
    import matplotlib.pyplot as plt

    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.mesh import mesh_from_geometry
    from continuum_ref.model import ContinuumModel
    from continuum_ref.plot import plot_yield
    from continuum_ref.ssr import critical_g

    t0 = time.perf_counter()
    p = scene.LongtanParams()
    mass = equivalent_rock_mass(p)
    section = GeometrySpec([scene.slope_region()])         # one region: no joints
    mesh = mesh_from_geometry(section, h, points=scene.monitoring_points())
    material = MohrCoulomb(E=p.block_E, nu=p.block_nu, dilation=0.0, **mass)
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
        "material": (f"Mohr-Coulomb c {mass['cohesion'] / 1e6:.3f} MPa, friction "
                     f"{mass['friction']:.1f}, T {mass['tensile_strength'] / 1e6:.2f} MPa, "
                     "dilation 0 (bridges smeared, k = 0.7; no joints)"),
        "runtime_s": time.perf_counter() - t0,
    }
