"""Case ``coal_buckling``: buckling of a 3.5 m footwall layer on a 75 m, 30 degree open-pit coal
slope (thesis section 5.3.2, Table 5.4; Stead & Eberhardt 1997): gravity, then the layer's
tensile strength lowered everywhere until the slope fails.

Methods:

- ``dem``: the damage model (comparisons/scenes/coal_buckling.py: a Voronoi layer on a basal
  plane of friction 20, running on below the pit floor), the stages of
  ``comparisons.chapter5.schedule_stages``: gravity at the table's strengths (T 30 kPa), T
  lowered through the variant's values and, not in the thesis, the cohesion at
  T = 0. Reported: T at failure (last stable, first failed) and where the buckle forms;
- ``conventional``: the same blocks with unbreakable flaws (full variant);
- ``continuum``: ``continuum_ref`` strength reduction: the layer an equivalent Mohr-Coulomb
  mass, the footwall and floor rock elastic (``equivalent_rock_mass``).

Thrust line (``thrust``): after each stage the layer is cut across every 2.5 m along the face
and the force its down-dip part exerts on its up-dip part is read from the contacts
(``dem_core.output.sections.thrust_line``): the thrust N, the shear V and where the thrust
crosses the cut (e / t from mid-layer). A masonry layer stands while that line stays inside
its section; against it, the thrust a free slab on its basal plane hands to the toe
(``free_slab_thrust``).

Buckle (``buckle``): after the first failed level the model runs ``post_failure_steps`` more steps;
the layer blocks that moved in them by more than ``FRACTION`` of the motion of the fastest 1 % of
the blocks are the failing part (``chapter5.moving_blocks``); the buckle is where the layer moved
furthest out of the face then (along the face's outward normal): its height above the toe as a
fraction of the slope height (the thesis: the lower third), and the heights of the lowest and
highest moving blocks.
"""
from __future__ import annotations

import numpy as np

from comparisons import centrifuge, chapter5, staged
from comparisons.results import CaseResult, Curve
from comparisons.scenes import coal_buckling as scene
from comparisons.sweep import run_sweep
from comparisons.variants import STAGED_OPTIONAL, pick_variant

DESCRIPTION = ("Footwall buckling, 75 m open-pit coal slope at 30 degrees (Stead & Eberhardt "
               "1997, thesis 5.3.2): layer tensile strength lowered to failure; damage model "
               "vs conventional vs continuum")
KPA = 1e3
REFERENCE = {
    "thesis_dem_failure_T_kPa": 10.0,
    "thesis_buckle": "at the lower third of the face, from the toe (fig 5.11b)",
    "source": "Alzo'ubi (2009) thesis 5.3.2, table 5.4; Stead & Eberhardt (1997)",
}
FAILURE_DISPLACEMENT = 0.5      # m of a watched point in one level
CREEP = 2e-3                    # m over the last fifth of a level: still moving
FRACTION, MIN_MOTION = 0.2, 0.02   # the mechanism: moving > 0.2 x the fastest 1 % (> 2 cm)
WATCH = ("toe", "lower", "middle", "upper", "crest")

VARIANTS = {
    # quick: 0.7 m cells (five across the layer), T in 5 kPa steps to 10 kPa then 0, the
    # cohesion at T = 0 in halvings, 10000 steps a level and after a failure (about 10 s)
    "quick": dict(edge_length=0.7, values=[25, 20, 15, 10, 0], cohesion_values=[150, 75, 0],
                  max_steps=10_000, post_failure_steps=10_000, conventional=False,
                  continuum=True, continuum_h=3.0, workers=1, threads=1,
                  solver={"step_estimate": "auto"}, settle=False,
                  judge="response"),
    # full: 0.5 m cells (seven across), T in 5 kPa steps, the cohesion in 25-50 kPa steps, the
    # conventional model, 20000 steps a level and after a failure
    "full": dict(edge_length=0.5, values=[25, 20, 15, 10, 5, 0],
                 cohesion_values=[200, 150, 100, 50, 25, 0], max_steps=20_000,
                 post_failure_steps=20_000, conventional=True, continuum=True,
                 continuum_h=1.5, workers=2, threads=1, solver={}, settle=False,
                 judge="response"),
}


def members(v: dict, seed: int) -> list:
    base = dict(edge_length=v["edge_length"], seed=seed)
    out = [{"label": "damage model", "params": base, "v": v}]
    if v["conventional"]:
        out.append({"label": "conventional", "params": dict(base, conventional=True), "v": v})
    for m in out:
        m["solver"], m["settle"], m["judge"] = dict(v["solver"]), v["settle"], v["judge"]
    return out


