"""Virtual rock-mechanics lab on DEM specimens: compression, tension, direct shear, calibration.

Every test drives rigid loading parts (platens, shear-box halves; groups of a ``Model``) and
reads the force the specimen exerts on them. Each loading path is a list of stages
(``dem_core.workflow.loading``: ``Load``, ``ServoLoad``) that a scene file can carry; the ``*_test``
functions run them on a model and return the curve. Conventions: SI units;
compressive stress and strain positive; shear stress positive in the direction the lower box
moves (+x), read on the stationary box. Strains are platen displacement over specimen
height; the lateral strain of the compression test is the change of distance between the
specimen's two side faces over the width (expansion positive), so Poisson's ratio = lateral /
axial.

The moduli measured on a 2D assembly are the 2D (plane) values ``E_2d``, ``nu_2d``; their
plane-strain equivalents are ``nu = nu_2d / (1 + nu_2d)``, ``E = E_2d (1 - nu^2)``
(``dem_core.contact.elastic``).

Quasi-static loading: the platen/box velocity is given as a displacement per time step
(``rate``, m/step, times the model's time step gives the velocity), because with mass scaling
the time step, not the physical density, sets the inertia; a run is quasi-static when halving
the rate does not change the peak (``rate_check``).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from dem_core.contact.elastic import spacing_from_area
from dem_core.workflow.loading import Load, ServoLoad
from dem_core.model import Model
from dem_core.workflow.stages import run_stages

__all__ = ["LabCurve", "contact_force", "compression_load", "tension_load", "shear_stages",
           "curve_of", "compression_test", "tension_test", "direct_shear",
           "elastic_moduli", "calibrate_cohesion", "stiffness_for_moduli",
           "calibrate_stiffness", "plane_strain", "rate_check"]


@dataclass
class LabCurve:
    """A lab test record.

    Attributes
    ----------
    x, y : (n,) arrays. Compression/tension: axial strain and stress (Pa); shear: shear
        displacement (m) and shear stress (Pa).
    time : (n,) array, s. Model time of each record (to pick the crack log at the peak).
    lateral : (n,) array. Compression: lateral strain; shear: normal stress measured (Pa).
    peak : float. Max of y (Pa).
    x_at_peak : float.
    steps : int. Time steps run. runtime_s : float. dt : float (s).
    n_blocks : int. cracks : dict (tension / shear counts). model : the Model at the end.
    """

    x: np.ndarray
    y: np.ndarray
    time: np.ndarray
    lateral: np.ndarray
    peak: float
    x_at_peak: float
    steps: int
    runtime_s: float
    dt: float
    n_blocks: int
    cracks: dict
    model: Model = field(repr=False, default=None)


def contact_force(model: Model, group) -> np.ndarray:
    """Total force (N/m) the rest of the model exerts on ``group`` in the last step, (fx, fy).

    Read from the blocks' unbalanced forces, which for blocks whose motion is prescribed are
    the contact forces on them (valid without gravity and applied loads on the group).
    """
    idx = model.group(group)
    return model.state.force[idx, :2].sum(axis=0)


# ---------------------------------------------------------------------------- loading paths
def compression_load(width: float, height: float, rate: float, gauge=(), max_strain=0.05,
                     post_peak=0.7, chunk=200) -> Load:
    """The unconfined compression path as a stage: ``platen_top`` moves down at ``rate``
    m/step (no rotation, no sideways motion) against ``platen_bottom`` (fixed by the scene);
    the stress is the mean of the two platens' reactions over ``width``; ``gauge``: the two
    side groups whose x distance gives the lateral strain. Stops at ``max_strain`` or once the
    stress fell below ``post_peak`` x peak."""
    return Load("platen_top", rate, (0.0, -1.0), read_on=("platen_top", "platen_bottom"),
                length=width, max_displacement=max_strain * height, post_peak=post_peak,
                gauge=tuple(gauge), chunk=chunk)


def tension_load(width: float, height: float, rate: float, max_strain=0.02, post_peak=0.5,
                 chunk=200) -> Load:
    """Direct tension as a stage: ``platen_top`` (glued) pulled up at ``rate`` m/step."""
    return Load("platen_top", rate, (0.0, 1.0), read_on=("platen_top", "platen_bottom"),
                length=width, max_displacement=max_strain * height, post_peak=post_peak,
                chunk=chunk)


def shear_stages(length: float, normal_stress: float, rate: float, max_displacement: float,
                 post_peak=0.8, chunk=200, settle_tol=0.02, max_settle_steps=40_000) -> list:
    """Direct shear at constant normal stress as two stages.

    1. ``box_up`` is servo-controlled in -y to press with ``normal_stress x length`` (N/m),
       held in x and rotation, at most 20 x the shear rate, until the load is reached within
       ``settle_tol`` (consolidation).
    2. ``box_low`` (fixed by the scene) moves in +x at ``rate`` m/step; the shear stress is
       the x force on the stationary upper box over ``length``, like a load cell on the
       reaction side: the force on the moving half also holds what accelerates the lower half
       of the specimen when the box starts (times 1 / (1 - damping) with local damping), a
       start-up transient of up to +45 % of the friction line at sn = 0.3 MPa in the fully
       jointed (k = 1) specimen. Stops at ``max_displacement`` or when the shear stress fell
       below ``post_peak`` x peak beyond 1.5 x the displacement at the peak.
    """
    if not (normal_stress >= 0 and math.isfinite(normal_stress)):
        raise ValueError(f"normal stress must be finite and >= 0 Pa, got {normal_stress!r}")
    return [ServoLoad("box_up", normal_stress, length, (0.0, -1.0), v_max=20.0 * rate,
                      settle_tol=settle_tol, max_steps=max_settle_steps, chunk=chunk),
            Load("box_low", rate, (1.0, 0.0), read_on=("box_up",), length=length,
                 max_displacement=max_displacement, post_peak=post_peak, past_peak=1.5,
                 chunk=chunk)]


def curve_of(record, model: Model, t0: float, scale_x=1.0, lateral="gauge", scale_lateral=1.0,
             keep_model=False) -> LabCurve:
    """A LabCurve from a ``Load`` stage's record: x = displacement x ``scale_x`` (1/height for
    a strain), y = reaction, lateral = ``record.detail[lateral]`` x ``scale_lateral``."""
    det = record.detail
    x, y = det["displacement"] * scale_x, det["reaction"]
    i = int(np.argmax(y))
    return LabCurve(x=x, y=y, time=det["time"], lateral=det[lateral] * scale_lateral,
                    peak=float(y[i]), x_at_peak=float(x[i]), steps=int(model.step),
                    runtime_s=time.perf_counter() - t0, dt=float(model.dt),
                    n_blocks=int(model.n_blocks), cracks=model.crack_counts(),
                    model=model if keep_model else None)


def compression_test(model: Model, width: float, height: float, rate: float, gauge=(),
                     max_strain=0.05, post_peak=0.7, chunk=200, keep_model=False) -> LabCurve:
    """Unconfined compression (``compression_load``) on a model with groups "platen_bottom"
    (fixed here) and "platen_top": axial strain, stress (Pa) and lateral strain."""
    t0 = time.perf_counter()
    model.fix("platen_bottom")
    rec = run_stages(model, [compression_load(width, height, rate, gauge, max_strain,
                                              post_peak, chunk)])[-1]
    return curve_of(rec, model, t0, 1.0 / height, "gauge", 1.0 / width, keep_model)


def tension_test(model: Model, width: float, height: float, rate: float, max_strain=0.02,
                 post_peak=0.5, chunk=200, keep_model=False) -> LabCurve:
    """Direct tension (``tension_load``): tensile strain and stress, both positive."""
    t0 = time.perf_counter()
    model.fix("platen_bottom")
    rec = run_stages(model, [tension_load(width, height, rate, max_strain, post_peak,
                                          chunk)])[-1]
    return curve_of(rec, model, t0, 1.0 / height, "gauge", 0.0, keep_model)


def direct_shear(model: Model, length: float, normal_stress: float, rate: float,
                 max_displacement: float, post_peak=0.8, chunk=200, settle_tol=0.02,
                 max_settle_steps=40_000, keep_model=False) -> LabCurve:
    """Direct shear at constant normal stress (``shear_stages``) on a model with groups
    "box_up" and "box_low" (fixed here): shear displacement (m), shear stress (Pa) and, as
    ``lateral``, the normal stress measured on the upper box (Pa)."""
    t0 = time.perf_counter()
    stages = shear_stages(length, normal_stress, rate, max_displacement, post_peak, chunk,
                          settle_tol, max_settle_steps)
    model.fix("box_low")
    rec = run_stages(model, stages)[-1]
    return curve_of(rec, model, t0, 1.0, "across", 1.0, keep_model)


# ---------------------------------------------------------------------------- moduli
def elastic_moduli(curve: LabCurve, lo=0.1, hi=0.5) -> dict:
    """E_2d (Pa) and nu_2d from the pre-peak part of a compression curve between ``lo`` and
    ``hi`` x peak stress (least-squares slopes), and their plane-strain equivalents."""
    ipk = int(np.argmax(curve.y))
    s, e, lat = curve.y[:ipk + 1], curve.x[:ipk + 1], curve.lateral[:ipk + 1]
    sel = (s >= lo * curve.peak) & (s <= hi * curve.peak)
    if sel.sum() < 3:
        raise ValueError(f"only {sel.sum()} records between {lo} and {hi} x peak: load slower "
                         "or record more often")
    E2 = float(np.polyfit(e[sel], s[sel], 1)[0])
    nu2 = float(np.polyfit(e[sel], lat[sel], 1)[0])
    return {"E_2d": E2, "nu_2d": nu2, **plane_strain(E2, nu2)}


def plane_strain(E_2d: float, nu_2d: float) -> dict:
    """Plane-strain E, nu of the 3D solid whose 2D (plane) moduli are E_2d, nu_2d."""
    nu = nu_2d / (1 + nu_2d)
    return {"E": E_2d * (1 - nu * nu), "nu": nu}


def rate_check(run, rate: float) -> dict:
    """Peak at ``rate`` and ``rate / 2``; ``run(rate) -> LabCurve``. Quasi-static if the
    relative change is small (the caller judges; 2-3 % is typical of Voronoi specimens)."""
    a, b = run(rate), run(0.5 * rate)
    return {"rate": rate, "peak": a.peak, "peak_half_rate": b.peak,
            "rel_change": abs(a.peak - b.peak) / b.peak, "steps": a.steps,
            "steps_half_rate": b.steps, "runtime_s": a.runtime_s + b.runtime_s}


# ---------------------------------------------------------------------------- calibration
def calibrate_cohesion(ucs_of, target_ucs: float, c0: float, rel_tol=0.02, max_runs=8,
                       progress=None) -> dict:
    """Flaw cohesion giving ``target_ucs`` (Pa): secant steps, bisection once bracketed.

    ``ucs_of(c) -> float`` runs the compression test with flaw cohesion c (Pa). The UCS of a
    Voronoi specimen grows with c (thesis fig. 3.9) but not strictly linearly, and is flat
    where tension failure governs: once bracketed, regula falsi with the Illinois weighting.
    If an unbracketed step that changed c by more than 1.5 x changes the UCS by less than half
    the tolerance, the target is out of the reach of c (e.g. below the strength of the fully broken, interlocked assembly): the
    search stops with ``converged=False`` and the closest run.

    Returns dict(cohesion, ucs, converged, history=[(c, ucs), ...]).
    """
    if not (target_ucs > 0 and c0 > 0):
        raise ValueError(f"target UCS and start cohesion must be > 0, got {target_ucs!r}, {c0!r}")
    hist = []

    def f(c):
        u = float(ucs_of(c))
        hist.append((c, u))
        if progress:
            progress(f"calibration: c = {c / 1e6:.4g} MPa -> UCS {u / 1e6:.4g} MPa")
        return u - target_ucs

    def done(g):
        return abs(g) <= rel_tol * target_ucs

    a, fa = c0, f(c0)
    if done(fa):
        return _cal(a, hist, True)
    # second point: proportional guess (UCS roughly proportional to c near the target)
    b = max(a * target_ucs / (fa + target_ucs), 1e-3 * a)
    fb = f(b)
    side = 0
    while len(hist) < max_runs and not done(fb):
        if fa * fb < 0:            # bracketed: Illinois regula falsi
            c = b - fb * (b - a) / (fb - fa)
            fc = f(c)
            if fc * fb < 0:
                a, fa = b, fb
                side = 0
            else:
                fa = 0.5 * fa if side == -1 else fa
                side = -1
            b, fb = c, fc
        else:                      # not bracketed: secant (extrapolating), kept positive
            if abs(fb - fa) < 0.5 * rel_tol * target_ucs and max(a, b) > 1.5 * min(a, b):
                break              # the UCS no longer responds to c: the target is out of reach
            slope = (fb - fa) / (b - a) if b != a else 0.0
            c = b - fb / slope if slope > 0 else b * (1.5 if fb < 0 else 0.67)
            c = min(max(c, 0.25 * b), 4.0 * b)
            a, fa = b, fb
            b, fb = c, f(c)
    return _cal(b if done(fb) else min(hist, key=lambda h: abs(h[1] - target_ucs))[0],
                hist, done(fb))


def _cal(c, hist, converged):
    ucs = dict(hist)[c]
    return {"cohesion": float(c), "ucs": float(ucs), "converged": bool(converged),
            "history": [(float(a), float(b)) for a, b in hist]}


def _nu2d_of_ratio(r):
    return (1 - r) / (3 + r)


def _ratio_of_nu2d(nu2):
    if not -1.0 < nu2 < 1.0 / 3.0:
        raise ValueError(f"a rigid-block lattice has nu_2d in (-1, 1/3); target {nu2!r} is not "
                         "reachable")
    return (1 - 3 * nu2) / (1 + nu2)


def stiffness_for_moduli(E: float, nu: float, mean_block_area: float, block_E=None,
                         block_nu=0.25) -> dict:
    """Contact kn, ks (Pa/m) giving an assembly of plane-strain modulus E (Pa) and Poisson's
    ratio nu, by inverting ``dem_core.contact.elastic.lattice_moduli`` (regular hexagon lattice of the
    same mean block area).

    With deformable blocks (``block_E``), the block compliance in series (centroid-to-edge
    distance h = d/2 on each side, ``dem_core.contact.elastic.series_stiffness``) is removed from the
    lattice's contact compliance; ValueError if the blocks alone are softer than the target.
    """
    if not (E > 0 and mean_block_area > 0):
        raise ValueError(f"need E > 0 and a block area > 0, got {E!r}, {mean_block_area!r}")
    nu2 = nu / (1 - nu)                        # inverse of nu = nu_2d / (1 + nu_2d)
    E2 = E / (1 - nu * nu)
    r = _ratio_of_nu2d(nu2)
    d = spacing_from_area(mean_block_area)
    kn_eff = E2 * (3 + r) / (2 * d * (1 + r))   # E_2d = 2 d kn (kn + ks)/(3 kn + ks)
    ks_eff = r * kn_eff
    if block_E is None:
        return {"kn": kn_eff, "ks": ks_eff, "d": d}
    h = 0.5 * d
    Ep = block_E / (1 - block_nu ** 2)
    G = block_E / (2 * (1 + block_nu))
    cn = 1.0 / kn_eff - 2 * h / Ep
    cs = 1.0 / ks_eff - 2 * h / G
    if cn <= 0 or cs <= 0:
        raise ValueError(f"blocks of E = {block_E:.3g} Pa are softer than the target assembly "
                         f"E = {E:.3g} Pa at block size d = {d:.3g} m: no contact stiffness fits")
    return {"kn": 1.0 / cn, "ks": 1.0 / cs, "d": d}


def calibrate_stiffness(measure, E: float, nu: float, kn0: float, ks0: float, rel_tol=0.03,
                        max_runs=5, progress=None) -> dict:
    """Correct kn, ks until the measured moduli match E and nu (plane strain).

    ``measure(kn, ks) -> (E, nu)`` runs an elastic compression test. Each iteration scales
    kn and ks by E / E_measured (the modulus is proportional to the contact stiffness for rigid
    blocks) and shifts ks/kn by the lattice relation so that the measured nu moves by the
    missing amount. Returns dict(kn, ks, E, nu, converged, history).
    """
    kn, ks = float(kn0), float(ks0)
    hist = []
    for _ in range(max_runs):
        Em, num = measure(kn, ks)
        hist.append((kn, ks, Em, num))
        if progress:
            progress(f"stiffness: kn {kn:.3g}, ks {ks:.3g} -> E {Em:.3g} Pa, nu {num:.3f}")
        ok = abs(Em - E) <= rel_tol * E and abs(num - nu) <= max(0.02, rel_tol * abs(nu))
        if ok:
            return {"kn": kn, "ks": ks, "E": Em, "nu": num, "converged": True, "history": hist}
        r = ks / kn
        nu2_m, nu2_t = num / (1 - num), nu / (1 - nu)
        r_new = _ratio_of_nu2d(min(max(_nu2d_of_ratio(r) + (nu2_t - nu2_m), -0.9), 0.33))
        scale = E / Em
        # keep E fixed while changing the ratio: E_2d is proportional to kn (1 + r) / (3 + r)
        ratio_fix = ((1 + r) / (3 + r)) / ((1 + r_new) / (3 + r_new))
        kn = kn * scale * ratio_fix
        ks = r_new * kn
    Em, num = hist[-1][2], hist[-1][3]
    return {"kn": hist[-1][0], "ks": hist[-1][1], "E": Em, "nu": num, "converged": False,
            "history": hist}

