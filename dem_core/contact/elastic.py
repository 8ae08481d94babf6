"""Elastic helpers: contact stiffness guides, block compliance in series, assembly moduli.

Sign and unit conventions: stiffness kn, ks in Pa/m; moduli in Pa; plane strain.

Block compliance in series
--------------------------
The blocks are rigid; a scene that states a block modulus (the thesis's deformable UDEC blocks)
gets it as a compliance in series with each contact spring. A contact at distance ``h`` from
the centroid of each block (measured along the contact normal) sees a half-block of length h:

    1/kn_eff = 1/kn + h_a/E'_a + h_b/E'_b,    E' = E/(1 - nu^2)  (plane-strain sheet modulus)
    1/ks_eff = 1/ks + h_a/G_a + h_b/G_b,      G = E/(2(1 + nu))

Assembly moduli of a regular lattice
------------------------------------
Rigid hexagons (the Voronoi cells of a triangular lattice of centroid spacing d) joined by
edge contacts of length l = d/sqrt(3): per bond Kn = kn l, Ks = ks l. A uniform strain with
particle rotation equal to the mean rotation stores W = (lambda/2) tr(e)^2 + mu e:e with
lambda = sqrt(3)/4 (Kn - Ks), mu = sqrt(3)/4 (Kn + Ks), so in 2D

    nu_2d = (1 - ks/kn) / (3 + ks/kn),    E_2d = 2 d kn (kn + ks) / (3 kn + ks).

E_2d and nu_2d are the moduli a plane (2D) uniaxial test measures; the plane-strain E and nu
of the equivalent 3D solid are nu = nu_2d / (1 + nu_2d), E = E_2d (1 - nu^2).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["kn_from_zone", "series_stiffness", "lattice_moduli", "spacing_from_area"]


def kn_from_zone(E, nu, dz_min):
    """Thesis eq 3.7/4.9: kn = (K + 4G/3) / dz_min, Pa/m (the thesis allows up to 10x this)."""
    if not (E > 0 and -1 < nu < 0.5 and dz_min > 0):
        raise ValueError(f"need E > 0, -1 < nu < 0.5, dz_min > 0; got {E!r}, {nu!r}, {dz_min!r}")
    K = E / (3 * (1 - 2 * nu))
    G = E / (2 * (1 + nu))
    return (K + 4 * G / 3) / dz_min


def series_stiffness(kn, ks, h_a, h_b, E_a, nu_a, E_b, nu_b):
    """Contact springs in series with two half-blocks (module docstring); arrays broadcast.

    ``E = inf`` (or None before broadcasting) means a rigid block.
    """
    E_a, E_b = np.asarray(E_a, dtype=float), np.asarray(E_b, dtype=float)
    Ep_a, Ep_b = E_a / (1 - np.square(nu_a)), E_b / (1 - np.square(nu_b))
    G_a, G_b = E_a / (2 * (1 + np.asarray(nu_a))), E_b / (2 * (1 + np.asarray(nu_b)))
    kn_eff = 1.0 / (1.0 / kn + h_a / Ep_a + h_b / Ep_b)
    ks_eff = 1.0 / (1.0 / ks + h_a / G_a + h_b / G_b)
    return kn_eff, ks_eff


def spacing_from_area(mean_block_area):
    """Centroid spacing d of a hexagonal lattice with the given cell area: A = sqrt(3)/2 d^2."""
    return math.sqrt(2.0 * mean_block_area / math.sqrt(3.0))


def lattice_moduli(kn, ks, d):
    """Moduli of the regular rigid-hexagon lattice (module docstring).

    Parameters
    ----------
    kn, ks : float, Pa/m. Contact stiffness (use the series values if blocks are deformable).
    d : float, m. Centroid spacing (``spacing_from_area(mean area)`` for a Voronoi assembly).

    Returns
    -------
    dict with E_2d, nu_2d (what a 2D test measures) and E, nu (plane-strain equivalents), Pa.
    """
    r = ks / kn
    nu_2d = (1 - r) / (3 + r)
    E_2d = 2 * d * kn * (kn + ks) / (3 * kn + ks)
    nu = nu_2d / (1 + nu_2d)
    return {"E_2d": E_2d, "nu_2d": nu_2d, "E": E_2d * (1 - nu * nu), "nu": nu}
