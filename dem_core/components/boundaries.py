"""What the driver's loading verbs do to the bundles: prescribed velocities, applied loads and
excavation, as functions of the arrays they change (``Model.set_velocity``, ``apply_load``,
``remove``). Velocities m/s and rad/s (CCW +), forces N/m, moments N m/m.
"""
from __future__ import annotations

import math

import numpy as np

from ..step.state import FIX_ROT, FIX_X, FIX_Y

__all__ = ["prescribe", "spread_load", "remove_blocks", "set_stress"]


def prescribe(props, state, idx, velocity) -> None:
    """Prescribe ``velocity`` = (vx, vy, omega) of blocks ``idx``; None leaves a component
    free. The blocks take the velocity now; their fixity bits say which components are held."""
    for bit, col, v in zip((FIX_X, FIX_Y, FIX_ROT), range(3), velocity):
        if v is None:
            continue
        if not math.isfinite(v):
            raise ValueError(f"velocity component {col} is {v!r}")
        props.fixity[idx] |= bit
        props.velocity_bc[idx, col] = v
        if col < 2:
            state.vel[idx, col] = v
        else:
            state.omega[idx] = v


def spread_load(load, mass, idx, force) -> None:
    """A total force (fx, fy, N/m) on blocks ``idx``, shared by mass, and a moment (N m/m) on
    each: ``force`` = (fx, fy, moment), written into ``load`` (nb, 3)."""
    fx, fy, moment = force
    if not all(math.isfinite(v) for v in force):
        raise ValueError(f"load must be finite, got {tuple(force)!r}")
    w = mass[idx] / mass[idx].sum()
    load[idx, 0], load[idx, 1], load[idx, 2] = fx * w, fy * w, moment


def remove_blocks(props, state, contacts, idx, name=None):
    """Excavate blocks ``idx`` (group ``name``): inactive, held still; returns the contacts
    without theirs. ValueError naming the group when none of its blocks is left."""
    if not np.any(props.active[idx] > 0):
        name = repr(name) if isinstance(name, str) else f"of blocks {idx.tolist()}"
        raise ValueError(f"remove: group {name} has no blocks left to remove ("
                         f"{'it is empty' if idx.size == 0 else 'all removed already'})")
    props.active[idx], props.fixity[idx], props.velocity_bc[idx] = 0, FIX_X | FIX_Y | FIX_ROT, 0.0
    state.vel[idx], state.omega[idx] = 0.0, 0.0
    c = contacts
    keep = (props.active[c.block_a[:c.n]] > 0) & (props.active[c.block_b[:c.n]] > 0)
    return c.take(np.flatnonzero(keep))


def set_stress(contacts, rows, sn, ts) -> None:
    """Give contacts ``rows`` (None: every live one) a stress: ``sn`` normal (Pa, compression
    +) and ``ts`` shear (Pa, on B along t), scalars or arrays over the rows; the law carries on
    from it by increments (``contact.law``)."""
    c = contacts
    rows = np.arange(c.n) if rows is None else np.asarray(rows, dtype=np.int64)
    sn = np.broadcast_to(np.asarray(sn, dtype=np.float64), rows.shape)
    ts = np.broadcast_to(np.asarray(ts, dtype=np.float64), rows.shape)
    if not (np.all(np.isfinite(sn)) and np.all(np.isfinite(ts))):
        raise ValueError("contact stresses must be finite (Pa)")
    c.sn[rows], c.sn_elastic[rows], c.ts[rows] = sn, sn, ts
