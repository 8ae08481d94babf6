"""The explicit time step: central differences (leapfrog) with local non-viscous damping.

One step (``run_steps`` loops it inside numba, no Python in between)::

    f  = 0
    f += contact forces                      forces.py / parallel.py (law.py)
    f += gravity                             components/gravity.py   (empty bundle: nothing)
    f += applied loads                       components/loads.py
    f += water pressure                      components/water.py
    f += cables and bolts: grout on the      components/cables.py (forces only)
         blocks; segments and grout on
         their nodes
    f += liners: bonds on the blocks;        components/liner.py (forces only)
         elements, bonds, weight on nodes
    servo velocities from f                  components/servo.py: last, so it reacts to every
                                             force of the step
    deformable blocks' zones: their forces   deformable/component.py (empty bundle: nothing)
         (elastic, the contacts' shares),
         the rigid part off
    kick = dt, or dt / 2 on the first step after a kinetic-damping stop   relaxation.next_kick
    blocks, for each free velocity component:                             integration.advance
                                       F_d = f - alpha |f| sign(v)        (local damping)
                                       v  += F_d / m_inertial * kick
    prescribed components:             v   = v_bc
    x += v dt;  theta += omega dt;  rot = R(theta);  checks (stability, search needed)
    then the same update, same dt, alpha and kick, for the cable and liner nodes (x, and a
    liner node's theta) and the deformable blocks' gridpoints (mean motion removed)
                                             integration.advance_nodes
    kinetic damping (every ``kinetic_interval`` steps): the kinetic energy of blocks,
    gridpoints and support nodes; a stop zeroes all their velocities       relaxation.end_step

Everything that moves is advanced in the one integration, with one clock (``time``, which the
support kernels' event logs read) and one ``Integrator``: the force kernels only add forces.

With threads (``Model(threads=n)``, a non-empty ``Parallel`` bundle) ``run_steps_threaded``
runs the same step, the same numbers for every block, bit for bit, in one of two shapes:

- gravity the only force besides the contacts' (``only_gravity``): ``region.run_steps_region``,
  all the steps in one parallel region. Each thread's chunk of contacts, then gravity and the
  moves of the blocks it owns (all their contacts in the chunk); then, on one thread, the
  shared blocks' forces, gravity and moves;
- otherwise: ``parallel.add_contact_forces_parallel`` (which also zeroes f, block by block),
  the other forces, and the damping and integration ``advance_parallel`` (from
  ``MIN_THREADED_BLOCKS`` blocks up; serial below): two regions; then, on the calling thread,
  ``advance_nodes`` (support nodes, gridpoints) and kinetic damping, as in ``run_steps``.

Velocities live at half steps (t - dt/2, t + dt/2), positions at whole steps. With alpha = 0 the
scheme is symplectic: energy oscillates by O((omega dt)^2) and does not drift.

Kinetic damping (dynamic relaxation) is in ``relaxation``.

Run status codes: 0 done, 1 a block moved more than half the search margin since the last
contact search (the driver searches and continues), 2 unstable (NaN, or a block moving more than
a tenth of its radius, or turning 0.1 rad, in one step; ``bad`` names the block).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..components import add_cables, add_gravity, add_liners, add_loads, add_water, servo_velocities
from ..deformable.component import add_deformable
from ..contact.forces import add_contact_forces
from .integration import (DONE, MIN_THREADED_BLOCKS, NEED_SEARCH, UNSTABLE, advance,
                          advance_nodes, advance_parallel)
from .kinematics import body_point
from .threads.parallel import add_contact_forces_parallel
from .threads.region import run_steps_region
from .relaxation import end_step, free_kinetic_energy, next_kick, stop_free_motion

__all__ = ["run_steps", "run_steps_threaded", "frequency_bound", "free_kinetic_energy",
           "stop_free_motion", "advance", "advance_parallel", "only_gravity", "DONE",
           "NEED_SEARCH", "UNSTABLE"]


@njit(cache=True)
def run_steps(nsteps, time, integ, world, parts):
    """Advance up to ``nsteps`` steps on one thread; returns (steps done, time, status, block).

    ``integ`` the Integrator, ``world`` and ``parts`` the step's records (``world.py``).
    Stops early with status 1 (search needed, after completing the step) or 2 (unstable,
    before moving).
    """
    s, p = world.state, world.props
    for step in range(nsteps):
        s.force[:] = 0.0
        add_contact_forces(world.contacts, world.strength, s, world.cracks, time,
                           world.corners, integ.edge_elements, world.zones)
        add_other_forces(time, world, parts)
        kick = next_kick(integ)
        status, bad = advance(s, p, integ, kick)
        if status == UNSTABLE:
            return step, time, UNSTABLE, bad
        advance_nodes(integ, world, parts, kick)
        time += integ.dt
        end_step(integ, world, parts)
        if status == NEED_SEARCH:
            return step + 1, time, NEED_SEARCH, bad
    return nsteps, time, DONE, -1


# A function of its own, not a branch of ``run_steps``: a serial model then never compiles the
# threaded kernels (docs/performance.md, "The test suite's time").
@njit(cache=True)
def run_steps_threaded(nsteps, time, integ, world, parts, par):
    """``run_steps`` on the threads: ``par`` the Parallel bundle (chunks and scratch); the
    same numbers, bit for bit. When gravity is the only force besides the contacts' (the
    other bundles empty), all the steps run in one parallel region
    (``region.run_steps_region``); otherwise each step's contact pass is one region and its
    integration another (from ``MIN_THREADED_BLOCKS`` blocks up)."""
    if only_gravity(parts, world.zones):
        return run_steps_region(nsteps, time, integ, world, parts.gravity, par)
    s, p = world.state, world.props
    for step in range(nsteps):
        add_contact_forces_parallel(world.contacts, world.strength, s, world.cracks, time,
                                    world.corners, par, integ.edge_elements,  # (zeroes f)
                                    world.zones)
        add_other_forces(time, world, parts)
        kick = next_kick(integ)
        if s.pos.shape[0] < MIN_THREADED_BLOCKS:
            status, bad = advance(s, p, integ, kick)
        else:
            status, bad = advance_parallel(s, p, integ, kick)
        if status == UNSTABLE:
            return step, time, UNSTABLE, bad
        advance_nodes(integ, world, parts, kick)
        time += integ.dt
        end_step(integ, world, parts)
        if status == NEED_SEARCH:
            return step + 1, time, NEED_SEARCH, bad
    return nsteps, time, DONE, -1


@njit(cache=True)
def only_gravity(parts, zones):
    """True when none of the force components but gravity is in the scene (their bundles
    empty: no applied loads, water, cables, liners, servos or deformable blocks)."""
    if zones is not None:
        if zones.point_offsets.shape[0] != 0:
            return False
    return (parts.loads.blocks.shape[0] == 0 and parts.water.contact.shape[0] == 0
            and parts.water.face_block.shape[0] == 0 and parts.cables.node_pos.shape[0] == 0
            and parts.liners.node_pos.shape[0] == 0 and parts.servo.offsets.shape[0] <= 1)


@njit(cache=True)
def add_other_forces(time, world, parts):
    """Every force but the contacts', the servos, and the deformable blocks' zones' forces, at
    the step's ``time`` (s). Nothing moves here (``integration.advance``, ``advance_nodes``)."""
    s, p = world.state, world.props
    add_gravity(parts.gravity, s, p)
    add_loads(parts.loads, s, p)
    add_water(parts.water, s, p)
    add_cables(parts.cables, s, p, time)
    add_liners(parts.liners, s, p, time, parts.gravity)
    servo_velocities(parts.servo, s, p)
    add_deformable(world.zones, world.contacts, s, p, parts.gravity)


@njit(cache=True)
def frequency_bound(c, s, p):
    """(nb,) upper bound of omega^2 per block: 2 (sum k L / m + sum k L r^2 / I), k = kn + ks.

    The factor 2 bounds the coupling to the neighbours (Gershgorin 1931: every eigenvalue
    lies within a row's diagonal plus the sum of its off-diagonal magnitudes); the sum of kn
    and ks bounds both directions. The critical step of central differences is 2/omega_max
    (e.g. Belytschko, Liu & Moran 2000, Nonlinear Finite Elements, ch. 6).
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
