"""Material descriptions for the continuum model (plain dataclasses, no DOLFINx).

Units: Pa for moduli and strengths, degrees for angles, kg/m3 for density.
Strength parameters follow the rock-mechanics convention (compression positive); the tensile
strength is given as a positive number (the magnitude of the tensile stress at failure).
"""
import math
from dataclasses import dataclass, replace

import numpy as np

from . import hoek_brown as hb

__all__ = ["Elastic", "MohrCoulomb", "HoekBrown", "lame", "davis_factor"]


def _positive(name, value):
    if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value) and value > 0):
        raise ValueError(f"{name}={value!r} must be a finite number > 0")


def _elastic_check(E, nu):
    _positive("E", E)
    if not (math.isfinite(nu) and -1.0 < nu < 0.5):
        raise ValueError(f"nu={nu!r} must be in (-1, 0.5)")


def lame(E, nu):
    """Lame constants (lambda, G) of an isotropic solid, in the unit of E."""
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def davis_factor(friction, dilation):
    """Davis (1968) strength factor beta = cos(psi) cos(phi) / (1 - sin(psi) sin(phi)).

    Angles in degrees, 0 <= psi <= phi < 90; beta = 1 for associated flow (psi = phi) and
    cos(phi) for psi = 0. Reference: Davis, E. H. (1968), Theories of plasticity and the
    failure of soil masses, in Lee (ed.), Soil Mechanics: Selected Topics, Butterworths.
    """
    phi, psi = math.radians(friction), math.radians(dilation)
    return math.cos(psi) * math.cos(phi) / (1.0 - math.sin(psi) * math.sin(phi))


