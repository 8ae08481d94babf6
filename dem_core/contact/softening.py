"""Softening flaws: after the peak, tension and cohesion fall with the contact's plastic opening
and slip so that the work spent is a fracture energy (a cohesive crack; Hillerborg, Modéer &
Petersson 1976, Cement and Concrete Research 6, 773-782).

One irreversible damage variable per contact, ``kappa`` in [0, 1], the plastic displacement
normalised by the critical one of its mode and summed over the modes (the two modes share one
plastic displacement, so a crack opened half-way in tension has half its shear strength left)::

    d kappa = dw_p / w_c + ds_p / s_c          dw_p plastic opening, ds_p |plastic slip|, m
    T(kappa)   = T_res + (T - T_res) f(kappa)
    c(kappa)   = c_res + (c - c_res) f(kappa)
    tan phi(kappa) = tan phi_res + (tan phi - tan phi_res) f(kappa)

with a softening shape f, f(0) = 1, f(1) = 0, and A_f = int_0^1 f dx, so that the work under the
curve of a pure mode is the fracture energy (J/m^2 = N/m)::

    w_c = G_I  / ((T - T_res) A_f)             critical opening, m
    s_c = G_II / ((c - c_res) A_f)             critical slip, m

Shapes (``SHAPES``): ``linear``, f = 1 - x (A_f = 1/2, so w_c = 2 G_I / T); ``hordijk``,
f = (1 + (3x)^3) e^(-6.93 x) - 28 x e^(-6.93) (Hordijk 1991, "Local approach to fatigue of
concrete", PhD thesis, TU Delft; Cornelissen, Hordijk & Reinhardt 1986), A_f = 0.1947, so
w_c = 5.14 G_I / T.

Each step the trial stresses are returned to the softened envelope with kappa implicit (the
stress at the end of the step is the envelope at the new kappa): first the tension cut-off,
then Coulomb with the normal stress so found. The returned plastic displacement delta solves

    q - k delta = A + B f(kappa + delta / L)      (q the trial's excess measure, L = w_c or s_c)

on [0, L (1 - kappa)]; beyond it the contact is fully softened: it is "broken" (tension or
shear, the mode of the step that finished it) and takes the residual law from then on. The
solution is unique when k L > B max|f'| (no snap-back at the contact: ``snap_back_stiffness``);
materials that violate it with their own kn, ks are refused when the table is made. The
work of the step is A delta + B L (F(kappa_new) - F(kappa)), F the integral of f: exact along
the envelope.

Unloading from the softening branch is elastic from the plastic displacement reached
(plasticity, not secant damage: the crack stays open by what it opened plastically), as in
3DEC's softening joints. The stable time step needs no change: the branch's tangent is
negative, so it lowers no natural period.
"""
from __future__ import annotations

import functools
import math
import warnings

import numpy as np
from numba import njit

from .elastic import lattice_moduli

__all__ = ["SHAPES", "shape_area", "shape_max_slope", "critical_displacement",
           "return_to_envelope", "shape_value", "shape_integral", "snap_back", "check_contacts",
           "characteristic_lengths", "warn_unresolved", "SofteningResolutionWarning"]

SHAPES = {"linear": 1, "hordijk": 2}    # the code in MaterialTable's softening column

_C1, _C2 = 3.0, 6.93                   # Hordijk's constants
_TAIL = (1.0 + _C1 ** 3) * math.exp(-_C2)


@njit(cache=True, inline="always")
def shape_value(shape, x):
    """f(x) of the shape (1 linear, 2 Hordijk); x in [0, 1]."""
    if shape == 1:
        return 1.0 - x
    return (1.0 + (_C1 * x) ** 3) * math.exp(-_C2 * x) - x * _TAIL


@njit(cache=True, inline="always")
def shape_integral(shape, x):
    """F(x) = int_0^x f: for Hordijk, int (1 + 27 t^3) e^(-a t) dt closed form."""
    if shape == 1:
        return x - 0.5 * x * x
    a = _C2
    e = math.exp(-a * x)
    p = x ** 3 / a + 3.0 * x * x / a ** 2 + 6.0 * x / a ** 3 + 6.0 / a ** 4
    return (1.0 - e) / a + _C1 ** 3 * (6.0 / a ** 4 - e * p) - 0.5 * _TAIL * x * x


