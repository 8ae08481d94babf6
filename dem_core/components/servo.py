"""Servo-controlled groups: a group moved along a direction so that the reaction it feels stays
at a target force (constant normal stress on a shear box or a platen)."""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = ["Servo", "servo_bundle", "servo_row", "servo_velocities"]


class Servo(NamedTuple):
    """offsets : (ns + 1,) int64. CSR of each servo's blocks in ``blocks`` (ns = 0: none).
    blocks : (m,) int64.
    params : (ns, 5) float64. [dir_x, dir_y, target force N/m, gain (m/s)/(N/m), v_max m/s]."""

    offsets: np.ndarray
    blocks: np.ndarray
    params: np.ndarray


def servo_bundle(groups) -> Servo:
    """From a list of (block indices, params row); empty list: no servo."""
    if not groups:
        return Servo(np.zeros(1, np.int64), np.zeros(0, np.int64), np.zeros((0, 5)))
    offs = np.concatenate([[0], np.cumsum([len(g) for g, _ in groups])]).astype(np.int64)
    blocks = np.concatenate([g for g, _ in groups]).astype(np.int64)
    return Servo(offs, blocks, np.array([prm for _, prm in groups], dtype=np.float64))


def servo_row(contacts, idx, force, direction, gain, v_max, dt):
    """(params row (5,), fixity bits) of a servo on blocks ``idx`` keeping ``force`` (N/m)
    along ``direction``; the default ``gain`` moves the group by 1/10 of the force error's
    elastic displacement per step of ``dt`` (the stiffness of the contacts it feels)."""
    from ..step.state import FIX_ROT, FIX_X, FIX_Y

    d = np.asarray(direction, dtype=np.float64)
    d = d / np.hypot(*d)
    if not (np.isfinite(force) and force >= 0):
        raise ValueError(f"servo force must be finite and >= 0 N/m, got {force!r}")
    c = contacts
    ing = np.isin(c.block_a[:c.n], idx) ^ np.isin(c.block_b[:c.n], idx)
    k = float((c.kn[:c.n][ing] * c.length[:c.n][ing]).sum()) or 1.0
    gain = 0.1 / (k * dt) if gain is None else float(gain)
    v_max = np.inf if v_max is None else float(v_max)
    bits = (FIX_X if abs(d[0]) > 0 else 0) | (FIX_Y if abs(d[1]) > 0 else 0) | FIX_ROT
    return np.array([d[0], d[1], force, gain, v_max]), bits


@njit(cache=True)
def servo_velocities(servo, s, p):
    """Set each servo group's velocity along its direction from the force it feels.

    P = -sum(f . dir) over the group's blocks is the reaction (every force of the step: it runs
    after all other contributions); the velocity along dir is gain (target - P), clipped to
    v_max, written into ``p.velocity_bc`` (the other component is kept).
    """
    f, vbc = s.force, p.velocity_bc
    for g in range(servo.offsets.shape[0] - 1):
        dx, dy = servo.params[g, 0], servo.params[g, 1]
        reaction = 0.0
        for j in range(servo.offsets[g], servo.offsets[g + 1]):
            i = servo.blocks[j]
            reaction -= f[i, 0] * dx + f[i, 1] * dy
        v = servo.params[g, 3] * (servo.params[g, 2] - reaction)
        vmax = servo.params[g, 4]
        v = min(max(v, -vmax), vmax)
        for j in range(servo.offsets[g], servo.offsets[g + 1]):
            i = servo.blocks[j]
            along = vbc[i, 0] * dx + vbc[i, 1] * dy
            vbc[i, 0] += (v - along) * dx
            vbc[i, 1] += (v - along) * dy
