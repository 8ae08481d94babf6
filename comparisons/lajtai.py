"""Case ``lajtai``: virtual lab calibration and Lajtai's direct shear tests (thesis ch. 3,
sections 3.5-3.8, Table 3.1).

Studies (DEM damage model, ``dem`` method):

1. **Virtual lab** on a 2:1 Voronoi specimen (``comparisons.scenes.lajtai``): unconfined
   compression (stress-strain, peak = UCS, E and Poisson's ratio from the pre-peak part), a
   direct tension test, a loading-rate check (peak at the rate and at half of it), and the
   calibration of the flaw cohesion for the target UCS 4.1 MPa (thesis 3.5: c = 1.2 MPa), with
   UCS against flaw cohesion (thesis fig. 3.9).
2. **Lajtai's specimens**: rock bridges between open joints (slots) and closed joints, k = 0.5,
   flaws T 1.1 MPa, friction 37, the calibrated cohesion (thesis figs 3.10-3.12).
3. **Persistence** k (joints at both ends, friction 30 for flaws and joints, flaw T 1.0 MPa,
   joints T = c = 0; thesis 3.6, fig. 3.14) and its normalised form (fig. 3.15).
4. **Tensile strength** T = 0.5 vs 1.0 MPa at k = 0, friction 30 (thesis 3.7, fig. 3.16).
5. **Scale**: block edge 5, 7, 9, 11 mm at k = 0, stiffness scaled by eq. 3.7 (thesis 3.8,
   fig. 3.17); full variant only.
6. **Error against run time**: UCS and the k = 0, sn = 1.2 MPa point at several block sizes and
   time-step safety factors (full variant only).

The ``continuum`` method is the same UCS and direct-shear geometry in ``continuum_ref`` with
Mohr-Coulomb + tension cut-off (see ``comparisons.lajtai_continuum``).

Reference envelope (``lajtai_envelope``): Lajtai's composite envelope built from the thesis
parameters (thesis 2.3, 3.4 eq. 3.6, 3.5). See its docstring.
"""
from __future__ import annotations

import dataclasses
import math
import time
from types import SimpleNamespace

import numpy as np

from comparisons import lab, store
from comparisons.progress import stage_reporter
from comparisons.results import CaseResult, Curve
from comparisons.scenes import lajtai as scene
from comparisons.sweep import run_sweep
from comparisons.variants import pick_variant
from dem_core.output.plot import block_picture, draw_picture, magnification
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import run_stages

DESCRIPTION = ("Virtual lab (UCS, tension, E/nu, cohesion calibration) and Lajtai's direct "
               "shear envelopes: open/closed joints, persistence, T, scale (thesis ch. 3)")

MPA = 1e6

VARIANTS = {
    "quick": dict(
        ucs_edge=0.007, shear_edge=0.007, ucs_rate=1.5e-7, shear_rate=3e-7,
        ucs_max_strain=0.02, shear_max_disp=0.003,
        normal_stresses=[0.3e6, 1.2e6, 2.4e6], lajtai_normal_stresses=[0.3e6, 1.2e6, 2.4e6],
        persistence=[0.0, 0.5, 1.0], tensile=[0.5e6, 1.0e6], scale_edges=[],
        cohesion_sweep=[], accuracy_edges=[], accuracy_safety=[], continuum=True,
        continuum_h=0.01, continuum_normal_stresses=[0.3e6, 1.2e6, 2.4e6], workers=1,
        zone_size=None, edge_elements=None),
    "full": dict(
        ucs_edge=0.007, shear_edge=0.007, ucs_rate=1.5e-7, shear_rate=2e-7,
        ucs_max_strain=0.03, shear_max_disp=0.004,
        normal_stresses=[0.3e6, 0.6e6, 0.9e6, 1.2e6, 1.5e6, 1.8e6, 2.1e6, 2.4e6],
        lajtai_normal_stresses=[0.3e6, 0.6e6, 0.9e6, 1.2e6, 1.5e6, 1.8e6],
        persistence=[0.0, 0.25, 0.5, 0.7, 1.0], tensile=[0.5e6, 1.0e6],
        scale_edges=[0.005, 0.007, 0.009, 0.011],
        cohesion_sweep=[0.3e6, 0.6e6, 0.9e6, 1.5e6, 2.0e6, 2.4e6],
        accuracy_edges=[0.005, 0.006, 0.007, 0.009, 0.011, 0.014], accuracy_safety=[0.3, 0.9],
        continuum=True, continuum_h=0.008, continuum_normal_stresses=[0.3e6, 0.9e6, 1.5e6, 2.4e6],
        workers=2, zone_size=None, edge_elements=None),
}
# zone_size: None, rigid Voronoi blocks with their compliance in series with the contacts (the
# default); a size (m), the specimen's blocks deformable (UDEC's, as the thesis's), meshed into
# zones of that size (Model's ``deformable``). With 3.5 mm zones the calibration reaches the
# thesis's 4.1 MPa at c = 0.75 MPa, which rigid blocks cannot (their floor is 4.4 MPa), at about
# 20 times a rigid test's run time (benchmarks/trials/deformable_ucs.py, docs/comparisons.md).
# edge_elements: None, the scenes' contacts (the end-spring pair of the thesis's UDEC); True, edge
# elements on the rigid specimens (docs/cases/lajtai.md, "The UCS floor on edge elements").

