"""Contact forces on several threads (numba ``prange``), bit-for-bit equal to the serial kernel.

The serial kernel (``forces.add_contact_forces``) adds each contact's force to its two blocks as
it goes: in a parallel loop that is a write race. Here the work is split in three passes:

1. every contact (in parallel): geometry, the law, its force and point, stored per contact;
2. the crack log (serially, in contact order, so the log is the same as the serial one);
3. every block (in parallel): the sum of its contacts' forces in contact order, read through a
   block -> contact table (CSR) built when the contact list changes.

Each block sums the same numbers in the same order as the serial kernel, so the results are
identical (tests/test_mech_parallel.py). Used when ``Model(threads=n)`` with n > 1.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .law import coulomb_law

__all__ = ["contact_table", "add_contact_forces_parallel"]


@njit(cache=True)
def contact_table(nc, block_a, block_b, nb):
    """(offsets (nb + 1,), entries (2 nc,)): the contacts of each block in contact order; an
    entry is 2 k for block A of contact k (force subtracted), 2 k + 1 for block B (added)."""
    count = np.zeros(nb + 1, np.int64)
    for k in range(nc):
        count[block_a[k] + 1] += 1
        count[block_b[k] + 1] += 1
    for i in range(nb):
        count[i + 1] += count[i]
    fill = count[:-1].copy()
    entries = np.empty(2 * nc, np.int64)
    for k in range(nc):
        a, b = block_a[k], block_b[k]
        entries[fill[a]] = 2 * k
        fill[a] += 1
        entries[fill[b]] = 2 * k + 1
        fill[b] += 1
    return count, entries


@njit(cache=True, parallel=True)
def add_contact_forces_parallel(nc, block_a, block_b, point_a, point_b, normal_b, length, kn,
                                ks, material, strength, sn, ts, un, us, up, broken, slipping,
                                pos, rot, f, time, cracks, crack_count, work, events,
                                table_offsets, table_entries):
    """Same inputs and effect as ``forces.add_contact_forces``; ``work`` (>= nc, 4) and
    ``events`` (>= nc,) are scratch, ``table_*`` from ``contact_table``."""
    for k in prange(nc):
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
        events[k] = event
        if event == 1 or event == 2:
            broken[k] = event
        L = length[k]
        work[k, 0] = L * (s_n * nx - t_s * ny)
        work[k, 1] = L * (s_n * ny + t_s * nx)
        work[k, 2] = xa
        work[k, 3] = ya
    for k in range(nc):                      # the crack log, in contact order
        event = events[k]
        if event == 1 or event == 2:
            i = crack_count[0]
            if i < cracks.shape[0]:
                cracks[i, 0] = time
                cracks[i, 1] = work[k, 2]
                cracks[i, 2] = work[k, 3]
                cracks[i, 3] = event
                cracks[i, 4] = block_a[k]
                cracks[i, 5] = block_b[k]
                cracks[i, 6] = material[k]
            crack_count[0] = i + 1
    nb = table_offsets.shape[0] - 1
    for i in prange(nb):
        for j in range(table_offsets[i], table_offsets[i + 1]):
            e = table_entries[j]
            k = e >> 1
            fx, fy, xa, ya = work[k, 0], work[k, 1], work[k, 2], work[k, 3]
            if e & 1:
                f[i, 0] += fx
                f[i, 1] += fy
                f[i, 2] += (xa - pos[i, 0]) * fy - (ya - pos[i, 1]) * fx
            else:
                f[i, 0] -= fx
                f[i, 1] -= fy
                f[i, 2] -= (xa - pos[i, 0]) * fy - (ya - pos[i, 1]) * fx
