"""Case ``common_toppling``: block-flexural toppling of an excavated slope with one joint set
dipping 80 degrees into it, after Nichol et al. (2002) (thesis 5.2.2, figs 5.6-5.10, tables 5.2
and 5.3). Scene and every geometry assumption:
comparisons/scenes/common_toppling.py.

Two studies, each a list of sweep members (``comparisons.staged.stage_run``):

- **Strength study** (the 6 m model, table 5.2): under gravity with high strength, all 12 lifts
  removed together, solved; then table 5.2 is assigned with the flaws' tensile strength at
  ``T_START`` (above the thesis's 7 MPa that held) and T is lowered through the variant's
  ``t_values`` (``StrengthSchedule`` on the intact rock ``"*"``, bisected to ``refine_to``):
  the T at which a rupture forms. The thesis raised T from 1 MPa until the slope held (7 MPa)
  and then lowered it to 6.8 MPa; lowering from a stable state is the same bracket without
  re-running broken states. The same schedule is run with the flaws' friction 30 -> 50
  degrees and cohesion 5 -> 15 MPa (the thesis: neither stops the rupture, so T at rupture
  should not move) and in conventional mode (unbreakable flaws: the thesis's conventional UDEC
  without cross joints, which cannot form a rupture).
- **Layer thickness study** (table 5.3): for each spacing and T, table 5.3 is assigned under
  gravity before any excavation, then the lifts are removed one by one, each followed by a
  solve; the run stops at the first solve that fails (``stop_on_failure``). Hc = the slope
  height after that lift (``scene.height_after``); None when all 12 lifts stand.

Failure ("a rupture forms") at a solve or a schedule level: the model does not come to
equilibrium, the thesis's "does not come to equilibrium ... and/or a continuous rupture
surface". With the variants' judge, "response" (``workflow.response``), a solve is "failing"
(a mechanism seen twice over windows of the response time) or "undecided" (neither at rest
nor a mechanism within its cap of windows): both end the excavation, and Hc is the height at
which the slope is no longer shown to stand (the run's ``hc_verdict`` says which; the 6 m
T = 0.25 MPa quick slope creeps on at 4-7 mm per N_r after its last lift with the ratio steady
at 1e-4: a slow mechanism, "failing" at 271,500 steps since 2026-12-01, "undecided" at the
20-window cap before). With ``judge="budget"``: the ratio
is not reached within ``max_steps`` and the largest block displacement is still growing at
the step limit (``monitor.verdict``; "moving but slowing" counts as standing). The strength
schedule also fails a level as soon as a block has moved more than
``FAILURE_DISPLACEMENT`` in it; the lift-by-lift solves do not, because one block lost from
the surface after a lift is not the slope failing (measured: the full 1.5 m model, T = 1 MPa,
"failed" that way at 30 m with no rupture surface). The rupture surface of a failed state is
then the largest connected group of intact-rock cracks reaching the lower half of the face
the slope had then
(``comparisons.centrifuge.rupture``, cracks linked within ``RUPTURE_LINK`` x max(edge length,
spacing)), counted as one when at least ``RUPTURE_MIN`` of the slope height long
(``has_rupture``); it is reported with each failure, not part of the test (a failure without one,
e.g. the whole jointed mass creeping by joint slip, is marked in the Hc table and figure:
``critical_height`` rows are spacing (m), T (MPa), Hc (m or None), rupture found).

Continuum: comparisons/common_toppling_continuum.py.
"""
from __future__ import annotations

from comparisons import centrifuge
from comparisons.results import CaseResult, Curve
from comparisons.scenes import common_toppling as scene
from comparisons.staged import judge_note, stage_run
from comparisons.sweep import run_sweep
from comparisons.variants import STAGED_OPTIONAL, pick_variant
from dem_core.workflow.stages import STOPS, ChangeMaterial, Excavate, Gravity, Solve
from dem_core.workflow.strength import StrengthSchedule

DESCRIPTION = ("Common (block-flexural) toppling after Nichol et al. 2002 (thesis 5.2.2): "
               "flaw T at rupture of the 6 m model, and critical height Hc against T and layer "
               "thickness; damage model vs conventional DEM vs continuum")

