"""The continuum column of case ``longtan``: the case's scene (comparisons/scenes/longtan.py,
the one its DEM runs) in ``continuum_ref``, through ``continuum_ref.scene_run.run_scene``.

Material (``continuum_section``): an equivalent Mohr-Coulomb rock mass (**assumption**: the
thesis gives no continuum run for Longtan): the cross joints' rock bridges smeared over the mass
as in the conventional model (Jennings' rule with the other columns' k = 0.7): c = (1 - k)
c_intact + k c_joint = 0.474 MPa, tan(phi) = (1 - k) tan(phi_intact) + k tan(phi_joint) = 0
(both 0, see the scene), T = (1 - k) 4.81 MPa = 1.44 MPa; E 2.0 GPa, nu 0.25; non-associated
(dilation 0). Isotropic: the continuous joints are not represented (their c = 0 along one
direction cannot be in an isotropic criterion), so the continuum is weak in every direction,
not only along the bases.

Geometry: the scene's section as one region (``scene.slope_region``, "rock"), not its five
regions: they split the rock only for the DEM (the Voronoi zone, the joint-bounded rock, the
toe column) and all take the one material here; meshing their outlines would only bend the
mesh. Boundaries, points A and B and density are the scene's.

Stages: the continuum's own (``centrifuge.continuum_stages``), not the DEM's g-ramp: gravity
at 1 g, then raised with step cutting until Newton fails or a node moves more than
``RUNAWAY`` (``continuum_ref.ssr.critical_g``, resolution 1 g).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from comparisons.centrifuge import continuum_critical_g, continuum_search_step, continuum_stages
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


def continuum_section(p: scene.LongtanParams, h: float) -> dict:
    """The scene's "continuum" section: mesh size ``h`` (m) and the rock mass of the module
    docstring as a file entry (Pa, degrees)."""
    rock = {"kind": "mohr_coulomb", "E": p.block_E, "nu": p.block_nu, "dilation": 0.0,
            **equivalent_rock_mass(p)}
    return {"h": float(h), "materials": {"rock": rock}}


def continuum_scene(h: float, g_max: float, p: scene.LongtanParams | None = None):
    """The case's scene as one region with its continuum section and stages (module
    docstring)."""
    p = p or scene.LongtanParams()
    return replace(scene.scene(p), geometry=GeometrySpec([scene.slope_region()]),
                   stages=continuum_stages(g_max, RUNAWAY),
                   continuum={**continuum_section(p, h),
                              "search_step": continuum_search_step(g_max)})


def run_continuum(h: float, g_max: float, result) -> dict:
    """Critical g, displacement at A and B against g, and a yield-indicator figure
    (``centrifuge.continuum_critical_g``)."""
    p = scene.LongtanParams()
    mass = equivalent_rock_mass(p)
    return continuum_critical_g(
        continuum_scene(h, g_max, p), result,
        f"Mohr-Coulomb c {mass['cohesion'] / 1e6:.3f} MPa, friction {mass['friction']:.1f}, "
        f"T {mass['tensile_strength'] / 1e6:.2f} MPa, dilation 0 (bridges smeared, k = 0.7; "
        f"no joints)")