@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elastic solid: Young's modulus E (Pa), Poisson's ratio nu."""

    E: float
    nu: float

    def __post_init__(self):
        _elastic_check(self.E, self.nu)


@dataclass(frozen=True)
class MohrCoulomb:
    """Perfectly plastic Mohr-Coulomb solid with an optional tension cut-off (Rankine).

    f = s1 - Kphi s3 - 2 c sqrt(Kphi) <= 0 with Kphi = (1 + sin phi)/(1 - sin phi), s1 >= s3
    principal stresses, compression positive; cut-off: -s_i <= tensile_strength for every i.

    Attributes
    ----------
    E, nu : float
        Elastic constants (Pa, -).
    cohesion : float
        c (Pa), > 0.
    friction : float
        phi in degrees, 0 <= phi < 90.
    dilation : float or None
        psi in degrees (0 <= psi <= phi); None means associated flow (psi = phi).
    tensile_strength : float or None
        Cut-off T >= 0 in Pa (tension magnitude); None for no cut-off. A value above the
        Mohr-Coulomb apex c / tan(phi) is inactive.
    """

    E: float
    nu: float
    cohesion: float
    friction: float
    dilation: float = None
    tensile_strength: float = None

    def __post_init__(self):
        _elastic_check(self.E, self.nu)
        _positive("cohesion", self.cohesion)
        if not (math.isfinite(self.friction) and 0.0 <= self.friction < 90.0):
            raise ValueError(f"friction={self.friction!r} must be in [0, 90) degrees")
        if self.dilation is not None and not (0.0 <= self.dilation <= self.friction):
            raise ValueError(f"dilation={self.dilation!r} must be in [0, friction={self.friction}]")
        if self.tensile_strength is not None and not (
                math.isfinite(self.tensile_strength) and self.tensile_strength >= 0.0):
            raise ValueError(f"tensile_strength={self.tensile_strength!r} must be >= 0 or None")

    @property
    def psi(self):
        """Dilation angle in degrees (phi when associated)."""
        return self.friction if self.dilation is None else self.dilation

    def reduced(self, factor):
        """Strength reduced by a factor F (shear strength reduction).

        Convention: c/F, tan(phi)/F, tan(psi)/F (psi kept <= phi) and tensile_strength/F.
        """
        _positive("factor", factor)
        phi = math.degrees(math.atan(math.tan(math.radians(self.friction)) / factor))
        psi = None if self.dilation is None else min(
            phi, math.degrees(math.atan(math.tan(math.radians(self.dilation)) / factor)))
        t = None if self.tensile_strength is None else self.tensile_strength / factor
        return replace(self, cohesion=self.cohesion / factor, friction=phi, dilation=psi,
                       tensile_strength=t)

    def davis(self):
        """The associated material of Davis (1968) for this non-associated one.

        c* = beta c, tan(phi*) = beta tan(phi), psi* = phi* (associated), beta =
        `davis_factor(phi, psi)`; the tension cut-off is kept (the apex c* cot(phi*) =
        c cot(phi) does not move). Along a velocity discontinuity (a thin shear band) of a
        psi < phi material, shear and normal stress obey tau = c* + sigma tan(phi*), so the
        collapse load of mechanisms of rigid blocks is the associated one with (c*, phi*)
        (Drescher & Detournay 1993, Geotechnique 43(3)); elsewhere it is an approximation,
        on the safe side. An associated material is returned unchanged.
        """
        if self.dilation is None or self.dilation == self.friction:
            return replace(self, dilation=None)
        beta = davis_factor(self.friction, self.dilation)
        phi = math.degrees(math.atan(beta * math.tan(math.radians(self.friction))))
        return replace(self, cohesion=beta * self.cohesion, friction=phi, dilation=None)


@dataclass(frozen=True)
class HoekBrown:
    """Perfectly plastic generalized Hoek-Brown solid (associated flow).

    f = s1 - s3 - sci (mb s3/sci + s)^a <= 0, compression positive (thesis eq 2.1).

    Attributes
    ----------
    E, nu : float
        Rock-mass elastic constants (Pa, -).
    sci : float
        Intact uniaxial compressive strength (Pa).
    mb, s, a : float
        Rock-mass constants (see `continuum_ref.hoek_brown.parameters`).
    """

    E: float
    nu: float
    sci: float
    mb: float
    s: float
    a: float

    def __post_init__(self):
        _elastic_check(self.E, self.nu)
        _positive("sci", self.sci)
        _positive("mb", self.mb)
        _positive("s", self.s)
        if not (0.5 <= self.a < 1.0):
            raise ValueError(f"a={self.a!r} must be in [0.5, 1)")

    @classmethod
    def from_gsi(cls, gsi, mi, sci, D=0.0, E=None, nu=0.3):
        """Build from GSI, mi, sci and D (Hoek et al. 2002); E defaults to Em (2002)."""
        mb, s, a = hb.parameters(gsi, mi, D)
        E = hb.modulus_hoek2002(gsi, sci, D) if E is None else E
        return cls(E=E, nu=nu, sci=sci, mb=mb, s=s, a=a)

    @property
    def tensile_strength(self):
        """Isotropic (apex) tensile strength s sci / mb as a positive number (Pa)."""
        return self.s * self.sci / self.mb

    def equivalent_mohr_coulomb(self, sigma3_max, dilation=None):
        """The Mohr-Coulomb rock mass that strength reduction uses for this one.

        c and phi are the Hoek et al. (2002) fit (eqs 13-14, `hoek_brown.
        equivalent_mohr_coulomb`) over st < sigma3 < sigma3_max (Pa, compression positive;
        e.g. `hoek_brown.sigma3_max_slope`), with a tension cut-off at the Hoek-Brown tensile
        strength s sci / mb and dilation psi in degrees (None: associated). Strength reduction
        then follows the Mohr-Coulomb rule (`MohrCoulomb.reduced`, `continuum_ref.ssr`).
        """
        c, phi = hb.equivalent_mohr_coulomb(self.sci, self.mb, self.s, self.a, sigma3_max)
        return MohrCoulomb(E=self.E, nu=self.nu, cohesion=c, friction=phi, dilation=dilation,
                           tensile_strength=self.tensile_strength)
