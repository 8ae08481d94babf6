"""The continuum column of case ``checkerboard``: the case's scene (comparisons/scenes/
checkerboard.py, the one its DEM runs) with a "continuum" section and the continuum's stages
(``continuum_scene``), and its strength-reduction factor of safety per UCS.

Material (``continuum_section``): each unit is a Hoek-Brown rock mass (Hoek et al. 2002,
D = 0; Table 7.2's GSI and mi; the weathered units at sigma_ci = UCS, the fresh ones at Table
7.2's sigma_ci) with Table 7.1's E and nu. Strength reduction needs a Mohr-Coulomb solid
(``continuum_ref.ssr``), so each unit is converted with ``hoek_brown.equivalent_mohr_coulomb``
over sigma3 up to the scene's ``SIGMA3_MAX`` (the same fit as the DEM's flaws; the weathered
units' c and friction equal the flaws'), with the Hoek-Brown tensile strength s sci / mb as the
tension cut-off (9-28 kPa in the weathered units: the rock mass's, not the back-calculated
one) and dilation 0: a "mohr_coulomb" entry per region (a "hoek_brown" entry would carry
gravity on the Hoek-Brown criterion itself, not on the fit that is reduced). No joints and no
fault: the rock mass's GSI rates them (the continuum is the rock-mass model, as in Hoek-Brown
practice).

Stages: the continuum's own, not the DEM's (``base_stages``: gravity at 10 x the flaws'
strength, their real strengths by ``change_material``, the water table; the slivers'
excavation): gravity to equilibrium, then the factor of safety (``FactorOfSafety`` up to
``f_max``, resolution ``F_TOL``). The contact materials' changes do not reach a rock mass given
by its own entry, and the water is left out as before (the table lies below the weathered
zone).

The mesh is graded (the section's ``refine``): h within 100 m of the cut's toe and crest,
growing linearly to 4 h 600 m away; at a uniform 20 m (the quick variant's h) F moves by 1-2 %
and the searches end without a mechanism (docs/comparisons.md, "Continuum columns from the
scene files"). Run by ``continuum_ref.scene_run.run_scene``.
"""
from __future__ import annotations

import time
from dataclasses import replace

from comparisons.scenes import checkerboard as scene
from continuum_ref import hoek_brown as hb
from dem_core.workflow.stages import FactorOfSafety, Gravity

F_TOL = 0.02        # resolution of the factor of safety


def rock_masses(p: scene.CheckerboardParams) -> dict:
    """{region name: "mohr_coulomb" file entry (Pa, degrees)} (module docstring)."""
    out = {}
    for r in scene.regions(p):
        unit = scene.unit_of(r.name)
        u = scene.UNITS[unit]
        sci = p.ucs if unit in scene.WEATHERED else u["sci"]
        mb, s, a = hb.parameters(u["gsi"], u["mi"])
        c, phi = hb.equivalent_mohr_coulomb(sci, mb, s, a, scene.SIGMA3_MAX)
        out[r.name] = {"kind": "mohr_coulomb", "E": u["E"], "nu": u["nu"], "cohesion": c,
                       "friction": phi, "dilation": 0.0, "tensile_strength": s * sci / mb}
    return out


def continuum_section(p: scene.CheckerboardParams, h: float, h_far: float | None = None) -> dict:
    """The scene's "continuum" section: mesh size ``h`` (m) within 100 m of the cut's toe and
    crest, growing to ``h_far`` (default 4 h) 600 m away, and each region's rock mass."""
    return {"h": float(h), "materials": rock_masses(p),
            "refine": {"points": [list(map(float, scene.TOE)),
                                  list(map(float, scene.crest(p)))],
                       "h_far": float(4.0 * h if h_far is None else h_far),
                       "d_near": 100.0, "d_far": 600.0}}


def continuum_scene(p: scene.CheckerboardParams, h: float, f_max: float = 8.0,
                    h_far: float | None = None):
    """The case's scene with its continuum section and stages (module docstring)."""
    sc = scene.scene(p, stages=[])
    flaws = tuple(sorted(n for n in sc.materials if n.startswith("flaw:")))
    stages = [Gravity(1.0), FactorOfSafety(flaws, f_levels=(1.0, float(f_max)),
                                           refine_to=F_TOL)]
    return replace(sc, stages=stages, continuum=continuum_section(p, h, h_far))


def run_continuum(p: scene.CheckerboardParams, h: float, h_far: float | None = None,
                  f_max: float = 8.0) -> dict:
    """The factor of safety of ``continuum_scene`` by ``continuum_ref.scene_run.run_scene``.
    Returns {"ucs_MPa", "factor_of_safety" (the last stable F), "first_failed", "mechanism",
    "h", "elements", "runtime_s"}."""
    from continuum_ref.scene_run import run_scene

    t0 = time.perf_counter()
    seen = {}
    records = run_scene(continuum_scene(p, h, f_max, h_far),
                        on_stage=lambda model, rec: seen.update(model=model))
    fos = records[-1]
    if fos.kind != "factor_of_safety":
        raise RuntimeError(f"continuum: stage {fos.index} ({fos.kind}) {fos.verdict}: {fos.note}")
    mesh = seen["model"].mesh_data.mesh
    return {"ucs_MPa": p.ucs / 1e6, "factor_of_safety": float(fos.detail["last_converged"]),
            "first_failed": fos.first_failed, "mechanism": fos.verdict == "limit", "h": h,
            "elements": int(mesh.topology.index_map(2).size_local),
            "runtime_s": time.perf_counter() - t0}