# thesis 3.6-3.8: flaws and joints at friction 30 for the persistence, T and scale studies
STUDY_FRICTION = 30.0
STUDY_TENSILE = 1.0e6
ENVELOPE_POINT_SN = 1.2e6    # Pa, the envelope point of the error-vs-run-time study


# ---------------------------------------------------------------------------- reference
def lajtai_envelope(sn, tensile, cohesion, friction, persistence=0.0, joints="closed",
                    ultimate_friction=None):
    """Lajtai's (1969) composite failure envelope of a shear plane with rock bridges, Pa.

    Built from three mechanisms (thesis 2.3: "the first part ... is controlled by the tensile
    strength, the second part ... by the cohesion, and the third part ... by the friction
    angle"; 3.4 eq. 3.6; compression positive):

    - tensile fracture of a bridge: its minor principal stress reaches -T under the plane's
      normal stress s and shear stress t (s_xx = 0), i.e. t = sqrt(T (T + s)) (eq. 3.6);
    - shear through a bridge: t = c + s tan(phi);
    - ultimate friction on the whole ruptured plane: t = s tan(phi_u).

    A bridge fails at the lower of the first two, ``tau_b(s) = min(...)``. With bridge fraction
    b = 1 - k the bridges carry s / b when the joints are open (voids carry nothing) and s when
    they are closed; following Lajtai, friction on closed joints is not mobilised at the bridge
    failure (cohesion first, friction later), so the peak is

        tau = max(b tau_b(s_b), s tan(phi_u)),   s_b = s / b (open) or s (closed).

    For k = 1 (no bridge) it is the friction line. At s = 0 the two bridge limits are T and c,
    and the tensile branch rises with slope T / (2 sqrt(T (T + s))) <= 1/2; with the thesis's
    parameters (c = 1.2 >= T = 1.1 or 1.0 MPa, friction 30-37) the tensile branch is the
    lower one at every normal stress, so the envelope has a tensile part and, at high stress,
    the frictional part. If c < T the Coulomb part governs at low stress instead.

    Parameters: ``sn`` (Pa, array), ``tensile``, ``cohesion`` (Pa), ``friction`` (deg),
    ``persistence`` k in [0, 1], ``joints`` "open" or "closed", ``ultimate_friction`` (deg,
    default ``friction``).
    """
    s = np.asarray(sn, dtype=float)
    phi_u = friction if ultimate_friction is None else ultimate_friction
    b = 1.0 - persistence
    friction_line = s * math.tan(math.radians(phi_u))
    if b <= 0:
        return friction_line
    sb = s / b if joints == "open" else s
    tau_t = np.sqrt(tensile * (tensile + np.maximum(sb, -tensile)))
    tau_c = cohesion + sb * math.tan(math.radians(friction))
    return np.maximum(b * np.minimum(tau_t, tau_c), friction_line)


def mc_cohesion_from_ucs(ucs, friction):
    """Mohr-Coulomb cohesion (Pa) of a material with this UCS and friction angle (deg)."""
    p = math.radians(friction)
    return ucs * (1 - math.sin(p)) / (2 * math.cos(p))


# ---------------------------------------------------------------------------- members
def ucs_member(q: dict) -> dict:
    """One compression (``q["test"] == "ucs"``) or tension test; plain data in and out. The
    result's ``picture`` is the specimen at the end of the test (``block_picture``); with
    ``q["vtk"]`` (a .vtu path) the model's final state is written there too."""
    width = q.get("width", scene.UCS_WIDTH)
    height = 2.0 * width
    t0 = time.perf_counter()
    glued = q.get("test") == "tension"
    sc = ucs_scene_of(q)
    m = build_model(sc)
    records = run_stages(m, sc.stages, progress=stage_reporter(m, len(sc.stages)))
    cv = lab.curve_of(records[-1], m, t0, 1.0 / height, "gauge", 0.0 if glued else 1.0 / width)
    if q.get("vtk"):
        m.write_vtk(q["vtk"])
    moduli = {}
    if not glued:
        try:
            moduli = lab.elastic_moduli(cv)
        except ValueError:
            pass
    ipk = int(np.argmax(cv.y))
    return {"peak": cv.peak, "strain_at_peak": cv.x_at_peak, "moduli": moduli,
            "softened": bool(cv.y[-1] < 0.9 * cv.peak), "steps": cv.steps, "dt": cv.dt,
            "n_blocks": cv.n_blocks, "cracks": cv.cracks, "curve": np.column_stack(
                [cv.x, cv.y, cv.lateral]), "ipeak": ipk,
            "picture": block_picture(m, cracks=None, joints=()),
            "runtime_s": time.perf_counter() - t0, "params": q}


def ucs_scene_of(q: dict):
    """The scene of one compression (``q["test"] == "ucs"``) or tension test (``ucs_member``'s
    input, e.g. ``ucs_query``): the specimen, its platens and its loading stage."""
    p = scene.FlawParams(edge_length=q["edge"], tensile=q["tensile"], cohesion=q["cohesion"],
                         friction=q["friction"], kn=q["kn"], ks=q["ks"], seed=q["seed"])
    width = q.get("width", scene.UCS_WIDTH)
    return _specimen_solver(scene.ucs_scene(p, width, 2.0 * width,
                                            glued_platens=q.get("test") == "tension",
                                            safety=q.get("safety", 0.5), rate=q["rate"],
                                            max_strain=q["max_strain"]), q)