def stages(p: scene.CoalBucklingParams, v: dict) -> list:
    return chapter5.variant_stages("flaw:layer", v, WATCH, FAILURE_DISPLACEMENT, CREEP)


def run_member(member: dict) -> dict:
    """One run of the stage list (a sweep member: plain dict in, plain dict out)."""
    p = scene.CoalBucklingParams(**member["params"])
    stations = thrust_stations(p)
    run, mechanism = chapter5.run_schedule(scene.scene(p, stages(p, member["v"])), member,
                                           lambda r: buckle(p, r),
                                           read=lambda m: thrust(p, m, stations))
    run["buckle"] = mechanism
    reads = run.pop("reads")
    after = [i for i, st in enumerate(run["stages"]) if st["kind"] == "solve"]
    run["thrust"] = {"stations_m": stations.tolist(),
                     "free_slab_N": free_slab_thrust(p, stations).tolist(),
                     "after_gravity": reads[after[0]] if after else None,
                     "end": reads[-1]}
    return run


def thrust_stations(p: scene.CoalBucklingParams) -> np.ndarray:
    """Stations s (m) along the face from the toe (- below the pit floor), every 2.5 m from
    about 5 m above the buried layer's end at the model's base to 2.5 m below the crest."""
    length = scene.HEIGHT / np.sin(np.radians(scene.FACE_DIP))
    below = p.floor_depth / np.sin(np.radians(scene.FACE_DIP))
    return np.arange(-2.5 * np.floor((below - 5.0) / 2.5), length - 2.0, 2.5)


def thrust(p: scene.CoalBucklingParams, model, stations) -> dict:
    """The layer's thrust line at ``stations`` (module docstring), lists of N, V (N/m),
    e / t and the contacts crossing each cut."""
    from dem_core.output.sections import thrust_line

    (tx, ty), (cx, cy) = scene.face(p)
    layer = np.asarray(model.blocks.region_id) == model.blocks.region_names.index("layer")
    return thrust_line(model, layer, (tx, ty), (cx - tx, cy - ty), scene.outward_normal(),
                       p.layer_thickness, stations)


def free_slab_thrust(p: scene.CoalBucklingParams, stations, g=9.81) -> np.ndarray:
    """N/m: the thrust a free slab up-dip of station s hands on when its basal plane is at
    its friction limit, gamma t (L - s)(sin beta - cos beta tan phi_b), L the face's length,
    beta the face's dip, phi_b the basal friction (limit equilibrium of a slab on a plane)."""
    beta, phi = np.radians(scene.FACE_DIP), np.radians(p.basal_friction)
    length = scene.HEIGHT / np.sin(beta)
    return p.density * g * p.layer_thickness * np.clip(length - np.asarray(stations), 0.0,
                                                       None) \
        * (np.sin(beta) - np.cos(beta) * np.tan(phi))


def buckle(p: scene.CoalBucklingParams, run: dict) -> dict | None:
    """Where the layer failed (module docstring), or None if nothing moved."""
    moving = chapter5.moving_blocks(run, FRACTION, MIN_MOTION)
    if moving is None:
        return None
    x, y = moving["xy0"][:, 0], moving["xy0"][:, 1]
    layer = (scene.depth_below_face(p, x, y) > 0) & (y > p.floor_depth - 5.0)
    if not layer.any():
        return None
    out = moving["du"][layer] @ scene.outward_normal()
    height = (y[layer] - p.floor_depth) / scene.HEIGHT
    top = int(np.argmax(out))
    return {"blocks": int(layer.sum()), "height_fraction": float(height[top]),
            "outward_m": float(out[top]), "lowest_height_fraction": float(height.min()),
            "highest_height_fraction": float(height.max())}


def equivalent_rock_mass(p: scene.CoalBucklingParams, tensile: float) -> dict:
    """The layer as a Mohr-Coulomb mass of the flaws' cohesion and friction and the tensile
    strength ``tensile`` (Pa): the intact layer, as the thesis's table gives it. The continuum
    has no interface: the basal plane (friction 20) is welded, so the continuum is an upper
    bound of the layered slope (its layer cannot slide on its base)."""
    return {"cohesion": p.flaw_cohesion, "friction": p.flaw_friction,
            "tensile_strength": tensile}


