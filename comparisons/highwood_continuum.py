"""The continuum column of case ``highwood``: the same section in ``continuum_ref``, the same
boundaries and in-situ field, its factor of safety by strength reduction.

Equivalent rock mass (**assumption**: the thesis gives no continuum run for this site): an
isotropic Mohr-Coulomb mass with the intact quartzite's strength of table 5.5 (c 5 MPa,
friction 30 degrees, T 1.6 MPa), E 20 GPa, nu 0.25, dilation 0 (non-associated), density of
25 kN/m3. The bedding (c = 0, T = 0 along one direction) cannot enter an isotropic criterion,
so the continuum has no beds to buckle: its F is the margin of the intact rock mass against a
shear mechanism, the upper bound the beds' slenderness takes away. Stages: gravity, the
geostatic field of ratio k from the crest level (``continuum_ref.from_scene.apply_insitu``),
equilibrium, then F (c, tan(phi) divided by F; ``continuum_ref.ssr.factor_of_safety``).
"""
from __future__ import annotations

import time

from comparisons.scenes import highwood as scene
from dem_core.geometry import GeometrySpec
from dem_core.workflow.insitu import InSitu

F_MAX = 20.0


def equivalent_rock_mass(p: scene.HighwoodParams) -> dict:
    """The Mohr-Coulomb properties (SI units) of the module docstring."""
    return {"cohesion": p.flaw_cohesion, "friction": p.flaw_friction,
            "tensile_strength": p.flaw_tensile_strength}


def factor_of_safety(p: scene.HighwoodParams, h: float) -> dict:
    """F of the section at stress ratio ``p.stress_ratio`` with a mesh of size ``h`` (m)."""
    from continuum_ref import ssr
    from continuum_ref.from_scene import apply_boundaries, apply_insitu, mesh_from_scene, \
        scene_bounds
    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.model import ContinuumModel

    t0 = time.perf_counter()
    sc = scene.scene(p)
    mesh = mesh_from_scene(sc, h, geometry=GeometrySpec([scene.slope_region(p)]))
    rock = MohrCoulomb(E=p.block_E, nu=p.block_nu, dilation=0.0, **equivalent_rock_mass(p))
    cm = ContinuumModel(mesh, rock, sc.density)
    apply_boundaries(cm, sc, scene_bounds(sc))
    cm.set_gravity(1.0)
    apply_insitu(cm, sc, InSitu.geostatic(scene.DENSITY, p.stress_ratio,
                                          surface=p.base + p.slope_height))
    if not cm.equilibrate().converged:
        return {"stress_ratio": p.stress_ratio, "factor_of_safety": None,
                "note": "no equilibrium under the in-situ field", "runtime_s":
                time.perf_counter() - t0}
    cm.reset_displacement()
    fos = ssr.factor_of_safety(cm, [rock], f_max=F_MAX, first_step=1.0, tol=0.05)
    # F: the last stable level when the search ended in a mechanism; a non-convergence
    # without one is reported as such (first_failed, no F); None: stood up to F_MAX
    return {"stress_ratio": p.stress_ratio,
            "factor_of_safety": float(fos.value) if fos.found else None,
            "last_stable": float(fos.value), "first_failed": fos.first_failed,
            "mechanism": bool(fos.mechanism), "runtime_s": time.perf_counter() - t0}


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