def shear_member(q: dict) -> dict:
    """One direct-shear test at constant normal stress; plain data in and out. With
    ``q["picture"]`` the result's ``picture`` is the specimen at the end of the test
    (``block_picture``, joints drawn); with ``q["vtk"]`` (a .vtu path) the model's final
    state is written there."""
    p = scene.FlawParams(edge_length=q["edge"], tensile=q["tensile"], cohesion=q["cohesion"],
                         friction=q["friction"], kn=q["kn"], ks=q["ks"], seed=q["seed"])
    s = scene.ShearParams(joints=q["joints"], k=q["k"], joint_friction=q["joint_friction"])
    t0 = time.perf_counter()
    sc = _specimen_solver(scene.shear_scene(p, s, safety=q.get("safety", 0.5),
                                            normal_stress=q["sn"], rate=q["rate"],
                                            max_displacement=q["max_disp"]), q)
    m = build_model(sc)
    records = run_stages(m, sc.stages, progress=stage_reporter(m, len(sc.stages)))
    cv = lab.curve_of(records[-1], m, t0, 1.0, "across")
    if q.get("vtk"):
        m.write_vtk(q["vtk"])
    out = {"peak": cv.peak, "disp_at_peak": cv.x_at_peak, "steps": cv.steps, "dt": cv.dt,
           "n_blocks": cv.n_blocks, "cracks": cv.cracks,
           "normal_measured": float(np.mean(cv.lateral[1:])) if len(cv.lateral) > 1 else 0.0,
           "curve": np.column_stack([cv.x, cv.y, cv.lateral]),
           "runtime_s": time.perf_counter() - t0, "params": q}
    if q.get("picture"):
        out["picture"] = block_picture(m, cracks=None, joints="joint:")
    return out


def _specimen_solver(sc, q: dict):
    """The scene with its specimen's blocks deformable when ``q["zone_size"]`` (m) is set, and
    with the contact model ``q["edge_elements"]`` when it is not None (None: the scene's)."""
    solver = dict(sc.solver)
    if q.get("zone_size") is not None:
        solver["deformable"] = {"rock": q["zone_size"]}
    if q.get("edge_elements") is not None:
        solver["edge_elements"] = q["edge_elements"]
    return dataclasses.replace(sc, solver=solver)


def _vtk(q: dict, name: str) -> dict:
    """``q`` with ``vtk``: ``<vtk folder>/<name>.vtu`` when the run writes VTK files
    (``store.vtk_folder``), else ``q`` as it is."""
    folder = store.vtk_folder()
    return q if folder is None else {**q, "vtk": str(folder / f"{name}.vtu")}


def ucs_query(cfg: dict, cohesion: float, **over) -> dict:
    """The ``ucs_member`` input of the variant settings ``cfg`` (a ``VARIANTS`` entry with a
    ``seed``) at flaw cohesion ``cohesion`` (Pa), with ``over`` replacing any of its items."""
    return {**_flaw_params(cfg, cohesion=cohesion), "test": "ucs", "rate": cfg["ucs_rate"],
            "max_strain": cfg["ucs_max_strain"], **over}


def _flaw_params(cfg, **over):
    base = dict(edge=cfg["ucs_edge"], tensile=scene.THESIS_TENSILE,
                cohesion=scene.THESIS_COHESION, friction=scene.THESIS_FRICTION,
                kn=scene.THESIS_KN, ks=scene.THESIS_KS, seed=cfg["seed"],
                zone_size=cfg["zone_size"], edge_elements=cfg["edge_elements"])
    base.update(over)
    return base


# ---------------------------------------------------------------------------- the run
def run(variant="quick", seed: int = 1, progress=None) -> CaseResult:
    """Run the case: ``variant`` is "quick", "full" or a settings mapping (``VARIANTS`` keys)."""
    variant, cfg = pick_variant("lajtai", VARIANTS, variant,
                                optional={"zone_size": None, "edge_elements": None})
    cfg["seed"] = seed
    say = progress or (lambda msg: None)
    res = CaseResult(case="lajtai", variant=variant, seed=seed)
    t_dem = time.perf_counter()
    dem = {"envelopes": {}, "runtime_by_study_s": {}}

    t0 = time.perf_counter()                     # 1. the virtual lab: UCS and tension
    best, ucs_vs_c = _virtual_lab(cfg, dem, say)
    dem["runtime_by_study_s"]["lab"] = time.perf_counter() - t0
    res.curves["ucs_stress_strain"] = Curve(
        ["axial_strain", "axial_stress_pa", "lateral_strain"], best["curve"])
    res.curves["ucs_vs_cohesion"] = Curve(["flaw_cohesion_mpa", "ucs_mpa"], ucs_vs_c)

    t0 = time.perf_counter()                     # 2-5. the direct shear studies
    keys, out = _shear_runs(cfg, say)
    dem["runtime_by_study_s"]["direct_shear"] = time.perf_counter() - t0
    runs = _envelopes(cfg, keys, out, dem, res)

    if cfg["accuracy_edges"]:                    # 6. error against run time
        dem["accuracy"] = accuracy_study(cfg, scene.THESIS_COHESION, say)
    dem["runtime_s"] = time.perf_counter() - t_dem
    res.methods["dem"] = dem

    _references(res, dem, runs, scene.THESIS_COHESION)
    if cfg["continuum"]:
        _continuum(res, cfg, say)
    _figures(res, dem, runs, best, ucs_vs_c, cfg)
    res.notes += _notes(cfg)
    return res


