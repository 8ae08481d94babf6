"""Force contributions. Each adds into ``f`` ((nb, 3): fx, fy in N/m, moment in N m/m, CCW +).

A step calls only the contributions its scene has (``integrate.run_steps`` flags), so a scene
without servo or applied loads pays nothing for them.
"""
from __future__ import annotations

import warnings

import numpy as np
from numba import njit
from numba.core.errors import NumbaPerformanceWarning

from .law import coulomb_law

__all__ = ["add_contact_forces", "add_gravity", "add_loads", "servo_velocities"]


@njit(cache=True, inline="always")
def contact_update(k, block_a, block_b, point_a, point_b, normal_b, length, kn, ks, material,
                   strength, sn, ts, un, us, up, broken, slipping, pos, rot):
    """One contact: geometry (contacts.py) and the law (law.py); updates the contact's state
    and returns (fx, fy, xa, ya, event): the force on B (N/m; minus it on A), the contact point
    (m) and the law's event (1 tension failure, 2 shear failure, 3 slip). Shared by the serial
    kernel below and the threaded one (``parallel.py``), so both compute the same numbers."""
    a = block_a[k]
    b = block_b[k]
    ca, sa = rot[a, 0], rot[a, 1]
    cb, sb = rot[b, 0], rot[b, 1]
    xa = pos[a, 0] + ca * point_a[k, 0] - sa * point_a[k, 1]
    ya = pos[a, 1] + sa * point_a[k, 0] + ca * point_a[k, 1]
    dx = pos[b, 0] + cb * point_b[k, 0] - sb * point_b[k, 1] - xa
    dy = pos[b, 1] + sb * point_b[k, 0] + cb * point_b[k, 1] - ya
    nx = cb * normal_b[k, 0] - sb * normal_b[k, 1]
    ny = sb * normal_b[k, 0] + cb * normal_b[k, 1]
    u_n = dx * nx + dy * ny
    u_s = dy * nx - dx * ny
    s_n, t_s, u_p, event = coulomb_law(u_n, u_s, up[k], kn[k], ks[k], strength,
                                       material[k], broken[k])
    sn[k] = s_n
    ts[k] = t_s
    un[k] = u_n
    us[k] = u_s
    up[k] = u_p
    slipping[k] = 1 if (event == 2 or event == 3) else 0
    if event == 1 or event == 2:
        broken[k] = event
    L = length[k]
    return L * (s_n * nx - t_s * ny), L * (s_n * ny + t_s * nx), xa, ya, event


@njit(cache=True, inline="always")
def log_crack(cracks, crack_count, time, xa, ya, event, a, b, m):
    """Append a failure (rows [time, x, y, mode, block_a, block_b, material])."""
    i = crack_count[0]
    if i < cracks.shape[0]:
        cracks[i, 0] = time
        cracks[i, 1] = xa
        cracks[i, 2] = ya
        cracks[i, 3] = event
        cracks[i, 4] = a
        cracks[i, 5] = b
        cracks[i, 6] = m
    crack_count[0] = i + 1


# parallel=True without a prange: numba's parallel pipeline compiles this loop to code that
# ran 11x faster (13 vs 146 ns per contact on the 2-core VM, 2026-11-21; same results to the
# bit) than the plain pipeline; it still runs on the calling thread. Numba warns that it found
# nothing to parallelise: expected here, so that one warning is silenced.
warnings.filterwarnings("ignore", category=NumbaPerformanceWarning,
                        message=r"(?s).*parallel=True.*no transformation for parallel")
@njit(cache=True, parallel=True)
def add_contact_forces(nc, block_a, block_b, point_a, point_b, normal_b, length, kn, ks,
                       material, strength, sn, ts, un, us, up, broken, slipping,
                       pos, rot, f, time, cracks, crack_count):
    """All contacts (``contact_update``), forces added to both blocks in contact order.

    ``rot`` is (nb, 2) [cos theta, sin theta]. A new failure is appended to ``cracks``
    (rows [time, x, y, mode, block_a, block_b, material]) at ``crack_count[0]``.
    """
    for k in range(nc):
        fx, fy, xa, ya, event = contact_update(k, block_a, block_b, point_a, point_b, normal_b,
                                               length, kn, ks, material, strength, sn, ts, un,
                                               us, up, broken, slipping, pos, rot)
        a = block_a[k]
        b = block_b[k]
        if event == 1 or event == 2:
            log_crack(cracks, crack_count, time, xa, ya, event, a, b, material[k])
        f[b, 0] += fx
        f[b, 1] += fy
        f[b, 2] += (xa - pos[b, 0]) * fy - (ya - pos[b, 1]) * fx
        f[a, 0] -= fx
        f[a, 1] -= fy
        f[a, 2] -= (xa - pos[a, 0]) * fy - (ya - pos[a, 1]) * fx


@njit(cache=True)
def add_gravity(mass, active, g, f):
    """Body force m g on every active block (real mass, whatever the inertial mass)."""
    for i in range(mass.shape[0]):
        if active[i]:
            f[i, 0] += mass[i] * g[0]
            f[i, 1] += mass[i] * g[1]


@njit(cache=True)
def add_loads(load, active, f):
    """Constant applied forces and moments (N/m, N m/m)."""
    for i in range(load.shape[0]):
        if active[i]:
            f[i, 0] += load[i, 0]
            f[i, 1] += load[i, 1]
            f[i, 2] += load[i, 2]


@njit(cache=True)
def servo_velocities(servo_offsets, servo_blocks, servo_params, f, velocity_bc):
    """Set each servo group's velocity to hold a target force along its direction.

    ``servo_params`` rows: [dir_x, dir_y, target (N/m), gain (m/s per N/m), v_max (m/s)].
    The group pushes along dir; P = -sum(f . dir) over its blocks is the reaction it feels
    (contact and other forces); the velocity along dir is gain (target - P), clipped to v_max.
    """
    for s in range(servo_offsets.shape[0] - 1):
        dx, dy = servo_params[s, 0], servo_params[s, 1]
        p = 0.0
        for j in range(servo_offsets[s], servo_offsets[s + 1]):
            i = servo_blocks[j]
            p -= f[i, 0] * dx + f[i, 1] * dy
        v = servo_params[s, 3] * (servo_params[s, 2] - p)
        vmax = servo_params[s, 4]
        v = min(max(v, -vmax), vmax)
        for j in range(servo_offsets[s], servo_offsets[s + 1]):
            i = servo_blocks[j]        # replace only the component along dir
            along = velocity_bc[i, 0] * dx + velocity_bc[i, 1] * dy
            velocity_bc[i, 0] += (v - along) * dx
            velocity_bc[i, 1] += (v - along) * dy


def no_servo():
    """Empty servo arrays (the scene has no servo)."""
    return np.zeros(1, np.int64), np.zeros(0, np.int64), np.zeros((0, 5))
