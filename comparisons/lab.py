"""Virtual rock-mechanics lab on DEM specimens: compression, tension, direct shear, calibration.

Every test drives rigid loading parts (platens, shear-box halves; groups of a ``Model``) and
reads the force the specimen exerts on them (``contact_force``). Conventions: SI units;
compressive stress and strain positive; shear stress positive in the direction the lower box
moves (+x), read on the stationary box. Strains are platen displacement over specimen
height; the lateral strain of the compression test is the change of distance between the
specimen's two side faces over the width (expansion positive), so Poisson's ratio = lateral /
axial.

The moduli measured on a 2D assembly are the 2D (plane) values ``E_2d``, ``nu_2d``; their
plane-strain equivalents are ``nu = nu_2d / (1 + nu_2d)``, ``E = E_2d (1 - nu^2)``
(``dem_core.elastic``).

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

from dem_core.elastic import spacing_from_area
from dem_core.model import Model

__all__ = ["LabCurve", "contact_force", "compression_test", "tension_test", "direct_shear",
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


def _mean_x(model, idx):
    return float(model.state.pos[idx, 0].mean())


def compression_test(model: Model, width: float, height: float, rate: float,
                     left=None, right=None, max_strain=0.05, post_peak=0.7, chunk=200,
                     keep_model=False) -> LabCurve:
    """Unconfined compression between ``platen_bottom`` (fixed) and ``platen_top`` (moving
    down at ``rate`` m/step, no rotation, no sideways motion).

    Parameters
    ----------
    model : Model with groups "platen_bottom", "platen_top".
    width, height : float, m. Specimen size (stress = force / width, strain = shortening / height).
    rate : float, m per time step.
    left, right : index arrays of side blocks for the lateral strain (optional).
    max_strain : stop at this axial strain.
    post_peak : stop once the stress has fallen below this fraction of the peak.
    chunk : steps between records.
    """
    t0 = time.perf_counter()
    m = model
    m.fix("platen_bottom")
    top = m.group("platen_top")
    bot = m.group("platen_bottom")
    y0 = float(m.state.pos[top, 1].mean())
    w0 = None if left is None else _mean_x(m, right) - _mean_x(m, left)
    strain, stress, lateral, times = [0.0], [0.0], [0.0], [m.time]
    while True:
        m.set_velocity("platen_top", vx=0.0, vy=-rate / m.dt)   # dt may change after searches
        m.cycle(chunk)
        f_top, f_bot = contact_force(m, top), contact_force(m, bot)
        times.append(m.time)
        strain.append((y0 - float(m.state.pos[top, 1].mean())) / height)
        stress.append(0.5 * (f_top[1] - f_bot[1]) / width)
        if w0 is not None:
            lateral.append(((_mean_x(m, right) - _mean_x(m, left)) - w0) / width)
        else:
            lateral.append(0.0)
        peak = max(stress)
        if strain[-1] > max_strain or (stress[-1] < post_peak * peak and peak > 0):
            break
    return _curve(strain, stress, times, lateral, m, t0, keep_model)


def tension_test(model: Model, width: float, height: float, rate: float, max_strain=0.02,
                 post_peak=0.5, chunk=200, keep_model=False) -> LabCurve:
    """Direct tension: glued platens, ``platen_top`` pulled up at ``rate`` m/step.

    Returns tensile strain and tensile stress (both positive in tension).
    """
    t0 = time.perf_counter()
    m = model
    m.fix("platen_bottom")
    top, bot = m.group("platen_top"), m.group("platen_bottom")
    y0 = float(m.state.pos[top, 1].mean())
    strain, stress, times = [0.0], [0.0], [m.time]
    while True:
        m.set_velocity("platen_top", vx=0.0, vy=rate / m.dt)
        m.cycle(chunk)
        f_top, f_bot = contact_force(m, top), contact_force(m, bot)
        times.append(m.time)
        strain.append((float(m.state.pos[top, 1].mean()) - y0) / height)
        stress.append(0.5 * (f_bot[1] - f_top[1]) / width)
        peak = max(stress)
        if strain[-1] > max_strain or (stress[-1] < post_peak * peak and peak > 0):
            break
    return _curve(strain, stress, times, np.zeros(len(strain)), m, t0, keep_model)


def direct_shear(model: Model, length: float, normal_stress: float, rate: float,
                 max_displacement: float, post_peak=0.8, chunk=200, settle_tol=0.02,
                 max_settle_steps=40_000, keep_model=False) -> LabCurve:
    """Direct shear at constant normal stress.

    ``box_up`` is held in x and rotation and servo-controlled in y to press on the specimen
    with ``normal_stress x length`` (N/m); once the normal load is reached (within
    ``settle_tol``), ``box_low`` moves in +x at ``rate`` m/step. Stops at
    ``max_displacement`` or when the shear stress has fallen below ``post_peak`` x peak after
    at least 1.5 x the displacement at peak.

    Returns shear displacement (m), shear stress (Pa, x-force on the stationary upper box over
    ``length``) and the normal stress measured on the upper box (Pa).

    The shear force is read on the stationary half, like a load cell on the reaction side: the
    force on the moving half also holds what accelerates the lower half of the specimen when
    the box starts (times 1 / (1 - damping) with local damping), a start-up transient of up to
    +45 % of the friction line at sn = 0.3 MPa in the fully jointed (k = 1) specimen.
    """
    t0 = time.perf_counter()
    m = model
    if not (normal_stress >= 0 and math.isfinite(normal_stress)):
        raise ValueError(f"normal stress must be finite and >= 0 Pa, got {normal_stress!r}")
    up, low = m.group("box_up"), m.group("box_low")
    m.fix(low)
    m.set_velocity(up, vx=0.0, vy=None, omega=0.0)
    target = normal_stress * length
    v_shear = rate / m.dt
    m.servo(up, target, direction=(0.0, -1.0), v_max=20.0 * v_shear)
    steps = 0
    while steps < max_settle_steps:        # consolidate under the normal load
        m.cycle(chunk)
        steps += chunk
        fy = contact_force(m, up)[1]
        if abs(fy - target) <= settle_tol * max(target, 1.0) and m.unbalanced_ratio() < 1e-3:
            break
    x0 = float(m.state.pos[low, 0].mean())
    disp, tau, sn, times = [0.0], [0.0], [contact_force(m, up)[1] / length], [m.time]
    while True:
        m.set_velocity(low, vx=rate / m.dt, vy=0.0, omega=0.0)
        m.cycle(chunk)
        f_up = contact_force(m, up)
        times.append(m.time)
        disp.append(float(m.state.pos[low, 0].mean()) - x0)
        tau.append(f_up[0] / length)
        sn.append(f_up[1] / length)
        i = int(np.argmax(tau))
        if disp[-1] >= max_displacement:
            break
        if tau[i] > 0 and tau[-1] < post_peak * tau[i] and disp[-1] > 1.5 * disp[i]:
            break
    return _curve(disp, tau, times, sn, m, t0, keep_model)


def _curve(x, y, times, lateral, m, t0, keep_model) -> LabCurve:
    x, y, lateral = np.asarray(x), np.asarray(y), np.asarray(lateral)
    i = int(np.argmax(y))
    return LabCurve(x=x, y=y, time=np.asarray(times), lateral=lateral, peak=float(y[i]),
                    x_at_peak=float(x[i]), steps=int(m.step), runtime_s=time.perf_counter() - t0, dt=float(m.dt),
                    n_blocks=int(m.n_blocks), cracks=m.crack_counts(),
                    model=m if keep_model else None)


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
    ratio nu, by inverting ``dem_core.elastic.lattice_moduli`` (regular hexagon lattice of the
    same mean block area).

    With deformable blocks (``block_E``), the block compliance in series (centroid-to-edge
    distance h = d/2 on each side, ``dem_core.elastic.series_stiffness``) is removed from the
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

