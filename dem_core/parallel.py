"""Contact forces on several threads (numba ``prange``), bit-for-bit equal to the serial kernel.

The serial kernel (``forces.add_contact_forces``) adds each contact's force to its two blocks as
it goes: in a parallel loop that is a write race. Here the work is split in three passes:

1. every contact (in parallel, by chunks: about ``CHUNKS_PER_THREAD`` per thread): geometry,
   the law, its force and point,
   stored per contact;
2. the crack log (serially, in contact order, so the log is the same as the serial one),
   reading only the chunks of pass 1 that had a bond failure;
3. every block (in parallel): the sum of its contacts' forces in contact order, read through a
   block -> contact table (CSR) built when the contact list changes; this pass also zeroes
   the block's force first (the step's zeroing, in the same pass).

Each block sums the same numbers in the same order as the serial kernel, so the results are
identical (tests/test_mech_parallel.py). Used when ``Model(threads=n)`` with n > 1 and the
model has at least ``MIN_CONTACTS`` live contacts.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, prange

from .forces import contact_update, edge_correction, log_crack

__all__ = ["Parallel", "contact_table", "add_contact_forces_parallel", "no_parallel",
           "parallel_bundle"]


class Parallel(NamedTuple):
    """Scratch and the block -> contact table of the threaded kernel; all empty: serial.

    work : (nc, 4) float64. Per contact: force on B (N/m) and contact point (m).
    events : (nc,) int64. Per contact: the law's event.
    failures : (number of chunks,) int64. Per chunk of the first pass: its bond failures (the
        crack-log pass reads only the chunks that have some).
    offsets : (nb + 1,) int64, entries : (2 nc,) int64. ``contact_table``.
    chunk : int. Contacts per chunk of the first pass (0 when serial).
    """

    work: np.ndarray
    events: np.ndarray
    failures: np.ndarray
    offsets: np.ndarray
    entries: np.ndarray
    chunk: int


def no_parallel() -> Parallel:
    """The empty bundle: the step runs the serial kernel."""
    return Parallel(np.zeros((0, 4)), np.zeros(0, np.int64), np.zeros(0, np.int64),
                    np.zeros(0, np.int64), np.zeros(0, np.int64), 0)


def parallel_bundle(c, nb, threads) -> Parallel:
    """Scratch and table for the live contacts of ``c`` among ``nb`` blocks, on ``threads``."""
    offsets, entries = contact_table(c.count[0], c.block_a, c.block_b, nb)
    chunk = max(MIN_CHUNK, -(-c.n // (CHUNKS_PER_THREAD * threads)))
    return Parallel(np.empty((c.n, 4)), np.empty(c.n, np.int64),
                    np.zeros(-(-c.n // chunk), np.int64), offsets, entries, chunk)


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


# parallel=True without a prange, as forces.add_contact_forces (numba's parallel pipeline
# compiles the loop much faster than the plain one), and the same inlined contact_update in
# the same kind of loop: the same machine arithmetic as the serial kernel. (Inlining
# contact_update straight into the prange body instead gave different round-off in numba 0.68:
# a shear displacement of 0 where the serial kernel had -3.5e-18 m.)
@njit(cache=True, parallel=True)
def contact_range(c, strength, s, rnd, dfm, work, events, k0, k1):
    """Contacts k0 <= k < k1 (``forces.contact_update``): force on B, point and event stored
    per contact in ``work`` and ``events``; returns the number of bond failures among them."""
    failures = 0
    for k in range(k0, k1):
        fx, fy, xa, ya, event = contact_update(k, c, strength, s, rnd, dfm)
        events[k] = event
        if event == 1 or event == 2:
            failures += 1
        work[k, 0] = fx
        work[k, 1] = fy
        work[k, 2] = xa
        work[k, 3] = ya
    return failures


# below this many live contacts ``Model(threads=n)`` runs the serial kernels (same results):
# thread start-up and the per-contact scratch cost more than a second core gives there (two
# threads: 0.37x one at 6,020 contacts, 1.25x at 61,702; benchmarks/two_threads.py)
MIN_CONTACTS = 30_000

# chunks of the first pass per thread (a chunk is one call, and a thread's unit of work), and
# the fewest contacts in a chunk
CHUNKS_PER_THREAD, MIN_CHUNK = 8, 256


@njit(cache=True, parallel=True)
def add_contact_forces_parallel(c, strength, s, cracks, time, rnd, par, edges, dfm):
    """Same inputs and effect as ``forces.add_contact_forces``, with the ``Parallel`` bundle."""
    work, events, failures = par.work, par.events, par.failures
    nc = c.count[0]
    chunk = par.chunk
    for j in prange(-(-nc // chunk)):
        failures[j] = contact_range(c, strength, s, rnd, dfm, work, events, j * chunk,
                                    min(nc, (j + 1) * chunk))
    for j in range(-(-nc // chunk)):         # the crack log, in contact order
        if failures[j] == 0:
            continue
        for k in range(j * chunk, min(nc, (j + 1) * chunk)):
            event = events[k]
            if event == 1 or event == 2:
                log_crack(cracks, time, work[k, 2], work[k, 3], event, c.block_a[k],
                          c.block_b[k], c.material[k])
    f, pos = s.force, s.pos
    nb = par.offsets.shape[0] - 1
    for i in prange(nb):
        f[i, 0] = 0.0                        # (the step leaves the zeroing to this pass)
        f[i, 1] = 0.0
        f[i, 2] = 0.0
        for j in range(par.offsets[i], par.offsets[i + 1]):
            e = par.entries[j]
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
            p = c.partner[k] if edges else -1
            if 0 <= p < k:                   # the edge's share (forces.edge_correction)
                gx, gy, mb, ma = edge_correction(k, c, s, xa, ya)
                if e & 1:
                    f[i, 0] += gx
                    f[i, 1] += gy
                    f[i, 2] += mb
                else:
                    f[i, 0] -= gx
                    f[i, 1] -= gy
                    f[i, 2] -= ma
