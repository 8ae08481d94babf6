"""The ``Model`` options of deformable blocks checked and turned into their bundle.

``deformable`` = {block group or "*": zone size m} and ``zone_strength`` = {block group or "*":
dict(cohesion=Pa, friction=deg, dilation=deg, tensile_strength=Pa)} (``SolverOptions``) name
block groups; here they are checked against the blocks (ValueError naming a bad entry), the
zone size of each block is resolved (the smallest its groups give), and the zones are meshed
(``component.deformable_bundle``). A deformable block's shared edges are split into its zone
size, so each contact acts on one boundary segment (``contact.contacts.split_edges``).
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.contacts import split_edges
from . import component as zone_kernels
from .zone_plasticity import new_keys, strength_table

__all__ = ["check_groups", "deformable_sizes", "zone_strengths", "zone_sizes", "zone_bundle",
           "contact_edges"]


def check_groups(option, name, groups) -> None:
    """ValueError naming ``name`` unless it is one of ``groups`` or "*"."""
    if name != "*" and name not in groups:
        raise ValueError(f"{option}: no block group {name!r}; groups are {sorted(groups)} "
                         "(or '*' for every block)")


def deformable_sizes(deformable, groups, rounding, edge_elements):
    """The ``deformable`` option checked: a plain dict {group or "*": zone size m}, or None."""
    if deformable is None:
        return None
    if not isinstance(deformable, dict) or not deformable:
        raise ValueError(f"deformable must be a dict {{group name or '*': zone size m}} or "
                         f"None, got {deformable!r}")
    if rounding:
        raise ValueError(f"deformable blocks do not take corner rounding yet "
                         f"(rounding={rounding!r}): use rounding=0")
    if edge_elements:
        raise ValueError("deformable blocks do not take edge_elements=True yet")
    out = {}
    for name, size in deformable.items():
        check_groups("deformable", name, groups)
        if isinstance(size, bool) or not isinstance(size, (int, float, np.number)) or \
                not (math.isfinite(size) and size > 0):
            raise ValueError(f"deformable: the zone size of {name!r} must be a finite "
                             f"length > 0 m, got {size!r}")
        out[str(name)] = float(size)
    return out


def zone_strengths(zone_strength, deformable, groups):
    """The ``zone_strength`` option checked: a plain dict {group or "*": dict(cohesion=,
    friction=, dilation=, tensile_strength=)}, or None."""
    if zone_strength is None:
        return None
    if not isinstance(zone_strength, dict) or not zone_strength:
        raise ValueError(f"zone_strength must be a dict {{group name or '*': dict(cohesion=Pa"
                         f", friction=deg, ...)}} or None, got {zone_strength!r}")
    if deformable is None:
        raise ValueError("zone_strength needs deformable blocks: pass deformable= to Model")
    out = {}
    for name, row in zone_strength.items():
        check_groups("zone_strength", name, groups)
        if not isinstance(row, dict) or any(isinstance(v, bool) or
                                            not isinstance(v, (int, float, np.number))
                                            for v in row.values()):
            raise ValueError(f"zone_strength: the entry of {name!r} must be a dict of "
                             f"numbers (cohesion=Pa, friction=deg, ...), got {row!r}")
        row = new_keys(row, f"zone_strength[{name!r}]")
        strength_table(row, 1, f"zone_strength[{name!r}]")
        out[str(name)] = {k: float(v) for k, v in row.items()}
    return out


def zone_sizes(deformable, group_blocks, n_blocks) -> np.ndarray:
    """(nb,) the zone size of each block (m; the smallest its groups give), NaN: rigid.
    ``group_blocks(name)``: the block indices of a group."""
    size = np.full(n_blocks, np.nan)
    for name, h in deformable.items():
        idx = np.arange(n_blocks) if name == "*" else group_blocks(name)
        size[idx] = np.fmin(size[idx], h)
    return size


def zone_bundle(blocks, props, sizes, moduli, zone_strength, group_blocks):
    """The zones of the deformable blocks (``component.Deformable``; empty when ``sizes`` is
    None). ``moduli``: (block_E, block_nu) per block; their density is their block's
    (mass / area); ``zone_strength`` the checked option."""
    if sizes is None:
        return zone_kernels.no_deformable()
    nb = blocks.n_blocks
    block_E, block_nu = moduli
    size = zone_sizes(sizes, group_blocks, nb)
    bad = np.flatnonzero(np.isfinite(size) & ~np.isfinite(block_E))
    if bad.size:
        raise ValueError(f"deformable block {int(bad[0])} needs a finite block_E (Pa), got "
                         f"{block_E[bad[0]]!r}: pass block_E= to Model")
    rho = props.mass / blocks.area
    strength = strength_table(None, nb)
    for name, row in (zone_strength or {}).items():
        idx = np.arange(nb) if name == "*" else group_blocks(name)
        strength[idx] = strength_table(row, 1)
    return zone_kernels.deformable_bundle(props, size, block_E, block_nu, rho, strength,
                                          blocks.centroid, blocks.bounds())


def contact_edges(blocks, sizes, group_blocks):
    """The shared edges the initial contacts are made of: a deformable block's split into its
    zone size, the others whole (``sizes`` None: the blocks' own edges)."""
    if sizes is None:
        return blocks
    size = np.nan_to_num(zone_sizes(sizes, group_blocks, blocks.n_blocks), nan=np.inf)
    return split_edges(blocks, np.minimum(size[blocks.edge_block_a], size[blocks.edge_block_b]))
