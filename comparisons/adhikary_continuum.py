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

from comparisons.centrifuge import continuum_critical_g
from comparisons.scenes import adhikary as scene

RUNAWAY = 0.02   # m


def run_continuum(h: float, g_max: float, result) -> dict:
    """Critical g, displacement at A and B against g, and a yield-indicator figure."""
    from continuum_ref.from_scene import mesh_from_scene
    from continuum_ref.materials import MohrCoulomb

    t0 = time.perf_counter()
    p = scene.AdhikaryParams()
    sc = scene.scene(p)
    mesh = mesh_from_scene(sc, h)
    material = MohrCoulomb(E=p.block_E, nu=p.block_nu, cohesion=p.flaw_cohesion,
                           friction=p.flaw_friction, dilation=0.0,
                           tensile_strength=p.flaw_tensile_strength)
    out = continuum_critical_g(
        sc, mesh, material, g_max, result, RUNAWAY,
        "Mohr-Coulomb c 1.6 MPa, friction 37, T 1.1 MPa, dilation 0 (intact rock smeared; no "
        "joints)")
    out["runtime_s"] = time.perf_counter() - t0
    return out