def _virtual_lab(cfg: dict, dem: dict, say):
    """The UCS calibration of the flaw cohesion (``lab.calibrate_cohesion``), a sweep of c, the
    loading-rate check and the tension test at the thesis's c; their numbers go into ``dem``.
    Returns the calibrated UCS run and the (c MPa, UCS MPa) rows."""
    def ucs_q(c, **over):
        name = f"ucs_c{c / MPA:.6g}" + "".join(f"_{k}{v:g}" for k, v in over.items())
        return _vtk(ucs_query(cfg, c, **over), name)

    def one(q):                    # one run, through run_sweep: kept, and loaded on resume
        return run_sweep(ucs_member, [q])[0]

    ucs_runs = {}

    def ucs_of(c):
        r = one(ucs_q(c))
        ucs_runs[c] = r
        return r["peak"]

    cal = lab.calibrate_cohesion(ucs_of, scene.THESIS_UCS, scene.THESIS_COHESION,
                                 rel_tol=0.02, max_runs=7, progress=say)
    c_cal = cal["cohesion"]
    best = ucs_runs[c_cal]
    # Lajtai's specimens and the tension test use the thesis's calibrated c = 1.2 MPa, not
    # ours: our rigid-block assembly reaches UCS = 4.1 MPa only near c = 0.05 MPa, where the
    # assembly's tensile strength collapses (bonds inclined to the pull fail in shear), so our
    # c would miss the other target of the calibration, T; the report gives both (notes).
    c_use = scene.THESIS_COHESION
    at_thesis_c = ucs_runs[scene.THESIS_COHESION]
    sweep_c = [c for c in cfg["cohesion_sweep"] if all(abs(c - k) > 1 for k in ucs_runs)]
    for c, r in zip(sweep_c, run_sweep(ucs_member, [ucs_q(c) for c in sweep_c],
                                       workers=cfg["workers"], progress=say)):
        ucs_runs[c] = r
    ucs_vs_c = np.array(sorted((c / MPA, r["peak"] / MPA) for c, r in ucs_runs.items()))
    say(f"UCS {best['peak'] / MPA:.3g} MPa at c = {c_cal / MPA:.3g} MPa "
        f"(converged {cal['converged']})")
    rate = lab.rate_check(lambda rt: _as_curve(one(ucs_q(c_cal, rate=rt))), cfg["ucs_rate"])
    tension = one(_vtk({**ucs_q(c_use), "test": "tension", "max_strain": 0.01},
                       f"tension_c{c_use / MPA:g}"))
    dem.update({
        "ucs_mpa": best["peak"] / MPA, "calibrated_cohesion_mpa": c_cal / MPA,
        "calibration_converged": cal["converged"],
        "cohesion_used_mpa": c_use / MPA,
        "calibration_history_mpa": [[c / MPA, u / MPA] for c, u in cal["history"]],
        "ucs_at_thesis_cohesion_mpa": at_thesis_c["peak"] / MPA,
        "ucs_softened": best["softened"],
        "ucs_strain_at_peak": best["strain_at_peak"],
        "E_2d_gpa": best["moduli"].get("E_2d", float("nan")) / 1e9,
        "nu_2d": best["moduli"].get("nu_2d", float("nan")),
        "E_plane_strain_gpa": best["moduli"].get("E", float("nan")) / 1e9,
        "nu_plane_strain": best["moduli"].get("nu", float("nan")),
        "tensile_strength_mpa": tension["peak"] / MPA,
        "ucs_rate_check": {"rate_m_per_step": rate["rate"],
                           "velocity_m_s": rate["rate"] / best["dt"],
                           "peak_mpa": rate["peak"] / MPA,
                           "peak_half_rate_mpa": rate["peak_half_rate"] / MPA,
                           "rel_change": rate["rel_change"]},
        "ucs_specimen": {"width_m": scene.UCS_WIDTH, "height_m": scene.UCS_HEIGHT,
                         "edge_m": cfg["ucs_edge"], "blocks": best["n_blocks"],
                         "steps": best["steps"], "dt_s": best["dt"],
                         "runtime_s": best["runtime_s"]},
    })
    return best, ucs_vs_c