MPA = 1e6
TABLE_5_2 = dict(flaw_friction=30.0, flaw_cohesion=5e6, flaw_tensile_strength=1e6)
TABLE_5_3 = dict(flaw_friction=42.0, flaw_cohesion=14e6)           # T 1..5 MPa
T_START = 10e6                 # Pa: the strength schedule starts above the thesis's 7 MPa
FAILURE_DISPLACEMENT = 1.0     # m in one solve: beyond the ~0.15 m elastic crest movement
RUPTURE_LINK = 2.0
RUPTURE_MIN = 0.25             # a rupture surface spans at least this fraction of the height

REFERENCE = {
    "tensile_at_rupture_6m_MPa": [6.8, 7.0],   # 7 held (limiting equilibrium), 6.8 ruptured
    "table_5_2_ruptures_6m": True,
    "friction_50_stops_rupture": False,
    "cohesion_15_stops_rupture": False,
    "crest_moves_more_than_toe": True,
    "hc_rises_with_T": True,
    "thinner_layers_need_more_T": True,
    "source": "Alzo'ubi (2009) thesis 5.2.2, tables 5.2, 5.3, figs 5.7-5.10",
}

VARIANTS = {
    # quick: the 6 m model only, 3 m flaws in a 24 m zone (about 960 blocks), T lowered from
    # 10 MPa in coarse steps bisected to 0.125 MPa; Hc at two tensile strengths
    "quick": dict(spacings=[6.0], edge_length=3.0, zone_depth=24.0, relax_iterations=10,
                  t_values=[7e6, 4e6, 2e6, 1e6, 0.5e6, 0.25e6], refine_to=0.25e6,
                  studies=["friction 50", "cohesion 15"], conventional=True,
                  hc_tensile=[0.25e6, 1e6], max_steps=40_000, continuum=True,
                  continuum_h=8.0, workers=2, solver={}, settle=False,
                  judge="response"),
    # full: the thesis's three models, 1 m flaws in a 30 m zone, T in 0.5 MPa steps bisected
    # to 0.05 MPa, Hc at T = 1..5 MPa (and the quick's 0.25 MPa: the assumed slope needs less)
    "full": dict(spacings=[6.0, 3.0, 1.5], edge_length=1.0, zone_depth=30.0,
                 relax_iterations=20,
                 t_values=[7e6, 6e6, 5e6, 4e6, 3e6, 2e6, 1.5e6, 1e6, 0.75e6, 0.5e6, 0.25e6,
                           0.1e6],
                 refine_to=0.05e6, studies=["friction 50", "cohesion 15"], conventional=True,
                 hc_tensile=[0.25e6, 1e6, 2e6, 3e6, 4e6, 5e6], max_steps=100_000,
                 continuum=True, continuum_h=4.0, workers=2, solver={}, settle=False,
                 judge="response"),
}

STUDIES = {"friction 50": dict(flaw_friction=50.0), "cohesion 15": dict(flaw_cohesion=15e6)}


def _solve(max_steps: int, failure_displacement=FAILURE_DISPLACEMENT) -> Solve:
    return Solve(1e-5, max_steps, failure_displacement=failure_displacement)


def strength_stages(p: scene.ToppleParams, v: dict) -> list:
    """Gravity at high strength, the 12 lifts removed together, table 5.2 (``p``) with
    T = T_START, then T lowered through ``v["t_values"]`` (module docstring)."""
    lifts = [Excavate(scene.lift_name(k)) for k in range(1, scene.N_LIFTS + 1)]
    start = dict(p.intact_strength(), tensile_strength=T_START)
    return ([Gravity(1.0), Solve(1e-5, v["max_steps"])] + lifts
            + [Solve(1e-5, v["max_steps"]), ChangeMaterial("*", start), _solve(v["max_steps"]),
               StrengthSchedule("*", "tensile_strength", tuple(v["t_values"]),
                                refine_to=v["refine_to"], max_steps=v["max_steps"],
                                failure_displacement=FAILURE_DISPLACEMENT)])


