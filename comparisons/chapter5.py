"""What the thesis's chapter-5 strength-schedule cases (``underdip``, ``coal_buckling``) share:
the stage list "gravity, then the flaws' tensile strength lowered until the slope fails", the
blocks that moved at failure, and the continuum column's strength reduction.

Stage list (``schedule_stages``):

1. gravity switched on with the table's strengths and solved (``failure_displacement``: a slope
   that fails here fails at the table's strength), as the thesis did ("brought to equilibrium
   under gravity loading"). The solver is local damping 0.8 (UDEC's default, the scenes'
   ``solver``). **Why not kinetic damping** (the centrifuge cases' solver): in a trial of the
   underdip slope with kinetic damping, gravity switched on at once broke 4447 flaws in
   tension and the slope collapsed (the blocks fall until the contacts carry them and the
   overshoot breaks the weak bonds), and no level came to equilibrium within 20000 steps;
   with local damping (a trial with 3 m cells) 32 flaws broke and each level came to
   equilibrium (ratio 1e-5) within 1600-5000 steps;
2. ``strength_schedule``: the flaws' tensile strength through ``values`` (each solved to
   equilibrium or judged failed, ``dem_core.workflow.strength.StrengthSchedule``);
3. optionally (``cohesion_values``) a second schedule at the lowest tensile strength reached:
   the flaws' cohesion lowered. It is not in the thesis: it shows which strength the mechanism
   needs when lowering the tensile strength alone does not fail the slope;
4. optionally (``post_failure_steps``) that many more steps at the strengths the model ended
   with (the first failed level, if one failed): the search stops as soon as a level is judged
   failed, often when the failing blocks have moved only centimetres (the "still moving"
   verdict); the extra steps let the mechanism develop so that the blocks that moved can be
   told from the elastic settlement (a slope that stood does not move in them).

The mechanism (``moving_blocks``): the blocks that moved during the post-failure steps by more
than a fraction (0.2) of the motion of the fastest 1 % of the blocks then (the 99th percentile
of the active blocks' motion: a few loose blocks running off the crest do not set the scale;
with one rounding radius on every block, tried on 2026-12-02, they ran 0.34 m where the
underdip slope's failing mass moved 0.05-0.15 m, and the largest motion left out everything
below mid-height; with sharp corners the two rules agree, 0.087 against 0.090 H).
Their motion in those steps, not their displacement since the start, picks them out: the elastic
settlement under gravity (up to 5 cm at the face of the underdip slope) is as large as a
mechanism that has just started, and under local damping a failing slope creeps (0.1-0.3 m in
10,000-20,000 steps).
"""
from __future__ import annotations

import time

import numpy as np

from dem_core.workflow.stages import Cycle, Gravity, Solve
from dem_core.workflow.strength import StrengthSchedule


def schedule_stages(flaws: str, values, watch, *, max_steps: int,
                    failure_displacement: float, creep: float, cohesion_values=(),
                    post_failure_steps: int = 0, ratio: float = 1e-5) -> list:
    """The stage list of the module docstring. ``flaws``: the material the schedules lower;
    ``values`` (Pa, decreasing); ``watch``: point names judged; ``max_steps``,
    ``failure_displacement`` (m), ``creep`` (m) per level as in ``limit.search_failure``."""
    judge = dict(max_steps=max_steps, failure_displacement=failure_displacement, creep=creep,
                 watch=tuple(watch), ratio=ratio)
    out = [Gravity(1.0), Solve(ratio, max_steps, failure_displacement=failure_displacement),
           StrengthSchedule(flaws, "tensile_strength", tuple(values), **judge)]
    if len(cohesion_values):
        out.append(StrengthSchedule(flaws, "cohesion", tuple(cohesion_values), **judge))
    if post_failure_steps:
        out.append(Cycle(int(post_failure_steps)))
    return out


def variant_stages(flaws: str, v: dict, watch, failure_displacement: float,
                   creep: float) -> list:
    """``schedule_stages`` from a case variant ``v`` (``values`` and ``cohesion_values`` in
    kPa, ``max_steps``, ``post_failure_steps``)."""
    return schedule_stages(flaws, [1e3 * t for t in v["values"]], watch,
                           max_steps=v["max_steps"], failure_displacement=failure_displacement,
                           creep=creep, cohesion_values=[1e3 * c for c in v["cohesion_values"]],
                           post_failure_steps=v["post_failure_steps"])


