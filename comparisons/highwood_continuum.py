"""The continuum column of case ``highwood``: the case's scene (comparisons/scenes/highwood.py,
the one its DEM runs: its boundaries, points and in-situ field) in ``continuum_ref``, through
``continuum_ref.scene_run.run_scene``, and its factor of safety by strength reduction.

Material (``continuum_section``): equivalent rock mass (**assumption**: the thesis gives no
continuum run for this site): an isotropic Mohr-Coulomb mass with the intact quartzite's
strength of table 5.5 (c 5 MPa, friction 30 degrees, T 1.6 MPa), E 20 GPa, nu 0.25, dilation 0
(non-associated), density of 25 kN/m3. The bedding (c = 0, T = 0 along one direction) cannot
enter an isotropic criterion, so the continuum has no beds to buckle: its F is the margin of
the intact rock mass against a shear mechanism, the upper bound the beds' slenderness takes
away.

Geometry: the scene's section as one region (``scene.slope_region``, "rock"), not its beds:
they are regions only for the DEM (each bed's own contact materials) and all take the one
material here; meshing their outlines (beds down to 0.4 m) would only crowd the mesh (and
gmsh refuses the quick variant's beds at h = 6 m: "Could not create line"). The one region
takes the back rock's flaw material as its contact material, which the continuum does not
use (a scene names one for every region).

Stages (``continuum_stages``): the continuum's own, not the DEM's (``scene.stages``: strong
quartzite, gravity, the in-situ field, solved, the real strength by ``change_material``, then
a ``strength_schedule`` of the quartzite's T; the contact materials' changes do not reach a
rock mass given by its own entry): the geostatic field of ratio k from the crest level set at
0 g, gravity (the field equilibrated under it, displacements zeroed), then F (c, tan(phi)
divided by F; ``FactorOfSafety`` up to ``F_MAX``, resolution ``F_TOL``).
"""
from __future__ import annotations

import time
from dataclasses import replace

from comparisons.scenes import highwood as scene
from dem_core.geometry import GeometrySpec
from dem_core.workflow.insitu import InSitu
from dem_core.workflow.stages import FactorOfSafety, Gravity

F_MAX = 20.0
F_TOL = 0.05         # resolution of the factor of safety
F_STEP = 1.0         # the search's first and largest step in F (the section's search_step)


def equivalent_rock_mass(p: scene.HighwoodParams) -> dict:
    """The Mohr-Coulomb strength (SI units) of the module docstring."""
    return {"cohesion": p.flaw_cohesion, "friction": p.flaw_friction,
            "tensile_strength": p.flaw_tensile_strength}


def continuum_section(p: scene.HighwoodParams, h: float) -> dict:
    """The scene's "continuum" section: mesh size ``h`` (m) and the rock mass of the module
    docstring as a file entry (Pa, degrees)."""
    rock = {"kind": "mohr_coulomb", "E": p.block_E, "nu": p.block_nu, "dilation": 0.0,
            **equivalent_rock_mass(p)}
    return {"h": float(h), "materials": {"rock": rock}, "search_step": {"F": F_STEP}}


def continuum_stages(p: scene.HighwoodParams) -> list:
    """The in-situ field at ratio ``p.stress_ratio``, gravity, F (module docstring)."""
    field = InSitu.geostatic(scene.DENSITY, p.stress_ratio, surface=p.base + p.slope_height)
    return [field, Gravity(1.0),
            FactorOfSafety((scene.QUARTZITE,), f_levels=(1.0, F_MAX), refine_to=F_TOL)]


def continuum_scene(p: scene.HighwoodParams, h: float):
    """The case's scene as one region with its continuum section and stages (module
    docstring)."""
    sc = scene.scene(p)
    # a scene names a contact material for each region's flaws; the continuum uses none
    mats = dict(sc.materials, **{"flaw:rock": sc.materials["flaw:back"]})
    return replace(sc, geometry=GeometrySpec([scene.slope_region(p)]), materials=mats,
                   stages=continuum_stages(p), continuum=continuum_section(p, h))


def factor_of_safety(p: scene.HighwoodParams, h: float) -> dict:
    """F of the section at stress ratio ``p.stress_ratio`` with a mesh of size ``h`` (m)."""
    from continuum_ref.scene_run import run_scene

    t0 = time.perf_counter()
    records = run_scene(continuum_scene(p, h))
    fos = records[-1]
    if fos.kind != "factor_of_safety":
        return {"stress_ratio": p.stress_ratio, "factor_of_safety": None,
                "note": "no equilibrium under the in-situ field", "runtime_s":
                time.perf_counter() - t0}
    # F: the last stable level when the search ended in a mechanism; a non-convergence
    # without one is reported as such (first_failed, no F); None: stood up to F_MAX
    return {"stress_ratio": p.stress_ratio,
            "factor_of_safety": fos.value if fos.verdict == "limit" else None,
            "last_stable": float(fos.detail["last_converged"]),
            "first_failed": fos.first_failed, "mechanism": fos.verdict == "limit",
            "runtime_s": time.perf_counter() - t0}


def run_continuum(params: dict, ratios, h: float) -> dict:
    """F per stress ratio (None: no mechanism up to ``F_MAX``), the material in words and the
    total run time."""
    t0 = time.perf_counter()
    rows = [factor_of_safety(scene.HighwoodParams(**dict(params, stress_ratio=k)), h)
            for k in ratios]
    p = scene.HighwoodParams(**params)
    return {"stress_ratio": [r["stress_ratio"] for r in rows],
            "factor_of_safety": [r["factor_of_safety"] for r in rows],
            "last_stable": [r.get("last_stable") for r in rows],
            "first_failed": [r.get("first_failed") for r in rows],
            "mechanism": [r.get("mechanism") for r in rows], "h_m": h,
            "f_max": F_MAX,
            "material": f"isotropic Mohr-Coulomb c {p.flaw_cohesion / 1e6:g} MPa, friction "
                        f"{p.flaw_friction:g}, T {p.flaw_tensile_strength / 1e6:g} MPa, dilation 0 "
                        "(intact quartzite, no bedding)",
            "runtime_s": time.perf_counter() - t0}
