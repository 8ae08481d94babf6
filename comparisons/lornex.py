"""Case ``lornex``: the Highland Valley Copper Lornex pit south-east wall, 15 mining blocks
against the survey prisms' displacement record (thesis chapter 6, sections 6.4-6.8, Tables 6.1-6.5).

Methods (each one sweep member running the scene's whole stage list,
``comparisons.staged.stage_run``; the scene and every assumption: comparisons/scenes/lornex.py):

- ``dem``: the damage model, flaws (intact rock) breakable, at T = 0.1 MPa (the site estimate)
  and T = 1.0 MPa (thesis 6.8.4);
- ``conventional``: the same model with the flaws unbreakable (the thesis's conventional UDEC:
  slip on the faults and secondary joints only);
- ``continuum``: Hoek-Brown rock mass per RMR zone (Table 6.1/6.2), no joints, the same
  stages (comparisons/lornex_continuum.py).

Mining-induced displacement (thesis 6.5: the field's is the total minus the background
movement): a prism's displacement vector after the solve that follows a group of mining blocks
minus its displacement at the pre-mining equilibrium (after the in-situ stress, the real
strengths and the water table were solved), its magnitude |du| in m; so the cumulative
displacement after block n is the sum of the increments of blocks 1..n. A merged stage (the
quick variant) is compared with Table 6.4's row of its last block.

Each solve stops at equilibrium (unbalanced ratio 1e-5), after ``max_steps`` steps (verdict
"failed": still moving) or when a block has moved ``failure_displacement`` (20 m) in it. A
stage still moving at ``max_steps`` gives a displacement that grows with ``max_steps`` (the
slope creeps): each stage's verdict is reported with the displacements.
"""
from __future__ import annotations

import numpy as np

from comparisons.results import CaseResult, Curve
from comparisons.scenes import lornex as scene
from comparisons.staged import INTACT, stage_run
from comparisons.sweep import run_sweep
from comparisons.variants import STAGED_OPTIONAL, pick_variant

DESCRIPTION = ("Lornex pit south-east wall, Highland Valley Copper (thesis ch. 6): block "
               "toppling under 15 mining blocks against prism records (Table 6.4); damage model "
               "T 0.1 / 1.0 MPa vs conventional DEM vs Hoek-Brown continuum")

PRISMS = tuple(scene.PRISMS)           # bottom to top
# Table 6.4: cumulative mining-induced displacement (m) after blocks 1..15 (the 1 m of the
# block-5 runoff event already subtracted by the thesis)
TABLE_6_4 = {
    "SMP 560": [0, 0, 0, 0, 2.5, 2.95, 3.55, 4.15, 6.05, 6.55, 8.95, 9.40, 12.90, 14.1, 16.3],
    "SMP 468": [0.1, 0.20, 0.90, 1.10, 1.70, 2.10, 2.50, 2.85, 3.75, 4.10, 6.10, 6.50, 9.20,
                10.40, 12.40],
    "SMP 413": [0.0, 0.0, 0.4, 0.50, 0.80, 1.10, 1.50, 2.00, 2.90, 3.35, 5.55, 5.95, 9.15, 10.35,
                13.05],
    "SMP 454": [0.1, 0.50, 1.50, 1.80, 3.20, 3.60, 4.10, 4.45, 5.45, 5.75, 7.65, 8.00, 10.50,
                11.70, 13.30],
}
REFERENCE = {
    "table_6_4_m": TABLE_6_4,
    "movement_mode": "sliding with normal scarps at the crest, toppling with obsequent scarps "
                     "mid-slope, bulging and crushed material at the toe, no continuous rupture",
    "tensile_effect": "T 1.0 MPa: less fracturing, less displacement than T 0.1 MPa",
    "source": "Alzo'ubi (2009) thesis ch. 6; Tosney et al. (2000, 2004); Tosney (2001)",
}
MERGED = ((1, 2, 3), (4, 5, 6), (7, 8, 9), (10, 11, 12), (13, 14, 15))
VARIANTS = {
    # quick: 8 m flaws, 5 stages of 3 blocks, on the eigen step (each DEM run 23-46 s on one
    # core on the response judge; max_steps, 20 000 per solve, is the budget judge's; the
    # continuum at h = 15 m 5 s: about 65 s on 2 cores)
    "quick": dict(edge_length=8.0, relax_iterations=5, stage_blocks=MERGED, max_steps=20_000,
                  tensile=[0.1e6, 1.0e6], conventional=True, continuum=True, continuum_h=15.0,
                  workers=2, solver={"step_estimate": "auto"}, settle=False,
                  judge="response"),
    # full: the thesis's 1.4 m flaws and the 15 blocks one by one
    "full": dict(edge_length=1.4, relax_iterations=20, stage_blocks=scene.ALL_BLOCKS,
                 max_steps=100_000, tensile=[0.1e6, 1.0e6], conventional=True, continuum=True,
                 continuum_h=5.0, workers=2, solver={}, settle=False,
                 judge="response"),
}
MPA = 1e6


