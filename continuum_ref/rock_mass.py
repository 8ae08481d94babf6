"""A continuum rock mass from the DEM's own inputs (a scene's blocks, joints and flaws), for a
continuum-versus-discrete comparison that needs no invented material.

A continuum without joints cannot be the jointed rock; it can bracket it. ``dem_rock_mass``
gives one isotropic Mohr-Coulomb material per region, with a stated ``bound``:

- ``"joints"``: the strength of the region's weakest joint set (its peak c, phi and T),
  everywhere and in every direction. The DEM's rock can fail only along its joints or through
  its flaws, so where the joints are not oriented to slide the continuum fails too early: a
  lower bound of the jointed slope's strength (the field slope: continuum F = 0.83 against
  the DEM's 1.11, docs/scenes.md).
- ``"intact"``: the flaws' peak strength (the Voronoi bonds, or the edges the joints do not
  cover), as if the joints were not there: an upper bound, reached where the rupture runs
  through intact rock.

The weakest set is the one with the least shear strength c + sigma tan(phi) at sigma = rho g
H / 2, half the overburden of the scene's height H. A joint set with no cohesion gets 1 Pa, so
that the Mohr-Coulomb apex stays finite (the continuum then has the joints' friction alone).

Stiffness (both bounds; Goodman 1989, "Introduction to Rock Mechanics", 2nd ed., ch. 6;
Amadei & Goodman 1981): the joints' compliance adds to the rock's,

    1 / E_m = 1 / E_r + sum_i p_i / (kn_i s_i),    1 / G_m = 1 / G_r + sum_i p_i / (ks_i s_i),

s_i the set's spacing (m), p_i its persistence, kn_i, ks_i its stiffness (Pa/m). Summing every
set gives the modulus across all of them at once: the rock mass's softest direction, an
isotropic lower bound of its stiffness. The rock between the joints, E_r and G_r, is the
Voronoi flaw lattice of the region (``dem_core.contact.elastic.lattice_moduli``, plane strain,
d the spacing of hexagons of the region's edge length) in series with deformable blocks
(``block_E``, ``block_nu``); rigid blocks without Voronoi flaws are rigid (the joints alone
make the modulus). nu_m = E_m / (2 G_m) - 1, kept in [0, 0.49].

``dilation`` (degrees, default 0: non-associated, what slope practice uses) is the flow rule's
psi for a strength reduction (``continuum_ref.ssr``).

In a scene file: ``"continuum": {"materials": {"rock": {"kind": "dem_rock_mass", "bound":
"joints"}}}`` (``dem_core.workflow.scene.CONTINUUM_MATERIALS``).
"""
from __future__ import annotations

import math

from .materials import MohrCoulomb

__all__ = ["dem_rock_mass", "BOUNDS", "rock_stiffness", "weakest_joint_set"]

BOUNDS = ("joints", "intact")
G = 9.81                    # m/s^2
NO_COHESION = 1.0           # Pa: the cohesion of a joint set that has none


def dem_rock_mass(scene, region: str, bound: str, dilation: float = 0.0,
                  materials=None) -> MohrCoulomb:
    """The Mohr-Coulomb rock mass of ``region`` (a name of ``scene.geometry.regions``) at
    ``bound`` (``BOUNDS``; module docstring): E, nu from ``rock_stiffness``; c, phi, T of the
    weakest joint set or of the region's flaws; psi = ``dilation`` (degrees, at most phi).
    ``materials``: the contact materials (name or pattern -> ``Material``) to derive it from,
    default the scene's (a stage may have changed them)."""
    from dem_core.contact.materials import material_for

    mats = scene.materials if materials is None else materials
    if bound not in BOUNDS:
        raise ValueError(f"bound must be one of {BOUNDS}, got {bound!r}")
    regions = {r.name: r for r in scene.geometry.regions}
    if region not in regions:
        raise ValueError(f"region {region!r} is not in the scene; regions are {sorted(regions)}")
    E, nu = rock_stiffness(scene, region, mats)
    if bound == "joints":
        joint = weakest_joint_set(scene, region, mats)
        if joint is None:
            raise ValueError(f"region {region!r}: no joint set cuts it, so there is no joint "
                             f"bound; use bound \"intact\"")
        mat = material_for(f"joint:{joint.name}", mats)
    else:
        mat = material_for(f"flaw:{region}", mats)
    c = mat.cohesion if mat.cohesion > 0.0 else NO_COHESION
    phi = float(mat.friction)
    return MohrCoulomb(E=E, nu=nu, cohesion=c, friction=phi, dilation=min(dilation, phi),
                       tensile_strength=float(mat.tensile_strength))


def _sets_in(scene, region):
    return [j for j in scene.geometry.joint_sets
            if j.persistence > 0.0 and (not j.regions or region in j.regions)]


def weakest_joint_set(scene, region, materials=None):
    """The joint set of ``region`` with the least peak shear strength c + sigma tan(phi) at
    sigma = density g H / 2 (H the scene's height, m), or None when no set cuts it;
    ``materials`` default the scene's."""
    from dem_core.contact.materials import material_for

    ys = [y for r in scene.geometry.regions for _, y in r.polygon().exterior.coords]
    sigma = scene.density * G * (max(ys) - min(ys)) / 2.0

    mats = scene.materials if materials is None else materials

    def strength(j):
        m = material_for(f"joint:{j.name}", mats)
        return m.cohesion + sigma * math.tan(math.radians(m.friction))
    sets = _sets_in(scene, region)
    return min(sets, key=strength) if sets else None


def rock_stiffness(scene, region: str, materials=None) -> tuple:
    """(E_m, nu_m) in Pa, - of ``region``: the rock between the joints with every joint set's
    compliance added (module docstring); ``materials`` default the scene's."""
    from dem_core.contact.elastic import lattice_moduli, spacing_from_area
    from dem_core.contact.materials import material_for

    mats = scene.materials if materials is None else materials
    compliance_n = compliance_s = 0.0           # 1/E, 1/G of the rock between the joints
    vor = scene.geometry.voronoi.get(region)
    if vor is not None:
        flaw = material_for(f"flaw:{region}", mats)
        d = spacing_from_area(1.5 * math.sqrt(3.0) * vor.edge_length ** 2)   # hexagons
        lat = lattice_moduli(flaw.kn, flaw.ks, d)
        compliance_n += 1.0 / lat["E"]
        compliance_s += 2.0 * (1.0 + lat["nu"]) / lat["E"]
    if scene.block_E is not None:
        compliance_n += 1.0 / scene.block_E
        compliance_s += 2.0 * (1.0 + scene.block_nu) / scene.block_E
    for j in _sets_in(scene, region):
        m = material_for(f"joint:{j.name}", mats)
        compliance_n += j.persistence / (m.kn * j.spacing)
        compliance_s += j.persistence / (m.ks * j.spacing)
    if compliance_n <= 0.0:
        raise ValueError(f"region {region!r}: rigid blocks with neither Voronoi flaws nor "
                         f"joints have no modulus to give a continuum; set block_E")
    E, Gm = 1.0 / compliance_n, 1.0 / compliance_s
    return E, min(max(E / (2.0 * Gm) - 1.0, 0.0), 0.49)
