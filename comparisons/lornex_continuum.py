"""The continuum column of case ``lornex``: the case's scene (comparisons/scenes/lornex.py, the
one its DEM runs: the same section, regions, mining blocks, in-situ field and water table) in
``continuum_ref``, through ``continuum_ref.scene_run.run_scene``.

Material (``continuum_section``): the rock mass of each RMR zone is Hoek-Brown (1988,
disturbed; thesis Table 6.1: UCS 65 MPa, mi 28, m and s by RMR, a = 0.5) with Table 6.2's
modulus Em = 10^((RMR - 10) / 40) GPa and nu 0.3, associated flow
(``continuum_ref.materials.HoekBrown``). No joints: the faults and the secondary joints are in
the rock mass's RMR (the classification rates them), so the continuum is the conventional
rock-mass model the mine's engineers used for Table 6.1, not the jointed one.

Stages (``continuum_stages``): the DEM's (``scene.stages``) without its strength changes and
solves (the rock at 10 x its contact strength, then the real one, by ``change_material``: they
do not reach a rock mass given by its own entry), the in-situ field first: the geostatic stress
(k = 1.5, from the pre-mining surface) set at 0 g, gravity (the field equilibrated under it,
displacements zeroed), the water table (load-stepped pore pressure), then each block of the
groups of ``stage_blocks`` excavated (``ContinuumModel.excavate``: the removed cells' stress
released by load stepping). The run stops at a block that does not converge (the DEM's scene
goes on: the mine did). Mining-induced displacement: each prism's displacement after a group
minus that at the end of the water stage.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from comparisons.scenes import lornex as scene
from dem_core.workflow.insitu import InSitu
from dem_core.workflow.stages import Excavate, Gravity


def rock_masses(p: scene.LornexParams) -> dict:
    """{region name: "hoek_brown" file entry (Pa)} (module docstring)."""
    out = {}
    for r in scene.regions(p):
        c = scene.RMR[scene.rmr_of(r.name)]
        out[r.name] = {"kind": "hoek_brown", "E": c["E"], "nu": scene.NU, "sci": scene.UCS,
                       "mb": c["m"], "s": c["s"], "a": 0.5}
    return out


def continuum_section(p: scene.LornexParams, h: float) -> dict:
    """The scene's "continuum" section: mesh size ``h`` (m) and each region's rock mass."""
    return {"h": float(h), "materials": rock_masses(p)}


def continuum_stages(p: scene.LornexParams) -> list:
    """The in-situ field, gravity, the water table, the mining blocks (module docstring)."""
    field = InSitu.geostatic(p.density, p.k_ratio, surface=scene.premining_surface())
    blocks = [Excavate(scene.block_name(b)) for group in p.stage_blocks for b in group]
    return [field, Gravity(1.0), scene.water_table(p)] + blocks


def continuum_scene(p: scene.LornexParams, h: float):
    """The case's scene with its continuum section and stages (module docstring)."""
    return replace(scene.scene(p, with_stages=False), stages=continuum_stages(p),
                   continuum=continuum_section(p, h), after_failure="stop")


def run_continuum(p: scene.LornexParams, h: float) -> dict:
    """Mesh size ``h`` (m). Returns {"h", "elements", "stages": [{"blocks", "converged",
    "points": {prism: [ux, uy]}}], "cumulative": {prism: [|u| after each group]}, "runtime_s"};
    a group whose excavation does not converge ends the run (its "converged" is False)."""
    from continuum_ref.scene_run import run_scene

    t0 = time.perf_counter()
    end = {}
    records = run_scene(continuum_scene(p, h), on_stage=lambda model, rec: end.update(model=model))
    for rec, what in zip(records[1:3], ("the in-situ field", "the water table")):
        if rec.verdict != "equilibrium":
            raise RuntimeError(f"continuum: {what} did not come to equilibrium")
    water, mined = records[2].points, iter(records[3:])
    stages = []
    for group in p.stage_blocks:
        done = [rec for _, rec in zip(group, mined)]
        if not done:
            break
        ok = len(done) == len(group) and all(r.verdict == "equilibrium" for r in done)
        last = done[-1].points
        stages.append({"blocks": list(group), "converged": ok,
                       "points": {k: [last[k][0] - water[k][0], last[k][1] - water[k][1]]
                                  for k in last}})
        if not ok:
            break
    cumulative = {k: [float(np.hypot(*s["points"][k])) for s in stages] for k in water}
    mesh = end["model"].mesh_data.mesh
    return {"h": h, "elements": int(mesh.topology.index_map(2).size_local),
            "stages": stages, "cumulative": cumulative,
            "runtime_s": time.perf_counter() - t0}