def continuum_scene(v: dict, tensile: float):
    """The case's scene as its continuum runs it (``chapter5.continuum_scene``): the layer of
    ``equivalent_rock_mass`` (dilation 0), the footwall and floor elastic, E and nu of the
    blocks."""
    from continuum_ref.materials import Elastic, MohrCoulomb

    p = scene.CoalBucklingParams()
    layer = MohrCoulomb(E=p.block_E, nu=p.block_nu, dilation=0.0,
                        **equivalent_rock_mass(p, tensile))
    rock = Elastic(E=p.block_E, nu=p.block_nu)
    return chapter5.continuum_scene(scene.scene(p), scene.regions(p),
                                    {"footwall": rock, "floor": rock, "layer": layer},
                                    v["continuum_h"])


def run_continuum(v: dict, tensile: float) -> dict:
    p = scene.CoalBucklingParams()
    mass = equivalent_rock_mass(p, tensile)
    out = chapter5.continuum_fos(continuum_scene(v, tensile))
    out["material"] = (f"layer Mohr-Coulomb c {mass['cohesion'] / 1e6:.2f} MPa, friction "
                       f"{mass['friction']:.0f}, T {tensile / KPA:.0f} kPa, dilation 0; "
                       f"footwall and floor elastic E {p.block_E / 1e9:.0f} GPa; basal plane "
                       f"welded; h {v['continuum_h']} m")
    return out


def run(variant="quick", seed: int = 1, progress=None) -> CaseResult:
    """Run the case: ``variant`` is "quick", "full" or a settings mapping (``VARIANTS`` keys)."""
    variant, v = pick_variant("coal_buckling", VARIANTS, variant, optional=STAGED_OPTIONAL)
    progress = progress or (lambda message: None)
    result = CaseResult("coal_buckling", variant, seed, reference=dict(REFERENCE))
    runs = run_sweep(run_member, members(v, seed), workers=v["workers"], progress=progress)
    for r in runs:
        result.methods["conventional" if r["label"] == "conventional" else "dem"] = _entry(r)
    t_fail = result.methods["dem"]["T_failure_kPa"]
    result.add_error("dem T at failure (kPa) vs thesis", t_fail, 10.0)
    b = runs[0]["buckle"]
    result.add_error("dem buckle height (fraction of H) vs thesis lower third",
                     None if b is None else b["height_fraction"], [0.0, 1.0 / 3.0])
    toe_n, slab_n, e_max = thrust_at_toe(runs[0]["thrust"])
    result.add_error("dem thrust at the toe, end of the run (MN/m) vs free slab on its base",
                     toe_n / 1e6, slab_n / 1e6)
    result.add_error("dem thrust line on the exposed layer, largest |e| / t vs the kern",
                     e_max, [0.0, 1.0 / 6.0])
    if "conventional" in result.methods:
        result.add_error("conventional T at failure (kPa) vs thesis DM",
                         result.methods["conventional"]["T_failure_kPa"], 10.0, "conventional")
    if v["continuum"]:
        progress("continuum: strength reduction at T = 0")
        result.methods["continuum"] = run_continuum(v, 0.0)
    _curves_and_figures(result, runs)
    result.notes += [
        "Gravity switched on with the table's strengths, local damping 0.8 "
        "(comparisons/chapter5.py).",
        "After T the cohesion is lowered at T = 0 (not in the thesis): which strength the "
        "buckle needs.",
        staged.judge_note(v["judge"], f"still moving (> {CREEP} m over the last fifth, not "
                          f"slowing) after {v['max_steps']} steps", FAILURE_DISPLACEMENT,
                          f"a watched point ({', '.join(WATCH)})"),
        "Thrust line: the layer cut across every 2.5 m (dem_core.output.sections); the free "
        "slab's thrust is what its basal plane at its friction limit hands to the toe "
        "(limit equilibrium). A layer whose thrust stays inside its kern needs no tensile "
        "strength or cohesion to stand (docs/cases/coal_buckling.md).",
        "The layer runs on below the pit floor (buttressed by the floor rock); dimensions "
        "beyond height, angle and thickness, density and block modulus are assumptions "
        "(comparisons/scenes/coal_buckling.py).",
    ]
    return result


def _entry(r) -> dict:
    t = next(s for s in r["searches"] if s["parameter"] == "tensile_strength")
    c = next((s for s in r["searches"] if s["parameter"] == "cohesion"), None)

    def kpa(x):
        return None if x is None else x / KPA
    return {"T_levels_kPa": [kpa(x) for x in t["level"]], "T_verdicts": list(t["verdict"]),
            "T_last_stable_kPa": kpa(t["last_stable"]), "T_failure_kPa": kpa(t["failure"]),
            "c_last_stable_kPa": None if c is None else kpa(c["last_stable"]),
            "c_failure_kPa": None if c is None else kpa(c["failure"]),
            "buckle": r["buckle"], "blocks": r["blocks"], "cracks": r["cracks"],
            "thrust": r["thrust"],
            "stages": [(s["kind"], s["verdict"], s["steps"]) for s in r["stages"]],
            "runtime_s": r["runtime_s"]}


