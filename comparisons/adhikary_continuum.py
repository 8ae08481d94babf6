"""The continuum column of case ``adhikary``: the case's scene (comparisons/scenes/adhikary.py,
the one its DEM runs) in ``continuum_ref``, through ``continuum_ref.scene_run.run_scene``.

Material (``continuum_section``): Mohr-Coulomb with a tension cut-off, the intact model
material's strength smeared over the mass (flaw c 1.6 MPa, friction 37, T 1.1 MPa; block E
2.6 GPa, nu 0.16): the bedding joints are not represented, which is the point the thesis makes
about continuum models of toppling (ch. 2.3.2, 4.2.2): a continuum cannot form the rupture
surface through the columns. Non-associated flow (dilation 0).

Stages: the continuum's own (``centrifuge.continuum_stages``), not the DEM's g-ramp: gravity
at 1 g, then raised with step cutting until Newton fails to converge or a node moves more than
``RUNAWAY`` (``continuum_ref.ssr.critical_g``, resolution 1 g); the DEM's ramp starts at its
first level and judges the displacement within a level. A and B are the scene's points.
"""
from __future__ import annotations

from dataclasses import replace

from comparisons.centrifuge import continuum_critical_g, continuum_search_step, continuum_stages
from comparisons.scenes import adhikary as scene

RUNAWAY = 0.02   # m
LABEL = ("Mohr-Coulomb c 1.6 MPa, friction 37, T 1.1 MPa, dilation 0 (intact rock smeared; no "
         "joints)")


def continuum_section(p: scene.AdhikaryParams, h: float) -> dict:
    """The scene's "continuum" section: mesh size ``h`` (m) and the rock mass of the module
    docstring as a file entry (Pa, degrees)."""
    rock = {"kind": "mohr_coulomb", "E": p.block_E, "nu": p.block_nu,
            "cohesion": p.flaw_cohesion, "friction": p.flaw_friction, "dilation": 0.0,
            "tensile_strength": p.flaw_tensile_strength}
    return {"h": float(h), "materials": {"rock": rock}}


def continuum_scene(h: float, g_max: float, p: scene.AdhikaryParams | None = None):
    """The case's scene with its continuum section and stages (module docstring)."""
    p = p or scene.AdhikaryParams()
    return replace(scene.scene(p), stages=continuum_stages(g_max, RUNAWAY),
                   continuum={**continuum_section(p, h),
                              "search_step": continuum_search_step(g_max)})


def run_continuum(h: float, g_max: float, result) -> dict:
    """Critical g, displacement at A and B against g, and a yield-indicator figure
    (``centrifuge.continuum_critical_g``)."""
    return continuum_critical_g(continuum_scene(h, g_max), result, LABEL)
