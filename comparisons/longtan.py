"""Case ``longtan``: the block-toppling centrifuge model of the Longtan intake slope, Zhang et
al. (2006) (thesis section 4.3, Tables 4.2 and 4.3).

Methods:

- ``dem``: the damage model (open non-persistent cross joints, Voronoi flaws in the rock
  bridges and the columns near the face), gravity raised step by step to failure
  (``dem_core.workflow.gravity_ramp``, watching points A and B), at the base flaw tensile strength
  (4.81 MPa) first and, in the full variant, lower ones; the cracks at failure and the rupture
  surface (``dem_core.output.rupture``: flaw cracks linked within ``RUPTURE_LINK`` block edges or one
  column spacing, the group reaching the lower half of the face) with its angle to the normal
  of the continuous joints.
- ``conventional``: the thesis's conventional UDEC: fully persistent cross joints carrying the
  bridges' strength smeared as cohesion (0.316 / 0.474 MPa, friction 0), unbreakable flaws.
- ``continuum``: the same section in ``continuum_ref`` (equivalent Mohr-Coulomb rock mass,
  comparisons/longtan_continuum.py), critical g-level.

Failure at a g-level: as in case ``adhikary`` (no equilibrium with A or B still moving by more
than ``CREEP`` over the last fifth of the level, or more than ``FAILURE_DISPLACEMENT`` in one
level; kinetic damping, ``comparisons.centrifuge``); the failure g is the first failed level
after bisecting [last stable, failed] to the variant's ``refine_to``. The scene's
dimensions are assumptions (only the width is given): see comparisons/scenes/longtan.py.
"""
from __future__ import annotations

from comparisons import centrifuge
from comparisons.results import CaseResult, Curve
from comparisons.scenes import longtan as scene
from comparisons.sweep import run_sweep
from comparisons.variants import pick_variant

DESCRIPTION = ("Centrifuge block toppling, Longtan intake slope (Zhang et al. 2006, thesis "
               "4.3): failure g and rupture; damage model vs conventional DEM vs continuum")

MPA = 1e6

REFERENCE = {
    "experiment_failure_g": 130.0,
    "thesis_dem_failure_g": 134.0,
    "thesis_conventional_failure_g": 146.0,
    "experiment_rupture": "through the toe, shallower than conventional UDEC's (fig. 4.22)",
    "source": "Alzo'ubi (2009) thesis 4.3; Zhang, Chen & Wang (2006/2007)",
}

# solver (both variants): Model options over the scene's for every run, e.g. {"edge_elements":
# True}; neither contact model makes the failure g converge with block size here (the bridges'
# tips: docs/verification.md)
VARIANTS = {
    # quick: 8 mm blocks near the face (about 1.5 across the toe column's bridges, 2 across
    # the others'), 40 g levels bisected to 10 g, the base strength only; on the step from the
    # largest eigenvalue (``step_estimate="eigen"``, 1.55 times the bounded one), so 19,000
    # steps a level are the old 30,000 bounded steps' simulated time (about 40 s on 2 cores
    # against 65 s: docs/comparisons.md)
    "quick": dict(edge_length=0.008, relax_iterations=10, g_levels=list(range(40, 401, 40)),
                  refine_to=10.0, max_steps=19_000, tensile=[4.81e6], conventional=True,
                  continuum=True, continuum_h=0.02, workers=2, threads=1,
                  solver={"step_estimate": "eigen"},
                  judge="response"),
    # full: 5 mm blocks (2.3 across the toe bridges), 20 g levels bisected to 2 g, three
    # tensile strengths (each run 4-8 minutes on one core: docs/comparisons.md, "After the
    # solver fix")
    "full": dict(edge_length=0.005, relax_iterations=50, g_levels=list(range(20, 601, 20)),
                 refine_to=2.0, max_steps=60_000, tensile=[4.81e6, 3.5e6, 2.5e6], conventional=True,
                 continuum=True, continuum_h=0.008, workers=2, threads=1, solver={},
                 judge="response"),
}

FAILURE_DISPLACEMENT = 0.006     # m in one level: 1.5 % of the slope height
CREEP = 2e-4                     # m over the last fifth of a level: still moving
RUPTURE_LINK = 3.0               # cracks closer than this many block edges are linked ...
TOE_PART = 0.5                   # ... the rupture must reach the lower half of the face


def run_member(member: dict) -> dict:
    """One g-ramp of the scene (a sweep member: plain dict in, plain dict out)."""
    params = scene.LongtanParams(**member["params"])
    run = centrifuge.ramp_run(scene, params, member, FAILURE_DISPLACEMENT, CREEP,
                              rupture_materials=("flaw:",))
    link = max(RUPTURE_LINK * params.edge_length, params.column_spacing)
    run["rupture"] = centrifuge.rupture(run, link, centrifuge.lower_part_of_face(
        scene.face(), TOE_PART), scene.JOINT_DIP, scene.face(), "left")
    return run


