"""Mohr-Coulomb zones with a tension cut-off (plastic deformable blocks): the strength table
and the return of one zone's stress to the yield surface.

Stress **tension positive** (the zones' convention). s1 >= s3 are the zone's in-plane principal
stresses (s1 the most tensile); the out-of-plane stress szz is not one of them: it is carried
elastically, szz = lam (exx_e + eyy_e), and the plastic strain has no out-of-plane part
(``Zones.plastic[:, 3]``, ezz_p, stays 0 with this return; the column is there for a return
that treats szz as a principal stress, as FLAC's does). Perfectly plastic (no softening):

    shear     f_s = N_phi s1 - s3 - 2 c sqrt(N_phi) <= 0,   N_phi = (1 + sin phi) / (1 - sin phi)
    tension   f_t = s1 - T <= 0,                            T <= c / tan(phi) (the apex)

i.e. in compression magnitudes sigma_1 = N_phi sigma_3 + UCS, UCS = 2 c cos phi / (1 - sin phi)
(plane strain, szz left out). Flow is non-associated in shear, potential g_s = N_psi s1 - s3
(dilation angle psi), associated in tension (g_t = s1):

    d eps_p (principal 1, 3) = l_s (N_psi, -1) + l_t (1, 0),   l_s, l_t >= 0

With a1 = lam + 2 mu, a2 = lam the in-plane elastic law s = a1 e1 + a2 e3 (and 1 <-> 3),
an elastic trial (s1, s3) outside the surface returns, in the frame of its principal axes
(which the return keeps), to one of four places (each a linear 1- or 2-unknown solve):

    shear       l_s = f_s / (a1 (1 + N_phi N_psi) - a2 (N_phi + N_psi)), if then s1 <= T
    tension     l_t = f_t / a1, s1 = T, s3 -= l_t a2, if then f_s <= 0 and s3 <= T
    corner      s1 = T, s3 = N_phi T - 2 c sqrt(N_phi) (both surfaces)
    two-way     s1 = s3 = T (biaxial tension: the cut-off on both principal stresses)

These tile the outside of the surface in the (s1, s3) half-plane (the return directions of
the two surfaces both point out of both). Reference: de Souza Neto, Peric & Owen,
Computational Methods for Plasticity (2008), ch. 8.2 (Mohr-Coulomb return in principal
stresses); Itasca FLAC theory manual, "Mohr-Coulomb model" (shear and tension regions,
tension cut-off, the T cap at the apex).

The strength table, one row per zone: cohesion c (Pa; +inf: an elastic zone, which skips the
return), friction angle phi (deg, in [0, 90)), dilation angle psi (deg, in [0, phi]),
tensile strength T (Pa, >= 0, stored capped at c / tan phi).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._moved import renamed

__all__ = ["strength_table", "elastic_table", "mohr_coulomb", "new_keys", "SHEAR", "TENSION",
           "SHEAR_PAST", "TENSION_PAST"]

# ``yielded`` bits: failing now (this step), or at some step before
SHEAR, TENSION, SHEAR_PAST, TENSION_PAST = 1, 2, 4, 8
KEYS = ("cohesion", "friction", "dilation", "tensile_strength")
# keys of a strength dict that were renamed, accepted with a DeprecationWarning for one release
OLD_KEYS = {"tensile": "tensile_strength"}


def new_keys(row: dict, where="strength") -> dict:
    """``row`` (a strength dict) with each old key (``OLD_KEYS``) renamed to its new one, with a
    DeprecationWarning naming the new key; ValueError when both spellings are given."""
    return renamed(row, OLD_KEYS, where, "key", ValueError)


def elastic_table(nz):
    """(nz, 4): every zone elastic (c = +inf)."""
    return np.tile(np.array([np.inf, 0.0, 0.0, np.inf]), (nz, 1))


def strength_table(strength, nz, where="strength"):
    """The (nz, 4) table [c Pa, phi deg, psi deg, T Pa] (module docstring) of ``strength``:
    None (elastic), a dict(cohesion=, friction=, dilation=0, tensile_strength=+inf) of scalars
    or (nz,) arrays, or a (4,) or (nz, 4) table. ValueError names a bad value; T is capped at
    c / tan phi. The old key ``tensile`` is still read, with a DeprecationWarning."""
    if strength is None:
        return elastic_table(nz)
    if isinstance(strength, dict):
        strength = new_keys(strength, where)
        unknown = set(strength) - set(KEYS)
        missing = {"cohesion", "friction"} - set(strength)
        if unknown or missing:
            raise ValueError(f"{where}: keys are cohesion (Pa), friction (deg), dilation (deg, "
                             f"default 0), tensile_strength (Pa, default the apex c / tan phi); "
                             f"got unknown {sorted(unknown)}, missing {sorted(missing)}")
        cols = [strength.get(k, d) for k, d in zip(KEYS, (None, None, 0.0, np.inf))]
    else:
        arr = np.asarray(strength, float)
        if arr.shape not in ((4,), (nz, 4)):
            raise ValueError(f"{where}: a table must be (4,) or ({nz}, 4) [c, phi, psi, T], "
                             f"got shape {arr.shape}")
        cols = list(np.broadcast_to(arr, (nz, 4)).T)
    try:
        c, phi, psi, T = (np.array(np.broadcast_to(np.asarray(v, float), (nz,))) for v in cols)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: values must be numbers (or one per zone, {nz}), got "
                         f"{strength!r}") from None
    checks = (("cohesion", c, ~np.isnan(c) & (c >= 0), "must be >= 0 Pa (+inf: elastic)"),
              ("friction", phi, (phi >= 0) & (phi < 90), "must be in [0, 90) deg"),
              ("dilation", psi, (psi >= 0) & (psi <= phi), "must be in [0, friction] deg"),
              ("tensile_strength", T, ~np.isnan(T) & (T >= 0), "must be >= 0 Pa"))
    for name, v, ok, rule in checks:
        if not np.all(ok):
            raise ValueError(f"{where}: {name} {rule}, got {v[~ok][0]!r}")
    with np.errstate(divide="ignore"):
        apex = np.where(phi > 0, c / np.tan(np.radians(phi)), np.inf)
    T = np.minimum(T, apex)
    elastic = np.isinf(c)
    return np.column_stack([c, np.where(elastic, 0.0, phi), np.where(elastic, 0.0, psi),
                            np.where(elastic, np.inf, T)])


@njit(cache=True, inline="always")
def _principal_return(s1, s3, a1, a2, nphi, k, npsi, T):
    """(s1, s3, de1, de3, mode) after the return of the trial (s1 >= s3) (module docstring);
    mode 0 elastic, else the bits SHEAR | TENSION of the active surfaces."""
    fs = nphi * s1 - s3 - k
    ft = s1 - T
    if fs <= 0.0 and ft <= 0.0:
        return s1, s3, 0.0, 0.0, 0
    rs1, rs3 = a1 * npsi - a2, a2 * npsi - a1          # D dg_s/ds: the shear return direction
    if fs > 0.0:
        ls = fs / (nphi * rs1 - rs3)
        if s1 - ls * rs1 <= T:
            return s1 - ls * rs1, s3 - ls * rs3, ls * npsi, -ls, SHEAR
    det = a1 * a1 - a2 * a2
    if ft > 0.0:
        lt = ft / a1
        t3 = s3 - lt * a2
        if t3 > T:                                      # both principal stresses cut off
            l1 = (a1 * (s1 - T) - a2 * (s3 - T)) / det
            l3 = (a1 * (s3 - T) - a2 * (s1 - T)) / det
            return T, T, l1, l3, TENSION
        if nphi * T - t3 - k <= 0.0:
            return T, t3, lt, 0.0, TENSION
    s3c = nphi * T - k                                  # the corner of shear and tension
    ls = (a2 * (s1 - T) - a1 * (s3 - s3c)) / det
    lt = (rs1 * (s3 - s3c) - rs3 * (s1 - T)) / det
    return T, s3c, ls * npsi + lt, -ls, SHEAR | TENSION


@njit(cache=True, inline="always")
def mohr_coulomb(sxx, syy, sxy, lam, mu, c, phi, psi, T):
    """One zone's trial stress (Pa, tension +, any in-plane axes) returned to the Mohr-Coulomb
    surface with tension cut-off (module docstring; c, T Pa, phi, psi deg): (sxx, syy, sxy,
    dexx_p, deyy_p, dgxy_p, mode), the plastic strain increment in the same axes (gxy
    engineering shear) and mode (0: elastic, else SHEAR | TENSION bits). Principal axes kept."""
    m = 0.5 * (sxx + syy)
    d = 0.5 * (sxx - syy)
    r = math.sqrt(d * d + sxy * sxy)
    sp, cp = math.sin(math.radians(phi)), math.cos(math.radians(phi))
    spsi = math.sin(math.radians(psi))
    nphi = (1.0 + sp) / (1.0 - sp)
    k = 2.0 * c * cp / (1.0 - sp)                       # 2 c sqrt(N_phi)
    npsi = (1.0 + spsi) / (1.0 - spsi)
    s1, s3, e1, e3, mode = _principal_return(m + r, m - r, lam + 2.0 * mu, lam, nphi, k, npsi, T)
    if mode == 0:
        return sxx, syy, sxy, 0.0, 0.0, 0.0, 0
    c2, s2 = (d / r, sxy / r) if r > 0.0 else (1.0, 0.0)     # cos, sin of twice the s1 axis
    m1, r1 = 0.5 * (s1 + s3), 0.5 * (s1 - s3)
    em, er = 0.5 * (e1 + e3), 0.5 * (e1 - e3)
    return (m1 + r1 * c2, m1 - r1 * c2, r1 * s2, em + er * c2, em - er * c2, 2.0 * er * s2,
            mode)


@njit(cache=True, inline="always")
def yield_zone(strength, plastic, yielded, e, sxx, syy, sxy, lam, mu):
    """Zone e's trial stress (its co-rotated frame) returned to its strength ``strength[e]``;
    its plastic strain ``plastic[e]`` and ``yielded[e]`` bits updated. The new stress. (The
    arrays, not the zones' bundle: an inlined helper taking the bundle costs its reference
    counts at every zone and step, which made Mohr-Coulomb zones 3.3x slower than elastic.)"""
    sxx, syy, sxy, dxx, dyy, dxy, mode = mohr_coulomb(
        sxx, syy, sxy, lam, mu, strength[e, 0], strength[e, 1], strength[e, 2],
        strength[e, 3])
    past = yielded[e] | ((yielded[e] & (SHEAR | TENSION)) << 2)
    yielded[e] = (past & (SHEAR_PAST | TENSION_PAST)) | mode
    if mode:
        plastic[e, 0] += dxx
        plastic[e, 1] += dyy
        plastic[e, 2] += dxy
    return sxx, syy, sxy
