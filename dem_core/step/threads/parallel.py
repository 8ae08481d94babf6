"""Contact forces on several threads (numba ``prange``), bit-for-bit equal to the serial kernel.

The serial kernel (``forces.add_contact_forces``) adds each contact's force to its two blocks as
it goes, in contact order. The contacts are ordered by their lower block
(``detection.sort_for_locality``), so a contiguous range of contacts touches a band of blocks.
Here the contact list is cut into one range (a *chunk*) per thread, and each block is either

- *owned* by a chunk: all its contacts lie in that chunk. The chunk's thread zeroes its force
  and adds its contacts' forces as it goes, in contact order, as the serial kernel does: no
  other thread writes to it, and it gets the same numbers in the same order; or
- *shared*: its contacts lie in two or more chunks (the blocks along a band's edge, about a row
  of blocks per cut), or it has none. The chunks store those contacts' forces and points in a
  scratch array, and after the parallel region one serial pass zeroes each shared block and
  adds its contacts' forces in contact order through a block -> contact table.

So every block sums the same numbers in the same order as the serial kernel and the results
are bit for bit the same (tests/test_mech_parallel.py). A bond failure is kept per contact
(event and point) and logged after the region in contact order, reading only the chunks that
had one, so the crack log is the serial one too. The traffic is the serial kernel's: the
scratch is written only for the contacts of shared blocks and for failures.

Used when ``Model(threads=n)`` with n > 1 and the model has at least ``MIN_CONTACTS`` live
contacts. An edge element's correction (``forces.edge_correction``) needs its partner contact
updated first: the partner joins the same two blocks, so for an owned block it lies in the same
chunk, before it. For a shared block, the chunk computes it when the partner lies in the same
chunk (kept in ``Parallel.edge_work``); otherwise both blocks have contacts in two chunks, so
both are shared, and the serial pass computes it after all contacts are updated.

When gravity is the only other force, each step is one pass of the threads (``region``, which
also keeps the threads in one region for many steps): an owned block's force is complete when
its chunk's contacts are done, and no other chunk reads it, so the chunk's thread adds its
gravity and moves it there; the shared blocks follow in the serial part of the step. That is
why the shared pass never reads an owned block's pose: it may already have moved.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from ...contact.forces import chunk_forces, edge_correction, log_crack
from ..state import Parallel, no_parallel

__all__ = ["Parallel", "contact_table", "add_contact_forces_parallel", "log_failures",
           "shared_forces", "no_parallel", "parallel_bundle", "chunk_owners"]


def parallel_bundle(c, nb, threads, edges=False) -> Parallel:
    """Chunks, owners and table for the live contacts of ``c`` among ``nb`` blocks, one chunk
    per thread (``threads``); ``edges``: the model has edge elements (scratch for their
    shares)."""
    nc = int(c.count[0])
    chunks = max(1, min(threads, nc))
    first = np.array([nc * j // chunks for j in range(chunks + 1)], np.int64)
    owner = chunk_owners(first, c.block_a, c.block_b, nb)
    own_offsets, own_blocks = _owned(owner, chunks)
    shared = np.flatnonzero(owner < 0).astype(np.int64)
    offsets, entries = contact_table(nc, c.block_a, c.block_b, nb, shared)
    return Parallel(first, owner, own_offsets, own_blocks, shared, offsets, entries,
                    np.empty((c.n, 4)), np.empty((c.n if edges else 0, 4)),
                    np.zeros(c.n, np.int8), np.zeros(chunks, np.int64))


@njit(cache=True)
def chunk_owners(first, block_a, block_b, nb):
    """(nb,) the chunk holding all of each block's contacts, or -1: in several, or in none."""
    owner = np.full(nb, -2, np.int64)              # -2: no contact yet
    for j in range(first.shape[0] - 1):
        for k in range(first[j], first[j + 1]):
            for i in (block_a[k], block_b[k]):
                if owner[i] == -2:
                    owner[i] = j
                elif owner[i] != j:
                    owner[i] = -1
    for i in range(nb):
        if owner[i] == -2:
            owner[i] = -1
    return owner


def _owned(owner, chunks):
    """(offsets (chunks + 1,), blocks): the blocks each chunk owns, by chunk."""
    blocks = np.flatnonzero(owner >= 0)
    blocks = blocks[np.argsort(owner[blocks], kind="stable")].astype(np.int64)
    counts = np.bincount(owner[owner >= 0], minlength=chunks)
    return np.concatenate([[0], np.cumsum(counts)]).astype(np.int64), blocks


@njit(cache=True)
def contact_table(nc, block_a, block_b, nb, blocks):
    """(offsets (len(blocks) + 1,), entries): the contacts of each of ``blocks`` in contact
    order; an entry is 2 k for block A of contact k, 2 k + 1 for block B."""
    row = np.full(nb, -1, np.int64)
    for r in range(blocks.shape[0]):
        row[blocks[r]] = r
    count = np.zeros(blocks.shape[0] + 1, np.int64)
    for k in range(nc):
        for i in (block_a[k], block_b[k]):
            if row[i] >= 0:
                count[row[i] + 1] += 1
    for r in range(blocks.shape[0]):
        count[r + 1] += count[r]
    fill = count[:-1].copy()
    entries = np.empty(count[-1], np.int64)
    for k in range(nc):
        ra, rb = row[block_a[k]], row[block_b[k]]
        if ra >= 0:
            entries[fill[ra]] = 2 * k
            fill[ra] += 1
        if rb >= 0:
            entries[fill[rb]] = 2 * k + 1
            fill[rb] += 1
    return count, entries


