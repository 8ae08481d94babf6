"""Contact search, broad phase: which pairs of blocks may touch.

Each active block's axis-aligned box, grown by the search margin, is binned on a uniform grid of
cells (about two median block radii); a pair is reported once, by the cell holding the lower-left
corner of the two boxes' overlap (``grid_pairs``). ``world_vertices`` gives every block's
vertices in the world frame, for both phases.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..step.kinematics import body_point

__all__ = ["world_vertices", "boxes", "grid_pairs"]


@njit(cache=True)
def world_vertices(pos, rot, offsets, local):
    """(nv, 2) world coordinates of every block vertex, m."""
    out = np.empty_like(local)
    for b in range(pos.shape[0]):
        for j in range(offsets[b], offsets[b + 1]):
            out[j, 0], out[j, 1] = body_point(pos, rot, b, local[j, 0], local[j, 1])
    return out


@njit(cache=True)
def boxes(wv, offsets, active, margin):
    """(lo, hi): each active block's bounding box grown by ``margin`` (m); inactive blocks
    get empty boxes (lo = +inf, hi = -inf)."""
    nb = offsets.shape[0] - 1
    lo = np.empty((nb, 2))
    hi = np.empty((nb, 2))
    for b in range(nb):
        lo[b, 0] = lo[b, 1] = np.inf
        hi[b, 0] = hi[b, 1] = -np.inf
        if not active[b]:
            continue
        for j in range(offsets[b], offsets[b + 1]):
            for d in range(2):
                lo[b, d] = min(lo[b, d], wv[j, d] - margin)
                hi[b, d] = max(hi[b, d], wv[j, d] + margin)
    return lo, hi


@njit(cache=True)
def grid_pairs(lo, hi, active, cell):
    """(np, 2) int64 pairs (i < j) of active blocks whose boxes overlap."""
    nb = lo.shape[0]
    x0, y0, x1, y1 = np.inf, np.inf, -np.inf, -np.inf
    for b in range(nb):
        if active[b]:
            x0, y0 = min(x0, lo[b, 0]), min(y0, lo[b, 1])
            x1, y1 = max(x1, hi[b, 0]), max(y1, hi[b, 1])
    if x1 < x0:
        return np.zeros((0, 2), np.int64)
    while ((x1 - x0) / cell + 1) * ((y1 - y0) / cell + 1) > 4 * nb + 64:
        cell *= 1.5                               # bound the number of cells
    ncx = int((x1 - x0) / cell) + 1
    ncy = int((y1 - y0) / cell) + 1
    count = np.zeros(ncx * ncy + 1, np.int64)
    for b in range(nb):
        if active[b]:
            for iy in range(int((lo[b, 1] - y0) / cell), int((hi[b, 1] - y0) / cell) + 1):
                for ix in range(int((lo[b, 0] - x0) / cell), int((hi[b, 0] - x0) / cell) + 1):
                    count[iy * ncx + ix + 1] += 1
    start = np.cumsum(count)
    fill = start.copy()
    members = np.empty(start[-1], np.int64)
    for b in range(nb):
        if active[b]:
            for iy in range(int((lo[b, 1] - y0) / cell), int((hi[b, 1] - y0) / cell) + 1):
                for ix in range(int((lo[b, 0] - x0) / cell), int((hi[b, 0] - x0) / cell) + 1):
                    members[fill[iy * ncx + ix]] = b
                    fill[iy * ncx + ix] += 1
    pairs = np.empty((4 * nb + 16, 2), np.int64)
    n = 0
    for c in range(ncx * ncy):
        for p in range(start[c], start[c + 1]):
            for q in range(p + 1, start[c + 1]):
                i, j = members[p], members[q]
                if lo[i, 0] > hi[j, 0] or lo[j, 0] > hi[i, 0] or lo[i, 1] > hi[j, 1] \
                        or lo[j, 1] > hi[i, 1]:
                    continue
                cx = int((max(lo[i, 0], lo[j, 0]) - x0) / cell)
                cy = int((max(lo[i, 1], lo[j, 1]) - y0) / cell)
                if cy * ncx + cx != c:
                    continue                      # reported by another cell
                if n == pairs.shape[0]:
                    bigger = np.empty((2 * n, 2), np.int64)
                    bigger[:n] = pairs
                    pairs = bigger
                pairs[n, 0], pairs[n, 1] = min(i, j), max(i, j)
                n += 1
    return pairs[:n]