def height_stages(p: scene.ToppleParams, v: dict) -> list:
    """Gravity at high strength, table 5.3 (``p``) assigned and solved, then each lift removed
    and solved in turn (module docstring)."""
    out = [Gravity(1.0), Solve(1e-5, v["max_steps"]), ChangeMaterial("*", p.intact_strength()),
           Solve(1e-5, v["max_steps"])]
    for k in range(1, scene.N_LIFTS + 1):
        # judged only by "still moving at the step limit": a single surface block lost after
        # a lift is not the slope failing (module docstring)
        out += [Excavate(scene.lift_name(k)), _solve(v["max_steps"], None)]
    return out


def critical_height(run: dict, slope: float = scene.SLOPE_HEIGHT) -> tuple:
    """(Hc m, verdict): the slope height after the first lift whose solve did not stand
    (``stages.STOPS``: "failed", "failing", "undecided" or "unstable"), and that verdict;
    (None, None) if every lift stood. ``slope``: the final slope's height (m), whose 12
    lifts the run removed (``ToppleParams.slope_height``)."""
    lifts = 0
    for s in run["stages"]:
        lifts += s["kind"] == "excavate"
        if s["kind"] == "solve" and s["verdict"] in STOPS:
            return (scene.height_after(lifts, slope) if lifts else 0.0), s["verdict"]
    return None, None


def run_member(member: dict) -> dict:
    """One member: the strength schedule or the excavation to failure (``member["study"]``)."""
    p = scene.ToppleParams(**member["params"])
    if member["study"] == "strength":
        run = stage_run(scene.scene(p, strength_stages(p, member["v"])), member)
    else:
        run = stage_run(scene.scene(p, height_stages(p, member["v"])), member,
                        stop_on_failure=True)
        run["hc"], run["hc_verdict"] = critical_height(run, p.slope_height)
    run["rupture"] = find_rupture(run, p)
    return run


def has_rupture(run: dict, height: float) -> bool:
    """True when the run's rupture surface is at least RUPTURE_MIN x ``height`` (m) long (a
    through-going surface, not a few cracks at the face)."""
    return run["rupture"] is not None and run["rupture"]["length_m"] >= RUPTURE_MIN * height


def find_rupture(run: dict, p: scene.ToppleParams) -> dict | None:
    """The rupture surface of a run's cracks (module docstring): it must reach the lower half
    of the face the slope had when it failed (the final face, or the face at Hc)."""
    face = scene.face_at(run.get("hc") or p.slope_height, p.slope_height)
    link = RUPTURE_LINK * max(p.edge_length, p.spacing)
    return centrifuge.rupture(run, link, centrifuge.lower_part_of_face(face, 0.5),
                              scene.JOINT_DIP, face, "left")


def members(v: dict, seed: int) -> list:
    """The sweep members of variant ``v``: the 6 m strength schedules (table 5.2, its
    friction and cohesion studies, conventional), then Hc per spacing and T (table 5.3)."""
    geo = dict(edge_length=v["edge_length"], zone_depth=v["zone_depth"],
               relax_iterations=v["relax_iterations"], seed=seed)
    vv = {k: v[k] for k in ("t_values", "refine_to", "max_steps")}
    base = dict(geo, spacing=6.0, **TABLE_5_2)
    out = [dict(label="6 m, table 5.2", study="strength", params=base, v=vv)]
    out += [dict(label=f"6 m, {name}", study="strength", params=dict(base, **STUDIES[name]),
                 v=vv) for name in v["studies"]]
    if v["conventional"]:
        out.append(dict(label="conventional", study="strength",
                        params=dict(base, conventional=True), v=vv))
    for s in v["spacings"]:
        for t in v["hc_tensile"]:
            out.append(dict(label=f"Hc {s:g} m, T={t / MPA:g}", study="height", v=vv,
                            params=dict(geo, spacing=s, flaw_tensile_strength=t, **TABLE_5_3)))
    for m in out:
        m["solver"], m["settle"], m["judge"] = dict(v["solver"]), v["settle"], v["judge"]
    return out


