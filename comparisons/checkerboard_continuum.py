"""The continuum column of case ``checkerboard``: the same section in ``continuum_ref`` and its
strength-reduction factor of safety per UCS.

Each unit is a Hoek-Brown rock mass (Hoek et al. 2002, D = 0; Table 7.2's GSI and mi; the
weathered units at sigma_ci = UCS, the fresh ones at Table 7.2's sigma_ci) with Table 7.1's E
and nu. Strength reduction needs a Mohr-Coulomb solid (``continuum_ref.ssr``), so each unit is
converted with ``hoek_brown.equivalent_mohr_coulomb`` over sigma3 up to the scene's
``SIGMA3_MAX`` (the same fit as the DEM's flaws; the weathered units' c and friction equal the
flaws'), with the Hoek-Brown tensile strength s sci / mb as the tension cut-off (9-30 kPa: the
rock mass's, not the back-calculated one) and dilation 0. No joints and no fault: the rock
mass's GSI rates them (the continuum is the rock-mass model, as in Hoek-Brown practice).
Gravity to equilibrium (no water: the table lies below the weathered zone), then the factor
of safety.
"""
from __future__ import annotations

import time

from comparisons.scenes import checkerboard as scene
from continuum_ref import hoek_brown as hb
from dem_core.geometry import GeometrySpec


def rock_masses(p: scene.CheckerboardParams) -> dict:
    """{region name: MohrCoulomb} (module docstring)."""
    from continuum_ref.materials import MohrCoulomb

    out = {}
    for r in scene.regions(p):
        unit = scene.unit_of(r.name)
        u = scene.UNITS[unit]
        sci = p.ucs if unit in scene.WEATHERED else u["sci"]
        mb, s, a = hb.parameters(u["gsi"], u["mi"])
        c, phi = hb.equivalent_mohr_coulomb(sci, mb, s, a, scene.SIGMA3_MAX)
        out[r.name] = MohrCoulomb(E=u["E"], nu=u["nu"], cohesion=c, friction=phi,
                                  dilation=0.0, tensile_strength=s * sci / mb)
    return out


def run_continuum(p: scene.CheckerboardParams, h: float, h_far: float | None = None,
                  f_max: float = 8.0) -> dict:
    """Element size ``h`` (m) within 100 m of the cut's toe and crest, growing linearly to
    ``h_far`` (default 4 h) 600 m away (``continuum_ref.mesh.refine_near``). Returns
    {"ucs_MPa", "factor_of_safety", "first_failed", "mechanism", "h", "elements",
    "runtime_s"}."""
    from continuum_ref import ssr
    from continuum_ref.from_scene import apply_boundaries, mesh_from_scene, scene_bounds
    from continuum_ref.mesh import refine_near
    from continuum_ref.model import ContinuumModel

    t0 = time.perf_counter()
    sc = scene.scene(p, stages=[])
    h_far = 4.0 * h if h_far is None else h_far
    field = refine_near([scene.TOE, scene.crest(p)], h, h_far, 100.0, 600.0)
    mesh = mesh_from_scene(sc, h_far, geometry=GeometrySpec(sc.geometry.regions),
                           size_field=field)
    masses = rock_masses(p)
    cm = ContinuumModel(mesh, masses, scene.DENSITY)
    apply_boundaries(cm, sc, scene_bounds(sc))
    cm.set_gravity(1.0)
    if not cm.equilibrate().converged:
        raise RuntimeError("continuum: gravity did not come to equilibrium")
    res = ssr.factor_of_safety(cm, list(cm.materials), f_max=f_max, first_step=0.25,
                               tol=0.02)
    return {"ucs_MPa": p.ucs / 1e6, "factor_of_safety": float(res.value),
            "first_failed": None if res.first_failed is None else float(res.first_failed),
            "mechanism": bool(res.mechanism), "h": h,
            "elements": int(mesh.mesh.topology.index_map(2).size_local),
            "runtime_s": time.perf_counter() - t0}
