"""Hoek-Brown rock-mass parameters as plain numpy (no DOLFINx).

Conventions
-----------
Stresses are **compression positive** here, as in the Hoek-Brown papers: sigma1 >= sigma3 are the
major and minor principal stresses. All strength functions work in any consistent stress unit
(pass sci in Pa and you get Pa back). Moduli are in Pa (the published formulas are in GPa and
MPa; the conversion is done here once). Angles are returned in degrees.

References
----------
Hoek, E., Carranza-Torres, C., Corkum, B. (2002). Hoek-Brown failure criterion - 2002 edition.
Proc. NARMS-TAC, Toronto. (Eqs for mb, s, a, sc, st, scm, the equivalent c and phi and the
sigma3max rule for slopes.)
Hoek, E., Diederichs, M. S. (2006) is NOT used; Em follows the 2002 paper.
Hoek, E., Brown, E. T. (1988). The Hoek-Brown failure criterion - a 1988 update. (RMR-based m, s
for undisturbed and disturbed rock.) Serafim, J. L., Pereira, J. P. (1983) for
Em = 10^((RMR-10)/40) GPa. Alzo'ubi (2009), thesis eqs 2.1-2.6 and Tables 6.1, 6.2.
"""
from dataclasses import dataclass

import numpy as np

__all__ = [
    "HoekBrownParameters", "parameters", "parameters_rmr1988", "major_principal_stress",
    "uniaxial_compressive_strength", "tensile_strength", "global_strength",
    "sigma3_max_slope", "sigma3_max_tunnel", "equivalent_mohr_coulomb",
    "modulus_hoek2002", "modulus_rmr", "bulk_and_shear_modulus",
]


@dataclass(frozen=True)
class HoekBrownParameters:
    """Generalized Hoek-Brown constants of a rock mass.

    Attributes
    ----------
    mb : float
        Reduced value of the material constant mi (-).
    s : float
        Rock-mass constant, 1 for intact rock (-).
    a : float
        Exponent, 0.5 for the original (1988) criterion (-).
    """

    mb: float
    s: float
    a: float

    def __iter__(self):
        return iter((self.mb, self.s, self.a))


def _check_range(name, value, low, high):
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)) or np.any(arr < low) or np.any(arr > high):
        raise ValueError(f"{name}={value!r} must be finite and within [{low}, {high}]")


def _check_positive(name, value):
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ValueError(f"{name}={value!r} must be finite and > 0")


def parameters(gsi, mi, D=0.0):
    """Hoek et al. (2002) eqs 2-4 (thesis eqs 2.2-2.4): mb, s and a from GSI, mi and D.

    mb = mi exp((GSI-100)/(28-14D)), s = exp((GSI-100)/(9-3D)),
    a = 1/2 + (exp(-GSI/15) - exp(-20/3))/6.

    Parameters
    ----------
    gsi : float
        Geological Strength Index, 0..100.
    mi : float
        Intact-rock material constant (> 0).
    D : float
        Disturbance factor, 0 (undisturbed) .. 1 (very disturbed).

    Returns
    -------
    HoekBrownParameters
        (mb, s, a); unpacks as a tuple.
    """
    _check_range("gsi", gsi, 0.0, 100.0)
    _check_positive("mi", mi)
    _check_range("D", D, 0.0, 1.0)
    mb = mi * np.exp((gsi - 100.0) / (28.0 - 14.0 * D))
    s = np.exp((gsi - 100.0) / (9.0 - 3.0 * D))
    a = 0.5 + (np.exp(-gsi / 15.0) - np.exp(-20.0 / 3.0)) / 6.0
    return HoekBrownParameters(float(mb), float(s), float(a))


def parameters_rmr1988(rmr, mi, disturbed):
    """Hoek and Brown (1988) m and s from RMR (Bieniawski 1976), with a = 1/2.

    Undisturbed: m = mi exp((RMR-100)/28), s = exp((RMR-100)/9).
    Disturbed:   m = mi exp((RMR-100)/14), s = exp((RMR-100)/6)  (thesis Table 6.1).
    """
    _check_range("rmr", rmr, 0.0, 100.0)
    _check_positive("mi", mi)
    dm, ds = (14.0, 6.0) if disturbed else (28.0, 9.0)
    return HoekBrownParameters(float(mi * np.exp((rmr - 100.0) / dm)),
                               float(np.exp((rmr - 100.0) / ds)), 0.5)


def major_principal_stress(sigma3, sci, mb, s, a):
    """Thesis eq 2.1: sigma1 = sigma3 + sci (mb sigma3/sci + s)^a (compression positive).

    Raises for sigma3 below the tensile strength (where the bracket is negative).
    """
    _check_positive("sci", sci)
    base = mb * np.asarray(sigma3, dtype=float) / sci + s
    if np.any(base < -1e-14):
        raise ValueError(f"sigma3={sigma3!r} is below the Hoek-Brown tensile strength "
                         f"{tensile_strength(sci, mb, s)!r}")
    return sigma3 + sci * np.maximum(base, 0.0) ** a