def run(variant="quick", seed: int = 1, progress=None) -> CaseResult:
    """Run the case: ``variant`` is "quick", "full" or a settings mapping (``VARIANTS`` keys)."""
    variant, v = pick_variant("common_toppling", VARIANTS, variant, optional=STAGED_OPTIONAL)
    progress = progress or (lambda message: None)
    result = CaseResult("common_toppling", variant, seed, reference=dict(REFERENCE))
    ms = members(v, seed)
    progress(f"{len(ms)} DEM runs")
    runs = {r["label"]: r for r in run_sweep(run_member, ms, workers=v["workers"],
                                             progress=progress)}
    _strength_results(result, runs, v)
    _height_results(result, runs, v)
    result.notes += _notes(v)
    if v["continuum"]:
        from comparisons.common_toppling_continuum import run_continuum

        progress("continuum: staged excavation and strength reduction")
        result.methods["continuum"] = run_continuum(v["continuum_h"], result)
    return result


def _file_name(label: str) -> str:
    """"6 m, friction 50" -> "6_m_friction_50"."""
    return label.replace(", ", "_").replace(" ", "_").replace("=", "")


def _t_at_rupture(run: dict):
    """(last stable T, first failed T) of a strength schedule, MPa (None: none failed)."""
    s = run["search"]
    return (None if s["last_stable"] is None else s["last_stable"] / MPA,
            None if s["failure"] is None else s["failure"] / MPA)


def _point_motion(run: dict, level) -> dict:
    """Total displacement (m) of each point at the schedule level ``level`` (Pa)."""
    s = run["search"]
    k = s["level"].index(level)
    return {p: float((s["point_ux"][p][k] ** 2 + s["point_uy"][p][k] ** 2) ** 0.5)
            for p in s["point_ux"]}


def _strength_results(result, runs, v):
    """The 6 m strength schedules: T at rupture, the studies, conventional, figures."""
    from comparisons.staged import history_figure

    base = runs["6 m, table 5.2"]
    stable, failed = _t_at_rupture(base)
    moved = _point_motion(base, base["search"]["failure"]) if failed is not None else {}
    result.methods["dem"] = {
        "tensile_at_rupture_MPa": failed, "last_stable_tensile_MPa": stable,
        "table_5_2_ruptures": failed is not None and failed >= 1.0,
        "studies": {name: dict(zip(("last_stable_MPa", "failure_MPa"),
                                   _t_at_rupture(runs[f"6 m, {name}"])))
                    for name in v["studies"]},
        "displacement_at_rupture_m": moved, "rupture": base["rupture"],
        "cracks": base["cracks"], "blocks": base["blocks"], "contacts": base["contacts"],
        "t_resolution_MPa": v["refine_to"] / MPA,
        "runtime_s": float(sum(r["runtime_s"] for k, r in runs.items()
                               if k != "conventional")),
    }
    result.add_error("dem T at rupture (6 m) vs thesis", failed, [6.8, 7.0])
    if "conventional" in runs:
        conv = runs["conventional"]
        result.methods["conventional"] = {
            "tensile_at_rupture_MPa": _t_at_rupture(conv)[1],
            "lowest_tensile_MPa": min(conv["search"]["level"]) / MPA,
            "blocks": conv["blocks"], "runtime_s": conv["runtime_s"]}
    for label in [k for k in runs if runs[k].get("search")]:
        r = runs[label]
        result.curves["schedule_" + _file_name(label)] = Curve(
            ["tensile_MPa", "ux_crest_m", "ux_toe_m"],
            [[lv / MPA, a, b] for lv, a, b in zip(r["search"]["level"],
                                                   r["search"]["point_ux"]["crest"],
                                                   r["search"]["point_ux"]["toe"])])
    result.figures["displacement_vs_tensile"] = history_figure(
        [runs[k] for k in runs if runs[k].get("search")], ("crest", "toe"), 1e6, "MPa",
        xlabel="flaw tensile strength (MPa), lowered; x: first failed level")
    line = None if base["rupture"] is None else base["rupture"]["polyline"]
    result.figures["cracks_at_rupture"] = centrifuge.cracks_figure(
        scene, base, line, f"damage model, 6 m layers, table 5.2: intact-rock cracks at the "
        f"first failed T = {failed} MPa (last stable {stable} MPa)")


