"""Many steps in one parallel region, for a scene whose only force besides the contacts' is gravity.

``run_steps_region`` is ``step.run_steps`` on the threads, bit for bit. A step: each chunk's
contacts (``forces.chunk_forces``), then gravity and the moves of the blocks the chunk owns
(``parallel``: all their contacts are in the chunk, so their forces are complete); then,
serially, the crack log, the shared blocks' forces, gravity and moves, the time, kinetic
damping and the next step's kick. The threads stay in one region for all the steps of the
call: entering a region costs its second thread a wake-up (a few per cent of a 1e4-block step
and more than a 1e3-block step: docs/performance.md, "Many steps in one region"), paid here
once per call (``Model.cycle`` calls every ``history_every`` steps) instead of once
per step.

The threads keep step with three counters (``atomics``), never with a lock:

- ``claimed[j]``: the steps of chunk j taken so far. A thread takes chunk j of step n by moving
  ``claimed[j]`` from n to n + 1 (compare-and-exchange): each chunk of each step is done by
  exactly one thread. A thread tries its own chunk first (its data stays in its core's cache),
  then the others;
- ``done``: the chunks finished over all steps. The thread that finishes the last chunk of
  step n (``done`` reaches (n + 1) x chunks) closes the step: the serial part;
- ``released``: the steps closed. A thread starts step n only once ``released`` >= n
  (``load_acquire``; the closing thread's writes are then seen), and closes step n with
  ``store_release(released, n + 1)``.

No thread ever waits for a chunk no thread has taken: it takes every untaken chunk of its step
itself before it waits. So the region finishes whatever number of threads the layer actually
runs (one thread alone does every chunk of every step: the serial arithmetic, no deadlock), and
a thread that starts late (a sleeping TBB worker) skips the steps already closed. A step that
ends the call (a search needed, an unstable block, the last step) sets ``end`` before it is
released; threads stop at ``end``.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .atomics import (compare_exchange, fetch_add, load_acquire, spin_pause, store_release,
                      yield_cpu)
from ...components.gravity import add_gravity_to
from ...contact.forces import chunk_forces
from ..integration import DONE, NEED_SEARCH, UNSTABLE, advance_range, merge_status
from .parallel import ONE_REGION_MIN_CONTACTS, log_failures, shared_forces
from ..relaxation import end_step, next_kick
from ..world import World

__all__ = ["run_steps_region", "MIN_CONTACTS"]

# below this many live contacts ``Model(threads=n)`` runs the serial kernels when the step is
# this one region (``parallel.ONE_REGION_MIN_CONTACTS``)
MIN_CONTACTS = ONE_REGION_MIN_CONTACTS

# a waiting thread spins this many times (with x86 ``pause``), then yields its core at every
# turn
SPINS = 20_000

# the slots of the int64 ``sync`` array
RELEASED, DONE_CHUNKS, END, STATUS, BAD = 0, 1, 2, 3, 4


@njit(cache=True)
def run_steps_region(nsteps, time, integ, world, gravity, par):
    """Up to ``nsteps`` steps in one region; returns (steps done, time, status, block) as
    ``step.run_steps``; ``world`` the step's World record (``step/world.py``), ``gravity``
    its only other force, ``par`` the Parallel bundle. Only a step with an unstable block
    differs from the serial one: the other chunks' blocks have moved (the run stops there)."""
    if nsteps <= 0:
        return 0, time, DONE, -1
    chunks = par.first.shape[0] - 1
    sync = np.zeros(5, np.int64)
    sync[END], sync[STATUS], sync[BAD] = nsteps, DONE, -1
    clock = np.array([time, next_kick(integ)])        # this step's time and kick (s)
    claimed = np.zeros(chunks, np.int64)
    results = np.empty((chunks, 2), np.int64)          # first unstable, last search, by chunk
    _region(nsteps, integ, world.state, world.props, world.contacts, world.strength,
            world.cracks, world.corners, world.zones, gravity, par, sync, clock, claimed,
            results)
    return sync[END], clock[0], sync[STATUS], sync[BAD]