# below this many live contacts ``Model(threads=n)`` runs the serial kernels (same results)
# when the step takes a region a step (a force besides gravity and the contacts'): starting a
# region costs more than a second core gives there (two threads against one:
# benchmarks/two_threads.py, the measured speed-ups in docs/performance.md, "Two threads").
MIN_CONTACTS = 15_000
# the same when the step is one region (gravity the only force besides the contacts':
# ``region.run_steps_region``): two threads against one, 200-3,000 steps a call, gain from
# about 1,800 contacts (docs/performance.md, "Many steps in one region")
ONE_REGION_MIN_CONTACTS = 3_000


# Each chunk calls forces.chunk_forces, the serial kernel's own loop (the same machine
# arithmetic; inlining the contact update straight into the prange body instead gave different
# round-off in numba 0.68: a shear displacement of 0 where the serial kernel had -3.5e-18 m).
@njit(cache=True, parallel=True)
def add_contact_forces_parallel(c, strength, s, cracks, time, rnd, par, edges, zones):
    """Same inputs and effect as ``forces.add_contact_forces``, with the ``Parallel`` bundle
    (which also zeroes the forces: the step leaves that to this kernel)."""
    failures = par.failures
    chunks = par.first.shape[0] - 1
    for jp in prange(chunks):
        # numba types a prange index int64 when it types this function and uint64 when it
        # builds the threads' function, and so compiled chunk_forces twice (each a long cold
        # start: docs/performance.md, "The serial kernel and numba's pipelines"); the cast
        # leaves one signature
        j = np.int64(jp)
        failures[j] = chunk_forces(c, strength, s, rnd, zones, par, edges, j, cracks, time)
    log_failures(c, cracks, time, par)
    shared_forces(c, s, par, edges)


@njit(cache=True)
def log_failures(c, cracks, time, par):
    """The chunks' bond failures appended to the crack log in contact order (the serial
    kernel's order)."""
    for j in range(par.failures.shape[0]):
        if par.failures[j] == 0:
            continue
        for k in range(par.first[j], par.first[j + 1]):
            event = par.events[k]
            if event != 0:
                log_crack(cracks, time, par.work[k, 2], par.work[k, 3], event, c.block_a[k],
                          c.block_b[k], c.material[k])
                par.events[k] = 0


@njit(cache=True, inline="always")
def shared_forces(c, s, par, edges):
    """Each shared block's force: zeroed, then its contacts' forces from ``par.work`` added in
    contact order (the serial kernel's order), with the edge elements' shares. An edge whose
    two contacts lie in two chunks gets its share here, once (``edge_correction`` keeps the
    edge's compressed length and may scale a shear stress), before either block sums it."""
    f, pos, work = s.force, s.pos, par.work
    if edges:
        for r in range(par.shared.shape[0]):
            for j in range(par.offsets[r], par.offsets[r + 1]):
                e = par.entries[j]
                k = e >> 1
                p = c.partner[k]
                if e & 1 and 0 <= p < k and not _same_chunk(par.first, p, k):
                    gx, gy, mb, ma = edge_correction(k, c, s, work[k, 2], work[k, 3])
                    par.edge_work[k, 0] = gx
                    par.edge_work[k, 1] = gy
                    par.edge_work[k, 2] = mb
                    par.edge_work[k, 3] = ma
    for r in range(par.shared.shape[0]):
        i = par.shared[r]
        f[i, 0] = 0.0
        f[i, 1] = 0.0
        f[i, 2] = 0.0
        for j in range(par.offsets[r], par.offsets[r + 1]):
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
            if 0 <= p < k:                   # the edge's share (forces.edge_correction):
                gx, gy, mb, ma = (par.edge_work[k, 0], par.edge_work[k, 1],  # by its chunk
                                  par.edge_work[k, 2], par.edge_work[k, 3])  # or above
                if e & 1:
                    f[i, 0] += gx
                    f[i, 1] += gy
                    f[i, 2] += mb
                else:
                    f[i, 0] -= gx
                    f[i, 1] -= gy
                    f[i, 2] -= ma


@njit(cache=True, inline="always")
def _same_chunk(first, p, k):
    """True when contacts p < k lie in the same chunk (no chunk starts in p < start <= k)."""
    for j in range(1, first.shape[0] - 1):
        if p < first[j] <= k:
            return False
    return True


def threads_bundle(contacts, n_blocks, threads, edge_elements, one_region) -> Parallel:
    """The Parallel bundle of a model on ``threads`` threads, or the empty one (serial) when
    one thread is asked for or the model has too few live contacts for threads to pay:
    ``MIN_CONTACTS``, or ``ONE_REGION_MIN_CONTACTS`` when the step is one parallel region
    (``one_region``: gravity the only force besides the contacts')."""
    if threads <= 1:
        return no_parallel()
    if contacts.n < (ONE_REGION_MIN_CONTACTS if one_region else MIN_CONTACTS):
        return no_parallel()
    import numba
    numba.set_num_threads(threads)
    return parallel_bundle(contacts, n_blocks, threads, edge_elements)