def members(v: dict, seed: int) -> list:
    """The sweep members: one per tensile strength, then the conventional run."""
    base = dict(edge_length=v["edge_length"], relax_iterations=v["relax_iterations"],
                seed=seed, stage_blocks=[list(g) for g in v["stage_blocks"]],
                max_steps=v["max_steps"])
    out = [dict(label=f"T={t / MPA:g} MPa", params=dict(base, tensile=t)) for t in v["tensile"]]
    if v["conventional"]:
        out.append(dict(label="conventional", params=dict(base, tensile=v["tensile"][0],
                                                          conventional=True)))
    for m in out:
        m["solver"], m["settle"], m["judge"] = dict(v["solver"]), v["settle"], v["judge"]
        m["point_history"] = True
    return out


def params_of(member: dict) -> scene.LornexParams:
    d = dict(member["params"])
    d["stage_blocks"] = tuple(tuple(int(b) for b in g) for g in d["stage_blocks"])
    return scene.LornexParams(**d)


def run_member(member: dict) -> dict:
    """One DEM run of the whole stage list (a sweep member: plain dict in, plain dict out),
    with each prism's cumulative mining-induced displacement (module docstring)."""
    p = params_of(member)
    run = stage_run(scene.scene(p), member, crack_materials=INTACT)
    first, after = scene.mining_stage_indices(p)
    base = run["stages"][first]["points"]
    run["mining"] = {
        "last_block": [max(g) for g in p.stage_blocks],
        "verdict": [run["stages"][i]["verdict"] for i in after],
        "steps": [run["stages"][i]["steps"] for i in after],
        "cracks": [sum(run["stages"][i]["cracks"].values()) for i in after],
        "cumulative": {k: [float(np.hypot(run["stages"][i]["points"][k][0] - base[k][0],
                                          run["stages"][i]["points"][k][1] - base[k][1]))
                           for i in after] for k in PRISMS}}
    run["mining"]["motion"] = _stage_motion(run.pop("point_history"), run["stages"], after,
                                            base)
    run["premining_cracks"] = int(sum(run["stages"][first]["cracks"].values()))
    run["mode"] = movement_mode(run["picture"], p)
    return run


def _stage_motion(hist: dict, stages: list, after: list, base: dict) -> list:
    """Per mining solve: its start and end model time (s) and, at each recorded time within
    it, the mean over the prisms of their mining-induced displacement (m)."""
    t = np.asarray(hist["time"])
    mean = np.mean([np.hypot(np.asarray(hist[f"{k}.ux"]) - base[k][0],
                             np.asarray(hist[f"{k}.uy"]) - base[k][1]) for k in PRISMS], axis=0)
    out = []
    for i in after:
        t0, t1 = stages[i - 1]["time"], stages[i]["time"]
        sel = (t >= t0) & (t <= t1)
        out.append({"start_s": t0, "end_s": t1, "t_s": t[sel].tolist(),
                    "mean_m": mean[sel].tolist()})
    return out