def thrust_at_toe(th: dict) -> tuple:
    """(N at the toe at the end of the run, the free slab's there, N/m; the largest |e| / t
    of the thrust line on the exposed layer, s >= 0) of a run's ``thrust``."""
    s = np.asarray(th["stations_m"])
    end = th["end"]
    e = np.abs(np.asarray(end["e_over_t"], float))[s >= 0]
    return (float(np.interp(0.0, s, end["N"])), float(np.interp(0.0, s, th["free_slab_N"])),
            float(np.nanmax(e)))


def thrust_figure(run: dict, p: scene.CoalBucklingParams):
    """Thrust N along the layer (DEM after gravity and at the end, and the free slab's) and
    the thrust line e / t against the section and its kern."""
    import matplotlib.pyplot as plt

    th = run["thrust"]
    s = np.asarray(th["stations_m"])
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    ax1.plot(s, np.asarray(th["free_slab_N"]) / 1e6, "k--",
             label=f"free slab on its basal plane at friction {p.basal_friction:g} deg "
                   f"(limit equilibrium)")
    states = (("after_gravity", "gravity, table 5.4's strengths", "C0-"),
              ("end", "end: T = 0, then c = 0", "C3-"))
    for key, label, style in states:
        if th.get(key):
            ax1.plot(s, np.asarray(th[key]["N"]) / 1e6, style, label=f"DEM, {label}")
            ax2.plot(s, th[key]["e_over_t"], style, label=f"DEM, {label}")
    ax1.set_ylabel("thrust N along the layer (MN/m)")
    ax1.legend(fontsize=8)
    for y, text in ((0.5, "face"), (-0.5, "basal plane")):
        ax2.axhline(y, color="k", lw=1)
        ax2.text(s[-1], y, text, ha="right", va="bottom" if y > 0 else "top", fontsize=8)
    for y in (1 / 6, -1 / 6):
        ax2.axhline(y, color="0.6", lw=0.8, ls=":")
    ax2.text(s[0], 1 / 6, "kern (t/6)", fontsize=8, va="bottom", color="0.4")
    ax2.set_ylim(-0.7, 0.7)
    ax2.set_ylabel("thrust line e / t (from mid-layer)")
    ax2.set_xlabel("distance s along the face from the toe (m; < 0: below the pit floor)")
    for ax in (ax1, ax2):
        ax.axvline(0.0, color="0.5", lw=0.8)
        ax.grid(alpha=0.3)
    ax2.text(0.5, -0.62, "toe (pit floor)", fontsize=8, color="0.4")
    ax2.legend(fontsize=8, loc="lower left")
    fig.suptitle(f"coal footwall layer, {p.layer_thickness:g} m thick, {p.edge_length:g} m "
                 f"cells: where the thrust runs")
    fig.tight_layout()
    return fig


def _curves_and_figures(result, runs):
    for r in runs:
        name = r["label"].replace(" ", "_")
        for s in r["searches"]:
            rows = np.column_stack([s["level"]] + [s["point_ux"][k] for k in WATCH])
            result.curves[f"{s['parameter']}_search_{name}"] = Curve(
                [s["parameter"] + "_Pa"] + [f"ux_{k}_m" for k in WATCH], rows)
    for i, (key, label) in enumerate((("history", "flaw tensile strength (kPa)"),
                                      ("history_cohesion", "flaw cohesion at T = 0 (kPa)"))):
        chosen = [dict(r, search=r["searches"][i]) for r in runs
                  if len(r["searches"]) > i and len(r["searches"][i]["level"]) > 1]
        if chosen:
            result.figures[key] = staged.history_figure(
                chosen, ("toe", "lower", "middle"), scale=KPA, unit="kPa",
                xlabel=f"{label}; x: first failed level")
    base = runs[0]
    b = base["buckle"]
    title = ("coal footwall, damage model: final state" + (
        "" if b is None else f"; largest outward movement at {b['height_fraction']:.2f} H "
        f"above the toe"))
    result.figures["blocks_at_failure"] = centrifuge.cracks_figure(scene, base, None, title)
    result.figures["thrust_line"] = thrust_figure(base, scene.CoalBucklingParams(
        **base["params"]))
