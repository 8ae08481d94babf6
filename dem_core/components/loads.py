"""Applied constant loads: a force (N/m) and a moment (N m/m) on chosen blocks."""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = ["Loads", "add_loads", "loads_bundle"]


class Loads(NamedTuple):
    """blocks : (m,) int64. Loaded blocks (m = 0: no loads).
    force : (m, 3) float64. (fx N/m, fy N/m, moment N m/m, CCW +) on each."""

    blocks: np.ndarray
    force: np.ndarray


def loads_bundle(load) -> Loads:
    """The bundle of a dense (nb, 3) load table: only the blocks with a non-zero load."""
    load = np.asarray(load, dtype=np.float64)
    rows = np.flatnonzero(np.any(load != 0.0, axis=1)).astype(np.int64)
    return Loads(rows, np.ascontiguousarray(load[rows]))


@njit(cache=True)
def add_loads(loads, s, p):
    """f_i += applied load of block i, for active loaded blocks."""
    for r in range(loads.blocks.shape[0]):
        i = loads.blocks[r]
        if p.active[i]:
            s.force[i, 0] += loads.force[r, 0]
            s.force[i, 1] += loads.force[r, 1]
            s.force[i, 2] += loads.force[r, 2]
