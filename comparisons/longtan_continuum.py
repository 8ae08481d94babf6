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

from comparisons.centrifuge import continuum_critical_g
from comparisons.scenes import longtan as scene
from dem_core.geometry import GeometrySpec

RUNAWAY = 0.02   # m


def equivalent_rock_mass(p: scene.LongtanParams) -> dict:
    """Jennings' smeared strength of the jointed mass (module docstring), SI units."""
    k = p.persistence
    tan_phi = (1 - k) * np.tan(np.radians(p.flaw_friction)) + k * np.tan(
        np.radians(p.base_friction))
    return {"cohesion": (1 - k) * p.flaw_cohesion, "friction": float(np.degrees(
        np.arctan(tan_phi))), "tensile_strength": (1 - k) * p.flaw_tensile_strength}


def run_continuum(h: float, g_max: float, result) -> dict:
    """Critical g, displacement at A and B against g, and a yield-indicator figure."""
    from continuum_ref.from_scene import mesh_from_scene
    from continuum_ref.materials import MohrCoulomb

    t0 = time.perf_counter()
    p = scene.LongtanParams()
    mass = equivalent_rock_mass(p)
    sc = scene.scene(p)
    section = GeometrySpec([scene.slope_region()])         # one region: no joints
    mesh = mesh_from_scene(sc, h, geometry=section)
    material = MohrCoulomb(E=p.block_E, nu=p.block_nu, dilation=0.0, **mass)
    out = continuum_critical_g(
        sc, mesh, material, g_max, result, RUNAWAY,
        f"Mohr-Coulomb c {mass['cohesion'] / 1e6:.3f} MPa, friction {mass['friction']:.1f}, "
        f"T {mass['tensile_strength'] / 1e6:.2f} MPa, dilation 0 (bridges smeared, k = 0.7; "
        f"no joints)")
    out["runtime_s"] = time.perf_counter() - t0
    return out