def uniaxial_compressive_strength(sci, s, a):
    """Rock-mass uniaxial compressive strength sc = sci s^a (thesis eq 2.5)."""
    _check_positive("sci", sci)
    return sci * s ** a


def tensile_strength(sci, mb, s):
    """Rock-mass tensile strength st = -s sci / mb (thesis eq 2.6; negative = tension)."""
    _check_positive("sci", sci)
    _check_positive("mb", mb)
    return -s * sci / mb


def global_strength(sci, mb, s, a):
    """Hoek et al. (2002) eq 18: global rock-mass strength scm.

    scm = sci (mb + 4s - a(mb - 8s)) (mb/4 + s)^(a-1) / (2 (1+a)(2+a)).
    """
    _check_positive("sci", sci)
    return (sci * (mb + 4.0 * s - a * (mb - 8.0 * s)) * (mb / 4.0 + s) ** (a - 1.0)
            / (2.0 * (1.0 + a) * (2.0 + a)))


def sigma3_max_slope(scm, unit_weight, height):
    """Hoek et al. (2002) eq 20 for slopes: s3max = 0.72 scm (scm / (gamma H))^-0.91.

    Parameters
    ----------
    scm : float
        Global rock-mass strength (Pa).
    unit_weight : float
        gamma = rho g (N/m3).
    height : float
        Slope height H (m).
    """
    _check_positive("scm", scm)
    _check_positive("unit_weight", unit_weight)
    _check_positive("height", height)
    return 0.72 * scm * (scm / (unit_weight * height)) ** -0.91


def sigma3_max_tunnel(scm, unit_weight, depth):
    """Hoek et al. (2002) eq 19 for deep tunnels: s3max = 0.47 scm (scm / (gamma H))^-0.94."""
    _check_positive("scm", scm)
    _check_positive("unit_weight", unit_weight)
    _check_positive("depth", depth)
    return 0.47 * scm * (scm / (unit_weight * depth)) ** -0.94


def equivalent_mohr_coulomb(sci, mb, s, a, sigma3_max):
    """Hoek et al. (2002) eqs 13-14: c' and phi' fitted over st < sigma3 < sigma3_max.

    With s3n = sigma3_max / sci and q = 6 a mb (s + mb s3n)^(a-1):
    phi' = asin(q / (2 (1+a)(2+a) + q)),
    c' = sci ((1+2a) s + (1-a) mb s3n) (s + mb s3n)^(a-1) / ((1+a)(2+a) sqrt(1 + q/((1+a)(2+a)))).

    Returns
    -------
    (c, phi_deg) : tuple of float
        Cohesion in the unit of sci, friction angle in degrees.
    """
    _check_positive("sci", sci)
    _check_positive("sigma3_max", sigma3_max)
    s3n = sigma3_max / sci
    base = (s + mb * s3n) ** (a - 1.0)
    q = 6.0 * a * mb * base
    k = (1.0 + a) * (2.0 + a)
    phi = np.degrees(np.arcsin(q / (2.0 * k + q)))
    c = sci * ((1.0 + 2.0 * a) * s + (1.0 - a) * mb * s3n) * base / (k * np.sqrt(1.0 + q / k))
    return float(c), float(phi)


def modulus_hoek2002(gsi, sci, D=0.0):
    """Hoek et al. (2002) eqs 21-22: rock-mass modulus Em in Pa.

    Em [GPa] = (1 - D/2) sqrt(sci[MPa]/100) 10^((GSI-10)/40) for sci <= 100 MPa,
    and (1 - D/2) 10^((GSI-10)/40) above.

    Parameters
    ----------
    sci : float
        Intact uniaxial compressive strength in Pa.
    """
    _check_range("gsi", gsi, 0.0, 100.0)
    _check_positive("sci", sci)
    _check_range("D", D, 0.0, 1.0)
    root = np.sqrt(min(sci / 100e6, 1.0))
    return float((1.0 - D / 2.0) * root * 10.0 ** ((gsi - 10.0) / 40.0) * 1e9)


def modulus_rmr(rmr):
    """Serafim and Pereira (1983), thesis eq 6.2: Em = 10^((RMR-10)/40) GPa, returned in Pa."""
    _check_range("rmr", rmr, 0.0, 100.0)
    return 10.0 ** ((np.asarray(rmr, dtype=float) - 10.0) / 40.0) * 1e9


def bulk_and_shear_modulus(E, nu):
    """Isotropic K = E / (3 (1 - 2 nu)) and G = E / (2 (1 + nu)), same unit as E."""
    _check_positive("E", E)
    _check_range("nu", nu, -0.999, 0.499999)
    return E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))