def _shear_runs(cfg: dict, say):
    """Every direct-shear specimen of the studies (Lajtai's open and closed joints, persistence
    k, tensile strength, block size; thesis 3.6-3.8), run as one sweep: the (study, sn) keys
    and {key: run}."""
    members, keys = [], []
    c_use = scene.THESIS_COHESION

    def add(study, sn_list, pic=(), **over):
        for sn in sn_list:
            q = {**_flaw_params(cfg, edge=cfg["shear_edge"], cohesion=c_use), "joints": "none",
                 "k": 0.0, "joint_friction": scene.THESIS_FRICTION, "sn": sn,
                 "rate": cfg["shear_rate"], "max_disp": cfg["shear_max_disp"], **over}
            q["picture"] = sn in pic
            members.append(_vtk(q, f"{study}_sn{sn / MPA:g}"))
            keys.append((study, sn))

    sns, lsns = cfg["normal_stresses"], cfg["lajtai_normal_stresses"]
    lo_hi = (lsns[0], lsns[-1])
    add("lajtai_open", lsns, pic=lo_hi, joints="open", k=scene.LAJTAI_PERSISTENCE)
    add("lajtai_closed", lsns, pic=lo_hi, joints="closed", k=scene.LAJTAI_PERSISTENCE)
    # thesis 3.6-3.8 give these studies Table 3.1's properties with friction 30 and T 1.0 MPa:
    # the flaw cohesion is Table 3.1's 1.2 MPa, as in their reference envelopes, not our
    # calibrated value (ours reaches 4.1 MPa only at c ~ 0, where the halves of the k = 1
    # specimen break up under the box instead of sliding on the joint)
    study = dict(friction=STUDY_FRICTION, joint_friction=STUDY_FRICTION, tensile=STUDY_TENSILE,
                 cohesion=scene.THESIS_COHESION)
    for k in cfg["persistence"]:
        add(f"persistence_k{k:g}", sns, pic=(sns[0],) if k in (0.0, 0.5) else (),
            joints="closed" if k > 0 else "none", k=k, **study)
    for T in cfg["tensile"]:
        if T != STUDY_TENSILE or 0.0 not in cfg["persistence"]:
            add(f"tensile_T{T / MPA:g}", sns, **{**study, "tensile": T})
    p7 = scene.FlawParams(edge_length=cfg["shear_edge"])
    for e in cfg["scale_edges"]:
        if abs(e - cfg["shear_edge"]) < 1e-12:
            continue
        pe = scene.stiffness_for_edge(p7, e)
        add(f"scale_edge{e * 1e3:g}mm", sns, edge=e, kn=pe.kn, ks=pe.ks, **study)
    say(f"direct shear: {len(members)} runs")
    out = dict(zip(keys, run_sweep(shear_member, members, workers=cfg["workers"],
                                   progress=say)))
    return keys, out


def _envelopes(cfg: dict, keys: list, out: dict, dem: dict, res: CaseResult) -> dict:
    """Each study's envelope (peak shear against normal stress) into ``dem["envelopes"]`` and
    the curves, and the shear specimen's summary; {study: [(sn, run), ...]}. Studies that are
    the same runs share them: T = 1.0 MPa is the k = 0 persistence run, and so is the 7 mm
    edge of the scale study."""
    sns, lsns = cfg["normal_stresses"], cfg["lajtai_normal_stresses"]
    alias = {}
    if 0.0 in cfg["persistence"]:
        alias[f"tensile_T{STUDY_TENSILE / MPA:g}"] = "persistence_k0"
        if cfg["scale_edges"]:
            alias[f"scale_edge{cfg['shear_edge'] * 1e3:g}mm"] = "persistence_k0"
    studies = sorted({s for s, _ in keys} | set(alias), key=_study_order)
    runs = {}
    for st in studies:
        src = alias.get(st, st)
        runs[st] = [(sn, out[(src, sn)]) for sn in (lsns if st.startswith("lajtai") else sns)]
        dem["envelopes"][st] = [[sn / MPA, r["peak"] / MPA] for sn, r in runs[st]]
        res.curves[f"envelope_{st}"] = Curve(
            ["normal_stress_mpa", "peak_shear_mpa", "normal_measured_mpa", "disp_at_peak_m",
             "steps", "runtime_s"],
            np.array([[sn / MPA, r["peak"] / MPA, r["normal_measured"] / MPA, r["disp_at_peak"],
                       r["steps"], r["runtime_s"]] for sn, r in runs[st]]))
    dem["shear_specimen"] = {"length_m": scene.SHEAR_LENGTH, "height_m": scene.SHEAR_HEIGHT,
                             "edge_m": cfg["shear_edge"],
                             "blocks": out[keys[0]]["n_blocks"],
                             "rate_m_per_step": cfg["shear_rate"],
                             "mean_steps": float(np.mean([r["steps"] for r in out.values()])),
                             "mean_runtime_s": float(np.mean([r["runtime_s"]
                                                              for r in out.values()]))}
    return runs


def _study_order(name):
    order = ["lajtai_open", "lajtai_closed", "persistence", "tensile", "scale"]
    for i, o in enumerate(order):
        if name.startswith(o):
            return (i, name)
    return (len(order), name)


def _as_curve(r):
    """The fields of a member's result that ``lab.rate_check`` reads, as attributes."""
    return SimpleNamespace(peak=r["peak"], steps=r["steps"], runtime_s=r["runtime_s"])


