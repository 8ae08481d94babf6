"""Deformable blocks at the model's boundary and seen from outside: which gridpoints lie on the
sides of the model's box, holding a deformable block there (``Model.fix(..., at=...)``), the
zones' motion at a history point and their unbalanced force (docs/mechanics.md, "Held
deformable blocks"). The kernels that move held blocks' gridpoints are in ``deformable.py``
(``_move_held``); the fields are the ``Deformable`` bundle's.
"""
from __future__ import annotations

import numpy as np

__all__ = ["BOX_SIDES", "box_sides", "hold_points", "point_motion", "unbalanced"]


# bits of Deformable.box_sides
BOX_SIDES = {"left": 1, "right": 2, "bottom": 4, "top": 8}


def box_sides(x0, point_offsets, origin, bounds):
    """(ng,) int8: ``BOX_SIDES`` bits of the sides of the model's box (x0, y0, x1, y1) each
    gridpoint lies on (within 1e-9 of the box's size)."""
    out = np.zeros(len(x0), np.int8)
    if origin is None or bounds is None:
        return out
    bx0, by0, bx1, by1 = bounds
    tol = 1e-9 * max(bx1 - bx0, by1 - by0)
    owner = np.repeat(np.arange(len(point_offsets) - 1), np.diff(point_offsets))
    w = x0 + np.asarray(origin, float)[owner]
    for (axis, edge), bit in zip(((0, bx0), (0, bx1), (1, by0), (1, by1)), BOX_SIDES.values()):
        out[np.abs(w[:, axis] - edge) <= tol] |= bit
    return out


def hold_points(d, blocks, bits, sides=None):
    """Hold deformable ``blocks`` (an index array) in the FIX_X / FIX_Y ``bits``: each held
    whole (``held``), with its gridpoints on the box ``sides`` (names of ``BOX_SIDES``; None:
    any side) held along ``bits``; a block with fewer than two such gridpoints has all of
    them held (it is held whole, as a rigid block would be)."""
    mask = sum(BOX_SIDES[n] for n in BOX_SIDES) if sides is None else \
        sum(BOX_SIDES[n] for n in sides)
    for b in blocks:
        g0, g1 = d.point_offsets[b], d.point_offsets[b + 1]
        on = (d.box_sides[g0:g1] & mask) != 0
        d.point_held[g0:g1][on if on.sum() >= 2 else slice(None)] |= bits
        d.held[b] = 1


def point_motion(d, b, r):
    """(ux, uy, vx, vy), block axes: the zones' displacement and velocity at body point r of
    block b (linear in the zone that contains r at rest, else the nearest; zeros for a rigid
    block)."""
    zones = np.flatnonzero(d.zone_block == b)
    if zones.size == 0:
        return 0.0, 0.0, 0.0, 0.0
    p = d.x0[d.nodes[zones]]                                  # (n, 3, 2)
    a, e1, e2 = p[:, 0], p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    q = np.asarray(r, float) - a
    l1 = (q[:, 0] * e2[:, 1] - q[:, 1] * e2[:, 0]) / det
    l2 = (e1[:, 0] * q[:, 1] - e1[:, 1] * q[:, 0]) / det
    w = np.stack([1 - l1 - l2, l1, l2], axis=1)
    k = int(np.argmax(w.min(axis=1)))                         # inside, or the least outside
    g = d.nodes[zones[k]]
    u = w[k] @ (d.x[g] - d.x0[g])
    v = w[k] @ d.v[g]
    return float(u[0]), float(u[1]), float(v[0]), float(v[1])


def unbalanced(d, active, gravity):
    """(N/m, N/m): sum of |f| (the non-rigid force of the last step, before damping) over the
    gridpoints of the active deformable blocks, less the held components (reactions); and what
    the held blocks add to the ratio's denominator (``monitor.unbalanced_ratio``): their
    gridpoints' weight and reactions (a held block is not in the blocks' sum)."""
    counts = np.diff(d.point_offsets)
    live = np.repeat(np.asarray(active) > 0, counts)
    held = np.stack([d.point_held & 1, d.point_held & 2], axis=1) > 0
    free = np.where(held, 0.0, d.f)
    reaction = np.where(held, d.f, 0.0)
    num = float(np.hypot(free[live, 0], free[live, 1]).sum())
    on = live & np.repeat(d.held > 0, counts)
    den = float(d.mass[on].sum() * np.hypot(*gravity) + np.hypot(reaction[on, 0],
                                                                   reaction[on, 1]).sum())
    return num, den