def run_schedule(sc, member: dict, locate, read=None) -> tuple:
    """Run scene ``sc`` (stages from ``schedule_stages``) as a sweep member
    (``staged.stage_run``, with the blocks' poses after each stage, and ``read``'s results
    after each stage as its ``reads``) and, if a search failed, ``locate(run)`` (the case's
    reading of the mechanism, from ``moving_blocks``). Returns (run without the poses, the
    mechanism or None)."""
    from comparisons import staged

    # on after a failed schedule: the cohesion schedule and the post-failure steps belong to it
    run = staged.stage_run(sc, member, poses=True, stop_on_failure=False, read=read)
    failed = any(s["failure"] is not None for s in run["searches"])
    mechanism = locate(run) if failed else None
    del run["poses"]                   # used up: keep the member's result small
    return run, mechanism


def moving_blocks(run: dict, fraction: float = 0.2, min_motion: float = 0.02,
                  percentile: float = 99.0) -> dict | None:
    """The mechanism of a failed run: the active blocks that moved, during its last stage (the
    post-failure steps), more than ``fraction`` of the ``percentile``-th percentile of the
    active blocks' motion in it (100: the largest block's, the rule before 2026-12-02); None
    when no block moved more than ``min_motion`` (m) then (the slope stood). Needs the run's
    ``poses`` (``staged.stage_run(..., poses=True)``). Returns the blocks' start centroids
    ``xy0`` (n, 2) m, their motion in the last stage ``du`` (n, 2) m, ``largest`` (m) and
    ``scale`` (m, the percentile the fraction is of)."""
    (pos_a, _), (pos_b, _) = run["poses"][-2], run["poses"][-1]
    du = np.asarray(pos_b) - np.asarray(pos_a)
    active = np.asarray(run["picture"]["active"]).astype(bool)
    size = np.hypot(du[:, 0], du[:, 1]) * active
    largest = float(size.max()) if size.size else 0.0
    if largest < min_motion:
        return None
    scale = float(np.percentile(size[active], percentile))
    keep = size > fraction * scale
    return {"xy0": np.asarray(run["picture"]["pos0"])[keep], "du": du[keep],
            "n": int(keep.sum()), "largest": largest, "scale": scale}


def continuum_scene(sc, regions, materials: dict, h: float, f_max: float = 6.0,
                    f_start: float = 1.0):
    """The continuum of a chapter-5 slope: the scene ``sc`` with its section ``regions`` only
    (the scene's Regions, meshed without joints), the continuum section (``materials``:
    region name -> ``continuum_ref`` material, as file entries; mesh size ``h`` m) and the
    stages gravity at 1 g, then the strength-reduction factor of safety from ``f_start`` to
    ``f_max`` (resolution 0.02)."""
    from dataclasses import replace

    from continuum_ref.scene_run import material_entry
    from dem_core.geometry import GeometrySpec
    from dem_core.workflow.stages import FactorOfSafety

    return replace(sc, geometry=GeometrySpec(list(regions)),
                   # (the continuum reduces its own materials: the stage's are the DEM's)
                   stages=[Gravity(1.0), FactorOfSafety(tuple(sc.materials),
                                                        f_levels=(f_start, f_max),
                                                        refine_to=0.02)],
                   continuum={"h": float(h), "materials": {
                       k: material_entry(m) for k, m in materials.items()}})


def continuum_fos(sc):
    """The strength-reduction factor of safety of a ``continuum_scene`` ``sc`` (the section
    meshed without joints, under gravity with the scene's boundaries) through
    ``continuum_ref.scene_run.run_scene``. Returns a dict:
    ``factor_of_safety`` (None without a mechanism up to the stage's last level),
    ``last_converged``, ``first_failed``, ``mechanism``, ``runtime_s`` (meshing included)."""
    from continuum_ref.scene_run import run_scene

    t0 = time.perf_counter()
    records = run_scene(sc)
    fos = records[-1]
    if fos.kind != "factor_of_safety":
        return {"factor_of_safety": None, "first_failed": 1.0, "mechanism": False,
                "note": "no equilibrium under gravity at F = 1",
                "runtime_s": time.perf_counter() - t0}
    last = fos.detail.get("last_converged")
    return {"factor_of_safety": fos.value if fos.verdict == "limit" else None,
            "last_converged": None if last is None else float(last),
            "first_failed": fos.first_failed, "mechanism": fos.verdict == "limit",
            "runtime_s": time.perf_counter() - t0}