def accuracy_study(cfg, c_cal, say):
    """UCS and the k = 0, sn = 1.2 MPa shear peak against block edge and safety factor.

    ``cfg``: a variant dict (``VARIANTS``) with ``seed``, whose ``accuracy_edges`` (m) and
    ``accuracy_safety`` (time-step safety factors, at ``ucs_edge``) are run; ``c_cal``: flaw
    cohesion, Pa. Stiffness is scaled with the edge (eq. 3.7). Returns {"reference", "rows"}:
    per run the edge, safety, UCS and shear peak (MPa), their run times (s) and their relative
    errors against the finest edge (the converged answer stands in for an exact one).
    Used by the full variant and by benchmarks/lab_resolution.py."""
    p7 = scene.FlawParams(edge_length=cfg["ucs_edge"])
    params_u, params_s, labels = [], [], []
    cases = [(e, 0.5) for e in cfg["accuracy_edges"]]
    cases += [(cfg["ucs_edge"], sf) for sf in cfg["accuracy_safety"]]
    for e, sf in cases:
        pe = scene.stiffness_for_edge(p7, e)
        base = _flaw_params(cfg, edge=e, cohesion=c_cal, kn=pe.kn, ks=pe.ks, safety=sf)
        params_u.append({**base, "test": "ucs", "rate": cfg["ucs_rate"],
                         "max_strain": cfg["ucs_max_strain"]})
        params_s.append({**base, "friction": STUDY_FRICTION, "tensile": STUDY_TENSILE,
                         "joints": "none", "k": 0.0, "joint_friction": STUDY_FRICTION,
                         "sn": ENVELOPE_POINT_SN, "rate": cfg["shear_rate"],
                         "max_disp": cfg["shear_max_disp"]})
        labels.append((e, sf))
    say(f"accuracy study: {len(labels)} block sizes / safety factors")
    ru = run_sweep(ucs_member, params_u, workers=cfg["workers"], progress=say)
    rs = run_sweep(shear_member, params_s, workers=cfg["workers"], progress=say)
    fine = int(np.argmin([e for e, _ in labels]))       # the finest edge is the reference
    rows = []
    for (e, sf), u, s in zip(labels, ru, rs):
        rows.append({"edge_m": e, "safety": sf,
                     "ucs_mpa": u["peak"] / MPA, "ucs_runtime_s": u["runtime_s"],
                     "ucs_rel_error": abs(u["peak"] / ru[fine]["peak"] - 1),
                     "shear_mpa": s["peak"] / MPA, "shear_runtime_s": s["runtime_s"],
                     "shear_rel_error": abs(s["peak"] / rs[fine]["peak"] - 1),
                     "blocks_ucs": u["n_blocks"], "blocks_shear": s["n_blocks"]})
    return {"reference": f"finest edge {labels[fine][0] * 1e3:g} mm", "rows": rows}


def _references(res, dem, runs, c_cal):
    T, phi, c = scene.THESIS_TENSILE, scene.THESIS_FRICTION, scene.THESIS_COHESION
    res.reference.update({
        "ucs_mpa": scene.THESIS_UCS / MPA, "calibrated_cohesion_mpa": c / MPA,
        "flaw_tensile_strength_mpa": T / MPA, "flaw_friction_deg": phi,
        "kn_gpa_m": scene.THESIS_KN / 1e9, "ks_gpa_m": scene.THESIS_KS / 1e9,
        "block_E_gpa": scene.THESIS_BLOCK_E / 1e9,
        "k1_friction_deg": STUDY_FRICTION,
        "envelope": "Lajtai composite (lajtai_envelope), thesis parameters",
        "source": "thesis 3.5-3.8, Table 3.1, figs 3.8-3.17 (figure data not digitised)"})
    res.add_error("ucs_mpa", dem["ucs_mpa"], scene.THESIS_UCS / MPA)
    res.add_error("calibrated_cohesion_mpa", dem["calibrated_cohesion_mpa"], c / MPA)
    tan30 = math.tan(math.radians(STUDY_FRICTION))
    if "persistence_k1" in runs:
        ratio = np.mean([r["peak"] / (sn * tan30) for sn, r in runs["persistence_k1"]])
        res.add_error("k1_over_friction_line", float(ratio), 1.0)
    for st, rr in runs.items():
        sn = np.array([s for s, _ in rr])
        ours = np.array([r["peak"] for _, r in rr])
        ref = _reference_for(st, sn, c_cal)
        res.add_error(f"{st}_over_lajtai", float(np.mean(ours / ref)), 1.0)


def _reference_for(study, sn, c_cal):
    """The Lajtai composite envelope for one study (Pa)."""
    if study.startswith("lajtai_"):
        return lajtai_envelope(sn, scene.THESIS_TENSILE, scene.THESIS_COHESION,
                               scene.THESIS_FRICTION, scene.LAJTAI_PERSISTENCE,
                               joints=study.split("_")[1])
    T = STUDY_TENSILE
    k = 0.0
    if study.startswith("persistence_k"):
        k = float(study[len("persistence_k"):])
    if study.startswith("tensile_T"):
        T = float(study[len("tensile_T"):]) * MPA
    return lajtai_envelope(sn, T, scene.THESIS_COHESION, STUDY_FRICTION, k, joints="closed")


def _continuum(res, cfg, say):
    try:
        from comparisons import lajtai_continuum
    except ImportError as exc:            # DOLFINx missing: the DEM results still stand
        res.notes.append(f"continuum column skipped: {exc}")
        return
    t0 = time.perf_counter()
    out = lajtai_continuum.run(cfg["continuum_normal_stresses"], h=cfg["continuum_h"],
                               progress=say)
    out["runtime_s"] = time.perf_counter() - t0
    res.methods["continuum"] = out
    res.add_error("continuum_ucs_mpa", out["ucs_mpa"], scene.THESIS_UCS / MPA,
                  method="continuum")
    res.curves["envelope_continuum"] = Curve(["normal_stress_mpa", "peak_shear_mpa"],
                                             np.array(out["envelope"]))


