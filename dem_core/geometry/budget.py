"""How large a geometry's model will be, estimated before it is built, and the limit on it.

Blocks of a region with Voronoi flaws: its target cell count (``tessellate.target_cell_count``,
the integral of dA / (CELL_AREA h^2)) plus one piece per length h of the joint traces that
split its cells (a set of spacing s and persistence k has about k A / s of trace in an area A).
Blocks of a region cut by its joints alone: the cells of the arrangement of the sets' full
lines, 1 + sum n_i + sum_{i<j} A / (s_i s_j |sin theta_ij|), with n_i the region's width
across set i over its spacing (each line adds a cell, each crossing one more).

Memory: ``BYTES_PER_BLOCK`` per block, the peak resident memory of a Voronoi build and its
``Model`` per block (``benchmarks/memory_per_block.py``; docs/performance.md, "Memory per
block and per cell"). A geometry whose estimate needs more than the memory the machine has
available (MemAvailable in /proc/meminfo), or has more blocks than a set limit (the
``max_blocks`` argument, else the environment variable ``DEM_MAX_BLOCKS``), is refused
before any seed is placed, with the numbers and the edge length that would fit.
"""
from __future__ import annotations

import math
import os

import numpy as np

from .tessellate import CELL_AREA, target_cell_count

__all__ = ["BYTES_PER_BLOCK", "MAX_BLOCKS_VARIABLE", "available_memory", "estimate_blocks",
           "check_size", "limit_from"]

BYTES_PER_BLOCK = 8000          # 5.8 kB measured (docs/performance.md), plus a search's snapshot
MAX_BLOCKS_VARIABLE = "DEM_MAX_BLOCKS"


def available_memory() -> int | None:
    """Bytes of memory the machine has available now (MemAvailable of /proc/meminfo), or None
    where that cannot be read."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def _sets_in(region, sets) -> list:
    return [s for s in sets if s.regions is None or region.name in s.regions]


def _voronoi_blocks(region, poly, vs, spec) -> float:
    """Cells of the tessellation plus the pieces its joints split off (module docstring)."""
    cells = target_cell_count(poly, vs, np.random.default_rng(vs.seed))
    h = math.sqrt(poly.area / (CELL_AREA * max(cells, 1.0)))       # the mean edge length
    trace = sum(s.persistence * poly.area / s.spacing for s in _sets_in(region, spec.joint_sets))
    trace += sum(poly.intersection(_line(j)).length for j in _sets_in(region, spec.joints))
    return cells + trace / h


def _line(joint):
    import shapely
    return shapely.LineString(joint.points)


def _jointed_blocks(region, poly, spec) -> float:
    """Cells of the arrangement of the region's joint-set lines (module docstring)."""
    sets = _sets_in(region, spec.joint_sets)
    xy = np.asarray(poly.exterior.coords)
    n = [float(np.ptp(xy @ s.normal())) / s.spacing for s in sets]
    blocks = 1.0 + sum(n) + len(_sets_in(region, spec.joints))
    for i in range(len(sets)):
        for j in range(i + 1, len(sets)):
            sin = abs(float(np.cross(sets[i].direction(), sets[j].direction())))
            if sin > 1e-9:
                blocks += poly.area / (sets[i].spacing * sets[j].spacing * sin)
    return blocks


def estimate_blocks(spec) -> dict:
    """Region name -> the estimated number of blocks it will be built into (module
    docstring; a ``GeometrySpec``)."""
    out = {}
    for r in spec.regions:
        poly, vs = r.polygon(), spec.voronoi.get(r.name)
        out[r.name] = (_voronoi_blocks(r, poly, vs, spec) if vs is not None
                       else _jointed_blocks(r, poly, spec))
    return out


def limit_from(max_items, variable, available, bytes_each) -> tuple:
    """(the largest count allowed, why): the smaller of ``max_items`` (else the environment
    ``variable``, a whole number) and the ``available`` bytes over ``bytes_each``."""
    if max_items is None and os.environ.get(variable):
        try:
            max_items = int(os.environ[variable])
        except ValueError:
            raise ValueError(f"{variable}={os.environ[variable]!r} must be a whole number") \
                from None
    limits = []
    if max_items is not None:
        limits.append((float(max_items), f"the limit of {max_items:.3g} ({variable})"))
    if available is not None:
        limits.append((available / bytes_each,
                       f"the {available / 1e9:.3g} GB of memory this machine has available "
                       f"({bytes_each / 1e3:.3g} kB each, measured)"))
    return min(limits) if limits else (math.inf, "no limit")


def check_size(spec, max_blocks=None, available=None) -> float:
    """The estimated block count of ``spec``; ValueError with the numbers when it is above the
    limit (``limit_from``: ``max_blocks`` or ``DEM_MAX_BLOCKS``, and the ``available`` memory,
    bytes, default ``available_memory()``), naming the largest region and the edge length
    that would fit."""
    per_region = estimate_blocks(spec)
    total = sum(per_region.values())
    limit, why = limit_from(max_blocks, MAX_BLOCKS_VARIABLE,
                            available_memory() if available is None else available,
                            BYTES_PER_BLOCK)
    if total <= limit:
        return total
    name = max(per_region, key=per_region.get)
    vs = spec.voronoi.get(name)
    grow = math.sqrt(total / limit)             # blocks ~ 1 / h^2
    fix = (f"an edge_length of at least {vs.edge_length * grow:.2g} m in region {name!r} "
           f"(now {vs.edge_length:g} m)" if vs is not None else
           f"joint spacings about {grow:.2g} times wider in region {name!r}")
    raise ValueError(f"geometry: about {total:.3g} blocks (region {name!r}: "
                     f"{per_region[name]:.3g}) would need about "
                     f"{total * BYTES_PER_BLOCK / 1e9:.3g} GB, more than {why}, which allow "
                     f"{limit:.3g} blocks; {fix} would fit")
