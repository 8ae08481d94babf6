"""Deformable blocks at the model's boundary and seen from outside: which gridpoints lie on the
sides of the model's box, holding a deformable block there (``Model.fix(..., at=...)``), the
zones' motion at a history point and their unbalanced force (docs/mechanics.md, "Held
deformable blocks"). The kernels that move held blocks' gridpoints are in ``component.py``
(``_move_held``); the fields are the ``Deformable`` bundle's.
"""
from __future__ import annotations

import numpy as np

from ..step.state import FIX_ROT, FIX_X, FIX_Y

__all__ = ["BOX_SIDES", "box_sides", "hold", "hold_points", "release", "sides", "point_motion",
           "unbalanced"]


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


def hold_points(zones, blocks, bits, sides=None):
    """Hold deformable ``blocks`` (an index array) in the FIX_X / FIX_Y ``bits``: each held
    whole (``held``), with its gridpoints on the box ``sides`` (names of ``BOX_SIDES``; None:
    any side) held along ``bits``; a block with fewer than two such gridpoints has all of
    them held (it is held whole, as a rigid block would be)."""
    mask = sum(BOX_SIDES[n] for n in BOX_SIDES) if sides is None else \
        sum(BOX_SIDES[n] for n in sides)
    for b in blocks:
        g0, g1 = zones.point_offsets[b], zones.point_offsets[b + 1]
        on = (zones.box_sides[g0:g1] & mask) != 0
        zones.point_held[g0:g1][on if on.sum() >= 2 else slice(None)] |= bits
        zones.held[b] = 1


def point_motion(zones, b, r):
    """(ux, uy, vx, vy), block axes: the zones' displacement and velocity at body point r of
    block b (linear in the zone that contains r at rest, else the nearest; zeros for a rigid
    block)."""
    in_block = np.flatnonzero(zones.zone_block == b)
    if in_block.size == 0:
        return 0.0, 0.0, 0.0, 0.0
    p = zones.x0[zones.nodes[in_block]]                          # (n, 3, 2)
    a, e1, e2 = p[:, 0], p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    q = np.asarray(r, float) - a
    l1 = (q[:, 0] * e2[:, 1] - q[:, 1] * e2[:, 0]) / det
    l2 = (e1[:, 0] * q[:, 1] - e1[:, 1] * q[:, 0]) / det
    w = np.stack([1 - l1 - l2, l1, l2], axis=1)
    k = int(np.argmax(w.min(axis=1)))                         # inside, or the least outside
    g = zones.nodes[in_block[k]]
    u = w[k] @ (zones.x[g] - zones.x0[g])
    v = w[k] @ zones.v[g]
    return float(u[0]), float(u[1]), float(v[0]), float(v[1])


def unbalanced(zones, active, gravity):
    """(N/m, N/m): sum of |f| (the non-rigid force of the last step, before damping) over the
    gridpoints of the active deformable blocks, less the held components (reactions); and what
    the held blocks add to the ratio's denominator (``monitor.unbalanced_ratio``): their
    gridpoints' weight and reactions (a held block is not in the blocks' sum)."""
    counts = np.diff(zones.point_offsets)
    live = np.repeat(np.asarray(active) > 0, counts)
    held = np.stack([zones.point_held & 1, zones.point_held & 2], axis=1) > 0
    free = np.where(held, 0.0, zones.f)
    reaction = np.where(held, zones.f, 0.0)
    num = float(np.hypot(free[live, 0], free[live, 1]).sum())
    on = live & np.repeat(zones.held > 0, counts)
    den = float(zones.mass[on].sum() * np.hypot(*gravity) + np.hypot(reaction[on, 0],
                                                                   reaction[on, 1]).sum())
    return num, den


def release(zones, idx) -> None:
    """Free the deformable blocks among ``idx`` and their gridpoints (``Model.free``)."""
    if zones.point_offsets.shape[0] == 0:
        return
    nb = zones.point_offsets.shape[0] - 1
    zones.held[idx] = 0
    zones.point_held[np.repeat(np.isin(np.arange(nb), idx), np.diff(zones.point_offsets))] = 0


def sides(at):
    """``at`` of ``Model.set_velocity`` checked: None, a side name or a list of them."""
    if at is None:
        return None
    names = [at] if isinstance(at, str) else list(at)
    bad = [n for n in names if n not in BOX_SIDES]
    if bad or not names:
        raise ValueError(f"at must name sides of the model's box {sorted(BOX_SIDES)}, got "
                         f"{at!r}")
    return names


def hold(zones, props, soft, held_xy, at) -> None:
    """Hold the deformable blocks ``soft`` as ``Model.set_velocity`` asks: their gridpoints
    on the box sides ``at`` in the directions ``held_xy`` = (x held, y held), their frames
    whole (docs/mechanics.md, "Held deformable blocks")."""
    x, y = held_xy
    if soft.size == 0 or not (x or y):
        return
    hold_points(zones, soft, (FIX_X if x else 0) | (FIX_Y if y else 0), sides(at))
    props.fixity[soft] = FIX_X | FIX_Y | FIX_ROT