def equal_time(runs: list) -> dict | None:
    """The DEM runs compared at the same model time within the first mining solve that none of
    them ends at rest: each run's mean prism displacement (m, mining-induced) at the solve's
    start plus the shortest of their solve times. A failing solve ends where its judge proved
    the mechanism, which differs from run to run, so the displacements at the solves' ends
    compare the judges' stopping times; at the same time they compare the mechanisms' speeds.
    None when every solve of some run comes to rest."""
    if not runs or any("motion" not in r["mining"] for r in runs):
        return None                   # runs kept from before the histories were recorded
    verdicts = [r["mining"]["verdict"] for r in runs]
    for k in range(min(len(v) for v in verdicts)):
        if all(v[k] != "equilibrium" for v in verdicts):
            motions = [r["mining"]["motion"][k] for r in runs]
            span = min(m["end_s"] - m["start_s"] for m in motions)
            return {"stage": k + 1, "time_s": span,
                    "mean_m": {r["label"]: float(np.interp(m["start_s"] + span, m["t_s"],
                                                           m["mean_m"]))
                               for r, m in zip(runs, motions)}}
    return None


BANDS = {"toe": (scene.Y_TOE, scene.Y_PREMINING), "mid-slope": (scene.Y_PREMINING,
         scene.Y_WEAK_CREST), "crest": (scene.Y_WEAK_CREST, scene.Y_CREST)}


def movement_mode(pic: dict, p: scene.LornexParams) -> dict:
    """The movement mode read from the final blocks of the toppling zone, per elevation band
    (``BANDS``, by the blocks' start positions; displacement since the start of the model):
    the blocks' mean rotation (degrees; negative = clockwise = toppling forward, out of the
    face, which faces +x), mean displacement ux, uy (m) and the dip of the mean displacement
    (degrees below horizontal; negative = upward). The field's mode reads: crest dipping
    steeply down (sliding on the 55 degree secondary joints, normal scarps), mid-slope
    forward rotation (toppling, obsequent scarps), toe heave (uy > 0, bulging)."""
    from shapely import contains_xy

    p0 = np.asarray(pic["pos0"])
    u = np.asarray(pic["pos"]) - p0
    rot = np.degrees(np.asarray(pic["theta"]) - np.asarray(pic["theta0"]))
    inside = (np.asarray(pic["active"]) > 0) & contains_xy(scene.toppling_zone(p), p0[:, 0],
                                                           p0[:, 1])
    out = {}
    for name, (lo, hi) in BANDS.items():
        sel = inside & (p0[:, 1] >= lo) & (p0[:, 1] < hi) & np.isfinite(u).all(axis=1)
        if not sel.any():
            continue
        ux, uy = float(u[sel, 0].mean()), float(u[sel, 1].mean())
        out[name] = {"blocks": int(sel.sum()), "rotation_deg": float(rot[sel].mean()),
                     "ux_m": ux, "uy_m": uy,
                     "dip_deg": float(np.degrees(np.arctan2(-uy, ux)))}
    return out


def field_rows(last_blocks) -> dict:
    """Table 6.4's rows at the given blocks, {prism: [m]}."""
    return {k: [TABLE_6_4[k][b - 1] for b in last_blocks] for k in PRISMS}


def rms(model: dict, last_blocks) -> dict:
    """RMS error (m) of each prism's cumulative displacement over the stages, and over all
    prisms, absolute and as a fraction of the prism's final field displacement (the overall
    one of the mean final displacement). Stages the model did not reach are left out."""
    field = field_rows(last_blocks)
    out, every = {}, []
    for k in PRISMS:
        n = min(len(model[k]), len(field[k]))
        d = np.asarray(model[k][:n]) - np.asarray(field[k][:n])
        every.append(d)
        out[k] = {"rms_m": float(np.sqrt(np.mean(d ** 2))),
                  "rms_fraction": float(np.sqrt(np.mean(d ** 2)) / TABLE_6_4[k][-1])}
    d = np.concatenate(every)
    final = np.mean([TABLE_6_4[k][-1] for k in PRISMS])
    out["all"] = {"rms_m": float(np.sqrt(np.mean(d ** 2))),
                  "rms_fraction": float(np.sqrt(np.mean(d ** 2)) / final)}
    return out


def _method(run: dict) -> dict:
    m = run["mining"]
    return {"label": run["label"], "cumulative_m": m["cumulative"], "verdict": m["verdict"],
            "steps": m["steps"], "cracks_per_stage": m["cracks"], "cracks": run["cracks"],
            "premining_cracks": run["premining_cracks"], "last_block": m["last_block"],
            "rms": rms(m["cumulative"], m["last_block"]), "blocks": run["blocks"],
            "contacts": run["contacts"], "mode": run["mode"], "runtime_s": run["runtime_s"]}


