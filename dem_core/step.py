"""The explicit time step: central differences (leapfrog) with local non-viscous damping.

One step (``run_steps`` loops it inside numba, no Python in between)::

    f  = 0
    f += contact forces                      forces.py / parallel.py (law.py)
    f += gravity                             components/gravity.py   (empty bundle: nothing)
    f += applied loads                       components/loads.py
    f += water pressure                      components/water.py
    f += cables and bolts (grout); their     components/cables.py
         nodes move one step
    f += liners (bond); their nodes move     components/liner.py
    servo velocities from f                  components/servo.py: last, so it reacts to every
                                             force of the step
    deformable blocks' zones: their forces   components/deformable.py (empty bundle: nothing)
         (elastic, the contacts' shares),
         the rigid part off; they move
    for each free velocity component:  F_d = f - alpha |f| sign(v)        (local damping)
                                       v  += F_d / m_inertial * dt
    prescribed components:             v   = v_bc
    x += v dt;  theta += omega dt;  rot = R(theta);  checks (stability, search needed)
    kinetic damping (every ``kinetic_interval`` steps; a stop also stops the zones)

With threads (``Model(threads=n)``, a non-empty ``Parallel`` bundle) ``run_steps_threaded``
runs the same step with ``parallel.add_contact_forces_parallel`` (which also zeroes f, block
by block) and the damping and integration ``advance_parallel`` (from ``MIN_THREADED_BLOCKS``
blocks up): the same numbers for every block, bit for bit.

Velocities live at half steps (t - dt/2, t + dt/2), positions at whole steps. With alpha = 0 the
scheme is symplectic: energy oscillates by O((omega dt)^2) and does not drift.

Kinetic damping (dynamic relaxation, ``Integrator.kinetic_interval`` > 0): every that many steps
the kinetic energy of the free velocity components (inertial masses) is compared with the last
check; when it has fallen, the model has just passed a kinetic-energy peak, i.e. its lowest
active mode is near its static position, and every free velocity is set to zero. The motion
restarts as leapfrog starts from rest: the first velocity update after the stop is half a step
(v = a dt/2), which makes the stopped position a turning point of every mode (a plain v = 0
restart starts each fast mode with its amplitude divided by cos(omega dt/2): docs/history.md).
The interval must stay well below a quarter of the slowest period; local damping converges a
slender model's lowest bending mode only over many of its periods, kinetic damping within a few
quarter periods. Prescribed velocities are kept.

Run status codes: 0 done, 1 a block moved more than half the search margin since the last
contact search (the driver searches and continues), 2 unstable (NaN, or a block moving more than
a tenth of its radius, or turning 0.1 rad, in one step; ``bad`` names the block).
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .components import add_cables, add_gravity, add_liners, add_loads, add_water, servo_velocities
from .components.deformable import add_deformable, zone_kinetic_energy
from .components.nodes import damped
from .forces import add_contact_forces
from .kinematics import body_point, set_rotation
from .parallel import add_contact_forces_parallel

__all__ = ["run_steps", "run_steps_threaded", "frequency_bound", "free_kinetic_energy", "stop_free_motion",
           "advance", "advance_parallel", "DONE", "NEED_SEARCH", "UNSTABLE"]

DONE, NEED_SEARCH, UNSTABLE = 0, 1, 2


@njit(cache=True)
def run_steps(nsteps, time, integ, s, p, c, strength, cracks, rnd, gravity, loads, water,
              cables, liners, servo, dfm):
    """Advance up to ``nsteps`` steps on one thread; returns (steps done, time, status, block).

    ``integ`` Integrator, ``s`` BlockState, ``p`` BlockProps, ``c`` Contacts, ``strength`` the
    material table's (nm, 7) rows, ``cracks`` CrackLog, ``rnd`` the corners' Rounding (empty:
    sharp corners), then the component bundles (the last, ``dfm``, the deformable blocks'
    zones, is also read by the contact kernels). Stops early with status 1 (search needed,
    after completing the step) or 2 (unstable, before moving).
    """
    for step in range(nsteps):
        s.force[:] = 0.0
        add_contact_forces(c, strength, s, cracks, time, rnd, integ.edge_elements, dfm)
        kick = add_other_forces(integ, s, p, c, gravity, loads, water, cables, liners, servo,
                                dfm)
        status, bad = advance(s, p, integ, kick)
        if status == UNSTABLE:
            return step, time, UNSTABLE, bad
        time += integ.dt
        end_step(integ, s, p, dfm)
        if status == NEED_SEARCH:
            return step + 1, time, NEED_SEARCH, bad
    return nsteps, time, DONE, -1


# A function of its own, not a branch of ``run_steps``: a serial model then never compiles the
# threaded kernels (150 s of numba's first compile of a small model, docs/performance.md).
@njit(cache=True)
def run_steps_threaded(nsteps, time, integ, s, p, c, strength, cracks, rnd, par, gravity,
                       loads, water, cables, liners, servo, dfm):
    """``run_steps`` on the threads: ``par`` the Parallel bundle (chunks and scratch); the
    same numbers, bit for bit."""
    for step in range(nsteps):
        add_contact_forces_parallel(c, strength, s, cracks, time, rnd, par,  # (zeroes f)
                                    integ.edge_elements, dfm)
        kick = add_other_forces(integ, s, p, c, gravity, loads, water, cables, liners, servo,
                                dfm)
        if s.pos.shape[0] < MIN_THREADED_BLOCKS:
            status, bad = advance(s, p, integ, kick)
        else:
            status, bad = advance_parallel(s, p, integ, kick)
        if status == UNSTABLE:
            return step, time, UNSTABLE, bad
        time += integ.dt
        end_step(integ, s, p, dfm)
        if status == NEED_SEARCH:
            return step + 1, time, NEED_SEARCH, bad
    return nsteps, time, DONE, -1


@njit(cache=True)
def add_other_forces(integ, s, p, c, gravity, loads, water, cables, liners, servo, dfm):
    """Every force but the contacts', the servos, and the deformable blocks' zones (which move
    here); returns the time of this step's velocity kick (s): ``dt``, or ``dt / 2`` on the
    first step after a kinetic-damping stop."""
    add_gravity(gravity, s, p)
    add_loads(loads, s, p)
    add_water(water, s, p)
    add_cables(cables, s, p)
    add_liners(liners, s, p)
    servo_velocities(servo, s, p)
    kick = 0.5 * integ.dt if integ.kinetic[2] != 0.0 else integ.dt
    add_deformable(dfm, c, s, p, kick)
    integ.kinetic[2] = 0.0
    return kick


@njit(cache=True)
def end_step(integ, s, p, dfm):
    """Kinetic damping after the blocks moved (a stop also stops the zones)."""
    kinetic_damping(integ, s, p, dfm)
    if integ.kinetic[2] != 0.0:
        dfm.v[:] = 0.0


@njit(cache=True)
def advance(s, p, integ, kick):
    """Damp, integrate, turn and check every block (one pass over the blocks); returns
    (status, block).

    ``kick`` (s): the time of the velocity update (``dt``, or ``dt / 2`` on the first step after
    a kinetic-damping stop); positions always move by v dt, and each block's ``rot`` and
    ``rot_half`` follow its new theta. The checks compare squares (no square roots): unstable
    when |v| dt > radius / 10 or |omega| dt > 0.1 (or NaN), before the block moves (the pass
    stops there); a search is needed when |x - x_search| + |theta - theta_search| radius
    exceeds half the margin. The block named is the unstable one, or the last that needs a
    search.
    """
    unstable, search = advance_range(s, p, integ, kick, 0, s.pos.shape[0])
    if unstable >= 0:
        return UNSTABLE, unstable
    if search >= 0:
        return NEED_SEARCH, search
    return DONE, -1


# One compiled loop for the serial pass and for each chunk of the threaded one, so both do the
# same machine arithmetic. (Written out, not through an inlined per-block helper taking the
# bundles: that made the serial step about 15 % slower, benchmarks/throughput.py.)
@njit(cache=True)
def advance_range(s, p, integ, kick, i0, i1):
    """``advance`` of blocks i0 <= i < i1; returns (the first unstable block, which stops the
    pass before it moves, or -1; the last block that needs a search, or -1)."""
    dt, alpha, vel, omega = integ.dt, integ.damping, s.vel, s.omega
    search = -1
    for n in range(i1 - i0):
        b = i0 + n
        i = np.uint64(b)       # unsigned: no negative-index wraparound on every access
        if not p.active[i]:
            continue
        fx = p.fixity[i]
        if fx & 1:
            vel[i, 0] = p.velocity_bc[i, 0]
        else:
            vel[i, 0] += damped(s.force[i, 0], vel[i, 0], alpha) * p.inv_mass[i] * kick
        if fx & 2:
            vel[i, 1] = p.velocity_bc[i, 1]
        else:
            vel[i, 1] += damped(s.force[i, 1], vel[i, 1], alpha) * p.inv_mass[i] * kick
        if fx & 4:
            omega[i] = p.velocity_bc[i, 2]
        else:
            omega[i] += damped(s.force[i, 2], omega[i], alpha) * p.inv_inertia[i] * kick
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


# the threaded integration pass from this many blocks up: below it the start of a parallel
# region (about 60 us with numba's TBB layer on the 2-core VM) costs more than the pass
# (0.17 ms at 10,834 blocks on one thread, 0.18 ms on two; benchmarks/two_threads.py)
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
        u, n = advance_range(s, p, integ, kick, j * chunk, min(nb, (j + 1) * chunk))
        if u >= 0:
            first_unstable = min(first_unstable, u)
        last_search = max(last_search, n)
    if first_unstable < nb:
        return UNSTABLE, first_unstable
    if last_search >= 0:
        return NEED_SEARCH, last_search
    return DONE, -1


@njit(cache=True)
def kinetic_damping(integ, s, p, dfm):
    """Every ``kinetic_interval`` steps: stop all free motion after a kinetic-energy peak
    (the blocks' and the deformable blocks' gridpoints')."""
    if integ.kinetic_interval <= 0:
        return
    k = integ.kinetic
    k[1] += 1.0
    if k[1] < integ.kinetic_interval:
        return
    k[1] = 0.0
    ke = free_kinetic_energy(s, p) + zone_kinetic_energy(dfm, p.active)
    if ke < k[0]:
        stop_free_motion(s, p)
        ke = 0.0
        k[2] = 1.0          # restart from rest: half a kick next step
    k[0] = ke


@njit(cache=True)
def free_kinetic_energy(s, p):
    """1/2 sum m v^2 + I w^2 over free velocity components, inertial (scaled) masses, J/m."""
    ke = 0.0
    for i in range(s.vel.shape[0]):
        if not p.active[i]:
            continue
        fx = p.fixity[i]
        if p.inv_mass[i] > 0.0:
            if not fx & 1:
                ke += s.vel[i, 0] * s.vel[i, 0] / p.inv_mass[i]
            if not fx & 2:
                ke += s.vel[i, 1] * s.vel[i, 1] / p.inv_mass[i]
        if p.inv_inertia[i] > 0.0 and not fx & 4:
            ke += s.omega[i] * s.omega[i] / p.inv_inertia[i]
    return 0.5 * ke


@njit(cache=True)
def stop_free_motion(s, p):
    """Zero every free velocity component (prescribed ones keep their value)."""
    for i in range(s.vel.shape[0]):
        if not p.active[i]:
            continue
        fx = p.fixity[i]
        if not fx & 1:
            s.vel[i, 0] = 0.0
        if not fx & 2:
            s.vel[i, 1] = 0.0
        if not fx & 4:
            s.omega[i] = 0.0


@njit(cache=True)
def frequency_bound(c, s, p):
    """(nb,) upper bound of omega^2 per block: 2 (sum k L / m + sum k L r^2 / I), k = kn + ks.

    The factor 2 bounds the coupling to the neighbours (Gershgorin); the sum of kn and ks bounds
    both directions. The critical step of central differences is 2/omega_max.
    """
    nb = p.mass.shape[0]
    kt = np.zeros(nb)
    kr = np.zeros(nb)
    for k in range(c.count[0]):
        a, b = c.block_a[k], c.block_b[k]
        kk = (c.kn[k] + c.ks[k]) * c.length[k]
        x, y = body_point(s.pos, s.rot, a, c.point_a[k, 0], c.point_a[k, 1])
        kt[a] += kk
        kt[b] += kk
        kr[a] += kk * ((x - s.pos[a, 0]) ** 2 + (y - s.pos[a, 1]) ** 2)
        kr[b] += kk * ((x - s.pos[b, 0]) ** 2 + (y - s.pos[b, 1]) ** 2)
    return 2.0 * (kt / p.mass + kr / p.inertia)