def shape_area(shape: str) -> float:
    """A_f = int_0^1 f (1/2 linear, 0.1947 Hordijk)."""
    return float(shape_integral(SHAPES[shape], 1.0))


@functools.lru_cache(maxsize=None)
def shape_max_slope(shape: str) -> float:
    """max |f'| on [0, 1] (1 linear; 6.96 Hordijk, at x = 0), from the derivative sampled."""
    if shape == "linear":
        return 1.0
    x = [i / 4000.0 for i in range(4001)]
    h = 1e-7
    return max(abs(shape_value(2, min(1.0, t + h)) - shape_value(2, max(0.0, t - h)))
               / (min(1.0, t + h) - max(0.0, t - h)) for t in x)


def critical_displacement(G, drop, shape: str) -> float:
    """w_c (or s_c), m, of fracture energy ``G`` (J/m^2) for a strength drop ``drop`` (Pa):
    G / (drop A_f); 0 (the mode is brittle, as without softening) when G or the drop is 0."""
    if G == 0.0 or drop <= 0.0:
        return 0.0
    return G / (drop * shape_area(shape))


@njit(cache=True, inline="always")
def _residual(q, kL, kappa, A, B, shape, x):
    """q - k delta - max(0, A + B f(x)) with delta = L (x - kappa)."""
    env = A + B * shape_value(shape, x)
    return q - kL * (x - kappa) - (env if env > 0.0 else 0.0)


@njit(cache=True)
def return_to_envelope(q, k, L, kappa, A, B, shape):
    """(kappa_new, delta, work): the return of a trial excess q (Pa; the trial stress measure,
    yielding: q > max(0, A + B f(kappa))) to the envelope max(0, A + B f) (Pa) with stiffness
    k (Pa/m) and critical displacement L (m); delta the plastic displacement (m), work its
    work per unit area (J/m^2). kappa_new = 1 (fully softened) when the trial passes the end
    of the curve; delta is then the displacement up to it and the caller applies the
    residual law to the rest."""
    if L <= 0.0:                                # a brittle mode: softened at once
        return 1.0, 0.0, 0.0
    kL = k * L
    if _residual(q, kL, kappa, A, B, shape, 1.0) >= 0.0:
        x = 1.0
    else:
        lo, hi = kappa, 1.0                     # r(lo) > 0 > r(hi): bisection and secant
        rlo = _residual(q, kL, kappa, A, B, shape, lo)
        rhi = _residual(q, kL, kappa, A, B, shape, hi)
        x = lo
        for _ in range(100):
            x = lo + (hi - lo) * rlo / (rlo - rhi)      # regula falsi (Illinois)
            if not (lo < x < hi):
                x = 0.5 * (lo + hi)
            r = _residual(q, kL, kappa, A, B, shape, x)
            if r == 0.0 or hi - lo <= 1e-15:
                break
            if r > 0.0:
                lo, rlo = x, r
                rhi *= 0.5
            else:
                hi, rhi = x, r
                rlo *= 0.5
            if abs(r) <= 1e-13 * (abs(q) + kL):
                break
    delta = L * (x - kappa)
    work = A * delta + B * L * (shape_integral(shape, x) - shape_integral(shape, kappa))
    return x, delta, (work if work > 0.0 else 0.0)


def snap_back(G, k, L, drop, shape: str):
    """(k_min, G needed) when a softening of fracture energy ``G`` (J/m^2), critical
    displacement ``L`` (m) and strength drop ``drop`` (Pa) snaps back at the softest of the
    stiffnesses ``k`` (Pa/m; a number or an array): the return (``return_to_envelope``) has
    one solution only while k L > drop max|f'|, i.e. while the peak's elastic displacement
    drop / k is shorter than the softening. None when it does not (or the mode is brittle)."""
    k_min = float(np.min(k))
    slope = shape_max_slope(shape)
    if L > 0.0 and k_min * L <= drop * slope:
        return k_min, G * drop * slope / (k_min * L)        # L grows in proportion to G
    return None


