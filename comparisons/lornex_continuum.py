"""The continuum column of case ``lornex``: the same section and stages in ``continuum_ref``.

The rock mass of each RMR zone is Hoek-Brown (1988, disturbed; thesis Table 6.1: UCS 65 MPa,
mi 28, m and s by RMR, a = 0.5) with Table 6.2's modulus Em = 10^((RMR - 10) / 40) GPa and nu
0.3, associated flow (``continuum_ref.materials.HoekBrown``). No joints: the faults and the
secondary joints are in the rock mass's RMR (the classification rates them), so the continuum
is the conventional rock-mass model the mine's engineers used for Table 6.1, not the jointed
one. Stages as the DEM's: gravity with the geostatic stress (k = 1.5, from the pre-mining
surface) brought to equilibrium, the water table (load-stepped pore pressure), then the scene's
groups of mining blocks, each excavated (``ContinuumModel.excavate``: the removed cells' stress
released by load stepping). Mining-induced displacement: each prism's displacement after a
group minus that before the first one (``reset_displacement`` after the water stage).
"""
from __future__ import annotations

import time

import numpy as np

from comparisons.scenes import lornex as scene
from dem_core.geometry import GeometrySpec


def rock_masses(p: scene.LornexParams) -> dict:
    """{region name: HoekBrown} (module docstring)."""
    from continuum_ref.materials import HoekBrown

    out = {}
    for r in scene.regions(p):
        c = scene.RMR[scene.rmr_of(r.name)]
        out[r.name] = HoekBrown(E=c["E"], nu=scene.NU, sci=scene.UCS, mb=c["m"], s=c["s"], a=0.5)
    return out


def run_continuum(p: scene.LornexParams, h: float) -> dict:
    """Mesh size ``h`` (m). Returns {"h", "elements", "stages": [{"blocks", "converged",
    "points": {prism: [ux, uy]}}], "cumulative": {prism: [|u| after each group]}, "runtime_s"};
    a group whose excavation does not converge ends the run (its "converged" is False)."""
    from continuum_ref.from_scene import (apply_boundaries, apply_insitu, apply_water,
                                          mesh_from_scene, scene_bounds)
    from continuum_ref.model import ContinuumModel
    from dem_core.workflow.insitu import InSitu

    t0 = time.perf_counter()
    sc = scene.scene(p, with_stages=False)
    mesh = mesh_from_scene(sc, h, geometry=GeometrySpec(sc.geometry.regions))
    cm = ContinuumModel(mesh, rock_masses(p), p.density)
    apply_boundaries(cm, sc, scene_bounds(sc))
    cm.set_gravity(1.0)
    apply_insitu(cm, sc, InSitu.geostatic(p.density, p.k_ratio,
                                          surface=scene.premining_surface()))
    if not cm.equilibrate().converged:
        raise RuntimeError("continuum: the in-situ field did not come to equilibrium")
    if not apply_water(cm, scene.water_table(p), solve=True).converged:
        raise RuntimeError("continuum: the water table did not come to equilibrium")
    cm.reset_displacement()
    stages, total = [], {k: np.zeros(2) for k in sc.points}
    for group in p.stage_blocks:
        ok = True
        for b in group:
            r = cm.excavate(scene.block_name(b))
            ok = ok and r.converged
            for k, v in r.displacement.items():
                total[k] = total[k] + np.asarray(v, float)
            if not ok:
                break
        stages.append({"blocks": list(group), "converged": bool(ok),
                       "points": {k: [float(v[0]), float(v[1])] for k, v in total.items()}})
        if not ok:
            break
    cumulative = {k: [float(np.hypot(*s["points"][k])) for s in stages] for k in sc.points}
    return {"h": h, "elements": int(mesh.mesh.topology.index_map(2).size_local),
            "stages": stages, "cumulative": cumulative,
            "runtime_s": time.perf_counter() - t0}
