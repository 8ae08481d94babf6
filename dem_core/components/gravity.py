"""Gravity: the body force m g on every active block (real mass, whatever the inertial mass
under mass scaling). A centrifuge g-level is the same force with a larger g."""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = ["Gravity", "add_gravity", "add_gravity_to", "gravity_bundle"]


class Gravity(NamedTuple):
    """accel : (k, 2) float64, m/s^2. The acceleration of gravity; k = 0 when the scene has
    none (the kernel then does nothing), k = 1 otherwise."""

    accel: np.ndarray


def gravity_bundle(accel) -> Gravity:
    """The bundle for acceleration ``accel`` (2,) m/s^2; empty when it is zero."""
    g = np.asarray(accel, dtype=np.float64).reshape(1, 2)
    return Gravity(g if np.any(g != 0.0) else np.zeros((0, 2)))


@njit(cache=True)
def add_gravity(grav, s, p):
    """f_i += m_i g for every active block i (N/m)."""
    add_gravity_to(grav, s, p, None, 0, p.mass.shape[0])


@njit(cache=True)
def add_gravity_to(grav, s, p, blocks, r0, r1):
    """f_i += m_i g for the active blocks r0 <= i < r1 (``blocks`` None), or blocks[r0:r1] (an
    int64 array: the threaded step's owned and shared blocks,
    ``region``)."""
    for r in range(grav.accel.shape[0]):
        gx, gy = grav.accel[r, 0], grav.accel[r, 1]
        for n in range(r1 - r0):
            if blocks is None:          # (numba compiles each case without the other)
                b = r0 + n
            else:
                b = blocks[np.uint64(r0 + n)]
            i = np.uint64(b)            # unsigned: no negative-index wraparound
            if p.active[i]:
                s.force[i, 0] += p.mass[i] * gx
                s.force[i, 1] += p.mass[i] * gy