# The World's members one by one: numba's parallel region takes a record of arrays (integ,
# par) but not a record of records (its gufunc wrapper refuses the World), so the region
# takes the members and each thread's worker gets the World built again. The scratch arrays
# are made by the caller: numba 0.68.1 read back, after a prange loop, the values from before
# it of an array the same function had allocated and the loop had written through a called
# function (docs/history.md).
@njit(cache=True, parallel=True)
def _region(nsteps, integ, s, p, c, strength, cracks, corners, zones, gravity, par, sync,
            clock, claimed, results):
    """The threads, one ``_worker`` each."""
    for jp in prange(claimed.shape[0]):
        _worker(np.int64(jp), nsteps, integ, World(s, p, c, strength, cracks, corners, zones),
                gravity, par, sync, clock, claimed, results)


@njit(cache=True)
def _worker(own, nsteps, integ, world, gravity, par, sync, clock, claimed, results):
    """One thread's loop over the steps (module docstring)."""
    chunks = claimed.shape[0]
    n = 0
    while True:
        released = load_acquire(sync, RELEASED)
        spins = 0
        while released < n:                          # step n - 1 not closed yet
            spins += 1
            if spins > SPINS:        # the closing thread may be waiting for a core
                yield_cpu()
            else:
                spin_pause()
            released = load_acquire(sync, RELEASED)
        n = released                                 # a late thread skips closed steps
        if n >= load_acquire(sync, END):
            return
        for q in range(chunks):
            j = (own + q) % chunks
            if not compare_exchange(claimed, j, n, n + 1):
                continue                             # another thread has it
            _chunk(j, integ, world, gravity, par, clock, results)
            if fetch_add(sync, DONE_CHUNKS, 1) + 1 == (n + 1) * chunks:
                _close(n, nsteps, integ, world, gravity, par, sync, clock, results)
        n += 1


@njit(cache=True)
def _chunk(j, integ, world, gravity, par, clock, results):
    """Chunk j's contacts, then gravity and the moves of the blocks it owns."""
    s, p = world.state, world.props
    par.failures[j] = chunk_forces(world.contacts, world.strength, s, world.corners,
                                   world.zones, par, integ.edge_elements, j, world.cracks,
                                   clock[0])
    r0, r1 = par.own_offsets[j], par.own_offsets[j + 1]
    add_gravity_to(gravity, s, p, par.own_blocks, r0, r1)
    results[j, 0], results[j, 1] = advance_range(s, p, integ, clock[1], r0, r1,
                                                 par.own_blocks)


@njit(cache=True)
def _close(n, nsteps, integ, world, gravity, par, sync, clock, results):
    """The serial end of step n: crack log, shared blocks, status, time, kinetic damping, the
    next kick; then step n is released."""
    s, p, c = world.state, world.props, world.contacts
    nb = s.pos.shape[0]
    log_failures(c, world.cracks, clock[0], par)
    shared_forces(c, s, par, integ.edge_elements)
    ns = par.shared.shape[0]
    add_gravity_to(gravity, s, p, par.shared, 0, ns)
    first_unstable, last_search = nb, -1
    for j in range(results.shape[0]):
        if results[j, 0] >= 0:
            first_unstable = min(first_unstable, results[j, 0])
        last_search = max(last_search, results[j, 1])
    if first_unstable == nb:
        u, m = advance_range(s, p, integ, clock[1], 0, ns, par.shared)
        first_unstable = u if u >= 0 else nb
        last_search = max(last_search, m)
    status, bad = merge_status(first_unstable, last_search, nb)
    sync[STATUS], sync[BAD] = status, bad
    if status == UNSTABLE:
        sync[END] = n                                # the step is not done: no time, no damping
    else:
        clock[0] += integ.dt
        end_step(integ, world, None)          # (no support here: ``run.only_gravity``)
        if status == NEED_SEARCH or n + 1 >= nsteps:
            sync[END] = n + 1
        else:
            clock[1] = next_kick(integ)
    store_release(sync, RELEASED, n + 1)