def _notes(cfg):
    return [
        f"UCS specimen {scene.UCS_WIDTH * 1e3:g} x {scene.UCS_HEIGHT * 1e3:g} mm between "
        f"rigid platens (contact friction {scene.PLATEN_FRICTION:g} deg, unbonded: lubricated); "
        f"tension test with glued platens. Block edge {cfg['ucs_edge'] * 1e3:g} mm.",
        f"Direct-shear specimen {scene.SHEAR_LENGTH * 1e3:g} x {scene.SHEAR_HEIGHT * 1e3:g} mm, "
        "shear plane at mid-height, split box with glued plates and frictionless walls, the "
        "gap between the halves' walls 1/3 of the height; constant normal stress by a servo on "
        "the upper box, the lower box moved in +x. Shear stress = upper-box force / total "
        "length.",
        f"Lajtai's specimens taken with k = {scene.LAJTAI_PERSISTENCE} (joints from both ends); "
        f"open joints are {scene.SLOT_HEIGHT * 1e3:g} mm slots.",
        "Flaw cohesion of every shear study and of the tension test = Table 3.1's 1.2 MPa "
        "('cohesion_used_mpa'), as in the thesis. Our calibration to UCS = 4.1 MPa converges "
        "near c = 0.05 MPa only ('calibrated_cohesion_mpa'): at c = 1.2 MPa our rigid Voronoi "
        "specimen gives ~6.2 MPa ('ucs_at_thesis_cohesion_mpa'), and at c ~ 0.05 MPa its direct "
        "tension strength falls to ~0.04 MPa, so UCS and tensile targets cannot both be met "
        "with rigid blocks at this size (UDEC's blocks were deformable; the variant setting "
        "'zone_size' makes them deformable here too).",
        ("Blocks: rigid, their E and nu in series with the contacts." if cfg["zone_size"] is None
         else f"Blocks: deformable, zones of {cfg['zone_size'] * 1e3:g} mm."),
        "Direct-shear stress is read on the stationary upper box (the moving box also carries "
        "the start-up inertia of the lower half).",
        "Loading rates are platen / box displacements per time step (mass scaling sets the "
        "step); the UCS rate check reruns at half the rate.",
        "UCS = peak stress up to the strain limit "
        f"{cfg['ucs_max_strain']:g}; 'ucs_softened' says whether the curve dropped after it.",
        "Scale study: kn, ks scaled as 1 / edge (thesis eq. 3.7) from the 7 mm values.",
        "Error-vs-run-time reference: the finest block size run (not a thesis value).",
        "Reference envelope: lajtai_envelope() (module docstring), thesis T, c, phi; the "
        "figures' data points were not digitised, so the comparison is against this closed "
        "form, not against Lajtai's measurements.",
    ]


# ---------------------------------------------------------------------------- figures
def _figures(res, dem, runs, best, ucs_vs_c, cfg):
    """The case's figures: the UCS test, the envelopes, the normalised persistence strength,
    the specimens after the peak and error against run time (each only with its runs)."""
    import matplotlib
    matplotlib.use("Agg")

    _ucs_figure(res, dem, best, ucs_vs_c)
    _envelope_figure(res, runs, cfg)
    if any(s.startswith("persistence") for s in runs) and "persistence_k0" in runs:
        _persistence_figure(res, runs)
    _specimens_figure(res, runs)
    if "accuracy" in dem:
        _accuracy_figure(res, dem["accuracy"]["rows"])


def _ucs_figure(res, dem, best, ucs_vs_c):
    """Stress-strain of the calibrated UCS test (fig 3.8), UCS against c (fig 3.9), the
    specimen at the end."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2), gridspec_kw={"width_ratios": [3, 3, 2]})
    cur = best["curve"]
    ax[0].plot(cur[:, 0] * 100, cur[:, 1] / MPA, label="axial")
    ax[0].plot(cur[:, 2] * 100, cur[:, 1] / MPA, label="lateral")
    ax[0].axhline(scene.THESIS_UCS / MPA, ls="--", c="k", lw=0.8, label="thesis UCS 4.1 MPa")
    ax[0].set_xlabel("strain (%)")
    ax[0].set_ylabel("axial stress (MPa)")
    ax[0].set_title(f"UCS test, c = {dem['calibrated_cohesion_mpa']:.2f} MPa (fig. 3.8)")
    ax[0].legend()
    ax[1].plot(ucs_vs_c[:, 0], ucs_vs_c[:, 1], "o-", label="DEM")
    ax[1].plot([scene.THESIS_COHESION / MPA], [scene.THESIS_UCS / MPA], "k*", ms=12,
               label="thesis: c 1.2 -> UCS 4.1")
    ax[1].set_xlabel("flaw cohesion (MPa)")
    ax[1].set_ylabel("UCS (MPa)")
    ax[1].set_title("UCS against flaw cohesion (fig. 3.9)")
    ax[1].legend()
    _specimen(ax[2], best, f"UCS specimen, end of test\n(axial strain {100 * cur[-1, 0]:.2f} "
                           f"%)")
    fig.tight_layout()
    res.figures["ucs"] = fig


def _envelope_figure(res, runs, cfg):
    """Peak shear against normal stress per study group (figs 3.11-3.17), Lajtai's composite
    envelope dashed, the continuum's envelope on the last panel."""
    import matplotlib.pyplot as plt

    groups = [("lajtai", "Lajtai specimens, k = 0.5 (figs 3.11-3.12)"),
              ("persistence", "persistence, friction 30 (fig. 3.14)"),
              ("tensile", "flaw tensile strength, k = 0 (fig. 3.16)"),
              ("scale", "block size, k = 0 (fig. 3.17)")]
    groups = [(g, t) for g, t in groups if any(s.startswith(g) for s in runs)]
    fig, axes = plt.subplots(1, len(groups), figsize=(5 * len(groups), 4.2), squeeze=False)
    for ax, (g, title) in zip(axes[0], groups):
        for i, st in enumerate(s for s in runs if s.startswith(g)):
            sn = np.array([s for s, _ in runs[st]]) / MPA
            tau = np.array([r["peak"] for _, r in runs[st]]) / MPA
            line, = ax.plot(sn, tau, "o-", label=st)
            if g in ("lajtai", "persistence", "tensile"):
                ss = np.linspace(0, sn.max(), 60)
                ax.plot(ss, _reference_for(st, ss * MPA, 0) / MPA, "--", c=line.get_color(),
                        lw=0.9)
        ss = np.linspace(0, max(cfg["normal_stresses"]) / MPA, 10)
        ax.plot(ss, ss * math.tan(math.radians(STUDY_FRICTION)), "k:", lw=0.8,
                label="friction 30")
        ax.set_xlabel("normal stress (MPa)")
        ax.set_ylabel("peak shear stress (MPa)")
        ax.set_title(title + "\n(dashed: Lajtai composite)", fontsize=9)
        ax.legend(fontsize=7)
    if "continuum" in res.methods:
        env = np.array(res.methods["continuum"]["envelope"])
        axes[0][-1].plot(env[:, 0], env[:, 1], "s-", c="0.4", label="continuum MC")
        axes[0][-1].legend(fontsize=7)
    res.figures["envelopes"] = fig