def run(variant="quick", seed: int = 1, progress=None) -> CaseResult:
    """Run the case: ``variant`` is "quick", "full" or a settings mapping (``VARIANTS`` keys)."""
    variant, v = pick_variant("longtan", VARIANTS, variant,
                              optional={"solver": {}, "judge": "response"})
    progress = progress or (lambda message: None)
    result = CaseResult("longtan", variant, seed, reference=dict(REFERENCE))
    members = centrifuge.ramp_members(v, seed)
    centrifuge.check_members(scene, scene.LongtanParams, members, FAILURE_DISPLACEMENT, CREEP)
    progress(f"{len(members)} DEM runs (g-levels {v['g_levels'][0]}..{v['g_levels'][-1]})")
    runs = run_sweep(run_member, members, workers=v["workers"], progress=progress)
    by_label = {r["label"]: r for r in runs}
    dem_runs = [by_label[centrifuge.tensile_label(t)] for t in v["tensile"]]
    base_run = dem_runs[0]
    result.methods["dem"] = {
        "failure_g": [[r["params"]["flaw_tensile_strength"] / MPA, r["failure_g"]]
                      for r in dem_runs],
        "last_stable_g": [[r["params"]["flaw_tensile_strength"] / MPA, r["last_stable_g"]]
                          for r in dem_runs],
        "rupture": base_run["rupture"], "cracks": base_run["cracks"],
        "blocks": base_run["blocks"], "contacts": base_run["contacts"],
        "g_step": v["g_levels"][1] - v["g_levels"][0], "g_max": v["g_levels"][-1],
        "g_resolution": v.get("refine_to") or v["g_levels"][1] - v["g_levels"][0],
        "runtime_s": float(sum(r["runtime_s"] for r in dem_runs)),
    }
    result.add_error("dem failure g vs thesis UDEC-DM", base_run["failure_g"], 134.0)
    result.add_error("dem failure g vs experiment", base_run["failure_g"], 130.0)
    if "conventional" in by_label:
        conv = by_label["conventional"]
        result.methods["conventional"] = {
            "failure_g": conv["failure_g"], "last_stable_g": conv["last_stable_g"],
            "rupture": conv["rupture"], "blocks": conv["blocks"],
            "runtime_s": conv["runtime_s"]}
        result.add_error("conventional failure g vs thesis", conv["failure_g"], 146.0,
                         "conventional")
        result.add_error("conventional failure g vs experiment", conv["failure_g"], 130.0,
                         "conventional")
    if v["continuum"]:
        from comparisons.longtan_continuum import run_continuum

        progress("continuum: critical g-level")
        result.methods["continuum"] = run_continuum(v["continuum_h"], v["g_levels"][-1],
                                                    result)
        result.add_error("continuum failure g vs experiment",
                         result.methods["continuum"]["failure_g"], 130.0, "continuum")
    _curves_and_figures(result, runs, base_run)
    result.notes += [
        "Only the model width (0.752 m) is given; slope height 0.40 m, face 75 degrees, base "
        "0.10 m, column spacing 50 mm, cross-joint spacing 100 mm and the bridges at the "
        "columns' back sides are assumptions (comparisons/scenes/longtan.py), so the failure "
        "g-levels compare the methods with each other more than with the thesis's numbers.",
        "Flaw cohesion 1.58 MPa derived from the conventional base cohesions 0.474 = 0.3 x "
        "1.58 and 0.316 = 0.2 x 1.58 MPa; flaw friction 0 as the bases' (the smearing holds "
        "only with equal friction on bridge and joint).",
        "Conventional: the smeared base cohesion is kept after slip (plastic, as in the "
        "Goodman-Bray analysis Zhang et al. extended); the intact rock is elastic (glued "
        "flaws), so it cannot yield as UDEC's zones did.",
        f"Failure test on points A and B: no equilibrium with their displacement still growing "
        f"(> {CREEP} m over the last fifth of a level) or > {FAILURE_DISPLACEMENT} m in one "
        f"level; g resolution {result.methods['dem']['g_resolution']} g (bisected); kinetic "
        f"damping. A failure g of None means no failure up to {v['g_levels'][-1]} g; its "
        f"error is then reported as missing.",
    ]
    result.notes += centrifuge.unstable_notes(runs)
    return result


def _name(label: str) -> str:
    return label.replace("=", "").replace(" ", "_")


def _curves_and_figures(result, runs, base_run):
    import numpy as np

    for r in runs:
        result.curves["displacement_" + _name(r["label"])] = Curve(
            ["g_level", "ux_A_m", "ux_B_m"], centrifuge.displacement_rows(r))
        xy = np.asarray(r["crack_xy"], float).reshape(-1, 2)
        result.curves["cracks_" + _name(r["label"])] = Curve(
            ["x_m", "y_m", "mode_1tension_2shear"], np.column_stack([xy, r["crack_mode"]]))
        if r["rupture"] is not None:
            result.curves["rupture_" + _name(r["label"])] = Curve(
                ["x_m", "y_m"], np.asarray(r["rupture"]["polyline"]))
    result.figures["displacement_vs_g"] = centrifuge.displacement_figure(
        runs, result.methods.get("continuum"))
    line = None if base_run["rupture"] is None else base_run["rupture"]["polyline"]
    result.figures["cracks_at_failure"] = centrifuge.cracks_figure(
        scene, base_run, line, f"damage model, {base_run['label']} MPa: flaw cracks at "
        f"failure g = {base_run['failure_g']}")