def run(variant="quick", seed: int = 1, progress=None) -> CaseResult:
    """Run the case: ``variant`` is "quick", "full" or a settings mapping (``VARIANTS`` keys)."""
    variant, v = pick_variant("lornex", VARIANTS, variant, optional=STAGED_OPTIONAL)
    progress = progress or (lambda message: None)
    result = CaseResult("lornex", variant, seed, reference=dict(REFERENCE))
    ms = members(v, seed)
    progress(f"{len(ms)} DEM runs, {len(v['stage_blocks'])} mining stages each")
    runs = {r["label"]: r for r in run_sweep(run_member, ms, workers=v["workers"],
                                             progress=progress)}
    dem = [runs[m["label"]] for m in ms if m["label"] != "conventional"]
    result.methods["dem"] = {"runs": [_method(r) for r in dem], "equal_time": equal_time(dem),
                             "runtime_s": float(sum(r["runtime_s"] for r in dem))}
    _errors(result, dem[0]["mining"], "dem")
    if "conventional" in runs:
        result.methods["conventional"] = _method(runs["conventional"])
        _errors(result, runs["conventional"]["mining"], "conventional")
    if v["continuum"]:
        from comparisons.lornex_continuum import run_continuum

        progress(f"continuum: Hoek-Brown zones, h = {v['continuum_h']} m")
        p = params_of(ms[0])
        c = run_continuum(p, v["continuum_h"])
        lasts = [max(g) for g in p.stage_blocks][:len(c["stages"])]
        c["last_block"], c["rms"] = lasts, rms(c["cumulative"], lasts)
        result.methods["continuum"] = c
        _errors(result, {"cumulative": c["cumulative"], "last_block": lasts}, "continuum")
    _curves_and_figures(result, list(runs.values()), dem)
    result.notes += _notes(v, runs, result.methods["dem"]["equal_time"])
    return result


def _errors(result, mining: dict, method: str) -> None:
    """Each prism's displacement after the last stage against Table 6.4's row of its block."""
    for k in PRISMS:
        vals = mining["cumulative"][k]
        if vals:
            result.add_error(f"{method} {k} cumulative displacement after block "
                             f"{mining['last_block'][len(vals) - 1]} (m)", vals[-1],
                             TABLE_6_4[k][mining["last_block"][len(vals) - 1] - 1], method)


def _notes(v, runs, same=None) -> list:
    out = ["The section, the mining blocks, the RMR zones, the toppling zone, the prisms' "
           "places and the water table are reconstructed from the thesis's words (its figures "
           "6.5-6.13 were not available): comparisons/scenes/lornex.py states each assumption.",
           "Mining-induced displacement: |u(after the stage) - u(pre-mining equilibrium)| of "
           "each prism (m); Table 6.4 is the field's total minus the background movement.",
           (f"Each solve stops at equilibrium or after {v['max_steps']} steps (verdict "
            "'failed': still moving; its displacement then grows with the step cap)."
            if v.get("judge") == "budget" else
            "Each solve ends at rest ('equilibrium') or where the response judge proved a "
            "mechanism ('failing'): a failing solve's displacement is where the judge stopped, "
            "a lower bound of what the failing slope moves, so runs are compared at the same "
            "model time (below).")]
    for label, r in runs.items():
        out.append(f"{label}: stage verdicts {r['mining']['verdict']}")
    if same:
        out.append(f"At the same model time, {same['time_s']:.1f} s into mining stage "
                   f"{same['stage']} (the first that no DEM run ends at rest), the mean "
                   "mining-induced displacement of the four prisms: " + ", ".join(
                       f"{k} {val:.2f} m" for k, val in same["mean_m"].items()) + ".")
    return out


def _name(label: str) -> str:
    return label.replace("=", "").replace(" ", "_")


