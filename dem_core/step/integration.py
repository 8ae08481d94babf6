"""Damping, integration and the movement checks of the time step (``step.run``): the one
integration of everything that moves. The blocks on one thread (``advance``), on the threads by
chunks of blocks (``advance_parallel``), or for a list of blocks (``advance_range`` with
``blocks``: the threaded step's owned and shared blocks, ``region``); every path runs the one
compiled loop of ``advance_range``, so every block gets the same numbers, bit for bit. Then
``advance_nodes``: the cable and liner nodes (``nodes.advance_support``) and the deformable
blocks' gridpoints (``deformable.component.advance_zones``), with the same dt, damping and kick
(and, in ``relaxation``, the same kinetic-damping stop), from the forces their kernels left.

For each free velocity component:  F_d = f - alpha |f| sign(v)   (local non-viscous damping:
                                   Cundall 1987, "Distinct element models of rock and soil
                                   structure"; Itasca's UDEC manual)
                                   v  += F_d / m_inertial * kick
prescribed components:             v   = v_bc
then x += v dt, theta += omega dt, rot = R(theta). The energy account (``BlockState.work``,
``output.energy``) adds, per component, the work put in through a prescribed one, -f v_bc dt
(the force the contacts and gravity put on the block, held at its velocity), and what local
damping took out of a free one, (f - F_d) (v_old + v_new) / 2 kick (the kinetic-energy change
the damping force made over the kick). ``kick`` (s) is ``dt``, or ``dt / 2`` on the
first step after a kinetic-damping stop (``step.relaxation``). The same for every support node
and gridpoint (velocities at half steps, positions by v dt).

Status codes: 0 done, 1 a block moved more than half the search margin since the last contact
search, 2 unstable (NaN, or a block moving more than a tenth of its radius, or turning 0.1 rad,
in one step).
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..deformable.component import advance_zones
from .nodes import advance_support, damped
from .kinematics import set_rotation

__all__ = ["advance", "advance_range", "advance_parallel", "advance_nodes", "merge_status",
           "DONE", "NEED_SEARCH", "UNSTABLE", "MIN_THREADED_BLOCKS"]

DONE, NEED_SEARCH, UNSTABLE = 0, 1, 2

@njit(cache=True)
def advance(s, p, integ, kick):
    """Damp, integrate, turn and check every block (one pass over the blocks); returns
    (status, block).

    ``s`` BlockState, ``p`` BlockProps, ``integ`` Integrator, ``kick`` (s) the time of the
    velocity update; positions always move by v dt, and each block's ``rot`` and ``rot_half``
    follow its new theta. The checks compare squares (no square roots): unstable when
    |v| dt > radius / 10 or |omega| dt > 0.1 (or NaN), before the block moves (the pass stops
    there); a search is needed when |x - x_search| + |theta - theta_search| radius exceeds half
    the margin. The block named is the unstable one, or the last that needs a search.
    """
    unstable, search = advance_range(s, p, integ, kick, 0, s.pos.shape[0], None)
    return merge_status(unstable, search, s.pos.shape[0])


@njit(cache=True, inline="always")
def merge_status(unstable, search, nb):
    """(status, block) from the first unstable block (``nb``: none) and the last block that
    needs a search (-1: none)."""
    if 0 <= unstable < nb:
        return UNSTABLE, unstable
    if search >= 0:
        return NEED_SEARCH, search
    return DONE, -1


# One compiled loop for the serial pass, each chunk of the threaded one and the block lists of
# the threaded step, so all do the same machine arithmetic. (Written out, not through an
# inlined per-block helper taking the bundles: that made the serial step about 15 % slower,
# benchmarks/throughput.py.)
@njit(cache=True)
def advance_range(s, p, integ, kick, i0, i1, blocks):
    """``advance`` of blocks i0 <= i < i1 (``blocks`` None), or of blocks[i0:i1] (an int64
    array); returns (the first unstable block, which stops the pass before it moves, or -1;
    the last block that needs a search, or -1)."""
    dt, alpha, vel, omega = integ.dt, integ.damping, s.vel, s.omega
    search = -1
    for n in range(i1 - i0):
        # None: numba compiles a loop of its own without the list (a branch on the list in
        # every pass made the serial pass 14-18 % slower)
        if blocks is None:
            b = i0 + n
        else:
            b = blocks[np.uint64(i0 + n)]
        i = np.uint64(b)       # unsigned: no negative-index wraparound on every access
        if not p.active[i]:
            continue
        fx = p.fixity[i]
        f, work = s.force, s.work
        if fx & 1:
            vel[i, 0] = p.velocity_bc[i, 0]
            work[i, 0] -= f[i, 0] * vel[i, 0] * dt
        else:
            v0, fd = vel[i, 0], damped(f[i, 0], vel[i, 0], alpha)
            vel[i, 0] += fd * p.inv_mass[i] * kick
            work[i, 1] += (f[i, 0] - fd) * 0.5 * (v0 + vel[i, 0]) * kick
        if fx & 2:
            vel[i, 1] = p.velocity_bc[i, 1]
            work[i, 0] -= f[i, 1] * vel[i, 1] * dt
        else:
            v0, fd = vel[i, 1], damped(f[i, 1], vel[i, 1], alpha)
            vel[i, 1] += fd * p.inv_mass[i] * kick
            work[i, 1] += (f[i, 1] - fd) * 0.5 * (v0 + vel[i, 1]) * kick
        if fx & 4:
            omega[i] = p.velocity_bc[i, 2]
            work[i, 0] -= f[i, 2] * omega[i] * dt
        else:
            v0, fd = omega[i], damped(f[i, 2], omega[i], alpha)
            omega[i] += fd * p.inv_inertia[i] * kick
            work[i, 1] += (f[i, 2] - fd) * 0.5 * (v0 + omega[i]) * kick
        v_max = 0.1 * p.radius[i] / dt
        if not (vel[i, 0] * vel[i, 0] + vel[i, 1] * vel[i, 1] <= v_max * v_max
                and abs(omega[i]) * dt <= 0.1):             # also catches NaN
            return b, search
        s.pos[i, 0] += vel[i, 0] * dt
        s.pos[i, 1] += vel[i, 1] * dt
        s.theta[i] += omega[i] * dt
        set_rotation(s.theta, s.rot, s.rot_half, i)
        left = integ.half_margin - abs(s.theta[i] - s.theta_search[i]) * p.radius[i]
        dx, dy = s.pos[i, 0] - s.pos_search[i, 0], s.pos[i, 1] - s.pos_search[i, 1]
        if left < 0.0 or dx * dx + dy * dy > left * left:
            search = b
    return -1, search


# the threaded integration pass of the two-region step (a scene with forces other than the
# contacts' and gravity) from this many blocks up: below it the start of a parallel region
# costs more than the pass (benchmarks/two_threads.py; docs/performance.md, "Two threads")
MIN_THREADED_BLOCKS = 30_000

# chunks of ``advance_parallel`` (a chunk is one call, a thread's unit of work), and the
# fewest blocks in a chunk
ADVANCE_CHUNKS, MIN_ADVANCE_CHUNK = 16, 256


@njit(cache=True, parallel=True)
def advance_parallel(s, p, integ, kick):
    """``advance`` on the threads, by chunks of blocks (``advance_range``): every block the
    same numbers. Differs only when a block is unstable: the blocks of the other chunks have
    moved (the run stops there)."""
    nb = s.pos.shape[0]
    chunk = max(MIN_ADVANCE_CHUNK, -(-nb // ADVANCE_CHUNKS))
    first_unstable, last_search = nb, -1
    for jp in prange(-(-nb // chunk)):
        j = np.int64(jp)                # (parallel.add_contact_forces_parallel: why)
        u, n = advance_range(s, p, integ, kick, j * chunk, min(nb, (j + 1) * chunk), None)
        if u >= 0:
            first_unstable = min(first_unstable, u)
        last_search = max(last_search, n)
    return merge_status(first_unstable, last_search, nb)


@njit(cache=True)
def advance_nodes(integ, world, parts, kick):
    """Everything else that moves, after the blocks (``advance``), with their ``integ.dt``,
    local damping ``integ.damping`` and ``kick`` (s): the cable and liner nodes (``parts``'
    bundles; empty: nothing) and the deformable blocks' gridpoints (``world.zones``; None or
    empty: nothing), from the forces their kernels computed this step."""
    advance_support(parts.cables, parts.liners, integ.dt, kick, integ.damping)
    advance_zones(world.zones, world.props, integ.dt, kick, integ.damping)
