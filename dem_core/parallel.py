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

from .forces import contact_update, log_crack

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
        fx, fy, xa, ya, event = contact_update(k, block_a, block_b, point_a, point_b, normal_b,
                                               length, kn, ks, material, strength, sn, ts, un,
                                               us, up, broken, slipping, pos, rot)
        events[k] = event
        work[k, 0] = fx
        work[k, 1] = fy
        work[k, 2] = xa
        work[k, 3] = ya
    for k in range(nc):                      # the crack log, in contact order
        event = events[k]
        if event == 1 or event == 2:
            log_crack(cracks, crack_count, time, work[k, 2], work[k, 3], event, block_a[k],
                      block_b[k], material[k])
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