def check_contacts(table, contacts) -> None:
    """ValueError naming the material when a softening bond would snap back at one of its
    contacts, whose stiffness (in series with the blocks) may be below the material's own."""
    m = contacts.live("material")
    names = {v: k for k, v in SHAPES.items()}
    for i in np.flatnonzero(table.softening > 0):
        mine = m == i
        if not mine.any():
            continue
        shape = names[int(table.softening[i])]
        for mode, k, L, drop in (
                ("fracture_energy_I", contacts.live("kn")[mine], table.critical_opening[i],
                 table.tensile_strength[i] - table.residual_tensile_strength[i]),
                ("fracture_energy_II", contacts.live("ks")[mine], table.critical_slip[i],
                 table.cohesion[i] - table.res_cohesion[i])):
            G = L * drop * shape_area(shape)
            snaps = snap_back(G, k, L, drop, shape)
            if snaps:
                k_min, need = snaps
                raise ValueError(
                    f"{table.names[i]}: the {mode} softening would snap back at a contact of "
                    f"stiffness {k_min:.4g} Pa/m (in series with its blocks): the peak's elastic "
                    f"displacement {drop / k_min:.3g} m against a softening length of {L:.3g} m;"
                    f" it needs {mode} > {need:.4g} J/m^2")


def characteristic_lengths(table, contacts, pos) -> dict:
    """{material name: (l_ch_I, l_ch_II, d)}, m, of every softening material: Hillerborg's
    l_ch = E' G_I / T^2 and its shear analogue G_mod G_II / c^2 (with the drops T - T_res and
    c - c_res), E' and G_mod the plane moduli of the lattice its contacts make
    (``elastic.lattice_moduli`` with their median stiffness and d, the median distance
    between the centroids ``pos`` of the two blocks of each of its contacts: the blocks'
    size where that material is)."""
    out = {}
    m = contacts.live("material")
    a, b = contacts.live("block_a"), contacts.live("block_b")
    for i in np.flatnonzero(table.softening > 0):
        mine = m == i
        if not mine.any():
            continue
        kn = float(np.median(contacts.live("kn")[mine]))
        ks = float(np.median(contacts.live("ks")[mine]))
        d = float(np.median(np.hypot(*(pos[a[mine]] - pos[b[mine]]).T)))
        mod = lattice_moduli(kn, ks, d)          # E_2d: plane strain's E / (1 - nu^2)
        E, G_mod = mod["E_2d"], mod["E_2d"] / (2.0 * (1.0 + mod["nu_2d"]))
        dT = table.tensile_strength[i] - table.residual_tensile_strength[i]
        dc = table.cohesion[i] - table.res_cohesion[i]
        area = shape_integral(int(table.softening[i]), 1.0)
        G_I = table.critical_opening[i] * dT * area
        G_II = table.critical_slip[i] * dc * area
        out[table.names[i]] = (E * G_I / dT ** 2 if dT > 0 else 0.0,
                               G_mod * G_II / dc ** 2 if dc > 0 else 0.0, d)
    return out


RESOLVED_SPACINGS = 4      # blocks (centroid spacings d) a characteristic length must span


class SofteningResolutionWarning(UserWarning):
    """Blocks larger than a softening material's characteristic length."""


def warn_unresolved(lengths: dict) -> None:
    """One warning per softening material whose characteristic length spans fewer than
    ``RESOLVED_SPACINGS`` of its blocks (d of ``characteristic_lengths``): the softening zone is
    then not resolved, and the answer again depends on block size (Bazant & Oh 1983's crack
    band condition). The bound is measured: a notched beam's peak load was 18 % / 13 % above
    its resolved value at l_ch = 2.4 d / 3.6 d and within 4 % at 4.8 d (docs/verification.md,
    "Resolution: how many blocks per l_ch")."""
    for name, (l_I, l_II, d) in lengths.items():
        short = [f"{mode} = {l:.3g} m" for mode, l in (("l_ch_I", l_I), ("l_ch_II", l_II))
                 if 0.0 < l < RESOLVED_SPACINGS * d]
        if short:
            warnings.warn(f"{name}: blocks of {d:.3g} m are too large for its characteristic "
                          f"length ({', '.join(short)}: fewer than {RESOLVED_SPACINGS} blocks "
                          f"across it); use blocks smaller than l_ch / {RESOLVED_SPACINGS} or a "
                          "larger fracture energy", SofteningResolutionWarning, stacklevel=3)