def _persistence_figure(res, runs):
    """Each persistence's peak over the intact (k = 0) peak (fig 3.15)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    intact = np.array([r["peak"] for _, r in runs["persistence_k0"]])
    for st in (s for s in runs if s.startswith("persistence")):
        sn = np.array([s for s, _ in runs[st]])
        ax.plot(sn / MPA, np.array([r["peak"] for _, r in runs[st]]) / intact, "o-",
                label=st)
    sn = np.array([s for s, _ in runs["persistence_k0"]])
    ax.plot(sn / MPA, sn * math.tan(math.radians(STUDY_FRICTION)) / intact, "k:",
            label="friction 30 / intact")
    ax.set_xlabel("normal stress (MPa)")
    ax.set_ylabel("peak shear / intact (k = 0) peak")
    ax.set_title("normalised strength (fig. 3.15)")
    ax.legend(fontsize=7)
    res.figures["persistence_normalised"] = fig


def _specimens_figure(res, runs):
    """The specimens that kept a picture, after the peak (blocks, joints, cracks by mode)."""
    import matplotlib.pyplot as plt

    pics, seen = [], set()
    for st, rr in runs.items():                   # an aliased study's runs are drawn once
        pics += [(st, sn, r) for sn, r in rr if "picture" in r and id(r) not in seen]
        seen |= {id(r) for _, r in rr}
    if not pics:
        return
    n = len(pics)
    cols = min(n, 3)
    rows = int(math.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(5.5 * cols, 3.4 * rows), squeeze=False)
    for ax, (st, sn, r) in zip(axes.flat, pics):
        _specimen(ax, r, f"{st}, sn {sn / MPA:g} MPa: end of test at shear displacement "
                         f"{1e3 * r['curve'][-1, 0]:.2f} mm\n(peak at "
                         f"{1e3 * r['disp_at_peak']:.2f} mm)")
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle("direct-shear specimens after the peak: blocks coloured by displacement, "
                 "joints black, cracks red tension / blue shear", fontsize=9)
    fig.tight_layout()
    res.figures["shear_specimens"] = fig


def _accuracy_figure(res, rows):
    """Error against run time of the UCS and a shear peak over block sizes and steps."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for key, lab_, mk in (("ucs", "UCS", "o"), ("shear", "shear peak, sn 1.2 MPa", "s")):
        t = [r[f"{key}_runtime_s"] for r in rows]
        e = [max(r[f"{key}_rel_error"], 1e-4) for r in rows]
        ax.loglog(t, e, mk, label=lab_)
        for r, ti, ei in zip(rows, t, e):
            tag = f"{r['edge_m'] * 1e3:g} mm" + ("" if r["safety"] == 0.5 else
                                                f", sf {r['safety']:g}")
            ax.annotate(tag, (ti, ei), fontsize=6)
            if abs(r["edge_m"] - 0.007) < 1e-9 and r["safety"] == 0.5:
                ax.plot(ti, ei, "r*", ms=12)
    ax.set_xlabel("run time (s)")
    ax.set_ylabel("relative difference from the finest run")
    ax.set_title("error against run time (red star: thesis 7 mm)")
    ax.legend(fontsize=7)
    res.figures["error_vs_runtime"] = fig
    res.curves["error_vs_runtime"] = Curve(
        ["edge_m", "safety", "ucs_mpa", "ucs_runtime_s", "ucs_rel_error", "shear_mpa",
         "shear_runtime_s", "shear_rel_error"],
        np.array([[r["edge_m"], r["safety"], r["ucs_mpa"], r["ucs_runtime_s"],
                   r["ucs_rel_error"], r["shear_mpa"], r["shear_runtime_s"],
                   r["shear_rel_error"]] for r in rows]))


def _specimen(ax, run, title):
    """A specimen at the end of its test (``run["picture"]``), displacement magnified (stated
    in the title), coloured by displacement (mm), joints and cracks drawn."""
    k = magnification(run["picture"])
    draw_picture(run["picture"], ax, k, unit="mm")
    ax.set_title(f"{title}, displacement magnified x {k:g}", fontsize=8)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_xlabel("")
    ax.set_ylabel("")