def _height_results(result, runs, v):
    """Hc per spacing and T (table 5.3), its figure and the picture of a failed run."""
    import matplotlib.pyplot as plt

    rows = [[r["params"]["spacing"], r["params"]["flaw_tensile_strength"] / MPA, r["hc"],
             r["hc"] is not None and has_rupture(r, r["hc"])]
            for r in runs.values() if "hc" in r]
    result.methods["dem"]["critical_height"] = rows
    result.curves["critical_height"] = Curve(
        ["spacing_m", "tensile_MPa", "hc_m", "with_rupture"],
        [[s, t, float("nan") if h is None else h, float(k)] for s, t, h, k in rows])
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    marked = False                          # one legend entry for the failures without rupture
    for i, sp in enumerate(v["spacings"]):
        pts = sorted((t, h, k) for s, t, h, k in rows if s == sp)
        colour = f"C{i}"
        fail = [(t, h) for t, h, _ in pts if h is not None]
        stood = [t for t, h, _ in pts if h is None]
        local = [(t, h) for t, h, k in pts if h is not None and not k]
        if fail:
            ax.plot(*zip(*fail), "-o", color=colour, label=f"{sp:g} m layers: Hc")
        if local:
            ax.plot(*zip(*local), "x", ms=10, color="k",
                    label=None if marked else "failed without a rupture surface")
            marked = True
        if stood:
            ax.plot(stood, [scene.SLOPE_HEIGHT] * len(stood), "^", mfc="none", ms=9,
                    color=colour, label=f"{sp:g} m layers: all 12 lifts stood")
    ax.axhline(scene.SLOPE_HEIGHT, color="0.5", ls=":", lw=1)
    ax.set_ylim(0, scene.SLOPE_HEIGHT + 2 * scene.LIFT)
    ax.set_xlabel("flaw tensile strength T (MPa)")
    ax.set_ylabel("critical slope height Hc (m)")
    ax.set_title("table 5.3 (flaw friction 42, c 14 MPa): slope height after the lift whose "
                 "solve fails\n(dotted: the full 120 m height)", fontsize=8)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    result.figures["critical_height_vs_tensile"] = fig
    failed = [r for r in runs.values() if r.get("hc") is not None]
    if failed:
        r = failed[0]
        line = None if r["rupture"] is None else r["rupture"]["polyline"]
        result.figures["cracks_at_hc"] = centrifuge.cracks_figure(
            scene, r, line, f"damage model, {r['label']} MPa: cracks when the lift that "
            f"makes the slope {r['hc']:g} m high fails")


def _notes(v) -> list:
    return [
        "Fig 5.6 is not in the text: the 120 m slope at 60 degrees on a 30 m base, its 12 "
        "lifts of 10 m, the 80 m crest and 40 m toe bench and the zone of flaws along the "
        f"face ({v['zone_depth']:g} m deep) are assumptions "
        "(comparisons/scenes/common_toppling.py). The columns' bending stress scales as "
        "gamma H^2 / t, so T at rupture measures the assumed height as much as the rock.",
        "Behind the zone the columns are cut into coarse cells glued by unbreakable contacts, "
        "so they bend (UDEC's zoned blocks) but cannot break (the thesis had no flaws there); "
        "a rupture is therefore confined to the zone and tends to follow its inner edge.",
        judge_note(v["judge"], f"no equilibrium (ratio 1e-5) within {v['max_steps']} steps "
                   "with the largest displacement still growing ('moving', slowing, counts as "
                   "standing)", FAILURE_DISPLACEMENT),
        f"T resolution {v['refine_to'] / MPA:g} MPa; T schedule from {T_START / MPA:g} MPa.",
        "Continuum: table 5.2's intact rock without joints (an upper bound); the joints' "
        "strength everywhere (c 0, phi 30) would stand only to 30 degrees: F = 0.33 at 60.",
    ]