def _curves_and_figures(result, runs, dem):
    for r in runs:
        m = r["mining"]
        result.curves["prisms_" + _name(r["label"])] = Curve(
            ["last_block"] + [k.replace(" ", "_") + "_m" for k in PRISMS],
            np.column_stack([m["last_block"]] + [m["cumulative"][k] for k in PRISMS]))
        xy = np.asarray(r["crack_xy"], float).reshape(-1, 2)
        result.curves["cracks_" + _name(r["label"])] = Curve(
            ["x_m", "y_m", "mode_1tension_2shear"], np.column_stack([xy, r["crack_mode"]]))
    result.curves["field_table_6_4"] = Curve(
        ["block"] + [k.replace(" ", "_") + "_m" for k in PRISMS],
        np.column_stack([np.arange(1, 16)] + [TABLE_6_4[k] for k in PRISMS]))
    result.figures["prisms_vs_block"] = prism_figure(runs, result.methods.get("continuum"))
    for r in runs:
        result.figures["blocks_" + _name(r["label"])] = block_figure(r)


def prism_figure(runs, continuum=None):
    """Cumulative mining-induced displacement (m) of each prism against the mining block:
    Table 6.4 (black) and each method, one panel per prism."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    colours = plt.get_cmap("tab10")
    for ax, k in zip(axes.ravel(), PRISMS):
        ax.plot(range(1, 16), TABLE_6_4[k], "k-o", ms=3, label="field (Table 6.4)")
        for i, r in enumerate(runs):
            m = r["mining"]
            n = len(m["cumulative"][k])
            ax.plot(m["last_block"][:n], m["cumulative"][k], "-s", ms=4, color=colours(i),
                    label=r["label"])
        if continuum is not None:
            ax.plot(continuum["last_block"], continuum["cumulative"][k], "--^", ms=4,
                    color="tab:gray", label="continuum (Hoek-Brown)")
        ax.set_title(k, fontsize=9)
        ax.set_ylabel("cumulative displacement (m)")
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("mining block")
    axes[0, 0].legend(fontsize=7, loc="upper left")
    fig.suptitle("Lornex SE wall: mining-induced displacement of the prisms, model vs field",
                 fontsize=10)
    fig.tight_layout()
    return fig


COLOUR_LIMIT = 5.0     # m: the colour scale of the block plots stops here (toe blocks fly)
ZOOM = ((0.0, 180.0), (1520.0, 1630.0))     # m: the crest and the upper slope


def block_figure(run: dict):
    """The wall after the last mining stage at true scale: blocks coloured by displacement
    (m, capped at ``COLOUR_LIMIT``), cracks through intact rock (red tension, blue shear),
    joints black, the prisms; arrows: the displacement of the flaw zone's blocks (x 5); right:
    the crest and upper slope (``ZOOM``), where the scarps form."""
    import matplotlib.pyplot as plt

    from dem_core.output.plot import draw_picture

    pic = run["picture"]
    fig, axes = plt.subplots(1, 2, figsize=(15, 5.8), gridspec_kw={"width_ratios": [1.6, 1]})
    for ax in axes:
        draw_picture(pic, ax, 1.0, unit="m", colour_limit=COLOUR_LIMIT)
        for name, (x, y) in scene.monitoring_points().items():
            ax.plot(x, y, "w^", mec="k")
            ax.annotate(name, (x, y), xytext=(6, 6), textcoords="offset points", fontsize=8)
    p0, p = np.asarray(pic["pos0"]), np.asarray(pic["pos"])
    u = p - p0
    zone = scene.toppling_zone(params_of(run)).buffer(5.0)
    from shapely import contains_xy
    sel = (np.asarray(pic["active"]) > 0) & contains_xy(zone, p0[:, 0], p0[:, 1]) \
        & (np.hypot(*u.T) < 4 * COLOUR_LIMIT)
    axes[0].quiver(p0[sel, 0], p0[sel, 1], u[sel, 0], u[sel, 1], angles="xy",
                   scale_units="xy", scale=0.2, width=0.0015, color="orange")
    axes[1].set_xlim(*ZOOM[0])
    axes[1].set_ylim(*ZOOM[1])
    axes[0].legend(fontsize=7, loc="lower left")
    axes[0].set_title(f"{run['label']}: after the last mining stage (true scale; arrows: flaw "
                      f"zone displacement x 5), {run['cracks']} cracks", fontsize=9)
    axes[1].set_title("crest and upper slope (true scale)", fontsize=9)
    fig.tight_layout()
    return fig
